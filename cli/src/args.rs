//! The command line: global flags and the subcommands (each defined with its flags in
//! `commands/`, the values they take parsed in `values`), and [`run`], which hands the
//! parsed line to its subcommand. The help text comes from these definitions.

use clap::{Parser, Subcommand};
use octsolid::MemoryBudget;

use crate::commands::{
    bench, build, convert, csg, demo, export, hull, info, join, mesh_info, offset, radiosity, render, shape, slice,
    transform, view, voxelize,
};
use crate::values::parse_bytes;

/// octsolid: solid modeling on linear octrees.
#[derive(Parser, Debug)]
#[command(name = "octsolid", version, long_about = None)]
pub struct Args {
    /// Refuse jobs whose estimated memory exceeds this (e.g. 512MiB, 8GiB; default: half the RAM).
    #[arg(long, global = true, value_parser = parse_bytes)]
    pub memory_budget: Option<u64>,

    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Voxelize a primitive shape into a solid file (.oct, .octs, .vox, .binvox, .vdb,
    /// or its true surface as .obj, .stl, .ply, .3mf, .glb).
    #[command(after_help = "Examples:\n  octsolid shape sphere --radius 1 --depth 9 -o ball.oct\n  \
octsolid shape box --size 80,40,30 --center 40,20,15 --voxel-size 0.5 -o bracket.oct")]
    Shape(shape::ShapeArgs),
    /// Combine solid files by a set operation (bringing them into one domain first).
    ///
    /// The common domain is --domain, else the smallest cube holding every input's
    /// domain; its depth --depth, else the deepest input's, or deeper where an input's
    /// voxels nest only at a finer level.
    #[command(after_help = "Example:\n  octsolid csg difference cube.oct ball.oct -o hollow.oct")]
    Csg(csg::CsgArgs),
    /// Voxelize a scene file's solid (the named one, or the union of its shape solids) to a solid file.
    #[command(after_help = "Example:\n  octsolid build scenes/gear.toml -o gear.oct")]
    Build(build::BuildArgs),
    /// Move, turn or scale a solid, or bring it into another domain or depth.
    ///
    /// The result's domain is --domain, else the moved domain when the move is exact
    /// (keys permuted, mirrored or scaled), else the cube around the moved solid; its
    /// depth --depth, else the input's.
    #[command(after_help = "Example:\n  octsolid transform hollow.oct --rotate z,45 --translate 0,0,1 -o turned.oct")]
    Transform(transform::TransformArgs),
    /// Grow (positive) or shrink (negative) a solid by a ball: every point within the
    /// distance of it, or of its outside, exact to the voxel.
    #[command(after_help = "Examples:\n  octsolid offset part.oct --by 0.2 -o grown.oct\n  \
octsolid offset part.oct --voxels -3 -o shrunk.oct")]
    Offset(offset::OffsetArgs),
    /// Hollow a solid to a wall of a thickness inside its surface (--outward: outside).
    #[command(after_help = "Example:\n  octsolid shell part.oct --thickness 2 -o wall.oct")]
    Shell(offset::ShellArgs),
    /// Round a solid's convex edges (an opening by a ball) and concave edges (a
    /// closing); --convex or --concave for one kind.
    #[command(after_help = "Example:\n  octsolid round part.oct --radius 1 -o rounded.oct")]
    Round(offset::RoundArgs),
    /// The convex hull of a solid: the hull of its voxels' corners, voxelized into the
    /// same domain, exactly.
    #[command(after_help = "Example:\n  octsolid hull part.oct -o hull.oct")]
    Hull(hull::HullArgs),
    /// Print what a solid file holds (.oct, .octs, .vox, .binvox, .vdb) and measure it
    /// (area, centre of mass, inertia, components).
    #[command(after_help = "Example:\n  octsolid info hollow.oct --json")]
    Info(info::InfoArgs),
    /// Finish a sharded job run as tasks (`--cells`): check that their parts cover
    /// every cell and write the solid's index.
    #[command(
        after_help = "Example:\n  octsolid voxelize bunny.obj --depth 11 --shard-level 3 -o bunny.octs --cells 0..256\n  \
octsolid voxelize bunny.obj --depth 11 --shard-level 3 -o bunny.octs --cells 256..512\n  octsolid join bunny.octs"
    )]
    Join(join::JoinArgs),
    /// Convert a solid file between .oct, MagicaVoxel .vox, .binvox and OpenVDB .vdb
    /// (also to .glb or a mesh), each format by its extension.
    ///
    /// The solids keep their domain unless --domain or --depth is given; then each is
    /// brought into that domain (exactly where the voxels nest, else resampled).
    /// .vox, .vdb and .glb keep several solids (a palette colour, a grid, a mesh each);
    /// .oct, .binvox and the meshes get their union.
    #[command(after_help = "Example:\n  octsolid convert hollow.oct hollow.vox")]
    Convert(convert::ConvertArgs),
    /// Draw a cross-section of a solid file (any solid format) as a PNG.
    #[command(after_help = "Example:\n  octsolid slice hollow.oct --axis z --at 0.5 --size 768 -o hollow-slice.png")]
    Slice(slice::SliceArgs),
    /// Voxelize a mesh (OBJ, STL, PLY) or a Bezier patch set (.patches) into a solid file.
    #[command(after_help = "Examples:\n  octsolid voxelize models/stanford-bunny.obj --depth 10 -o bunny.oct\n  \
