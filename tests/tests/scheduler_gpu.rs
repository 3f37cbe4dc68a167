//! The megakernel on a real adapter (lavapipe in CI), checked against CPU
//! computations: exact counts, outputs, overflow and error reporting.

use std::time::Duration;

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Binding, CompileOptions, CompiledGraph, Executor, ExecutorConfig, Gpu, Graph, Policy,
    Procedure, ProcedureId, RunError, RunReport, Seeds, Strategy, readback::read_buffer, wgpu,
};
use tests::config;
use tests::graphs::{
    Node, binary_tree, hash_rounds, hashing_tree, ping_pong, ping_pong_counts, scratch_sum,
};

/// Both payload paths (atomics, and coherent memory when the device has it),
/// each with one chunk per batch and with a drawn number of chunks.
fn option_sets(gpu: &Gpu, rng: &mut StdRng) -> Vec<CompileOptions> {
    let mut paths = vec![CompileOptions::default()];
    if gpu
        .device
        .features()
        .contains(wgpu::Features::MEMORY_DECORATION_COHERENT)
    {
        paths.push(CompileOptions::with_features(
            wgpu::Features::MEMORY_DECORATION_COHERENT,
        ));
    }
    paths
        .into_iter()
        .flat_map(|options| {
            let chunked = CompileOptions {
                chunks_per_batch: rng.random_range(2..=5),
                ..options.clone()
            };
            [options, chunked]
        })
        .collect()
}

/// Runs `compiled` under the megakernel, the strategy these tests exercise
/// (`Strategy::Auto` picks Rounds on some adapters).
fn run(
    gpu: &Gpu,
    compiled: &CompiledGraph,
    config: ExecutorConfig,
    seeds: &Seeds,
    bindings: &[Binding<'_>],
) -> Result<RunReport, RunError> {
    Executor::new(&gpu.device, &gpu.queue, compiled, &config)?.run_with(
        Strategy::Megakernel,
        seeds,
        bindings,
    )
}

#[gpu_test]
fn binary_tree_counts_are_exact_for_any_workgroup_count() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("binary_tree_counts"));
    for options in option_sets(gpu, &mut rng) {
        let depth = rng.random_range(8..=13);
        let tree = binary_tree(depth);
        let compiled = tree.compile(&options).unwrap();
        for workgroups in [1, 2, 64] {
            let report = run(
                gpu,
                &compiled,
                config(workgroups, 1 << 15),
                &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
                &[],
            )
            .unwrap();
            let grow = report.procedure(&tree.ids).unwrap();
            let total = (1u64 << (depth + 1)) - 1;
            assert_eq!(
                grow.executed, total,
                "depth {depth}, {workgroups} workgroups, {} chunk(s)",
                options.chunks_per_batch
            );
            assert_eq!(grow.enqueued, total - 1);
            assert_eq!((grow.dropped, grow.fan_out_overflow), (0, 0));
            assert!(grow.high_water >= 1 && grow.high_water <= u64::from(grow.capacity));
        }
    }
}

/// Barriers in a body on a partially filled last batch: every thread reaches
/// the barrier, with or without an item, and scratch is per item.
#[gpu_test]
fn scratch_and_barriers_with_a_partial_last_batch() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("scratch_and_barriers"));
    for options in option_sets(gpu, &mut rng) {
        let sum = scratch_sum();
        let compiled = sum.compile(&options).unwrap();
        // 16 items per chunk: draw a count that leaves the last chunk partial.
        let count = loop {
            let n = rng.random_range(17..3000u32);
            if n % 16 != 0 {
                break n;
            }
        };
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("out"),
            size: 4 * u64::from(count),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let seeds: Vec<Node> = (0..count).map(|id| Node { depth: 0, id }).collect();
        for workgroups in [1, 3] {
            let report = run(
                gpu,
                &compiled,
                config(workgroups, 4096),
                &Seeds::new().add(&sum.ids, &seeds),
                &[Binding::buffer("out", &out)],
            )
            .unwrap();
            assert_eq!(
                report.procedure(&sum.ids).unwrap().executed,
                u64::from(count)
            );
            let bytes =
                read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(30)).unwrap();
            let values: &[u32] = bytemuck::cast_slice(&bytes);
            for (id, &value) in values.iter().enumerate() {
                assert_eq!(
                    value,
                    256 * id as u32 + 136,
                    "item {id} of {count}, {workgroups} workgroups, {} chunk(s)",
                    options.chunks_per_batch
                );
            }
        }
    }
}

#[gpu_test]
fn cycles_across_procedures_match_a_cpu_simulation_under_both_policies() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("cycles"));
    let depth = rng.random_range(6..=9);
    let seeds: Vec<Node> = (0..rng.random_range(1..40))
        .map(|_| Node {
            depth: 0,
            id: rng.random(),
        })
        .collect();
    let (pings, pongs) = ping_pong_counts(depth, &seeds);
    for policy in [Policy::Priority, Policy::RoundRobin] {
        let options = CompileOptions {
            policy,
            ..CompileOptions::default()
        };
        let graph = ping_pong(depth);
        let compiled = graph.compile(&options).unwrap();
        for workgroups in [1, 3, 32] {
            let report = run(
                gpu,
                &compiled,
                config(workgroups, 1 << 16),
                &Seeds::new().add(&graph.ids.ping, &seeds),
                &[],
            )
            .unwrap();
            assert_eq!(
                report.procedure(&graph.ids.ping).unwrap().executed,
                pings,
                "{policy:?}, {workgroups} workgroups"
            );
            assert_eq!(
                report.procedure(&graph.ids.pong).unwrap().executed,
                pongs,
                "{policy:?}, {workgroups} workgroups"
            );
        }
    }
}

