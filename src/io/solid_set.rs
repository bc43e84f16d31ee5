//! What a solid file holds once read, whatever its format: [`Solids`], one domain and
//! the [`ColouredSolid`]s over it, and the [`ReadOptions`] every reader takes. The
//! format modules (`vox`, `vdb`, `gltf`, ...) build these, and write a [`SolidsRef`]:
//! the same, borrowed, so that a solid is written without copying its tree (a
//! [`Solids`] lends itself as one, [`Solids::borrowed`]; one tree is
//! [`SolidsRef::one`]). `solids` picks the format by extension above them all.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;

use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::{Domain, LinearOctree};
use crate::render::{Material, Scene};

/// A solid with what the file says about its look.
#[derive(Clone, Debug, PartialEq)]
pub struct ColouredSolid {
    /// A name: the grid's in `.vdb`, `colour N` for palette index `N` in `.vox`, the
    /// file's stem otherwise.
    pub name: String,
    /// Linear RGB in `[0, 1]`, when the file gives one.
    pub color: Option<DVec3>,
    /// The `.vox` palette index (1..=255) the solid came from or should go to.
    pub palette_index: Option<u8>,
    /// Material properties as the file names them (`.vox` MATL: `_type`, `_rough`,
    /// `_metal`, `_ior`, ...); empty when the file has none.
    pub material: BTreeMap<String, String>,
    /// The solid, over the shared domain.
    pub tree: LinearOctree,
}

impl ColouredSolid {
    /// A solid with a name and an optional colour, no palette index or material.
    #[must_use]
    pub fn new(name: impl Into<String>, color: Option<DVec3>, tree: LinearOctree) -> Self {
        ColouredSolid { name: name.into(), color, palette_index: None, material: BTreeMap::new(), tree }
    }
}

/// A [`ColouredSolid`] borrowed: what the writers read of a solid.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidRef<'a> {
    /// As [`ColouredSolid::name`].
    pub name: Cow<'a, str>,
    /// As [`ColouredSolid::color`].
    pub color: Option<DVec3>,
    /// As [`ColouredSolid::palette_index`].
    pub palette_index: Option<u8>,
    /// As [`ColouredSolid::material`].
    pub material: &'a BTreeMap<String, String>,
    /// The solid, over the shared domain.
    pub tree: &'a LinearOctree,
}

/// [`Solids`] borrowed: one domain and the solids over it, to be written.
#[derive(Clone, Debug, PartialEq)]
pub struct SolidsRef<'a> {
    /// The shared domain.
    pub domain: Domain,
    /// The solids, in the order they are written.
    pub solids: Vec<SolidRef<'a>>,
}

/// No material properties, for a solid that has none.
static NO_MATERIAL: BTreeMap<String, String> = BTreeMap::new();

impl<'a> SolidsRef<'a> {
    /// One solid named `name`, with an optional colour, over its own domain.
    #[must_use]
    pub fn one(name: impl Into<Cow<'a, str>>, color: Option<DVec3>, tree: &'a LinearOctree) -> Self {
        let solid = SolidRef { name: name.into(), color, palette_index: None, material: &NO_MATERIAL, tree };
        SolidsRef { domain: *tree.domain(), solids: vec![solid] }
    }

    /// One solid without a colour named by the stem of `path` (`solid` when it has
    /// none): what a file of one solid is read back as.
    #[must_use]
    pub fn of_file(path: impl AsRef<Path>, tree: &'a LinearOctree) -> Self {
        SolidsRef::one(file_stem(path.as_ref()), None, tree)
    }

    /// Checks every solid's invariants and that all share `domain` ([`Solids::validate`]).
    pub fn validate(&self) -> Result<()> {
        for s in &self.solids {
            s.tree.validate()?;
            if *s.tree.domain() != self.domain {
                return Err(Error::DomainMismatch {
                    left: self.domain.to_string(),
                    right: s.tree.domain().to_string(),
                });
            }
        }
        Ok(())
    }
}

/// What a solid file holds ([`crate::SolidFile::solids`]): one domain and the solids over it (each `tree`'s
/// domain is `domain`).
#[derive(Clone, Debug, PartialEq)]
pub struct Solids {
    /// The shared domain.
    pub domain: Domain,
    /// The solids, in the file's order (`.vox`: ascending palette index).
    pub solids: Vec<ColouredSolid>,
}

impl Solids {
    /// A scene of the solids that hold voxels, each named `"{name}: {solid}"` in its
    /// colour (the default material's where the file gives none) and its material
    /// where the file gives one (a `.vox` `MATL`: [`Material::from_magicavoxel`]),
    /// lit by the default lights around `bounds`, or, when a solid emits, by its
    /// emitters alone (as a scene file without lights).
    #[must_use]
    pub fn scene(self, name: &str, bounds: &Aabb) -> Scene {
        let mut scene = Scene::new();
        let mut emits = false;
        for solid in self.solids.into_iter().filter(|s| !s.tree.is_empty()) {
            let color = solid.color.unwrap_or(Material::default().color);
            let material = Material::from_magicavoxel(color, &solid.material);
            emits |= material.emission != DVec3::ZERO;
            scene.add(format!("{name}: {}", solid.name), solid.tree, material);
        }
        scene.lights = if emits { Vec::new() } else { Scene::default_lights(bounds) };
        scene
    }

    /// Checks every solid's invariants and that all share `domain`.
    pub fn validate(&self) -> Result<()> {
        self.borrowed().validate()
    }

    /// The solids, borrowed, to be written.
    #[must_use]
    pub fn borrowed(&self) -> SolidsRef<'_> {
        let solids = self
            .solids
            .iter()
            .map(|s| SolidRef {
                name: Cow::Borrowed(&s.name),
                color: s.color,
                palette_index: s.palette_index,
                material: &s.material,
                tree: &s.tree,
            })
            .collect();
        SolidsRef { domain: self.domain, solids }
    }

    /// The union of all solids.
    #[must_use]
    pub fn union(&self) -> LinearOctree {
        self.solids.iter().fold(LinearOctree::empty(self.domain), |acc, s| &acc | &s.tree)
    }
}

/// How files are read. `Default` is the documented behaviour of each format.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadOptions {
    /// Memory limit for what a file's header claims (checked before allocating).
    pub budget: MemoryBudget,
    /// `.vox`: world edge of one voxel (1 by default: a voxel is one world unit).
    pub voxel_size: f64,
    /// `.vox` and `.vdb`: use the domain octsolid stored in the file (so a written
    /// solid reads back with its exact domain) when it holds every voxel; `false`
    /// always fits the domain to the voxels.
    pub stored_domain: bool,
    /// `.vdb` fog volumes: a voxel is inside when its value is above this.
    pub fog_threshold: f64,
    /// `.vdb`: the grid to read by name; `None` reads the first float, double or
    /// bool grid.
    pub grid: Option<String>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            budget: MemoryBudget::default(),
            voxel_size: 1.0,
            stored_domain: true,
            fog_threshold: 0.5,
            grid: None,
        }
    }
}

/// The stem of `path`, the name of the solid of a file of one (`solid` when it has
/// none).
pub(crate) fn file_stem(path: &Path) -> String {
    path.file_stem().map_or_else(|| "solid".into(), |s| s.to_string_lossy().into_owned())
}
