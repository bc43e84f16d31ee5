//! glTF 2.0 binary (`.glb`, Khronos glTF 2.0 specification, "GLB File Format"): the
//! boundary mesh of each solid ([`crate::mesh::try_boundary_mesh`], closed and
//! manifold) with vertex normals and one PBR material (base colour) a solid. Written
//! only. Mapping in `docs/FORMAT.md`, section ".glb".
//!
//! Layout: a 12-byte header (`glTF`, version 2, total length), a JSON chunk padded
//! with spaces and a BIN chunk padded with zeros, each 4-byte aligned. A solid is one
//! node, one mesh of one triangle primitive (`POSITION` and `NORMAL` as `f32` VEC3,
//! indices as `u32`) and one material (`baseColorFactor` = the solid's linear colour,
//! light grey without one; metallic 0, roughness 0.8). Coordinates are world
//! coordinates as they are, in `f32`; glTF's up is +Y, so a solid whose world is z-up
//! (octsolid's own convention) or x-up stands upright by its node's `rotation`: a
//! quarter turn about x (z-up: `(x, y, z) -> (x, z, -y)`) or about z (x-up:
//! `(x, y, z) -> (-y, x, z)`); a y-up solid (from an OBJ) has none.
//!
//! Normals: every face of the boundary is axis-aligned, so a vertex shared by faces of
//! different directions is written once a direction with that direction as its
//! normal: shading is exactly flat, and welding the positions gives back the closed
//! manifold mesh. Empty solids have no mesh (glTF forbids empty accessors) and are
//! left out. A solid whose coordinates `f32` cannot hold (past its range, or so far
//! out that neighbouring voxel corners round to one value) is refused, as STL refuses
//! vertices it cannot keep apart.
//!
//! Meshes given whole ([`write_meshes`]: the true surface of `export --surface smooth`)
//! are written the same way, one node a mesh, with smooth vertex normals: each vertex's
//! faces are grouped by direction (a face joins the first group whose first face's
//! normal is within [`CREASE_DEGREES`] of its own), and each group writes the vertex
//! once with its faces' area-weighted mean normal, so sharp edges stay sharp.
//!
//! Memory: every solid's boundary is counted first (exposed squares of node faces, a
//! pass that allocates nothing), and the largest mesh being built plus every square's
//! share of the file (split vertices, indices, the buffer and the file around it) is
//! checked against the budget before any mesh is built.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;
use smallvec::SmallVec;

use super::solid_set::{Solids, SolidsRef};
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryOptions, BoundarySize, TriangleMesh, boundary_mesh_of_size};
use crate::progress::NoProgress;
use crate::shape::Axis;
use crate::surface::Fans;

/// Colour of a solid without one (linear).
const DEFAULT_COLOR: DVec3 = DVec3::splat(0.6);
/// Estimated peak bytes an exposed square of the boundary takes in the file being
/// built, beyond its mesh: split vertices and their map, indices, the buffer and the
/// file around it.
const BYTES_PER_SQUARE: u64 = 200;
/// Estimated bytes of the JSON document a solid (its node, mesh, material, views and
/// accessors, several times over as it is assembled).
const BYTES_PER_SOLID: u64 = 16 << 10;
/// Beside them: the small tables a mesh is built with, whatever its size.
const FIXED_BYTES: u64 = 256 << 10;
/// Faces around a vertex whose normals differ by more than this many degrees are
/// shaded apart ([`write_meshes`]).
pub const CREASE_DEGREES: f64 = 30.0;
const GLB_MAGIC: u32 = 0x4654_6C67;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// A mesh ready for glTF: positions and normals (`f32`), indices.
pub struct FlatMesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit axis normal of each vertex.
    pub normals: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

