//! The fuzz targets: one function a parser, each taking a whole file as `&[u8]` and
//! reading it through the library's public API, plus four that go on past parsing
//! (a solid measured, exported and read back; a mesh voxelized; patches voxelized; a
//! scene rendered by two visibility methods).
//!
//! A target returns `Ok` with a short summary of what it read, or the library's
//! `Err`: both are fine (bad input must be refused with an error, and is); a panic, a
//! hang or a memory blow-up is a finding, and so is a broken promise the targets
//! assert (a round trip that changes a solid, two visibility methods that disagree).
//! The summary and the error's text are what the driver's novelty feedback compares.
//! Every job runs under a small [`MemoryBudget`] ([`BUDGET`], the scene targets
//! [`SCENE_BUDGET`]), so input that asks for too much is refused cleanly, and whatever
//! escapes the budget shows as a memory blow-up.
//!
//! Departures from "just call the parser", each to keep one case short or to step
//! past what is known and open:
//! - the `.oct` targets decode the case with its length and checksum fixed
//!   ([`oct_fixed`]), the `.rad`, `.octs` index and part targets with the checksum
//!   fixed ([`rad_fixed`]);
//! - `join_part` joins the case as the one part of a job beside the shards of two
//!   fixed jobs ([`join_fixture`]), its folder named by the job in the case's header,
//!   so that a mutated part reaches the join's checks of every shard;
//! - voxelizing targets use depth 4 or 5, and the scene targets a 16 MiB budget (a scene
//!   may ask for depth 21 and is refused or small under it);
//! - `mesh_voxelize` voxelizes meshes of at most [`MAX_VOXELIZED_TRIANGLES`]: the
//!   solid voxelizer's work grows with the triangles meeting each node (coincident
//!   ones go to the exact predicates' slow path), so a file of one face repeated
//!   hundreds of times (what duplicating a line makes) takes half a second at depth 5
//!   and one repeated thousands of times seconds, which is slow, not stuck;
//! - `solid_export` writes binvox only up to resolution 256 (binvox output is a dense
//!   run-length grid of `resolution^3` voxels, with no budget), measures solids only
//!   up to depth [`MAX_MEASURED_DEPTH`] (the boundary area's time grows with the size
//!   of the boundary in 16^3 bricks, not with the nodes: a one-node full solid takes
//!   0.3 s at depth 12, about twice as long each level deeper), and asserts its round
//!   trips only over proper domains (`proper_domain`);
//! - the scene targets build only scenes whose depths are at most
//!   [`MAX_SCENE_DEPTH`], and `scene_render` compares the two pictures only through a
//!   proper camera (`proper_camera`);
//! - `patches_voxelize` does not ask for the patch set's report, which tessellates at
//!   1/1000 of its size (a third of a second for the teapot), and voxelizes only patch
//!   sets within [`MAX_PATCH_COORDINATE`].

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use glam::DVec3;

use octsolid::import::{Fill, ImportOptions, Input, default_domain, voxelize_input};
use octsolid::io::oct::Metadata;
use octsolid::io::{ReadOptions, Solids, binvox, gltf, oct, vdb, vox};
use octsolid::mesh::{BoundaryOptions, MeshShape, PolygonTables, mesh_from_bytes, try_boundary_mesh};
use octsolid::octree::{Cells, Domain, VoxelizeOptions, voxelize};
use octsolid::patch::read_patches;
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{Camera, Material, Method, Projection, RenderOptions, Scene, render};
use octsolid::scene_file::read_scene;
use octsolid::shape::{Axis, Cuboid, Sphere};
use octsolid::sharded::{self, ShardIndex, StreamOptions};
use octsolid::{MemoryBudget, NoProgress, Result};

use crate::scratch;

/// The staging folder of output `out`, as docs/FORMAT.md names it: `OUT.partial`
/// beside the output.
fn staging_dir(out: &Path) -> PathBuf {
    let mut name = out.file_name().expect("an output file name").to_os_string();
    name.push(".partial");
    out.with_file_name(name)
}

