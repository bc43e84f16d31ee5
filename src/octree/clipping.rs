//! What an operation lost to its domain: a result that reaches a face of the domain
//! its input kept clear of (an offset, a shell or a round grew past it, and the
//! voxels beyond are cut off), or that came out empty from a solid that was not.
//!
//! The test is on the solids' bounds: a face is reached when the bounds come within
//! half a voxel of it. Callers (the CLI's `offset`, the Python package's offsets) say
//! so as a warning; the result itself is what the domain holds.

use super::LinearOctree;

/// How a result was cut by its domain ([`clipping`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Clipping {
    /// Nothing is left of a solid that was not empty.
    Emptied,
    /// The result reaches a face of the domain (`[-x, -y, -z, +x, +y, +z]`) the input
    /// kept clear of.
    AtFaces([bool; 6]),
}

/// How `result` was cut by its domain, made from `input` (both in one domain), or
/// `None` when nothing was.
#[must_use]
pub fn clipping(input: &LinearOctree, result: &LinearOctree) -> Option<Clipping> {
    if result.is_empty() && !input.is_empty() {
        return Some(Clipping::Emptied);
    }
    let domain = result.domain();
    let (edges, half) = (domain.aabb(), domain.voxel_size() / 2.0);
    let touches = |tree: &LinearOctree| {
        tree.bounds().map_or([false; 6], |b| {
            let low = (b.min - edges.min).cmplt(glam::DVec3::splat(half));
            let high = (edges.max - b.max).cmplt(glam::DVec3::splat(half));
            [low.x, low.y, low.z, high.x, high.y, high.z]
        })
    };
    let (before, after) = (touches(input), touches(result));
    let newly: [bool; 6] = std::array::from_fn(|i| after[i] && !before[i]);
    newly.contains(&true).then_some(Clipping::AtFaces(newly))
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::octree::{Domain, voxelize};
    use crate::shape::{Cuboid, Sphere};

    #[test]
    fn a_result_reaching_faces_its_input_kept_clear_of_is_clipped_there() {
        let domain = Domain::new(DVec3::ZERO, 1.0, 5).unwrap();
        let solid = |shape: &dyn crate::shape::Shape| voxelize(shape, domain, &Default::default()).unwrap();
        let ball = solid(&Sphere::new(DVec3::splat(0.5), 0.3).unwrap());
        let empty = LinearOctree::empty(domain);
        assert_eq!(clipping(&ball, &ball), None);
        assert_eq!(clipping(&ball, &empty), Some(Clipping::Emptied));
        assert_eq!(clipping(&empty, &empty), None);
        // A box from the low x face to the middle: grown to the high y face as well.
        let low_x = solid(&Cuboid::new(DVec3::new(0.25, 0.5, 0.5), DVec3::new(0.5, 0.4, 0.4)).unwrap());
        let to_high_y = solid(&Cuboid::new(DVec3::new(0.25, 0.7, 0.5), DVec3::new(0.5, 0.6, 0.4)).unwrap());
        assert_eq!(clipping(&low_x, &to_high_y), Some(Clipping::AtFaces([false, false, false, false, true, false])));
        // The face the input touched already does not count.
        assert_eq!(clipping(&to_high_y, &low_x), None);
    }
}
