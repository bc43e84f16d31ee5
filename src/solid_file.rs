//! The door for solid files: [`SolidFile::read`] reads any solid file octsolid reads
//! with what it records about its source, and [`write_solid_file`] writes solids,
//! borrowed, as any solid or mesh format; each by the file's [`FileKind`].
//!
//! | kind | read | written from |
//! |------|------|--------------|
//! | `.oct` | the solid, its [`Metadata`] (up axis, units) and its surface data when the file has it | one solid, with [`WriteOptions::meta`] and [`WriteOptions::surface`] |
//! | `.octs` | the whole sharded solid within the budget ([`crate::sharded`]; [`SolidFile::read_to_draw`]: at the finest depth that fits) | one solid, at the default cell level, with the metadata |
//! | `.vox`, `.vdb` | one solid a palette colour, one a grid (a level set's with its surface data from the distances) | one solid each |
//! | `.binvox` | one solid | one solid |
//! | `.glb` | | each solid's true surface with smooth normals (on [`WriteOptions::surface`] for one solid; [`WriteOptions::mesh_style`] gives the staircase) |
//! | `.obj`, `.stl`, `.ply`, `.3mf` | | one solid's true surface ([`crate::surface::extract`], on [`WriteOptions::surface`]; [`WriteOptions::mesh_style`] gives the staircase), `.3mf` in the unit and up axis of [`WriteOptions::meta`] ([`write_mesh_file`]) |
//!
//! It sits above `io`, `mesh` and `sharded` (it reads and writes through all three) and
//! below `scene_file`, whose solid leaves it reads. A file of one solid is read as one
//! solid named by the file's stem, without a colour; the formats of many keep their
//! names and colours. Writing borrows the trees ([`SolidsRef`]): nothing is copied to
//! be written.

use std::path::Path;

use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::io::gltf::{self, NamedMesh};
use crate::io::oct::{self, Metadata, Units};
use crate::io::{ColouredSolid, ReadOptions, Solids, SolidsRef, WriteOptions, binvox, file_stem, one_solid, vdb, vox};
use crate::mesh::BoundarySize;
use crate::mesh::{ThreeMfOptions, ThreeMfUnit, TriangleMesh, write_mesh_with};
use crate::octree::LinearOctree;
use crate::progress::{Progress, Stages};
use crate::shape::Axis;
use crate::sharded::{self, ShardedSolid, StreamOptions};
use crate::surface::{ExtractOptions, HermiteData, Style, SurfaceMesh, extract, peak_bytes};

/// A solid file as read: its kind, its solids over one domain, and what it records
/// about its source.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidFile {
    /// The format, by extension.
    pub kind: FileKind,
    /// The solids (one for `.oct`, `.octs` and `.binvox`).
    pub solids: Solids,
    /// `.oct`'s and `.octs`'s up axis and units; the default elsewhere.
    pub meta: Metadata,
    /// The solid's surface data (crossings and normals of its boundary faces) where an
    /// `.oct` file carries it ([`oct::read_and_surface`]) or a `.vdb` level set's
    /// distances give it ([`vdb::read_and_surface`]); `None` elsewhere.
    pub surface: Option<HermiteData>,
    /// A sharded solid read coarser than it is to fit the budget
    /// ([`SolidFile::read_to_draw`]): its own depth; `None` when read at full depth.
    pub coarsened_from: Option<u8>,
}

