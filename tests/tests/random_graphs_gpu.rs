//! Random procedure graphs (cycles included) on the GPU against a CPU
//! simulation of the same graph (`tests::random_graph`).
//!
//! - `random_graphs_give_the_cpu_counts`: each case draws a graph, compiles it
//!   under both policies and runs it under both strategies with 1 and with
//!   several workgroups, in queues large enough for everything that ever
//!   enters them. Per procedure, `executed` and `enqueued` must equal the
//!   simulation exactly.
//! - `tiny_queues_give_the_cpu_counts_or_a_full_account_of_the_overflow`: each
//!   case runs a graph with 4..64-item queues under both strategies. The run
//!   must end, and either give the simulation's counts or return
//!   `QueueOverflow` with a report that accounts for every item.
//!
//! Every case is a fresh shader compile on lavapipe, so the default is 4 cases
//! per test. Environment variables:
//!
//! - `RANDOM_GRAPH_CASES=50`: run 50 cases per test instead.
//! - `TEST_SEED=<seed>`: replay the one case a failure printed, e.g.
//!   `TEST_SEED=123 cargo test --release -p tests --test random_graphs_gpu -- tiny_queues`.
//!   With a seed given, each test runs that single case.
//!
//! Everything a case draws (graph, workgroups, rounds per batch, iteration
//! budget, capacities, policy of the tiny-queue test) comes from its seed.
//! Run with `-- --nocapture` to see each graph and the time of each run.
//!
//! A run that llvmpipe's loop limit cut short (`RunError::LoopLimit`) is
//! detected by the scheduler and run again (printed), up to 4 attempts; the
//! final run's counts are checked like any other run's.

use std::time::{Duration, Instant};

use gpu_test::gpu_test;
use scheduler::{
    Capacities, CompiledGraph, Executor, ExecutorConfig, Policy, RunError, RunReport, Strategy,
};
use tests::random_graph::{Counts, GenerateOptions, RandomGraph, SplitMix64};

/// Cases per test (see [`tests::random_graph::cases`]): each is two shader
/// compiles.
fn cases() -> usize {
    tests::random_graph::cases(4)
}

/// The seed of one case, printed (and replayable) through `tests::seed`.
fn case_seed(test: &str, case: usize) -> u64 {
    tests::seed(&format!("{test} case {case}"))
}

fn replay(test: &str, seed: u64) -> String {
    format!(
        "replay with TEST_SEED={seed} cargo test --release -p tests --test random_graphs_gpu -- {test}"
    )
}

/// Megakernel plus Rounds with a random batch size.
fn strategies(rng: &mut SplitMix64) -> [Strategy; 2] {
    [
        Strategy::Megakernel,
        Strategy::Rounds {
            rounds_per_batch: rng.pick(&[1, 3, 8]),
        },
    ]
}

/// Runs again, at most [`LOOP_ATTEMPTS`] times in all, while llvmpipe cuts a
/// loop short ([`RunError::LoopLimit`]: the scheduler detected it and refused
/// to give results; it happens under CPU contention, docs/scheduler.md "Loop
/// limits"), also in a run that overflowed too: an overflow is reported
/// first and lists the cut loops in `also`, and the workgroups a cut loop
/// ended leave items unrun, so its account is short. Every cut is printed.
/// Each attempt starts from the seeds, and the graphs have no resources to
/// reset.
fn run(
    executor: &mut Executor,
    strategy: Strategy,
    graph: &RandomGraph,
    what: &str,
) -> Result<RunReport, RunError> {
    let mut attempt = 1;
    let start = Instant::now();
    loop {
        match executor.run_with(strategy, &graph.run_seeds(), &[]) {
            Err(RunError::LoopLimit { waits, .. }) if attempt < LOOP_ATTEMPTS => {
                eprintln!(
                    "{what}: llvmpipe cut {waits} loop(s) (attempt {attempt}); running again"
                );
                attempt += 1;
            }
            Err(RunError::QueueOverflow { also, .. })
                if attempt < LOOP_ATTEMPTS && also.iter().any(|p| p.contains("loop limit")) =>
            {
                eprintln!(
                    "{what}: an overflow, and llvmpipe cut loops: {also:?} (attempt {attempt}); running again"
                );
                attempt += 1;
            }
            result => {
                let start_to_end = start.elapsed().as_secs_f64();
                eprintln!("  {what}: {start_to_end:.2} s");
                return result;
            }
        }
    }
}

