//! Joins (`Graph::join`) on the GPU, through the tree sum of
//! `workloads::tree_sum`: a random tree built top-down and summed bottom-up
//! in the same run, checked node by node against the CPU.
//!
//! - `random_trees_sum_like_the_cpu`: trees of depth 1, 30 and a random
//!   depth, fan-outs drawn from 1..=16 (so joins nest up to 30 deep), under
//!   both strategies at 1 and 64 workgroups: every continuation fires
//!   exactly once, after all its children, and every node's sum equals the
//!   CPU's. `TEST_SEED=<seed>` replays a case.
//! - `a_full_join_pool_is_measured_and_grown_once`: a pool too small fails
//!   with `JoinPoolOverflow` and the exact need; a retry succeeds in two
//!   attempts.
//! - `quadrature_estimates_combine_bottom_up`: adaptive quadrature whose
//!   value and error estimates are combined bottom-up by joins, every root's
//!   equal to the CPU's.
//! - `joins_of_children_lost_to_an_overflow_are_listed`: a queue too small
//!   drops children; the overflow error lists their unfired joins.
//! - `a_lost_child_is_reported_with_its_joins`: a body that counts a child
//!   it never enqueues leaves its join and every join above it unfired,
//!   reported as `JoinsUnfinished` naming the continuation.

use std::time::Duration;

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Capacities, CompileOptions, Executor, ExecutorConfig, RunError, Strategy, TraceOptions,
};
use workloads::tree_sum::{self, TreeParams, TreeSumGraph};

fn config(workgroups: u32, join_pool: u32) -> ExecutorConfig {
    ExecutorConfig {
        workgroups: Some(workgroups),
        capacities: Capacities::default().with_join_pool(join_pool),
        timeout: Duration::from_secs(60),
        ..Default::default()
    }
}

fn executor(
    workgroups: u32,
    join_pool: u32,
    split_body: Option<&str>,
    options: CompileOptions,
) -> (Executor, TreeSumGraph) {
    tree_sum::executor(
        tests::gpu(),
        &options,
        &config(workgroups, join_pool),
        split_body,
    )
    .unwrap_or_else(|e| panic!("building the tree sum: {e}"))
}

const STRATEGIES: [Strategy; 2] = [
    Strategy::Megakernel,
    Strategy::Rounds {
        rounds_per_batch: 8,
    },
];

#[gpu_test]
fn random_trees_sum_like_the_cpu() {
    let seed = tests::seed("random_trees_sum_like_the_cpu");
    let mut rng = StdRng::seed_from_u64(seed);
    // (depth, fan-out): the extremes, then random ones.
    let shapes = [
        (1, rng.random_range(1..=tree_sum::MAX_FAN)),
        (30, tree_sum::MAX_FAN),
        (30, 1),
        (30, rng.random_range(1..=tree_sum::MAX_FAN)),
        (
            rng.random_range(2..=12),
            rng.random_range(1..=tree_sum::MAX_FAN),
        ),
    ];
    let trees: Vec<TreeParams> = shapes
        .into_iter()
        .map(|(depth, fan)| TreeParams::new(depth, fan, rng.random()))
        .collect();
    let default = tree_sum::options(tests::gpu());
    // The megakernel's one-chunk batches finish their joins after the slots'
    // release, batches of several chunks after each chunk; a traced module
    // keeps its trace between the markers and the join pool.
    let several_chunks = CompileOptions {
        chunks_per_batch: 4,
        ..default.clone()
    }
    .traced(TraceOptions { capacity: 256 });
    for (workgroups, options) in [(1, &default), (64, &default), (8, &several_chunks)] {
        let (mut executor, tree) = executor(
            workgroups,
            scheduler::DEFAULT_JOIN_POOL,
            None,
            options.clone(),
        );
        for params in &trees {
            let totals = tree_sum::cpu_reference(params);
            assert_eq!(
                totals.depth, params.depth,
                "the spine reaches the last level"
            );
            for strategy in STRATEGIES {
                let what =
                    format!("{params:?}, {strategy}, {workgroups} workgroup(s), seed {seed}");
                let checked = tree_sum::run(&mut executor, &tree, params, strategy, 4)
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                eprintln!("{what}\n{}{}", checked.summary, checked.report);
                assert!(
                    checked.mismatches.is_empty(),
                    "{what}: GPU and CPU disagree:\n{}",
                    checked.mismatches.join("\n")
                );
            }
        }
    }
}

#[gpu_test]
fn a_full_join_pool_is_measured_and_grown_once() {
    let params = TreeParams::new(12, 6, 0x1234_5678);
    let totals = tree_sum::cpu_reference(&params);
    assert!(totals.inner > 8, "a tree with joins to spare: {totals:?}");
    for strategy in STRATEGIES {
        let (mut executor, tree) = executor(4, 8, None, tree_sum::options(tests::gpu()));
        tree_sum::prepare(&mut executor, &params, totals.nodes).unwrap();
        match executor.run_with(strategy, &tree_sum::seeds(&tree, &params), &[]) {
            Err(RunError::JoinPoolOverflow {
                capacity, needed, ..
            }) => assert_eq!((capacity, needed), (8, totals.inner), "{strategy}"),
            other => panic!("{strategy}: expected a join pool overflow, got {other:?}"),
        }
        let checked = tree_sum::run(&mut executor, &tree, &params, strategy, 2)
            .unwrap_or_else(|e| panic!("{strategy}: {e}"));
        assert!(
            checked.mismatches.is_empty(),
            "{strategy}: {:?}",
            checked.mismatches
        );
        assert_eq!(checked.report.attempts, 2, "{strategy}");
        assert_eq!(checked.report.retries.join_pool, 1, "{strategy}");
        assert!(u64::from(checked.report.join_pool.capacity) >= totals.inner);
    }
}

