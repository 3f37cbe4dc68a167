//! Criterion benchmark: megakernel vs. flat dispatch on the spawn tree.
//!
//! `cargo bench -p benches --bench scheduler`. Defaults to 2^16 items so that
//! it stays quick on lavapipe; set `SCHEDULER_BENCH_ITEMS_LOG2` for another
//! size. Times are GPU timestamps (wall time where the device lacks them),
//! fed to criterion with `iter_custom`. Each variant is verified against the
//! CPU reference before it is measured; a mismatch panics.
#![expect(
    missing_docs,
    reason = "criterion_group! defines an undocumented public function"
)]

use std::time::Duration;

use benches::flat::FlatKernel;
use benches::megakernel::{SpawnTree, compile};
use benches::suite::recommended_iteration_budget;
use benches::workload::{FIXED_WORK, Workload};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use scheduler::{Capacities, DeviceRequest, ExecutorConfig, Gpu};

fn items_log2() -> u32 {
    std::env::var("SCHEDULER_BENCH_ITEMS_LOG2")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(16)
}

fn spawn_tree(c: &mut Criterion) {
    let gpu = Gpu::new(&DeviceRequest::default()).expect("no GPU adapter");
    let adapter = gpu.describe();
    eprintln!("adapter: {adapter}");
    let mut group = c.benchmark_group("spawn_tree");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    for work in [FIXED_WORK, 0] {
        let workload = Workload::new(items_log2(), work).expect("bad size");
        let expected = workload.reference();
        group.throughput(Throughput::Elements(u64::from(workload.items())));

        let flat = FlatKernel::new(&gpu.device, &gpu.queue, workload).expect("flat pipeline");
        flat.run_verified(&expected, "flat")
            .unwrap_or_else(|e| panic!("{e}"));
        group.bench_function(format!("flat/work{work}"), |b| {
            b.iter_custom(|iters| {
                (0..iters)
                    .map(|_| flat.run().unwrap_or_else(|e| panic!("{e}")).0)
                    .sum()
            });
        });

        let compiled = compile(&workload, &gpu.device).expect("graph compiles");
        let config = ExecutorConfig {
            capacities: Capacities::uniform(workload.items()),
            iteration_budget: recommended_iteration_budget(&adapter),
            ..ExecutorConfig::default()
        };
        let mut tree = SpawnTree::new(&gpu.device, &gpu.queue, &compiled, workload, &config)
            .expect("megakernel executor");
        tree.run_verified(&expected, "megakernel")
            .unwrap_or_else(|e| panic!("{e}"));
        group.bench_function(format!("megakernel/work{work}"), |b| {
            b.iter_custom(|iters| {
                (0..iters)
                    .map(|_| tree.run().unwrap_or_else(|e| panic!("{e}")).0.time)
                    .sum()
            });
        });
    }
    group.finish();
}

criterion_group!(benches, spawn_tree);
criterion_main!(benches);
