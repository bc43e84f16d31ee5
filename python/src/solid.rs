//! `Solid`: a linear octree ([`LinearOctree`], shared, never changed) with its file
//! metadata and its lazily made surface data ([`crate::surface`]), and the functions
//! that make one: `voxelize` (a shape), `from_mesh` and `load_mesh` (triangles),
//! `load` (any solid file). Every method is one or a few library calls, the ones the
//! matching `octsolid` command makes, so the answers and the files are the CLI's:
//!
//! | Python | `octsolid` | library |
//! | --- | --- | --- |
//! | `voxelize(shape, depth)` | `shape` | `Domain::around` (2% margin), `octree::voxelize` |
//! | `load_mesh(path, depth)`, `from_mesh` | `voxelize` | `import::voxelize_input` |
//! | `load(path)` | any command's input | `SolidFile::read`, its union |
//! | `a | b`, `&`, `-`, `^`; `.union(b)`, `.intersection`, `.difference`, `.symmetric_difference` | `csg` | `common_domain`, `surface::fit_with_surface`, `combine_all`, `HermiteData::combine` |
//! | `.save(path)` | `-o path` | `write_solid_file` (`.oct` with its surface data) |
//! | `.export(path)` | `export` | `surface::extract`, `separate_sheets` (STL), `write_mesh_file` (3MF in the solid's unit, upright) |
//! | `.transform(...)` | `transform` | `Motion`, `surface::transform_with_surface` |
//! | `.offset`, `.shell`, `.round` | `offset`, `shell`, `round` | `LinearOctree::offset`, `shell`, `round` |
//! | `.measure()` | `info` | `LinearOctree::measure` |
//!
//! The GIL is released (`Python::detach`) for every step that voxelizes, combines,
//! moves, meshes, measures or touches a file. The calls that do long work take
//! `memory_budget=` (the CLI's `--memory-budget`, [`crate::budget`]) and most take
//! `progress=` (a bar or a callable, [`crate::progress`]), made ready and run by a
//! [`crate::job::Job`]; the operators use the default budget, the named set operations take one (the whole job's, as `octsolid
//! csg` counts it: the operands held, the result made beside them).

use std::path::PathBuf;
use std::sync::Arc;

use numpy::ndarray::{Array2, Array3, ArrayView1};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray2};
use octsolid::glam::DVec3;
use octsolid::import::{self, Fill, ImportOptions, Input};
use octsolid::io::oct::Metadata;
use octsolid::io::{ReadOptions, SolidsRef, WriteOptions};
use octsolid::mesh::{InsideRule, TriangleMesh, separate_sheets};
use octsolid::octree::{
    Clipping, Domain, LinearOctree, Metric, Motion, OffsetOptions, SetOp, Turn, VoxelizeOptions, common_domain,
    voxelize as voxelize_shape,
};
use octsolid::render::{CameraRequest, RenderOverrides, Up, render_picture};
use octsolid::shape::Shape as _;
use octsolid::surface::{
    DEFAULT_TOLERANCE, ExtractOptions, HermiteData, Style, extract, fit_with_surface, offset_with_surface,
    resolve_offsets, round_with_surface, shell_with_surface, transform_with_surface,
};
use octsolid::{Drawing, FileKind, MemoryBudget, NoProgress, SolidFile};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::budget::{Budget, budget_of};
use crate::errors::{ToPyResult, invalid, warn, warn_read_past};
use crate::ints::{depth_arg, optional_depth_arg, slice_size_arg};
use crate::job::Job;
use crate::progress::Want;
use crate::shapes::{Shape, axis_of};
use crate::surface::LazySurface;

/// The most voxels `Solid.to_numpy` makes an array of unless told otherwise (2^27, a
/// 512^3 grid, 128 MiB of bools).
const DENSE_LIMIT: u64 = 1 << 27;

/// A solid: the full nodes of a linear octree over a cubic domain. Combine with `|`,
/// `&`, `-` and `^` (operands over other domains are brought into one as `octsolid
/// csg` does); measure, save, export, mesh, move, offset and render it.
#[pyclass(frozen, module = "octsolid")]
pub struct Solid {
    /// The octree, shared with solids made from it and with `keys()` arrays.
    pub tree: Arc<LinearOctree>,
    /// What an `.oct` file records of its source (up axis, units).
    pub meta: Metadata,
    /// The surface data, made when first needed.
    pub surface: Arc<LazySurface>,
}

impl Solid {
    /// The surface data, made now if it was not yet (without the GIL).
    pub fn surface_data(&self, py: Python<'_>) -> PyResult<Option<Arc<HermiteData>>> {
        let (surface, tree) = (&self.surface, &self.tree);
        py.detach(|| surface.get(tree)).py()
    }

    /// The surface data as the solid's `.oct` file gives it back, to draw and mesh.
    pub fn surface_read_back(&self, py: Python<'_>) -> PyResult<Option<Arc<HermiteData>>> {
        let (surface, tree) = (&self.surface, &self.tree);
        py.detach(|| surface.as_read_back(tree)).py()
    }

    /// The solid's drawing with its surface data as its `.oct` file gives it back (what
    /// `octsolid render` of that file draws), made without the GIL.
    pub fn drawing(&self, py: Python<'_>) -> PyResult<Drawing> {
        let surface = self.surface_read_back(py)?;
        let up = Up::Axis(self.meta.up.unwrap_or(octsolid::shape::Axis::Z));
        let tree = &self.tree;
        py.detach(|| {
            let mut drawing = Drawing::of_solid((**tree).clone(), "solid", up)?;
            if let Some(surface) = surface {
                drawing = drawing.with_surface((*surface).clone());
            }
            Ok(drawing)
        })
        .py()
    }

