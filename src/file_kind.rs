//! What a file holds, decided by its extension: the one place octsolid reads file
//! extensions.
//!
//! [`FileKind::of`] maps a path to one of the kinds a caller accepts, case-insensitively:
//! `.toml` scenes, `.oct` solids, the voxel formats of other tools (`.vox`, `.binvox`,
//! `.vdb`, read by [`crate::io::read_solids`]), `.obj` / `.stl` / `.ply` meshes and
//! `.patches` Bezier patch sets. A missing extension, or one the caller does not accept, is
//! [`Error::UnknownExtension`], which names the file and lists every extension the
//! caller accepts, so a command's error says all it reads (a mesh loader's, for one,
//! names `.patches` only when it reads patches too).
//!
//! The file's kind also implies its up axis ([`FileKind::default_up`]): OBJ and PLY
//! meshes are y-up by convention (the Stanford bunny, Spot); STL, patches (the Utah
//! teapot), scenes, octsolid's own `.oct` solids and the voxel formats are z-up
//! (MagicaVoxel's editor is; binvox and `.vdb` record no up axis, and z keeps a solid
//! converted to and from `.oct` looking the same).

use std::path::Path;

use crate::error::{Error, Result};
use crate::shape::Axis;

/// The kinds of file octsolid reads, each with one extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FileKind {
    /// A scene file, `.toml` (see `docs/SCENES.md`).
    Scene,
    /// A solid in octsolid's own format, `.oct`.
    Oct,
    /// A sharded solid, a folder `.octs` of `.oct` shards and an index
    /// ([`crate::sharded`]).
    Octs,
    /// MagicaVoxel voxels, one solid a palette colour, `.vox`.
    Vox,
    /// A binvox voxel grid, `.binvox`.
    Binvox,
    /// An OpenVDB grid, `.vdb`.
    Vdb,
    /// A Wavefront OBJ mesh, `.obj`.
    Obj,
    /// An STL mesh (ASCII or binary), `.stl`.
    Stl,
    /// A PLY mesh (ASCII or binary little-endian), `.ply`.
    Ply,
    /// A set of bicubic Bezier patches, `.patches`.
    Patches,
}

impl FileKind {
    /// Every kind, in the order errors list them.
    pub const ALL: &'static [FileKind] = &[
        FileKind::Scene,
        FileKind::Oct,
        FileKind::Octs,
        FileKind::Vox,
        FileKind::Binvox,
        FileKind::Vdb,
        FileKind::Obj,
        FileKind::Stl,
        FileKind::Ply,
        FileKind::Patches,
    ];

    /// The voxel solids: what [`crate::io::read_solids`] reads, and sharded solids
    /// ([`crate::sharded::ShardedSolid`]).
    pub const SOLIDS: &'static [FileKind] =
        &[FileKind::Oct, FileKind::Octs, FileKind::Vox, FileKind::Binvox, FileKind::Vdb];

    /// The triangle meshes.
    pub const MESHES: &'static [FileKind] = &[FileKind::Obj, FileKind::Stl, FileKind::Ply];

    /// What [`crate::import::Input::load`] reads: the meshes and patch sets.
    pub const SURFACES: &'static [FileKind] = &[FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::Patches];

    /// The extension, without the dot, in lower case.
    #[must_use]
    pub fn extension(self) -> &'static str {
        match self {
            FileKind::Scene => "toml",
            FileKind::Oct => "oct",
            FileKind::Octs => "octs",
            FileKind::Vox => "vox",
            FileKind::Binvox => "binvox",
            FileKind::Vdb => "vdb",
            FileKind::Obj => "obj",
            FileKind::Stl => "stl",
            FileKind::Ply => "ply",
            FileKind::Patches => "patches",
        }
    }

    /// The kind of `path` by its extension (case-insensitive), if it is one of
    /// `accepted`; else [`Error::UnknownExtension`] naming the file, the extension
    /// found (empty when there is none) and every accepted one.
    pub fn of(path: impl AsRef<Path>, accepted: &[FileKind]) -> Result<FileKind> {
        let path = path.as_ref();
        let found = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_default();
        accepted.iter().copied().find(|k| found.eq_ignore_ascii_case(k.extension())).ok_or_else(|| {
            Error::UnknownExtension {
                path: path.to_path_buf(),
                found,
                accepted: accepted.iter().map(|k| k.extension()).collect(),
            }
        })
    }

    /// The world's up axis a file of this kind implies: y for OBJ and PLY meshes (y-up
    /// by convention), z for everything else (octsolid's own convention, and STL's,
    /// MagicaVoxel's and the teapot's).
    #[must_use]
    pub fn default_up(self) -> Axis {
        match self {
            FileKind::Obj | FileKind::Ply => Axis::Y,
            FileKind::Scene
            | FileKind::Oct
            | FileKind::Octs
            | FileKind::Vox
            | FileKind::Binvox
            | FileKind::Vdb
            | FileKind::Stl
            | FileKind::Patches => Axis::Z,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_found_by_its_extension_in_any_case() {
        for &kind in FileKind::ALL {
            let lower = format!("dir.v2/part.{}", kind.extension());
            assert_eq!(FileKind::of(Path::new(&lower), FileKind::ALL).unwrap(), kind);
            let upper = lower.to_ascii_uppercase();
            assert_eq!(FileKind::of(Path::new(&upper), FileKind::ALL).unwrap(), kind);
        }
    }

    #[test]
    fn an_unaccepted_or_missing_extension_names_the_file_and_every_accepted_one() {
        let e = FileKind::of(Path::new("teapot.patches"), FileKind::MESHES).unwrap_err();
        match &e {
            Error::UnknownExtension { path, found, accepted } => {
                assert_eq!(path, Path::new("teapot.patches"));
                assert_eq!(found, "patches");
                assert_eq!(accepted, &["obj", "stl", "ply"]);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            FileKind::of(Path::new("model.3ds"), FileKind::SURFACES).unwrap_err().to_string(),
            "model.3ds: unexpected extension '.3ds' (use .obj, .stl, .ply or .patches)"
        );
        assert_eq!(
            FileKind::of(Path::new("dir.d/model"), FileKind::ALL).unwrap_err().to_string(),
            "dir.d/model: no extension (use .toml, .oct, .octs, .vox, .binvox, .vdb, .obj, .stl, .ply or .patches)"
        );
    }

    #[test]
    fn obj_and_ply_are_y_up_and_the_rest_z_up() {
        let up: Vec<Axis> = FileKind::ALL.iter().map(|k| k.default_up()).collect();
        assert_eq!(up, [Axis::Z, Axis::Z, Axis::Z, Axis::Z, Axis::Z, Axis::Z, Axis::Y, Axis::Z, Axis::Y, Axis::Z]);
    }
}
