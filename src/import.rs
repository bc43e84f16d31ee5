//! Solids from files: meshes (OBJ, STL, PLY) and patch sets (`.patches`), voxelized
//! as solids or surfaces. The CLI's `voxelize` and `mesh-info` are one call each here.
//! Every fill is checked against the memory budget before it starts and reports its
//! progress (the voxelizers share one driver, see [`crate::octree`]).

use std::path::Path;

use glam::DAffine3;

use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::file_kind::FileKind;
use crate::mesh::{
    BoundarySize, InsideRule, MeshReport, MeshVoxelizeOptions, PolygonTables, SurfaceKind, TriangleMesh,
    read_mesh_and_warnings, voxelize_mesh, voxelize_surface,
};
use crate::octree::{Domain, LinearOctree, VoxelizeOptions};
use crate::patch::{
    BezierPatch, estimate_tessellation_bytes, read_patches, segments_for, tessellate_with_params, tessellate_within,
    voxelize_patch_surface,
};
use crate::progress::{NoProgress, Progress};
use crate::surface::HermiteData;
use crate::warning::Warning;

/// What to make of the surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Fill {
    /// The enclosed solid.
    Solid,
    /// Every voxel the surface touches.
    Surface,
    /// A thin, 6-separating shell.
    Thin,
}

impl std::str::FromStr for Fill {
    type Err = String;
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        match s {
            "solid" => Ok(Fill::Solid),
            "surface" => Ok(Fill::Surface),
            "thin" => Ok(Fill::Thin),
            _ => Err(format!("'{s}' is not a fill (use solid, surface or thin)")),
        }
    }
}

/// A loaded input: a triangle mesh, or patches with the mesh tessellated from them.
pub enum Input {
    /// A triangle mesh.
    Mesh(TriangleMesh),
    /// Bezier patches.
    Patches(Vec<BezierPatch>),
}

impl Input {
    /// Loads a mesh or a `.patches` file by extension ([`FileKind::SURFACES`]).
    pub fn read(path: impl AsRef<Path>) -> Result<Input> {
        Input::read_and_warnings(path).map(|(input, _)| input)
    }

    /// [`Input::read`], with what the mesh loader read past
    /// ([`crate::mesh::read_mesh_and_warnings`]; a patch set has none).
    pub fn read_and_warnings(path: impl AsRef<Path>) -> Result<(Input, Vec<Warning>)> {
        let path = path.as_ref();
        Ok(match FileKind::of(path, FileKind::SURFACES)? {
            FileKind::Patches => (Input::Patches(read_patches(path)?), Vec::new()),
            _ => {
                let (mesh, warnings) = read_mesh_and_warnings(path)?;
                (Input::Mesh(mesh), warnings)
            }
        })
    }

    /// Moves the input by the affine map `map` (mesh vertices or patch control points;
    /// see [`TriangleMesh::transform`] and [`BezierPatch::transformed`] for maps that
    /// reverse orientation).
    pub fn transform(&mut self, map: DAffine3) {
        match self {
            Input::Mesh(m) => m.transform(map),
            Input::Patches(p) => p.iter_mut().for_each(|q| *q = q.transformed(map)),
        }
    }

    /// Bounding box: of the mesh, or of the patches' control points.
    #[must_use]
    pub fn bounds(&self) -> crate::aabb::Aabb {
        match self {
            Input::Mesh(m) => m.bounds(),
            Input::Patches(p) => p.iter().map(BezierPatch::bounds).reduce(|a, b| a.union(&b)).expect("patches"),
        }
    }

    /// The triangles standing for the input; patches are tessellated finely enough for
    /// a voxel of `voxel_size`, refused when that exceeds `budget`
    /// ([`crate::patch::estimate_tessellation_bytes`]).
    pub fn triangles(&self, voxel_size: f64, budget: MemoryBudget) -> Result<std::borrow::Cow<'_, TriangleMesh>> {
        Ok(match self {
            Input::Mesh(m) => std::borrow::Cow::Borrowed(m),
            Input::Patches(p) => std::borrow::Cow::Owned(tessellate_within(p, self.segments(voxel_size), budget)?),
        })
    }

    /// The segments a patch side is tessellated into for a voxel of `voxel_size` (0 for
    /// a mesh).
    fn segments(&self, voxel_size: f64) -> u32 {
        match self {
            Input::Mesh(_) => 0,
            Input::Patches(p) => {
                let extent = p.iter().map(|q| q.bounds().size().max_element()).fold(0.0, f64::max);
                segments_for(extent, voxel_size / 4.0)
            }
        }
    }

    /// Diagnostics of the mesh (patches: of a tessellation at 1/1000 of their size,
    /// refused when that exceeds `budget`).
    pub fn report(&self, budget: MemoryBudget) -> Result<MeshReport> {
        let size = self.bounds().size().max_element();
        let mesh = self.triangles(size / 1000.0, budget)?;
        Ok(PolygonTables::new(&mesh).report())
    }
}

