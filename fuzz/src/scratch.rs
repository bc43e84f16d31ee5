//! The scratch folder: a folder of this process under the system's temporary folder
//! where the targets whose loaders take only a path (`.patches`, scene files) write
//! each case, beside the fixtures the scene corpus names (`box.obj`, `open.stl`,
//! `ball.oct`, `tiny.patches`, `tex.png`), so that a mutated scene still reaches the
//! mesh, octree, patch and texture loaders it points at.
//!
//! Each case gets a fresh name (a counter), so targets may run on several threads at
//! once (the corpus test does); [`remove`] deletes the folder at the end of a run.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::DVec3;
use octsolid::io::oct;
use octsolid::octree::{Domain, voxelize};
use octsolid::shape::Sphere;

/// A closed cube of edge 2 around the origin, six outward quads.
pub const BOX_OBJ: &str = "# fixture: a closed cube\n\
v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 1 5 8 4\nf 2 3 7 6\n";

/// An open mesh: two triangles of a square, ASCII STL.
pub const OPEN_STL: &str = "solid open\n\
facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 1 1 0\n endloop\nendfacet\n\
facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 1 0\n  vertex 0 1 0\n endloop\nendfacet\n\
endsolid open\n";

/// One bicubic patch, a gently curved square.
pub const TINY_PATCHES: &str = "1\n\
1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n16\n\
0,0,0\n1,0,0.2\n2,0,0.2\n3,0,0\n0,1,0.2\n1,1,0.5\n2,1,0.5\n3,1,0.2\n\
0,2,0.2\n1,2,0.5\n2,2,0.5\n3,2,0.2\n0,3,0\n1,3,0.2\n2,3,0.2\n3,3,0\n";

/// A ball of radius 0.9 in the cube `[-1, 1]^3` at depth 4, as `.oct` bytes.
#[must_use]
pub fn ball_oct() -> Vec<u8> {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 4).expect("a valid domain");
    let ball = Sphere::new(DVec3::ZERO, 0.9).expect("a valid sphere");
    oct::encode(&voxelize(&ball, domain, &Default::default()).expect("a small voxelization"))
}

/// A 4 x 4 PNG checkerboard.
#[must_use]
pub fn tex_png() -> Vec<u8> {
    let img = image::RgbImage::from_fn(4, 4, |x, y| {
        if (x + y) % 2 == 0 { image::Rgb([230, 40, 40]) } else { image::Rgb([20, 20, 200]) }
    });
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png).expect("a PNG in memory");
    bytes
}

/// The folder, made with its fixtures on first use.
fn folder() -> &'static Path {
    static FOLDER: OnceLock<PathBuf> = OnceLock::new();
    FOLDER.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("octsolid-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("the scratch folder can be made");
        let fixtures: [(&str, Vec<u8>); 5] = [
            ("box.obj", BOX_OBJ.into()),
            ("open.stl", OPEN_STL.into()),
            ("tiny.patches", TINY_PATCHES.into()),
            ("ball.oct", ball_oct()),
            ("tex.png", tex_png()),
        ];
        for (name, bytes) in fixtures {
            std::fs::write(dir.join(name), bytes).expect("a fixture can be written");
        }
        dir
    })
}

/// A path in the scratch folder for one case, ending in `.ext`; nothing is written.
#[must_use]
pub fn case_path(ext: &str) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    folder().join(format!("case-{}.{ext}", NEXT.fetch_add(1, Ordering::Relaxed)))
}

/// Writes `bytes` to a fresh case path ending in `.ext`, runs `f` on the path and
/// deletes the file.
pub fn with_file<T>(bytes: &[u8], ext: &str, f: impl FnOnce(&Path) -> T) -> T {
    struct Remove(PathBuf);
    impl Drop for Remove {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.0);
        }
    }
    let path = Remove(case_path(ext));
    std::fs::write(&path.0, bytes).expect("a case file can be written to the scratch folder");
    f(&path.0)
}

/// Deletes the scratch folder (if it was made).
pub fn remove() {
    let dir = std::env::temp_dir().join(format!("octsolid-fuzz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(dir);
}