    /// The set operation `op` of `operands`, as `octsolid csg` makes it (module doc),
    /// within `budget` as the whole job's (the operands are held while they are fitted
    /// into one domain and the result is made beside them).
    fn combine(py: Python<'_>, op: SetOp, operands: &[&Solid], budget: MemoryBudget) -> PyResult<Solid> {
        let mut trees: Vec<Arc<LinearOctree>> = operands.iter().map(|s| s.tree.clone()).collect();
        let held = |trees: &[Arc<LinearOctree>]| trees.iter().map(|t| t.bytes() as u64).sum::<u64>();
        let mut surfaces: Vec<Arc<LazySurface>> = operands.iter().map(|s| s.surface.clone()).collect();
        let target = common_domain(&trees.iter().map(|t| *t.domain()).collect::<Vec<_>>()).py()?;
        for i in 0..trees.len() {
            if *trees[i].domain() == target {
                continue;
            }
            let data = if surfaces[i].is_some() { operands[i].surface_data(py)? } else { None };
            let tree = trees[i].clone();
            let left = MemoryBudget(budget.0.saturating_sub(held(&trees)));
            let (fitted, surface) = py
                .detach(|| -> octsolid::Result<_> {
                    let options = VoxelizeOptions { budget: left, progress: &NoProgress };
                    let moved = fit_with_surface(&tree, data.as_deref(), target, &options)?;
                    Ok((moved.tree, moved.surface))
                })
                .map_err(|e| whole_job(e, held(&trees), operands.len(), budget))
                .py()?;
            trees[i] = Arc::new(fitted);
            surfaces[i] = LazySurface::ready(surface);
        }
        // The result: at most as many nodes as the operands together (what the merge reserves).
        let nodes: u64 = trees.iter().map(|t| t.node_count() as u64).sum();
        let job = format!("the {op} of {} solids of {nodes} nodes beside them", trees.len());
        budget.check(job, held(&trees).saturating_add(nodes.saturating_mul(8))).py()?;
        let operand_trees = trees.clone();
        let result = py
            .detach(|| LinearOctree::combine_all(&operand_trees.iter().map(|t| &**t).collect::<Vec<_>>(), op))
            .py()?;
        let surface = if surfaces.iter().any(|s| s.is_some()) {
            LazySurface::later(Box::new(move |result: &LinearOctree| {
                let none = HermiteData::none();
                let data = trees.iter().zip(&surfaces).map(|(t, s)| s.get(t)).collect::<octsolid::Result<Vec<_>>>()?;
                let operands: Vec<_> =
                    trees.iter().zip(&data).map(|(t, d)| (&**t, d.as_deref().unwrap_or(&none))).collect();
                HermiteData::combine(op, &operands, result).map(Some)
            }))
        } else {
            LazySurface::none()
        };
        Ok(Solid { tree: Arc::new(result), meta: operands[0].meta, surface })
    }

    /// `self` and `other` (a solid) under `op`, within `budget`.
    fn with(&self, py: Python<'_>, other: &Bound<'_, PyAny>, op: SetOp, budget: MemoryBudget) -> PyResult<Solid> {
        let other = other
            .cast::<Solid>()
            .map_err(|_| invalid("operand", "a set operation of solids needs two solids (voxelize a shape first)"))?;
        Solid::combine(py, op, &[self, other.get()], budget)
    }

    /// The solid's extracted boundary mesh, as `octsolid export` makes it
    /// (`normal_tolerance` in degrees, `--normal-tolerance`).
    fn extracted(
        &self,
        py: Python<'_>,
        style: Style,
        tolerance: f64,
        normal_tolerance: Option<f64>,
        job: Job,
    ) -> PyResult<TriangleMesh> {
        check_normal_tolerance(normal_tolerance)?;
        let hermite = self.surface_read_back(py)?;
        let tree = &self.tree;
        job.run(py, |budget, progress| {
            let hermite = hermite.as_deref().cloned().unwrap_or_else(HermiteData::none);
            let options = ExtractOptions { style, tolerance, normal_tolerance, unit_faces: false, budget };
            Ok(extract(tree, &hermite, &options, progress)?.mesh)
        })
    }

    /// An offset, shell or round as `octsolid` makes it of this solid's `.oct` file:
    /// `along` the surface data as that file gives it back when the solid has some
    /// and `metric` is the Euclidean one (the result then carries its new crossings),
    /// else `plain` on the voxels.
    fn derived_along_surface(
        &self,
        py: Python<'_>,
        what: &str,
        job: Job,
        metric: &str,
        plain: impl FnOnce(&LinearOctree, &OffsetOptions) -> octsolid::Result<LinearOctree> + Send,
        along: impl FnOnce(&LinearOctree, &HermiteData, &OffsetOptions) -> octsolid::Result<(LinearOctree, HermiteData)>
        + Send,
    ) -> PyResult<Solid> {
        let metric: Metric = metric.parse().map_err(|e: String| invalid("metric", e))?;
        let surface = if metric == Metric::Euclidean { self.surface_read_back(py)? } else { None };
        let tree = &self.tree;
        let (result, data) = job.run(py, |budget, progress| {
            let options = OffsetOptions { budget, progress, metric };
            match surface {
                Some(surface) => along(tree, &surface, &options).map(|(t, d)| (t, Some(d))),
                None => plain(tree, &options).map(|t| (t, None)),
            }
        })?;
        warn_if_clipped(py, tree, &result, what)?;
        Ok(Solid { tree: Arc::new(result), meta: self.meta, surface: LazySurface::ready(data) })
    }
}