/// What [`voxelize_input`] did.
#[derive(Clone, Debug)]
pub struct VoxelizeSummary {
    /// Triangles voxelized (0 for a patch surface, made from the patches directly).
    pub triangles: usize,
    /// Exact signed-tetrahedron volume of the triangles, for a solid of a closed
    /// mesh (`None` for surfaces and open meshes, whose signed sum depends on where
    /// the origin is and measures nothing).
    pub mesh_volume: Option<f64>,
    /// The inside rule used, for solids.
    pub rule: Option<InsideRule>,
    /// For solids: triangles left out because they bound nothing (a repeated corner,
    /// or a copy facing the other way: `TriangleMesh::solid_boundary`).
    pub void_triangles: usize,
    /// For solids: whether the mesh is closed (every edge once each way).
    pub closed: bool,
}

/// How an input is voxelized.
#[derive(Clone, Copy)]
pub struct ImportOptions<'a> {
    /// What to make of the surface.
    pub fill: Fill,
    /// The inside rule for solids.
    pub inside: InsideRule,
    /// Refuse the job when its estimated memory exceeds this.
    pub budget: MemoryBudget,
    /// Receives the voxelizer's progress.
    pub progress: &'a dyn Progress,
}

impl Default for ImportOptions<'_> {
    /// A solid by the automatic inside rule, under the default budget, no progress.
    fn default() -> Self {
        ImportOptions {
            fill: Fill::Solid,
            inside: InsideRule::Auto,
            budget: MemoryBudget::default(),
            progress: &NoProgress,
        }
    }
}

/// Voxelizes `input` into `domain` as `options.fill`.
pub fn voxelize_input(
    input: &Input,
    domain: Domain,
    options: &ImportOptions,
) -> Result<(LinearOctree, VoxelizeSummary)> {
    let ImportOptions { fill, inside, budget, progress } = *options;
    let h = domain.voxel_size();
    let options = VoxelizeOptions { budget, progress };
    if let (Input::Patches(p), Fill::Surface) = (input, fill) {
        let tree = voxelize_patch_surface(p, domain, &options)?;
        let summary = VoxelizeSummary { triangles: 0, mesh_volume: None, rule: None, void_triangles: 0, closed: false };
        return Ok((tree, summary));
    }
    let mesh = input.triangles(h, budget)?;
    match fill {
        Fill::Solid => {
            let options = MeshVoxelizeOptions { inside, budget, progress };
            let (tree, stats) = voxelize_mesh(&mesh, domain, &options)?;
            let closed = mesh.is_watertight();
            let summary = VoxelizeSummary {
                triangles: mesh.triangles.len(),
                mesh_volume: closed.then(|| mesh.volume()),
                rule: stats.rule,
                void_triangles: stats.void_triangles,
                closed,
            };
            Ok((tree, summary))
        }
        Fill::Surface | Fill::Thin => {
            let kind = if fill == Fill::Thin { SurfaceKind::Thin } else { SurfaceKind::Conservative };
            let tree = voxelize_surface(&mesh, domain, kind, &options)?;
            let summary = VoxelizeSummary {
                triangles: mesh.triangles.len(),
                mesh_volume: None,
                rule: None,
                void_triangles: 0,
                closed: false,
            };
            Ok((tree, summary))
        }
    }
}

/// The surface data of `tree`, the solid [`voxelize_input`] made of `input` with
/// `summary`: the crossings and normals of the triangles it voxelized, under the rule
/// it used ([`HermiteData::from_mesh`]; patches: their tessellation's moved onto the
/// patches, [`HermiteData::from_patches`]).
/// `None` for surfaces and thin shells, which have no inside to cross out of. Refused
/// when the estimate (the boundary faces' crossings, the triangles' hierarchy and
/// oracle) exceeds `budget`.
pub fn surface_of_input(
    input: &Input,
    tree: &LinearOctree,
    summary: &VoxelizeSummary,
    budget: MemoryBudget,
) -> Result<Option<HermiteData>> {
    let Some(rule) = summary.rule else { return Ok(None) };
    let faces = BoundarySize::of(tree).unit_faces;
    let estimate = faces.saturating_mul(FACE_BYTES).saturating_add(summary.triangles as u128 * TRIANGLE_BYTES);
    budget.check(
        format!("the crossings of {faces} boundary faces and {} triangles", summary.triangles),
        u64::try_from(estimate).unwrap_or(u64::MAX),
    )?;
    Ok(Some(match input {
        Input::Mesh(mesh) => HermiteData::from_mesh(mesh, rule, tree),
        Input::Patches(patches) => {
            // The tessellation `triangles` voxelized, with each triangle's parameters.
            let n = input.segments(tree.domain().voxel_size());
            budget.check("tessellating patches", estimate_tessellation_bytes(patches.len(), n))?;
            let (mesh, params) = tessellate_with_params(patches, n);
            HermiteData::from_patches(patches, &mesh, &params, rule, tree)
        }
    }))
}

/// Bytes a boundary face takes while its crossing is found: its key in the list of
/// faces and its crossing, kept or not.
const FACE_BYTES: u128 = 48;
/// Bytes a triangle takes while the crossings are found: the hierarchy's corners, box,
/// index and share of nodes, and the winding number's cluster and corners.
const TRIANGLE_BYTES: u128 = 300;

/// The default domain: the input's bounding cube grown by 2% on each side.
pub fn default_domain(input: &Input, depth: u8) -> Result<Domain> {
    Domain::around(&input.bounds(), 0.02, depth)
}