/// The budget of every target but the scene's.
pub const BUDGET: MemoryBudget = MemoryBudget(256 << 20);
/// The budget of `solid_export`'s writers: their time grows with the faces or voxels
/// the budget lets through (`.vox` of a depth-12 solid of a few large nodes sorts its
/// voxels for 1.4 s under 256 MiB).
pub const EXPORT_BUDGET: MemoryBudget = MemoryBudget(64 << 20);
/// The scene target's budget: a scene voxelizes at its own depth, and the time that
/// takes grows with the memory the budget allows.
pub const SCENE_BUDGET: MemoryBudget = MemoryBudget(16 << 20);

/// One fuzz target.
#[derive(Clone, Copy, Debug)]
pub struct Target {
    /// Its name on the command line and its artifact folder.
    pub name: &'static str,
    /// The corpus folders (under `fuzz/corpus/`) its seeds come from.
    pub corpus: &'static [&'static str],
    /// The extension its artifacts are saved with.
    pub ext: &'static str,
    /// What it does, for `--list`.
    pub about: &'static str,
    /// The target itself.
    pub run: fn(&[u8]) -> Result<String>,
}

/// Every target, parsers first.
pub const TARGETS: &[Target] = &[
    Target {
        name: "oct",
        corpus: &["oct"],
        ext: "oct",
        about: "io::oct::decode_and_metadata as given, decode_and_surface with the lengths and CRC-32s fixed",
        run: oct_target,
    },
    Target { name: "obj", corpus: &["obj"], ext: "obj", about: "mesh_from_bytes as OBJ", run: obj },
    Target { name: "stl", corpus: &["stl"], ext: "stl", about: "mesh_from_bytes as STL", run: stl },
    Target { name: "ply", corpus: &["ply"], ext: "ply", about: "mesh_from_bytes as PLY", run: ply },
    Target { name: "patches", corpus: &["patches"], ext: "patches", about: "patch::read_patches", run: patches },
    Target {
        name: "scene",
        corpus: &["scene"],
        ext: "toml",
        about: "scene_file::read_scene (reads and builds the scene, 16 MiB budget)",
        run: scene,
    },
    Target {
        name: "scene_render",
        corpus: &["scene"],
        ext: "toml",
        about: "a scene loaded and rendered at 8x6 by ray tracing and by a raster method, which must agree",
        run: scene_render,
    },
    Target {
        name: "rad",
        corpus: &["rad"],
        ext: "rad",
        about: "render::radiosity::Radiosity::read against a fixed small room, as given and with the CRC-32 fixed",
        run: rad_target,
    },
    Target {
        name: "octs_index",
        corpus: &["octs"],
        ext: "index",
        about: "sharded::ShardIndex::decode, as given and with the CRC-32 fixed; what it reads encodes back to itself",
        run: octs_index,
    },
    Target {
        name: "join_part",
        corpus: &["part"],
        ext: "part",
        about: "sharded::join of a job folder holding the case as its part file (CRC-32 fixed) beside two fixed jobs' shards",
        run: join_part,
    },
    Target { name: "vox", corpus: &["vox"], ext: "vox", about: "io::vox::decode", run: vox_target },
    Target { name: "binvox", corpus: &["binvox"], ext: "binvox", about: "io::binvox::decode", run: binvox_target },
    Target { name: "vdb", corpus: &["vdb"], ext: "vdb", about: "io::vdb::decode", run: vdb_target },
    Target {
        name: "solid_export",
        corpus: &["oct", "vox", "binvox", "vdb"],
        ext: "bin",
        about: "a solid file (by magic) decoded, measured, written to every format, .oct and .vdb read back",
        run: solid_export,
    },
    Target {
        name: "mesh_voxelize",
        corpus: &["obj", "stl", "ply"],
        ext: "mesh",
        about: "a mesh (OBJ, STL or PLY by content) loaded, reported, voxelized solid/surface/thin and as a MeshShape",
        run: mesh_voxelize,
    },
    Target {
        name: "patches_voxelize",
        corpus: &["patches"],
        ext: "patches",
        about: "a patch set loaded, reported, voxelized as a surface and as a tessellated solid",
        run: patches_voxelize,
    },
];

