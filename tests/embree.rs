//! Embree (the harness's `embree` feature) sees the same surfaces as the independent
//! references, on the same rays as the benchmark's:
//!
//! - over an octree's boundary faces, the octree's exact walk: the same hit or miss, the
//!   same distance within 1e-4 of the scene size (Embree is `f32`, as obvhs, and is held
//!   to obvhs's tolerance in `tests/bvh.rs`), the same axis normal, the same occluded
//!   shadow rays; rays whose octree hit lies within 1e-4 voxel of a voxel edge are left
//!   out, as in `tests/bvh.rs` (a tie between faces, and a ray through a shared edge can
//!   slip between two triangles in `f32`);
//! - over a triangle mesh (the 3,700-triangle watertight bunny), a brute-force `f64`
//!   Moller-Trumbore test of every triangle: hit or miss, distance within 1e-4 of the
//!   box's diagonal, normal within 1e-4, occlusion; rays that cross some triangle within
//!   1e-4 (barycentric) of its edges are left out, for the same reason;
//! - traced 8 rays a call (`EmbreePackets`), the same hit counts as one ray a call;
//! - in the benchmark matrix, rows for every Embree contender with the hit counts of the
//!   other contenders over the same triangles, bytes at least its vertex and index
//!   buffers, and its version in the report.
//!
//! Runs with `cargo test --release --features embree --test embree`
//! (declared in `harness/Cargo.toml`, where the feature is).

use glam::DVec3;
use octsolid::mesh::{BoundaryOptions, TriangleMesh, boundary_mesh, read_mesh};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{DEFAULT_VIEW, Traversal};
use octsolid::samples::classic_csg;
use octsolid::shape::{Menger, Shape, Sphere};
use octsolid::{MemoryBudget, NoProgress, Ray, RayCast};
use octsolid_harness::embree_contender::{available, backface_culling};
use octsolid_harness::markdown::render_section;
use octsolid_harness::rays::{RayKind, light_position, primary_rays, random_rays, shadow_rays};
use octsolid_harness::{
    Contender, ContenderKind, EmbreeBvh, EmbreePackets, MatrixOptions, RaySet, SceneKind, SurfaceHit, run_matrix,
};

/// The repository's models folder.
const MODELS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../models");

fn solid(shape: &dyn Shape, depth: u8) -> LinearOctree {
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, depth).unwrap();
    voxelize(shape, domain, &VoxelizeOptions::default()).unwrap()
}

/// Whether the octree's hit point is within 1e-4 voxel of a voxel edge.
fn near_edge(tree: &LinearOctree, ray: &Ray, hit: &SurfaceHit) -> bool {
    let d = tree.domain();
    let p = (ray.origin + ray.dir * hit.t - d.min()) / d.voxel_size();
    p.to_array().iter().filter(|c| (**c - c.round()).abs() < 1e-4).count() >= 2
}

/// Both trace modes give the same hit counts on every set.
fn packets_agree(name: &str, embree: &EmbreeBvh, packets: &EmbreePackets, sets: &[RaySet]) {
    for set in sets {
        let (one, eight) = (embree.trace(set), packets.trace(set));
        assert_eq!(one, eight, "{name} {}: {one} hits one ray a call, {eight} in packets", set.kind.name());
    }
}

fn agree_with_octree(name: &str, tree: &LinearOctree) {
    let octree = Traversal::new(tree);
    let faces = boundary_mesh(tree, &BoundaryOptions::default());
    let embree = EmbreeBvh::build(&faces);
    let bounds = tree.bounds().unwrap();
    let edge = tree.domain().edge();
    let primary = primary_rays(&bounds, DEFAULT_VIEW, DVec3::Z, 64);
    let shadow = shadow_rays(&octree, &primary, light_position(&bounds));
    let random = random_rays(&bounds, 6000, 7);
    let (mut hits, mut excluded) = (0, 0);
    let closest = primary.rays.iter().chain(&random.rays);
    for (i, ray) in closest.clone().enumerate() {
        let expected = octree.closest_hit(ray);
        if expected.is_some_and(|h| near_edge(tree, ray, &h)) {
            excluded += 1;
            continue;
        }
        hits += usize::from(expected.is_some());
        match (expected, embree.closest_hit(ray)) {
            (None, None) => {}
            (Some(e), Some(g)) => {
                assert!((e.t - g.t).abs() <= 1e-4 * edge, "{name} ray {i}: t {} vs octree {}", g.t, e.t);
                assert!((e.normal - g.normal).length() < 1e-6, "{name} ray {i}: normal {} vs {}", g.normal, e.normal);
            }
            (e, g) => panic!("{name} ray {i}: embree {g:?} vs octree {e:?}"),
        }
    }
    let total = closest.count();
    assert!(hits > total / 10, "{name}: only {hits} of {total} rays hit");
    assert!(excluded * 100 < total, "{name}: {excluded} of {total} rays excluded");
    let occluded = shadow.rays.iter().filter(|r| octree.occluded(r)).count();
    for (i, ray) in shadow.rays.iter().enumerate() {
        assert_eq!(embree.occluded(ray), octree.occluded(ray), "{name} shadow ray {i}");
    }
    assert!(
        occluded > 0 && occluded < shadow.rays.len(),
        "{name}: {occluded} of {} shadow rays occluded",
        shadow.rays.len()
    );
    packets_agree(name, &embree, &EmbreePackets::build(&faces), &[primary, shadow, random]);
}

