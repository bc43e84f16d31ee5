//! What a file holds, decided by its extension: the one place octsolid reads file
//! extensions, for every file it reads or writes.
//!
//! [`FileKind::of`] maps a path to one of the kinds a caller accepts, case-insensitively.
//! A missing extension, or one the caller does not accept, is
//! [`Error::UnknownExtension`], which names the file and lists every extension the
//! caller accepts, so a command's error says all it reads or writes (a mesh loader's,
//! for one, names `.patches` only when it reads patches too). The kinds, with what
//! octsolid does with each (the sets a caller passes to [`FileKind::of`]):
//!
//! | kind | extension | read as | written from | set |
//! |------|-----------|---------|--------------|-----|
//! | [`Scene`](FileKind::Scene) | `.toml` | a scene | | [`DRAWN`](FileKind::DRAWN) |
//! | [`Oct`](FileKind::Oct) | `.oct` | a solid (with its metadata) | a solid | [`SOLIDS`](FileKind::SOLIDS), [`SOLID_OUTPUTS`](FileKind::SOLID_OUTPUTS) |
//! | [`Octs`](FileKind::Octs) | `.octs` | a sharded solid | a solid | both |
//! | [`Vox`](FileKind::Vox), [`Binvox`](FileKind::Binvox), [`Vdb`](FileKind::Vdb) | `.vox`, `.binvox`, `.vdb` | solids | solids | both |
//! | [`Glb`](FileKind::Glb) | `.glb` | | each solid's surface, one mesh a solid | [`SOLID_OUTPUTS`](FileKind::SOLID_OUTPUTS) |
//! | [`Obj`](FileKind::Obj), [`Stl`](FileKind::Stl), [`Ply`](FileKind::Ply) | `.obj`, `.stl`, `.ply` | a mesh | a mesh, a solid's boundary | [`MESHES`](FileKind::MESHES), [`SOLID_OUTPUTS`](FileKind::SOLID_OUTPUTS) |
//! | [`ThreeMf`](FileKind::ThreeMf) | `.3mf` | | a mesh, a solid's boundary | [`MESH_OUTPUTS`](FileKind::MESH_OUTPUTS), [`SOLID_OUTPUTS`](FileKind::SOLID_OUTPUTS) |
//! | [`Patches`](FileKind::Patches) | `.patches` | Bezier patches | | [`SURFACES`](FileKind::SURFACES) |
//! | [`Png`](FileKind::Png), [`Exr`](FileKind::Exr) | `.png`, `.exr` | | a picture | [`PICTURES`](FileKind::PICTURES) |
//! | [`Rad`](FileKind::Rad) | `.rad` | a radiosity solution | a radiosity solution | |
//!
//! The capabilities ([`FileKind::reads_solid`], [`FileKind::writes_solid`],
//! [`FileKind::is_mesh`], [`FileKind::writes_mesh`], [`FileKind::is_picture`], [`FileKind::holds_many_solids`])
//! are membership of those sets, so a set and its question never disagree.
//!
//! The file's kind also implies its up axis ([`FileKind::default_up`]): OBJ and PLY
//! meshes are y-up by convention (the Stanford bunny, Spot); STL, patches (the Utah
//! teapot), scenes, octsolid's own `.oct` solids and the voxel formats are z-up
//! (MagicaVoxel's editor is; binvox and `.vdb` record no up axis, and z keeps a solid
//! converted to and from `.oct` looking the same).

use std::path::Path;

use crate::error::{Error, Result};
use crate::shape::Axis;

