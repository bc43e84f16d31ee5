//! The benchmark matrix: every scene at every depth, every contender, every ray kind, on
//! one thread and on all threads; build time, bytes and rays a second for each.
//!
//! Fairness rules: every contender traces the same [`RaySet`]s (made once a scene and
//! depth), in the same rayon pools (a 1-thread pool and an `threads`-thread pool, chunks
//! of 256 rays a task); builds run in the all-threads pool (the BVH builders use rayon,
//! Embree's is given the pool's thread count, the octree's build is sequential). Times
//! are medians of `repeats` runs after one warm-up run; a run longer than a second is
//! not repeated.

use std::path::PathBuf;
use std::time::Instant;

use super::bvh_contender::BvhCrateBvh;
use super::contender::Contender;
#[cfg(feature = "embree")]
use super::embree_contender::{self, EmbreeBvh, EmbreePackets};
use super::machine::Machine;
use super::obvhs_contender::ObvhsBvh;
use super::rays::{RayKind, RaySet, light_position, primary_rays, random_rays, shadow_rays};
use super::scenes::{BenchScene, SceneKind, build_scene};
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::Progress;
use octsolid::mesh::{BoundaryOptions, TriangleMesh, try_boundary_mesh};
use octsolid::render::{Traversal, Tree64};
use octsolid::{Error, Result};

/// The structures under test.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ContenderKind {
    /// Our traversal octree and its ray walk.
    Octree,
    /// Our 64-tree (4x4x4 nodes) and its mirrored walk, the octree's hits.
    Tree64,
    /// `obvhs` CWBVH over the octree's boundary faces.
    ObvhsFaces,
    /// `bvh` crate BVH over the octree's boundary faces.
    BvhFaces,
    /// Embree 3 over the octree's boundary faces, one ray a call (`embree` feature).
    EmbreeFaces,
    /// Embree 3 over the octree's boundary faces, 8-ray packets (`embree` feature).
    EmbreePacketsFaces,
    /// `obvhs` CWBVH over the original triangle mesh.
    ObvhsMesh,
    /// `bvh` crate BVH over the original triangle mesh.
    BvhMesh,
    /// Embree 3 over the original triangle mesh, one ray a call (`embree` feature).
    EmbreeMesh,
    /// Embree 3 over the original triangle mesh, 8-ray packets (`embree` feature).
    EmbreePacketsMesh,
}

/// The contenders over boundary faces that this build measures.
#[cfg(not(feature = "embree"))]
const OVER_FACES: &[ContenderKind] = &[ContenderKind::ObvhsFaces, ContenderKind::BvhFaces];
/// The contenders over boundary faces that this build measures.
#[cfg(feature = "embree")]
const OVER_FACES: &[ContenderKind] = &[
    ContenderKind::ObvhsFaces,
    ContenderKind::BvhFaces,
    ContenderKind::EmbreeFaces,
    ContenderKind::EmbreePacketsFaces,
];
/// The contenders over the original mesh that this build measures.
#[cfg(not(feature = "embree"))]
const OVER_MESH: &[ContenderKind] = &[ContenderKind::ObvhsMesh, ContenderKind::BvhMesh];
/// The contenders over the original mesh that this build measures.
#[cfg(feature = "embree")]
const OVER_MESH: &[ContenderKind] =
    &[ContenderKind::ObvhsMesh, ContenderKind::BvhMesh, ContenderKind::EmbreeMesh, ContenderKind::EmbreePacketsMesh];

impl ContenderKind {
    /// All contenders, in report order (Embree's are measured only with the `embree`
    /// feature).
    pub const ALL: [ContenderKind; 10] = [
        ContenderKind::Octree,
        ContenderKind::Tree64,
        ContenderKind::ObvhsFaces,
        ContenderKind::BvhFaces,
        ContenderKind::EmbreeFaces,
        ContenderKind::EmbreePacketsFaces,
        ContenderKind::ObvhsMesh,
        ContenderKind::BvhMesh,
        ContenderKind::EmbreeMesh,
        ContenderKind::EmbreePacketsMesh,
    ];