#[test]
fn embree_is_there_and_culls_no_back_faces() {
    let version = available().as_ref().expect("an Embree device");
    assert!(version.starts_with("3."), "Embree {version}");
    // Every contender counts hits from both sides; the agreement below relies on it.
    assert_eq!(backface_culling(), Some(false));
}

#[test]
fn sphere_embree_agrees_with_the_octree() {
    agree_with_octree("sphere", &solid(&Sphere::new(DVec3::ZERO, 0.9).unwrap(), 6));
}

#[test]
fn menger_embree_agrees_with_the_octree() {
    agree_with_octree("menger", &solid(&Menger::new(DVec3::ZERO, 1.8, 2).unwrap(), 6));
}

#[test]
fn classic_csg_embree_agrees_with_the_octree() {
    agree_with_octree("classic csg", &solid(&classic_csg(), 6));
}

/// A brute-force crossing of the ray `o + t d` with triangle `abc` (f64 Moller-Trumbore,
/// no culling): `t > 0` and the least barycentric coordinate (negative outside).
fn crossing(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<(f64, f64)> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (t > 0.0).then_some((t, u.min(v).min(1.0 - u - v)))
}

/// What brute force says about `ray`: `None` when some crossing before `t_max` is within
/// 1e-4 of a triangle's edge (left out); else the closest hit, if any.
fn brute_force(mesh: &TriangleMesh, ray: &Ray) -> Option<Option<SurfaceHit>> {
    let mut best: Option<(f64, usize)> = None;
    for (k, t) in mesh.triangles.iter().enumerate() {
        let corners = t.map(|i| mesh.vertices[i as usize]);
        let Some((t, margin)) = crossing(ray.origin, ray.dir, corners) else { continue };
        if t >= ray.t_max {
            continue;
        }
        if margin.abs() < 1e-4 {
            return None;
        }
        if margin > 0.0 && best.is_none_or(|b| t < b.0) {
            best = Some((t, k));
        }
    }
    Some(best.map(|(t, k)| {
        let [a, b, c] = mesh.triangles[k].map(|i| mesh.vertices[i as usize]);
        let n = (b - a).cross(c - a).normalize();
        SurfaceHit { t, normal: if n.dot(ray.dir) > 0.0 { -n } else { n } }
    }))
}

#[test]
fn embree_agrees_with_brute_force_on_a_mesh() {
    let mesh = read_mesh(format!("{MODELS}/bunny-watertight.obj")).unwrap();
    let embree = EmbreeBvh::build(&mesh);
    let bounds = mesh.bounds();
    let diag = bounds.size().length();
    let primary = primary_rays(&bounds, SceneKind::Bunny.view(), DVec3::Y, 96);
    let random = random_rays(&bounds, 4000, 11);
    let (mut hits, mut excluded, mut worst) = (0, 0, 0.0f64);
    // Shadow rays from brute force's primary hits, lifted back 1e-4 of the diagonal.
    let light = light_position(&bounds);
    let mut shadow = Vec::new();
    for (i, ray) in primary.rays.iter().chain(&random.rays).enumerate() {
        let Some(expected) = brute_force(&mesh, ray) else {
            excluded += 1;
            continue;
        };
        match (expected, embree.closest_hit(ray)) {
            (None, None) => {}
            (Some(e), Some(g)) => {
                hits += 1;
                worst = worst.max((e.t - g.t).abs() / diag);
                assert!((e.t - g.t).abs() <= 1e-4 * diag, "ray {i}: t {} vs brute force {}", g.t, e.t);
                assert!((e.normal - g.normal).length() < 1e-4, "ray {i}: normal {} vs {}", g.normal, e.normal);
                if i < primary.rays.len() {
                    let origin = ray.origin + ray.dir * (e.t - 1e-4 * diag);
                    let to = light - origin;
                    shadow.push(Ray { origin, dir: to.normalize(), t_max: to.length() });
                }
            }
            (e, g) => panic!("ray {i}: embree {g:?} vs brute force {e:?}"),
        }
    }
    let total = primary.rays.len() + random.rays.len();
    assert!(hits > total / 5, "only {hits} of {total} rays hit");
    assert!(excluded * 100 < total, "{excluded} of {total} rays excluded");
    let mut occluded = 0;
    for (i, ray) in shadow.iter().enumerate() {
        let Some(expected) = brute_force(&mesh, ray) else { continue };
        occluded += usize::from(expected.is_some());
        assert_eq!(embree.occluded(ray), expected.is_some(), "shadow ray {i}");
    }
    assert!(occluded > 0 && occluded < shadow.len(), "{occluded} of {} shadow rays occluded", shadow.len());
    eprintln!(
        "bunny: {hits} hits, {excluded} excluded, {occluded} occluded, worst t error {worst:.2e} of the diagonal"
    );
    let shadow = RaySet { kind: RayKind::Shadow, rays: shadow };
    packets_agree("bunny", &embree, &EmbreePackets::build(&mesh), &[primary, shadow, random]);
}