impl SolidFile {
    /// Reads the solid file at `path`: `.oct`, a sharded `.octs` (whole, refused when
    /// it exceeds `options.budget`), `.vox`, `.binvox` or `.vdb` by extension
    /// ([`FileKind::SOLIDS`]; any other is [`Error::UnknownExtension`], listing these).
    pub fn read(path: impl AsRef<Path>, options: &ReadOptions) -> Result<SolidFile> {
        let path = path.as_ref();
        let kind = FileKind::of(path, FileKind::SOLIDS)?;
        let file = match kind {
            FileKind::Oct => {
                let (tree, meta, surface) = oct::read_and_surface(path, options.budget)?;
                SolidFile { surface, ..SolidFile::one(path, kind, tree, meta) }
            }
            FileKind::Octs => {
                let solid = ShardedSolid::open(path)?;
                let tree = solid.read(options.budget)?;
                SolidFile::one(path, kind, tree, solid.index().meta)
            }
            FileKind::Binvox => SolidFile::one(path, kind, binvox::read(path, options.budget)?, Metadata::default()),
            FileKind::Vox => SolidFile::many(kind, vox::read(path, options)?),
            FileKind::Vdb => {
                let (solids, surface) = vdb::read_and_surface(path, options)?;
                SolidFile { surface, ..SolidFile::many(kind, solids) }
            }
            other => unreachable!("{other:?} is not in FileKind::SOLIDS"),
        };
        debug_assert!(file.solids.validate().is_ok());
        Ok(file)
    }

    /// Reads the solid file at `path` to be drawn: as [`SolidFile::read`], but a
    /// sharded solid larger than the budget comes at the finest depth that fits it
    /// ([`ShardedSolid::read_within`]; [`SolidFile::coarsened_from`] says so).
    pub fn read_to_draw(path: impl AsRef<Path>, options: &ReadOptions) -> Result<SolidFile> {
        let path = path.as_ref();
        if FileKind::of(path, FileKind::SOLIDS)? != FileKind::Octs {
            return SolidFile::read(path, options);
        }
        let solid = ShardedSolid::open(path)?;
        let tree = solid.read_within(options.budget)?;
        let depth = solid.index().domain.depth();
        let mut file = SolidFile::one(path, FileKind::Octs, tree, solid.index().meta);
        file.coarsened_from = (file.solids.domain.depth() < depth).then_some(depth);
        Ok(file)
    }

    /// Every solid in one (the solid itself when there is one).
    #[must_use]
    pub fn union(&self) -> LinearOctree {
        match self.solids.solids.as_slice() {
            [one] => one.tree.clone(),
            _ => self.solids.union(),
        }
    }

    /// The union, taking the solid out when there is one.
    #[must_use]
    pub fn into_union(mut self) -> LinearOctree {
        if self.solids.solids.len() == 1 {
            return self.solids.solids.remove(0).tree;
        }
        self.solids.union()
    }

    /// A file of one solid without a colour, named by the file's stem.
    fn one(path: &Path, kind: FileKind, tree: LinearOctree, meta: Metadata) -> SolidFile {
        let solids = Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new(file_stem(path), None, tree)] };
        SolidFile { kind, solids, meta, surface: None, coarsened_from: None }
    }

    /// A file of the solids a format of many read.
    fn many(kind: FileKind, solids: Solids) -> SolidFile {
        SolidFile { kind, solids, meta: Metadata::default(), surface: None, coarsened_from: None }
    }
}

