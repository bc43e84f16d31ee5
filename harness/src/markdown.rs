//! The report section of BENCHMARKS.md: machine and date, one table a scene, the plots,
//! and a summary in words generated from the measured numbers; and the splice that
//! replaces only the text between the section's markers.

use std::fmt::Write as _;

use super::matrix::{CaseResult, ContenderKind, ContenderResult, MatrixResults};
use super::rays::RayKind;
use super::scenes::SceneKind;
use octsolid::{Error, Result, human_bytes};

/// First line of the section.
pub const BEGIN: &str = "<!-- bvh-report:begin -->";
/// Last line of the section.
pub const END: &str = "<!-- bvh-report:end -->";

/// `existing` with the lines from [`BEGIN`] to [`END`] (inclusive) replaced by
/// `section` (which holds both markers); appended after a blank line when there is no
/// section yet. Everything outside the markers is kept byte for byte. `name` names the
/// file in errors (a begin marker without an end).
pub fn splice_section(existing: &str, section: &str, name: &std::path::Path) -> Result<String> {
    let Some(begin) = existing.find(BEGIN) else {
        let mut out = existing.to_string();
        if !out.is_empty() && !out.ends_with('\n') {
            out.push('\n');
        }
        if !out.is_empty() {
            out.push('\n');
        }
        out.push_str(section);
        return Ok(out);
    };
    let Some(end) = existing[begin..].find(END).map(|e| begin + e + END.len()) else {
        let line = existing[..begin].lines().count() + 1;
        return Err(Error::Parse {
            path: name.to_path_buf(),
            line,
            reason: format!("'{BEGIN}' has no '{END}' after it"),
        });
    };
    // The section ends with a newline; keep the one after the old end marker out.
    let rest = existing[end..].strip_prefix('\n').unwrap_or(&existing[end..]);
    Ok(format!("{}{}{}", &existing[..begin], section, rest))
}

/// Mrays/s with its ratio to the octree's, e.g. `12.3 (0.45x)`.
fn cell(c: &ContenderResult, octree: Option<&ContenderResult>, kind: RayKind, threads: usize) -> String {
    let Some(s) = c.speed(kind, threads) else { return "-".into() };
    match octree.and_then(|o| o.speed(kind, threads)) {
        Some(o) if c.kind != ContenderKind::Octree => format!("{:.2} ({:.2}x)", s.mrays(), s.mrays() / o.mrays()),
        _ => format!("{:.2}", s.mrays()),
    }
}

/// Ratio `a / b` of the same measurement of two contenders in one case.
fn speed_ratio(case: &CaseResult, a: ContenderKind, b: ContenderKind, kind: RayKind, threads: usize) -> Option<f64> {
    let sa = case.contender(a)?.speed(kind, threads)?;
    let sb = case.contender(b)?.speed(kind, threads)?;
    Some(sa.mrays() / sb.mrays())
}

/// `min..max` of ratios, e.g. `3.1x to 40x`.
fn range(values: &[f64]) -> String {
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if (hi - lo).abs() < 0.05 * hi { format!("{lo:.2}x") } else { format!("{lo:.2}x to {hi:.2}x") }
}

/// The summary in words: who wins where, from the numbers.
fn findings(r: &MatrixResults) -> String {
    let mut out = String::new();
    build_finding(r, &mut out);
    for kind in RayKind::ALL {
        tracing_finding(r, kind, &mut out);
    }
    bunny_findings(r, &mut out);
    packet_finding(r, &mut out);
    agreement_finding(r, &mut out);
    out
}

/// The BVHs over the octree's own boundary faces that trace one ray a call, as the
/// octree does (Embree's 8-ray packets have their own finding).
const FACES: [ContenderKind; 3] = [ContenderKind::ObvhsFaces, ContenderKind::BvhFaces, ContenderKind::EmbreeFaces];

