//! An octree moved by any affine map: exact where the map allows, resampled otherwise.
//!
//! Exact maps: `p -> s P p + t` with `P` a signed permutation matrix (one entry +-1 in
//! each row and column: the 48 symmetries of a cube, made of quarter turns and
//! mirrors), a scale `s > 0` and any translation `t`. Such a map sends the domain's cube
//! onto a cube and its voxel lattice onto that cube's lattice, so the moved solid is
//! the same voxels with new indices: output axis `i` reads input axis `a = perm[i]`,
//! as `c_a` or, mirrored, `N - 1 - c_a` (a symmetry of the octree: every node maps to
//! one node, as [`LinearOctree::mirror`] and [`LinearOctree::rotate90`]), in the domain
//! whose corner is the lowest corner of the moved cube,
//! `min'_i = t_i + s min_a` or `t_i - s (min_a + edge)`, and whose edge is `s edge`. No
//! voxel is sampled and nothing is clipped, whatever `s` and `t`.
//!
//! A linear part is taken as `s P` when, row by row, the entry of largest magnitude
//! is within a relative 1e-12 of `s` and the others within 1e-12 `s` of zero: a quarter
//! turn built from degrees has `cos 90 = 6e-17`, not 0. The result is then the exact
//! image under that `s P`.
//!
//! A target domain other than the moved one is reached from the exact image by
//! [`LinearOctree::fit_to`]: exactly where the lattices nest, by one sampling otherwise.
//!
//! Any other map is resampled (as [`LinearOctree::resample`]) into the cube around the
//! image of the solid's bounds (the box of their moved corners, grown by 2% a side) at the
//! octree's own depth: nearest sampling at the new voxel centres, the surface moved by
//! up to about one voxel (see `resample.rs`).

use glam::{DAffine3, DMat3, DVec3};

use super::fit::Fit;
use super::resample::OctreeShape;
use crate::aabb::Aabb;
use crate::error::Result;
use crate::octree::domain::Domain;
use crate::octree::driver::VoxelizeOptions;
use crate::octree::linear::LinearOctree;
use crate::octree::voxelize::voxelize;

/// Relative tolerance of the entries of a cube symmetry times a scale.
const SYMMETRY_TOLERANCE: f64 = 1e-12;

/// A linear map `s P` with `P` a signed permutation: output axis `i` is `sign[i]` times
/// input axis `perm[i]`, all scaled by `scale`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CubeSymmetry {
    pub(crate) scale: f64,
    pub(crate) perm: [usize; 3],
    /// `true` where the axis is mirrored (the entry is negative).
    pub(crate) mirrored: [bool; 3],
}

impl CubeSymmetry {
    /// `m` as `s P` (within [`SYMMETRY_TOLERANCE`]), `None` when it is not one.
    pub(crate) fn of(m: DMat3) -> Option<CubeSymmetry> {
        let row = |i: usize| DVec3::new(m.x_axis[i], m.y_axis[i], m.z_axis[i]);
        let scale = row(0).abs().max_element();
        if !(scale.is_finite() && scale > 0.0) {
            return None;
        }
        let mut perm = [0; 3];
        let mut mirrored = [false; 3];
        for i in 0..3 {
            let r = row(i);
            let a = r.abs().max_position();
            let off = (0..3).filter(|&j| j != a).map(|j| r[j].abs()).fold(0.0, f64::max);
            if (r[a].abs() - scale).abs() > SYMMETRY_TOLERANCE * scale || off > SYMMETRY_TOLERANCE * scale {
                return None;
            }
            (perm[i], mirrored[i]) = (a, r[a] < 0.0);
        }
        let is_permutation = perm[0] != perm[1] && perm[1] != perm[2] && perm[0] != perm[2];
        is_permutation.then_some(CubeSymmetry { scale, perm, mirrored })
    }
}

/// Where [`LinearOctree::transformed`] takes a solid, decided before any voxel is
/// sampled, so a caller that remakes the solid another way (from its smooth surface,
/// [`crate::surface::transform_with_surface`]) samples nothing twice.
pub(crate) enum MovePlan {
    /// The map is a cube symmetry times a scale plus a translation: the exact image,
    /// to be fitted into `target`.
    Exact { image: LinearOctree, target: Domain },
    /// Any other map: the solid is sampled into `target`.
    Resample { target: Domain },
}

