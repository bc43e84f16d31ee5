//! A solid with surface data moved where its voxels do not follow (a turn other than a
//! quarter turn, a scale or a target domain whose lattice does not nest in the
//! solid's): resampled from its smooth surface, not from its voxels.
//!
//! [`LinearOctree::transformed`] and [`LinearOctree::fit_to`] resample a solid by its
//! voxels: each new voxel centre takes the voxel it falls in, so the surface moves by
//! up to half a voxel diagonal and a curved one shows rings, and the crossings, which
//! lie on the old lattice's segments, are lost. With surface data the solid knows its
//! surface to a hundredth of a voxel ([`extract`]'s smooth mesh: closed, oriented,
//! manifold). [`resample_with_surface`] moves that mesh by the map, voxelizes it into
//! the target domain (each voxel by its centre, parity rule: the mesh is closed) and
//! takes the crossings of the new boundary faces from the moved triangles
//! ([`HermiteData::from_mesh`]). The moved solid and its data are then as faithful as
//! the surface was: a resampled sphere keeps its area to the true surface's accuracy,
//! where resampling by voxels adds a ring of half-voxel steps.
//!
//! Departure: where two voxels of the solid touch along an edge or at a corner the
//! mesh has a sheet (two vertices at one point), so the moved solid may be joined or
//! parted there differently from a resampling by voxels; both are within a voxel.

use glam::DAffine3;

use super::extract::{ExtractOptions, Style, extract};
use super::hermite::HermiteData;
use crate::error::{Error, Result};
use crate::mesh::{InsideRule, MeshVoxelizeOptions, voxelize_mesh};
use crate::octree::{Domain, LinearOctree, VoxelizeOptions};

/// The solid `tree` with surface data `surface` moved by `map` (finite, invertible;
/// a point `p` goes to `map * p`) and voxelized into `target`, from its smooth surface
/// (see the module doc), with the crossings of its new boundary faces.
///
/// # Errors
/// When `map` is not finite and invertible, or the extraction or the voxelization
/// exceeds `options.budget`.
pub fn resample_with_surface(
    tree: &LinearOctree,
    surface: &HermiteData,
    map: DAffine3,
    target: Domain,
    options: &VoxelizeOptions,
) -> Result<(LinearOctree, HermiteData)> {
    let det = map.matrix3.determinant();
    if !(map.is_finite() && det.is_finite() && det != 0.0) {
        return Err(Error::invalid("transform", "it is not finite and invertible"));
    }
    let extract_options = ExtractOptions { style: Style::Smooth, budget: options.budget, ..ExtractOptions::default() };
    let mut mesh = extract(tree, surface, &extract_options, options.progress)?.mesh;
    for v in &mut mesh.vertices {
        *v = map.transform_point3(*v);
    }
    if det < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    let voxelize =
        MeshVoxelizeOptions { inside: InsideRule::Parity, budget: options.budget, progress: options.progress };
    let (moved, _) = voxelize_mesh(&mesh, target, &voxelize)?;
    let data = HermiteData::from_mesh(&mesh, InsideRule::Parity, &moved);
    Ok((moved, data))
}

#[cfg(test)]
mod tests {
    use glam::{DMat3, DVec3};

    use super::*;
    use crate::octree::voxelize;
    use crate::shape::Sphere;

    /// A sphere with its exact crossings turned 30 degrees about a tilted axis into a
    /// domain of other voxels: the smooth surface of the result keeps the sphere's
    /// area and volume far closer than a resampling by voxels keeps its voxels', and
    /// every new crossing lies on the sphere to a small part of a voxel.
    #[test]
    fn a_resampled_sphere_keeps_its_true_surface() {
        let (center, r) = (DVec3::new(0.03, -0.02, 0.01), 0.7);
        let sphere = Sphere::new(center, r).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 7).unwrap();
        let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
        let surface = HermiteData::from_shape(&sphere, &tree);
        let turn = DMat3::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 30f64.to_radians());
        let map = DAffine3::from_mat3_translation(turn, DVec3::new(0.1, 0.0, -0.05));
        let target = Domain::new(DVec3::splat(-1.013), 2.03, 7).unwrap();
        let (moved, data) = resample_with_surface(&tree, &surface, map, target, &VoxelizeOptions::default()).unwrap();
        let moved_center = map.transform_point3(center);
        let voxel = target.voxel_size();
        // Every crossing on the moved sphere, within a fiftieth of a voxel.
        assert!(data.len() > 10_000);
        for &(key, crossing) in data.faces() {
            let p = target.min() + crossing.point(key) * voxel;
            let off = ((p - moved_center).length() - r).abs() / voxel;
            assert!(off < 0.02, "crossing {off} voxel off the sphere");
        }
        // The smooth surface of the moved solid: area and volume of the true sphere.
        let mesh = extract(&moved, &data, &ExtractOptions::default(), &crate::NoProgress).unwrap().mesh;
        let (area, volume) = (4.0 * std::f64::consts::PI * r * r, 4.0 / 3.0 * std::f64::consts::PI * r.powi(3));
        assert!((mesh.area() / area - 1.0).abs() < 2e-3, "area {} against {area}", mesh.area());
        assert!((mesh.volume() / volume - 1.0).abs() < 2e-3, "volume {} against {volume}", mesh.volume());
        // Resampled by voxels instead, the voxels' volume is further off.
        let (by_voxels, _) = tree.transformed(map, |_| Ok(target), &VoxelizeOptions::default()).unwrap();
        let voxels_off = (by_voxels.volume() / volume - 1.0).abs();
        let surface_off = (moved.volume() / volume - 1.0).abs();
        assert!(surface_off <= voxels_off + 1e-3, "voxels {surface_off} against {voxels_off} by voxels");
    }
}
