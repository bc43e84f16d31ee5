//! Adaptive voxelization against brute force, analytic volumes, thread counts and
//! memory budgets.

use std::f64::consts::PI;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::samples;
use octsolid::shape::{Shape, Sphere};
use octsolid::{Error, morton};
use octsolid::{NoProgress, Progress};

fn options() -> VoxelizeOptions<'static> {
    VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress }
}

/// Every voxel centre tested one by one: the brute-force oracle.
fn brute_force(shape: &dyn Shape, domain: Domain) -> LinearOctree {
    let voxels = (0..domain.voxel_total()).map(morton::decode).filter(|v| shape.contains(domain.voxel_center(*v)));
    LinearOctree::from_voxels(domain, voxels).unwrap()
}

#[test]
fn matches_brute_force_voxel_centres() {
    let domain = Domain::new(DVec3::new(-1.1, -1.3, -1.2), 2.6, 6).unwrap();
    let sphere = Sphere::new(DVec3::new(0.1, -0.05, 0.2), 0.93).unwrap();
    let shapes: [(&str, &dyn Shape); 3] =
        [("sphere", &sphere), ("classic", &samples::classic_csg()), ("showcase", &samples::showcase())];
    for (name, shape) in shapes {
        let tree = voxelize(shape, domain, &options()).unwrap();
        tree.validate().unwrap();
        assert!(!tree.is_empty(), "{name}");
        assert_eq!(tree, brute_force(shape, domain), "{name}");
    }
}

#[test]
fn sphere_volume_converges_to_the_analytic_one() {
    let r = 0.8;
    let sphere = Sphere::new(DVec3::new(0.01, 0.02, -0.03), r).unwrap();
    let exact = 4.0 / 3.0 * PI * r * r * r;
    let mut last_error = f64::INFINITY;
    for depth in [6, 8, 10] {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
        let tree = voxelize(&sphere, domain, &options()).unwrap();
        let error = (tree.volume() / exact - 1.0).abs();
        assert!(error < 0.01, "depth {depth}: relative error {error}");
        assert!(error < last_error * 1.5, "error should shrink with depth");
        last_error = error;
    }
}

#[test]
fn classic_csg_volume_is_analytic() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap();
    let tree = voxelize(&samples::classic_csg(), domain, &options()).unwrap();
    // Clipped ball minus the three bores' union (Steinmetz solids), see examples/classic_csg.rs.
    let h: f64 = 0.3;
    let clipped = 4.0 / 3.0 * PI * 1.3f64.powi(3) - 2.0 * PI * h * h * (3.0 * 1.3 - h);
    let r3 = 0.6f64.powi(3);
    let bores = 3.0 * PI * 0.36 * 2.0 - 16.0 * r3 + 8.0 * (2.0 - 2f64.sqrt()) * r3;
    let exact = clipped - bores;
    assert!((tree.volume() / exact - 1.0).abs() < 0.01, "{} vs {exact}", tree.volume());
}

#[test]
fn same_octree_for_any_thread_count() {
    let domain = Domain::new(DVec3::splat(-1.8), 3.6, 8).unwrap();
    let shape = samples::showcase();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| voxelize(&shape, domain, &options()).unwrap())
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(5));
}

#[test]
fn work_follows_the_surface() {
    // Node count grows about 4x a level (surface), far from the 8x of a volume.
    let sphere = Sphere::new(DVec3::ZERO, 0.9).unwrap();
    let nodes = |depth| {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
        voxelize(&sphere, domain, &options()).unwrap().node_count() as f64
    };
    let ratio = nodes(9) / nodes(8);
    assert!((3.0..5.0).contains(&ratio), "nodes grew {ratio}x a level");
}

#[test]
fn over_budget_is_refused_before_work_with_the_estimate() {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 21).unwrap();
    let sphere = Sphere::new(DVec3::ZERO, 0.9).unwrap();
    let budget = MemoryBudget(1 << 30);
    let err = voxelize(&sphere, domain, &VoxelizeOptions { budget, progress: &NoProgress }).unwrap_err();
    assert!(matches!(err, Error::OverBudget { estimate, .. } if estimate > 1 << 40), "{err}");
    let text = err.to_string();
    assert!(text.contains("depth 21") && text.contains("TiB") && text.contains("1.0 GiB"), "{text}");
}

