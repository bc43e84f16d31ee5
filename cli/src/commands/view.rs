//! `octsolid view INPUT [--port N] [--watch] [--bind ADDR]`: an interactive viewer in
//! the browser. A small HTTP server (bound to 127.0.0.1 unless `--bind` says
//! otherwise) serves one page, shipped inside the binary (`view_page.html`), and the
//! frames it asks for.
//!
//! Routes, all `GET`; anything else is a 404 (paths are never files), other methods
//! 405:
//! - `/`: the page.
//! - `/frame?QUERY`: a PNG, the bytes `octsolid render INPUT` writes with the flags the
//!   query names (`eye=X,Y,Z`, `target=X,Y,Z`, `up=z`, `fov=35`, `size=1280x720`,
//!   `method=front-to-back`, `spp=1`, `normals=axis`, `no-shadows=1`, `ortho=1`,
//!   `view=front`, `zoom=2`, `aa=adaptive`, `max-depth=3`, `section=x,0.25`): each key
//!   is parsed as the flag's value is (the library's `FromStr`s) into the library's
//!   camera request and option overrides that `render` builds from its flags, so a
//!   frame and a rendered file of the same flags are the same bytes.
//! - `/camera?QUERY`: the camera those flags give, as JSON (the page orbits from it).
//! - `/state`: JSON with a version counter (raised by each reload under `--watch`), the
//!   last load's error (with its file, line and column) and the solids' figures.
//!
//! Bounds: a query of at most 2,048 bytes with known keys and plain characters, at
//! most 4,096 pixels a side and 4x4 samples, coordinates within 1e9 and zooms in
//! 1e-6..1e6: anything else is a 400 with the reason, and the server goes on. A frame
//! whose estimated memory exceeds `--memory-budget` (as `render` estimates it, before
//! drawing) is a 507 with the estimate. Frames are rendered one at a time (each on
//! every core); `/state` and the page are answered meanwhile. The page keeps at most
//! one request in flight and asks only for the newest camera.
//!
//! The server (`crate::http`) answers only requests naming this machine as their host,
//! and stays up whatever clients send: its limits are in its module docs.

use std::net::{IpAddr, SocketAddr};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, SystemTime};

use anyhow::{Context, Result, anyhow};
use octsolid::io::png;
use octsolid::render::{
    AntiAliasingKind, Camera, CameraRequest, Method, NamedView, Normals, Projection, RenderOverrides, Scene, Section,
    Up,
};
use octsolid::scene_file::CachePolicy;
use octsolid::{Drawing, FileKind, MemoryBudget, NoProgress};

use crate::camera_flags::in_flags_words;
use crate::drawn::{self, Source};
use crate::http::{Request, Response, Server};
use crate::solid_input::ReadFlags;
use crate::stages::Stages;
use crate::values::{parse_finite, parse_size, parse_vec3};