/// The target called `name`.
#[must_use]
pub fn by_name(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

/// The read options of the solid formats: the defaults under [`BUDGET`].
fn read_options() -> ReadOptions {
    ReadOptions { budget: BUDGET, ..ReadOptions::default() }
}

/// `n` rounded down to a power of two, so summaries vary little with sizes.
fn bucket(n: u64) -> u64 {
    if n == 0 { 0 } else { 1 << n.ilog2() }
}

/// Where the `.oct` header keeps the flags, the payload length and the CRC-32
/// (`docs/FORMAT.md`).
const OCT_FLAGS_AT: usize = 10;
const OCT_PAYLOAD_LEN_AT: usize = 64;
const OCT_CRC_AT: usize = 72;
/// The `.oct` flag of a surface section after the payload.
const OCT_SURFACE_FLAG: u8 = 1;
/// A surface section's header and checksum: its body length sits at 16.
const SURFACE_HEADER_BYTES: usize = 24;

/// `bytes` with the `.oct` header's payload length and CRC-32 made to match the file
/// (the CRC covers the header before it and the payload), so that a mutated file gets
/// past those two checks to the fields and nodes behind them; shorter than a header,
/// unchanged. With the surface flag set and a payload length that fits, the payload
/// keeps its length and the section after it gets its body length and CRC-32 fixed,
/// so mutations reach its faces too.
#[must_use]
pub fn oct_fixed(bytes: &[u8]) -> Vec<u8> {
    let mut fixed = bytes.to_vec();
    if fixed.len() >= oct::HEADER_BYTES {
        let rest = (fixed.len() - oct::HEADER_BYTES) as u64;
        let stored = u64::from_le_bytes(fixed[OCT_PAYLOAD_LEN_AT..OCT_PAYLOAD_LEN_AT + 8].try_into().expect("8 bytes"));
        let surface = fixed[OCT_FLAGS_AT] & OCT_SURFACE_FLAG != 0 && stored <= rest;
        let payload = if surface { stored } else { rest };
        fixed[OCT_PAYLOAD_LEN_AT..OCT_PAYLOAD_LEN_AT + 8].copy_from_slice(&payload.to_le_bytes());
        let end = oct::HEADER_BYTES + payload as usize;
        let mut crc = crc32fast::Hasher::new();
        crc.update(&fixed[..OCT_CRC_AT]);
        crc.update(&fixed[oct::HEADER_BYTES..end]);
        fixed[OCT_CRC_AT..OCT_CRC_AT + 4].copy_from_slice(&crc.finalize().to_le_bytes());
        let section = &mut fixed[end..];
        if surface && section.len() >= SURFACE_HEADER_BYTES + 4 {
            let crc_at = section.len() - 4;
            let body = (crc_at - SURFACE_HEADER_BYTES) as u64;
            section[16..24].copy_from_slice(&body.to_le_bytes());
            let crc = crc32fast::hash(&section[..crc_at]);
            section[crc_at..].copy_from_slice(&crc.to_le_bytes());
        }
    }
    fixed
}

/// Decodes the file as it is, then with its length and checksum fixed
/// ([`oct_fixed`]); the outcome is the second's.
fn oct_target(bytes: &[u8]) -> Result<String> {
    let raw = oct::decode_and_metadata(bytes, Path::new("fuzz.oct"), BUDGET);
    let (tree, meta, surface) = oct::decode_and_surface(&oct_fixed(bytes), Path::new("fuzz.oct"), BUDGET)?;
    let faces = surface.map(|s| bucket(s.len() as u64));
    Ok(format!(
        "depth {} nodes ~{} {meta:?} surface faces ~{faces:?} as given {}",
        tree.depth(),
        bucket(tree.node_count() as u64),
        raw.is_ok()
    ))
}

fn mesh(bytes: &[u8], name: &str) -> Result<String> {
    let (mesh, warnings) = mesh_from_bytes(bytes, &scratch::case_path(name))?;
    Ok(format!("triangles ~{} warnings {}", bucket(mesh.triangles.len() as u64), warnings.len()))
}

fn obj(bytes: &[u8]) -> Result<String> {
    mesh(bytes, "obj")
}

fn stl(bytes: &[u8]) -> Result<String> {
    mesh(bytes, "stl")
}

fn ply(bytes: &[u8]) -> Result<String> {
    mesh(bytes, "ply")
}

fn patches(bytes: &[u8]) -> Result<String> {
    let patches = scratch::with_file(bytes, "patches", |p| read_patches(p))?;
    Ok(format!("patches ~{}", bucket(patches.len() as u64)))
}

/// The deepest `depth` the scene targets build: past it a mesh solid moved far away
/// (its triangles collapsed by rounding, so its budget estimate is near zero) takes
/// 0.5 s at depth 10, 8 s at depth 12 and longer than anyone waits at 21 (an open
/// issue).
pub const MAX_SCENE_DEPTH: i64 = 10;

/// Whether the scene text asks for a `depth` past [`MAX_SCENE_DEPTH`] anywhere (text
/// that is not TOML goes on to the reader, which refuses it).
fn too_deep(bytes: &[u8]) -> bool {
    fn deep(value: &toml::Value) -> bool {
        match value {
            toml::Value::Table(t) => {
                t.iter().any(|(k, v)| (k == "depth" && v.as_integer().is_some_and(|d| d > MAX_SCENE_DEPTH)) || deep(v))
            }
            toml::Value::Array(a) => a.iter().any(deep),
            _ => false,
        }
    }
    let table = std::str::from_utf8(bytes).ok().and_then(|text| text.parse::<toml::Table>().ok());
    table.is_some_and(|t| deep(&toml::Value::Table(t)))
}

/// The scene `.rad` cases are read against: a closed emitting room at depth 3 (its
/// solution's seeds are [`rad_seed`]s), built once.
pub fn rad_scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(|| {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 3).expect("a valid domain");
        let cube = |edge: f64| Cuboid::new(DVec3::ZERO, DVec3::splat(edge)).expect("a valid box");
        let tree = voxelize(&(cube(1.5) - cube(1.0)), domain, &VoxelizeOptions::default()).expect("a small room");
        let mut scene = Scene::new();
        scene.lights.clear();
        scene.add("room", tree, Material { kd: 1.0, emission: DVec3::ONE, ..Material::default() });
        scene
    })
}

