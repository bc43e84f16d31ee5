//! [`extract`]: a solid's true surface as an indexed triangle mesh, the one road every
//! mesh leaving the octree takes (export, the mesh outputs of every command, area,
//! radiosity's patches).
//!
//! Steps ([`Style::Smooth`], the default): the dual mesh ([`super::dual`]: a vertex a
//! sheet at each boundary voxel corner, placed by its QEF in its cell), its quads cut
//! into triangles along the diagonal nearer the crossing, then positions mapped to the
//! domain. [`Style::Voxels`] is the voxels' own boundary, the staircase, bit for bit as
//! [`crate::mesh::try_boundary_mesh`] makes it.

use glam::DVec3;
use rayon::prelude::*;

use super::cluster::merge_cells;
use super::dual::{DualMesh, VertexKind};
use super::hermite::HermiteData;
use super::simplify::{SimplifyOptions, SimplifyReport, simplify_with_progress};
use super::untangle::untangle;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryOptions, BoundarySize, TriangleMesh, try_boundary_mesh};
use crate::octree::LinearOctree;
use crate::progress::{Progress, Stages, stop_if_cancelled};

/// The share of the tolerance the cell merge takes before simplification (module
/// `cluster`); simplification takes the rest.
const MERGE_SHARE: f64 = 0.25;

/// The stages' shares of the progress bar: their wall clock on the classic part at
/// depth 9 within 0.04 voxel, tenths of a second on two threads (dual contouring, the
/// untangling, the cell merge, simplification), so the bar moves evenly.
const STAGE_WEIGHTS: [u64; 4] = [10, 7, 20, 52];

/// Estimated peak bytes a boundary face with a crossing takes in the extraction (the
/// staircase's quads and sheets, the fans, the QEF's results, the triangles), beyond
/// [`FIXED_BYTES`]: the most allocated, measured on spheres at depths 6 to 9 (the
/// writers' budget test), was 272 a face.
const BYTES_PER_FACE: u64 = 320;
/// The same with simplification within 0.04 voxel (the merge and the collapses'
/// blocks): 424 a face at depth 9, 675 at depth 6.
const BYTES_PER_SIMPLIFIED_FACE: u64 = 704;
/// The same for a face without a crossing, whose vertices are estimated (relaxed, then
/// untangled): 1,105 to 1,261 a face.
const BYTES_PER_ESTIMATED_FACE: u64 = 1280;
/// Beside them, whatever the size: the smallest surfaces' tables and blocks (a sphere
/// at depth 5 took 1.6 MiB more than its faces' share).
const FIXED_BYTES: u64 = 2 << 20;

/// Which surface leaves the octree.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Style {
    /// The true surface: dual contouring of the crossings (estimated where there are
    /// none).
    #[default]
    Smooth,
    /// The voxels' boundary, the exact staircase.
    Voxels,
}

impl Style {
    /// Every style, in the order help lists them.
    pub const ALL: [Style; 2] = [Style::Smooth, Style::Voxels];

    /// The style's one spelling (`smooth`, `voxels`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Style::Smooth => "smooth",
            Style::Voxels => "voxels",
        }
    }
}

crate::spelling::spelled!(Style);

/// How [`extract`] works.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtractOptions {
    /// The smooth surface or the staircase.
    pub style: Style,
    /// The largest distance, in voxels, simplification may move the smooth surface
    /// (0: none, a vertex every boundary voxel corner).
    pub tolerance: f64,
    /// With a tolerance: the largest angle, in degrees, between a simplified face's
    /// normal and the normals of the merged mesh's faces under it (a true bound,
    /// module `simplify`); `None`: no bound.
    pub normal_tolerance: Option<f64>,
    /// [`Style::Voxels`]: one voxel face two triangles (else coplanar faces merged).
    pub unit_faces: bool,
    /// Refuse before allocating when the estimate exceeds this.
    pub budget: MemoryBudget,
}

impl ExtractOptions {
    /// Refuses a tolerance that is not a finite number of voxels, 0 or more, and a
    /// normal tolerance that is not a finite angle, 0 or more (a NaN or a negative one
    /// was taken as none).
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance >= 0.0) {
            let t = crate::error::Number(self.tolerance);
            return Err(Error::invalid("tolerance", format!("{t} is not a number of voxels, 0 or more")));
        }
        if let Some(angle) = self.normal_tolerance.filter(|a| !(a.is_finite() && *a >= 0.0)) {
            let a = crate::error::Number(angle);
            return Err(Error::invalid("normal tolerance", format!("{a} is not an angle in degrees, 0 or more")));
        }
        Ok(())
    }
}

impl Default for ExtractOptions {
    fn default() -> Self {
        ExtractOptions {
            style: Style::Smooth,
            tolerance: DEFAULT_TOLERANCE,
            normal_tolerance: None,
            unit_faces: false,
            budget: MemoryBudget::unlimited(),
        }
    }
}

/// Flat blocks of cells merged into one vertex each before simplification: Ju et al.'s
/// octree simplification (2002, section 4), each block's vertices within a quarter of
/// the tolerance of one plane (a fitted plane's distance, not a bound) and the faces
/// around it within the normal bound that distance gives the fan (module `fan_cone`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CellMerge {
    /// Blocks merged.
    pub blocks: usize,
    /// Dual contouring vertices those blocks held.
    pub vertices: usize,
    /// The largest distance of a merged vertex's original from its block's plane, in
    /// voxels.
    pub max_plane_distance: f64,
}

/// The tolerance without one given, in voxels.
pub const DEFAULT_TOLERANCE: f64 = 0.0;

