//! What `benches/bvh.rs` and `benches/embree.rs` share: one contender's build and
//! trace benchmarks in the group `bvh`, ids `{id}/build` and `{id}/{rays}_{threads}t`.

use criterion::{BenchmarkId, Criterion, Throughput};
use octsolid_harness::{Contender, RaySet};

/// Build and trace benchmarks of contender `C`.
pub fn contender<C: Contender>(
    c: &mut Criterion,
    id: &str,
    input: &C::Input,
    rays: &[RaySet],
    pools: &[rayon::ThreadPool],
) {
    let mut group = c.benchmark_group("bvh");
    group.sample_size(10);
    group.bench_function(BenchmarkId::new(id, "build"), |b| {
        b.iter(|| pools[pools.len() - 1].install(|| C::build(input)))
    });
    let structure = pools[pools.len() - 1].install(|| C::build(input));
    for set in rays {
        group.throughput(Throughput::Elements(set.rays.len() as u64));
        for pool in pools {
            let name = format!("{}_{}t", set.kind.name(), pool.current_num_threads());
            group.bench_function(BenchmarkId::new(id, name), |b| b.iter(|| pool.install(|| structure.trace(set))));
        }
    }
    group.finish();
}