/// Host-side limit of one run. The first run of an executor includes
/// lavapipe's shader compile, which takes tens of seconds on a busy machine.
const TIMEOUT: Duration = Duration::from_secs(120);

/// Separates the draws of a run's settings from those of its graph.
const RUN_SALT: u64 = 0x005e_ed0f_c0de;

/// Attempts per run when llvmpipe cuts loops short.
const LOOP_ATTEMPTS: u32 = 4;

fn executor(compiled: &CompiledGraph, config: &ExecutorConfig) -> Executor {
    let gpu = tests::gpu();
    Executor::new(&gpu.device, &gpu.queue, compiled, config).unwrap()
}

/// Random iteration budget: the CPU default (64 batches), or, for graphs of at
/// most [`SMALL_BUDGET_ITEMS`] items, a small one that makes the megakernel
/// leave and be dispatched again many times (each dispatch costs milliseconds
/// on lavapipe, so larger graphs keep the default).
fn iteration_budget(rng: &mut SplitMix64, items: u64) -> Option<u32> {
    let small = rng.chance(1, 2).then(|| rng.range(4, 32));
    small.filter(|_| items <= SMALL_BUDGET_ITEMS)
}

/// Largest graph (in items) that may get a small iteration budget.
const SMALL_BUDGET_ITEMS: u64 = 2000;

/// Per-procedure differences between a report and the simulation.
fn count_mismatches(graph: &RandomGraph, expected: &Counts, report: &RunReport) -> Vec<String> {
    let mut mismatches = Vec::new();
    for (p, spec) in graph.procedures.iter().enumerate() {
        let Some(stats) = report.procedure_named(&spec.name) else {
            mismatches.push(format!("{} is missing from the report", spec.name));
            continue;
        };
        let got = (stats.seeded, stats.executed, stats.enqueued);
        let want = (
            expected.seeded[p],
            expected.executed[p],
            expected.enqueued[p],
        );
        if got != want {
            mismatches.push(format!(
                "{}: (seeded, executed, enqueued) = {got:?}, simulation {want:?}",
                spec.name
            ));
        }
        if stats.dropped != 0 || stats.fan_out_overflow != 0 {
            mismatches.push(format!(
                "{}: dropped {}, fan-out overflow {}",
                spec.name, stats.dropped, stats.fan_out_overflow
            ));
        }
        if stats.high_water > u64::from(stats.capacity) {
            mismatches.push(format!(
                "{}: high-water {} above the capacity {}",
                spec.name, stats.high_water, stats.capacity
            ));
        }
    }
    mismatches
}