/// The BVHs over the original mesh that trace one ray a call.
const MESH: [ContenderKind; 3] = [ContenderKind::ObvhsMesh, ContenderKind::BvhMesh, ContenderKind::EmbreeMesh];

/// Embree traced 8 rays a call, and the same structure one ray a call.
const PACKETS: [(ContenderKind, ContenderKind); 2] = [
    (ContenderKind::EmbreePacketsFaces, ContenderKind::EmbreeFaces),
    (ContenderKind::EmbreePacketsMesh, ContenderKind::EmbreeMesh),
];

/// Build: octree build speed and memory against each BVH over the same boundary faces.
fn build_finding(r: &MatrixResults, out: &mut String) {
    let mut build = Vec::new();
    let mut bytes = Vec::new();
    for case in &r.cases {
        let Some(o) = case.contender(ContenderKind::Octree) else { continue };
        for k in FACES {
            if let Some(c) = case.contender(k).filter(|c| c.skipped.is_none()) {
                build.push(c.build_ms / o.build_ms.max(1e-6));
                bytes.push(c.bytes as f64 / o.bytes.max(1) as f64);
            }
        }
    }
    if build.is_empty() {
        return;
    }
    let faster = build.iter().filter(|&&x| x > 1.0).count();
    let _ = writeln!(
        out,
        "- **Build.** Against a BVH over its own boundary faces, the octree built faster in {faster} of {} \
         cases (the BVH took {} the octree's time) and took less memory in {} of {} (the BVH held {} the \
         octree's bytes). The octree's build is one sequential pass over the sorted node keys; a BVH must \
         sort or partition every boundary triangle, and it stores boxes and triangles where the octree \
         stores 8 bytes an inner node.",
        build.len(),
        range(&build),
        bytes.iter().filter(|&&x| x > 1.0).count(),
        bytes.len(),
        range(&bytes),
    );
}

/// Tracing rays of `kind` against the BVHs over the same faces.
fn tracing_finding(r: &MatrixResults, kind: RayKind, out: &mut String) {
    let threads = r.options.threads;
    let mut ratios = Vec::new();
    let mut lost = Vec::new();
    for case in &r.cases {
        for k in FACES {
            if let Some(x) = speed_ratio(case, ContenderKind::Octree, k, kind, threads) {
                ratios.push(x);
                if x < 1.0 {
                    lost.push(format!("{} {} at depth {}", k.label(), case.scene.name(), case.depth));
                }
            }
        }
    }
    if ratios.is_empty() {
        return;
    }
    let wins = ratios.iter().filter(|&&x| x >= 1.0).count();
    let _ = write!(
        out,
        "- **{} rays, {threads} threads, same boundary faces.** The octree was faster in {wins} of {} cases \
         ({} the BVH's rays a second).",
        kind.name(),
        ratios.len(),
        range(&ratios)
    );
    if lost.is_empty() {
        let _ = writeln!(
            out,
            " Its walk steps through empty space a node at a time with exact integer-plane crossings and \
             stops at the first full node, while a BVH over the faces tests overlapping boxes and then \
             triangles."
        );
    } else {
        let _ = writeln!(
            out,
            " It lost to {}: there the BVH's wide nodes and f32 box tests cost less than the octree's \
             per-level f64 plane crossings.",
            lost.join(", ")
        );
    }
}

/// The original bunny mesh, primary rays: is the octree within 2x of each BVH?
fn bunny_findings(r: &MatrixResults, out: &mut String) {
    let threads = r.options.threads;
    for case in r.cases.iter().filter(|c| c.scene == SceneKind::Bunny) {
        for k in MESH {
            let (Some(x), Some(mesh)) =
                (speed_ratio(case, ContenderKind::Octree, k, RayKind::Primary, threads), case.contender(k))
            else {
                continue;
            };
            let verdict = if x >= 1.0 {
                "faster than it".to_string()
            } else if x >= 0.5 {
                format!("within 2x of it ({:.2}x slower)", 1.0 / x)
            } else {
                format!(
                    "**not** within 2x of it ({:.2}x slower): the mesh has only {} triangles, so the BVH is shallow, \
                     while the octree at depth {} must cross about twice as many levels and many small nodes near \
                     the surface",
                    1.0 / x,
                    mesh.triangles,
                    case.depth
                )
            };
            let _ = writeln!(
                out,
                "- **Bunny, primary rays, depth {}.** Against {} ({} triangles), the octree is {verdict}.",
                case.depth,
                k.label(),
                mesh.triangles
            );
        }
    }
}