#[test]
fn progress_reaches_its_total() {
    #[derive(Default)]
    struct Count {
        total: AtomicU64,
        done: AtomicU64,
    }
    impl Progress for Count {
        fn start(&self, total: u64) {
            self.total.store(total, Ordering::SeqCst);
        }
        fn advance(&self, n: u64) {
            self.done.fetch_add(n, Ordering::SeqCst);
        }
    }
    for depth in [2, 3, 7] {
        let count = Count::default();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
        let sphere = Sphere::new(DVec3::ZERO, 0.7).unwrap();
        voxelize(&sphere, domain, &VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &count }).unwrap();
        assert_eq!(count.done.load(Ordering::SeqCst), count.total.load(Ordering::SeqCst), "depth {depth}");
    }
}

/// A new user's bracket: an L of two 80 mm plates, 6 mm thick, with a 10 mm hole. On a
/// grid of 0.5 mm (`Domain::on_grid`) its voxels span exactly 80 x 40 x 30 mm, and its
/// volume is the analytic one to the hole's staircase (any voxel that divides the
/// dimensions); the default domain (its bounds
/// alone) rounds each face to its nearest voxel plane.
#[test]
fn dimensions_are_exact_on_a_grid_of_the_shapes_round_coordinates() {
    use octsolid::shape::{Axis, Cuboid, Cylinder};
    let base = Cuboid::from_corners(DVec3::ZERO, DVec3::new(80.0, 40.0, 6.0)).unwrap();
    let wall = Cuboid::from_corners(DVec3::ZERO, DVec3::new(80.0, 6.0, 30.0)).unwrap();
    let hole = Cylinder::new(DVec3::new(40.0, 23.0, 3.0), Axis::Z, 5.0, 8.0).unwrap();
    let bracket = (base | wall) - hole;
    let bounds = bracket.bounds().unwrap();
    for voxel in [0.5, 0.25, 0.1, 2.0] {
        let domain = Domain::on_grid(&bounds, voxel, None).unwrap();
        assert_eq!(domain.voxel_size(), voxel);
        // Every lattice plane on a multiple of the voxel, the bounds inside with room.
        let k = domain.min() / voxel;
        assert!((k - k.round()).abs().max_element() < 1e-9, "{voxel}: min {} is off the grid", domain.min());
        let tree = voxelize(&bracket, domain, &VoxelizeOptions::default()).unwrap();
        let got = tree.bounds().unwrap();
        assert!(
            (got.min - bounds.min).abs().max_element() < 1e-9 && (got.max - bounds.max).abs().max_element() < 1e-9,
            "{voxel}: voxels span {:?}..{:?}",
            got.min,
            got.max
        );
        // Plates exact; the hole within its staircase of one voxel around.
        let plates = 80.0 * 40.0 * 6.0 + 80.0 * 6.0 * 24.0;
        let hole_volume = std::f64::consts::PI * 25.0 * 6.0;
        let staircase = 2.0 * std::f64::consts::PI * 5.0 * 6.0 * voxel;
        assert!((tree.volume() - (plates - hole_volume)).abs() < staircase, "{voxel}: volume {}", tree.volume());
    }
    // The default domain at a comparable voxel puts the faces off the planes.
    let around = Domain::around(&bounds, 0.02, 8).unwrap();
    let got = voxelize(&bracket, around, &VoxelizeOptions::default()).unwrap().bounds().unwrap();
    assert!((got.max.x - got.min.x - 80.0).abs() > 1e-6, "the default domain happens to fit: {:?}", got);
    // A depth too small for the grid is refused, naming what is needed.
    let err = Domain::on_grid(&bounds, 0.1, Some(8)).unwrap_err().to_string();
    assert!(err.contains("use depth 10 or more"), "{err}");
    assert!(Domain::on_grid(&bounds, 0.0, None).is_err() && Domain::on_grid(&bounds, f64::NAN, None).is_err());
}