#[gpu_test]
fn random_graphs_give_the_cpu_counts() {
    const TEST: &str = "random_graphs_give_the_cpu_counts";
    tests::gpu();
    for case in 0..cases() {
        let seed = case_seed(TEST, case);
        let start = Instant::now();
        let mut failures = Vec::new();
        let graph = RandomGraph::generate(seed, &GenerateOptions::default());
        let expected = graph.simulate(u64::MAX).expect("no bound");
        eprintln!("{graph}  {} items in all", expected.total_executed());
        // Anything else drawn for the run comes from the same seed.
        let mut rng = SplitMix64::new(seed ^ RUN_SALT);
        let several = rng.pick(&[2, 4]);
        let strategies = strategies(&mut rng);
        let budget = iteration_budget(&mut rng, expected.total_executed());
        // Each queue can hold everything that ever enters it, so no run may
        // overflow, whatever the order of execution.
        let mut capacities = Capacities::uniform(1);
        for (p, spec) in graph.procedures.iter().enumerate() {
            let entering = u32::try_from(expected.entering(p)).unwrap();
            capacities = capacities.with(&spec.name, entering.max(1).next_power_of_two());
        }
        for policy in [Policy::Priority, Policy::RoundRobin] {
            let compiled = graph
                .graph()
                .compile(&graph.compile_options(policy))
                .unwrap_or_else(|e| panic!("{graph}{e}\n{}", replay(TEST, seed)));
            for workgroups in [1, several] {
                let config = ExecutorConfig {
                    workgroups: Some(workgroups),
                    capacities: capacities.clone(),
                    iteration_budget: budget,
                    timeout: TIMEOUT,
                    ..ExecutorConfig::default()
                };
                let mut executor = executor(&compiled, &config);
                for strategy in strategies {
                    let what = format!(
                        "seed {seed}, {policy:?}, {strategy}, {workgroups} workgroup(s), iteration budget {budget:?}"
                    );
                    match run(&mut executor, strategy, &graph, &what) {
                        Ok(report) => {
                            let mismatches = count_mismatches(&graph, &expected, &report);
                            if !mismatches.is_empty() {
                                failures.push(format!(
                                    "{what}:\n  {}\n{report}",
                                    mismatches.join("\n  ")
                                ));
                            }
                        }
                        Err(error) => {
                            failures.push(format!("{what}: {error}"));
                            // An executor whose run failed (a timeout leaves
                            // its read-back buffer mapped) is not reused.
                            break;
                        }
                    }
                }
            }
        }
        if !failures.is_empty() {
            panic!("{graph}\n{}\n{}", failures.join("\n\n"), replay(TEST, seed));
        }
        eprintln!(
            "case {case}: 8 runs agree ({:.1} s)",
            start.elapsed().as_secs_f64()
        );
    }
}

#[gpu_test]
fn tiny_queues_give_the_cpu_counts_or_a_full_account_of_the_overflow() {
    const TEST: &str = "tiny_queues_give_the_cpu_counts_or_a_full_account_of_the_overflow";
    tests::gpu();
    let options = GenerateOptions {
        max_items: 20_000,
        // Seeds must fit the smallest queue.
        max_seeds_per_procedure: 4,
    };
    let (mut overflows, mut fits) = (0, 0);
    for case in 0..cases() {
        let seed = case_seed(TEST, case);
        let start = Instant::now();
        let graph = RandomGraph::generate(seed, &options);
        let expected = graph.simulate(u64::MAX).expect("no bound");
        let mut rng = SplitMix64::new(seed ^ RUN_SALT);
        let policy = rng.pick(&[Policy::Priority, Policy::RoundRobin]);
        let workgroups = rng.pick(&[1, 2, 4]);
        let strategies = strategies(&mut rng);
        let budget = iteration_budget(&mut rng, expected.total_executed());
        let mut capacities = Capacities::uniform(1);
        for spec in &graph.procedures {
            capacities = capacities.with(&spec.name, rng.range(4, 64));
        }
        eprintln!(
            "{graph}  {} items in all; {policy:?}, {workgroups} workgroup(s), capacities {:?}",
            expected.total_executed(),
            capacities.per_procedure
        );
        let compiled = graph
            .graph()
            .compile(&graph.compile_options(policy))
            .unwrap_or_else(|e| panic!("{graph}{e}\n{}", replay(TEST, seed)));
        let config = ExecutorConfig {
            workgroups: Some(workgroups),
            capacities,
            iteration_budget: budget,
            timeout: TIMEOUT,
            ..ExecutorConfig::default()
        };
        let mut executor = executor(&compiled, &config);
        // Queues that can hold everything that ever enters them cannot
        // overflow.
        let all_fit = graph
            .procedures
            .iter()
            .enumerate()
            .all(|(p, _)| expected.entering(p) <= u64::from(executor.capacities()[p]));
        let mut failures = Vec::new();
        for strategy in strategies {
            let what = format!(
                "seed {seed}, {policy:?}, {strategy}, {workgroups} workgroup(s), iteration budget {budget:?}, capacities {:?}",
                executor.capacities()
            );
            match run(&mut executor, strategy, &graph, &what) {
                Ok(report) => {
                    fits += 1;
                    let mismatches = count_mismatches(&graph, &expected, &report);
                    if !mismatches.is_empty() {
                        failures.push(format!("{what}:\n  {}\n{report}", mismatches.join("\n  ")));
                    }
                }
                Err(RunError::QueueOverflow {
                    procedure,
                    capacity,
                    dropped,
                    needed_at_least,
                    report,
                    also,
                    ..
                }) => {
                    overflows += 1;
                    let mut problems = overflow_problems(&graph, &expected, &report);
                    if all_fit {
                        problems
                            .push("overflow although every queue holds all that enters it".into());
                    }
                    match report.procedure_named(&procedure) {
                        None => problems.push(format!("the overflow names unknown `{procedure}`")),
                        Some(stats) => {
                            if stats.dropped == 0 || dropped != stats.dropped {
                                problems.push(format!(
                                    "{procedure}: the error says {dropped} dropped, the report {}",
                                    stats.dropped
                                ));
                            }
                            if capacity != stats.capacity {
                                problems.push(format!(
                                    "{procedure}: the error says capacity {capacity}, the report {}",
                                    stats.capacity
                                ));
                            }
                        }
                    }
                    if needed_at_least <= u64::from(capacity) {
                        problems.push(format!(
                            "{procedure}: needed at least {needed_at_least} <= capacity {capacity}"
                        ));
                    }
                    if !problems.is_empty() {
                        failures.push(format!(
                            "{what}: overflow of {procedure} (also: {also:?}):\n  {}\n{report}",
                            problems.join("\n  ")
                        ));
                    }
                }
                Err(error) => {
                    failures.push(format!("{what}: {error}"));
                    // An executor whose run failed (a timeout leaves its
                    // read-back buffer mapped) is not reused.
                    break;
                }
            }
        }
        if !failures.is_empty() {
            panic!("{graph}\n{}\n{}", failures.join("\n\n"), replay(TEST, seed));
        }
        eprintln!("case {case}: done ({:.1} s)", start.elapsed().as_secs_f64());
    }
    eprintln!("{fits} run(s) fitted, {overflows} overflowed");
}