/// A `.rad` file of [`rad_scene`] after `shots` shots (the corpus's seeds).
pub fn rad_seed(shots: u64) -> Result<Vec<u8>> {
    let options = RadiosityOptions { max_shots: Some(shots), budget: BUDGET, ..RadiosityOptions::default() };
    let solution = Radiosity::solve(rad_scene(), &options, &NoProgress)?;
    let path = scratch::case_path("rad");
    solution.write(&path)?;
    std::fs::read(&path).map_err(|source| octsolid::Error::Io { path, source })
}

/// `bytes` with its last four bytes the CRC-32 of the rest (a `.rad` file's checksum),
/// so that a mutated solution gets past it to the values; shorter than 4, unchanged.
#[must_use]
pub fn rad_fixed(bytes: &[u8]) -> Vec<u8> {
    let mut fixed = bytes.to_vec();
    if let Some(body) = fixed.len().checked_sub(4) {
        let crc = crc32fast::hash(&fixed[..body]);
        fixed[body..].copy_from_slice(&crc.to_le_bytes());
    }
    fixed
}

/// Loads the solution as it is, then with its checksum fixed ([`rad_fixed`]), for
/// [`rad_scene`]; the outcome is the second's.
fn rad_target(bytes: &[u8]) -> Result<String> {
    let load = |b: &[u8]| scratch::with_file(b, "rad", |path| Radiosity::read(path, rad_scene(), BUDGET));
    let raw = load(bytes).is_ok();
    let solution = load(&rad_fixed(bytes))?;
    let s = solution.stats();
    Ok(format!("elements {} shots ~{} as given {raw}", s.elements, bucket(s.shots)))
}