/// Embree's 8-ray packets against its own one ray a call, each ray kind, all threads.
fn packet_finding(r: &MatrixResults, out: &mut String) {
    let threads = r.options.threads;
    let mut parts = Vec::new();
    for kind in RayKind::ALL {
        let ratios: Vec<f64> = r
            .cases
            .iter()
            .flat_map(|case| PACKETS.iter().filter_map(move |&(p, one)| speed_ratio(case, p, one, kind, threads)))
            .collect();
        if !ratios.is_empty() {
            parts.push(format!("{} rays {}", kind.name(), range(&ratios)));
        }
    }
    if parts.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "- **Embree's 8-ray packets, {threads} threads.** Against the same Embree scene traced one ray a call, \
         8 consecutive rays a call ran at {} its rays a second. The other contenders, the octree included, \
         trace one ray a call.",
        parts.join(", ")
    );
}

/// Over `pairs` (a case, a contender, the contender it is compared with), the ray sets
/// compared and the largest difference in hits: rays, fraction of its set, and where.
fn largest_difference(pairs: &[(&CaseResult, ContenderKind, ContenderKind)]) -> (usize, Option<(u64, f64, String)>) {
    let mut sets = 0;
    let mut worst: Option<(u64, f64, String)> = None;
    for &(case, k, reference) in pairs {
        let (Some(c), Some(o)) = (case.contender(k), case.contender(reference)) else { continue };
        for s in &c.speeds {
            let Some(os) = o.speed(s.kind, s.threads) else { continue };
            sets += 1;
            let diff = s.hits.abs_diff(os.hits);
            let fraction = diff as f64 / s.rays.max(1) as f64;
            if diff > 0 && worst.as_ref().is_none_or(|w| fraction > w.1) {
                let at =
                    format!("{}, {} at depth {}, {} rays", k.label(), case.scene.name(), case.depth, s.kind.name());
                worst = Some((diff, fraction, at));
            }
        }
    }
    (sets, worst)
}

/// `what` and the result of [`largest_difference`] in words.
fn difference_words(what: &str, (sets, worst): (usize, Option<(u64, f64, String)>)) -> String {
    match worst {
        None => format!("{what} were equal in all {sets} ray sets"),
        Some((diff, fraction, at)) => {
            format!(
                "{what} differed by at most {diff} rays in {sets} ray sets ({:.3}% of the set: {at})",
                100.0 * fraction
            )
        }
    }
}

/// Hit counts on the same rays: each contender over the boundary faces against the
/// octree (the same surface), and Embree against obvhs over the original mesh (both
/// `f32`, neither culls back faces; the `bvh` crate culls them, which the open bunny
/// shows through its base).
fn agreement_finding(r: &MatrixResults, out: &mut String) {
    const OVER_FACES: [ContenderKind; 4] = [
        ContenderKind::ObvhsFaces,
        ContenderKind::BvhFaces,
        ContenderKind::EmbreeFaces,
        ContenderKind::EmbreePacketsFaces,
    ];
    let faces: Vec<_> = r.cases.iter().flat_map(|c| OVER_FACES.map(|k| (c, k, ContenderKind::Octree))).collect();
    let mesh: Vec<_> = r
        .cases
        .iter()
        .flat_map(|c| {
            [ContenderKind::EmbreeMesh, ContenderKind::EmbreePacketsMesh].map(|k| (c, k, ContenderKind::ObvhsMesh))
        })
        .collect();
    let (faces, mesh) = (largest_difference(&faces), largest_difference(&mesh));
    let mut parts = Vec::new();
    if faces.0 > 0 {
        parts.push(difference_words("the hit counts of the BVHs over the boundary faces and the octree's", faces));
    }
    if mesh.0 > 0 {
        parts.push(difference_words("Embree's and obvhs's over the original mesh", mesh));
    }
    if parts.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "- **Agreement.** On the same rays, {}. A difference is a ray that one hits and the other misses: one \
         through an edge shared by two triangles, which an f32 test can slip through, or, for shadow rays over \
         the original mesh, one that starts within a voxel of the mesh (its origin is on the octree's surface), \
         whose hit at a distance near 0 one of them can miss. `tests/bvh.rs` and `tests/embree.rs` compare every \
         ray with exact references.",
        parts.join("; ")
    );
}