/// Writes `solids` to `path` in the format its extension names
/// ([`FileKind::SOLID_OUTPUTS`]; any other is [`Error::UnknownExtension`], listing
/// them), borrowing the trees; returns the bytes written (a sharded solid's: its
/// shards').
///
/// `.vox`, `.vdb` and `.glb` write every solid with its name and colour; the others
/// hold one solid and refuse more (take the union first): `.oct` with `options.meta`
/// and `options.surface`, `.octs` with `options.meta` and no surface data (at the
/// default cell level, in one job: a command with its own cells writes through
/// [`sharded::write`]), `.binvox`, and `.obj`, `.stl`,
/// `.ply` and `.3mf` (and `.glb`, every solid's) the solid's surface by [`crate::surface::extract`] (the true surface,
/// contoured on `options.surface` or estimated from the voxels without it, or the
/// staircase with merged faces by `options.mesh_style`; `progress` counts its steps) and
/// written by [`write_mesh_file`] with `options.meta`, refused for an empty solid, which
/// has none, and as [`Error::OverBudget`] (naming the file) when the mesh's estimate
/// exceeds `options.budget`.
pub fn write_solid_file(
    path: impl AsRef<Path>,
    solids: &SolidsRef<'_>,
    options: &WriteOptions,
    progress: &dyn Progress,
) -> Result<u64> {
    let path = path.as_ref();
    let kind = FileKind::of(path, FileKind::SOLID_OUTPUTS)?;
    if kind == FileKind::Octs {
        let tree = one_solid(path, solids)?;
        let stream = StreamOptions { budget: options.budget, progress, ..StreamOptions::default() };
        let index = sharded::write(tree, options.meta, path, &stream)?.expect("every cell: an index");
        return Ok(index.shards.iter().map(|s| s.bytes).sum());
    }
    if kind.writes_mesh() {
        let tree = one_solid(path, solids)?;
        if tree.is_empty() {
            return Err(unwritable(path, "the solid is empty; there is no boundary to write as a mesh".into()));
        }
        let none = HermiteData::none();
        let hermite = options.surface.as_deref().unwrap_or(&none);
        let surface = surface_of(path, tree, hermite, &extract_options(options), progress)?;
        return write_mesh_file(&surface.mesh, path, &options.meta);
    }
    if kind == FileKind::Glb && options.mesh_style == Style::Smooth {
        let up = options.meta.up.unwrap_or(options.up);
        let surface = options.surface.as_deref();
        return Ok(write_glb_surfaces(path, solids, surface, &extract_options(options), up, progress)?.bytes);
    }
    crate::io::write_voxel_solids(path, kind, solids, options)
}

/// How [`write_solid_file`] meshes: in `options.mesh_style`, within `options.budget`,
/// unsimplified.
fn extract_options(options: &WriteOptions) -> ExtractOptions {
    ExtractOptions { style: options.mesh_style, budget: options.budget, ..Default::default() }
}

/// What [`write_glb_surfaces`] wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GlbSurfaces {
    /// The file's size in bytes.
    pub bytes: u64,
    /// Meshes written, one a non-empty solid.
    pub meshes: usize,
    /// Their triangles.
    pub triangles: usize,
    /// Whether some vertex was estimated from the voxels (no crossing there).
    pub estimated: bool,
}