/// Decodes a shard index as it is, then with its checksum fixed ([`rad_fixed`]: the
/// last four bytes, as in a `.rad` file); the outcome is the second's. An index read
/// must encode to an index that reads back equal (version 1 in, version 2 out).
fn octs_index(bytes: &[u8]) -> Result<String> {
    let path = Path::new("fuzz.octs/index");
    let raw = ShardIndex::decode(bytes, path).is_ok();
    let index = ShardIndex::decode(&rad_fixed(bytes), path)?;
    let again = ShardIndex::decode(&index.encode(), path).expect("an index read encodes to one that reads");
    assert_eq!(again, index, "an index changed through encode and decode");
    Ok(format!(
        "level {} full ~{} shards ~{} bounds {} as given {raw}",
        index.level,
        bucket(index.full.len() as u64),
        bucket(index.shards.len() as u64),
        index.voxel_bounds().is_some()
    ))
}

/// Two finished tasks, each over every cell of its job, in one domain at depth 4: job
/// A at cell level 1, job B (a small ball in a corner) at level 2, so their shard
/// files' names differ. Their part files are the `join_part` seeds.
pub struct JoinFixture {
    /// A folder holding both jobs' shard files (hard-linked into each case).
    pub shards: PathBuf,
    /// The shard files' names.
    pub names: Vec<String>,
    /// The part files of jobs A and B.
    pub parts: [Vec<u8>; 2],
}

/// The fixture of `join_part`, made on first use in the scratch folder.
pub fn join_fixture() -> &'static JoinFixture {
    static FIXTURE: OnceLock<JoinFixture> = OnceLock::new();
    FIXTURE.get_or_init(|| {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 4).expect("a valid domain");
        let ball = |r: f64, at: f64| Sphere::new(DVec3::splat(at), r).expect("a valid sphere");
        let jobs: [(&dyn octsolid::shape::Shape, u8, &[u8]); 2] =
            [(&ball(0.8, 0.0), 1, b"fixture A"), (&ball(0.3, -0.6), 2, b"fixture B")];
        let shards = scratch::case_path("fixture");
        std::fs::create_dir_all(&shards).expect("the fixture folder can be made");
        let mut names = Vec::new();
        let parts = jobs.map(|(shape, level, source)| {
            let out = scratch::case_path("octs");
            let all = 0..Cells::count(level);
            let options =
                StreamOptions { level: Some(level), cells: Some(&all), budget: BUDGET, progress: &NoProgress, source };
            sharded::voxelize_shape(shape, domain, Metadata::default(), &out, &options).expect("a small job");
            let staging = staging_dir(&out);
            let job =
                std::fs::read_dir(&staging).expect("a staging folder").next().expect("a job").expect("a job").path();
            let mut part = Vec::new();
            for entry in std::fs::read_dir(&job).expect("the job's folder") {
                let entry = entry.expect("a file");
                let name = entry.file_name().to_string_lossy().into_owned();
                if name.starts_with("part-") {
                    part = std::fs::read(entry.path()).expect("the part");
                } else {
                    std::fs::rename(entry.path(), shards.join(&name)).expect("a shard moved");
                    names.push(name);
                }
            }
            let _ = std::fs::remove_dir_all(&staging);
            part
        });
        JoinFixture { shards, names, parts }
    })
}

/// Joins a job folder holding the case as its only part file beside the fixture's
/// shards; the folder is named by the job the case's header names (bytes 80..96).
fn join_case(bytes: &[u8]) -> Result<ShardIndex> {
    let fixture = join_fixture();
    let out = scratch::case_path("octs");
    let staging = staging_dir(&out);
    let job: String = bytes.get(80..96).unwrap_or(&[0; 16]).iter().map(|b| format!("{b:02x}")).collect();
    let folder = staging.join(format!("job-{job}"));
    std::fs::create_dir_all(&folder).expect("a case folder can be made");
    for name in &fixture.names {
        let (from, to) = (fixture.shards.join(name), folder.join(name));
        if std::fs::hard_link(&from, &to).is_err() {
            std::fs::copy(&from, &to).expect("a shard can be copied");
        }
    }
    std::fs::write(folder.join("part-case"), bytes).expect("a case can be written");
    let joined = sharded::join(&out);
    let _ = std::fs::remove_dir_all(&staging);
    let _ = std::fs::remove_dir_all(&out);
    joined
}