/// The whole section, markers included; `images` is the folder of the plots relative
/// to the Markdown file, `plots` their file names.
#[must_use]
pub fn render_section(r: &MatrixResults, images: &str, plots: &[String]) -> String {
    let m = &r.machine;
    let o = &r.options;
    let threads = o.threads;
    let mut s = String::new();
    let _ = writeln!(s, "{BEGIN}");
    let _ = writeln!(s, "## Octree traversal against BVHs (`octsolid bench --report`)\n");
    let memory = m.memory.map_or(String::new(), |b| format!(", {}", human_bytes(b)));
    let _ = writeln!(
        s,
        "Measured on {} ({} hardware threads{memory}), {}, on {}. Generated by `octsolid bench --report`; \
         the same rays for every contender: primary = one a pixel of a {size}x{size} image from a framing \
         camera, shadow = from every primary hit towards a far point light, random = {} rays from the sphere \
         around the solid's box through random points of the box. Median of up to {} runs after a warm-up; \
         \"1\" and \"{threads}\" are thread counts (rayon pools). Build times use all threads. Cells are \
         Mrays/s with the ratio to the octree in brackets.\n",
        m.cpu,
        m.cores,
        m.os,
        m.date,
        o.random_rays,
        o.repeats,
        size = o.image_size,
    );
    let _ = writeln!(
        s,
        "Contenders: **octree** = our traversal octree (`src/render/trace/`, f64); **obvhs** = \
         obvhs CWBVH (`medium_build` preset, f32, SIMD); **bvh** = bvh crate binary SAH BVH (f64, \
         best-first traversal). *Boundary faces* = the octree's boundary mesh (`mesh::boundary_mesh`, \
         coplanar faces merged); *original mesh* = the triangles the bunny was voxelized from. Bytes: the \
         octree's traversal nodes; a BVH's node array plus the primitive data it keeps.\n"
    );
    if let Some(version) = &r.embree {
        let _ = writeln!(
            s,
            "**embree** = Embree {version}, the system library through the `embree` crate's bindings \
             (`harness/src/embree_contender.rs`; `--features embree`): its BVH at the default build quality \
             (medium), f32, one ray a call (`rtcIntersect1`, `rtcOccluded1`); *embree 8-ray packets* = the same \
             scene traced 8 consecutive rays a call (`rtcIntersect8`, `rtcOccluded8`; for primary rays 8 \
             neighbouring pixels of a row, with the coherent flag). Its build time includes creating the Embree \
             device; its bytes are what Embree's memory monitor counts once the scene is committed (BVH, \
             triangle data, vertex and index buffers).\n"
        );
    }
    let _ = writeln!(s, "### Findings\n\n{}", findings(r));
    for scene in &o.scenes {
        let _ = writeln!(s, "### {} ({})\n", scene.name(), scene.description());
        let _ = writeln!(
            s,
            "| depth | contender | triangles | build ms | bytes | primary 1 | primary {threads} | shadow 1 | \
             shadow {threads} | random 1 | random {threads} |"
        );
        let _ = writeln!(s, "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
        for case in r.cases.iter().filter(|c| c.scene == *scene) {
            let octree = case.contender(ContenderKind::Octree);
            for c in &case.contenders {
                let tris = if c.kind == ContenderKind::Octree {
                    format!("({} nodes)", case.octree_nodes)
                } else {
                    c.triangles.to_string()
                };
                if let Some(why) = &c.skipped {
                    let _ =
                        writeln!(s, "| {} | {} | {tris} | skipped: {why} | | | | | | | |", case.depth, c.kind.label());
                    continue;
                }
                let mut row = format!(
                    "| {} | {} | {tris} | {:.1} | {} |",
                    case.depth,
                    c.kind.label(),
                    c.build_ms,
                    human_bytes(c.bytes as u64)
                );
                for kind in RayKind::ALL {
                    for t in [1, threads] {
                        let _ = write!(row, " {} |", cell(c, octree, kind, t));
                    }
                }
                let _ = writeln!(s, "{row}");
            }
        }
        let _ = writeln!(s);
    }
    for p in plots {
        let _ = writeln!(s, "![{p}]({images}/{p})\n");
    }
    let _ = writeln!(s, "{END}");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn splice_replaces_only_the_section() {
        let old = format!("# Title\n\nbefore\n{BEGIN}\nold\n{END}\nafter\n");
        let new = splice_section(&old, &format!("{BEGIN}\nnew\n{END}\n"), Path::new("B.md")).unwrap();
        assert_eq!(new, format!("# Title\n\nbefore\n{BEGIN}\nnew\n{END}\nafter\n"));
    }

    /// A contender row with `hits` of 1,000 primary rays on 1 thread.
    fn row(kind: ContenderKind, hits: u64) -> ContenderResult {
        let speed = crate::matrix::Speed { kind: RayKind::Primary, threads: 1, rays: 1000, hits, seconds: 1.0 };
        ContenderResult { kind, skipped: None, triangles: 0, build_ms: 1.0, bytes: 1, nodes: 0, speeds: vec![speed] }
    }

    #[test]
    fn agreement_names_the_largest_difference_in_hits() {
        let case = |depth, contenders| CaseResult {
            scene: SceneKind::Sphere,
            depth,
            octree_nodes: 1,
            face_triangles: 1,
            faces_ms: 0.0,
            rays: vec![(RayKind::Primary, 1000)],
            contenders,
        };
        let cases = vec![
            case(8, vec![row(ContenderKind::Octree, 500), row(ContenderKind::ObvhsFaces, 498)]),
            case(10, vec![row(ContenderKind::Octree, 400), row(ContenderKind::EmbreeFaces, 407)]),
        ];
        let machine = crate::Machine::current();
        let mut r = MatrixResults { machine, options: crate::MatrixOptions::quick(), embree: None, cases };
        let mut out = String::new();
        agreement_finding(&r, &mut out);
        assert!(out.contains("octree's differed by at most 7 rays in 2 ray sets (0.700% of the set: embree, boundary faces, sphere at depth 10, primary rays)"), "{out}");
        assert!(!out.contains("Embree's and obvhs's"), "{out}");
        r.cases[1].contenders[1] = row(ContenderKind::EmbreeFaces, 400);
        r.cases[0].contenders[1] = row(ContenderKind::ObvhsFaces, 500);
        out.clear();
        agreement_finding(&r, &mut out);
        assert!(out.contains("octree's were equal in all 2 ray sets."), "{out}");
    }

    #[test]
    fn splice_appends_when_missing_and_refuses_an_open_section() {
        let section = format!("{BEGIN}\nx\n{END}\n");
        assert_eq!(splice_section("a\n", &section, Path::new("B.md")).unwrap(), format!("a\n\n{section}"));
        assert!(splice_section(&format!("a\n{BEGIN}\n"), &section, Path::new("B.md")).is_err());
    }
}