/// A solid's surface and what it is made of.
#[derive(Clone, Debug)]
pub struct SurfaceMesh {
    /// The mesh: closed, oriented, manifold, in world coordinates, one vertex a sheet.
    pub mesh: TriangleMesh,
    /// The style it was made in.
    pub style: Style,
    /// What simplification did (`None` at tolerance 0 and for the staircase).
    pub simplified: Option<SimplifyReport>,
    /// What merging flat blocks of cells did before simplification (`None` when there
    /// was no simplification).
    pub merged: Option<CellMerge>,
    /// The largest distance, in voxels, from a dual contouring vertex to the tangent
    /// planes of its crossings (0 for the staircase).
    pub vertex_distance: f64,
    /// Vertices placed by their crossings' planes: smooth, on a crease, at a corner.
    pub smooth: usize,
    /// Vertices on creases.
    pub creases: usize,
    /// Vertices at corners.
    pub corners: usize,
    /// Vertices estimated from occupancy alone (no crossing on their faces).
    pub estimated: usize,
    /// Vertices whose QEF point left its cell and was clamped back.
    pub clamped: usize,
}

impl SurfaceMesh {
    /// Whether any vertex was estimated from occupancy alone.
    #[must_use]
    pub fn is_estimate(&self) -> bool {
        self.estimated > 0
    }
}

/// The surface of `tree` from the crossings of `hermite` (module doc; faces without a
/// crossing are estimated). Empty solids give an empty mesh.
///
/// # Errors
/// When the estimated memory exceeds `options.budget`, or the mesh would need more than
/// `2^32` vertices.
pub fn extract(
    tree: &LinearOctree,
    hermite: &HermiteData,
    options: &ExtractOptions,
    progress: &dyn Progress,
) -> Result<SurfaceMesh> {
    options.validate()?;
    if options.style == Style::Voxels {
        let boundary = BoundaryOptions { unit_faces: options.unit_faces };
        let mesh = try_boundary_mesh(tree, &boundary, options.budget, progress)?;
        return Ok(SurfaceMesh {
            mesh,
            style: Style::Voxels,
            simplified: None,
            merged: None,
            vertex_distance: 0.0,
            smooth: 0,
            creases: 0,
            corners: 0,
            estimated: 0,
            clamped: 0,
        });
    }
    let size = BoundarySize::of(tree);
    let simplifying = options.tolerance > 0.0;
    let bytes = peak_bytes(size, hermite, simplifying);
    options.budget.check(format!("the surface of {} boundary voxel faces", size.unit_faces), bytes)?;
    let stages = Stages::weighted(progress, &STAGE_WEIGHTS[..if simplifying { 4 } else { 2 }]);
    let mut dual = whole_stage(&stages, || DualMesh::of(tree, size, hermite))??;
    let triangles = whole_stage(&stages, || untangle(&mut dual))?;
    let domain = tree.domain();
    let (min, voxel) = (domain.min(), domain.voxel_size());
    let to_world = |positions: &[DVec3]| positions.par_iter().map(|&p| min + p * voxel).collect::<Vec<DVec3>>();
    let count = |kind| dual.kinds.iter().filter(|&&k| k == kind).count();
    let (mut simplified, mut merged) = (None, None);
    let mut mesh;
    if simplifying && !triangles.is_empty() {
        let (positions, triangles, report) =
            whole_stage(&stages, || merge_cells(&dual, &triangles, MERGE_SHARE * options.tolerance))?;
        merged = Some(CellMerge {
            blocks: report.blocks,
            vertices: report.merged_vertices,
            max_plane_distance: report.max_plane_distance,
        });
        mesh = TriangleMesh { vertices: to_world(&positions), triangles, groups: Vec::new() };
        let rest = (1.0 - MERGE_SHARE) * options.tolerance * voxel;
        let simplify_options = SimplifyOptions {
            normal_tolerance: options.normal_tolerance.map(f64::to_radians),
            ..SimplifyOptions::new(rest)
        };
        let (smaller, report) = simplify_with_progress(&mesh, &simplify_options, &stages)?;
        mesh = smaller;
        simplified = Some(report);
    } else {
        mesh = TriangleMesh { vertices: to_world(&dual.positions), triangles, groups: Vec::new() };
    }
    let surface = SurfaceMesh {
        mesh,
        simplified,
        merged,
        style: Style::Smooth,
        vertex_distance: dual.vertex_distance,
        smooth: count(VertexKind::Smooth),
        creases: count(VertexKind::Crease),
        corners: count(VertexKind::Corner),
        estimated: count(VertexKind::Estimated),
        clamped: dual.clamped.iter().filter(|&&c| c).count(),
    };
    Ok(surface)
}

/// The estimated peak bytes of [`extract`]'s smooth surface of a solid of boundary
/// `size` with the crossings of `hermite` (its faces past the crossings' count taken as
/// estimated), `simplifying` or not.
pub(crate) fn peak_bytes(size: BoundarySize, hermite: &HermiteData, simplifying: bool) -> u64 {
    let faces = u64::try_from(size.unit_faces).unwrap_or(u64::MAX);
    let exact = faces.min(hermite.len() as u64);
    let per_face = if simplifying { BYTES_PER_SIMPLIFIED_FACE } else { BYTES_PER_FACE };
    exact
        .saturating_mul(per_face)
        .saturating_add((faces - exact).saturating_mul(BYTES_PER_ESTIMATED_FACE))
        .saturating_add(FIXED_BYTES)
}

/// Runs `work` as one stage of `stages`, shown whole when it ends; `Cancelled`
/// instead of its result when the job was cancelled meanwhile.
fn whole_stage<T>(stages: &Stages, work: impl FnOnce() -> T) -> Result<T> {
    stages.start(1);
    let done = work();
    stop_if_cancelled(stages)?;
    stages.finish();
    Ok(done)
}
