//! Checked mode counts every item's enqueues against its connection's
//! fan-out: one item over it, in a batch that stays well within its staging
//! room, fails the run with `RunError::ItemFanOutExceeded` naming the
//! procedure, the target, the item (its ticket: a seed's index) and its
//! count. Without checked mode only the batch is checked, and the same run
//! passes.

use gpu_test::gpu_test;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use scheduler::{
    Capacities, CompileOptions, CompiledGraph, Executor, ExecutorConfig, Graph, Procedure,
    RunError, RunReport, Seeds, Strategy,
};
use tests::graphs::Node;

/// 64 seeds of `Source`; the one with id `heavy` enqueues three `Sink`s
/// (one from each of three threads when `threads` > 1), the others none,
/// under a declared fan-out of 2.
fn graph(threads: u32, heavy: u32, options: &CompileOptions) -> CompiledGraph {
    let mut graph = Graph::new("one heavy item");
    graph.constant("HEAVY", heavy);
    let body = if threads == 1 {
        "if (valid && item.id == HEAVY) {
    for (var k = 0u; k < 3u; k += 1u) {
        enqueue_Sink(Node(1u, k));
    }
}"
    } else {
        "if (valid && item.id == HEAVY) {
    for (var k = 0u; k < 1u; k += 1u) {
        if (thread < 3u) {
            enqueue_Sink(Node(1u, thread));
        }
    }
}"
    };
    let source = graph.procedure(
        Procedure::of::<Node>("Source")
            .initial(true)
            .threads_per_item(threads)
            .body(body),
    );
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect_with_fan_out(&source, &sink, 2);
    graph.compile(options).unwrap()
}

fn run(compiled: &CompiledGraph, strategy: Strategy) -> Result<RunReport, RunError> {
    let gpu = tests::gpu();
    let config = ExecutorConfig {
        capacities: Capacities::uniform(256),
        workgroups: Some(2),
        ..ExecutorConfig::default()
    };
    let source = compiled.procedure_id::<Node>("Source").unwrap();
    let seeds: Vec<Node> = (0..64).map(|id| Node { depth: 0, id }).collect();
    Executor::new(&gpu.device, &gpu.queue, compiled, &config)?.run_with(
        strategy,
        &Seeds::new().add(&source, &seeds),
        &[],
    )
}

#[gpu_test]
fn one_item_over_its_fan_out_is_named_in_checked_mode() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("one item over its fan-out"));
    let features = scheduler::recommended_features(&gpu.device);
    for (threads, chunks) in [(1, 1), (4, 1), (1, 4), (4, 4)] {
        let heavy = rng.random_range(0..64);
        let options = CompileOptions {
            workgroup_size: 64,
            chunks_per_batch: chunks,
            ..CompileOptions::with_features(features)
        };
        for strategy in [Strategy::Megakernel, Strategy::rounds()] {
            let case = format!("{threads} thread(s), {chunks} chunk(s), {strategy}, item {heavy}");
            // Unchecked, the batch stays within its room: the run passes
            // and nothing is lost.
            let report = run(&graph(threads, heavy, &options), strategy)
                .unwrap_or_else(|e| panic!("{case}: {e}"));
            assert_eq!(
                report.procedure_named("Sink").unwrap().executed,
                3,
                "{case}"
            );
            assert!(report.fan_out_violations.is_empty(), "{case}");
            // Checked, the item is named.
            match run(&graph(threads, heavy, &options.clone().checked()), strategy) {
                Err(RunError::ItemFanOutExceeded {
                    procedure,
                    target,
                    item,
                    count,
                    declared,
                    items,
                    report,
                    ..
                }) => {
                    assert_eq!(
                        (
                            procedure.as_str(),
                            target.as_str(),
                            item,
                            count,
                            declared,
                            items
                        ),
                        ("Source", "Sink", heavy, 3, 2, 1),
                        "{case}"
                    );
                    assert_eq!(report.fan_out_violations.len(), 1, "{case}");
                    assert_eq!(
                        report.procedure_named("Sink").unwrap().executed,
                        3,
                        "{case}"
                    );
                }
                other => panic!("{case}: expected an item over its fan-out, got {other:?}"),
            }
        }
    }
}
