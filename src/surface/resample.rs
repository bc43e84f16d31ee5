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
//! [`fit_with_surface`] and [`transform_with_surface`] are the one road for a solid
//! that may carry data: exact moves carry the data along
//! ([`HermiteData::transformed`]), a refinement leaves it out, and where the voxels
//! would be sampled the solid is made from its smooth surface instead, without
//! sampling the voxels first (the target domain is decided before any sampling).
//!
//! Departure: where two voxels of the solid touch along an edge or at a corner the
//! mesh has a sheet (two vertices at one point), so the moved solid may be joined or
//! parted there differently from a resampling by voxels; both are within a voxel.

use glam::DAffine3;

use super::extract::{ExtractOptions, Style, extract};
use super::hermite::HermiteData;
use crate::error::{Error, Result};
use crate::mesh::{InsideRule, MeshVoxelizeOptions, voxelize_mesh};
use crate::octree::{Domain, Fit, LinearOctree, MovePlan, VoxelizeOptions};
use crate::progress::Stages;

/// A solid brought into a domain or moved, with what became of its surface data.
#[derive(Debug)]
pub struct Moved {
    /// The solid in its new domain.
    pub tree: LinearOctree,
    /// Its surface data: carried along by an exact move, made again from the smooth
    /// surface where the voxels did not follow ([`Fit::Resampled`]), `None` when the
    /// solid had none or a refinement left it out.
    pub surface: Option<HermiteData>,
    /// How the voxels got there.
    pub fit: Fit,
}

/// `tree` (with its surface data `surface`, if any) in `target`: unchanged when it is
/// there (the data copied), exact when the lattices nest ([`LinearOctree::fit_to`]; the data carried
/// along, or left out by a refinement), else voxelized again from its smooth surface
/// ([`resample_with_surface`]) when it has data, and sampled at the target's voxel
/// centres when it has none.
///
/// # Errors
/// When the result exceeds `options.budget`.
pub fn fit_with_surface(
    tree: &LinearOctree,
    surface: Option<&HermiteData>,
    target: Domain,
    options: &VoxelizeOptions,
) -> Result<Moved> {
    match surface {
        Some(data) if !tree.fits_exactly(&target) => {
            let (tree, data) = resample_with_surface(tree, data, DAffine3::IDENTITY, target, options)?;
            Ok(Moved { tree, surface: Some(data), fit: Fit::Resampled })
        }
        surface => {
            let (fitted, fit) = tree.fit_to(target, options)?;
            let surface = match fit {
                Fit::Same => surface.cloned(),
                _ => surface.and_then(|d| d.transformed(tree.domain(), DAffine3::IDENTITY, &fitted, fit)),
            };
            Ok(Moved { tree: fitted, surface, fit })
        }
    }
}

