//! `Executor::run_with_retry` grows overflowing queues to the need the run
//! measured, so that a run started with far too small queues succeeds within
//! four extra attempts besides those its bound on memory forces (one per
//! level of a self-feeding queue that outgrows twice its need), under both
//! strategies: on the Mandelbrot example
//! (recursive subdivision, whose queues must hold a whole level of tiles) and
//! on random graphs (cycles included). The retried run's results equal a run
//! configured right from the start.

use std::time::{Duration, Instant};

use gpu_test::gpu_test;
use scheduler::{
    Capacities, CompileOptions, Executor, ExecutorConfig, Policy, Retry, RunError, Seeds, Strategy,
};
use tests::random_graph::{GenerateOptions, RandomGraph, SplitMix64};

use workloads::mandelbrot;

/// Attempts the test accepts besides the retries the memory bound forces:
/// the first and four retries (over 40 random graphs, 160 runs, the most
/// was the first and three: a cycle of four procedures 11 deep, whose
/// children the estimate's three generations do not reach). A retry grows a queue that feeds itself to
/// at most twice the need it measured (docs/scheduler.md, "Overflow and
/// retry"), so a queue whose levels outgrow that (the Mandelbrot's tiles,
/// started from 16 slots for a need of about 900; a random graph's
/// self-feeding procedure of fan-out 4 and depth 8, started from 16 for a
/// need of about 5,000) is measured about once per level. The report counts
/// those retries (`RetryCauses::overflow_held`); any other retry is the
/// estimate falling short, and more than four of them fail the test.
const ATTEMPTS: u32 = 5;

/// The attempts a run made that the memory bound did not force.
fn unforced_attempts(report: &scheduler::RunReport) -> u32 {
    report.attempts - report.retries.overflow_held
}

/// Attempts `run_with_retry` may make, more than [`ATTEMPTS`], so that a run
/// needing more is measured (and printed) before the test fails.
const MEASURE_ATTEMPTS: u32 = 8;

/// Retries after loop limits come on top (llvmpipe cuts loops under CPU
/// contention); they are not what this test measures, so runs cut that way
/// are started again, at most this many times.
const LOOP_LIMIT_RESTARTS: u32 = 3;

/// Host-side limit of one attempt; the first includes lavapipe's compile.
const TIMEOUT: Duration = Duration::from_secs(120);

/// The capacities every test starts from.
const START_CAPACITIES: [u32; 2] = [16, 64];

fn strategies() -> [Strategy; 2] {
    [Strategy::Megakernel, Strategy::rounds()]
}

#[gpu_test]
fn mandelbrot_converges_within_four_extra_attempts() {
    let gpu = tests::gpu();
    let view = mandelbrot::View::whole_set(256, 256);
    let cpu = mandelbrot::cpu_mariani_silver(&view);
    let graph = mandelbrot::graph(&view);
    let options = CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
    let compiled = graph.graph.compile(&options).unwrap();
    let seeds = Seeds::new().add(&graph.tile, &view.roots());
    let mut measured = Vec::new();
    for capacity in START_CAPACITIES {
        for strategy in strategies() {
            let config = ExecutorConfig {
                capacities: Capacities::uniform(capacity),
                timeout: TIMEOUT,
                ..mandelbrot::config(gpu, &view, 1)
            };
            let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
            let unwritten = vec![mandelbrot::UNWRITTEN; view.pixels()];
            executor.write("counts", &unwritten).unwrap();
            let counts = executor.buffer("counts").unwrap().clone();
            let what = format!("{strategy}, starting from capacity {capacity}");
            let start = Instant::now();
            let report = retry_past_loop_limits(&what, || {
                let counts = counts.clone();
                let unwritten = unwritten.clone();
                let reset = move |_: &scheduler::wgpu::Device, queue: &scheduler::wgpu::Queue| {
                    queue.write_buffer(&counts, 0, scheduler::bytemuck::cast_slice(&unwritten));
                };
                executor.run_with_retry(strategy, &seeds, &[], Retry::new(MEASURE_ATTEMPTS, reset))
            });
            eprintln!(
                "{what}: {} attempt(s), {} held at twice the need, capacities {:?} ({:.1} s)\n{report}",
                report.attempts,
                report.retries.overflow_held,
                executor.capacities(),
                start.elapsed().as_secs_f64()
            );
            measured.push((what.clone(), report.attempts, unforced_attempts(&report)));
            let tile = report.procedure(&graph.tile).unwrap();
            let block = report.procedure(&graph.block).unwrap();
            let executed = (tile.executed, block.executed);
            // Exact, under the multiply-adds the driver fused: the tiles
            // executed depend on the counts.
            let counts = executor.read::<u32>("counts").unwrap();
            let matched = mandelbrot::match_subdivision(&view, &counts, &cpu, |cpu| {
                let expected = (cpu.tiles, cpu.blocks);
                if executed == expected {
                    Vec::new()
                } else {
                    vec![format!(
                        "(Tile, Block) executed: GPU {executed:?}, CPU {expected:?}"
                    )]
                }
            });
            if let Err(e) = matched {
                panic!("{what}: {e}");
            }
        }
    }
    eprintln!("attempts: {measured:?}");
    assert!(
        measured
            .iter()
            .all(|(_, _, unforced)| *unforced <= ATTEMPTS),
        "more than {ATTEMPTS} attempts besides those the memory bound forced: {measured:?}"
    );
}

