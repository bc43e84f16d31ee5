//! The build cost and bytes of the traversal octree and the 64-tree on the matrix's
//! solids (issue 41 item 3: the 64-tree built at least as fast, in no more memory):
//! `tree_build [SCENE...]` (default: every scene of `octsolid bench --report
//! --matrix-only`, at its depths 8 to 12). For each solid and depth one line a tree:
//! inner nodes, bytes as the report counts them, and the best CPU time of `REPEAT`
//! builds (default 5; the two trees built alternately, so load shifts both alike),
//! then the 64-tree's nodes a level (root first) counted from the linear octree's keys.
use octsolid::MemoryBudget;
use octsolid::octree::LinearOctree;
use octsolid::render::{Traversal, Tree64};
use octsolid_harness::matrix::MatrixOptions;
use octsolid_harness::scenes::{SceneKind, build_scene};
use std::collections::HashSet;
use std::path::Path;

/// CPU time of this thread, ns, so a loaded machine does not count.
fn cpu_ns() -> u64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `ts` is a valid timespec to write.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// The 64-tree's nodes a level, root first: the distinct ancestors of the keys at the
/// even octree levels above them (counted with the odd depth's root padded to twice
/// the domain, as `Tree64` does).
fn nodes_per_level(tree: &LinearOctree) -> Vec<usize> {
    let depth = u32::from(tree.depth());
    let levels = depth.div_ceil(2);
    let padded = 2 * levels;
    let mut seen: Vec<HashSet<u64>> = vec![HashSet::new(); levels as usize];
    for key in tree.keys() {
        let p = padded - key.k();
        if p == 0 {
            continue;
        }
        // The key sits in the node at level (p - 1) / 2 and in all above it.
        for l in 0..=(p - 1) / 2 {
            seen[l as usize].insert(key.start() >> (3 * (padded - 2 * l)));
        }
    }
    seen.iter().map(HashSet::len).collect()
}

fn main() {
    let names: Vec<String> = std::env::args().skip(1).collect();
    let repeat: usize = std::env::var("REPEAT").map_or(5, |v| v.parse().unwrap());
    let options = MatrixOptions::full();
    for kind in SceneKind::ALL {
        if !names.is_empty() && !names.iter().any(|n| n == kind.name()) {
            continue;
        }
        for depth in options.depths_of(kind) {
            let scene = build_scene(kind, depth, Path::new("models"), MemoryBudget::unlimited()).unwrap();
            let tree = &scene.tree;
            let (mut octree_ms, mut t64_ms) = (f64::INFINITY, f64::INFINITY);
            let (mut octree, mut t64) = (None, None);
            for _ in 0..repeat {
                let start = cpu_ns();
                octree = Some(Traversal::new(tree));
                octree_ms = octree_ms.min((cpu_ns() - start) as f64 * 1e-6);
                let start = cpu_ns();
                t64 = Some(Tree64::new(tree));
                t64_ms = t64_ms.min((cpu_ns() - start) as f64 * 1e-6);
            }
            let (octree, t64) = (octree.unwrap(), t64.unwrap());
            let name = kind.name();
            println!(
                "{name} {depth} octree: {} nodes, {} bytes, built in {octree_ms:.2} ms",
                octree.node_count(),
                octree.bytes()
            );
            println!(
                "{name} {depth} 64-tree: {} nodes, {} bytes ({:.3}x), built in {t64_ms:.2} ms ({:.3}x); a level: {:?}",
                t64.node_count(),
                t64.bytes(),
                t64.bytes() as f64 / octree.bytes() as f64,
                t64_ms / octree_ms,
                nodes_per_level(tree)
            );
        }
    }
}
