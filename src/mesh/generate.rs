//! Generated test meshes shared by tests, benches and examples: closed, outward
//! oriented, with known volumes.

use std::f64::consts::PI;

use glam::DVec3;

use super::TriangleMesh;

/// An icosphere of `radius`: the icosahedron subdivided `subdivisions` times, each new
/// vertex pushed to the sphere. `20 * 4^subdivisions` triangles.
#[must_use]
pub fn icosphere(center: DVec3, radius: f64, subdivisions: u32) -> TriangleMesh {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<DVec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, vertices: &mut Vec<DVec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                vertices.push(((vertices[a as usize] + vertices[b as usize]) * 0.5).normalize());
                (vertices.len() - 1) as u32
            })
        };
        let mut next = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let (ab, bc, ca) = (mid(a, b, &mut vertices), mid(b, c, &mut vertices), mid(c, a, &mut vertices));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    let vertices = vertices.into_iter().map(|v| center + v * radius).collect();
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}

/// A torus around z with centre-line radius `major` and tube radius `minor`,
/// `segments x sides` quads split into triangles.
#[must_use]
pub fn torus(major: f64, minor: f64, segments: u32, sides: u32) -> TriangleMesh {
    let mut vertices = Vec::with_capacity((segments * sides) as usize);
    for i in 0..segments {
        let u = 2.0 * PI * f64::from(i) / f64::from(segments);
        for j in 0..sides {
            let v = 2.0 * PI * f64::from(j) / f64::from(sides);
            let rho = major + minor * v.cos();
            vertices.push(DVec3::new(rho * u.cos(), rho * u.sin(), minor * v.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % segments) * sides + (j % sides);
    let mut triangles = Vec::with_capacity((2 * segments * sides) as usize);
    for i in 0..segments {
        for j in 0..sides {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            triangles.extend([[a, b, c], [a, c, d]]);
        }
    }
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}

/// A square frame: the box `[-1, 1]^2 x [-h/2, h/2]` with a square hole of side
/// `2 hole` through it along z. Genus 1, volume `(4 - 4 hole^2) h`.
#[must_use]
pub fn box_with_hole(hole: f64, height: f64) -> TriangleMesh {
    let square = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let z = [-height / 2.0, height / 2.0];
    // Vertex index: outer/inner (0/1) * 8 + bottom/top (0/1) * 4 + corner.
    let mut vertices = Vec::with_capacity(16);
    for scale in [1.0, hole] {
        for zz in z {
            for (x, y) in square {
                vertices.push(DVec3::new(x * scale, y * scale, zz));
            }
        }
    }
    let v = |inner: u32, top: u32, k: u32| inner * 8 + top * 4 + k % 4;
    let mut triangles = Vec::with_capacity(32);
    let mut quad = |a, b, c, d| triangles.extend([[a, b, c], [a, c, d]]);
    for k in 0..4 {
        quad(v(0, 1, k), v(0, 1, k + 1), v(1, 1, k + 1), v(1, 1, k)); // top ring
        quad(v(0, 0, k), v(1, 0, k), v(1, 0, k + 1), v(0, 0, k + 1)); // bottom ring
        quad(v(0, 0, k), v(0, 0, k + 1), v(0, 1, k + 1), v(0, 1, k)); // outer wall
        quad(v(1, 0, k + 1), v(1, 0, k), v(1, 1, k), v(1, 1, k + 1)); // inner wall
    }
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}

/// The axis-aligned box of centre `center` and edge lengths `size`: 8 corners, 12
/// triangles wound outward. Volume `size.x size.y size.z`.
#[must_use]
pub fn cuboid(center: DVec3, size: DVec3) -> TriangleMesh {
    // Corner k has bit a set when it lies on the high side of axis a.
    let vertices = (0..8)
        .map(|k| center + (DVec3::new(f64::from(k & 1), f64::from(k >> 1 & 1), f64::from(k >> 2 & 1)) - 0.5) * size)
        .collect();
    // Each face as a quad, counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
    let faces: [[u32; 4]; 6] = [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]];
    let triangles = faces.iter().flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]]).collect();
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}
