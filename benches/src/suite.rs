//! The whole comparison: for each work level, the flat dispatch and the
//! megakernel at each workgroup count, each verified and timed.

use std::time::Duration;

use scheduler::{Capacities, ExecutorConfig, Gpu, Strategy};

use crate::BenchError;
use crate::flat::FlatKernel;
use crate::megakernel::{SpawnTree, compile_with_chunks};
use crate::timing::{TimeSource, Timings};
use crate::workload::Workload;

/// What to measure.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchConfig {
    /// `log2` of the item count.
    pub items_log2: u32,
    /// Timed runs per variant (after one verified warm-up run).
    pub runs: u32,
    /// Hash rounds per item, one table block each.
    pub works: Vec<u32>,
    /// Megakernel workgroup counts, one row each (per iteration budget).
    pub workgroups: Vec<u32>,
    /// Megakernel iteration budgets (`None`: persistent until done), one row
    /// each per workgroup count. See [`recommended_iteration_budget`].
    pub iteration_budgets: Vec<Option<u32>>,
    /// Megakernel queue capacity in items; `None`: the item count, which no
    /// run can exceed.
    pub capacity: Option<u32>,
    /// Chunks per batch the megakernel is compiled with, one row each per
    /// workgroup count and budget ([`scheduler::CompileOptions::chunks_per_batch`]).
    pub chunks: Vec<u32>,
    /// Most workgroups per round dispatch, one Rounds row each per chunk
    /// count; empty: no Rounds rows.
    pub rounds_workgroups: Vec<u32>,
}

/// Which variant a row measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case", tag = "kind")]
pub enum Variant {
    /// The flat dispatch.
    Flat,
    /// The megakernel.
    Megakernel {
        /// Persistent workgroups.
        workgroups: u32,
        /// Queue capacity in items.
        capacity: u32,
        /// Iterations after which a workgroup leaves (`None`: never).
        iteration_budget: Option<u32>,
        /// Chunks per batch of the compiled module.
        chunks: u32,
    },
    /// The Rounds strategy over the same compiled module.
    Rounds {
        /// Most workgroups per round dispatch.
        workgroups: u32,
        /// Queue capacity in items.
        capacity: u32,
        /// Chunks per batch of the compiled module.
        chunks: u32,
    },
}

impl Variant {
    /// A short label for tables and errors.
    pub fn label(&self) -> String {
        match self {
            Self::Flat => "flat".into(),
            Self::Megakernel {
                workgroups,
                capacity,
                iteration_budget,
                chunks,
            } => format!(
                "megakernel wg={workgroups} cap={capacity} budget={} chunks={chunks}",
                budget_label(*iteration_budget)
            ),
            Self::Rounds {
                workgroups,
                capacity,
                chunks,
            } => format!("rounds wg={workgroups} cap={capacity} chunks={chunks}"),
        }
    }
}

/// One measured variant.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Row {
    /// The workload.
    pub workload: Workload,
    /// The variant.
    pub variant: Variant,
    /// Timed runs.
    pub timings: Timings,
    /// Items per second at the median time.
    pub items_per_second: f64,
    /// This row's items per second over the flat row's of the same work.
    pub ratio_to_flat: f64,
    /// The megakernel queue's high-water mark (items), median run.
    pub high_water: Option<u64>,
    /// Dispatches per megakernel run.
    pub dispatches: Option<u32>,
}

/// Everything one benchmark run measured.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SuiteReport {
    /// `Gpu::describe()` of the adapter.
    pub adapter: String,
    /// The configuration.
    pub config: BenchConfig,
    /// The rows, grouped by work level, flat first.
    pub rows: Vec<Row>,
}

/// `none` or the number.
pub fn budget_label(budget: Option<u32>) -> String {
    budget.map_or("none".to_owned(), |b| b.to_string())
}

/// Iteration budget the bench passes to the executor: none, so the scheduler
/// applies its own default (on drivers that cap loops, such as llvmpipe,
/// [`scheduler::Quirks::default_iteration_budget`], since the loop limiter
/// would otherwise cut long runs short; see docs/scheduler.md, "Loop limits").
pub fn recommended_iteration_budget(_adapter: &str) -> Option<u32> {
    None
}