/// Arguments of `octsolid view`.
#[derive(clap::Args, Debug)]
pub struct ViewArgs {
    /// Scene (.toml), solid (.oct) or mesh (.obj, .stl, .ply, .patches; voxelized first).
    pub input: PathBuf,
    /// Port to listen on (default: a free one).
    #[arg(long)]
    pub port: Option<u16>,
    /// Address to listen on; anything but a loopback address lets other machines in.
    #[arg(long, default_value = "127.0.0.1")]
    pub bind: IpAddr,
    /// Reload when the input (or a file in a scene's folder) is saved.
    #[arg(long)]
    pub watch: bool,
    /// Depth to voxelize a mesh at (default 9).
    #[arg(long)]
    pub depth: Option<u8>,
    /// The world's up, as for `render`.
    #[arg(long)]
    pub up: Option<Up>,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// The page, served at `/`.
const PAGE: &str = include_str!("view_page.html");
/// Longest query accepted, in bytes.
const MAX_QUERY: usize = 2048;
/// Largest frame side and samples a side.
const MAX_SIDE: u32 = 4096;
const MAX_SPP: u32 = 4;
/// Largest coordinate of an eye or target.
const MAX_COORDINATE: f64 = 1e9;

/// What the server shows: the last good load, its figures, and the last error.
struct Viewed {
    drawn: Option<Arc<Drawing>>,
    /// Raised at every (re)load, good or bad, so the page knows to redraw.
    version: u64,
    error: Option<String>,
    figures: serde_json::Value,
}

/// The last section view asked for, cut once for all its frames: its load's version,
/// the section and the cut scene. Its lock is held while a frame is drawn, so frames
/// are drawn one at a time.
type Cut = Option<(u64, Section, Scene)>;

/// `octsolid view INPUT [--port N] [--bind ADDR] [--watch]`
pub fn run(a: &ViewArgs, budget: MemoryBudget) -> Result<()> {
    let kind = FileKind::of(&a.input, FileKind::DRAWN)?;
    let drawn = open(a, kind, budget)?;
    let viewed = Arc::new(Mutex::new(Viewed {
        figures: figures(&drawn),
        drawn: Some(Arc::new(drawn)),
        version: 1,
        error: None,
    }));
    let server = Server::bind(SocketAddr::new(a.bind, a.port.unwrap_or(0)))?;
    let address = server.address();
    if !a.bind.is_loopback() {
        warn!("listening on {}: other machines can reach this viewer", a.bind);
    }
    out!("viewing {} at http://{address}/ (Ctrl-C stops)", a.input.display());
    if a.watch {
        let (viewed, input, source) = (Arc::clone(&viewed), a.input.clone(), source(a));
        std::thread::Builder::new()
            .spawn(move || watch(&viewed, &input, kind, &source, budget))
            .context("cannot start watching the input")?;
    }
    let (input, cut) = (a.input.clone(), Mutex::new(None));
    server.serve(move |request| {
        answer(&viewed, &cut, &input, budget, request)
            .unwrap_or_else(|Refusal(status, reason)| Response::text(status, reason))
    })
}

/// Opens the input as `render` does, a scene's solids through its cache: a reload
/// under `--watch` voxelizes only the solids whose inputs changed.
fn open(a: &ViewArgs, kind: FileKind, budget: MemoryBudget) -> Result<Drawing> {
    drawn::open(&a.input, kind, &source(a), CachePolicy::ReadWrite, budget, &mut Stages::new())
}

fn source(a: &ViewArgs) -> Source {
    Source { depth: a.depth, up: a.up, read: a.read.clone() }
}

/// A request refused: its status and why.
struct Refusal(u16, String);

type Reply = std::result::Result<Response, Refusal>;

fn answer(viewed: &Mutex<Viewed>, cut: &Mutex<Cut>, input: &Path, budget: MemoryBudget, request: &Request) -> Reply {
    if request.method != "GET" {
        return Err(Refusal(405, "only GET is served\n".into()));
    }
    let ok = |content_type, body| Ok(Response { status: 200, content_type, body });
    let (path, query) = request.path_and_query();
    match path {
        "/" => ok("text/html; charset=utf-8", PAGE.as_bytes().to_vec()),
        "/state" => {
            let viewed = viewed.lock().unwrap_or_else(PoisonError::into_inner);
            let state = serde_json::json!({
                "version": viewed.version,
                "error": viewed.error,
                "input": input.display().to_string(),
                "solids": viewed.figures,
            });
            ok("application/json", state.to_string().into_bytes())
        }
        "/frame" | "/camera" => {
            let frame = frame_query(query).map_err(|e| Refusal(400, format!("{e}\n")))?;
            let (drawn, version) = {
                let viewed = viewed.lock().unwrap_or_else(PoisonError::into_inner);
                (viewed.drawn.clone(), viewed.version)
            };
            let drawn = drawn.ok_or_else(|| Refusal(503, "nothing loaded\n".into()))?;
            let camera = drawn
                .camera(&frame.request, &frame.overrides, frame.section)
                .map_err(|e| Refusal(400, format!("{}\n", in_flags_words(e))))?;
            if path == "/camera" {
                return ok("application/json", camera_json(&camera).to_string().into_bytes());
            }
            let mut cut = cut.lock().unwrap_or_else(PoisonError::into_inner);
            let scene = match frame.section {
                None => drawn.scene(),
                Some(section) => {
                    if cut.as_ref().is_none_or(|(v, s, _)| (*v, *s) != (version, section)) {
                        *cut = Some((version, section, section.cut(drawn.scene())));
                    }
                    &cut.as_ref().expect("just cut").2
                }
            };
            let options = drawn.options(&frame.overrides, budget);
            let (bytes, _) = png::render_png(scene, &camera, &options, &NoProgress).map_err(|e| match e {
                octsolid::Error::OverBudget { .. } => Refusal(507, format!("{e}\n")),
                e => Refusal(400, format!("cannot render: {e}\n")),
            })?;
            ok("image/png", bytes)
        }
        _ => Err(Refusal(404, "not found\n".into())),
    }
}

/// What a frame query asks for: the camera, the option overrides and the section,
/// the library's types `render` builds from its flags.
#[derive(Default)]
struct Frame {
    request: CameraRequest,
    overrides: RenderOverrides,
    section: Option<Section>,
}

/// Parses a frame query (`KEY=VALUE&...`, switches `KEY=1`; see the module doc) and
/// bounds it; a key given twice, an unknown key or a bad value is refused by name.
fn frame_query(query: &str) -> Result<Frame> {
    fn value<T: std::str::FromStr<Err: std::fmt::Display>>(key: &str, v: &str) -> Result<T> {
        v.parse::<T>().map_err(|e| anyhow!("{key}: {e}"))
    }
    if query.len() > MAX_QUERY {
        anyhow::bail!("the query is longer than {MAX_QUERY} bytes");
    }
    let mut f = Frame::default();
    let mut seen = Vec::new();
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        let (key, v) = pair.split_once('=').unwrap_or((pair, ""));
        if !v.bytes().all(|b| b.is_ascii_alphanumeric() || b".,-+_".contains(&b)) {
            anyhow::bail!("{key}: '{v}' has characters no value needs");
        }
        if seen.contains(&key) {
            anyhow::bail!("{key}: given more than once");
        }
        seen.push(key);
        let number = |v: &str| parse_finite(v).map_err(|e| anyhow!("{key}: {e}"));
        let point = |v: &str| parse_vec3(v).map(glam::DVec3::from).map_err(|e| anyhow!("{key}: {e}"));
        let (r, o) = (&mut f.request, &mut f.overrides);
        match key {
            "eye" => r.eye = Some(point(v)?),
            "target" => r.target = Some(point(v)?),
            "up" => r.up = Some(value::<Up>(key, v)?),
            "fov" => r.fov = Some(number(v)?),
            "view" => r.view = Some(value::<NamedView>(key, v)?),
            "zoom" => r.zoom = Some(number(v)?),
            "ortho" => r.ortho = v != "0",
            "size" => o.size = Some(parse_size(v).map_err(|e| anyhow!("{key}: {e}"))?),
            "method" => o.method = Some(value::<Method>(key, v)?),
            "spp" => o.spp = Some(value::<u32>(key, v)?),
            "normals" => o.normals = Some(value::<Normals>(key, v)?),
            "aa" => o.aa = Some(value::<AntiAliasingKind>(key, v)?),
            "max-depth" => o.max_depth = Some(value::<u32>(key, v)?),
            "no-shadows" => o.shadows = (v != "0").then_some(false),
            "section" => f.section = Some(value::<Section>(key, v)?),
            _ => anyhow::bail!("unknown key '{key}'"),
        }
    }
    if let Some([w, h]) = f.overrides.size.filter(|&[w, h]| w > MAX_SIDE || h > MAX_SIDE) {
        anyhow::bail!("size {w}x{h}: at most {MAX_SIDE} pixels a side");
    }
    if let Some(spp) = f.overrides.spp.filter(|&n| n > MAX_SPP) {
        anyhow::bail!("spp {spp}: at most {MAX_SPP}");
    }
    for p in [f.request.eye, f.request.target].into_iter().flatten() {
        if p.abs().max_element() > MAX_COORDINATE {
            anyhow::bail!("{p}: coordinates within {MAX_COORDINATE:e}");
        }
    }
    if let Some(zoom) = f.request.zoom.filter(|z| !(1e-6..=1e6).contains(z)) {
        anyhow::bail!("zoom {zoom:e}: between 1e-6 and 1e6");
    }
    Ok(f)
}