/// What an overflowing run's report fails to account for: every item that
/// entered a queue ran, every dropped item is one of the simulation's, and
/// every queue that dropped items says it needed more than it had.
fn overflow_problems(graph: &RandomGraph, expected: &Counts, report: &RunReport) -> Vec<String> {
    let mut problems = Vec::new();
    for (p, spec) in graph.procedures.iter().enumerate() {
        let Some(s) = report.procedure_named(&spec.name) else {
            problems.push(format!("{} is missing from the report", spec.name));
            continue;
        };
        if s.seeded != expected.seeded[p] {
            problems.push(format!(
                "{}: seeded {}, expected {}",
                spec.name, s.seeded, expected.seeded[p]
            ));
        }
        if s.executed != s.seeded + s.enqueued {
            problems.push(format!(
                "{}: executed {} != seeded {} + enqueued {}",
                spec.name, s.executed, s.seeded, s.enqueued
            ));
        }
        // Dropped items and their descendants never existed, so a run does a
        // part of the simulated work, never more.
        if s.enqueued + s.dropped > expected.enqueued[p] {
            problems.push(format!(
                "{}: enqueued {} + dropped {} > simulation's enqueued {}",
                spec.name, s.enqueued, s.dropped, expected.enqueued[p]
            ));
        }
        if s.high_water > u64::from(s.capacity) {
            problems.push(format!(
                "{}: high-water {} above the capacity {}",
                spec.name, s.high_water, s.capacity
            ));
        }
        if s.dropped > 0 && s.needed_at_least <= u64::from(s.capacity) {
            problems.push(format!(
                "{}: dropped {} but needed at least {} <= capacity {}",
                spec.name, s.dropped, s.needed_at_least, s.capacity
            ));
        }
        if s.fan_out_overflow != 0 {
            problems.push(format!(
                "{}: fan-out overflow {}",
                spec.name, s.fan_out_overflow
            ));
        }
    }
    if report.procedures.iter().all(|s| s.dropped == 0) {
        problems.push("an overflow without a dropped item".into());
    }
    problems
}
