//! The section of issue 41's incoherent rays in the report (`octsolid bench --report
//! --issue-rays`, between its own markers in docs/bvh-report.md): where and what, one
//! table of rays a second, branch misses and instructions a ray, one of hit counts,
//! and the notes on what could not be measured.

use std::fmt::Write as _;
use std::path::Path;

use super::markdown::splice_between;
use super::matrix::ContenderKind;
use super::rays::RayKind;
use super::secondary_bench::{SecondaryResults, SecondaryRow};
use super::secondary_rays::{EYE, FOV_Y, LIFT_DIAGONALS};
use octsolid::io::write_atomic;
use octsolid::{Error, Result, human_bytes};

/// First line of the section.
pub const BEGIN: &str = "<!-- issue-rays:begin -->";
/// Last line of the section.
pub const END: &str = "<!-- issue-rays:end -->";

/// The sets in table order.
const SETS: [RayKind; 3] = [RayKind::Primary, RayKind::Bounce, RayKind::Shadow];

/// `mrays (ratio to the octree)`, or `-`.
fn speed(row: &SecondaryRow, octree: Option<&SecondaryRow>, kind: RayKind) -> String {
    let Some(s) = row.set(kind) else { return "-".into() };
    match octree.and_then(|o| o.set(kind)) {
        Some(o) if row.kind != Some(ContenderKind::Octree) => {
            format!("{:.2} ({:.2}x)", s.mrays(), s.mrays() / o.mrays())
        }
        _ => format!("{:.2}", s.mrays()),
    }
}

/// One count a ray per set, `p / b / s`, `n/a` where not counted.
fn per_ray(row: &SecondaryRow, value: impl Fn(&super::secondary_bench::SetResult) -> Option<f64>) -> String {
    SETS.map(|k| row.set(k).and_then(&value).map_or("n/a".to_string(), |v| format!("{v:.1}"))).join(" / ")
}

/// The measure in words: the bounce and shadow rays a second of each of ours
/// (the octree, the 64-tree) over each Embree's on the source mesh (target: at least
/// 1x), one line a pair.
fn against_embree(r: &SecondaryResults) -> String {
    let mut out = String::new();
    let ran = |row: &&SecondaryRow| row.skipped.is_none();
    let ours = r.rows.iter().filter(ran).filter(|row| row.kind.is_some_and(ContenderKind::is_ours));
    for own in ours {
        let embree = r
            .rows
            .iter()
            .filter(ran)
            .filter(|row| row.kind == Some(ContenderKind::EmbreeMesh) || row.label.starts_with("embreex"));
        for row in embree {
            let ratio = |k| Some(own.set(k)?.mrays() / row.set(k)?.mrays());
            let (Some(bounce), Some(shadow)) = (ratio(RayKind::Bounce), ratio(RayKind::Shadow)) else { continue };
            let name = if own.kind == Some(ContenderKind::Octree) { "Octree" } else { "64-tree" };
            let _ = writeln!(
                out,
                "- **{name} against {}** (issue 41's target: at least 1x): bounce rays {bounce:.2}x, shadow \
                 rays {shadow:.2}x.",
                row.label
            );
        }
    }
    if out.is_empty() { out } else { format!("\n{out}") }
}

/// The section, markers included.
#[must_use]
pub fn render_secondary(r: &SecondaryResults) -> String {
    let (m, o) = (&r.machine, &r.options);
    let mut s = String::new();
    let _ = writeln!(s, "{BEGIN}");
    let _ = writeln!(s, "## Issue 41's incoherent rays (`octsolid bench --report --issue-rays`)\n");
    let memory = m.memory.map_or(String::new(), |b| format!(", {}", human_bytes(b)));
    let count = |k: RayKind| r.rays.iter().find(|(kind, _)| *kind == k).map_or(0, |(_, n)| *n);
    let _ = writeln!(
        s,
        "Measured on {} ({} hardware threads{memory}), {}, on {}. `{}` ({} triangles) at depth {} \
         ({} boundary-face triangles). The rays (`harness/src/secondary_rays.rs`, written to `{}` for the \
         peers): **primary** = {} rays, one a pixel of a {size}x{size} view from the eye ({}, {}, {}) at \
         the box's centre, {FOV_Y} degrees; from each primary hit of the octree, {LIFT_DIAGONALS} voxel \
         diagonals off the surface along the face's normal, **bounce** = {} cosine-weighted rays about the \
         normal (seed {}, closest hit) and **shadow** = {} rays to a point light (any hit). One thread, its CPU time; \
         median of {} runs after a warm-up; builds on all threads. Cells are Mrays/s with the ratio to the \
         octree in brackets; branch misses and instructions are a ray, primary / bounce / shadow, counted \
         by `perf stat` around `walk_one` on one contender and one set (`benches/peers/branch_misses.sh`); \
         where it has no hardware counters, `valgrind --tool=callgrind --branch-sim=yes` simulates them \
         (BENCHMARKS.md). The 64-tree (4x4x4 nodes, `src/render/trace/tree64/`) finds the octree's hits \
         bit for bit.\n",
        m.cpu,
        m.cores,
        m.os,
        m.date,
        o.model.display(),
        r.mesh_triangles,
        o.depth,
        r.face_triangles,
        o.rays_dir.display(),
        count(RayKind::Primary),
        EYE.x,
        EYE.y,
        EYE.z,
        count(RayKind::Bounce),
        o.seed,
        count(RayKind::Shadow),
        o.repeats,
        size = o.size,
    );
    let octree = r.rows.iter().find(|row| row.kind == Some(ContenderKind::Octree));
    let _ = writeln!(
        s,
        "| contender | triangles | build ms | bytes | primary | bounce | shadow | branch misses a ray | \
         instructions a ray |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for row in &r.rows {
        let tris = if row.kind.is_some_and(ContenderKind::is_ours) { String::new() } else { row.triangles.to_string() };
        if let Some(why) = &row.skipped {
            let _ = writeln!(s, "| {} | {tris} | skipped: {why} | | | | | | |", row.label);
            continue;
        }
        let bytes = if row.bytes == 0 { "-".into() } else { human_bytes(row.bytes as u64) };
        let _ = writeln!(
            s,
            "| {} | {tris} | {:.1} | {bytes} | {} | {} | {} | {} | {} |",
            row.label,
            row.build_ms,
            speed(row, octree, RayKind::Primary),
            speed(row, octree, RayKind::Bounce),
            speed(row, octree, RayKind::Shadow),
            per_ray(row, |x| x.branch_misses),
            per_ray(row, |x| x.instructions),
        );
    }
    let _ = writeln!(s, "\nHits (closest hits found; occluded shadow rays):\n");
    let _ = writeln!(s, "| contender | primary | bounce | shadow |");
    let _ = writeln!(s, "|---|---:|---:|---:|");
    for row in r.rows.iter().filter(|row| row.skipped.is_none()) {
        let hits = SETS.map(|k| row.set(k).map_or("-".to_string(), |x| x.hits.to_string()));
        let _ = writeln!(s, "| {} | {} |", row.label, hits.join(" | "));
    }
    let _ = write!(s, "{}", against_embree(r));
    if !r.notes.is_empty() {
        let _ = writeln!(s);
        for note in &r.notes {
            let _ = writeln!(s, "- {note}");
        }
    }
    let _ = writeln!(s, "{END}");
    s
}

