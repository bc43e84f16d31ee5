//! Sheets moved apart: a closed mesh whose vertex table holds one position more than
//! once, changed so that no two vertices share a position even in `f32`, for formats
//! that store positions only (STL), whose readers weld corners by position.
//!
//! A boundary mesh ([`super::boundary_mesh`]) keeps one vertex a sheet where voxels
//! touch only along an edge or at a corner: the copies share a position but no edge,
//! and every edge has two faces. Welded by position, the copies become one vertex and
//! the edges along a contact get four faces. So each copy `v` of a shared position `p`
//! is moved a small step towards its own faces and away from the other copies':
//!
//! `t_v = unit(sum over the triangles at v of alpha_t unit(c_t - p))`,
//! `d_v = t_v - sum over the other copies u at p of t_u`,   `q_v = p + delta_v unit(d_v)`,
//!
//! `alpha_t` the angle of triangle `t` at `v` and `c_t` its centroid. Two voxels
//! touching at a corner or along an edge each take their own copy into themselves, so
//! a gap opens between them; two empty corners touching in a solid each take theirs
//! into the empty corner, so solid closes between them; where one sheet wraps around
//! another (a full corner whose three neighbours are empty), `t` of the outer one
//! vanishes and `d` takes it away from the inner one. The moved sheets do not cross
//! (tests/stl_export.rs checks the winding number around every configuration of the
//! eight voxels at a point, and random ones). Pseudo-normals would not do: at a
//! concave corner the inward normal points into the other sheet, and the two sheets
//! of a wrapped corner have the same one.
//!
//! The step is `delta_v = max(l_v / 1024, 4 ulp(m))`, `l_v` the shortest edge at `v`
//! (at least one voxel in a boundary mesh), `ulp(m)` the spacing of `f32` at `m`, the
//! largest coordinate magnitude of `p`: a thousandth of a voxel where `f32` resolves
//! it, else as many units in the last place as keep the copies apart after rounding
//! (the unit directions of two copies at a point differ by more than 1 in some
//! component, 1.06 at least over the configurations the tests try, so the moved
//! copies differ there by more than 4 ulp, and rounding moves each by half of one).
//! A step above `l_v / 16` is refused: that is coordinates beyond about `2^17` voxels
//! from the origin, where `f32` cannot separate the sheets without moving them visibly.
//! Readers that weld within a tolerance rather than exactly (trimesh: `10^-8`) keep
//! the copies apart when the step exceeds it, so for voxels above `10^-5`.
//!
//! Volume: moving one vertex by `d` changes the signed-tetrahedron volume by exactly
//! `d . A_v / 3`, `A_v` the sum of the area vectors of its triangles, so the enclosed
//! volume changes by at most `sum_v delta_v |A_v| / 3` (plus terms in `delta^2` where
//! moved vertices share a triangle). At `l_v / 1024` that is under `6 * 10^-4` voxel
//! volumes a copy at a voxel corner of a unit-face mesh.
//!
//! Then every used vertex is rounded to `f32` as STL stores it, and two vertices that
//! round to one point (the copies above, or distinct points that `f32` cannot tell
//! apart) are refused, naming them. Vertices at a position of their own keep their
//! coordinates bit for bit.

use glam::DVec3;
use rayon::prelude::*;

use super::TriangleMesh;
use crate::error::{Error, Result};

/// The step as a fraction of the shortest edge at a vertex.
pub const SEPARATION_STEP: f64 = 1.0 / 1024.0;
/// The largest step accepted, as a fraction of the shortest edge at a vertex.
pub const SEPARATION_LIMIT: f64 = 1.0 / 16.0;
/// The least step in units in the last place of `f32` at the vertex's coordinates.
const STEP_ULPS: f64 = 4.0;
/// Vertices or triangles a parallel task.
const CHUNK: usize = 4096;