/// `mesh` with each vertex split by the directions of its faces (module doc).
#[must_use]
pub fn flat_mesh(mesh: &TriangleMesh) -> FlatMesh {
    let mut out = FlatMesh { positions: Vec::new(), normals: Vec::new(), indices: Vec::new() };
    let mut ids: HashMap<(u32, u8), u32> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let [a, b, c] = mesh.corners(t);
        let n = (b - a).cross(c - a);
        // The face's axis: its normal's largest component (exactly one is non-zero).
        let axis = (0..3).max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs())).unwrap_or(0);
        let direction = axis as u8 * 2 + u8::from(n[axis] < 0.0);
        let mut normal = [0f32; 3];
        normal[axis] = if n[axis] < 0.0 { -1.0 } else { 1.0 };
        for &v in tri {
            let id = *ids.entry((v, direction)).or_insert_with(|| {
                let p = mesh.vertices[v as usize];
                out.positions.push([p.x as f32, p.y as f32, p.z as f32]);
                out.normals.push(normal);
                (out.positions.len() - 1) as u32
            });
            out.indices.push(id);
        }
    }
    out
}

/// `mesh` with smooth vertex normals, each vertex split where its faces turn by more
/// than [`CREASE_DEGREES`] (module doc).
#[must_use]
pub fn shaded_mesh(mesh: &TriangleMesh) -> FlatMesh {
    let normals: Vec<DVec3> = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            (b - a).cross(c - a)
        })
        .collect();
    let fans = Fans::of(mesh.vertices.len(), &mesh.triangles);
    let min_cosine = CREASE_DEGREES.to_radians().cos();
    let mut out = FlatMesh { positions: Vec::new(), normals: Vec::new(), indices: vec![0; 3 * mesh.triangles.len()] };
    for (v, &p) in mesh.vertices.iter().enumerate() {
        let fan = fans.of_vertex(v);
        // Groups: their first face's unit normal and the sum of their faces' normals;
        // each face of the fan, its group.
        let mut groups: SmallVec<[(DVec3, DVec3); 4]> = SmallVec::new();
        let group_of: SmallVec<[u32; 16]> = fan
            .iter()
            .map(|&t| {
                let n = normals[t as usize];
                let unit = n.normalize_or_zero();
                let g = match groups.iter().position(|g| g.0.dot(unit) >= min_cosine) {
                    Some(g) => {
                        groups[g].1 += n;
                        g
                    }
                    None => {
                        groups.push((unit, n));
                        groups.len() - 1
                    }
                };
                g as u32
            })
            .collect();
        let first = out.positions.len() as u32;
        for &(seed, sum) in &groups {
            let normal = sum.try_normalize().unwrap_or(seed);
            out.positions.push([p.x as f32, p.y as f32, p.z as f32]);
            out.normals.push([normal.x as f32, normal.y as f32, normal.z as f32]);
        }
        for (&t, g) in fan.iter().zip(group_of) {
            let corner = mesh.triangles[t as usize].iter().position(|&c| c as usize == v).unwrap_or(0);
            out.indices[3 * t as usize + corner] = first + g;
        }
    }
    out
}

/// A mesh written as one glTF node ([`write_meshes`]): its name, its colour (linear; light
/// grey without one) and its triangles.
#[derive(Clone, Copy, Debug)]
pub struct NamedMesh<'a> {
    /// The node's, mesh's and material's name.
    pub name: &'a str,
    /// The base colour.
    pub color: Option<DVec3>,
    /// The triangles, counter-clockwise seen from outside.
    pub mesh: &'a TriangleMesh,
}