/// `Split` as in the workload, except that the spine node at depth 2
/// counts one child more than it enqueues.
fn losing_split_body() -> String {
    tree_sum::SPLIT_BODY.replace(
        "_ = join_open_Refit(Refit(item.id, item.key, first, n));",
        "_ = join_open_Refit(Refit(item.id, item.key, first, n));
            if (depth == 2u && level == 0u) {
                sched_join_add_child();
            }",
    )
}

#[gpu_test]
fn a_lost_child_is_reported_with_its_joins() {
    let body = losing_split_body();
    assert_ne!(body, tree_sum::SPLIT_BODY, "the lost child is in the body");
    let params = TreeParams::new(6, 3, 7);
    let totals = tree_sum::cpu_reference(&params);
    for (strategy, checked) in STRATEGIES.into_iter().flat_map(|s| [(s, false), (s, true)]) {
        let strategy_name = format!("{strategy}, checked mode {checked}");
        let options = CompileOptions {
            checked,
            ..tree_sum::options(tests::gpu())
        };
        let (mut executor, tree) = executor(4, scheduler::DEFAULT_JOIN_POOL, Some(&body), options);
        tree_sum::prepare(&mut executor, &params, totals.nodes).unwrap();
        match executor.run_with(strategy, &tree_sum::seeds(&tree, &params), &[]) {
            Err(RunError::JoinsUnfinished {
                continuation,
                joins,
                report,
                ..
            }) => {
                // The depth-2 spine node's join, and the two above it.
                assert_eq!(
                    (continuation.as_str(), joins),
                    ("Refit", 3),
                    "{strategy_name}"
                );
                let stats = report.join(&tree.refit).unwrap();
                assert_eq!(
                    (stats.opened, stats.fired),
                    (totals.inner, totals.inner - 3),
                    "{strategy_name}"
                );
            }
            other => panic!("{strategy_name}: expected unfinished joins, got {other:?}"),
        }
    }
}

/// Adaptive quadrature whose value and error estimates are combined
/// bottom-up by joins: every root's estimates equal the CPU's, under both
/// strategies, at 1 and 64 workgroups.
#[gpu_test]
fn quadrature_estimates_combine_bottom_up() {
    let seed = tests::seed("quadrature_estimates_combine_bottom_up");
    let problem = workloads::quadrature::Problem::random(seed, 100, 16);
    for workgroups in [1, 64] {
        for strategy in STRATEGIES {
            let what = format!("{strategy}, {workgroups} workgroup(s), seed {seed}");
            let checked = workloads::quadrature::run_combined(
                tests::gpu(),
                &problem,
                &config(workgroups, scheduler::DEFAULT_JOIN_POOL),
                strategy,
            )
            .unwrap_or_else(|e| panic!("{what}: {e}"));
            eprintln!("{what}\n{}{}", checked.summary, checked.report);
            assert!(
                checked.mismatches.is_empty(),
                "{what}: GPU and CPU disagree:\n{}",
                checked.mismatches.join("\n")
            );
        }
    }
}

/// Children lost to an overflowed queue leave their joins unfired: the run
/// fails with the overflow, which lists the unfired joins, and a retry that
/// grows the queue sums the tree.
#[gpu_test]
fn joins_of_children_lost_to_an_overflow_are_listed() {
    let params = TreeParams::new(12, 6, 0x00c0_ffee);
    let totals = tree_sum::cpu_reference(&params);
    for strategy in STRATEGIES {
        let config = ExecutorConfig {
            capacities: Capacities::default().with("Split", 16),
            ..config(4, scheduler::DEFAULT_JOIN_POOL)
        };
        let (mut executor, tree) = tree_sum::executor(
            tests::gpu(),
            &tree_sum::options(tests::gpu()),
            &config,
            None,
        )
        .unwrap();
        tree_sum::prepare(&mut executor, &params, totals.nodes).unwrap();
        match executor.run_with(strategy, &tree_sum::seeds(&tree, &params), &[]) {
            Err(RunError::QueueOverflow {
                procedure,
                also,
                report,
                ..
            }) => {
                assert_eq!(procedure, "Split", "{strategy}");
                let stats = report.join(&tree.refit).unwrap();
                assert!(stats.outstanding > 0, "{strategy}: {stats:?}");
                let listed = format!("{} join(s) of `Refit` never fired", stats.outstanding);
                assert!(also.contains(&listed), "{strategy}: {also:?}");
            }
            other => panic!("{strategy}: expected an overflow, got {other:?}"),
        }
        let checked = tree_sum::run(&mut executor, &tree, &params, strategy, 4)
            .unwrap_or_else(|e| panic!("{strategy}: {e}"));
        assert!(
            checked.mismatches.is_empty(),
            "{strategy}: {:?}",
            checked.mismatches
        );
    }
}