/// Warns (`octsolid.ClippedWarning`) when the `what` of `input` lost voxels to the
/// domain ([`octsolid::octree::clipping`]), as the CLI's `offset` does.
fn warn_if_clipped(py: Python<'_>, input: &LinearOctree, result: &LinearOctree, what: &str) -> PyResult<()> {
    let message = match octsolid::octree::clipping(input, result) {
        None => return Ok(()),
        Some(Clipping::Emptied) => format!("the {what} is empty: no voxel is left"),
        Some(Clipping::AtFaces(faces)) => {
            let names = ["-x", "-y", "-z", "+x", "+y", "+z"];
            let reached: Vec<&str> = names.into_iter().zip(faces).filter(|(_, f)| *f).map(|(n, _)| n).collect();
            let d = result.domain();
            format!(
                "the {what} reaches the domain's {} face{} (min {:?}, edge {}): what lies past it is cut off; give \
                 the solid a larger domain first (solid.transform(domain=(min, edge)))",
                reached.join(", "),
                if reached.len() == 1 { "" } else { "s" },
                d.min().to_array(),
                d.edge()
            )
        }
    };
    warn(py, "ClippedWarning", &message)
}

/// A refusal of one step of a set operation, whose budget was what the operands left
/// of the job's, as the whole job's: the step's estimate beside the `n` operands'
/// `held` bytes, against the job's `budget`.
fn whole_job(e: octsolid::Error, held: u64, n: usize, budget: MemoryBudget) -> octsolid::Error {
    match e {
        octsolid::Error::OverBudget { job, estimate, .. } => octsolid::Error::OverBudget {
            job: format!("{job} beside the {n} operands' {}", octsolid::human_bytes(held)),
            estimate: estimate.saturating_add(held),
            budget: budget.0,
        },
        e => e,
    }
}

/// A style name: `"smooth"` or `"voxels"`.
fn style_of(name: &str) -> PyResult<Style> {
    match name {
        "smooth" => Ok(Style::Smooth),
        "voxels" => Ok(Style::Voxels),
        other => Err(invalid("surface", format!("{other:?} is not \"smooth\" or \"voxels\""))),
    }
}

/// A domain given as `(min, edge)` at `depth`.
fn domain_of(domain: ([f64; 3], f64), depth: u8) -> PyResult<Domain> {
    Domain::new(DVec3::from_array(domain.0), domain.1, depth).py()
}