    /// The contenders built over the octree's boundary faces that this build measures,
    /// in report order: the BVH crates', then, with the `embree` feature, Embree's.
    #[must_use]
    pub fn over_faces() -> &'static [ContenderKind] {
        OVER_FACES
    }

    /// The contenders built over the original triangle mesh that this build measures,
    /// in report order.
    #[must_use]
    pub fn over_mesh() -> &'static [ContenderKind] {
        OVER_MESH
    }

    /// Whether it is one of ours, built from the linear octree (no triangles).
    #[must_use]
    pub fn is_ours(self) -> bool {
        matches!(self, ContenderKind::Octree | ContenderKind::Tree64)
    }

    /// Short name on command lines (`walk_one`'s `CONTENDER`), e.g. `embree-mesh`.
    #[must_use]
    pub fn slug(self) -> &'static str {
        match self {
            ContenderKind::Octree => "octree",
            ContenderKind::Tree64 => "tree64",
            ContenderKind::ObvhsFaces => "obvhs-faces",
            ContenderKind::BvhFaces => "bvh-faces",
            ContenderKind::EmbreeFaces => "embree-faces",
            ContenderKind::EmbreePacketsFaces => "embree-packets-faces",
            ContenderKind::ObvhsMesh => "obvhs-mesh",
            ContenderKind::BvhMesh => "bvh-mesh",
            ContenderKind::EmbreeMesh => "embree-mesh",
            ContenderKind::EmbreePacketsMesh => "embree-packets-mesh",
        }
    }

    /// The contender whose [`ContenderKind::slug`] is `slug`.
    #[must_use]
    pub fn from_slug(slug: &str) -> Option<ContenderKind> {
        ContenderKind::ALL.into_iter().find(|k| k.slug() == slug)
    }

    /// Name in tables and plots.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            ContenderKind::Octree => "octree (ours)",
            ContenderKind::Tree64 => "64-tree (ours)",
            ContenderKind::ObvhsFaces => "obvhs, boundary faces",
            ContenderKind::BvhFaces => "bvh, boundary faces",
            ContenderKind::EmbreeFaces => "embree, boundary faces",
            ContenderKind::EmbreePacketsFaces => "embree 8-ray packets, boundary faces",
            ContenderKind::ObvhsMesh => "obvhs, original mesh",
            ContenderKind::BvhMesh => "bvh, original mesh",
            ContenderKind::EmbreeMesh => "embree, original mesh",
            ContenderKind::EmbreePacketsMesh => "embree 8-ray packets, original mesh",
        }
    }
}

/// What to run.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixOptions {
    /// Scenes.
    pub scenes: Vec<SceneKind>,
    /// Depths of each scene.
    pub depths: Vec<u8>,
    /// Primary rays: one a pixel of a `image_size x image_size` image.
    pub image_size: u32,
    /// Number of random rays.
    pub random_rays: usize,
    /// Threads of the "all threads" runs.
    pub threads: usize,
    /// Timed runs a measurement (after one warm-up run).
    pub repeats: usize,
    /// BVHs over boundary faces are skipped above this many triangles (their build
    /// time and memory grow with it; the octree runs at every depth).
    pub max_bvh_triangles: usize,
    /// Folder holding the bunny's mesh.
    pub models: PathBuf,
    /// Memory budget for voxelizing the scenes.
    pub budget: MemoryBudget,
    /// Seed of the random rays.
    pub seed: u64,
}

impl MatrixOptions {
    /// The full matrix: depths 8, 10 and 12 (where the scene allows), a 384 x 384 image,
    /// 131,072 random rays, 3 runs.
    #[must_use]
    pub fn full() -> Self {
        MatrixOptions {
            scenes: SceneKind::ALL.to_vec(),
            depths: vec![8, 10, 12],
            image_size: 384,
            random_rays: 1 << 17,
            threads: std::thread::available_parallelism().map_or(1, usize::from),
            repeats: 3,
            max_bvh_triangles: 4_000_000,
            models: PathBuf::from("models"),
            budget: MemoryBudget::default(),
            seed: 0x5EED,
        }
    }

