//! The solid cache of scene files: the octrees a scene's solids were voxelized (or
//! moved) into, saved beside the scene so that rendering it again reads them instead
//! of building them again.
//!
//! Where: the folder `.octsolid-cache` beside the scene file (marked with a
//! `CACHEDIR.TAG`, so backup tools skip it), one file an entry named
//! `STEM.HASH.octcache` (`STEM` the scene file's name without `.toml`, `HASH` 16 hex
//! digits). After a load the folder holds the entries of that load's solids only:
//! entries of the same scene that the load did not use are removed.
//!
//! The key of a solid ([`SolidKey`]) is the text of everything that decides its
//! octree: the crate's version and the entry format's, the solid's kind, its `shape`
//! and `transform` as read (their specs in `Debug` form, exact to the bit), the domain it is voxelized into (the
//! bits of its floats) or the depth and inside rule of a mesh, and each file it reads
//! (its path, length, CRC-32 and 64-bit FNV-1a of its bytes, so an edit that keeps the
//! length and the modification time still changes the key). `HASH` is the FNV-1a of
//! the key, and the entry holds the key itself: an entry is used only when its key is
//! the solid's byte for byte, never on the hash alone.
//!
//! An entry (little-endian): the magic `OCTCACHE`, the format version (`u32`, 1), the
//! key's length (`u32`) and bytes, the CRC-32 of the version, length and key (`u32`),
//! then the solid as a whole `.oct` file (its own header and CRC-32,
//! `docs/FORMAT.md`). Entries are written atomically (`write_atomic`), so a reader
//! never sees half of one; an entry that fails any check (magic, version, lengths,
//! checksums, the `.oct` file's own checks, the memory budget, the domain the solid
//! must have) is not used: the solid is built again and the entry rewritten, with a
//! [`Warning`] saying why.
//!
//! What a hit saves: the voxelization (or the resampling of a moved `.oct` file).
//! The scene's shape trees are still built (their surfaces give smooth normals, their
//! bounds the shared domain), and the traversal octree is built from the loaded
//! octree, which is `O(n depth)` and a small share of a load (see docs/benchmark-log/2026-12.md,
//! "Fast pictures").

use crate::fnv::fnv1a;
use std::path::{Path, PathBuf};

use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::io::oct;
use crate::octree::{Domain, LinearOctree};
use crate::warning::{Place, Warning};

/// The folder of a scene's cache, beside the scene file.
pub const CACHE_DIR: &str = ".octsolid-cache";

/// The extension of a cache entry.
const EXTENSION: &str = "octcache";

/// The first bytes of an entry.
const MAGIC: [u8; 8] = *b"OCTCACHE";

/// The entry format's version: a change to the layout or to what a key holds bumps it.
const FORMAT: u32 = 1;

/// Bytes before the key: magic, version, key length.
const KEY_OFFSET: usize = 16;

/// The marker of a cache folder (<https://bford.info/cachedir/>).
const CACHEDIR_TAG: &str = "Signature: 8a477f597d28d172789f06886806bc55\n\
                            # This folder holds solids octsolid voxelized for the scenes beside it.\n\
                            # Deleting it is safe: they are built again when needed.\n";

/// Whether loading a scene reads and writes its solid cache.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CachePolicy {
    /// Neither read nor written: every solid is built (the default of
    /// [`super::read_scene`], which so writes nothing).
    #[default]
    Off,
    /// A solid whose inputs are unchanged is read from the cache; the others are built
    /// and stored (what `octsolid render` does unless told `--no-cache`).
    ReadWrite,
}

/// What the cache did during one load of a scene.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CacheReport {
    /// Solids read from the cache (not voxelized).
    pub hits: usize,
    /// Solids built (voxelized or moved) because no usable entry was there; each was
    /// then stored unless a warning says the write failed.
    pub misses: usize,
    /// The cache folder, when the policy used one.
    pub dir: Option<PathBuf>,
}

/// The key of one solid: the text of everything that decides its octree (module doc).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct SolidKey {
    text: String,
}

impl SolidKey {
    /// A key of a solid of `kind` (`shape`, `mesh`, `oct`).
    pub(crate) fn new(kind: &str) -> Self {
        SolidKey { text: format!("octsolid {} cache {FORMAT}\nsolid {kind}\n", env!("CARGO_PKG_VERSION")) }
    }

    /// Adds the line `name value` (a value's line breaks kept as `\n` escapes, so
    /// every part stays one line).
    pub(crate) fn line(&mut self, name: &str, value: &str) {
        self.text.push_str(name);
        self.text.push(' ');
        self.text.push_str(&value.replace('\\', "\\\\").replace('\n', "\\n"));
        self.text.push('\n');
    }