#[pymethods]
impl Solid {
    fn __or__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Union, MemoryBudget::default())
    }
    fn __and__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Intersection, MemoryBudget::default())
    }
    fn __sub__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Difference, MemoryBudget::default())
    }
    fn __xor__(&self, py: Python<'_>, other: &Bound<'_, PyAny>) -> PyResult<Solid> {
        self.with(py, other, SetOp::SymmetricDifference, MemoryBudget::default())
    }

    /// The union `self | other`, as `octsolid csg union`; `memory_budget` (bytes, or a
    /// size like `"2GiB"`) bounds the whole job (the operands held, the result made).
    #[pyo3(signature = (other, memory_budget=None))]
    fn union(&self, py: Python<'_>, other: &Bound<'_, PyAny>, memory_budget: Option<Budget>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Union, budget_of(memory_budget))
    }

    /// The intersection `self & other`, as `octsolid csg intersection` (`memory_budget`:
    /// as `union`).
    #[pyo3(signature = (other, memory_budget=None))]
    fn intersection(&self, py: Python<'_>, other: &Bound<'_, PyAny>, memory_budget: Option<Budget>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Intersection, budget_of(memory_budget))
    }

    /// The difference `self - other`, as `octsolid csg difference` (`memory_budget`: as
    /// `union`).
    #[pyo3(signature = (other, memory_budget=None))]
    fn difference(&self, py: Python<'_>, other: &Bound<'_, PyAny>, memory_budget: Option<Budget>) -> PyResult<Solid> {
        self.with(py, other, SetOp::Difference, budget_of(memory_budget))
    }

    /// The symmetric difference `self ^ other`, as `octsolid csg xor` (`memory_budget`:
    /// as `union`).
    #[pyo3(signature = (other, memory_budget=None))]
    fn symmetric_difference(
        &self,
        py: Python<'_>,
        other: &Bound<'_, PyAny>,
        memory_budget: Option<Budget>,
    ) -> PyResult<Solid> {
        self.with(py, other, SetOp::SymmetricDifference, budget_of(memory_budget))
    }

    /// Volume in world units: full voxels times the voxel's volume.
    #[getter]
    fn volume(&self) -> f64 {
        self.tree.volume()
    }

    /// Number of full octree nodes (the solid's size in memory is 8 bytes a node).
    #[getter]
    fn node_count(&self) -> usize {
        self.tree.node_count()
    }

    /// Number of full voxels.
    #[getter]
    fn voxel_count(&self) -> u64 {
        self.tree.voxel_count()
    }

    /// The full voxels' bounding box `(min, max)`, or `None` for the empty solid.
    #[getter]
    fn bounds(&self) -> Option<([f64; 3], [f64; 3])> {
        self.tree.bounds().map(|b| (b.min.to_array(), b.max.to_array()))
    }

    /// Octree depth: the domain is 2^depth voxels a side.
    #[getter]
    fn depth(&self) -> u8 {
        self.tree.depth()
    }

    /// The domain cube `(min, edge)`.
    #[getter]
    fn domain(&self) -> ([f64; 3], f64) {
        let d = self.tree.domain();
        (d.min().to_array(), d.edge())
    }

    /// A voxel's edge in world units.
    #[getter]
    fn voxel_size(&self) -> f64 {
        self.tree.domain().voxel_size()
    }

    fn __len__(&self) -> usize {
        self.tree.node_count()
    }

    fn __repr__(&self) -> String {
        let d = self.tree.domain();
        format!(
            "<octsolid.Solid {} nodes, depth {}, volume {:.6}, domain min {:?} edge {}>",
            self.tree.node_count(),
            d.depth(),
            self.tree.volume(),
            d.min().to_array(),
            d.edge()
        )
    }

    /// Volume, boundary area, centre of mass, inertia and components, as a dict:
    /// `volume`, `area` (converging to a smooth surface's), `voxel_face_area`,
    /// `centroid` (`None` when empty), `inertia` (3x3 about the centroid), `components`.
    fn measure<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let tree = &self.tree;
        let m = py.detach(|| tree.measure());
        let dict = PyDict::new(py);
        dict.set_item("volume", m.volume)?;
        dict.set_item("area", m.surface_area)?;
        dict.set_item("voxel_face_area", m.voxel_face_area)?;
        dict.set_item("centroid", m.centre_of_mass.map(|c| c.to_array()))?;
        let inertia = m.inertia.transpose().to_cols_array_2d();
        dict.set_item(
            "inertia",
            PyArray2::from_vec2(py, &inertia.map(Vec::from)).map_err(|e| invalid("inertia", e.to_string()))?,
        )?;
        dict.set_item("components", m.components)?;
        Ok(dict)
    }

    /// Writes the solid to `path` in the format its extension names: `.oct` (with the
    /// surface data, as `octsolid` writes it), `.octs`, `.vox`, `.binvox`, `.vdb`, or
    /// its true surface as a mesh (`.obj`, `.stl`, `.ply`, `.3mf`, `.glb`, as
    /// `octsolid shape ... -o` writes them). `surface=False` leaves the `.oct` file's
    /// surface section out (a smaller file, written sooner, as the library's
    /// `oct::write`; its smooth surface is then estimated from the voxels), and a mesh's
    /// surface is estimated from the voxels. Returns the bytes written. `memory_budget`: bytes
    /// or a size like `"2GiB"` (`--memory-budget`); `progress`: `True` for a bar on the
    /// terminal, or `f(done, total)` (a mesh format's meshing; the others are written
    /// in one step, reported `(0, 1)`, `(1, 1)`).
    #[pyo3(signature = (path, surface=true, memory_budget=None, progress=None))]
    fn save(
        &self,
        py: Python<'_>,
        path: PathBuf,
        surface: bool,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
    ) -> PyResult<u64> {
        let kind = FileKind::of(&path, FileKind::SOLID_OUTPUTS).py()?;
        let surface = if kind.uses_surface() && surface { self.surface_data(py)? } else { None };
        let (tree, meta) = (&self.tree, self.meta);
        let job = Job::new(memory_budget, progress, if kind.meshes_solid() { "meshing" } else { "writing" });
        job.run(py, |budget, progress| {
            let options = WriteOptions { meta, surface, budget, ..WriteOptions::default() };
            let written = octsolid::write_solid_file(&path, &SolidsRef::of_file(&path, tree), &options, progress);
            progress.end_in_one_step();
            written
        })
    }

    /// Writes the solid's boundary as a mesh, as `octsolid export` does: `.obj`,
    /// `.stl` (vertices where voxels touch moved apart), `.ply`, `.3mf` or `.glb`;
    /// `surface` `"smooth"` (dual contouring of the surface data) or `"voxels"`;
    /// `tolerance` in voxels and `normal_tolerance` in degrees as `--tolerance` and
    /// `--normal-tolerance` (`None`: no normal bound). Returns the bytes written. `memory_budget`: bytes or a size like `"2GiB"`
    /// (`--memory-budget`); `progress`: `True` for a bar on the terminal, or `f(done,
    /// total)` (the meshing; the staircase `.glb`, written in one step, reports `(0, 1)`, `(1, 1)`).
    #[pyo3(signature = (path, surface="smooth", tolerance=DEFAULT_TOLERANCE, normal_tolerance=None, memory_budget=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn export(
        &self,
        py: Python<'_>,
        path: PathBuf,
        surface: &str,
        tolerance: f64,
        normal_tolerance: Option<f64>,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
    ) -> PyResult<u64> {
        let mesh_kinds = [FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::ThreeMf, FileKind::Glb];
        let kind = FileKind::of(&path, &mesh_kinds).py()?;
        if self.tree.is_empty() {
            return Err(crate::errors::to_py(octsolid::Error::Unwritable {
                path,
                reason: "the solid is empty; there is no boundary to export".into(),
            }));
        }
        let style = style_of(surface)?;
        let job = Job::new(memory_budget, progress, "meshing");
        if kind == FileKind::Glb && style == Style::Smooth {
            check_normal_tolerance(normal_tolerance)?;
            let hermite = self.surface_read_back(py)?;
            let (tree, up) = (&self.tree, self.meta.up.unwrap_or(octsolid::shape::Axis::Z));
            return job.run(py, |budget, progress| {
                let options = ExtractOptions { style, tolerance, normal_tolerance, unit_faces: false, budget };
                let solids = SolidsRef::of_file(&path, tree);
                Ok(octsolid::write_glb_surfaces(&path, &solids, hermite.as_deref(), &options, up, progress)?.bytes)
            });
        }
        if kind == FileKind::Glb {
            let (tree, meta) = (&self.tree, self.meta);
            return job.run(py, |budget, progress| {
                let up = meta.up.unwrap_or(octsolid::shape::Axis::Z);
                let options = WriteOptions { up, budget, mesh_style: Style::Voxels, ..WriteOptions::default() };
                let written = octsolid::write_solid_file(&path, &SolidsRef::of_file(&path, tree), &options, progress);
                progress.end_in_one_step();
                written
            });
        }
        let mesh = self.extracted(py, style, tolerance, normal_tolerance, job)?;
        let meta = self.meta;
        py.detach(|| {
            if kind == FileKind::Stl {
                let separated = separate_sheets(&mesh).map_err(|e| octsolid::Error::Unwritable {
                    path: path.clone(),
                    reason: format!("cannot write STL ({e}); write .obj or .ply"),
                })?;
                return octsolid::write_mesh_file(&separated, &path, &meta);
            }
            octsolid::write_mesh_file(&mesh, &path, &meta)
        })
        .py()
    }

    /// The boundary as numpy arrays `(vertices, faces)`: float64 `(n, 3)` and uint32
    /// `(m, 3)` (counter-clockwise seen from outside), as `.export` meshes it
    /// (`tolerance`, `normal_tolerance`, `memory_budget`, `progress`: as `.export`'s).
    #[pyo3(signature = (surface="smooth", tolerance=DEFAULT_TOLERANCE, normal_tolerance=None, memory_budget=None, progress=None))]
    fn mesh<'py>(
        &self,
        py: Python<'py>,
        surface: &str,
        tolerance: f64,
        normal_tolerance: Option<f64>,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
    ) -> PyResult<MeshArrays<'py>> {
        let style = style_of(surface)?;
        let job = Job::new(memory_budget, progress, "meshing");
        let mesh = self.extracted(py, style, tolerance, normal_tolerance, job)?;
        Ok(mesh_arrays(py, mesh))
    }

    /// The Morton keys of the full nodes, a read-only uint64 array sharing the
    /// solid's memory (no copy; see the `.oct` format for their encoding).
    fn keys<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray1<u64>>> {
        let bits = slf.get().tree.key_bits();
        let view = ArrayView1::from(bits);
        // SAFETY: the array borrows the tree's keys, which the solid holds (frozen,
        // behind an Arc, never changed) for as long as the array, whose base it is,
        // lives; the array is made read-only below.
        let array = unsafe { PyArray1::borrow_from_array(&view, slf.clone().into_any()) };
        array.getattr("flags")?.setattr("writeable", false)?;
        Ok(array)
    }

    /// The solid as a dense bool array `a[x, y, z]` of 2^depth voxels a side, refused
    /// above `max_voxels` voxels (default 2^27) or when its bytes (one a voxel) pass
    /// `memory_budget` (bytes or a size like `"2GiB"`; default half the RAM).
    #[pyo3(signature = (max_voxels=DENSE_LIMIT, memory_budget=None))]
    fn to_numpy<'py>(
        &self,
        py: Python<'py>,
        max_voxels: u64,
        memory_budget: Option<Budget>,
    ) -> PyResult<Bound<'py, PyArray3<bool>>> {
        let d = self.tree.domain();
        if d.voxel_total() > max_voxels {
            return Err(invalid(
                "to_numpy",
                format!("depth {} is {} voxels, more than max_voxels = {max_voxels}", d.depth(), d.voxel_total()),
            ));
        }
        // (A larger max_voxels used to allocate whatever it allowed: an abort.)
        budget_of(memory_budget).check(format!("a dense array of {} voxels", d.voxel_total()), d.voxel_total()).py()?;
        let n = d.resolution() as usize;
        let tree = &self.tree;
        let grid = py.detach(|| {
            let mut grid = Array3::from_elem((n, n, n), false);
            for node in tree.nodes() {
                let [x, y, z] = node.min.map(|c| c as usize);
                let s = node.size as usize;
                grid.slice_mut(numpy::ndarray::s![x..x + s, y..y + s, z..z + s]).fill(true);
            }
            grid
        });
        Ok(grid.into_pyarray(py))
    }

    /// The solid moved as `octsolid transform` moves it: scaled by `scale` about the
    /// origin, turned by each `(axis, degrees)` of `rotate` in order, moved by
    /// `translate`; exact where voxels map to voxels, else resampled. `domain` `(min,
    /// edge)` and `depth` choose the target (default: the moved domain when exact, else
    /// a cube around the moved solid, at this depth). `memory_budget`: bytes or a size
    /// like `"2GiB"` (`--memory-budget`); `progress`: `True` for a bar on the terminal,
    /// or `f(done, total)` (a resampling's).
    #[pyo3(signature = (translate=None, rotate=None, scale=1.0, domain=None, depth=None, memory_budget=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn transform(
        &self,
        py: Python<'_>,
        translate: Option<[f64; 3]>,
        rotate: Option<Vec<(Bound<'_, PyAny>, f64)>>,
        scale: f64,
        domain: Option<([f64; 3], f64)>,
        #[pyo3(from_py_with = optional_depth_arg)] depth: Option<u8>,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
    ) -> PyResult<Solid> {
        let turns = rotate
            .unwrap_or_default()
            .iter()
            .map(|(axis, degrees)| Ok(Turn { axis: axis_of(axis)?, degrees: *degrees }))
            .collect::<PyResult<Vec<_>>>()?;
        let motion = Motion { scale, turns, translate: translate.map_or(DVec3::ZERO, DVec3::from) };
        let map = motion.checked_affine().py()?;
        let data = if self.surface.is_some() { self.surface_data(py)? } else { None };
        let tree = &self.tree;
        let job = Job::new(memory_budget, progress, "resampling");
        let (moved, surface) = job.run(py, |budget, progress| {
            let target = |default: Domain| -> octsolid::Result<Domain> {
                match (domain, depth) {
                    (Some((min, edge)), d) => Domain::new(DVec3::from_array(min), edge, d.unwrap_or(default.depth())),
                    (None, Some(d)) => default.with_depth(d),
                    (None, None) => Ok(default),
                }
            };
            let options = VoxelizeOptions { budget, progress };
            let moved = transform_with_surface(tree, data.as_deref(), map, target, &options)?;
            Ok((moved.tree, moved.surface))
        })?;
        Ok(Solid { tree: Arc::new(moved), meta: self.meta, surface: LazySurface::ready(surface) })
    }

    /// The solid grown (positive `by`) or shrunk (negative) by a ball of radius `|by|`
    /// world units, as `octsolid offset --by` (`voxels=True`: `by` counts voxels).
    /// `memory_budget`: bytes or a size like `"2GiB"` (`--memory-budget`); `progress`:
    /// `True` for a bar on the terminal, or `f(done, total)` (the band's); `metric`:
    /// `"euclidean"`, `"manhattan"` or `"chebyshev"` (`--metric`: other than euclidean,
    /// over the voxels, the result without surface data).
    #[pyo3(signature = (by, voxels=false, memory_budget=None, progress=None, metric="euclidean"))]
    fn offset(
        &self,
        py: Python<'_>,
        by: f64,
        voxels: bool,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
        metric: &str,
    ) -> PyResult<Solid> {
        let d = if voxels { by } else { by * self.tree.domain().voxels_per_unit() };
        self.derived_along_surface(
            py,
            "offset",
            Job::new(memory_budget, progress, "band"),
            metric,
            |tree, options| tree.offset(d, options),
            |tree, surface, options| offset_with_surface(tree, surface, d, options),
        )
    }

    /// The solid hollowed to a wall `thickness` world units thick inside its surface
    /// (`outward=True`: outside it), as `octsolid shell` (`memory_budget`, `progress`,
    /// `metric`: as `.offset`'s).
    #[pyo3(signature = (thickness, outward=false, memory_budget=None, progress=None, metric="euclidean"))]
    fn shell(
        &self,
        py: Python<'_>,
        thickness: f64,
        outward: bool,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
        metric: &str,
    ) -> PyResult<Solid> {
        if thickness <= 0.0 {
            return Err(invalid("thickness", format!("must be positive, not {thickness}")));
        }
        let t = thickness * self.tree.domain().voxels_per_unit();
        self.derived_along_surface(
            py,
            "shell",
            Job::new(memory_budget, progress, "band"),
            metric,
            |tree, options| tree.shell(t, outward, options),
            |tree, surface, options| shell_with_surface(tree, surface, t, outward, options),
        )
    }

    /// The solid with its edges rounded to `radius` world units, as `octsolid round`:
    /// both kinds of edge unless `convex` or `concave` picks one (`memory_budget`,
    /// `progress`, `metric`: as `.offset`'s).
    #[pyo3(signature = (radius, convex=false, concave=false, memory_budget=None, progress=None, metric="euclidean"))]
    #[allow(clippy::too_many_arguments)]
    fn round(
        &self,
        py: Python<'_>,
        radius: f64,
        convex: bool,
        concave: bool,
        memory_budget: Option<Budget>,
        progress: Option<Want>,
        metric: &str,
    ) -> PyResult<Solid> {
        if radius <= 0.0 {
            return Err(invalid("radius", format!("must be positive, not {radius}")));
        }
        let (convex, concave) = if convex || concave { (convex, concave) } else { (true, true) };
        let r = radius * self.tree.domain().voxels_per_unit();
        self.derived_along_surface(
            py,
            "round",
            Job::new(memory_budget, progress, "band"),
            metric,
            |tree, options| tree.round(r, convex, concave, options),
            |tree, surface, options| round_with_surface(tree, surface, r, convex, concave, options),
        )
    }

    /// The solid's picture as PNG bytes (480x360, as `octsolid.render` draws it), so a
    /// notebook shows a solid.
    fn _repr_png_<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
        let drawing = self.drawing(py)?;
        let png = py
            .detach(|| {
                let overrides = RenderOverrides { size: Some([480, 360]), ..RenderOverrides::default() };
                let camera = drawing.camera(&CameraRequest::default(), &overrides, None)?;
                let options = drawing.options(&overrides, MemoryBudget::default());
                let picture = render_picture(&drawing.into_scene(None), &camera, &options, &NoProgress)?.0;
                octsolid::io::png::encode(&picture.to_srgb8())
            })
            .py()?;
        Ok(pyo3::types::PyBytes::new(py, &png))
    }

    /// A cross-section as an `(size, size, 3)` uint8 picture, as `octsolid slice`
    /// draws it: the plane across `axis` (`"x"`, `"y"`, `"z"`) at `at` (default: the
    /// domain's middle).
    #[pyo3(signature = (axis="z", at=None, size=768))]
    fn slice<'py>(
        &self,
        py: Python<'py>,
        axis: &str,
        at: Option<f64>,
        #[pyo3(from_py_with = slice_size_arg)] size: u32,
    ) -> PyResult<Bound<'py, PyArray3<u8>>> {
        let axis: octsolid::shape::Axis = axis.to_ascii_lowercase().parse().map_err(|e: String| invalid("axis", e))?;
        let d = self.tree.domain();
        let at = at.unwrap_or(d.min()[axis.index()] + 0.5 * d.edge());
        let tree = &self.tree;
        let image = py.detach(|| octsolid::slice::slice_image(tree, axis, at, size)).py()?;
        Ok(crate::flat::picture_array(py, image))
    }

    /// Writes the cross-section `slice` makes as a PNG file at `path`, as `octsolid
    /// slice -o` does, without a numpy array in between (so a script that only writes
    /// pictures never imports numpy); returns the bytes written.
    #[pyo3(signature = (path, axis="z", at=None, size=768))]
    fn save_slice(&self, py: Python<'_>, path: PathBuf, axis: &str, at: Option<f64>, size: u32) -> PyResult<u64> {
        let axis: octsolid::shape::Axis = axis.to_ascii_lowercase().parse().map_err(|e: String| invalid("axis", e))?;
        let d = self.tree.domain();
        let at = at.unwrap_or(d.min()[axis.index()] + 0.5 * d.edge());
        let tree = &self.tree;
        py.detach(|| octsolid::io::png::write(&octsolid::slice::slice_image(tree, axis, at, size)?, &path)).py()
    }

    /// Whether the point `p` lies in a full voxel.
    fn contains(&self, p: [f64; 3]) -> bool {
        self.tree.contains_point(DVec3::from_array(p))
    }
}