/// The kinds of file octsolid reads or writes, each with one extension.
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
    /// A glTF 2.0 binary, `.glb`: written only, one boundary mesh a solid.
    Glb,
    /// A 3D Manufacturing Format package, `.3mf` (written: one mesh object, in
    /// millimetres).
    ThreeMf,
    /// A PNG picture (8-bit sRGB), `.png`: written only.
    Png,
    /// An OpenEXR picture (32-bit float linear radiance), `.exr`: written only.
    Exr,
    /// A radiosity solution, `.rad` (`render::radiosity`).
    Rad,
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
        FileKind::Glb,
        FileKind::ThreeMf,
        FileKind::Png,
        FileKind::Exr,
        FileKind::Rad,
    ];

    /// What a picture is drawn from (`render`, `view`): a scene, a solid, a mesh or a
    /// patch set.
    pub const DRAWN: &'static [FileKind] = &[
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

    /// The voxel solids: what [`crate::SolidFile::read`] reads (`.octs` too: sharded
    /// solids, [`crate::sharded::ShardedSolid`]).
    pub const SOLIDS: &'static [FileKind] =
        &[FileKind::Oct, FileKind::Octs, FileKind::Vox, FileKind::Binvox, FileKind::Vdb];

    /// What a solid can be written as ([`crate::write_solid_file`]): the voxel
    /// solids, or its surface as a mesh or a `.glb`.
    pub const SOLID_OUTPUTS: &'static [FileKind] = &[
        FileKind::Oct,
        FileKind::Octs,
        FileKind::Vox,
        FileKind::Binvox,
        FileKind::Vdb,
        FileKind::Glb,
        FileKind::Obj,
        FileKind::Stl,
        FileKind::Ply,
        FileKind::ThreeMf,
    ];

    /// The solid outputs that hold several solids, each with its colour (`.vox` one a
    /// palette colour, `.vdb` one a grid, `.glb` one a mesh); the others hold one.
    pub const MANY_SOLIDS: &'static [FileKind] = &[FileKind::Vox, FileKind::Vdb, FileKind::Glb];

    /// The pictures ([`crate::io::write_picture`]).
    pub const PICTURES: &'static [FileKind] = &[FileKind::Png, FileKind::Exr];

    /// The triangle meshes octsolid reads and writes.
    pub const MESHES: &'static [FileKind] = &[FileKind::Obj, FileKind::Stl, FileKind::Ply];

    /// What a mesh is written as ([`crate::mesh::write_mesh`]): the meshes, and `.3mf`
    /// (the printers' package; written only).
    pub const MESH_OUTPUTS: &'static [FileKind] = &[FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::ThreeMf];

    /// What [`crate::import::Input::read`] reads: the meshes and patch sets.
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
            FileKind::Glb => "glb",
            FileKind::ThreeMf => "3mf",
            FileKind::Png => "png",
            FileKind::Exr => "exr",
            FileKind::Rad => "rad",
        }
    }

    /// Whether a solid is read from this kind ([`FileKind::SOLIDS`]).
    #[must_use]
    pub fn reads_solid(self) -> bool {
        FileKind::SOLIDS.contains(&self)
    }

    /// Whether a solid can be written as this kind ([`FileKind::SOLID_OUTPUTS`]).
    #[must_use]
    pub fn writes_solid(self) -> bool {
        FileKind::SOLID_OUTPUTS.contains(&self)
    }

    /// Whether this kind is a triangle mesh ([`FileKind::MESHES`]).
    #[must_use]
    pub fn is_mesh(self) -> bool {
        FileKind::MESHES.contains(&self)
    }

    /// Whether a mesh is written as this kind ([`FileKind::MESH_OUTPUTS`]).
    #[must_use]
    pub fn writes_mesh(self) -> bool {
        FileKind::MESH_OUTPUTS.contains(&self)
    }

    /// Whether a solid written as this kind is meshed: the mesh outputs and `.glb` write
    /// its surface, contoured on its surface data.
    #[must_use]
    pub fn meshes_solid(self) -> bool {
        self == FileKind::Glb || self.writes_mesh()
    }

    /// Whether a solid written as this kind uses its surface data: `.oct` keeps it in
    /// its surface section, and the meshed kinds ([`FileKind::meshes_solid`]) contour
    /// their true surface on it.
    #[must_use]
    pub fn uses_surface(self) -> bool {
        self == FileKind::Oct || self.meshes_solid()
    }

    /// Whether this kind is a picture ([`FileKind::PICTURES`]).
    #[must_use]
    pub fn is_picture(self) -> bool {
        FileKind::PICTURES.contains(&self)
    }

    /// Whether this kind holds several solids, each with its colour
    /// ([`FileKind::MANY_SOLIDS`]).
    #[must_use]
    pub fn holds_many_solids(self) -> bool {
        FileKind::MANY_SOLIDS.contains(&self)
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
    /// MagicaVoxel's and the teapot's; the outputs only pictures and `.glb` are
    /// written with an up axis of their own choosing).
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
            | FileKind::Patches
            | FileKind::Glb
            | FileKind::ThreeMf
            | FileKind::Png
            | FileKind::Exr
            | FileKind::Rad => Axis::Z,
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
            FileKind::of(Path::new("dir.d/model"), FileKind::DRAWN).unwrap_err().to_string(),
            "dir.d/model: no extension (use .toml, .oct, .octs, .vox, .binvox, .vdb, .obj, .stl, .ply or .patches)"
        );
        assert_eq!(
            FileKind::of(Path::new("a.jpg"), FileKind::ALL).unwrap_err().to_string(),
            "a.jpg: unexpected extension '.jpg' (use .toml, .oct, .octs, .vox, .binvox, .vdb, .obj, .stl, .ply, \
             .patches, .glb, .3mf, .png, .exr or .rad)"
        );
    }

    #[test]
    fn obj_and_ply_are_y_up_and_the_rest_z_up() {
        let up: Vec<Axis> = FileKind::ALL.iter().map(|k| k.default_up()).collect();
        let mut expected = vec![Axis::Z; FileKind::ALL.len()];
        expected[6] = Axis::Y;
        expected[8] = Axis::Y;
        assert_eq!(up, expected);
        assert_eq!((FileKind::ALL[6], FileKind::ALL[8]), (FileKind::Obj, FileKind::Ply));
    }

    #[test]
    fn every_kind_has_its_own_extension_and_every_set_lists_kinds_once() {
        let mut extensions: Vec<&str> = FileKind::ALL.iter().map(|k| k.extension()).collect();
        extensions.sort_unstable();
        extensions.dedup();
        assert_eq!(extensions.len(), FileKind::ALL.len());
        let sets = [
            FileKind::DRAWN,
            FileKind::SOLIDS,
            FileKind::SOLID_OUTPUTS,
            FileKind::MANY_SOLIDS,
            FileKind::MESHES,
            FileKind::MESH_OUTPUTS,
            FileKind::SURFACES,
            FileKind::PICTURES,
        ];
        for set in sets {
            let mut kinds = set.to_vec();
            kinds.dedup();
            assert_eq!(kinds.len(), set.len(), "{set:?}");
            assert!(set.iter().all(|k| FileKind::ALL.contains(k)), "{set:?}");
        }
    }

    #[test]
    fn capabilities_are_the_sets() {
        use FileKind::*;
        let of = |test: fn(FileKind) -> bool| -> Vec<FileKind> {
            FileKind::ALL.iter().copied().filter(|&k| test(k)).collect()
        };
        assert_eq!(of(FileKind::reads_solid), [Oct, Octs, Vox, Binvox, Vdb]);
        assert_eq!(of(FileKind::writes_solid), [Oct, Octs, Vox, Binvox, Vdb, Obj, Stl, Ply, Glb, ThreeMf]);
        assert_eq!(of(FileKind::is_mesh), [Obj, Stl, Ply]);
        assert_eq!(of(FileKind::writes_mesh), [Obj, Stl, Ply, ThreeMf]);
        assert_eq!(of(FileKind::is_picture), [Png, Exr]);
        assert_eq!(of(FileKind::holds_many_solids), [Vox, Vdb, Glb]);
        // Every solid that holds many is written; every solid read is written back.
        assert!(FileKind::MANY_SOLIDS.iter().all(|k| k.writes_solid()));
        assert!(FileKind::SOLIDS.iter().all(|k| k.writes_solid()));
    }
}