    /// A quick matrix: depths 8 and 10, a 256 x 256 image, 65,536 random rays, 3 runs.
    #[must_use]
    pub fn quick() -> Self {
        MatrixOptions { depths: vec![8, 10], image_size: 256, random_rays: 1 << 16, repeats: 3, ..Self::full() }
    }

    /// The depths `scene` runs at: those of [`MatrixOptions::depths`] up to its
    /// [`SceneKind::max_depth`].
    pub fn depths_of(&self, scene: SceneKind) -> impl Iterator<Item = u8> + '_ {
        self.depths.iter().copied().filter(move |&d| d <= scene.max_depth())
    }

    /// Number of progress units [`run_matrix`] reports: one a build and one a measurement.
    #[must_use]
    pub fn work_units(&self) -> u64 {
        let per_contender = 1 + 2 * RayKind::ALL.len() as u64;
        let mesh = ContenderKind::over_mesh().len();
        let faces = 2 + ContenderKind::over_faces().len();
        let contenders = |s: SceneKind| (if s == SceneKind::Bunny { faces + mesh } else { faces }) as u64;
        self.scenes.iter().map(|&s| contenders(s) * per_contender * self.depths_of(s).count() as u64).sum()
    }
}

/// Rays a second of one contender on one ray set with one thread count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speed {
    /// Ray kind.
    pub kind: RayKind,
    /// Threads.
    pub threads: usize,
    /// Rays traced a run.
    pub rays: usize,
    /// Rays that hit (closest hit found, or shadow ray occluded).
    pub hits: u64,
    /// Median seconds a run.
    pub seconds: f64,
}

impl Speed {
    /// Million rays a second.
    #[must_use]
    pub fn mrays(&self) -> f64 {
        self.rays as f64 / self.seconds / 1e6
    }
}

/// One contender on one scene and depth.
#[derive(Clone, Debug, PartialEq)]
pub struct ContenderResult {
    /// Which contender.
    pub kind: ContenderKind,
    /// Why it did not run, if it did not.
    pub skipped: Option<String>,
    /// Triangles it was built over (0 for the octree).
    pub triangles: usize,
    /// Median build time in milliseconds.
    pub build_ms: f64,
    /// Bytes of the structure.
    pub bytes: usize,
    /// Nodes of the structure.
    pub nodes: usize,
    /// Rays a second, for each ray kind and thread count.
    pub speeds: Vec<Speed>,
}

impl ContenderResult {
    /// The speed for `kind` on `threads` threads, if measured.
    #[must_use]
    pub fn speed(&self, kind: RayKind, threads: usize) -> Option<&Speed> {
        self.speeds.iter().find(|s| s.kind == kind && s.threads == threads)
    }
}

/// One scene at one depth.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseResult {
    /// Scene.
    pub scene: SceneKind,
    /// Depth.
    pub depth: u8,
    /// Nodes of the linear octree.
    pub octree_nodes: usize,
    /// Triangles of the boundary-face mesh.
    pub face_triangles: usize,
    /// Milliseconds to extract the boundary faces (not part of any build time).
    pub faces_ms: f64,
    /// Rays of each kind.
    pub rays: Vec<(RayKind, usize)>,
    /// Results, in [`ContenderKind::ALL`] order.
    pub contenders: Vec<ContenderResult>,
}

impl CaseResult {
    /// The result of `kind`, if it was part of this case.
    #[must_use]
    pub fn contender(&self, kind: ContenderKind) -> Option<&ContenderResult> {
        self.contenders.iter().find(|c| c.kind == kind)
    }
}

/// Everything a matrix run measured.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixResults {
    /// Where and when.
    pub machine: Machine,
    /// What was run.
    pub options: MatrixOptions,
    /// Embree's version, when Embree ran (the `embree` feature).
    pub embree: Option<String>,
    /// One entry a scene and depth, scenes in order, then depths.
    pub cases: Vec<CaseResult>,
}

/// Median of `times` (sorted in place).
fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    let n = times.len();
    if n % 2 == 1 { times[n / 2] } else { 0.5 * (times[n / 2 - 1] + times[n / 2]) }
}