/// A mesh's vertices `(n, 3)` float64 and triangles `(m, 3)` uint32.
pub type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>);

/// A mesh as numpy arrays without copying its buffers: the vertices' `Vec<DVec3>` is
/// the `(n, 3)` float64 array's memory, the triangles' the `(m, 3)` uint32 one's.
pub fn mesh_arrays(py: Python<'_>, mesh: TriangleMesh) -> MeshArrays<'_> {
    let (n, m) = (mesh.vertices.len(), mesh.triangles.len());
    let vertices: Vec<f64> = crate::flat::vertices(mesh.vertices);
    let triangles: Vec<u32> = crate::flat::triangles(mesh.triangles);
    let vertices = Array2::from_shape_vec((n, 3), vertices).expect("3 coordinates a vertex");
    let triangles = Array2::from_shape_vec((m, 3), triangles).expect("3 corners a triangle");
    (vertices.into_pyarray(py), triangles.into_pyarray(py))
}

/// The default domain of a shape at `depth`: a cube around it with a 2% margin, as
/// `octsolid shape` makes it.
fn shape_domain(shape: &octsolid::shape::Csg, depth: u8) -> PyResult<Domain> {
    let bounds = shape.bounds().ok_or_else(|| {
        invalid("domain", "the shape is unbounded (a half-space, a complement); give domain=(min, edge)")
    })?;
    Domain::around(&bounds, 0.02, depth).py()
}

/// Voxelizes `shape` at `depth` (2^depth voxels a side) over `domain` `(min, edge)`,
/// default a cube around the shape (2% margin), as `octsolid shape` does; its offset,
/// shell and round nodes made on that lattice first (`surface::resolve_offsets`).
/// `memory_budget`: bytes or a size like `"2GiB"` (`--memory-budget`; default half the
/// RAM), a larger job refused before it starts; `progress`: `True` for a bar on the
/// terminal, or a callable `f(done, total)`.
#[pyfunction]
#[pyo3(signature = (shape, depth, domain=None, memory_budget=None, progress=None))]
pub fn voxelize(
    py: Python<'_>,
    shape: &Shape,
    #[pyo3(from_py_with = depth_arg)] depth: u8,
    domain: Option<([f64; 3], f64)>,
    memory_budget: Option<Budget>,
    progress: Option<Want>,
) -> PyResult<Solid> {
    let built = Arc::new(shape.build()?);
    let domain = match domain {
        Some(d) => domain_of(d, depth)?,
        None => shape_domain(&built, depth)?,
    };
    let (tree, built) = Job::new(memory_budget, progress, "voxelizing").run(py, |budget, progress| {
        let resolved = resolve_offsets(&built, domain, &VoxelizeOptions { budget, progress: &NoProgress })?;
        let tree = voxelize_shape(&resolved, domain, &VoxelizeOptions { budget, progress })?;
        Ok((tree, Arc::new(resolved)))
    })?;
    let surface =
        LazySurface::later(Box::new(move |tree: &LinearOctree| Ok(Some(HermiteData::from_shape(&*built, tree)))));
    Ok(Solid { tree: Arc::new(tree), meta: Metadata::default(), surface })
}

/// An inside rule by name: `"auto"`, `"parity"` or `"winding"`.
fn inside_of(name: &str) -> PyResult<InsideRule> {
    name.parse().map_err(|e: String| invalid("inside", e))
}

/// Voxelizes a loaded mesh or patch set as `octsolid voxelize` does, keeping how to
/// make its surface data.
#[allow(clippy::too_many_arguments)]
fn voxelize_input(
    py: Python<'_>,
    input: Input,
    depth: u8,
    inside: &str,
    domain: Option<([f64; 3], f64)>,
    up: octsolid::shape::Axis,
    what: &str,
    job: Job,
) -> PyResult<Solid> {
    let inside = inside_of(inside)?;
    let domain = match domain {
        Some(d) => domain_of(d, depth)?,
        None => import::default_domain(&input, depth).map_err(|e| cannot(what, e))?,
    };
    let budget = job.budget;
    let (tree, summary) = job.run_or(
        py,
        |budget, progress| {
            import::voxelize_input(&input, domain, &ImportOptions { fill: Fill::Solid, inside, budget, progress })
        },
        |e| cannot(what, e),
    )?;
    let surface = LazySurface::later(Box::new(move |tree: &LinearOctree| {
        import::surface_of_input(&input, tree, &summary, budget)
    }));
    Ok(Solid { tree: Arc::new(tree), meta: Metadata { up: Some(up), units: None }, surface })
}

/// `what: cannot voxelize: error` as an `octsolid.Error` of the error's kind.
fn cannot(what: &str, e: octsolid::Error) -> PyErr {
    let err = crate::errors::to_py(e);
    Python::attach(|py| {
        let message = format!("{what}: cannot voxelize: {}", err.value(py));
        match err.get_type(py).call1((message,)) {
            Ok(value) => PyErr::from_value(value),
            Err(e) => e,
        }
    })
}

/// `value` as a contiguous 2-D numpy array of `dtype`, refused (naming `what`)
/// when numpy cannot convert it or it is not 2-D.
fn as_2d<'py>(
    py: Python<'py>,
    value: &Bound<'py, PyAny>,
    dtype: &str,
    what: &'static str,
) -> PyResult<Bound<'py, PyAny>> {
    let array = py
        .import("numpy")?
        .call_method1("ascontiguousarray", (value, dtype))
        .map_err(|e| invalid(what, e.to_string()))?;
    if array.getattr("ndim")?.extract::<usize>()? != 2 {
        let shape: Vec<usize> = array.getattr("shape")?.extract()?;
        return Err(invalid(what, format!("need a 2-D array, not shape {shape:?}")));
    }
    Ok(array)
}

