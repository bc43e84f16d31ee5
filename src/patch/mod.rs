//! Bicubic Bezier patches: evaluation, normals, loading, and voxelization.
//!
//! A patch is `p(u, v) = sum_ij B_i(u) B_j(v) P_ij` over a 4x4 control net with the
//! cubic Bernstein polynomials `B`. It is evaluated by de Casteljau's algorithm
//! (repeated linear interpolation, numerically stable), its normal is
//! `p_u x p_v / |p_u x p_v|` (seed: parametric surfaces), and it splits at `u = 1/2`
//! or `v = 1/2` into two patches whose control nets converge to the surface. The
//! surface lies in the convex hull of its control points, so their bounding box bounds
//! every piece: the voxelizer refines pieces until their boxes are small.

mod bezier;
mod read;
mod voxelize;

pub use bezier::BezierPatch;
pub use read::read_patches;
pub use voxelize::{
    TriangleParams, estimate_surface_bytes, estimate_tessellation_bytes, segments_for, tessellate,
    tessellate_with_params, tessellate_within, voxelize_patch_surface,
};