#[test]
fn embree_bytes_cover_its_buffers() {
    let mesh = read_mesh(format!("{MODELS}/bunny-watertight.obj")).unwrap();
    let embree = EmbreeBvh::build(&mesh);
    let buffers = 12 * (mesh.vertices.len() + mesh.triangles.len());
    assert!(
        embree.bytes() >= buffers,
        "{} bytes, less than the {buffers} of the vertex and index buffers",
        embree.bytes()
    );
    assert!(
        embree.bytes() < 1000 * mesh.triangles.len(),
        "{} bytes for {} triangles",
        embree.bytes(),
        mesh.triangles.len()
    );
}

#[test]
fn the_matrix_runs_embree_on_the_same_rays() {
    let options = MatrixOptions {
        scenes: vec![SceneKind::Sphere, SceneKind::Bunny],
        depths: vec![5],
        image_size: 48,
        random_rays: 2000,
        threads: 2,
        repeats: 1,
        models: MODELS.into(),
        budget: MemoryBudget::default(),
        ..MatrixOptions::quick()
    };
    let results = run_matrix(&options, &NoProgress).unwrap();
    assert_eq!(results.embree.as_deref(), available().as_ref().ok().map(String::as_str));
    let hits = |case: &octsolid_harness::CaseResult, kind: ContenderKind, ray: RayKind, threads: usize| {
        let c = case.contender(kind).unwrap_or_else(|| panic!("no {} row", kind.label()));
        assert!(c.skipped.is_none(), "{} skipped: {:?}", kind.label(), c.skipped);
        c.speed(ray, threads).unwrap().hits
    };
    for case in &results.cases {
        let mut pairs = vec![(ContenderKind::EmbreeFaces, ContenderKind::ObvhsFaces)];
        if case.scene == SceneKind::Bunny {
            pairs.push((ContenderKind::EmbreeMesh, ContenderKind::ObvhsMesh));
        }
        for (embree, obvhs) in pairs {
            let row = case.contender(embree).unwrap();
            assert!(row.build_ms > 0.0 && row.bytes >= 24 * row.triangles, "{}: {row:?}", embree.label());
            let packets = if embree == ContenderKind::EmbreeFaces {
                ContenderKind::EmbreePacketsFaces
            } else {
                ContenderKind::EmbreePacketsMesh
            };
            for ray in RayKind::ALL {
                let (e, o) = (hits(case, embree, ray, 1), hits(case, obvhs, ray, 1));
                // Both f32 over the same triangles: they may differ only on rays that
                // graze a shared edge.
                assert!(
                    e.abs_diff(o) * 200 <= o.max(1),
                    "{} {}: embree {e} hits, obvhs {o}",
                    case.scene.name(),
                    ray.name()
                );
                assert_eq!(hits(case, embree, ray, 2), e, "{} {}: 2 threads", case.scene.name(), ray.name());
                assert_eq!(hits(case, packets, ray, 2), e, "{} {}: packets", case.scene.name(), ray.name());
            }
        }
    }
    let section = render_section(&results, "docs/images", &[]);
    for kind in [ContenderKind::EmbreeFaces, ContenderKind::EmbreePacketsMesh] {
        assert!(section.contains(kind.label()), "no {} row in the report", kind.label());
    }
    assert!(section.contains(&format!("Embree {}", results.embree.unwrap())));
    assert!(section.contains("- **Agreement.** On the same rays"), "no agreement line in the report");
}
