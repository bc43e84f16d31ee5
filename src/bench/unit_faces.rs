//! TEMPORARY: the exposed voxel faces of an octree as triangles, two a unit face, until
//! the boundary mesh export (`mesh::boundary_mesh`) is merged; the benchmark then builds
//! its BVHs over that export instead and this file goes.
//!
//! A face of a full voxel is exposed when the voxel across it is empty or outside the
//! domain. Each full node tests the voxels across each of its six faces: O(sum of
//! 6 size^2 log n) over the nodes. Triangles are wound counter-clockwise seen from
//! outside (the face's axis `a` and the next two axes `b`, `c` are a right-handed
//! frame, so corners `(0,0) (1,0) (1,1) (0,1)` in `(b, c)` face `+a`).

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::TriangleMesh;
use crate::octree::LinearOctree;

/// Two triangles for every exposed unit face of `tree`, in world coordinates.
#[must_use]
pub fn unit_face_mesh(tree: &LinearOctree) -> TriangleMesh {
    let domain = *tree.domain();
    let n = domain.resolution();
    let quads: Vec<[DVec3; 4]> = tree
        .nodes()
        .collect::<Vec<_>>()
        .par_iter()
        .flat_map_iter(|node| {
            let mut out = Vec::new();
            for a in 0..3 {
                let (b, c) = ((a + 1) % 3, (a + 2) % 3);
                for high in [false, true] {
                    let plane = if high { node.min[a] + node.size } else { node.min[a] };
                    for i in 0..node.size {
                        for j in 0..node.size {
                            let mut across = [0u32; 3];
                            across[b] = node.min[b] + i;
                            across[c] = node.min[c] + j;
                            let exposed = if high {
                                plane >= n || {
                                    across[a] = plane;
                                    !tree.contains_voxel(across)
                                }
                            } else {
                                plane == 0 || {
                                    across[a] = plane - 1;
                                    !tree.contains_voxel(across)
                                }
                            };
                            if exposed {
                                let corner = |db: u32, dc: u32| {
                                    let mut p = [0u32; 3];
                                    p[a] = plane;
                                    p[b] = across[b] + db;
                                    p[c] = across[c] + dc;
                                    domain.lattice_point(p)
                                };
                                let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                                out.push(if high { q } else { [q[0], q[3], q[2], q[1]] });
                            }
                        }
                    }
                }
            }
            out
        })
        .collect();
    let vertices = quads.iter().flatten().copied().collect();
    let triangles = (0..quads.len() as u32).flat_map(|q| [[4 * q, 4 * q + 1, 4 * q + 2], [4 * q, 4 * q + 2, 4 * q + 3]]).collect();
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}