    /// Adds the domain: its corner and edge as the bits of their floats, and its depth.
    pub(crate) fn domain(&mut self, d: &Domain) {
        let [x, y, z] = d.min().to_array().map(f64::to_bits);
        let value = format!("min {x:016x} {y:016x} {z:016x} edge {:016x} depth {}", d.edge().to_bits(), d.depth());
        self.line("domain", &value);
    }

    /// Adds the file at `path`: its length and two checksums of its bytes (of a
    /// sharded solid's index, which holds every shard's length and checksum).
    pub(crate) fn file(&mut self, path: &Path) -> Result<()> {
        let index = path.join(crate::sharded::INDEX_FILE);
        // A folder that is not a sharded solid is read as itself: refused as a folder.
        let read = if index.is_file() { index.as_path() } else { path };
        let bytes = crate::input_file::read(read)?;
        let value =
            format!("{} {} {:08x} {:016x}", path.display(), bytes.len(), crc32fast::hash(&bytes), fnv1a(&bytes));
        self.line("file", &value);
        Ok(())
    }

    /// The 64-bit hash that names the key's entry.
    fn hash(&self) -> u64 {
        fnv1a(self.text.as_bytes())
    }
}

/// The cache of one scene file during one load.
pub(crate) struct SceneCache {
    /// The cache folder.
    dir: PathBuf,
    /// The scene file's name without `.toml`: the first part of its entries' names.
    stem: String,
    /// The names of the entries this load used or wrote.
    used: Vec<String>,
    /// What happened, for the caller.
    report: CacheReport,
}

/// The cache folder and the entries' stem of the scene file `scene`.
fn place_of(scene: &Path) -> (PathBuf, String) {
    let folder = scene.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let stem = scene.file_stem().map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned());
    (folder.join(CACHE_DIR), stem)
}

/// Whether `name` is an entry of the scene whose stem is `stem`: `STEM.HASH.octcache`
/// with 16 hex digits for `HASH`.
fn is_entry_of(name: &str, stem: &str) -> bool {
    let Some(rest) = name.strip_suffix(&format!(".{EXTENSION}")) else { return false };
    let Some((entry_stem, hash)) = rest.rsplit_once('.') else { return false };
    entry_stem == stem && hash.len() == 16 && hash.bytes().all(|b| b.is_ascii_hexdigit())
}

/// Removes every cache entry of the scene file `scene` (and the cache folder when that
/// leaves it with nothing but its tag); returns how many entries were removed. No
/// cache folder is not an error.
pub fn clear_cache(scene: impl AsRef<Path>) -> Result<usize> {
    let (dir, stem) = place_of(scene.as_ref());
    let removed = remove_entries(&dir, |name| is_entry_of(name, &stem))?;
    remove_if_only_tag(&dir);
    Ok(removed)
}