/// [`join_case`] with the CRC-32 fixed (a join writes and syncs files: one join a
/// case; the checksum check itself is the index's, fuzzed by `octs_index`).
fn join_part(bytes: &[u8]) -> Result<String> {
    let fixed = rad_fixed(bytes);
    let index = join_case(&fixed)?;
    Ok(format!(
        "level {} shards ~{} checksum as given {}",
        index.level,
        bucket(index.shards.len() as u64),
        fixed == bytes
    ))
}

fn scene(bytes: &[u8]) -> Result<String> {
    if too_deep(bytes) {
        return Ok("too deep, not built".into());
    }
    let file = scratch::with_file(bytes, "toml", |path| read_scene(path, SCENE_BUDGET))?;
    Ok(format!(
        "solids {} lights {} warnings {}",
        file.scene.solids.len(),
        file.scene.lights.len(),
        file.warnings.len()
    ))
}

/// The raster visibility methods, each of which must give the ray tracer's picture.
const RASTER: [Method; 4] = [Method::FrontToBack, Method::Painter, Method::ZBuffer, Method::ScanLine];

/// Loads a scene and renders it at 8 x 6 pixels, one sample each (the file's normals,
/// shadows and ray depth kept), by the ray walk and by one raster method (picked by
/// the file's length): the two pictures must be the same, as every visibility method
/// promises.
fn scene_render(bytes: &[u8]) -> Result<String> {
    if too_deep(bytes) {
        return Ok("too deep, not built".into());
    }
    let file = scratch::with_file(bytes, "toml", |path| read_scene(path, SCENE_BUDGET))?;
    let options = RenderOptions { width: 8, height: 6, spp: 1, budget: SCENE_BUDGET, ..file.options };
    let (traced, stats) = render(&file.scene, &file.camera, &options, &NoProgress)?;
    let method = RASTER[bytes.len() % RASTER.len()];
    let (drawn, _) = render(&file.scene, &file.camera, &RenderOptions { method, ..options }, &NoProgress)?;
    let proper = proper_camera(&file.camera);
    assert!(traced == drawn || !proper, "{method:?} and the ray walk give different pictures");
    Ok(format!("hits {} secondary {} proper camera {proper}", bucket(stats.hits), bucket(stats.secondary_rays)))
}

/// Whether `camera` is one the scene reader should accept: finite, an eye apart from
/// the target, an up not along the view, a field of view in 1..=170 degrees or a view
/// height of at least 1e-6 of the eye's distance. The reader still lets some others
/// through (an orthographic `height = -0`, a NaN `fov`: open issues), and on those
/// the visibility methods need not agree.
fn proper_camera(camera: &Camera) -> bool {
    let view = camera.target - camera.eye;
    let distance = view.length();
    let finite = camera.eye.is_finite() && camera.target.is_finite() && camera.up.is_finite();
    let projection = match camera.projection {
        Projection::Perspective { fov_y } => (1.0..=170.0).contains(&fov_y),
        Projection::Orthographic { height } => height.is_finite() && height >= 1e-6 * distance,
    };
    finite && distance > 0.0 && view.normalize().cross(camera.up.normalize_or_zero()).length() > 1e-6 && projection
}

fn summary(solids: &Solids) -> String {
    let nodes: usize = solids.solids.iter().map(|s| s.tree.node_count()).sum();
    format!("depth {} solids {} nodes ~{}", solids.domain.depth(), solids.solids.len(), bucket(nodes as u64))
}

fn vox_target(bytes: &[u8]) -> Result<String> {
    Ok(summary(&vox::decode(bytes, Path::new("fuzz.vox"), &read_options())?))
}

fn binvox_target(bytes: &[u8]) -> Result<String> {
    let tree = binvox::decode(bytes, Path::new("fuzz.binvox"), BUDGET)?;
    Ok(format!("depth {} nodes ~{}", tree.depth(), bucket(tree.node_count() as u64)))
}

fn vdb_target(bytes: &[u8]) -> Result<String> {
    Ok(summary(&vdb::decode(bytes, Path::new("fuzz.vdb"), &read_options())?))
}