/// Writes `meshes` to `path` as one GLB, atomically, one node a non-empty mesh with
/// smooth normals ([`shaded_mesh`]), turned from `up` to glTF's +Y as the solids are;
/// returns the bytes written.
///
/// # Errors
/// A vertex `f32` cannot hold apart from its neighbours at `voxel` (far past the
/// range), a file past 4 GiB, or writing fails.
pub fn write_meshes(path: impl AsRef<Path>, meshes: &[NamedMesh<'_>], up: Axis, voxel: f64) -> Result<u64> {
    let path = path.as_ref();
    let rotation = rotation_json(up);
    let mut document = GltfDocument::default();
    for named in meshes.iter().filter(|m| !m.mesh.triangles.is_empty()) {
        check_single_precision(Some(named.mesh.bounds()), voxel)
            .map_err(|reason| Error::invalid("glTF output", format!("{}: {reason}", path.display())))?;
        let shaded = shaded_mesh(named.mesh);
        let first_accessor = document.accessors.len();
        let v0 = document.push_buffer_views(&shaded);
        document.push_accessors(&shaded, v0);
        document.push_material_mesh_node(named.name, named.color, first_accessor, &rotation);
    }
    let bytes = glb_container(document.json(), document.bin)?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// A JSON string literal.
fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A JSON number for a finite `f32` (Rust's shortest round-trip decimal).
fn json_number(v: f32) -> String {
    if v == v.trunc() && v.abs() < 1e15 { format!("{v:.1}") } else { format!("{v}") }
}

/// Refuses a solid whose corners `f32` cannot hold: a coordinate past `f32`'s range
/// (glTF's JSON would get `inf`) or so far out that neighbouring voxel corners, `voxel`
/// apart, round to one `f32` (faces would collapse). The rule: the spacing of `f32`
/// values at the largest coordinate is at most half a voxel, so two corners a voxel
/// apart stay apart after rounding to nearest.
fn check_single_precision(bounds: Option<crate::aabb::Aabb>, voxel: f64) -> std::result::Result<(), String> {
    let Some(bounds) = bounds else { return Ok(()) };
    let far = bounds.min.abs().max(bounds.max.abs()).max_element();
    let single = far as f32;
    let spacing = f64::from(single.next_up() - single);
    if single.is_finite() && spacing <= voxel / 2.0 {
        return Ok(());
    }
    let why = if single.is_finite() {
        format!("at {far:.3e} single precision steps by {spacing:.3e}, more than half the voxel size {voxel:.3e}")
    } else {
        format!("a coordinate of {far:.3e} is past single precision's range")
    };
    Err(format!("glTF stores coordinates as f32: {why}; write .oct or .vdb instead"))
}

/// Writes `solids` to `path` as one GLB, atomically; returns the bytes written.
pub fn write(path: impl AsRef<Path>, solids: &SolidsRef<'_>, up: Axis, budget: MemoryBudget) -> Result<u64> {
    let path = path.as_ref();
    let bytes = encode_for(solids, up, budget, Some(path))?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The node rotation (a unit quaternion `[x, y, z, w]`) that turns a world whose up is
/// `up` to glTF's +Y; `None` for +Y itself.
#[must_use]
pub fn up_rotation(up: Axis) -> Option<[f64; 4]> {
    let h = std::f64::consts::FRAC_1_SQRT_2;
    match up {
        Axis::X => Some([0.0, 0.0, h, h]),
        Axis::Y => None,
        Axis::Z => Some([-h, 0.0, 0.0, h]),
    }
}

/// The whole `.glb` for `solids`, whose world's up is `up` (module doc).
pub fn encode(solids: &Solids, up: Axis, budget: MemoryBudget) -> Result<Vec<u8>> {
    encode_for(&solids.borrowed(), up, budget, None)
}

/// [`encode`], naming `output` (when given) in a refusal of coordinates `f32` cannot
/// hold.
fn encode_for(solids: &SolidsRef<'_>, up: Axis, budget: MemoryBudget, output: Option<&Path>) -> Result<Vec<u8>> {
    check_single_precision_of(solids, output)?;
    let rotation = rotation_json(up);
    let options = BoundaryOptions::default();
    let sizes = boundary_sizes_within_budget(solids, &options, budget)?;
    let mut document = GltfDocument::default();
    for (solid, size) in solids.solids.iter().zip(sizes) {
        // Step 1: the closed manifold boundary, vertices split by face direction.
        let mesh = boundary_mesh_of_size(solid.tree, &options, size, &NoProgress)?;
        if mesh.triangles.is_empty() {
            continue;
        }
        let flat = flat_mesh(&mesh);
        let first_accessor = document.accessors.len();
        let v0 = document.push_buffer_views(&flat);
        document.push_accessors(&flat, v0);
        document.push_material_mesh_node(&solid.name, solid.color, first_accessor, &rotation);
    }
    glb_container(document.json(), document.bin)
}

/// Refuses the first solid whose coordinates `f32` cannot hold, naming `output` when
/// given.
pub(crate) fn check_single_precision_of(solids: &SolidsRef<'_>, output: Option<&Path>) -> Result<()> {
    for solid in &solids.solids {
        check_single_precision(solid.tree.bounds(), solids.domain.voxel_size()).map_err(|reason| {
            let reason = match output {
                Some(path) => format!("{}: {reason}", path.display()),
                None => reason,
            };
            Error::invalid("glTF output", reason)
        })?;
    }
    Ok(())
}

/// The node's `"rotation"` member (with its leading comma) that stands a world whose up
/// is `up` upright, empty for +Y.
fn rotation_json(up: Axis) -> String {
    up_rotation(up).map_or_else(String::new, |q| format!(",\"rotation\":[{}]", q.map(|c| format!("{c}")).join(",")))
}

/// Step 0: every solid's boundary counted before anything is built; the largest mesh,
/// and every solid's vertices, indices and bytes in the file, must fit the budget.
fn boundary_sizes_within_budget(
    solids: &SolidsRef<'_>,
    options: &BoundaryOptions,
    budget: MemoryBudget,
) -> Result<Vec<BoundarySize>> {
    let sizes: Vec<BoundarySize> = solids.solids.iter().map(|s| BoundarySize::of(s.tree)).collect();
    let squares: u128 = sizes.iter().map(|s| s.squares).sum();
    let largest = sizes.iter().map(|s| s.mesh_bytes(options)).max().unwrap_or(0);
    let estimate = u64::try_from(squares * u128::from(BYTES_PER_SQUARE))
        .unwrap_or(u64::MAX)
        .saturating_add(largest)
        .saturating_add(FIXED_BYTES + BYTES_PER_SOLID * solids.solids.len() as u64);
    budget.check(format!("a .glb file of {squares} exposed squares of node faces"), estimate)?;
    Ok(sizes)
}

/// The glTF document being built: the BIN chunk's bytes and the JSON objects of each
/// top-level array, one solid at a time.
#[derive(Default)]
struct GltfDocument {
    /// The BIN chunk, unpadded.
    bin: Vec<u8>,
    /// One node a written solid.
    nodes: Vec<String>,
    /// One mesh a written solid.
    meshes: Vec<String>,
    /// One material a written solid.
    materials: Vec<String>,
    /// Three buffer views a written solid: positions, normals, indices.
    views: Vec<String>,
    /// Three accessors a written solid, one a buffer view.
    accessors: Vec<String>,
}

impl GltfDocument {
    /// Step 2: three buffer views (positions, normals, indices), all 4-byte aligned,
    /// their bytes appended to the BIN chunk; returns the first view's index.
    fn push_buffer_views(&mut self, flat: &FlatMesh) -> usize {
        let pos_bytes: Vec<u8> = flat.positions.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let nrm_bytes: Vec<u8> = flat.normals.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let idx_bytes: Vec<u8> = flat.indices.iter().flat_map(|v| v.to_le_bytes()).collect();
        let v0 = self.views.len();
        for (data, target) in [(pos_bytes, 34962), (nrm_bytes, 34962), (idx_bytes, 34963)] {
            self.views.push(format!(
                "{{\"buffer\":0,\"byteOffset\":{},\"byteLength\":{},\"target\":{target}}}",
                self.bin.len(),
                data.len()
            ));
            self.bin.extend(data);
        }
        v0
    }

    /// Step 3: the accessors of the views from `v0` on; POSITION carries its exact
    /// `f32` bounds.
    fn push_accessors(&mut self, flat: &FlatMesh, v0: usize) {
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for p in &flat.positions {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        let vec3 = |v: [f32; 3]| format!("[{},{},{}]", json_number(v[0]), json_number(v[1]), json_number(v[2]));
        let n = flat.positions.len();
        self.accessors.push(format!(
            "{{\"bufferView\":{v0},\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\",\"min\":{},\"max\":{}}}",
            vec3(lo),
            vec3(hi)
        ));
        self.accessors
            .push(format!("{{\"bufferView\":{},\"componentType\":5126,\"count\":{n},\"type\":\"VEC3\"}}", v0 + 1));
        self.accessors.push(format!(
            "{{\"bufferView\":{},\"componentType\":5125,\"count\":{},\"type\":\"SCALAR\"}}",
            v0 + 2,
            flat.indices.len()
        ));
    }

    /// Step 4: the material of colour `color`, mesh (its accessors from
    /// `first_accessor` on) and node (turned by `rotation`, from [`rotation_json`]) of
    /// the solid or mesh `name`.
    fn push_material_mesh_node(&mut self, name: &str, color: Option<DVec3>, first_accessor: usize, rotation: &str) {
        let c = color.unwrap_or(DEFAULT_COLOR).clamp(DVec3::ZERO, DVec3::ONE);
        let m = self.materials.len();
        self.materials.push(format!(
            "{{\"name\":{},\"pbrMetallicRoughness\":{{\"baseColorFactor\":[{},{},{},1.0],\"metallicFactor\":0.0,\"roughnessFactor\":0.8}}}}",
            json_string(name),
            json_number(c.x as f32),
            json_number(c.y as f32),
            json_number(c.z as f32)
        ));
        self.meshes.push(format!(
            "{{\"name\":{},\"primitives\":[{{\"attributes\":{{\"POSITION\":{},\"NORMAL\":{}}},\"indices\":{},\"material\":{m},\"mode\":4}}]}}",
            json_string(name),
            first_accessor,
            first_accessor + 1,
            first_accessor + 2
        ));
        self.nodes.push(format!("{{\"name\":{},\"mesh\":{}{rotation}}}", json_string(name), self.meshes.len() - 1));
    }

    /// Step 5: the JSON document, unpadded; a scene without nodes when no solid was
    /// written.
    fn json(&self) -> String {
        let mut json = String::from("{\"asset\":{\"version\":\"2.0\",\"generator\":\"octsolid\"},\"scene\":0,");
        if self.nodes.is_empty() {
            json.push_str("\"scenes\":[{}]}");
        } else {
            let list = |items: &[String]| items.join(",");
            let indices: Vec<String> = (0..self.nodes.len()).map(|i| i.to_string()).collect();
            let _ = write!(
                json,
                "\"scenes\":[{{\"nodes\":[{}]}}],\"nodes\":[{}],\"meshes\":[{}],\"materials\":[{}],\
                 \"buffers\":[{{\"byteLength\":{}}}],\"bufferViews\":[{}],\"accessors\":[{}]}}",
                indices.join(","),
                list(&self.nodes),
                list(&self.meshes),
                list(&self.materials),
                self.bin.len(),
                list(&self.views),
                list(&self.accessors)
            );
        }
        json
    }
}

/// The GLB container around `json` and `bin`: the header, the JSON chunk padded with
/// spaces and the BIN chunk (left out when empty) padded with zeros; refused past the
/// 4 GiB a GLB's length can count.
fn glb_container(json: String, mut bin: Vec<u8>) -> Result<Vec<u8>> {
    let mut json = json.into_bytes();
    json.resize(json.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    let total = u32::try_from(total).map_err(|_| {
        Error::invalid("glTF output", format!("{total} bytes exceed the 4 GiB a GLB can hold; lower the depth"))
    })?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend([GLB_MAGIC, 2, total].map(u32::to_le_bytes).concat());
    out.extend([json.len() as u32, CHUNK_JSON].map(u32::to_le_bytes).concat());
    out.extend(json);
    if !bin.is_empty() {
        out.extend([bin.len() as u32, CHUNK_BIN].map(u32::to_le_bytes).concat());
        out.extend(bin);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    /// Each rotation takes its world's up to glTF's +Y and is a unit quaternion.
    #[test]
    fn up_rotations_stand_solids_upright() {
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let up = axis.unit();
            let turned = up_rotation(axis).map_or(up, |[x, y, z, w]| DQuat::from_xyzw(x, y, z, w) * up);
            assert!((turned - DVec3::Y).length() < 1e-12, "{axis:?}: {turned}");
        }
    }
}
