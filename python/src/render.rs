//! `render`: a solid, or a drawable file (a scene `.toml`, a solid file, a mesh),
//! drawn into a numpy picture, as `octsolid render` draws it: the library's
//! [`Drawing`] (opened from the file, or [`Drawing::of_solid`] with the solid's surface
//! data, as the CLI opens a `.oct` file it saved), its camera from a
//! [`CameraRequest`], its options from [`RenderOverrides`], then
//! [`render_picture`]; `(h, w, 3)` uint8 sRGB is [`Picture::to_srgb8`], the bytes
//! the CLI's PNG holds, and `hdr=True` the linear radiance its OpenEXR holds, as float32.
//! `Solid._repr_png_` is the same render of a solid, encoded as PNG.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyReadonlyArray3};
use octsolid::glam::DVec3;
use octsolid::image::RgbImage;
use octsolid::render::{CameraRequest, Method, Picture, RenderOverrides, Up, render_picture};
use octsolid::scene_file::CachePolicy;
use octsolid::{Drawing, DrawingOptions};
use pyo3::prelude::*;

use crate::budget::Budget;
use crate::errors::warn_read_past;
use crate::errors::{ToPyResult, invalid};
use crate::ints::{optional_size_arg, optional_spp_arg};
use crate::job::Job;
use crate::progress::Want;
use crate::solid::Solid;

/// What is drawn: a solid in memory or a file.
enum Subject<'a> {
    Solid(&'a Solid),
    File(PathBuf),
}

/// The camera and picture options of a call.
struct Request {
    camera: CameraRequest,
    overrides: RenderOverrides,
    cache: bool,
    /// The budget and where the progress goes.
    job: Job,
}

/// Renders `subject` as asked, without the GIL: a file is opened (its solids built,
/// a mesh voxelized) within the call's job, so Ctrl-C and the progress reach that too.
fn picture(py: Python<'_>, subject: &Subject<'_>, request: Request) -> PyResult<Picture> {
    let (camera, overrides) = (&request.camera, &request.overrides);
    let draw = |drawing: Drawing, budget, progress: &dyn octsolid::Progress| -> octsolid::Result<Picture> {
        let camera = drawing.camera(camera, overrides, None)?;
        let options = drawing.options(overrides, budget);
        let scene = drawing.into_scene(None);
        Ok(render_picture(&scene, &camera, &options, progress)?.0)
    };
    match subject {
        Subject::File(path) => {
            let cache = if request.cache { CachePolicy::ReadWrite } else { CachePolicy::Off };
            let (picture, warnings) = request.job.run(py, |budget, progress| {
                let options = DrawingOptions { cache, budget, progress, ..DrawingOptions::default() };
                let drawing = Drawing::open(path, &options)?;
                let warnings = drawing.warnings().to_vec();
                Ok((draw(drawing, budget, progress)?, warnings))
            })?;
            warn_read_past(py, &warnings)?;
            Ok(picture)
        }
        Subject::Solid(solid) => {
            let drawing = solid.drawing(py)?;
            request.job.run(py, |budget, progress| draw(drawing, budget, progress))
        }
    }
}

/// A method by its CLI name (`trace`, `front-to-back`, `painter`, `zbuffer`, `scanline`).
fn method_of(name: &str) -> PyResult<Method> {
    Method::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| {
        let names: Vec<_> = Method::ALL.iter().map(|m| m.name()).collect();
        invalid("method", format!("{name:?} is not one of {}", names.join(", ")))
    })
}