/// `mesh` with the copies of each shared position moved apart, each towards its own
/// faces and away from the others', so that STL's `f32` corners, welded by position,
/// give back the same vertices and triangles (module doc). Meant for closed,
/// outward-oriented meshes ([`TriangleMesh::is_watertight`]); a mesh without shared
/// positions comes back unchanged.
///
/// # Errors
/// When the mesh fails [`TriangleMesh::validate`], `f32` cannot separate the copies of a
/// position within [`SEPARATION_LIMIT`] of the shortest edge, or two vertices round to
/// the same `f32` point (copies that could not be moved apart, or distinct points
/// where the coordinates are too large for the distances between them).
pub fn separate_sheets(mesh: &TriangleMesh) -> Result<TriangleMesh> {
    mesh.validate()?;
    separate(mesh).map_err(|reason| Error::invalid("mesh for STL", reason))
}

/// [`separate_sheets`] after the check, with the reason of a refusal: the copies found,
/// moved apart, and every used vertex checked distinct in `f32`.
pub(crate) fn separate(mesh: &TriangleMesh) -> std::result::Result<TriangleMesh, String> {
    let vertices = separated_vertices(mesh)?;
    Ok(TriangleMesh { vertices, triangles: mesh.triangles.clone(), groups: mesh.groups.clone() })
}

/// The vertices of [`separate`]`(mesh)`. The copies are found and checked by sorting
/// positions in parallel (the first vertex at a position, and the first refusal in
/// vertex order, as one pass over the vertices with a hash table finds them).
pub(crate) fn separated_vertices(mesh: &TriangleMesh) -> std::result::Result<Vec<DVec3>, String> {
    let n = mesh.vertices.len();
    let mut used = vec![false; n];
    mesh.triangles.iter().flatten().for_each(|&i| used[i as usize] = true);
    let Copies { group, shared } = copies(mesh, &used);
    let mut out = mesh.vertices.clone();
    if shared.par_iter().any(|&s| s) {
        move_copies_apart(mesh, &group, &shared, &mut out)?;
    }
    distinct_in_f32(mesh, &out, &used)?;
    Ok(out)
}

/// A position's exact bits, `+0.0` and `-0.0` alike.
fn exact(v: DVec3) -> [u64; 3] {
    (v + DVec3::ZERO).to_array().map(f64::to_bits)
}

/// The vertices whose exact position another used vertex has.
struct Copies {
    /// Of each used vertex, the first vertex at its position (`u32::MAX` unused).
    group: Vec<u32>,
    /// Whether a vertex shares its position.
    shared: Vec<bool>,
}

/// The copies among the `used` vertices of `mesh`.
fn copies(mesh: &TriangleMesh, used: &[bool]) -> Copies {
    let n = mesh.vertices.len();
    // Sorted by position, then index: each position's run starts at its first vertex.
    let mut keyed: Vec<([u64; 3], u32)> = (0..n)
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&i| used[i])
        .map(|i| (exact(mesh.vertices[i]), i as u32))
        .collect();
    keyed.par_sort_unstable();
    let mut group = vec![u32::MAX; n];
    let mut shared = vec![false; n];
    let mut start = 0;
    for k in 0..keyed.len() {
        if keyed[k].0 != keyed[start].0 {
            start = k;
        }
        let (i, j) = (keyed[k].1 as usize, keyed[start].1);
        group[i] = j;
        if k != start {
            shared[i] = true;
            shared[j as usize] = true;
        }
    }
    Copies { group, shared }
}

/// Moves each copy of `mesh` (in `out`) by its step towards its own faces and away
/// from the other copies' (module doc), or refuses a step over the limit.
fn move_copies_apart(
    mesh: &TriangleMesh,
    group: &[u32],
    shared: &[bool],
    out: &mut [DVec3],
) -> std::result::Result<(), String> {
    let n = mesh.vertices.len();
    let (toward, shortest) = faces_seen_from_copies(mesh, shared);
    let mut all = vec![DVec3::ZERO; n];
    for v in (0..n).filter(|&v| shared[v]) {
        all[group[v] as usize] += toward[v];
    }
    for v in (0..n).filter(|&v| shared[v]) {
        let p = mesh.vertices[v];
        // Towards its own faces, away from the other copies' faces.
        let away = (2.0 * toward[v] - all[group[v] as usize]).normalize_or_zero();
        let ulp = f32_spacing(p.abs().max_element());
        let step = (shortest[v] * SEPARATION_STEP).max(STEP_ULPS * ulp);
        if step > shortest[v] * SEPARATION_LIMIT {
            return Err(format!(
                "vertex {v} at {p} shares its position with another sheet's, and f32 (spacing {ulp:e} there) \
                 cannot move them apart by {:e} or less ({SEPARATION_LIMIT} of their shortest edge)",
                shortest[v] * SEPARATION_LIMIT
            ));
        }
        out[v] = p + step * away;
    }
    Ok(())
}