#[gpu_test]
fn iteration_budget_spreads_the_run_over_dispatches() {
    let gpu = tests::gpu();
    let tree = binary_tree(10);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    let config = ExecutorConfig {
        iteration_budget: Some(2),
        ..config(2, 4096)
    };
    let report = run(
        gpu,
        &compiled,
        config,
        &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
        &[],
    )
    .unwrap();
    assert_eq!(report.procedure(&tree.ids).unwrap().executed, 2047);
    assert!(report.dispatches > 1, "{report}");
}

/// With many chunks per batch, each batch runs the bodies' loops once per
/// chunk, so the default CPU iteration budget also caps the chunks
/// (`LoopBudget::chunks`). One workgroup runs ~50 batches, 1,024 full chunks
/// of 256 items, here: capped at 64 batches alone, it would run them all in
/// one invocation, and its loops would pass llvmpipe's 65,535 iterations
/// (1,024 x 150 hash rounds). With the cap, an invocation runs 256 chunks.
#[gpu_test]
fn many_chunks_per_batch_stay_within_the_default_loop_budget() {
    let gpu = tests::gpu();
    let depth = 17;
    let items = (1u32 << (depth + 1)) - 1;
    let options = CompileOptions {
        chunks_per_batch: 16,
        ..CompileOptions::default()
    };
    let tree = hashing_tree(depth);
    let compiled = tree.compile(&options).unwrap();
    let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: 4 * (u64::from(items) + 1),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let report = run(
        gpu,
        &compiled,
        config(1, 1 << 18),
        &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
        &[Binding::buffer("out", &out)],
    )
    .unwrap();
    assert_eq!(
        report.procedure(&tree.ids).unwrap().executed,
        u64::from(items)
    );
    let bytes = read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(30)).unwrap();
    let values: &[u32] = bytemuck::cast_slice(&bytes);
    for id in 1..=items {
        assert_eq!(values[id as usize], hash_rounds(id), "item {id}");
    }
}

#[gpu_test]
fn overflow_is_a_typed_error_and_the_run_still_ends() {
    let gpu = tests::gpu();
    let tree = binary_tree(12);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    for workgroups in [1, 8] {
        match run(
            gpu,
            &compiled,
            config(workgroups, 64),
            &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
            &[],
        ) {
            Err(RunError::QueueOverflow {
                procedure,
                capacity,
                dropped,
                needed_at_least,
                needed,
                also,
                report,
            }) => {
                assert_eq!(procedure, "Grow");
                assert!(also.is_empty(), "{also:?}");
                assert_eq!(capacity, 64);
                assert!(dropped > 0);
                assert!(needed_at_least > 64);
                // The measured need: every item of the run, refused ones
                // included, fits it.
                let stats = report.procedure(&tree.ids).unwrap();
                assert_eq!(needed, stats.high_water + dropped);
                assert!(needed >= needed_at_least, "{needed} < {needed_at_least}");
                let grow = report.procedure(&tree.ids).unwrap();
                // Nothing is lost silently: what ran plus what was dropped
                // accounts for every enqueue attempt.
                assert_eq!(grow.executed, grow.seeded + grow.enqueued);
                assert!(grow.high_water <= 64);
            }
            other => panic!("expected an overflow, got {other:?}"),
        }
    }
}

#[gpu_test]
fn exceeding_the_declared_fan_out_is_reported() {
    let gpu = tests::gpu();
    let mut graph = Graph::new("greedy");
    let greedy = graph.procedure(Procedure::of::<Node>("Greedy").initial(true).body(
        "if (valid && item.depth == 0u) {
    for (var k = 0u; k < 2u; k += 1u) {
        enqueue_Greedy(Node(1u, item.id));
    }
}",
    ));
    // Declared 1 (the loop hides the bound), but each item enqueues 2.
    graph.connect_with_fan_out(&greedy, &greedy, 1);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    let seeds: Vec<Node> = (0..256).map(|id| Node { depth: 0, id }).collect();
    match run(
        gpu,
        &compiled,
        config(1, 4096),
        &Seeds::new().add(&greedy, &seeds),
        &[],
    ) {
        Err(RunError::FanOutExceeded {
            procedure,
            excess,
            report,
        }) => {
            assert_eq!(procedure, "Greedy");
            assert_eq!(excess, 256);
            assert_eq!(report.procedure(&greedy).unwrap().enqueued, 256);
        }
        other => panic!("expected a fan-out error, got {other:?}"),
    }
}