/// Renders a solid or a file (a scene `.toml`, a solid file, a mesh) as `octsolid
/// render` does: a `(h, w, 3)` uint8 sRGB array, the PNG's pixels bit for bit, or with
/// `hdr=True` a float32 array of linear radiance (the OpenEXR's). `size` `(w, h)`
/// (default: the scene's, or 960x720); `view` a named view (`front`, `top`, `iso`,
/// ...); `eye`, `target`, `fov` (degrees); `azimuth`, `elevation`, `zoom`, `up`;
/// `spp` samples a pixel side; `method` how visibility is decided; `exposure` in stops;
/// `progress=True` a bar on the terminal while it draws (or a callable `f(done,
/// total)`); `memory_budget`: bytes or a size like `"2GiB"` (`--memory-budget`).
#[pyfunction]
#[pyo3(signature = (
    solid_or_scene, size=None, view=None, eye=None, target=None, fov=None, spp=None, method=None,
    hdr=false, azimuth=None, elevation=None, zoom=None, up=None, exposure=None, cache=true, progress=None,
    memory_budget=None
))]
#[allow(clippy::too_many_arguments)]
pub fn render<'py>(
    py: Python<'py>,
    solid_or_scene: &Bound<'py, PyAny>,
    #[pyo3(from_py_with = optional_size_arg)] size: Option<(u32, u32)>,
    view: Option<&str>,
    eye: Option<[f64; 3]>,
    target: Option<[f64; 3]>,
    fov: Option<f64>,
    #[pyo3(from_py_with = optional_spp_arg)] spp: Option<u32>,
    method: Option<&str>,
    hdr: bool,
    azimuth: Option<f64>,
    elevation: Option<f64>,
    zoom: Option<f64>,
    up: Option<&str>,
    exposure: Option<f64>,
    cache: bool,
    progress: Option<Want>,
    memory_budget: Option<Budget>,
) -> PyResult<Bound<'py, PyAny>> {
    let solid = solid_or_scene.cast::<Solid>().ok();
    let subject = match &solid {
        Some(s) => Subject::Solid(s.get()),
        None => Subject::File(
            solid_or_scene.extract().map_err(|_| invalid("solid_or_scene", "give a Solid or a file's path"))?,
        ),
    };
    let camera = CameraRequest {
        up: up.map(|u| u.parse::<Up>().map_err(|e| invalid("up", e))).transpose()?,
        eye: eye.map(DVec3::from_array),
        target: target.map(DVec3::from_array),
        fov,
        view: view.map(|v| v.parse().map_err(|e: String| invalid("view", e))).transpose()?,
        azimuth,
        elevation,
        zoom,
        ..CameraRequest::default()
    };
    let overrides = RenderOverrides {
        size: size.map(|(w, h)| [w, h]),
        spp,
        method: method.map(method_of).transpose()?,
        exposure,
        ..RenderOverrides::default()
    };
    let job = Job::new(memory_budget, progress, "render");
    let request = Request { camera, overrides, cache, job };
    let picture = picture(py, &subject, request)?;
    if hdr {
        let (w, h) = (picture.width() as usize, picture.height() as usize);
        let radiance: Vec<f32> = picture.pixels().iter().flat_map(|p| p.to_array().map(|c| c as f32)).collect();
        let array = Array3::from_shape_vec((h, w, 3), radiance).expect("3 channels a pixel");
        return Ok(array.into_pyarray(py).into_any());
    }
    Ok(crate::flat::picture_array(py, picture.to_srgb8()).into_any())
}

/// Writes an `(h, w, 3)` uint8 picture (a render, a slice) as a PNG file, as
/// `octsolid` writes its pictures; returns the bytes written.
#[pyfunction]
pub fn write_png(py: Python<'_>, path: PathBuf, picture: PyReadonlyArray3<'_, u8>) -> PyResult<u64> {
    let a = picture.as_array();
    let &[h, w, 3] = a.shape() else {
        return Err(invalid("picture", format!("need shape (h, w, 3), not {:?}", a.shape())));
    };
    // Checked before the copy (a 100000 x 100000 view aborted on allocating it).
    let max = octsolid::render::MAX_IMAGE_SIZE as usize;
    if !(1..=max).contains(&w) || !(1..=max).contains(&h) {
        return Err(invalid("picture", format!("{w}x{h} is outside 1..={max} pixels a side")));
    }
    let raw: Vec<u8> = a.iter().copied().collect();
    let (w, h) = (u32::try_from(w), u32::try_from(h));
    let image = match (w, h) {
        (Ok(w), Ok(h)) => RgbImage::from_raw(w, h, raw),
        _ => None,
    }
    .ok_or_else(|| invalid("picture", "too large"))?;
    py.detach(|| octsolid::io::png::write(&image, &path)).py()
}