/// Splices the section into `markdown` (atomically; appended when the file has none, the
/// whole file when it is new).
pub fn write_secondary_report(r: &SecondaryResults, markdown: &Path) -> Result<()> {
    let existing = match std::fs::read_to_string(markdown) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(source) => return Err(Error::Io { path: markdown.to_path_buf(), source }),
    };
    let text = splice_between(&existing, &render_secondary(r), [BEGIN, END], markdown)?;
    write_atomic(markdown, |w| w.write_all(text.as_bytes()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::secondary_bench::{SecondaryOptions, SetResult};

    /// A row whose sets take `seconds` (primary, bounce, shadow) for 1,000,000 rays.
    fn row(kind: Option<ContenderKind>, label: &str, seconds: [f64; 3], misses: Option<f64>) -> SecondaryRow {
        let sets = SETS
            .iter()
            .zip(seconds)
            .map(|(&kind, seconds)| SetResult {
                kind,
                rays: 1_000_000,
                hits: 10,
                seconds,
                branch_misses: misses,
                instructions: None,
            })
            .collect();
        SecondaryRow { kind, label: label.into(), skipped: None, triangles: 3700, build_ms: 2.0, bytes: 0, sets }
    }

    #[test]
    fn the_section_has_its_markers_rows_ratios_and_notes() {
        let r = SecondaryResults {
            machine: crate::Machine::current(),
            options: SecondaryOptions::default(),
            mesh_triangles: 3700,
            face_triangles: 100,
            rays: vec![(RayKind::Primary, 1_000_000), (RayKind::Bounce, 400_000), (RayKind::Shadow, 400_000)],
            rows: vec![
                row(Some(ContenderKind::Octree), "octree (ours)", [0.2, 0.5, 0.25], Some(21.0)),
                row(Some(ContenderKind::Tree64), "64-tree (ours)", [0.3, 0.25, 0.2], None),
                row(Some(ContenderKind::EmbreeMesh), "embree, original mesh", [0.1, 0.125, 0.1], None),
            ],
            notes: vec!["branch misses: n/a, no counters".into()],
        };
        let s = render_secondary(&r);
        assert!(s.starts_with(BEGIN) && s.ends_with(&format!("{END}\n")), "{s}");
        // 1 M rays in 0.5 s against 0.125 s: 2 against 8 Mrays/s.
        assert!(s.contains("| 8.00 (4.00x) |"), "{s}");
        assert!(s.contains("| 21.0 / 21.0 / 21.0 | n/a / n/a / n/a |"), "{s}");
        assert!(s.contains("**Octree against embree, original mesh** (issue 41's target: at least 1x): bounce rays 0.25x, shadow rays 0.40x."), "{s}");
        // The 64-tree: 4 and 5 Mrays/s, 2x and 1.25x the octree's, half Embree's; no triangles.
        assert!(s.contains("| 64-tree (ours) |  | 2.0 | - | 3.33 (0.67x) | 4.00 (2.00x) | 5.00 (1.25x) |"), "{s}");
        assert!(s.contains("**64-tree against embree, original mesh** (issue 41's target: at least 1x): bounce rays 0.50x, shadow rays 0.50x."), "{s}");
        assert!(s.contains("- branch misses: n/a, no counters"), "{s}");
        let doc = format!("# Report\n\n{s}\nafter\n");
        let again = splice_between(&doc, &s, [BEGIN, END], Path::new("r.md")).unwrap();
        assert_eq!(again, doc);
    }
}