/// Removes the entries in `dir` whose names `doomed` picks; how many.
fn remove_entries(dir: &Path, doomed: impl Fn(&str) -> bool) -> Result<usize> {
    let io = |source| Error::Io { path: dir.to_path_buf(), source };
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(0),
        Err(e) => return Err(io(e)),
    };
    let mut removed = 0;
    for entry in entries {
        let entry = entry.map_err(io)?;
        if doomed(&entry.file_name().to_string_lossy()) {
            let path = entry.path();
            std::fs::remove_file(&path).map_err(|source| Error::Io { path, source })?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Removes `dir` when it holds only its `CACHEDIR.TAG`; best effort.
fn remove_if_only_tag(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let names: Vec<_> = entries.flatten().map(|e| e.file_name()).collect();
    if names.iter().all(|n| n == "CACHEDIR.TAG") {
        let _ = std::fs::remove_file(dir.join("CACHEDIR.TAG"));
        let _ = std::fs::remove_dir(dir);
    }
}

impl SceneCache {
    /// The cache of the scene file `scene`, `None` under [`CachePolicy::Off`].
    pub(crate) fn new(scene: &Path, policy: CachePolicy) -> Option<Self> {
        if policy == CachePolicy::Off {
            return None;
        }
        let (dir, stem) = place_of(scene);
        let report = CacheReport { dir: Some(dir.clone()), ..CacheReport::default() };
        Some(SceneCache { dir, stem, used: Vec::new(), report })
    }

    /// The entry file of `key`.
    fn entry(&self, key: &SolidKey) -> (String, PathBuf) {
        let name = format!("{}.{:016x}.{EXTENSION}", self.stem, key.hash());
        let path = self.dir.join(&name);
        (name, path)
    }

    /// The solid of `key`: read from its entry when there is a usable one (whose solid
    /// lies in `domain` when that is given), else `build()` and stored. What went
    /// wrong with the cache (an unusable entry, a failed write) is pushed onto
    /// `warnings`; only `build`'s errors are returned.
    pub(crate) fn solid(
        &mut self,
        key: &SolidKey,
        domain: Option<&Domain>,
        budget: MemoryBudget,
        warnings: &mut Vec<Warning>,
        build: impl FnOnce() -> Result<LinearOctree>,
    ) -> Result<LinearOctree> {
        let (name, path) = self.entry(key);
        self.used.push(name);
        match read_entry(&path, key, budget) {
            Ok(Some(tree)) if domain.is_none_or(|d| d == tree.domain()) => {
                self.report.hits += 1;
                return Ok(tree);
            }
            Ok(Some(_)) => warnings.push(unusable(&path, "its solid lies in another domain")),
            Ok(None) => {}
            Err(reason) => warnings.push(unusable(&path, &reason)),
        }
        let tree = build()?;
        self.report.misses += 1;
        if let Err(e) = self.store(&path, key, &tree) {
            warnings.push(Place::File.warning(&self.dir, format!("cannot write the scene cache: {e}")));
        }
        Ok(tree)
    }

    /// Writes the entry of `key` at `path`, creating the folder and its tag first.
    fn store(&self, path: &Path, key: &SolidKey, tree: &LinearOctree) -> Result<()> {
        std::fs::create_dir_all(&self.dir).map_err(|source| Error::Io { path: self.dir.clone(), source })?;
        let tag = self.dir.join("CACHEDIR.TAG");
        if !tag.exists() {
            write_atomic(&tag, |w| w.write_all(CACHEDIR_TAG.as_bytes()))?;
        }
        let bytes = encode_entry(key, tree);
        write_atomic(path, |w| w.write_all(&bytes)).map(drop)
    }

    /// Removes the scene's entries this load did not use (best effort: a failure only
    /// leaves a stale entry, which is never read for another key) and returns what
    /// the cache did.
    pub(crate) fn finish(self) -> CacheReport {
        let stale = |name: &str| is_entry_of(name, &self.stem) && !self.used.iter().any(|u| u == name);
        let _ = remove_entries(&self.dir, stale);
        self.report
    }
}

/// The warning that the entry at `path` was not used, and why.
fn unusable(path: &Path, reason: &str) -> Warning {
    Place::File.warning(path, format!("cache entry not used ({reason}); the solid was built again"))
}

/// The entry of `key` holding `tree` (module doc).
fn encode_entry(key: &SolidKey, tree: &LinearOctree) -> Vec<u8> {
    let key = key.text.as_bytes();
    let mut out = Vec::with_capacity(KEY_OFFSET + key.len() + 4);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT.to_le_bytes());
    out.extend_from_slice(&(key.len() as u32).to_le_bytes());
    out.extend_from_slice(key);
    let crc = crc32fast::hash(&out[MAGIC.len()..]);
    out.extend_from_slice(&crc.to_le_bytes());
    out.extend_from_slice(&oct::encode(tree));
    out
}

/// The solid of the entry at `path` if it is there and its key is `key`: `Ok(None)`
/// when there is no entry or it holds another key, `Err` with the reason when it
/// cannot be read or fails a check.
fn read_entry(path: &Path, key: &SolidKey, budget: MemoryBudget) -> std::result::Result<Option<LinearOctree>, String> {
    let size = match std::fs::metadata(path) {
        Ok(meta) => meta.len(),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(e.to_string()),
    };
    budget.check(format!("reading {}", path.display()), size).map_err(|e| e.to_string())?;
    let bytes = std::fs::read(path).map_err(|e| e.to_string())?;
    let u32_at = |at: usize| bytes.get(at..at + 4).map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")));
    if bytes.get(..MAGIC.len()) != Some(&MAGIC[..]) {
        return Err("not a cache entry".into());
    }
    match u32_at(MAGIC.len()) {
        Some(FORMAT) => {}
        Some(v) => return Err(format!("entry format {v}, this build reads {FORMAT}")),
        None => return Err("truncated".into()),
    }
    let key_len = u32_at(12).ok_or("truncated")? as usize;
    let key_end = KEY_OFFSET.checked_add(key_len).filter(|&end| end + 4 <= bytes.len()).ok_or("truncated")?;
    let stored_crc = u32_at(key_end).ok_or("truncated")?;
    if crc32fast::hash(&bytes[MAGIC.len()..key_end]) != stored_crc {
        return Err("its key fails its checksum".into());
    }
    if &bytes[KEY_OFFSET..key_end] != key.text.as_bytes() {
        return Ok(None);
    }
    oct::decode(&bytes[key_end + 4..], path, budget).map(Some).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_are_told_apart_by_their_scene_stem() {
        let hash = "0123456789abcdef";
        assert!(is_entry_of(&format!("a.{hash}.octcache"), "a"));
        assert!(is_entry_of(&format!("a.b.{hash}.octcache"), "a.b"));
        assert!(!is_entry_of(&format!("a.b.{hash}.octcache"), "a"));
        assert!(!is_entry_of(&format!("a.{hash}.oct"), "a"));
        assert!(!is_entry_of("a.0123.octcache", "a"));
        assert!(!is_entry_of("CACHEDIR.TAG", "a"));
    }
}