fn items_per_second(items: u32, time: Duration) -> f64 {
    f64::from(items) / time.as_secs_f64().max(1e-12)
}

fn label(workload: &Workload, variant: &Variant) -> String {
    format!(
        "{}, 2^{} items, work {}",
        variant.label(),
        workload.items_log2,
        workload.work
    )
}

/// Times the flat dispatch: one verified warm-up, `runs` timed runs, then a
/// second verification of the last timed run's output.
pub fn measure_flat(
    gpu: &Gpu,
    workload: Workload,
    runs: u32,
    expected: &[u32],
) -> Result<Timings, BenchError> {
    let name = label(&workload, &Variant::Flat);
    let flat = FlatKernel::new(&gpu.device, &gpu.queue, workload)?;
    flat.run_verified(expected, &name)?;
    let (times, walls): (Vec<_>, Vec<_>) = (0..runs)
        .map(|_| flat.run())
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    crate::verify::check_out(&gpu.device, &gpu.queue, flat.out(), expected, &name)?;
    Ok(Timings::new(times, &walls, flat.time_source()))
}

/// Times the megakernel or Rounds like [`measure_flat`]; also returns the
/// high-water mark and submission count of the median run.
pub fn measure_megakernel(
    gpu: &Gpu,
    compiled: &scheduler::CompiledGraph,
    workload: Workload,
    variant: Variant,
    runs: u32,
    expected: &[u32],
) -> Result<(Timings, u64, u32), BenchError> {
    let (workgroups, capacity, iteration_budget, strategy) = match variant {
        Variant::Megakernel {
            workgroups,
            capacity,
            iteration_budget,
            ..
        } => (workgroups, capacity, iteration_budget, Strategy::Megakernel),
        Variant::Rounds {
            workgroups,
            capacity,
            ..
        } => (workgroups, capacity, None, Strategy::rounds()),
        Variant::Flat => {
            return Err(BenchError::Config("not a scheduled variant".into()));
        }
    };
    let name = label(&workload, &variant);
    let config = ExecutorConfig {
        workgroups: Some(workgroups),
        capacities: Capacities::uniform(capacity),
        iteration_budget,
        ..ExecutorConfig::default()
    };
    let mut tree = SpawnTree::new(&gpu.device, &gpu.queue, compiled, workload, &config)?;
    tree.set_strategy(strategy);
    let (_, mut source) = tree.run_verified(expected, &name)?;
    let mut samples = Vec::with_capacity(runs as usize);
    for _ in 0..runs {
        let (sample, s) = tree.run()?;
        crate::megakernel::check_counters(&sample.report, workload.items(), &name)?;
        if s == TimeSource::WallClock {
            source = s;
        }
        samples.push(sample);
    }
    // The last timed run's output is verified too.
    crate::verify::check_out(&gpu.device, &gpu.queue, tree.out_buffer(), expected, &name)?;
    let walls: Vec<_> = samples.iter().map(|s| s.report.wall_time).collect();
    let timings = Timings::new(samples.iter().map(|s| s.time).collect(), &walls, source);
    let median_run = samples
        .iter()
        .min_by_key(|s| s.time.abs_diff(timings.median))
        .map(|s| &s.report);
    let high_water = median_run
        .and_then(|r| r.procedure_named(crate::megakernel::PROCEDURE))
        .map_or(0, |p| p.high_water);
    let dispatches = median_run.map_or(0, |r| r.dispatches);
    Ok((timings, high_water, dispatches))
}