/// The solid a triangle mesh encloses: `vertices` `(n, 3)` floats, `faces` `(m, 3)`
/// integer indices, voxelized at `depth` in the cube around it (2% margin) or
/// `domain`, inside by `inside`: `"auto"`, `"parity"` (watertight) or `"winding"`
/// (`memory_budget`, `progress`: as `voxelize`'s).
#[pyfunction]
#[pyo3(signature = (vertices, faces, depth, inside="auto", domain=None, memory_budget=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn from_mesh(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    #[pyo3(from_py_with = depth_arg)] depth: u8,
    inside: &str,
    domain: Option<([f64; 3], f64)>,
    memory_budget: Option<Budget>,
    progress: Option<Want>,
) -> PyResult<Solid> {
    // Any array-like (lists, other dtypes, trimesh's tracked arrays) as numpy's own.
    let vertices = as_2d(py, vertices, "float64", "vertices")?;
    let faces = as_2d(py, faces, "int64", "faces")?;
    let vertices: PyReadonlyArray2<'_, f64> = vertices.extract()?;
    let faces: PyReadonlyArray2<'_, i64> = faces.extract()?;
    let v = vertices.as_array();
    if v.ncols() != 3 {
        return Err(invalid("vertices", format!("need shape (n, 3), not {:?}", v.shape())));
    }
    let f = faces.as_array();
    if f.ncols() != 3 {
        return Err(invalid("faces", format!("need shape (m, 3), not {:?}", f.shape())));
    }
    let n = v.nrows();
    let vertices: Vec<DVec3> = v.rows().into_iter().map(|r| DVec3::new(r[0], r[1], r[2])).collect();
    let triangles = f
        .rows()
        .into_iter()
        .enumerate()
        .map(|(i, r)| {
            let corner = |c: i64| {
                u32::try_from(c)
                    .ok()
                    .filter(|&c| (c as usize) < n)
                    .ok_or_else(|| invalid("faces", format!("face {i} names vertex {c}, outside 0..{n}")))
            };
            Ok([corner(r[0])?, corner(r[1])?, corner(r[2])?])
        })
        .collect::<PyResult<Vec<_>>>()?;
    let mesh = TriangleMesh::new(vertices, triangles).py()?;
    let job = Job::new(memory_budget, progress, "voxelizing");
    voxelize_input(py, Input::Mesh(mesh), depth, inside, domain, octsolid::shape::Axis::Z, "mesh", job)
}