/// Decodes a solid file of any format octsolid reads, told by its first bytes (an
/// `.oct` file with its length and checksum fixed, [`oct_fixed`]).
fn decode_solids(bytes: &[u8]) -> Result<Solids> {
    if bytes.starts_with(&oct::MAGIC) {
        let tree = oct::decode(&oct_fixed(bytes), Path::new("fuzz.oct"), BUDGET)?;
        Ok(Solids { domain: *tree.domain(), solids: vec![octsolid::io::ColouredSolid::new("oct", None, tree)] })
    } else if bytes.starts_with(b"VOX ") {
        vox::decode(bytes, Path::new("fuzz.vox"), &read_options())
    } else if bytes.starts_with(b"#binvox") {
        let tree = binvox::decode(bytes, Path::new("fuzz.binvox"), BUDGET)?;
        Ok(Solids { domain: *tree.domain(), solids: vec![octsolid::io::ColouredSolid::new("binvox", None, tree)] })
    } else {
        vdb::decode(bytes, Path::new("fuzz.vdb"), &read_options())
    }
}

/// Whether `domain` is one whose round trips are asserted: its far corner finite and
/// its voxel edge a normal float. The `.oct` and other readers still accept domains
/// past these (an edge of `5e-324` whose voxels are 0 wide, a corner at `1e308` whose
/// far corner is infinite: an open issue), which `.vdb` then cannot read back.
fn proper_domain(domain: &octsolid::octree::Domain) -> bool {
    (domain.min() + glam::DVec3::splat(domain.edge())).is_finite() && domain.voxel_size() >= f64::MIN_POSITIVE
}

/// The deepest solid the `solid_export` target measures.
pub const MAX_MEASURED_DEPTH: u8 = 10;

/// Decodes a solid file, checks every solid and measures their union (up to
/// [`MAX_MEASURED_DEPTH`]), writes the union to `.oct`
/// and reads it back (it must be the same solid), writes all of them to `.vdb` and
/// reads the first four back by name (each the same solid), and builds `.glb`, `.vox` and (small) binvox
/// output.
fn solid_export(bytes: &[u8]) -> Result<String> {
    let solids = decode_solids(bytes)?;
    solids.validate()?;
    let union = solids.union();
    let components = if union.depth() <= MAX_MEASURED_DEPTH {
        let measures = union.measure();
        assert!(measures.volume >= 0.0 || measures.volume.is_nan(), "negative volume {}", measures.volume);
        measures.components
    } else {
        0
    };
    // What octsolid writes it must read back, as it was: asserted for proper domains.
    let proper = proper_domain(&solids.domain);
    match oct::decode(&oct::encode(&union), Path::new("again.oct"), MemoryBudget::unlimited()) {
        Ok(again) => assert!(again == union, ".oct round trip changed the solid"),
        Err(e) => assert!(!proper, ".oct cannot read what it wrote: {e}"),
    }
    let vdb_bytes = vdb::encode(&solids, vdb::Compression::Zip, EXPORT_BUDGET).unwrap_or_default();
    for solid in solids.solids.iter().take(4).filter(|_| !vdb_bytes.is_empty()) {
        let options =
            ReadOptions { budget: MemoryBudget::unlimited(), grid: Some(solid.name.clone()), ..ReadOptions::default() };
        match vdb::decode(&vdb_bytes, Path::new("again.vdb"), &options) {
            Ok(back) => {
                assert!(back.solids.len() == 1, ".vdb read {} grids by the name {:?}", back.solids.len(), solid.name);
                assert!(back.solids[0].tree == solid.tree || !proper, ".vdb round trip changed solid {:?}", solid.name);
            }
            Err(e) => assert!(!proper, ".vdb cannot read what it wrote: {e}"),
        }
    }
    let mesh = try_boundary_mesh(&union, &BoundaryOptions::default(), EXPORT_BUDGET, &NoProgress);
    let glb = gltf::encode(&solids, Axis::Z, EXPORT_BUDGET).map(|b| b.len());
    let vox = vox::encode(&solids, EXPORT_BUDGET).map(|b| b.len());
    let binvox = union.domain().resolution() <= 256 && binvox::encode(&union, EXPORT_BUDGET).is_ok();
    Ok(format!(
        "{} components {} mesh {} glb {} vox {} vdb {} binvox {}",
        summary(&solids),
        components,
        mesh.is_ok(),
        glb.is_ok(),
        vox.is_ok(),
        !vdb_bytes.is_empty(),
        binvox
    ))
}