/// Writes `solids` to `path` as one `.glb` of their surfaces: each non-empty solid's
/// surface by [`extract`] with `options` (contoured on `surface` when `solids` holds
/// one solid, estimated from the voxels otherwise), one mesh a solid with its name,
/// colour and smooth normals ([`gltf::write_meshes`]), turned from `up` to glTF's +Y;
/// `progress` fills once over the solids, weighted by their boundaries. `export` and
/// [`write_solid_file`] write `.glb` through it.
///
/// # Errors
/// Before any meshing: coordinates `f32` cannot hold, every solid empty, and the
/// meshes of all the solids together (each is kept until the file is written) over
/// `options.budget` ([`Error::OverBudget`] naming `path`); then as [`extract`] and
/// [`gltf::write_meshes`].
pub fn write_glb_surfaces(
    path: impl AsRef<Path>,
    solids: &SolidsRef<'_>,
    surface: Option<&HermiteData>,
    options: &ExtractOptions,
    up: Axis,
    progress: &dyn Progress,
) -> Result<GlbSurfaces> {
    let path = path.as_ref();
    solids.validate()?;
    // Refused before any meshing: coordinates f32 cannot hold, nothing to mesh, and
    // the meshes of every solid together past the budget (each is kept until the file
    // is written; `extract` checks one at a time).
    gltf::check_single_precision_of(solids, Some(path))?;
    let meshed: Vec<_> = solids.solids.iter().filter(|solid| !solid.tree.is_empty()).collect();
    if meshed.is_empty() {
        let what = if solids.solids.len() == 1 { "the solid is empty" } else { "every solid is empty" };
        return Err(unwritable(path, format!("{what}; there is no boundary to write as a mesh")));
    }
    let none = HermiteData::none();
    let hermite = match (surface, solids.solids.len()) {
        (Some(surface), 1) => surface,
        _ => &none,
    };
    let sizes: Vec<BoundarySize> = meshed.iter().map(|solid| BoundarySize::of(solid.tree)).collect();
    if options.style == Style::Smooth {
        let faces: u128 = sizes.iter().map(|s| s.unit_faces).sum();
        let simplifying = options.tolerance > 0.0;
        let bytes = sizes.iter().map(|&s| peak_bytes(s, hermite, simplifying)).fold(0u64, u64::saturating_add);
        let job = format!("writing {} (the surfaces of {} boundary voxel faces)", path.display(), faces);
        options.budget.check(job, bytes)?;
    }
    let weights: Vec<u64> = sizes.iter().map(|s| u64::try_from(s.unit_faces).unwrap_or(u64::MAX).max(1)).collect();
    let stages = Stages::weighted(progress, &weights);
    let surfaces = meshed
        .into_iter()
        .map(|solid| Ok((solid, surface_of(path, solid.tree, hermite, options, &stages)?)))
        .collect::<Result<Vec<_>>>()?;
    drop(stages);
    let meshes: Vec<NamedMesh> = surfaces
        .iter()
        .map(|(solid, surface)| NamedMesh { name: &solid.name, color: solid.color, mesh: &surface.mesh })
        .collect();
    let bytes = gltf::write_meshes(path, &meshes, up, solids.domain.voxel_size())?;
    Ok(GlbSurfaces {
        bytes,
        meshes: surfaces.len(),
        triangles: surfaces.iter().map(|(_, s)| s.mesh.triangles.len()).sum(),
        estimated: surfaces.iter().any(|(_, s)| s.is_estimate()),
    })
}

/// The surface of `tree` by [`extract`] with `options`, contoured on `hermite`, for
/// writing `path`: a refusal for memory names the output as the voxel formats'
/// refusals do (and stays one, so a caller tells it from a file that cannot be
/// written).
fn surface_of(
    path: &Path,
    tree: &LinearOctree,
    hermite: &HermiteData,
    options: &ExtractOptions,
    progress: &dyn Progress,
) -> Result<SurfaceMesh> {
    extract(tree, hermite, options, progress).map_err(|e| {
        e.wrapped(|e| match e {
            Error::OverBudget { job, estimate, budget } => {
                Error::OverBudget { job: format!("writing {} ({job})", path.display()), estimate, budget }
            }
            e => unwritable(path, format!("cannot mesh the solid: {e}")),
        })
    })
}

/// Writes `mesh` to `path` as the mesh format its extension names
/// ([`crate::mesh::write_mesh`]), recording `meta` where the format can: a `.3mf` model
/// takes its unit (millimetres when none is recorded, the 3MF default) and stands a
/// y-up or x-up world upright in 3MF's z-up by its build item's transform (the vertices
/// as they are, as `.glb` turns its node).
///
/// # Errors
/// As [`crate::mesh::write_mesh`].
pub fn write_mesh_file(mesh: &TriangleMesh, path: impl AsRef<Path>, meta: &Metadata) -> Result<u64> {
    let unit = meta.units.map_or(ThreeMfUnit::Millimetre, |u| match u {
        Units::Micrometre => ThreeMfUnit::Micron,
        Units::Millimetre => ThreeMfUnit::Millimetre,
        Units::Centimetre => ThreeMfUnit::Centimetre,
        Units::Metre => ThreeMfUnit::Metre,
        Units::Inch => ThreeMfUnit::Inch,
        Units::Foot => ThreeMfUnit::Foot,
    });
    write_mesh_with(mesh, path, &ThreeMfOptions { unit, up: meta.up.unwrap_or(Axis::Z) })
}

/// The error of a solid that cannot be written as `path`.
fn unwritable(path: &Path, reason: String) -> Error {
    Error::Unwritable { path: path.to_path_buf(), reason }
}