/// The solid the mesh or patch file at `path` encloses (`.obj`, `.stl`, `.ply`,
/// `.patches`), voxelized as `octsolid voxelize path --depth depth` does
/// (`memory_budget`, `progress`: as `voxelize`'s).
#[pyfunction]
#[pyo3(signature = (path, depth=8, inside="auto", domain=None, memory_budget=None, progress=None))]
pub fn load_mesh(
    py: Python<'_>,
    path: PathBuf,
    #[pyo3(from_py_with = depth_arg)] depth: u8,
    inside: &str,
    domain: Option<([f64; 3], f64)>,
    memory_budget: Option<Budget>,
    progress: Option<Want>,
) -> PyResult<Solid> {
    let up = FileKind::of(&path, FileKind::SURFACES).py()?.default_up();
    let (input, warnings) = py.detach(|| Input::read_and_warnings(&path)).py()?;
    warn_read_past(py, &warnings)?;
    let job = Job::new(memory_budget, progress, "voxelizing");
    voxelize_input(py, input, depth, inside, domain, up, &path.display().to_string(), job)
}

/// The solid in the file at `path`: `.oct`, `.octs`, `.vox`, `.binvox` or `.vdb` (a
/// file of several solids gives their union), with the surface data and metadata the
/// file carries; `memory_budget`: bytes or a size like `"2GiB"` (`--memory-budget`),
/// a larger file refused before it is read.
#[pyfunction]
#[pyo3(signature = (path, memory_budget=None))]
pub fn load(py: Python<'_>, path: PathBuf, memory_budget: Option<Budget>) -> PyResult<Solid> {
    FileKind::of(&path, FileKind::SOLIDS).py()?;
    let options = ReadOptions { budget: budget_of(memory_budget), ..ReadOptions::default() };
    let mut file = py.detach(|| SolidFile::read(&path, &options)).py()?;
    let meta = file.meta;
    let surface = LazySurface::read(file.surface.take());
    Ok(Solid { tree: Arc::new(file.into_union()), meta, surface })
}

/// Refuses a `normal_tolerance` that is not an angle in degrees.
fn check_normal_tolerance(normal_tolerance: Option<f64>) -> PyResult<()> {
    match normal_tolerance {
        Some(angle) if !(angle.is_finite() && angle >= 0.0) => {
            Err(invalid("normal_tolerance", format!("{angle} is not an angle in degrees (a number, 0 or more)")))
        }
        _ => Ok(()),
    }
}
