//! How `render` and `view` open what they draw: the library's [`Drawing::open_with`]
//! (a scene file, or one solid file or mesh in the library's default scene), with the
//! CLI's part around it: the read flags made into the formats' read options (warning
//! about a flag the format does not use), a spinner while a solid file is read, a
//! progress bar while a mesh is voxelized, the warnings printed, and each stage's name
//! given to [`Stages`] as the library tells it.

use std::path::Path;
use std::sync::OnceLock;

use anyhow::Result;
use octsolid::io::ReadOptions;
use octsolid::render::Up;
use octsolid::scene_file::CachePolicy;
use octsolid::{Drawing, DrawingOptions, DrawingStage, FileKind, MemoryBudget, Progress};

use crate::commands::print_warnings;
use crate::progress_bar::{Bar, Spinner};
use crate::solid_input::ReadFlags;
use crate::stages::Stages;

/// How a solid file or mesh is read for drawing: `--depth` (meshes), `--up` (it turns
/// a solid's default light) and the formats' read flags.
#[derive(Clone, Debug)]
pub(crate) struct Source {
    pub depth: Option<u8>,
    pub up: Option<Up>,
    pub read: ReadFlags,
}

/// Opens `input` (of `kind`) as `render` draws it, a scene's solids through its cache
/// as `cache` says, naming each stage in `stages` as it ends.
pub(crate) fn open(
    input: &Path,
    kind: FileKind,
    source: &Source,
    cache: CachePolicy,
    budget: MemoryBudget,
    stages: &mut Stages,
) -> Result<Drawing> {
    // A sharded solid is read with the formats' defaults: its flags are the others'.
    let read = if FileKind::SOLIDS.contains(&kind) && kind != FileKind::Octs {
        source.read.options(input, kind, budget)?
    } else {
        ReadOptions::default()
    };
    let mut spinner = FileKind::SOLIDS.contains(&kind).then(|| Spinner::new("reading"));
    let progress = LazyBar("voxelizing", OnceLock::new());
    let options = DrawingOptions { depth: source.depth, up: source.up, read, cache, budget, progress: &progress };
    let drawing = Drawing::open_with(input, &options, &mut |stage| match stage {
        DrawingStage::Read { warnings, coarsened } => {
            spinner = None;
            print_warnings(warnings);
            if let Some((from, depth)) = coarsened {
                warn!("{}: drawn at depth {depth} (its {from} does not fit the memory budget)", input.display());
            }
            stages.done("loading");
        }
        DrawingStage::Voxelized => stages.done("voxelizing"),
        DrawingStage::SceneBuilt => stages.done("building the traversal"),
        DrawingStage::SceneLoaded { warnings, hits, misses } => {
            print_warnings(warnings);
            let solids = |n: usize| if n == 1 { "1 solid".to_owned() } else { format!("{n} solids") };
            stages.done(match (hits, misses) {
                (0, _) => "loading and voxelizing the scene".to_owned(),
                (hits, 0) => format!("loading the scene ({} from its cache)", solids(hits)),
                (hits, misses) => format!("loading the scene ({} from its cache, {misses} voxelized)", solids(hits)),
            });
        }
        _ => {}
    })?;
    Ok(drawing)
}

/// A progress bar made when its work starts, so its clock starts with the work (a
/// mesh's voxelization, after the mesh is read), and never made for work without it.
struct LazyBar(&'static str, OnceLock<Bar>);

impl Progress for LazyBar {
    fn start(&self, total: u64) {
        self.1.get_or_init(|| Bar::new(self.0)).start(total);
    }
    fn advance(&self, n: u64) {
        if let Some(bar) = self.1.get() {
            bar.advance(n);
        }
    }
    fn finish(&self) {
        if let Some(bar) = self.1.get() {
            bar.finish();
        }
    }
    fn cancelled(&self) -> bool {
        crate::interrupt::interrupted()
    }
}
