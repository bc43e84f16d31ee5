//! A solid's surface data (the crossings and normals of its boundary faces,
//! [`HermiteData`]), made only when something needs it: an `.oct` file written with a
//! surface section (as `octsolid shape`, `voxelize` and `csg` write one), a smooth
//! mesh, a render's smooth normals. A solid voxelized from a shape or a mesh keeps how
//! to make it (its source), a solid read from a file the data the file carried, a set
//! operation's result its operands'.

use std::sync::{Arc, Mutex};

use octsolid::octree::LinearOctree;
use octsolid::surface::HermiteData;

/// How a solid's surface data is made from its tree.
pub type Maker = Box<dyn FnOnce(&LinearOctree) -> octsolid::Result<Option<HermiteData>> + Send>;

/// The surface data of a solid: made at most once, then kept.
pub struct LazySurface(Mutex<State>);

enum State {
    Pending(Maker),
    Ready(Option<Arc<HermiteData>>),
}

impl LazySurface {
    /// No surface data: the solid's faces are its voxels'.
    pub fn none() -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Ready(None))))
    }

    /// The data a file carried.
    pub fn ready(data: Option<HermiteData>) -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Ready(data.map(Arc::new)))))
    }

    /// Data made by `make` when first asked for.
    pub fn later(make: Maker) -> Arc<LazySurface> {
        Arc::new(LazySurface(Mutex::new(State::Pending(make))))
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
}
