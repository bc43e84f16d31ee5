//! Writing a sharded solid: cells stream in ([`ShardWriter`] is a [`CellSink`]), each
//! partly full cell is written at once as its shard file, and the full cells are
//! only counted. A job is one or more tasks, each over a range of cells; a task ends
//! by writing a part file (its job, its range, its full cells, its shards' entries)
//! and [`join`] turns the parts into the index once every cell is covered.
//!
//! Where things are written ([`super::staging`]): a whole job (one process, every
//! cell) writes into a `run-` folder of its own in `OUT.partial/` and publishes it as
//! `OUT` in one atomic step; the tasks of a job write into the job's folder
//! `OUT.partial/job-ID/`, each file atomically, so a task run again (a retry) writes
//! the same bytes again and the tasks of another job never mix in. The join takes the
//! job's lock, reads and checks every shard the parts list (length, CRC-32, the
//! `.oct` checks, counts, bounds: [`super::solid`]), links them into a `run-` folder
//! of its own with the index, publishes that, and only then removes the job's folder:
//! a join that fails or is killed leaves every part in place to join again. The join
//! is where the cells meet: the full cells are cut into the largest aligned nodes
//! ([`Cells::join_full`]), the only place eight cells can merge.

use std::path::{Path, PathBuf};

use super::INDEX_FILE;
use super::index::{Part, ShardEntry, ShardIndex, read_part};
use super::job::JobId;
use super::layout::Layout;
use super::solid::read_shard;
use super::staging::{self, JoinLock};
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::io::oct::{self, Metadata};
use crate::morton;
use crate::octree::{CellNodes, CellSink, Cells, Domain, LinearOctree, NodeKey, check_level};
use crate::surface::HermiteData;

/// The prefix of part files in a job's folder.
const PART_PREFIX: &str = "part-";

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// Writes the cells of one task of a sharded solid (see the module doc).
pub struct ShardWriter {
    out: PathBuf,
    root: PathBuf,
    /// The `run-` folder of a whole job, removed if the writer is dropped unfinished.
    run: Option<PathBuf>,
    folder: PathBuf,
    job: JobId,
    domain: Domain,
    meta: Metadata,
    cells: Cells,
    full: Vec<u64>,
    shards: Vec<ShardEntry>,
}

impl ShardWriter {
    /// A writer of the cells `cells` of job `job`, the solid going to folder `out`: a
    /// whole job (`task` false) in a `run-` folder of its own, a task in the job's
    /// folder. Removes what killed writers of `out` provably left (the `run-` and
    /// `old-` folders of dead processes of this host).
    pub fn create(
        out: &Path,
        domain: Domain,
        meta: Metadata,
        cells: Cells,
        job: JobId,
        task: bool,
    ) -> Result<ShardWriter> {
        check_level(&cells, &domain)?;
        let root = staging::staging_dir(out);
        staging::own_folder(&root)?;
        staging::remove_stale(&root);
        let (folder, run) = if task {
            let folder = staging::job_dir(&root, job);
            task_folder(&root, &folder)?;
            (folder, None)
        } else {
            let run = staging::new_run_folder(&root)?;
            (run.clone(), Some(run))
        };
        Ok(ShardWriter {
            out: out.to_path_buf(),
            root,
            run,
            folder,
            job,
            domain,
            meta,
            cells,
            full: Vec::new(),
            shards: Vec::new(),
        })
    }

    fn layout(&self) -> Layout {
        Layout { depth: self.domain.depth(), level: self.cells.level }
    }

    fn part(&mut self) -> Part {
        Part {
            job: self.job,
            domain: self.domain,
            meta: self.meta,
            cells: self.cells.clone(),
            full: std::mem::take(&mut self.full),
            shards: std::mem::take(&mut self.shards),
        }
    }

    /// Ends this task: writes its part file. The solid is complete once [`join`] has
    /// run over the parts of every task.
    pub fn finish_part(mut self) -> Result<()> {
        let range = &self.cells.range;
        let name = format!("{PART_PREFIX}{:016x}-{:016x}", range.start, range.end);
        let bytes = self.part().encode();
        write_atomic(self.folder.join(name), |w| w.write_all(&bytes))?;
        Ok(())
    }

    /// Ends a whole job: the index from its own cells into its folder, then the
    /// folder published as the output.
    pub fn finish(mut self) -> Result<ShardIndex> {
        let part = self.part();
        let index = index_of(&self.root, &[(part, self.folder.clone())])?;
        let bytes = index.encode();
        write_atomic(self.folder.join(INDEX_FILE), |w| w.write_all(&bytes))?;
        staging::publish(&self.folder, &self.out, &self.root)?;
        self.run = None;
        staging::remove_if_empty(&self.root);
        Ok(index)
    }
}

impl Drop for ShardWriter {
    fn drop(&mut self) {
        if let Some(run) = &self.run {
            let _ = std::fs::remove_dir_all(run);
            staging::remove_if_empty(&self.root);
        }
    }
}

