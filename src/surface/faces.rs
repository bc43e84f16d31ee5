//! The boundary faces of a solid, one a voxel face: the exposed rectangles of its full
//! nodes ([`crate::mesh`]'s boundary, step 1) cut into unit squares, each named by its
//! full voxel and direction ([`FaceKey`]); and the test of one face.

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::{BoundaryRect, exposed_squares};
use crate::morton;
use crate::octree::LinearOctree;

/// One of the six faces of a voxel: `2 * axis + 1` for the face towards `+axis`,
/// `2 * axis` towards `-axis`.
pub type Direction = u8;

/// A boundary face: the full voxel (its Morton code at the domain's depth) and the
/// direction of its face towards the empty neighbour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct FaceKey {
    /// Morton code of the full voxel.
    pub voxel: u64,
    /// The face's direction ([`Direction`]).
    pub direction: Direction,
}

impl FaceKey {
    /// The face of voxel `v` (lattice coordinates) towards `direction`.
    #[must_use]
    pub fn new(v: [u32; 3], direction: Direction) -> Self {
        FaceKey { voxel: morton::encode(v[0], v[1], v[2]), direction }
    }

    /// The full voxel's lattice coordinates.
    #[must_use]
    pub fn voxel(self) -> [u32; 3] {
        morton::decode(self.voxel)
    }

    /// The axis the face is normal to.
    #[must_use]
    pub fn axis(self) -> usize {
        usize::from(self.direction / 2)
    }

    /// Whether the face looks towards `+axis`.
    #[must_use]
    pub fn positive(self) -> bool {
        self.direction & 1 == 1
    }

    /// The outward unit vector of the face.
    #[must_use]
    pub fn outward(self) -> DVec3 {
        let mut n = DVec3::ZERO;
        n[self.axis()] = if self.positive() { 1.0 } else { -1.0 };
        n
    }
}

/// Every boundary face of `tree`, sorted: the exposed squares cut into unit faces
/// without merging them into rectangles first (the same faces: the squares tile the
/// boundary without overlap).
#[must_use]
pub(crate) fn boundary_faces(tree: &LinearOctree) -> Vec<FaceKey> {
    let squares = exposed_squares(tree);
    let mut faces: Vec<FaceKey> = squares.par_iter().flat_map_iter(unit_faces).collect();
    faces.par_sort_unstable();
    faces
}

/// Whether face `key` is a boundary face of `tree`: its voxel full, its neighbour
/// across the face empty or outside the domain.
#[must_use]
pub(crate) fn is_boundary_face(tree: &LinearOctree, key: FaceKey) -> bool {
    let v = key.voxel();
    if !tree.contains_voxel(v) {
        return false;
    }
    match neighbour(key, tree.domain().resolution()) {
        Some(n) => !tree.contains_voxel(n),
        None => true,
    }
}

/// The voxel across face `key` from its own, `None` outside a domain of `resolution`
/// voxels a side.
#[must_use]
pub(crate) fn neighbour(key: FaceKey, resolution: u32) -> Option<[u32; 3]> {
    let mut n = key.voxel();
    let a = key.axis();
    n[a] = if key.positive() { n[a].checked_add(1).filter(|&c| c < resolution)? } else { n[a].checked_sub(1)? };
    Some(n)
}

/// The unit faces of one exposed rectangle.
fn unit_faces(r: &BoundaryRect) -> impl Iterator<Item = FaceKey> + '_ {
    (0..r.h).flat_map(move |dv| (0..r.w).map(move |du| face_key(r, du, dv)))
}

/// The face of rectangle `r` at in-plane offset `(du, dv)` (a unit rectangle's is
/// `face_key(r, 0, 0)`).
pub(crate) fn face_key(r: &BoundaryRect, du: u32, dv: u32) -> FaceKey {
    let a = usize::from(r.axis);
    let mut v = [0; 3];
    // The full voxel lies on the inner side of the plane.
    v[a] = if r.positive { r.plane - 1 } else { r.plane };
    v[(a + 1) % 3] = r.u + du;
    v[(a + 2) % 3] = r.v + dv;
    FaceKey::new(v, 2 * r.axis + u8::from(r.positive))
}
