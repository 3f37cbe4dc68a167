//! Failed runs name their real cause, carry their report, and `run_with_retry`
//! recovers from what it can: over-seeding, overflow, and loop limits (by
//! lowering the iteration budget itself). On lavapipe in CI, where llvmpipe
//! caps every invocation's loops at 65,535 iterations in all.

use scheduler::{
    Atomic, CompileOptions, CompiledGraph, Executor, Graph, Procedure, ProcedureId, Resource,
    Retry, RunError, Seeds, Strategy,
};
use tests::config;
use tests::graphs::{Node, binary_tree};

/// Whether the adapter caps loops (llvmpipe): only there can a loop limit
/// happen.
fn caps_loops(gpu: &scheduler::Gpu) -> bool {
    scheduler::Quirks::of(&gpu.adapter.get_info()).caps_loops()
}

/// `Spawn` enqueues four `Spin`s per item; every `Spin` loops 70,000 times,
/// past llvmpipe's loop budget.
fn spin_graph() -> (CompiledGraph, ProcedureId<Node>, ProcedureId<Node>) {
    let mut graph = Graph::new("spin");
    graph.resource(Resource::storage::<[Atomic<u32>]>("sink"));
    let spawn = graph.procedure(Procedure::of::<Node>("Spawn").initial(true).body(
        "if (valid) {
    for (var c = 0u; c < 4u; c += 1u) { enqueue_Spin(Node(item.depth + 1u, 4u * item.id + c)); }
}",
    ));
    let spin = graph.procedure(Procedure::of::<Node>("Spin").initial(true).body(
        "var h = item.id;
for (var i = 0u; i < 70000u; i += 1u) { h = h * 1664525u + 1013904223u; }
if (valid && h == 7u) { atomicAdd(&sink[0], 1u); }",
    ));
    graph.connect_with_fan_out(&spawn, &spin, 4);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    (compiled, spawn, spin)
}

fn nodes(n: u32) -> Vec<Node> {
    (0..n).map(|id| Node { depth: 0, id }).collect()
}

#[test]
#[cfg_attr(skip_gpu_tests, ignore = "SKIP_GPU_TESTS=1")]
fn an_overflow_in_a_run_that_also_hits_the_loop_limit_reports_the_overflow() {
    let gpu = tests::gpu();
    let (compiled, spawn, _) = spin_graph();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 16)).unwrap();
    executor.create_buffer("sink", 1).unwrap();
    let result = executor.run(&Seeds::new().add(&spawn, &nodes(16)), &[]);
    let Err(RunError::QueueOverflow {
        procedure,
        also,
        report,
        ..
    }) = &result
    else {
        panic!("expected an overflow, got {result:?}");
    };
    assert_eq!(procedure, "Spin");
    assert!(report.procedure_named("Spin").unwrap().dropped > 0);
    if caps_loops(gpu) {
        assert!(
            also.iter().any(|a| a.contains("loop limit")),
            "the loop limit is named after the overflow: {also:?}"
        );
        let message = result.unwrap_err().to_string();
        assert!(
            message.starts_with("queue `Spin` overflowed") && message.contains("also:"),
            "{message}"
        );
    }
}

#[test]
#[cfg_attr(skip_gpu_tests, ignore = "SKIP_GPU_TESTS=1")]
fn a_loop_limit_carries_its_report_and_retry_lowers_the_budget() {
    let gpu = tests::gpu();
    let (compiled, _, spin) = spin_graph();
    let seeds = Seeds::new().add(&spin, &nodes(8));
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let mut executor =
            Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 1024)).unwrap();
        executor.create_buffer("sink", 1).unwrap();
        let first = executor.run_with(strategy, &seeds, &[]);
        if !caps_loops(gpu) {
            // No loop budget on this driver: the run simply ends.
            assert_eq!(first.unwrap().procedure(&spin).unwrap().executed, 8);
            continue;
        }
        let budget = executor.iteration_budget();
        let Err(RunError::LoopLimit { advice, report, .. }) = &first else {
            panic!("expected a loop limit, got {first:?}");
        };
        assert_eq!(report.procedure(&spin).unwrap().seeded, 8);
        match strategy {
            Strategy::Megakernel => assert!(
                advice.contains(&format!("half the iteration budget (now {budget})")),
                "{advice}"
            ),
            Strategy::Rounds { .. } => assert!(advice.contains("Under Rounds"), "{advice}"),
        }
        // Retry halves the budget down to 1, then says the bodies are at
        // fault; every attempt is bounded.
        let retried = executor.run_with_retry(strategy, &seeds, &[], Retry::without_reset(12));
        let Err(RunError::LoopLimit { advice, .. }) = &retried else {
            panic!("expected a loop limit, got {retried:?}");
        };
        assert!(advice.contains("shorten them"), "{advice}");
        if strategy == Strategy::Megakernel {
            assert_eq!(executor.iteration_budget(), 1);
        }
    }
}

#[test]
#[cfg_attr(skip_gpu_tests, ignore = "SKIP_GPU_TESTS=1")]
fn over_seeding_is_grown_by_retry() {
    let gpu = tests::gpu();
    let tree = binary_tree(5);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    let seeds: Vec<Node> = (0..40).map(|id| Node { depth: 5, id }).collect();
    let seeds = Seeds::new().add(&tree.ids, &seeds);
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 16)).unwrap();
    let refused = executor.run(&seeds, &[]);
    assert!(
        matches!(
            refused,
            Err(RunError::TooManySeeds {
                seeds: 40,
                capacity: 16,
                ..
            })
        ),
        "{refused:?}"
    );
    let report = executor
        .run_with_retry(Strategy::Megakernel, &seeds, &[], Retry::without_reset(2))
        .unwrap();
    assert_eq!(report.attempts, 2);
    assert_eq!(executor.capacities(), [64]);
    assert_eq!(report.procedure(&tree.ids).unwrap().executed, 40);
}