/// Times `run` `repeats` times (fewer when a run takes over a second); median seconds and
/// the last result.
fn time_median<T>(repeats: usize, mut run: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::with_capacity(repeats);
    loop {
        let started = Instant::now();
        let out = run();
        times.push(started.elapsed().as_secs_f64());
        if times.len() >= repeats.max(1) || times.iter().sum::<f64>() > 1.0 {
            return (median(&mut times), out);
        }
    }
}

/// The rayon pools of a run: one thread, and `threads` threads.
struct Pools {
    one: rayon::ThreadPool,
    all: rayon::ThreadPool,
    threads: usize,
}

impl Pools {
    fn new(threads: usize) -> Result<Self> {
        let pool = |n| {
            rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| Error::InvalidArgument {
                what: "threads",
                reason: format!("cannot start {n} threads: {e}"),
            })
        };
        Ok(Pools { one: pool(1)?, all: pool(threads.max(1))?, threads: threads.max(1) })
    }
}

/// Builds contender `C` from `input`, then traces every ray set on one and on all threads.
fn measure<C: Contender>(
    kind: ContenderKind,
    input: &C::Input,
    triangles: usize,
    ray_sets: &[RaySet],
    pools: &Pools,
    repeats: usize,
    progress: &dyn Progress,
) -> ContenderResult {
    let (build_s, structure) = pools.all.install(|| time_median(repeats, || C::build(input)));
    progress.advance(1);
    let mut speeds = Vec::new();
    for set in ray_sets {
        for (pool, threads) in [(&pools.one, 1), (&pools.all, pools.threads)] {
            let hits = pool.install(|| structure.trace(set));
            let (seconds, _) = pool.install(|| time_median(repeats, || structure.trace(set)));
            speeds.push(Speed { kind: set.kind, threads, rays: set.rays.len(), hits, seconds });
            progress.advance(1);
        }
    }
    ContenderResult {
        kind,
        skipped: None,
        triangles,
        build_ms: build_s * 1e3,
        bytes: structure.bytes(),
        nodes: structure.node_count(),
        speeds,
    }
}

/// Builds contender `kind` over `mesh` and measures it (see [`measure`]); Embree's are
/// skipped with the reason when no Embree device can be made.
fn measure_mesh(
    kind: ContenderKind,
    mesh: &TriangleMesh,
    ray_sets: &[RaySet],
    pools: &Pools,
    repeats: usize,
    progress: &dyn Progress,
) -> ContenderResult {
    let n = mesh.triangles.len();
    match kind {
        ContenderKind::ObvhsFaces | ContenderKind::ObvhsMesh => {
            measure::<ObvhsBvh>(kind, mesh, n, ray_sets, pools, repeats, progress)
        }
        ContenderKind::BvhFaces | ContenderKind::BvhMesh => {
            measure::<BvhCrateBvh>(kind, mesh, n, ray_sets, pools, repeats, progress)
        }
        #[cfg(feature = "embree")]
        ContenderKind::EmbreeFaces
        | ContenderKind::EmbreeMesh
        | ContenderKind::EmbreePacketsFaces
        | ContenderKind::EmbreePacketsMesh => match embree_contender::available() {
            Err(why) => {
                progress.advance(1 + 2 * RayKind::ALL.len() as u64);
                skipped(kind, n, why.clone())
            }
            Ok(_) if matches!(kind, ContenderKind::EmbreeFaces | ContenderKind::EmbreeMesh) => {
                measure::<EmbreeBvh>(kind, mesh, n, ray_sets, pools, repeats, progress)
            }
            Ok(_) => measure::<EmbreePackets>(kind, mesh, n, ray_sets, pools, repeats, progress),
        },
        other => {
            progress.advance(1 + 2 * RayKind::ALL.len() as u64);
            skipped(other, n, format!("{} is not built over a mesh in this binary", other.label()))
        }
    }
}

/// A contender that did not run, and why.
fn skipped(kind: ContenderKind, triangles: usize, reason: String) -> ContenderResult {
    ContenderResult { kind, skipped: Some(reason), triangles, build_ms: 0.0, bytes: 0, nodes: 0, speeds: Vec::new() }
}