/// Runs the whole comparison. `progress` receives one line per finished row.
pub fn run_suite(
    gpu: &Gpu,
    config: &BenchConfig,
    mut progress: impl FnMut(&Row),
) -> Result<SuiteReport, BenchError> {
    if config.runs == 0 {
        return Err(BenchError::Config(
            "at least one timed run is needed".into(),
        ));
    }
    let mut rows = Vec::new();
    for &work in &config.works {
        let workload = Workload::new(config.items_log2, work)?;
        let items = workload.items();
        let capacity = config.capacity.unwrap_or(items);
        let expected = workload.reference();

        let flat = measure_flat(gpu, workload, config.runs, &expected)?;
        let flat_rate = items_per_second(items, flat.median);
        let row = Row {
            workload,
            variant: Variant::Flat,
            items_per_second: flat_rate,
            ratio_to_flat: 1.0,
            timings: flat,
            high_water: None,
            dispatches: None,
        };
        progress(&row);
        rows.push(row);

        for &chunks in &config.chunks {
            let compiled = compile_with_chunks(&workload, &gpu.device, chunks)?;
            let variants = config.workgroups.iter().flat_map(|&workgroups| {
                config
                    .iteration_budgets
                    .iter()
                    .map(move |&iteration_budget| Variant::Megakernel {
                        workgroups,
                        capacity,
                        iteration_budget,
                        chunks,
                    })
            });
            let rounds = config
                .rounds_workgroups
                .iter()
                .map(|&workgroups| Variant::Rounds {
                    workgroups,
                    capacity,
                    chunks,
                });
            let variants = variants.chain(rounds);
            for variant in variants {
                let (timings, high_water, dispatches) =
                    measure_megakernel(gpu, &compiled, workload, variant, config.runs, &expected)?;
                let rate = items_per_second(items, timings.median);
                let row = Row {
                    workload,
                    variant,
                    items_per_second: rate,
                    ratio_to_flat: rate / flat_rate,
                    timings,
                    high_water: Some(high_water),
                    dispatches: Some(dispatches),
                };
                progress(&row);
                rows.push(row);
            }
        }
    }
    Ok(SuiteReport {
        adapter: gpu.describe(),
        config: config.clone(),
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use scheduler::DeviceRequest;

    /// Runs the workload at 2^12 items both ways, for both work levels, and
    /// compares both with the CPU reference (inside `run_suite`).
    #[test]
    fn both_variants_match_the_cpu_reference() {
        if std::env::var("SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
            return;
        }
        let gpu = Gpu::new(&DeviceRequest::default())
            .expect("no GPU adapter (set SKIP_GPU_TESTS=1 to skip GPU tests)");
        let config = BenchConfig {
            items_log2: 12,
            runs: 1,
            works: vec![crate::workload::FIXED_WORK, 0],
            workgroups: vec![scheduler::DEFAULT_WORKGROUPS, 3],
            iteration_budgets: vec![recommended_iteration_budget(&gpu.describe()), Some(5)],
            capacity: None,
            chunks: vec![1, 3],
            rounds_workgroups: vec![scheduler::DEFAULT_WORKGROUPS],
        };
        let report = run_suite(&gpu, &config, |_| {}).unwrap();
        // Per work level: flat, then 2 chunk counts x (2 workgroup counts x 2
        // budgets + 1 Rounds row).
        assert_eq!(report.rows.len(), 22);
        for row in &report.rows {
            assert!(row.items_per_second > 0.0, "{row:?}");
        }
    }

    /// The verification really fails on a wrong reference.
    #[test]
    fn a_wrong_reference_fails_loudly() {
        if std::env::var("SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
            return;
        }
        let gpu = Gpu::new(&DeviceRequest::default())
            .expect("no GPU adapter (set SKIP_GPU_TESTS=1 to skip GPU tests)");
        let workload = Workload::new(12, 64).unwrap();
        let mut wrong = workload.reference();
        wrong[1234] ^= 1;
        let flat = measure_flat(&gpu, workload, 1, &wrong);
        assert!(
            matches!(
                flat,
                Err(BenchError::Mismatch {
                    first: (1234, ..),
                    ..
                })
            ),
            "{flat:?}"
        );
        let compiled = crate::megakernel::compile(&workload, &gpu.device).unwrap();
        let variant = Variant::Megakernel {
            workgroups: 4,
            capacity: 4096,
            iteration_budget: None,
            chunks: 1,
        };
        let mega = measure_megakernel(&gpu, &compiled, workload, variant, 1, &wrong);
        assert!(
            matches!(
                mega,
                Err(BenchError::Mismatch {
                    first: (1234, ..),
                    ..
                })
            ),
            "{mega:?}"
        );
    }
}