octsolid voxelize part.stl --voxel-size 0.25 --units mm -o part.oct")]
    Voxelize(voxelize::VoxelizeArgs),
    /// Write the boundary of a solid as a closed, manifold triangle mesh (OBJ, STL, PLY, 3MF, GLB).
    ///
    /// Where voxels touch only along an edge or at a corner the mesh keeps one vertex
    /// for each sheet of the surface. OBJ and PLY store those vertices as they are. STL
    /// stores only positions, and readers join equal ones, so there each copy is moved
    /// by a thousandth of its shortest edge towards its own faces (more, up to a
    /// sixteenth, where f32 coordinates are too coarse for that; beyond, the export is
    /// refused). The STL reads back closed and manifold; each moved vertex changes its
    /// volume by at most the step times a third of the area of its faces (under 6e-4
    /// voxel volumes at a voxel corner of --unit-faces).
    #[command(after_help = "Example:\n  octsolid export hollow.oct -o hollow.stl")]
    Export(export::ExportArgs),
    /// Print a mesh's polygon-table diagnostics: edges, holes, non-manifold edges, volume.
    #[command(after_help = "Example:\n  octsolid mesh-info models/spot.obj --json")]
    MeshInfo(mesh_info::MeshInfoArgs),
    /// Render a scene file (.toml), a solid file (any solid format), or a mesh
    /// (voxelized first) to a picture: .png (8-bit sRGB) or .exr (linear radiance).
    #[command(after_help = "Examples:\n  octsolid render scenes/classic.toml\n  \
octsolid render models/spot.obj --front -z --view front -o spot.png\n  \
octsolid render scenes/cornell.toml --illumination radiosity -o cornell.exr")]
    Render(Box<render::RenderArgs>),
    /// Show a scene, solid file (any solid format) or mesh in the browser: orbit, zoom,
    /// pan, and a ray-traced still when the view rests (a server on 127.0.0.1; --watch
    /// reloads on save).
    #[command(after_help = "Example:\n  octsolid view scenes/classic.toml --watch")]
    View(view::ViewArgs),
    /// Solve a scene's diffuse interreflection (radiosity) and save the solution (.rad).
    #[command(after_help = "Example:\n  octsolid radiosity scenes/cornell.toml -o cornell.rad --json")]
    Radiosity(radiosity::RadiosityArgs),
    /// Octree traversal against the BVH crates obvhs and bvh: build time, bytes, rays a second.
    #[command(after_help = "Example:\n  octsolid bench --report")]
    Bench(bench::BenchArgs),
    /// Build the bundled showcase scene and render it to demo.png.
    #[command(after_help = "Example:\n  octsolid demo -o demo.png")]
    Demo(demo::DemoArgs),
}

/// Runs the parsed command line.
pub fn run(args: Args) -> anyhow::Result<()> {
    let budget = args.memory_budget.map_or_else(MemoryBudget::default, MemoryBudget);
    // The commands that make or draw something stop at Ctrl-C (module `interrupt`).
    if matches!(
        args.command,
        Command::Shape(_)
            | Command::Build(_)
            | Command::Offset(_)
            | Command::Shell(_)
            | Command::Round(_)
            | Command::Hull(_)
            | Command::Voxelize(_)
            | Command::Export(_)
            | Command::Render(_)
            | Command::Radiosity(_)
            | Command::Demo(_)
    ) {
        crate::interrupt::stop_jobs_on_ctrl_c();
    }
    match args.command {
        Command::Shape(a) => shape::run(&a, budget),
        Command::Csg(a) => csg::run(&a, budget),
        Command::Build(a) => build::run(&a, budget),
        Command::Transform(a) => transform::run(&a, budget),
        Command::Offset(a) => offset::run_offset(&a, budget),
        Command::Shell(a) => offset::run_shell(&a, budget),
        Command::Round(a) => offset::run_round(&a, budget),
        Command::Hull(a) => hull::run(&a, budget),
        Command::Info(a) => info::run(&a, budget),
        Command::Join(a) => join::run(&a),
        Command::Convert(a) => convert::run(&a, budget),
        Command::Slice(a) => slice::run(&a, budget),
        Command::Voxelize(a) => voxelize::run(&a, budget),
        Command::MeshInfo(a) => mesh_info::run(&a, budget),
        Command::Export(a) => export::run(&a, budget),
        Command::Render(a) => render::run(&a, budget),
        Command::View(a) => view::run(&a, budget),
        Command::Radiosity(a) => radiosity::run(&a, budget),
        Command::Demo(a) => demo::run(&a, budget),
        Command::Bench(a) => bench::run(&a, budget),
    }
}
