//! Solids larger than memory: a solid stored as **shards**, each the nodes of one
//! aligned cell of the domain, and jobs that stream through them cell by cell.
//!
//! A sharded solid is a folder (`NAME.octs`) holding an `index` and one `.oct` file
//! a shard (full format in `docs/FORMAT.md`). The domain is cut into the `8^L` cells
//! `L` levels below the root ([`Layout`]); the solid's nodes of a cell or larger
//! (the interior) live in the index as full nodes, and each cell the surface passes
//! through is a shard: an ordinary `.oct` file of the same domain holding the
//! solid's nodes in that cell, which any `.oct` reader opens. The sorted Morton order
//! makes everything range-local:
//!
//! - the canonical node list of the solid is the index's full nodes and the shards'
//!   nodes in Morton order, bit for bit the single-file solid's; a node reaching out
//!   of its cell cannot be written (cells are aligned nodes, and nodes nest) and is
//!   refused on reading;
//! - voxelization walks the top `L` levels once and each cell's subtree on its own,
//!   writing the cell's shard as soon as it is done ([`voxelize_shape`],
//!   [`voxelize_mesh`]);
//! - a set operation of sharded solids is, cell by cell, the k-way merge of their
//!   nodes in that cell ([`combine`]); only a few shards are ever in memory;
//! - a job's cells can be split among tasks on many machines, each writing its own
//!   shards and a part file into the job's staging folder (named by its identity,
//!   [`JobId`]); [`join`] checks every shard and makes the index once all parts are
//!   there. The output of a task depends on its cells only, so any split, any number
//!   of workers and any retried task give the same bytes;
//! - every writer stages in a folder of its own and publishes the solid in one atomic
//!   step, so concurrent writers of one output leave one complete solid.
//!
//! - offsets, shells and rounds go cell by cell ([`morph`]): each cell from a window of
//!   it and a halo of the distance read from its neighbours' shards;
//! - the surface leaves cell by cell ([`export_surface`]): each cell meshed from a
//!   window of its neighbours' voxels and the crossings its shards carry, the seams
//!   welded by vertices named in the whole solid's frame, triangles streamed out.
//!
//! Reading: [`ShardedSolid::open`] reads only the index; [`ShardedSolid::read`] the
//! whole solid within a memory budget, [`ShardedSolid::read_within`] the finest level
//! of detail that fits one (for rendering), [`Cursor`] the nodes of a range.

mod index;
mod job;
mod layout;
mod offset;
mod solid;
mod staging;
mod stream;
mod surface;
mod window;
mod writer;

pub use index::{INDEX_MAGIC, INDEX_VERSION, ShardEntry, ShardIndex};
pub use job::JobId;
pub use layout::Layout;
pub use offset::{Morph, morph};
pub use solid::{Cursor, ShardedSolid};
pub use stream::{StreamOptions, combine, voxelize_mesh, voxelize_shape, write};
pub use surface::{SurfaceExport, SurfaceExportOptions, export_surface};
pub use writer::{ShardWriter, join};

/// The index's file name in a sharded solid's folder.
pub const INDEX_FILE: &str = "index";