#[gpu_test]
fn seeding_and_binding_errors_are_typed() {
    let gpu = tests::gpu();
    let graph = ping_pong(3);
    let (ping, pong) = (&graph.ids.ping, &graph.ids.pong);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(1, 16)).unwrap();
    let node = [Node::default()];
    assert!(
        matches!(executor.run(&Seeds::new().add(pong, &node), &[]), Err(RunError::Seed { procedure, .. }) if procedure == "Pong")
    );
    // Handles that name no procedure of the graph, or carry items of the
    // wrong size, can only be made untyped; the run still refuses them.
    assert!(matches!(
        executor.run(
            &Seeds::new().add_untyped(&ProcedureId::named("Nope"), &node),
            &[]
        ),
        Err(RunError::Seed { .. })
    ));
    assert!(
        matches!(executor.run(&Seeds::new().add_untyped(&ping.untyped(), &[0u32; 3]), &[]), Err(RunError::Seed { reason, .. }) if reason.contains("bytes"))
    );
    assert!(matches!(
        executor.run(&Seeds::new().add(ping, &[Node::default(); 17]), &[]),
        Err(RunError::TooManySeeds {
            seeds: 17,
            capacity: 16,
            ..
        })
    ));

    let sum = scratch_sum();
    let compiled = sum.compile(&CompileOptions::default()).unwrap();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(1, 16)).unwrap();
    assert!(
        matches!(executor.run(&Seeds::new().add(&sum.ids, &node), &[]), Err(RunError::Binding(m)) if m.contains("out"))
    );
}

#[gpu_test]
fn too_large_configurations_are_refused_before_allocating() {
    let gpu = tests::gpu();
    let compiled = binary_tree(3).compile(&CompileOptions::default()).unwrap();
    let huge = config(1, 1 << 31);
    assert!(matches!(
        Executor::new(&gpu.device, &gpu.queue, &compiled, &huge),
        Err(RunError::TooLarge { .. })
    ));
    let plan = compiled.memory_plan(&huge);
    // A `Node` is 2 words; its slot is one 4-word packet.
    assert_eq!(plan.queue_bytes, (1u64 << 31) * 16);
}

#[gpu_test]
fn reports_round_trip_through_json_and_print_a_table() {
    let gpu = tests::gpu();
    let tree = binary_tree(5);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    let report = run(
        gpu,
        &compiled,
        config(2, 256),
        &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
        &[],
    )
    .unwrap();
    let back: RunReport = serde_json::from_str(&report.to_json()).unwrap();
    assert_eq!(back.procedures, report.procedures);
    let table = report.to_string();
    assert!(
        table.contains("Grow") && table.contains("high-water"),
        "{table}"
    );
}

#[gpu_test(expect_fail(
    backend = "gl",
    message = "LoopLimit",
    reason = "wgpu's GL backend on llvmpipe runs a dispatch within the submission, so no \
              host timeout can end it: the run ends when llvmpipe cuts its loops"
))]
fn a_run_past_its_timeout_returns_a_typed_error() {
    tests::gpu();
    // Its own device: the slow kernel keeps running after the timeout.
    let gpu = Gpu::new(&Default::default()).unwrap();
    let mut graph = Graph::new("slow");
    let slow = graph.procedure(Procedure::of::<Node>("Slow").initial(true).body(
        "var h = item.id;
for (var i = 0u; i < 20000u; i += 1u) {
    h = h * 1664525u + 1013904223u;
}
if (valid && h == 7u) {
    enqueue_Slow(item);
}",
    ));
    graph.connect(&slow, &slow);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    let seeds: Vec<Node> = (0..20_000).map(|id| Node { depth: 0, id }).collect();
    let config = ExecutorConfig {
        timeout: Duration::from_millis(1),
        ..config(2, 1 << 15)
    };
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
    let seeds = Seeds::new().add(&slow, &seeds);
    let result = executor.run(&seeds, &[]);
    // The error names the configured limit, and says that no report could
    // be read: the only submission never completed.
    assert!(
        matches!(&result, Err(RunError::Timeout { limit, report: None, .. }) if *limit == Duration::from_millis(1)),
        "{result:?}"
    );
    let message = result.unwrap_err().to_string();
    assert!(message.contains("No report could be read"), "{message}");
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
    // The executor stays usable: its read-back buffer was not left mapped.
    let again = executor.run(&seeds, &[]);
    assert!(matches!(again, Err(RunError::Timeout { .. })), "{again:?}");
    let _ = gpu.device.poll(wgpu::PollType::wait_indefinitely());
}

#[gpu_test]
fn a_timeout_of_any_length_is_accepted() {
    let gpu = tests::gpu();
    // `start + timeout` overflowed `Instant` for `Duration::MAX`; the longest
    // timeouts mean "no deadline", and the run ends normally.
    let tree = binary_tree(6);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    for timeout in [Duration::MAX, Duration::from_secs(u64::MAX)] {
        let config = ExecutorConfig {
            timeout,
            ..config(2, 1 << 10)
        };
        let report = run(
            gpu,
            &compiled,
            config,
            &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
            &[],
        )
        .unwrap();
        assert_eq!(report.procedure(&tree.ids).unwrap().executed, 127);
    }
}