/// Runs `run` again while it fails with a loop limit, and panics on any
/// other failure.
fn retry_past_loop_limits(
    what: &str,
    mut run: impl FnMut() -> Result<scheduler::RunReport, RunError>,
) -> scheduler::RunReport {
    let mut restarts = 0;
    loop {
        match run() {
            Ok(report) => return report,
            Err(RunError::LoopLimit { waits, .. }) if restarts < LOOP_LIMIT_RESTARTS => {
                eprintln!("{what}: llvmpipe cut {waits} loop(s); starting again");
                restarts += 1;
            }
            Err(error) => panic!("{what}: {error}"),
        }
    }
}

/// Cases per test (see [`tests::random_graph::cases`]): each is two shader
/// compiles.
fn cases() -> usize {
    tests::random_graph::cases(2)
}

#[gpu_test]
fn random_graphs_converge_within_four_extra_attempts() {
    const TEST: &str = "random_graphs_converge_within_four_extra_attempts";
    tests::gpu();
    let mut measured = Vec::new();
    for case in 0..cases() {
        let seed = tests::seed(&format!("{TEST} case {case}"));
        let graph = RandomGraph::generate(seed, &GenerateOptions::default());
        let expected = graph.simulate(u64::MAX).expect("no bound");
        let mut rng = SplitMix64::new(seed);
        let policy = rng.pick(&[Policy::Priority, Policy::RoundRobin]);
        let workgroups = rng.pick(&[1, 2, 4]);
        eprintln!(
            "{graph}  {} items in all; {policy:?}, {workgroups} workgroup(s)",
            expected.total_executed()
        );
        let compiled = graph
            .graph()
            .compile(&graph.compile_options(policy))
            .unwrap();
        let seeded = (0..graph.procedures.len())
            .map(|p| expected.seeded[p])
            .max()
            .unwrap_or(0);
        for capacity in START_CAPACITIES {
            for strategy in strategies() {
                let gpu = tests::gpu();
                let config = ExecutorConfig {
                    workgroups: Some(workgroups),
                    capacities: Capacities::uniform(capacity),
                    iteration_budget: None,
                    timeout: TIMEOUT,
                    ..ExecutorConfig::default()
                };
                let mut executor =
                    Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
                let what = format!(
                    "seed {seed}, {strategy}, starting from capacity {capacity} ({seeded} seeds at most per queue)"
                );
                let start = Instant::now();
                let report = retry_past_loop_limits(&what, || {
                    executor.run_with_retry(
                        strategy,
                        &graph.run_seeds(),
                        &[],
                        Retry::without_reset(MEASURE_ATTEMPTS),
                    )
                });
                eprintln!(
                    "  {what}: {} attempt(s), {} held at twice the need, capacities {:?} ({:.1} s)",
                    report.attempts,
                    report.retries.overflow_held,
                    executor.capacities(),
                    start.elapsed().as_secs_f64()
                );
                measured.push((report.attempts, unforced_attempts(&report)));
                for (p, spec) in graph.procedures.iter().enumerate() {
                    let stats = report.procedure_named(&spec.name).unwrap();
                    assert_eq!(
                        (stats.executed, stats.enqueued, stats.dropped),
                        (expected.executed[p], expected.enqueued[p], 0),
                        "{what}: {}\n{report}",
                        spec.name
                    );
                }
            }
        }
    }
    eprintln!("(attempts, not forced by the memory bound) per run: {measured:?}");
    assert!(
        measured.iter().all(|&(_, unforced)| unforced <= ATTEMPTS),
        "more than {ATTEMPTS} attempts besides those the memory bound forced: {measured:?}"
    );
}