/// Where each copy's faces lie, seen from its position (angle-weighted directions to
/// its triangles' centroids, summed to unit length), and its shortest edge.
fn faces_seen_from_copies(mesh: &TriangleMesh, shared: &[bool]) -> (Vec<DVec3>, Vec<f64>) {
    let n = mesh.vertices.len();
    let mut toward = vec![DVec3::ZERO; n];
    let mut shortest = vec![f64::INFINITY; n];
    // The triangles at a copy, in order (the sums below run in triangle order).
    let at_copies: Vec<usize> = (0..mesh.triangles.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&t| mesh.triangles[t].iter().any(|&v| shared[v as usize]))
        .collect();
    for t in at_copies {
        let ids = mesh.triangles[t];
        let c = mesh.corners(t);
        for k in 0..3 {
            let v = ids[k] as usize;
            if !shared[v] {
                continue;
            }
            let (a, b) = (c[(k + 1) % 3] - c[k], c[(k + 2) % 3] - c[k]);
            let angle = a.cross(b).length().atan2(a.dot(b));
            toward[v] += angle * (a + b).normalize_or_zero();
            shortest[v] = shortest[v].min(a.length()).min(b.length());
        }
    }
    for v in (0..n).filter(|&v| shared[v]) {
        toward[v] = toward[v].normalize_or_zero();
    }
    (toward, shortest)
}

/// Every used vertex of `out` distinct in `f32`, as STL stores it (`mesh`: the
/// positions before the move, named in a refusal).
fn distinct_in_f32(mesh: &TriangleMesh, out: &[DVec3], used: &[bool]) -> std::result::Result<(), String> {
    let n = mesh.vertices.len();
    let stored = |v: DVec3| (v.as_vec3() + glam::Vec3::ZERO).to_array().map(f32::to_bits);
    let infinite = (0..n).into_par_iter().with_min_len(CHUNK).find_first(|&i| used[i] && !out[i].as_vec3().is_finite());
    let mut keyed: Vec<([u32; 3], u32)> =
        (0..n).into_par_iter().with_min_len(CHUNK).filter(|&i| used[i]).map(|i| (stored(out[i]), i as u32)).collect();
    keyed.par_sort_unstable();
    // The first vertex whose f32 point an earlier one has: the least second of a run,
    // with the run's first.
    let repeat = (1..keyed.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .filter(|&k| keyed[k].0 == keyed[k - 1].0 && (k == 1 || keyed[k - 2].0 != keyed[k - 1].0))
        .map(|k| (keyed[k].1 as usize, keyed[k - 1].1 as usize))
        .min();
    // A scan in vertex order stops at whichever comes first.
    if let Some(i) = infinite
        && repeat.is_none_or(|(r, _)| i <= r)
    {
        return Err(format!("vertex {i} at {} does not fit in f32", mesh.vertices[i]));
    }
    if let Some((i, j)) = repeat {
        let (p, q, v) = (mesh.vertices[j], mesh.vertices[i], out[i]);
        return Err(if exact(p) == exact(q) {
            format!("vertices {j} and {i} at {p} are sheets that cannot be moved apart ({} in f32)", v.as_vec3())
        } else {
            format!(
                "vertices {j} at {p} and {i} at {q} are both {} in f32; the coordinates are too large for the \
                 distances between them",
                v.as_vec3()
            )
        });
    }
    Ok(())
}

/// The distance from `x >= 0` (rounded to `f32`) to the next larger `f32`.
fn f32_spacing(x: f64) -> f64 {
    let f = x as f32;
    f64::from(f.next_up()) - f64::from(f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_of_f32() {
        assert_eq!(f32_spacing(1.0), 2f64.powi(-23));
        assert_eq!(f32_spacing(1.5), 2f64.powi(-23));
        assert_eq!(f32_spacing(1e6), 0.0625);
        assert_eq!(f32_spacing(0.0), f64::from(f32::from_bits(1)));
    }
}
