//! The benchmark's scenes: a sphere, the Stanford bunny, a Menger sponge and the classic
//! CSG part, each voxelized at a chosen depth; the bunny keeps its triangle mesh.

use std::path::Path;

use glam::DVec3;

use octsolid::MemoryBudget;
use octsolid::Result;
use octsolid::mesh::{MeshVoxelizeOptions, TriangleMesh, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::Camera;
use octsolid::samples::classic_csg;
use octsolid::shape::{Axis, Menger, Sphere};

/// The file of the bunny inside the models folder.
pub const BUNNY_FILE: &str = "stanford-bunny.obj";

/// Menger sponge level of the benchmark.
pub const MENGER_LEVEL: u32 = 4;

/// Which scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SceneKind {
    /// A ball of radius 0.9 in the cube `[-1, 1]^3`.
    Sphere,
    /// The Stanford bunny (69,451 triangles) in its bounding cube with a 2% margin.
    Bunny,
    /// A level-4 Menger sponge of edge 1.8 in the cube `[-1, 1]^3`.
    Menger,
    /// The classic CSG part ([`classic_csg`]) in the cube `[-1.1, 1.1]^3`.
    ClassicCsg,
}

impl SceneKind {
    /// All scenes, in report order.
    pub const ALL: [SceneKind; 4] = [SceneKind::Sphere, SceneKind::Bunny, SceneKind::Menger, SceneKind::ClassicCsg];

    /// Short name, e.g. `classic-csg`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SceneKind::Sphere => "sphere",
            SceneKind::Bunny => "bunny",
            SceneKind::Menger => "menger",
            SceneKind::ClassicCsg => "classic-csg",
        }
    }

    /// One line saying what the scene is.
    #[must_use]
    pub fn description(self) -> &'static str {
        match self {
            SceneKind::Sphere => "ball of radius 0.9 in the cube [-1, 1]^3",
            SceneKind::Bunny => "Stanford bunny (models/stanford-bunny.obj) in its bounding cube with a 2% margin",
            SceneKind::Menger => "level-4 Menger sponge of edge 1.8 in the cube [-1, 1]^3",
            SceneKind::ClassicCsg => "classic CSG part (cube & sphere minus three cylinders) in the cube [-1.1, 1.1]^3",
        }
    }

    /// The deepest depth the matrix runs the scene at: 12 for the sphere and the bunny;
    /// 10 for the sponge and the CSG part, whose node counts (30 and 5 million at depth
    /// 10) would grow to hundreds of millions at 12.
    #[must_use]
    pub fn max_depth(self) -> u8 {
        match self {
            SceneKind::Sphere | SceneKind::Bunny => 12,
            SceneKind::Menger | SceneKind::ClassicCsg => 10,
        }
    }

    /// The world's up axis (the bunny is y-up).
    #[must_use]
    pub fn up_axis(self) -> Axis {
        if self == SceneKind::Bunny { Axis::Y } else { Axis::Z }
    }

    /// The world's up direction, [`SceneKind::up_axis`] as a vector.
    #[must_use]
    pub fn up(self) -> DVec3 {
        self.up_axis().unit()
    }

    /// The camera's viewing direction (from the target to the eye): the default view
    /// for [`SceneKind::up_axis`].
    #[must_use]
    pub fn view(self) -> DVec3 {
        Camera::default_view(self.up_axis())
    }
}

/// A scene voxelized at one depth.
#[derive(Clone, Debug)]
pub struct BenchScene {
    /// Which scene.
    pub kind: SceneKind,
    /// The solid.
    pub tree: LinearOctree,
    /// The triangle mesh it was voxelized from, if any.
    pub mesh: Option<TriangleMesh>,
}

/// Voxelizes `kind` at `depth`; the bunny is read from `models`.
pub fn build_scene(kind: SceneKind, depth: u8, models: &Path, budget: MemoryBudget) -> Result<BenchScene> {
    let options = VoxelizeOptions { budget, ..Default::default() };
    let unit = Domain::new(DVec3::splat(-1.0), 2.0, depth)?;
    let (tree, mesh) = match kind {
        SceneKind::Sphere => (voxelize(&Sphere::new(DVec3::ZERO, 0.9)?, unit, &options)?, None),
        SceneKind::Menger => (voxelize(&Menger::new(DVec3::ZERO, 1.8, MENGER_LEVEL)?, unit, &options)?, None),
        SceneKind::ClassicCsg => {
            (voxelize(&classic_csg(), Domain::new(DVec3::splat(-1.1), 2.2, depth)?, &options)?, None)
        }
        SceneKind::Bunny => {
            let (tree, mesh) = voxelized_model(&models.join(BUNNY_FILE), depth, budget)?;
            (tree, Some(mesh))
        }
    };
    Ok(BenchScene { kind, tree, mesh })
}

/// The mesh of `path` voxelized at `depth` in its bounding cube with a 2% margin (the
/// bunny's scene, `walk_one`'s solid), and the mesh.
pub fn voxelized_model(path: &Path, depth: u8, budget: MemoryBudget) -> Result<(LinearOctree, TriangleMesh)> {
    let mesh = read_mesh(path)?;
    let domain = Domain::around(&mesh.bounds(), 0.02, depth)?;
    let (tree, _) = voxelize_mesh(&mesh, domain, &MeshVoxelizeOptions { budget, ..Default::default() })?;
    Ok((tree, mesh))
}