fn camera_json(c: &Camera) -> serde_json::Value {
    let (fov, ortho_height) = match c.projection {
        Projection::Perspective { fov_y } => (Some(fov_y), None),
        Projection::Orthographic { height } => (None, Some(height)),
    };
    serde_json::json!({
        "eye": c.eye.to_array(), "target": c.target.to_array(), "up": c.up.to_array(),
        "fov": fov, "ortho_height": ortho_height,
    })
}

/// The panel's figures of each solid: nodes, voxels, volume, bounds, depth.
fn figures(drawn: &Drawing) -> serde_json::Value {
    drawn
        .scene()
        .solids
        .iter()
        .map(|s| {
            let bounds = s.tree.bounds().map(|b| [b.min.to_array(), b.max.to_array()]);
            serde_json::json!({
                "name": s.name, "nodes": s.tree.node_count(), "voxels": s.tree.voxel_count(),
                "volume": s.tree.volume(), "bounds": bounds, "depth": s.tree.domain().depth(),
            })
        })
        .collect()
}

/// Reloads when a watched file's modification time changes: the input, and for a
/// scene every file in its folder (the meshes and solids it names usually live there).
fn watch(viewed: &Mutex<Viewed>, input: &Path, kind: FileKind, source: &Source, budget: MemoryBudget) {
    let watched = || -> Vec<(PathBuf, Option<SystemTime>)> {
        let mut files = vec![input.to_path_buf()];
        if kind == FileKind::Scene {
            let folder = input.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
            if let Ok(entries) = std::fs::read_dir(folder) {
                files.extend(entries.filter_map(|e| Some(e.ok()?.path())).filter(|p| p.is_file()));
            }
        }
        files.sort();
        files.into_iter().map(|f| (f.clone(), std::fs::metadata(&f).and_then(|m| m.modified()).ok())).collect()
    };
    let mut seen = watched();
    loop {
        std::thread::sleep(Duration::from_millis(250));
        let now = watched();
        if now == seen {
            continue;
        }
        seen = now;
        let loaded = drawn::open(input, kind, source, CachePolicy::ReadWrite, budget, &mut Stages::new());
        let mut v = viewed.lock().unwrap_or_else(PoisonError::into_inner);
        v.version += 1;
        match loaded {
            Ok(drawn) => {
                v.figures = figures(&drawn);
                v.drawn = Some(Arc::new(drawn));
                v.error = None;
                out!("reloaded {}", input.display());
            }
            Err(e) => {
                let message = crate::one_line(&e);
                warn!("{message} (showing the last good load)");
                v.error = Some(message);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_query_becomes_the_librarys_request_and_overrides() {
        let f =
            frame_query("eye=1,2,3&fov=40&size=80x60&method=trace&aa=adaptive&no-shadows=1&section=x,0.25").unwrap();
        assert_eq!(f.request.eye, Some(glam::DVec3::new(1.0, 2.0, 3.0)));
        assert_eq!(f.request.fov, Some(40.0));
        assert_eq!(f.overrides.size, Some([80, 60]));
        assert_eq!(f.overrides.method, Some(Method::Trace));
        assert_eq!(f.overrides.aa, Some(AntiAliasingKind::Adaptive));
        assert_eq!(f.overrides.shadows, Some(false));
        assert_eq!(f.section.map(|s| s.at), Some(0.25));
        for (bad, says) in [
            ("method=fast", "method"),
            ("fov=1&fov=2", "more than once"),
            ("colour=red", "unknown key"),
            ("size=9000x10", "at most"),
            ("eye=1,2", "eye"),
        ] {
            let e = frame_query(bad).err().map(|e| e.to_string()).unwrap_or_default();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}
