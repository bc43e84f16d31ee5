//! Checks of meshes shared by the surface suites: closed, oriented and 2-manifold
//! (every directed edge once and its twin once, every vertex's triangles one fan),
//! and a binary STL's triangles in a canonical order, to compare two files'
//! triangles whatever order and starting corner their writers chose.

use std::collections::HashMap;
use std::path::Path;

use octsolid::mesh::TriangleMesh;

/// Every directed edge once and its reverse once (closed, oriented, each edge in two
/// faces), and every vertex's triangles one fan (2-manifold at the vertices, not
/// several discs pinched together).
pub fn assert_closed_manifold(mesh: &TriangleMesh, what: &str) {
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &mesh.triangles {
        assert!(t[0] != t[1] && t[1] != t[2] && t[2] != t[0], "{what}: degenerate triangle {t:?}");
        for i in 0..3 {
            *edges.entry((t[i], t[(i + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &edges {
        assert_eq!(n, 1, "{what}: edge {a}-{b} runs {n} times one way");
        assert_eq!(edges.get(&(b, a)), Some(&1), "{what}: edge {a}-{b} has no twin");
    }
    let mut around: HashMap<u32, Vec<(u32, u32)>> = HashMap::new();
    for t in &mesh.triangles {
        for i in 0..3 {
            around.entry(t[i]).or_default().push((t[(i + 1) % 3], t[(i + 2) % 3]));
        }
    }
    for (v, fan) in around {
        // Each triangle at `v` leads from its edge's first far corner to its second;
        // one fan is one cycle through all of them.
        let next: HashMap<u32, u32> = fan.iter().copied().collect();
        let (start, mut at, mut steps) = (fan[0].0, fan[0].0, 0);
        loop {
            at = next[&at];
            steps += 1;
            if at == start {
                break;
            }
        }
        assert_eq!(steps, fan.len(), "{what}: vertex {v} joins several fans");
    }
}

/// A binary STL's triangles, each as its three `f32` corners' bits from the least,
/// sorted.
pub fn stl_triangles(path: &Path) -> Vec<[[u32; 3]; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * n, "{}: the head's count is the triangles'", path.display());
    let mut out: Vec<[[u32; 3]; 3]> = (0..n)
        .map(|t| {
            let corner = |k: usize| {
                let at = 84 + 50 * t + 12 + 12 * k;
                [0, 1, 2].map(|a| u32::from_le_bytes(bytes[at + 4 * a..at + 4 * a + 4].try_into().unwrap()))
            };
            let c = [corner(0), corner(1), corner(2)];
            let least = (0..3).min_by_key(|&k| c[k]).unwrap();
            [c[least], c[(least + 1) % 3], c[(least + 2) % 3]]
        })
        .collect();
    out.sort_unstable();
    out
}