/// Makes (or finds) a job's folder `folder` in staging folder `root`, both checked.
fn task_folder(root: &Path, folder: &Path) -> Result<()> {
    // Another writer may remove an empty staging folder between the two steps.
    for _ in 0..8 {
        staging::own_folder(root)?;
        match staging::own_folder(folder) {
            Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => {}
            other => return other,
        }
    }
    staging::own_folder(folder)
}

impl CellSink for ShardWriter {
    fn cell(&mut self, index: u64, nodes: CellNodes) -> Result<()> {
        self.cell_with_surface(index, nodes, |_| None)
    }
}

impl ShardWriter {
    /// Takes cell `index` as [`CellSink::cell`] does, a shard with the surface data
    /// `surface` gives for its nodes (`None`: no surface section; every face must be
    /// a boundary face of the shard's own nodes, `crate::io::oct` checks on reading).
    pub fn cell_with_surface(
        &mut self,
        index: u64,
        nodes: CellNodes,
        surface: impl FnOnce(&LinearOctree) -> Option<HermiteData>,
    ) -> Result<()> {
        let keys = match nodes {
            CellNodes::Full => {
                self.full.push(index);
                return Ok(());
            }
            CellNodes::Nodes(keys) => keys,
        };
        let (nodes, depth) = (keys.len() as u64, self.domain.depth());
        let (mut min, mut max) = ([u32::MAX; 3], [0u32; 3]);
        for key in &keys {
            let lo = morton::decode(key.start());
            let size = 1u32 << key.k();
            for a in 0..3 {
                min[a] = min[a].min(lo[a]);
                max[a] = max[a].max(lo[a] + size - 1);
            }
        }
        debug_assert!(keys.iter().all(|k| k.level(depth) > self.cells.level));
        let tree = LinearOctree::from_canonical(self.domain, keys);
        let surface = surface(&tree);
        let bytes = oct::encode_with_surface(&tree, &self.meta, surface.as_ref());
        let path = self.folder.join(self.layout().shard_file(index));
        write_atomic(&path, |w| w.write_all(&bytes))?;
        let entry = ShardEntry {
            cell: index,
            nodes,
            voxels: tree.voxel_count(),
            bytes: bytes.len() as u64,
            crc32: crc32fast::hash(&bytes),
            min,
            max,
        };
        self.shards.push(entry);
        Ok(())
    }
}

/// The parts of one job found in its folder.
struct JobParts {
    job: JobId,
    folder: PathBuf,
    parts: Vec<(Part, PathBuf)>,
}

/// Reads the parts in job folder `folder` (of job `job`), sorted by range.
fn read_job(folder: PathBuf, job: JobId) -> Result<JobParts> {
    staging::check_own_folder(&folder)?;
    let mut parts = Vec::new();
    for entry in std::fs::read_dir(&folder).map_err(io_error(&folder))? {
        let entry = entry.map_err(io_error(&folder))?;
        if entry.file_name().to_string_lossy().starts_with(PART_PREFIX) {
            let path = entry.path();
            let part = read_part(&path)?;
            if part.job != job {
                return Err(Error::invalid(
                    "sharded job",
                    format!("{}: a part of job {} in the folder of job {job}; not joined", path.display(), part.job),
                ));
            }
            parts.push((part, path));
        }
    }
    parts.sort_by_key(|(p, _)| (p.cells.range.start, p.cells.range.end));
    Ok(JobParts { job, folder, parts })
}

/// Joins the parts of the job in `out`'s staging folder into the sharded solid `out`:
/// the one job whose parts cover every cell exactly once (parts of different jobs
/// are never joined), under the job's lock, every shard read and checked against its
/// part, the index written, the solid published in one atomic step (replacing an
/// earlier sharded solid there), and only then the job's folder removed.
pub fn join(out: &Path) -> Result<ShardIndex> {
    let root = staging::staging_dir(out);
    staging::check_own_folder(&root)?;
    staging::remove_stale(&root);
    let job = the_complete_job(&root, jobs_in(&root)?)?;
    let index = index_of(&job.folder, &job.parts)?;
    let _lock = JoinLock::acquire(&job.folder)?;
    // Every shard read and checked before anything is published or removed.
    let layout = index.layout();
    let budget = MemoryBudget::default();
    for entry in &index.shards {
        read_shard(&job.folder.join(layout.shard_file(entry.cell)), entry, index.domain, index.meta, layout, budget)?;
    }
    let run = staging::new_run_folder(&root)?;
    if let Err(e) = assemble(&run, &job.folder, &index, out, &root) {
        let _ = std::fs::remove_dir_all(&run);
        return Err(e);
    }
    // The solid is in place: the job's folder can go.
    std::fs::remove_dir_all(&job.folder).map_err(io_error(&job.folder))?;
    staging::remove_if_empty(&root);
    Ok(index)
}

