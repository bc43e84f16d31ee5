//! Shared by the test suites: a seeded generator, random solids and CSG trees, scratch folders, a
//! folder's files, mesh checks (closed and manifold; an STL's triangles), the exact
//! surfaces of analytic solids (the oracle of a mesh's distance and normals) and the
//! distance to a reference mesh.
#![allow(dead_code)]

pub mod exact_surface;
pub mod mesh_checks;
pub mod mesh_distance;
pub mod radiosity_room;
mod rng;

pub use rng::Rng;

use octsolid::octree::{Domain, LinearOctree, Node};
use octsolid::shape::{Csg, Cuboid, Sphere};

/// A random solid in `domain`: a few aligned nodes of random sizes and scattered
/// voxels, so both big nodes and ragged boundaries occur.
pub fn random_octree(rng: &mut Rng, domain: Domain) -> LinearOctree {
    let depth = domain.depth();
    let mut nodes = Vec::new();
    for _ in 0..rng.below(40) {
        let k = rng.below(u64::from(depth)) as u32;
        let cells = domain.resolution() >> k;
        let min = [0; 3].map(|_| (rng.below(u64::from(cells)) as u32) << k);
        nodes.push(Node { level: depth - k as u8, min, size: 1 << k });
    }
    for _ in 0..rng.below(200) {
        nodes.push(Node {
            level: depth,
            min: [0; 3].map(|_| rng.below(u64::from(domain.resolution())) as u32),
            size: 1,
        });
    }
    let tree = LinearOctree::from_nodes(domain, nodes).unwrap();
    tree.validate().unwrap();
    tree
}

/// A random CSG tree of boxes (edges 0.1 to 0.6) and spheres (radii 0.08 to 0.35)
/// centred in `centres` on each axis, combined by union (half the nodes), difference
/// and intersection, at most `levels` deep.
pub fn random_csg(rng: &mut Rng, levels: u32, centres: (f64, f64)) -> Csg {
    if levels == 0 || rng.below(4) == 0 {
        let center = rng.vec(centres.0, centres.1);
        return if rng.below(2) == 0 {
            Cuboid::new(center, rng.vec(0.1, 0.6)).unwrap().into()
        } else {
            Sphere::new(center, rng.range(0.08, 0.35)).unwrap().into()
        };
    }
    let (a, b) = (random_csg(rng, levels - 1, centres), random_csg(rng, levels - 1, centres));
    match rng.below(4) {
        0 | 1 => a | b,
        2 => a - b,
        _ => a & b,
    }
}

/// A [`Progress`](octsolid::Progress) that records what it was told, to
/// check that a job's units add up to its total, or that it never started.
#[derive(Default)]
pub struct Recorder {
    /// Calls to `start`.
    pub starts: std::sync::atomic::AtomicU64,
    /// The last total given to `start`.
    pub total: std::sync::atomic::AtomicU64,
    /// Units advanced since the last `start`.
    pub done: std::sync::atomic::AtomicU64,
    /// Calls to `finish`.
    pub finishes: std::sync::atomic::AtomicU64,
}

impl Recorder {
    /// `(starts, total, done, finishes)`.
    pub fn read(&self) -> (u64, u64, u64, u64) {
        use std::sync::atomic::Ordering::SeqCst;
        (self.starts.load(SeqCst), self.total.load(SeqCst), self.done.load(SeqCst), self.finishes.load(SeqCst))
    }
}

impl octsolid::Progress for Recorder {
    fn start(&self, total: u64) {
        use std::sync::atomic::Ordering::SeqCst;
        self.starts.fetch_add(1, SeqCst);
        self.total.store(total, SeqCst);
        self.done.store(0, SeqCst);
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, std::sync::atomic::Ordering::SeqCst);
    }
    fn finish(&self) {
        self.finishes.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    }
}

/// Every file of a folder, by name, with its bytes.
pub fn folder_files(dir: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| {
            let e = e.unwrap();
            (e.file_name().to_string_lossy().into_owned(), std::fs::read(e.path()).unwrap())
        })
        .collect();
    files.sort();
    files
}

/// An empty folder `{suite}-{name}` in the build's folder for test files
/// (`target/tmp`, Cargo's `CARGO_TARGET_TMPDIR`), emptied if an earlier run left it: a
/// failed test's files stay there to be looked at until the next run, and nothing is
/// left in the system's temporary directory.
pub fn scratch_dir(suite: &str, name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{suite}-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
