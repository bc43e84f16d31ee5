//! What `render` draws and `view` shows ([`Drawn`]): a scene file, or one solid file
//! or mesh in the library's default scene ([`Scene::of_solid`], a file's coloured
//! solids in theirs, the key light turned to up either way), with what frames it and
//! the options its file gives; the camera and options come from the library's
//! [`CameraRequest`] and [`RenderOverrides`] over those, so `render`'s flags and a
//! viewer's query make the same picture.

use std::path::Path;

use anyhow::{Context, Result};
use octsolid::import::{self, ImportOptions};
use octsolid::render::{Camera, CameraRequest, Framing, RenderOptions, RenderOverrides, Scene, Section, Up};
use octsolid::scene_file::{self, SceneReadOptions};
use octsolid::{FileKind, MemoryBudget};

use crate::camera_flags::in_flags_words;
use crate::commands::{load_input, print_warnings};
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_for_display};
use crate::stages::Stages;

/// What `render` draws (and `view` shows): a scene, or one solid file in the library's
/// default scene ([`Scene::of_solid`]), with what frames it and the options its file
/// gives (the defaults for a solid).
pub(crate) struct Drawn {
    pub scene: Scene,
    framed: Framed,
    options: RenderOptions,
}

impl Drawn {
    /// Loads a scene file (through its solid cache as `load` says), a solid file or a
    /// mesh (voxelized at `source.depth`, default 9) as `render` does.
    pub(crate) fn load(
        input: &Path,
        kind: FileKind,
        source: &Source,
        load: SceneReadOptions,
        stages: &mut Stages,
    ) -> Result<Drawn> {
        if kind != FileKind::Scene {
            return solid_scene(input, kind, source, load.budget, stages);
        }
        let file = scene_file::read_scene_with(input, &load)?;
        print_warnings(&file.warnings);
        let solids = |n: usize| if n == 1 { "1 solid".to_owned() } else { format!("{n} solids") };
        stages.done(match (file.cache.hits, file.cache.misses) {
            (0, _) => "loading and voxelizing the scene".to_owned(),
            (hits, 0) => format!("loading the scene ({} from its cache)", solids(hits)),
            (hits, misses) => format!("loading the scene ({} from its cache, {misses} voxelized)", solids(hits)),
        });
        Ok(Drawn { scene: file.scene, framed: Framed::Scene(file.camera), options: file.options })
    }

    /// The camera `request` asks for at the overridden options' aspect; for a section
    /// view, turned to see the cap ([`Section::facing_the_cap`]).
    pub(crate) fn camera(
        &self,
        request: &CameraRequest,
        overrides: &RenderOverrides,
        section: Option<Section>,
    ) -> Result<Camera> {
        let aspect = overrides.aspect(&self.options);
        let camera = match &self.framed {
            Framed::Solid(framing) => request.camera(framing, aspect),
            Framed::Scene(camera) => request.camera(&self.scene.framing(*camera, request), aspect),
        }
        .map_err(in_flags_words)?;
        Ok(section.map_or(camera, |s| s.facing_the_cap(camera, request)))
    }

    /// The scene to draw, cut by `section` when there is one.
    pub(crate) fn into_scene(self, section: Option<Section>) -> Scene {
        match section {
            Some(section) => section.cut(&self.scene),
            None => self.scene,
        }
    }

    /// The render options: the file's, with the overrides, within `budget`.
    pub(crate) fn options(&self, overrides: &RenderOverrides, budget: MemoryBudget) -> RenderOptions {
        RenderOptions { budget, ..overrides.apply(self.options) }
    }
}

/// How a solid file or mesh is read for drawing: `--depth` (meshes), `--up` (it turns
/// a solid's default light) and the formats' read flags.
#[derive(Clone, Debug)]
pub(crate) struct Source {
    pub depth: Option<u8>,
    pub up: Option<Up>,
    pub read: ReadFlags,
}

/// How the camera frames what is drawn: a scene file's camera (its framing is worked
/// out for the request: the solids' silhouettes only when it re-frames), or a solid's
/// silhouette and up.
enum Framed {
    Scene(Camera),
    Solid(Framing),
}

/// The default scene of one solid file (`.oct`, `.vox`, `.binvox`, `.vdb`, or a mesh or
/// patches voxelized at `depth`): [`Scene::of_solid`], or a file's coloured solids'
/// scene, the key light turned to up either way.
fn solid_scene(
    input: &Path,
    kind: FileKind,
    source: &Source,
    budget: MemoryBudget,
    stages: &mut Stages,
) -> Result<Drawn> {
    let Source { depth, up, read } = source;
    let (tree, recorded_up, coloured) = if FileKind::SOLIDS.contains(&kind) {
        // A sharded solid gets a quarter of the budget: the picture needs the rest.
        let file = read_for_display(input, read, MemoryBudget(budget.0 / 4))?;
        stages.done("loading");
        let up = file.meta.up;
        // One solid without a colour is drawn as it always was; else each in its colour.
        if matches!(file.solids.solids.as_slice(), [one] if one.color.is_none()) {
            (file.into_union(), up, None)
        } else {
            (file.union(), up, Some(file.solids))
        }
    } else {
        let loaded = load_input(input)?;
        stages.done("loading");
        let cannot = || format!("{}: cannot voxelize", input.display());
        let domain = import::default_domain(&loaded, depth.unwrap_or(9)).with_context(cannot)?;
        let options = ImportOptions { budget, progress: &Bar::new("voxelizing"), ..Default::default() };
        let tree = import::voxelize_input(&loaded, domain, &options).with_context(cannot)?.0;
        stages.done("voxelizing");
        (tree, None, None)
    };
    let bounds = tree.bounds().with_context(|| format!("{}: the solid is empty", input.display()))?;
    let up = up.unwrap_or(Up::Axis(recorded_up.unwrap_or(kind.default_up())));
    let framing = Framing::of_solid(&tree, up);
    let name = input.display().to_string();
    let scene = match coloured {
        None => Scene::of_solid(tree, name, up),
        Some(solids) => {
            let mut scene = solids.scene(&name, &bounds);
            scene.turn_light_to_up(&bounds, up);
            scene
        }
    };
    stages.done("building the traversal");
    Ok(Drawn { scene, framed: Framed::Solid(framing), options: RenderOptions::default() })
}
