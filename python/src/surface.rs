//! A solid's surface data (the crossings and normals of its boundary faces,
//! [`HermiteData`]), made only when something needs it: an `.oct` file written with a
//! surface section (as `octsolid shape`, `voxelize` and `csg` write one), a smooth
//! mesh, a render's smooth normals. A solid voxelized from a shape or a mesh keeps how
//! to make it (its source), a solid read from a file the data the file carried, a set
//! operation's result its operands'.
//!
//! A solid's data is written as it was made (so a saved file is the CLI's, byte for
//! byte), and drawn and meshed as the file it saves gives it back
//! ([`LazySurface::as_read_back`]: data made in memory through the file's 16-bit codes,
//! [`HermiteData::as_stored`]; data read from a file as read), so what a solid draws
//! and meshes in Python is, bit for bit, what `octsolid` draws and meshes from that file.

use std::sync::{Arc, Mutex};

use octsolid::octree::LinearOctree;
use octsolid::surface::HermiteData;

/// How a solid's surface data is made from its tree.
pub type Maker = Box<dyn FnOnce(&LinearOctree) -> octsolid::Result<Option<HermiteData>> + Send>;

/// The surface data of a solid: made at most once, then kept; and whether it was
/// read from a file (so it is already as a file gives it).
pub struct LazySurface(Mutex<State>, bool);

enum State {
    Pending(Maker),
    Ready(Option<Arc<HermiteData>>),
}

impl LazySurface {
    /// No surface data: the solid's faces are its voxels'.
    pub fn none() -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Ready(None)), false))
    }

    /// Data made in memory (by a move or a fit).
    pub fn ready(data: Option<HermiteData>) -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Ready(data.map(Arc::new))), false))
    }

    /// The data a file carried.
    pub fn read(data: Option<HermiteData>) -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Ready(data.map(Arc::new))), true))
    }

    /// Data made by `make` when first asked for.
    pub fn later(make: Maker) -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Pending(make)), false))
    }

    /// Whether there is or will be data (without making it).
    pub fn is_some(&self) -> bool {
        !matches!(*self.0.lock().unwrap_or_else(|p| p.into_inner()), State::Ready(None))
    }

    /// The data of `tree` (the solid this belongs to), made now if it was not yet.
    pub fn get(&self, tree: &LinearOctree) -> octsolid::Result<Option<Arc<HermiteData>>> {
        let mut state = self.0.lock().unwrap_or_else(|p| p.into_inner());
        if let State::Ready(data) = &*state {
            return Ok(data.clone());
        }
        let State::Pending(make) = std::mem::replace(&mut *state, State::Ready(None)) else { unreachable!() };
        let data = make(tree)?.map(Arc::new);
        *state = State::Ready(data.clone());
        Ok(data)
    }

    /// The data of `tree` as the `.oct` file it is written to gives it back: through
    /// the file's codes, unless it was read from a file.
    pub fn as_read_back(&self, tree: &LinearOctree) -> octsolid::Result<Option<Arc<HermiteData>>> {
        let data = self.get(tree)?;
        Ok(if self.1 { data } else { data.map(|d| Arc::new(d.as_stored())) })
    }
}
