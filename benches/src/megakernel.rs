//! The spawn tree as a scheduler graph, and an executor that runs it.

use std::time::Duration;

use scheduler::{
    Binding, CompileOptions, CompiledGraph, Executor, ExecutorConfig, Graph, Policy, Procedure,
    ProcedureId, Resource, RunReport, Seeds, Strategy, wgpu,
};

use crate::gpu::out_buffer;
use crate::timing::TimeSource;
use crate::workload::{HASH_WGSL, SpawnItem, Workload};
use crate::{BenchError, verify};

/// The body of the `Spawn` procedure.
pub const SPAWN_BODY_WGSL: &str = include_str!("../../shaders/benches/spawn_tree_body.wgsl");

/// Name of the one procedure.
pub const PROCEDURE: &str = "Spawn";

/// The spawn-tree graph for `workload`: one procedure `Spawn` that enqueues
/// into itself with fan-out 2 and writes `out`.
pub fn spawn_tree_graph(workload: &Workload) -> Graph {
    let mut graph = Graph::new(format!(
        "spawn tree 2^{} items, work {}",
        workload.items_log2, workload.work
    ));
    for (name, value) in workload.constants() {
        graph.constant(name, value);
    }
    graph
        .library(HASH_WGSL)
        .resource(Resource::storage::<[u32]>("out"));
    let spawn = graph.procedure(
        Procedure::of::<SpawnItem>(PROCEDURE)
            .initial(true)
            .body(SPAWN_BODY_WGSL),
    );
    graph.connect_with_fan_out(&spawn, &spawn, 2);
    graph
}

/// Compiles [`spawn_tree_graph`] with the features the scheduler recommends
/// for `device` (coherent queue payloads where available).
pub fn compile(workload: &Workload, device: &wgpu::Device) -> Result<CompiledGraph, BenchError> {
    compile_with_policy(workload, device, Policy::Priority)
}

/// Like [`compile`], with the given queue policy.
pub fn compile_with_policy(
    workload: &Workload,
    device: &wgpu::Device,
    policy: Policy,
) -> Result<CompiledGraph, BenchError> {
    compile_with_options(workload, device, policy, 1)
}

/// Like [`compile`], with the given chunks per batch.
pub fn compile_with_chunks(
    workload: &Workload,
    device: &wgpu::Device,
    chunks: u32,
) -> Result<CompiledGraph, BenchError> {
    compile_with_options(workload, device, Policy::Priority, chunks)
}

fn compile_with_options(
    workload: &Workload,
    device: &wgpu::Device,
    policy: Policy,
    chunks_per_batch: u32,
) -> Result<CompiledGraph, BenchError> {
    let options = CompileOptions {
        policy,
        chunks_per_batch,
        ..CompileOptions::with_features(scheduler::recommended_features(device))
    };
    Ok(spawn_tree_graph(workload).compile(&options)?)
}

/// One timed megakernel run.
#[derive(Clone, Debug)]
pub struct Sample {
    /// The run's time (GPU time when available).
    pub time: Duration,
    /// The executor's report.
    pub report: RunReport,
}

/// An executor for the spawn tree with its `out` buffer.
#[derive(Debug)]
pub struct SpawnTree {
    device: wgpu::Device,
    queue: wgpu::Queue,
    workload: Workload,
    executor: Executor,
    out: wgpu::Buffer,
    seeds: Seeds,
    strategy: Strategy,
}

impl SpawnTree {
    /// Creates the pipeline and queues for `config` (not timed).
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        compiled: &CompiledGraph,
        workload: Workload,
        config: &ExecutorConfig,
    ) -> Result<Self, BenchError> {
        let executor = Executor::new(device, queue, compiled, config)?;
        let spawn: ProcedureId<SpawnItem> = compiled.procedure_id(PROCEDURE).ok_or_else(|| {
            BenchError::Config(format!("the graph has no `{PROCEDURE}` of `SpawnItem`s"))
        })?;
        Ok(Self {
            device: device.clone(),
            queue: queue.clone(),
            workload,
            executor,
            out: out_buffer(device, workload.items(), "megakernel out"),
            seeds: Seeds::new().add(&spawn, &[SpawnItem::root()]),
            strategy: Strategy::Megakernel,
        })
    }

    /// Runs later runs with `strategy` (the megakernel by default).
    pub fn set_strategy(&mut self, strategy: Strategy) {
        self.strategy = strategy;
    }

    /// The `out` buffer.
    pub fn out_buffer(&self) -> &wgpu::Buffer {
        &self.out
    }

    /// The workgroups the executor launches.
    pub fn workgroups(&self) -> u32 {
        self.executor.workgroups()
    }

    /// Runs the tree once with the current strategy. The time is the report's
    /// GPU time (timestamps around the run's passes, which exclude seeding) or its wall time.
    pub fn run(&mut self) -> Result<(Sample, TimeSource), BenchError> {
        let report = self.executor.run_with(
            self.strategy,
            &self.seeds,
            &[Binding::buffer("out", &self.out)],
        )?;
        let (time, source) = match report.gpu_time {
            Some(t) => (t, TimeSource::GpuTimestamps),
            None => (report.wall_time, TimeSource::WallClock),
        };
        Ok((Sample { time, report }, source))
    }

    /// Fills `out` with the sentinel, runs once and checks both `out` and the
    /// counters (every id executed once, `items - 1` enqueues, nothing dropped).
    pub fn run_verified(
        &mut self,
        expected: &[u32],
        variant: &str,
    ) -> Result<(Sample, TimeSource), BenchError> {
        verify::fill_sentinel(&self.queue, &self.out);
        let (sample, source) = self.run()?;
        check_counters(&sample.report, self.workload.items(), variant)?;
        verify::check_out(&self.device, &self.queue, &self.out, expected, variant)?;
        Ok((sample, source))
    }
}

/// Checks the report against the tree's shape.
pub fn check_counters(report: &RunReport, items: u32, variant: &str) -> Result<(), BenchError> {
    let fail = |detail: String| BenchError::Counters {
        variant: variant.to_owned(),
        detail,
    };
    let stats = report
        .procedure_named(PROCEDURE)
        .ok_or_else(|| fail(format!("no `{PROCEDURE}` in the report")))?;
    let items = u64::from(items);
    if stats.executed != items || stats.enqueued != items - 1 || stats.seeded != 1 {
        return Err(fail(format!(
            "seeded {} executed {} enqueued {}, expected 1, {items} and {}",
            stats.seeded,
            stats.executed,
            stats.enqueued,
            items - 1
        )));
    }
    if stats.dropped > 0 || stats.fan_out_overflow > 0 {
        return Err(fail(format!(
            "dropped {} fan-out overflow {}",
            stats.dropped, stats.fan_out_overflow
        )));
    }
    Ok(())
}
