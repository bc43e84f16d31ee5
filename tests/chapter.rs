//! docs/CHAPTER.md's pictures stay makeable: `scripts/chapter.sh` run whole at a tiny
//! size (32x24, radiosity on large patches), every picture it writes a PNG of that
//! size, the same set of names as docs/images/chapter-*.png, and every picture the
//! chapter shows among them.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

mod common;

/// The `chapter-*.png` names in `dir`.
fn chapter_pictures(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("chapter-") && n.ends_with(".png"))
        .collect()
}

/// A PNG's width and height, from its IHDR chunk.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} is not a PNG", path.display());
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn the_chapter_script_runs_and_makes_every_picture_the_chapter_shows() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let out = common::scratch_dir("chapter", "pictures");
    let run = Command::new("bash")
        .arg(root.join("scripts/chapter.sh"))
        .env("OCTSOLID", env!("CARGO_BIN_EXE_octsolid"))
        .env("OUT", &out)
        .env("SIZE", "32x24")
        .env("PATCH", "1")
        .output()
        .unwrap();
    assert!(run.status.success(), "scripts/chapter.sh failed:\n{}", String::from_utf8_lossy(&run.stderr));
    let made = chapter_pictures(&out);
    for name in &made {
        assert_eq!(png_size(&out.join(name)), (32, 24), "{name}");
    }
    assert_eq!(made, chapter_pictures(&root.join("docs/images")), "the script's pictures and the committed ones");
    let chapter = std::fs::read_to_string(root.join("docs/CHAPTER.md")).unwrap();
    let shown: BTreeSet<String> =
        chapter.split("](images/").skip(1).filter_map(|rest| rest.split(')').next()).map(str::to_string).collect();
    assert!(!shown.is_empty());
    assert!(shown.is_subset(&made), "shown but not made: {:?}", shown.difference(&made).collect::<Vec<_>>());
    std::fs::remove_dir_all(&out).unwrap();
}