impl LinearOctree {
    /// The solid moved by the affine map `map` (a point `p` goes to `map * p`; finite
    /// and invertible) into the domain `target` makes of the default one: the moved
    /// domain when the map is a cube symmetry times a scale plus a translation (see the
    /// module doc), else the cube around the moved solid at the same depth; pass `Ok`
    /// to keep the default. Exact where the map sends voxels to voxels and the target's
    /// lattice nests in the moved one ([`LinearOctree::fit_to`]), else sampled once,
    /// straight from this solid; says which.
    ///
    /// Fails when `map` is not finite and invertible, when `target` fails, or when a
    /// resampling exceeds `options.budget`.
    pub fn transformed(
        &self,
        map: DAffine3,
        target: impl FnOnce(Domain) -> Result<Domain>,
        options: &VoxelizeOptions,
    ) -> Result<(LinearOctree, Fit)> {
        match self.plan_move(map, target)? {
            MovePlan::Exact { image, target } => image.fit_image(target, options),
            // (An empty solid has no surface to sample: it moves to an empty solid.)
            MovePlan::Resample { target } if self.is_empty() => Ok((LinearOctree::empty(target), Fit::Resampled)),
            MovePlan::Resample { target } => {
                Ok((voxelize(&OctreeShape::new(self, map)?, target, options)?, Fit::Resampled))
            }
        }
    }

    /// Where [`LinearOctree::transformed`] takes this solid (see [`MovePlan`]); fails
    /// as it does, before any sampling.
    pub(crate) fn plan_move(&self, map: DAffine3, target: impl FnOnce(Domain) -> Result<Domain>) -> Result<MovePlan> {
        crate::shape::check_invertible(&map)?;
        let Some(symmetry) = CubeSymmetry::of(map.matrix3) else {
            let moved = Aabb::from_points((0..8).map(|i| map.transform_point3(self.image_corner(i))));
            let default = Domain::around(&moved.expect("eight corners"), 0.02, self.depth())?;
            return Ok(MovePlan::Resample { target: target(default)? });
        };
        let image = self.exact_image(map, symmetry)?;
        let target = target(*image.domain())?;
        Ok(MovePlan::Exact { image, target })
    }

    /// This exact image of a solid fitted into `target`, its [`Fit::Same`] said as an
    /// exact move (the map moved it).
    pub(crate) fn fit_image(&self, target: Domain, options: &VoxelizeOptions) -> Result<(LinearOctree, Fit)> {
        let (tree, fit) = self.fit_to(target, options)?;
        let fit = if fit == Fit::Same { Fit::Exact { refined: 0, offset: [0; 3] } } else { fit };
        Ok((tree, fit))
    }

    /// The solid under `map`, whose linear part is `symmetry`: the same keys, permuted
    /// and mirrored, in the moved domain (see the module doc).
    fn exact_image(&self, map: DAffine3, symmetry: CubeSymmetry) -> Result<LinearOctree> {
        let d = self.domain();
        let n = d.resolution();
        let CubeSymmetry { scale, perm, mirrored } = symmetry;
        let tree = self.map_nodes(|min, size| {
            std::array::from_fn(|i| if mirrored[i] { n - min[perm[i]] - size } else { min[perm[i]] })
        });
        let corner = |i: usize| {
            let lo = d.min()[perm[i]];
            map.translation[i] + if mirrored[i] { -scale * (lo + d.edge()) } else { scale * lo }
        };
        let domain = Domain::new(DVec3::new(corner(0), corner(1), corner(2)), scale * d.edge(), d.depth())?;
        Ok(tree.reframed(domain))
    }

    /// Corner `i` of the solid's bounds (of the domain when it is empty).
    fn image_corner(&self, i: usize) -> DVec3 {
        self.bounds().unwrap_or_else(|| self.domain().aabb()).corner(i)
    }
}

#[cfg(test)]
mod tests {
    use glam::DQuat;

    use super::*;

    #[test]
    fn cube_symmetries_are_recognised_and_other_maps_not() {
        let quarter = DMat3::from_quat(DQuat::from_axis_angle(DVec3::Z, 90f64.to_radians()));
        let want = CubeSymmetry { scale: 1.0, perm: [1, 0, 2], mirrored: [true, false, false] };
        let got = CubeSymmetry::of(quarter).expect("a quarter turn");
        assert_eq!((got.perm, got.mirrored), (want.perm, want.mirrored));
        assert!((got.scale - 1.0).abs() < 1e-15);
        let mirror_scaled = DMat3::from_diagonal(DVec3::new(-2.0, 2.0, 2.0));
        assert_eq!(
            CubeSymmetry::of(mirror_scaled),
            Some(CubeSymmetry { scale: 2.0, perm: [0, 1, 2], mirrored: [true, false, false] })
        );
        let eighth = DMat3::from_quat(DQuat::from_axis_angle(DVec3::Z, 45f64.to_radians()));
        assert_eq!(CubeSymmetry::of(eighth), None);
        assert_eq!(CubeSymmetry::of(DMat3::from_diagonal(DVec3::new(1.0, 2.0, 1.0))), None);
        assert_eq!(CubeSymmetry::of(DMat3::ZERO), None);
    }
}