/// `tree` (with its surface data `surface`, if any) moved by `map` into the domain
/// `target` makes of the default one, as [`LinearOctree::transformed`] moves it: exact
/// for a cube symmetry times a scale plus a translation whose image nests in the target
/// (the data carried along, or left out by a refinement); otherwise voxelized again
/// from its moved smooth surface ([`resample_with_surface`]) when it has data, and
/// sampled at the target's voxel centres when it has none.
///
/// # Errors
/// When `map` is not finite and invertible, when `target` fails, or when the result
/// exceeds `options.budget`.
pub fn transform_with_surface(
    tree: &LinearOctree,
    surface: Option<&HermiteData>,
    map: DAffine3,
    target: impl FnOnce(Domain) -> Result<Domain>,
    options: &VoxelizeOptions,
) -> Result<Moved> {
    let Some(data) = surface else {
        let (tree, fit) = tree.transformed(map, target, options)?;
        return Ok(Moved { tree, surface: None, fit });
    };
    match tree.plan_move(map, target)? {
        MovePlan::Exact { image, target } if image.fits_exactly(&target) => {
            let (moved, fit) = image.fit_image(target, options)?;
            let surface = data.transformed(tree.domain(), map, &moved, fit);
            Ok(Moved { tree: moved, surface, fit })
        }
        MovePlan::Exact { target, .. } | MovePlan::Resample { target } => {
            let (moved, data) = resample_with_surface(tree, data, map, target, options)?;
            Ok(Moved { tree: moved, surface: Some(data), fit: Fit::Resampled })
        }
    }
}

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
    // The extraction and the voxelization, on one bar.
    let stages = Stages::new(options.progress, 2);
    let extract_options = ExtractOptions { style: Style::Smooth, budget: options.budget, ..ExtractOptions::default() };
    let mut mesh = extract(tree, surface, &extract_options, &stages)?.mesh;
    for v in &mut mesh.vertices {
        *v = map.transform_point3(*v);
    }
    if det < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    let voxelize = MeshVoxelizeOptions { inside: InsideRule::Parity, budget: options.budget, progress: &stages };
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

    /// The one road gives what its two steps gave, sampling nothing twice: an eighth
    /// turn, and a fit into a lattice that does not nest, are made from the smooth
    /// surface into the domain the voxels' own move picks; a quarter turn, and a fit
    /// by whole voxels, carry the data as [`HermiteData::transformed`] carries it; a
    /// solid without data moves by its voxels.
    #[test]
    fn moves_with_surface_give_the_two_steps_answers() {
        let sphere = Sphere::new(DVec3::new(0.05, -0.1, 0.02), 0.6).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let options = VoxelizeOptions::default();
        let tree = voxelize(&sphere, domain, &options).unwrap();
        let surface = HermiteData::from_shape(&sphere, &tree);
        let turn = |degrees: f64| {
            let m = DMat3::from_axis_angle(DVec3::Z, degrees.to_radians());
            DAffine3::from_mat3_translation(m, DVec3::new(0.1, 0.0, 0.2))
        };
        // Turned by an eighth: remade in the domain the voxels' resampling picks.
        let (by_voxels, fit) = tree.transformed(turn(45.0), Ok, &options).unwrap();
        assert_eq!(fit, Fit::Resampled);
        let (tree_want, data_want) =
            resample_with_surface(&tree, &surface, turn(45.0), *by_voxels.domain(), &options).unwrap();
        let got = transform_with_surface(&tree, Some(&surface), turn(45.0), Ok, &options).unwrap();
        assert_eq!((got.fit, &got.tree, got.surface.as_ref()), (Fit::Resampled, &tree_want, Some(&data_want)));
        // Turned by a quarter: the exact image, the data carried.
        let (image, fit) = tree.transformed(turn(90.0), Ok, &options).unwrap();
        assert!(matches!(fit, Fit::Exact { refined: 0, .. }));
        let carried = surface.transformed(tree.domain(), turn(90.0), &image, fit);
        let got = transform_with_surface(&tree, Some(&surface), turn(90.0), Ok, &options).unwrap();
        assert_eq!((got.fit, &got.tree, &got.surface), (fit, &image, &carried));
        assert!(carried.is_some_and(|d| d.len() == surface.len()));
        // Without data: the voxels' move.
        let got = transform_with_surface(&tree, None, turn(45.0), Ok, &options).unwrap();
        assert_eq!((got.fit, &got.tree, got.surface), (Fit::Resampled, &by_voxels, None));
        // Fitted by three whole voxels: carried; into a lattice a third of a voxel
        // off: remade.
        let voxel = domain.voxel_size();
        for (shift, exact) in [(3.0, true), (1.0 / 3.0, false)] {
            let target = Domain::new(domain.min() - DVec3::splat(shift * voxel), 2.0, 6).unwrap();
            let got = fit_with_surface(&tree, Some(&surface), target, &options).unwrap();
            assert_eq!(*got.tree.domain(), target);
            if exact {
                let (fitted, fit) = tree.fit_to(target, &options).unwrap();
                let carried = surface.transformed(tree.domain(), DAffine3::IDENTITY, &fitted, fit);
                assert_eq!((got.fit, &got.tree, &got.surface), (fit, &fitted, &carried));
            } else {
                let want = resample_with_surface(&tree, &surface, DAffine3::IDENTITY, target, &options).unwrap();
                assert_eq!((got.fit, got.tree, got.surface), (Fit::Resampled, want.0, Some(want.1)));
            }
        }
    }

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