/// Runs one scene at one depth.
fn run_case(scene: &BenchScene, options: &MatrixOptions, pools: &Pools, progress: &dyn Progress) -> Result<CaseResult> {
    let per_contender = 1 + 2 * RayKind::ALL.len() as u64;
    let octree = Traversal::new(&scene.tree);
    let bounds = scene.tree.bounds().unwrap_or_else(|| scene.tree.domain().aabb());
    // The same rays for everyone: primary from a framing camera, shadow from the
    // octree's primary hits, random through the solid's box.
    let primary = primary_rays(&bounds, scene.kind.view(), scene.kind.up(), options.image_size);
    let shadow = pools.all.install(|| shadow_rays(&octree, &primary, light_position(&bounds)));
    let random = random_rays(&bounds, options.random_rays, options.seed);
    let ray_sets = [primary, shadow, random];
    drop(octree);

    let repeats = options.repeats;
    let mut contenders = vec![
        measure::<Traversal>(ContenderKind::Octree, &scene.tree, 0, &ray_sets, pools, repeats, progress),
        measure::<Tree64>(ContenderKind::Tree64, &scene.tree, 0, &ray_sets, pools, repeats, progress),
    ];
    let started = Instant::now();
    // The boundary faces: the export's default, coplanar faces merged into rectangles.
    // A mesh over the memory budget skips the BVHs over it (the octree still runs).
    let faces =
        pools.all.install(|| try_boundary_mesh(&scene.tree, &BoundaryOptions::default(), options.budget, &NoProgress));
    let faces_ms = started.elapsed().as_secs_f64() * 1e3;
    let faces = match faces {
        Ok(faces) => Ok(faces),
        Err(e @ Error::OverBudget { .. }) => Err(e.to_string()),
        Err(e) => return Err(e),
    };
    let n = faces.as_ref().map_or(0, |f| f.triangles.len());
    for &kind in ContenderKind::over_faces() {
        match &faces {
            Err(why) => {
                contenders.push(skipped(kind, n, why.clone()));
                progress.advance(per_contender);
            }
            Ok(_) if n > options.max_bvh_triangles => {
                let reason = format!("{n} boundary triangles, above the limit of {}", options.max_bvh_triangles);
                contenders.push(skipped(kind, n, reason));
                progress.advance(per_contender);
            }
            Ok(f) => contenders.push(measure_mesh(kind, f, &ray_sets, pools, repeats, progress)),
        }
    }
    drop(faces);
    if let Some(mesh) = &scene.mesh {
        for &kind in ContenderKind::over_mesh() {
            contenders.push(measure_mesh(kind, mesh, &ray_sets, pools, repeats, progress));
        }
    }
    Ok(CaseResult {
        scene: scene.kind,
        depth: scene.tree.depth(),
        octree_nodes: scene.tree.node_count(),
        face_triangles: n,
        faces_ms,
        rays: ray_sets.iter().map(|s| (s.kind, s.rays.len())).collect(),
        contenders,
    })
}

/// Runs the matrix; `progress` receives [`MatrixOptions::work_units`] units.
pub fn run_matrix(options: &MatrixOptions, progress: &dyn Progress) -> Result<MatrixResults> {
    if options.image_size == 0 || options.random_rays == 0 {
        return Err(Error::InvalidArgument {
            what: "ray sets",
            reason: "the image size and the number of random rays must be positive".into(),
        });
    }
    let pools = Pools::new(options.threads)?;
    progress.start(options.work_units());
    let mut cases = Vec::new();
    for &kind in &options.scenes {
        for depth in options.depths_of(kind) {
            let scene = pools.all.install(|| build_scene(kind, depth, &options.models, options.budget))?;
            cases.push(run_case(&scene, options, &pools, progress)?);
        }
    }
    progress.finish();
    #[cfg(feature = "embree")]
    let embree = embree_contender::available().clone().ok();
    #[cfg(not(feature = "embree"))]
    let embree = None;
    Ok(MatrixResults { machine: Machine::current(), options: options.clone(), embree, cases })
}