/// The jobs with parts in staging folder `root`, in the order of their ids.
fn jobs_in(root: &Path) -> Result<Vec<JobParts>> {
    let mut jobs = Vec::new();
    for entry in std::fs::read_dir(root).map_err(io_error(root))? {
        let entry = entry.map_err(io_error(root))?;
        if let Some(job) = staging::job_of(&entry.file_name().to_string_lossy()) {
            jobs.push(read_job(entry.path(), job)?);
        }
    }
    jobs.sort_by_key(|j| j.job.0);
    Ok(jobs)
}

/// The job to join among `jobs` of staging folder `root`: the only one, or the only
/// one whose parts cover every cell; none, or several complete ones, are refused.
fn the_complete_job(root: &Path, mut jobs: Vec<JobParts>) -> Result<JobParts> {
    match jobs.len() {
        0 => Err(Error::invalid("sharded job", format!("{}: no part to join (did any task finish?)", root.display()))),
        1 => Ok(jobs.pop().expect("one")),
        _ => {
            let (complete, incomplete): (Vec<_>, Vec<_>) =
                jobs.into_iter().partition(|j| !j.parts.is_empty() && index_of(root, &j.parts).is_ok());
            let names = |js: &[JobParts]| js.iter().map(|j| j.folder.display().to_string()).collect::<Vec<_>>();
            match <[JobParts; 1]>::try_from(complete) {
                Ok([one]) => Ok(one),
                Err(complete) if complete.is_empty() => Err(Error::invalid(
                    "sharded job",
                    format!(
                        "{}: the parts of {} jobs are there ({}) and none covers every cell; parts of different jobs are never joined",
                        root.display(),
                        incomplete.len(),
                        names(&incomplete).join(", ")
                    ),
                )),
                Err(complete) => Err(Error::invalid(
                    "sharded job",
                    format!(
                        "{}: {} complete jobs ({}); remove the folders of those not wanted",
                        root.display(),
                        complete.len(),
                        names(&complete).join(", ")
                    ),
                )),
            }
        }
    }
}

/// The solid assembled in run folder `run` (the job's shards linked, or copied where
/// they cannot be, and the index written) and published as `out`.
fn assemble(run: &Path, job_folder: &Path, index: &ShardIndex, out: &Path, root: &Path) -> Result<()> {
    let layout = index.layout();
    for entry in &index.shards {
        let name = layout.shard_file(entry.cell);
        let (from, to) = (job_folder.join(&name), run.join(&name));
        if std::fs::hard_link(&from, &to).is_err() {
            std::fs::copy(&from, &to).map_err(io_error(&from))?;
        }
    }
    let bytes = index.encode();
    write_atomic(run.join(INDEX_FILE), |w| w.write_all(&bytes))?;
    staging::publish(run, out, root)
}

/// The index of a job from its parts (sorted by range): checks that they are of one
/// solid and cover every cell exactly once, and cuts the full cells into the largest
/// aligned nodes. `folder` names the job in errors.
fn index_of(folder: &Path, parts: &[(Part, PathBuf)]) -> Result<ShardIndex> {
    let Some((first, first_path)) = parts.first() else {
        return Err(Error::invalid(
            "sharded job",
            format!("{}: no part to join (did any task finish?)", folder.display()),
        ));
    };
    let (job, domain, meta, level) = (first.job, first.domain, first.meta, first.cells.level);
    let mut next = 0u64;
    for (part, path) in parts {
        if part.job != job || part.domain != domain || part.meta != meta || part.cells.level != level {
            return Err(Error::invalid(
                "sharded job",
                format!("{} and {} are parts of different solids", first_path.display(), path.display()),
            ));
        }
        let range = &part.cells.range;
        if range.start != next {
            let what = if range.start > next { "no part covers" } else { "two parts cover" };
            return Err(Error::invalid(
                "sharded job",
                format!(
                    "{}: {what} cells {}..{} (at {})",
                    folder.display(),
                    next.min(range.start),
                    next.max(range.start),
                    path.display()
                ),
            ));
        }
        next = range.end;
    }
    let count = Cells::count(level);
    if next != count {
        return Err(Error::invalid(
            "sharded job",
            format!("{}: no part covers cells {next}..{count}", folder.display()),
        ));
    }
    let full_cells = parts.iter().flat_map(|(p, _)| p.full.iter().copied());
    let full: Vec<NodeKey> = Cells::join_full(level, domain.depth(), full_cells);
    let shards: Vec<ShardEntry> = parts.iter().flat_map(|(p, _)| p.shards.iter().cloned()).collect();
    let nodes = full.len() as u64 + shards.iter().map(|s| s.nodes).sum::<u64>();
    let voxels = full.iter().map(|k| k.len()).sum::<u64>() + shards.iter().map(|s| s.voxels).sum::<u64>();
    Ok(ShardIndex { job, domain, meta, level, nodes, voxels, full, shards })
}