/// The format of a mesh file told by its content: `ply` first, STL by `solid` or by
/// a binary STL's exact size, else OBJ.
fn sniff_mesh(bytes: &[u8]) -> &'static str {
    let binary_stl = bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]);
        bytes.len() as u64 == 84 + 50 * u64::from(n)
    };
    if bytes.starts_with(b"ply") {
        "ply"
    } else if bytes.starts_with(b"solid") || binary_stl {
        "stl"
    } else {
        "obj"
    }
}

/// The most triangles the `mesh_voxelize` target voxelizes.
pub const MAX_VOXELIZED_TRIANGLES: usize = 256;

/// Loads a mesh, reports it, and when it has at most [`MAX_VOXELIZED_TRIANGLES`]
/// voxelizes it as a solid (depth 5), a surface and a thin shell (depth 4), and, when
/// it is closed, as a `MeshShape` (depth 4).
fn mesh_voxelize(bytes: &[u8]) -> Result<String> {
    let (mesh, _) = mesh_from_bytes(bytes, &scratch::case_path(sniff_mesh(bytes)))?;
    let report = PolygonTables::new(&mesh).report();
    if mesh.triangles.len() > MAX_VOXELIZED_TRIANGLES {
        return Ok(format!("{} not voxelized closed {}", sniff_mesh(bytes), report.watertight));
    }
    let input = Input::Mesh(mesh);
    let options = |fill| ImportOptions { fill, budget: BUDGET, ..ImportOptions::default() };
    let solid = voxelize_input(&input, default_domain(&input, 5)?, &options(Fill::Solid));
    let surface = voxelize_input(&input, default_domain(&input, 4)?, &options(Fill::Surface));
    let thin = voxelize_input(&input, default_domain(&input, 4)?, &options(Fill::Thin));
    let Input::Mesh(mesh) = &input else { unreachable!("made above") };
    let shape = MeshShape::new(mesh).and_then(|shape| {
        let options = VoxelizeOptions { budget: BUDGET, progress: &NoProgress };
        voxelize(&shape, default_domain(&input, 4)?, &options)
    });
    Ok(format!(
        "{} solid {} surface {} thin {} shape {} closed {}",
        sniff_mesh(bytes),
        solid.is_ok(),
        surface.is_ok(),
        thin.is_ok(),
        shape.is_ok(),
        report.watertight
    ))
}

/// The largest control point coordinate `patches_voxelize` voxelizes: past about
/// `1e154` squares overflow, and one control point at `1e200` in a 1 KB file makes the
/// patch surface voxelizer split pieces without end, past any budget (an open issue).
pub const MAX_PATCH_COORDINATE: f64 = 1e150;

/// Loads a patch set, voxelizes it as a surface (depth 5) and as a solid of its
/// tessellation (depth 4), and reports that tessellation.
fn patches_voxelize(bytes: &[u8]) -> Result<String> {
    let input = Input::Patches(scratch::with_file(bytes, "patches", |p| read_patches(p))?);
    let bounds = input.bounds();
    if bounds.min.abs().max(bounds.max.abs()).max_element() > MAX_PATCH_COORDINATE {
        return Ok("not voxelized".into());
    }
    let options = |fill| ImportOptions { fill, budget: BUDGET, ..ImportOptions::default() };
    let surface = voxelize_input(&input, default_domain(&input, 5)?, &options(Fill::Surface));
    let domain = default_domain(&input, 4)?;
    let solid = voxelize_input(&input, domain, &options(Fill::Solid));
    let mesh = input.triangles(domain.voxel_size(), BUDGET)?;
    let report = PolygonTables::new(&mesh).report();
    Ok(format!("surface {} solid {} closed {}", surface.is_ok(), solid.is_ok(), report.watertight))
}
