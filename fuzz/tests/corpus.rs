//! Every corpus file through every fuzz target (not only its own: a `.vdb` fed to the
//! OBJ reader is a fine case too). No target may panic, and each target must read
//! most of its own seeds (a corpus whose seeds are refused has stopped reaching past
//! the first check of its format). One test, so that the scratch folder the targets
//! share is removed once, after every case.

use std::collections::BTreeMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

use octsolid_fuzz::driver::corpus_files;
use octsolid_fuzz::targets::TARGETS;

#[test]
fn every_corpus_file_through_every_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    let mut files: Vec<PathBuf> = TARGETS.iter().flat_map(|t| corpus_files(t, &root)).collect();
    files.sort();
    files.dedup();
    assert!(files.len() >= 30, "the corpus has only {} files", files.len());
    let mut panics = Vec::new();
    let mut refused: BTreeMap<&str, (usize, Vec<String>)> = BTreeMap::new();
    for target in TARGETS {
        let own = corpus_files(target, &root);
        assert!(own.len() >= 2, "{} has {} seeds", target.name, own.len());
        for file in &files {
            let bytes = std::fs::read(file).unwrap();
            match catch_unwind(AssertUnwindSafe(|| (target.run)(&bytes))) {
                Err(_) => panics.push(format!("{} on {}", target.name, file.display())),
                Ok(Err(e)) if own.contains(file) => refused
                    .entry(target.name)
                    .or_insert((own.len(), Vec::new()))
                    .1
                    .push(format!("{}: {e}", file.display())),
                Ok(_) => {}
            }
        }
    }
    octsolid_fuzz::scratch::remove();
    assert!(panics.is_empty(), "panics:\n{}", panics.join("\n"));
    // A seed may be there to be refused (a big-endian PLY), but not more than a quarter.
    let too_many: Vec<String> = refused
        .iter()
        .filter(|(_, (own, refused))| refused.len() * 4 > *own)
        .map(|(name, (own, refused))| {
            format!("{name} refuses {} of {own} seeds:\n  {}", refused.len(), refused.join("\n  "))
        })
        .collect();
    assert!(too_many.is_empty(), "{}", too_many.join("\n"));
}
