//! Failed runs name their real cause, carry their report, and `run_with_retry`
//! recovers from what it can: over-seeding, overflow, and loop limits (by
//! lowering the iteration budget itself). On lavapipe in CI, where llvmpipe
//! caps every invocation's loops at 65,535 iterations in all.

use gpu_test::gpu_test;
use scheduler::wgpu;
use scheduler::{
    Atomic, CompileOptions, CompiledGraph, Executor, Graph, Procedure, ProcedureId, Resource,
    Retry, RunError, Seeds, Strategy,
};
use tests::config;
use tests::graphs::{Node, binary_tree};

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

#[gpu_test]
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
    if gpu_test::expect(gpu).loops_capped() {
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

#[gpu_test]
fn a_loop_limit_carries_its_report_and_retry_lowers_the_budget() {
    let gpu = tests::gpu();
    let (compiled, _, spin) = spin_graph();
    let seeds = Seeds::new().add(&spin, &nodes(8));
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let mut executor =
            Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 1024)).unwrap();
        executor.create_buffer("sink", 1).unwrap();
        let first = executor.run_with(strategy, &seeds, &[]);
        if !gpu_test::expect(gpu).loops_capped() {
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
            other => panic!("an unresolved strategy ran: {other}"),
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

/// `Count` adds one to `sink[0]` per item: a user resource that a repeated
/// run counts twice unless `reset` restores it.
fn counting_graph() -> (CompiledGraph, ProcedureId<Node>) {
    let mut graph = Graph::new("count");
    graph.resource(Resource::storage::<[Atomic<u32>]>("sink"));
    let count = graph.procedure(
        Procedure::of::<Node>("Count")
            .initial(true)
            .body("if (valid) { atomicAdd(&sink[0], 1u); }"),
    );
    (graph.compile(&CompileOptions::default()).unwrap(), count)
}

/// A zeroed one-word `sink` the test binds itself, so that `reset` and the
/// loop check can reach it while the executor runs.
fn sink(gpu: &scheduler::Gpu) -> wgpu::Buffer {
    let sink = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("sink"),
        size: 4,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_SRC
            | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    gpu.queue.write_buffer(&sink, 0, &[0; 4]);
    sink
}

fn read_word(gpu: &scheduler::Gpu, buffer: &wgpu::Buffer) -> u32 {
    let bytes = scheduler::readback::read_buffer(
        &gpu.device,
        &gpu.queue,
        buffer,
        std::time::Duration::from_secs(60),
    )
    .unwrap();
    u32::from_le_bytes(bytes[..4].try_into().unwrap())
}

/// An executor of `counting_graph` with an iteration budget of 8.
fn budgeted_executor(gpu: &scheduler::Gpu, compiled: &CompiledGraph) -> Executor {
    let config = scheduler::ExecutorConfig {
        iteration_budget: Some(8),
        ..config(2, 64)
    };
    Executor::new(&gpu.device, &gpu.queue, compiled, &config).unwrap()
}

/// A body's own loops were cut (as its counter reports, here scripted: 3
/// on the first run, 1 on the second): `run_with_retry` treats that as a
/// loop limit, halves the budget, resets the user's resources and succeeds
/// on the third attempt with the results of one clean run.
#[gpu_test]
fn body_loops_reported_cut_are_retried_with_a_halved_budget() {
    let gpu = tests::gpu();
    let (compiled, count) = counting_graph();
    let mut executor = budgeted_executor(gpu, &compiled);
    let sink = sink(gpu);
    let (checks, resets) = (std::cell::Cell::new(0), std::cell::Cell::new(0));
    let reported = [3, 1];
    let retry = Retry::new(4, |_, queue| {
        resets.set(resets.get() + 1);
        queue.write_buffer(&sink, 0, &[0; 4]);
    })
    .check_loops(|_, _| {
        let run = checks.get();
        checks.set(run + 1);
        Ok(reported.get(run).copied().unwrap_or(0))
    });
    let seeds = Seeds::new().add(&count, &nodes(40));
    let report = executor
        .run_with_retry(
            Strategy::Megakernel,
            &seeds,
            &[scheduler::Binding::buffer("sink", &sink)],
            retry,
        )
        .unwrap();
    assert_eq!(report.attempts, 3);
    assert_eq!(
        report.retries,
        scheduler::RetryCauses {
            loop_limit: 2,
            ..Default::default()
        }
    );
    assert_eq!((checks.get(), resets.get()), (3, 2));
    assert_eq!(executor.iteration_budget(), 2, "8 halved twice");
    assert_eq!(read_word(gpu, &sink), 40, "reset before each retry");
    assert_eq!(report.procedure(&count).unwrap().executed, 40);
}

/// Bodies whose loops are cut in every run: once the attempts are spent the
/// error is a loop limit that names the bodies' loops, with the attempts.
#[gpu_test]
fn body_loops_cut_in_every_attempt_end_in_a_loop_limit_naming_them() {
    let gpu = tests::gpu();
    let (compiled, count) = counting_graph();
    let mut executor = budgeted_executor(gpu, &compiled);
    let sink = sink(gpu);
    let resets = std::cell::Cell::new(0);
    let retry = Retry::new(3, |_, _| resets.set(resets.get() + 1)).check_loops(|_, _| Ok(5));
    let result = executor.run_with_retry(
        Strategy::Megakernel,
        &Seeds::new().add(&count, &nodes(8)),
        &[scheduler::Binding::buffer("sink", &sink)],
        retry,
    );
    let Err(RunError::LoopLimit {
        waits,
        body_loops,
        advice,
        report,
    }) = &result
    else {
        panic!("expected a loop limit, got {result:?}");
    };
    assert_eq!((*waits, *body_loops), (0, 5));
    assert_eq!(report.attempts, 3);
    assert_eq!(report.retries.loop_limit, 2);
    assert_eq!(resets.get(), 2);
    assert_eq!(executor.iteration_budget(), 2);
    assert!(
        advice.contains("bodies' own loops ran out the driver's per-invocation loop budget"),
        "{advice}"
    );
    let message = result.unwrap_err().to_string();
    assert!(
        message.contains("the bodies' own loops (5 cut)"),
        "{message}"
    );
}

#[gpu_test]
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

/// A chain of `Step`s, one item per round, each also enqueueing four
/// `Leaf`s into a queue of one: it runs far longer than its timeout, and its
/// `Leaf` queue overflows from the first round on.
fn long_chain() -> (CompiledGraph, ProcedureId<Node>) {
    let mut graph = Graph::new("long chain");
    let step = graph.procedure(Procedure::of::<Node>("Step").initial(true).body(
        "if (valid) {
    enqueue_Step(Node(item.depth + 1u, item.id));
    for (var c = 0u; c < 4u; c += 1u) { enqueue_Leaf(Node(item.depth, c)); }
}",
    ));
    let leaf = graph.procedure(Procedure::of::<Node>("Leaf").body(""));
    graph.connect(&step, &step);
    graph.connect_with_fan_out(&step, &leaf, 4);
    (graph.compile(&CompileOptions::default()).unwrap(), step)
}

#[gpu_test]
fn a_timeout_carries_the_report_of_the_completed_submissions_and_names_the_overflow() {
    let gpu = tests::gpu();
    let (compiled, step) = long_chain();
    let config = scheduler::ExecutorConfig {
        capacities: scheduler::Capacities::uniform(16).with("Leaf", 1),
        timeout: std::time::Duration::from_secs(1),
        ..config(1, 16)
    };
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
    let seeds = Seeds::new().add(&step, &[Node { depth: 0, id: 0 }]);
    // One round per submission: the host reads the counters after each.
    let strategy = Strategy::Rounds {
        rounds_per_batch: 1,
    };
    let result = executor.run_with(strategy, &seeds, &[]);
    let Err(RunError::Timeout {
        report: Some(report),
        also,
        ..
    }) = &result
    else {
        panic!("expected a timeout with a report, got {result:?}");
    };
    assert!(report.dispatches >= 1, "{report}");
    assert!(report.procedure(&step).unwrap().executed >= 1, "{report}");
    assert!(
        report.procedure_named("Leaf").unwrap().dropped > 0,
        "{report}"
    );
    assert!(
        also.first().is_some_and(|a| a.contains("queue `Leaf`")),
        "the overflow is named first: {also:?}"
    );
    let message = result.unwrap_err().to_string();
    assert!(
        message.contains("completed submission(s); by then: queue `Leaf`"),
        "{message}"
    );
}

#[gpu_test]
fn device_limits_are_checked_before_the_run() {
    let gpu = tests::gpu();
    let limits = gpu.device.limits();
    let tree = binary_tree(3);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    // More persistent workgroups than one dispatch may launch.
    let wide = config(limits.max_compute_workgroups_per_dimension + 1, 16);
    let refused = Executor::new(&gpu.device, &gpu.queue, &compiled, &wide);
    assert!(
        matches!(
            &refused,
            Err(RunError::ExceedsDeviceLimit {
                limit_name: "max_compute_workgroups_per_dimension",
                ..
            })
        ),
        "{refused:?}"
    );

    // A binding at an offset the device cannot bind, and one larger than a
    // storage binding may be: refused by name, before any dispatch.
    let mut graph = Graph::new("bound");
    graph.resource(Resource::storage::<[u32]>("out"));
    let run = graph.procedure(
        Procedure::of::<Node>("Run")
            .initial(true)
            .body("if (valid) { out[0] = item.id; }"),
    );
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(1, 16)).unwrap();
    let seeds = Seeds::new().add(&run, &nodes(1));
    let alignment = u64::from(limits.min_storage_buffer_offset_alignment);
    let buffer = gpu
        .device
        .create_buffer(&scheduler::wgpu::BufferDescriptor {
            label: Some("out"),
            size: 2 * alignment,
            usage: scheduler::wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
    let misaligned = scheduler::Binding {
        name: "out",
        resource: scheduler::wgpu::BindingResource::Buffer(scheduler::wgpu::BufferBinding {
            buffer: &buffer,
            offset: 4,
            size: None,
        }),
    };
    let result = executor.run(&seeds, &[misaligned]);
    assert!(
        matches!(
            &result,
            Err(RunError::ExceedsDeviceLimit {
                limit_name: "min_storage_buffer_offset_alignment",
                ..
            })
        ),
        "{result:?}"
    );
    let binding_limit = limits.max_storage_buffer_binding_size;
    if binding_limit < limits.max_buffer_size && binding_limit < 1 << 30 {
        let large = gpu
            .device
            .create_buffer(&scheduler::wgpu::BufferDescriptor {
                label: Some("too large"),
                size: binding_limit + 256,
                usage: scheduler::wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            });
        let result = executor.run(&seeds, &[scheduler::Binding::buffer("out", &large)]);
        assert!(
            matches!(
                &result,
                Err(RunError::ExceedsDeviceLimit {
                    limit_name: "max_storage_buffer_binding_size",
                    ..
                })
            ),
            "{result:?}"
        );
    } else {
        eprintln!("the device binds whole buffers up to {binding_limit} bytes: no larger one made");
    }
}

/// `Long` loops a million times per item, far past llvmpipe's budget of
/// 65,535 loop iterations per invocation.
fn long_body_graph() -> (CompiledGraph, ProcedureId<Node>) {
    let mut graph = Graph::new("long_body");
    graph.resource(Resource::storage::<[Atomic<u32>]>("sink"));
    let long = graph.procedure(Procedure::of::<Node>("Long").initial(true).body(
        "var h = item.id;
for (var i = 0u; i < 1000000u; i += 1u) { h = h * 1664525u + 1013904223u; }
if (valid && h == 7u) { atomicAdd(&sink[0], 1u); }",
    ));
    (graph.compile(&CompileOptions::default()).unwrap(), long)
}

/// A body whose own loop runs out the driver's budget is named as the cause
/// on the first attempt, without `Retry::check_loops`: the check after each
/// body call finds it, and the advice does not blame the scheduler's waits.
#[gpu_test]
fn a_body_past_the_loop_budget_is_diagnosed_as_the_bodys_on_the_first_attempt() {
    let gpu = tests::gpu();
    let (compiled, long) = long_body_graph();
    let seeds = Seeds::new().add(&long, &nodes(8));
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let mut executor = Executor::new(
            &gpu.device,
            &gpu.queue,
            &compiled,
            &scheduler::ExecutorConfig::default(),
        )
        .unwrap();
        executor.create_buffer("sink", 1).unwrap();
        let result = executor.run_with_retry(strategy, &seeds, &[], Retry::without_reset(1));
        if !gpu_test::expect(gpu).loops_capped() {
            // The diagnosis concerns drivers that cap loops (llvmpipe); this
            // one runs the loop to its end, so the run must simply succeed.
            eprintln!(
                "{strategy}: no loop cap on this driver, so there is no cut to diagnose; checking that the run succeeds"
            );
            assert_eq!(result.unwrap().procedure(&long).unwrap().executed, 8);
            continue;
        }
        let Err(RunError::LoopLimit {
            body_loops,
            advice,
            report,
            ..
        }) = &result
        else {
            panic!("{strategy}: expected a loop limit, got {result:?}");
        };
        assert_eq!(report.attempts, 1);
        assert!(*body_loops > 0, "{strategy}: {result:?}");
        assert!(
            advice.contains("the scheduler's waits are not the cause")
                && advice.contains("shorten them") == !matches!(strategy, Strategy::Megakernel),
            "{strategy}: {advice}"
        );
        assert!(
            !advice.contains("fewer chunks"),
            "1 chunk per batch: {advice}"
        );
        let message = result.unwrap_err().to_string();
        assert!(
            message.starts_with("loops were cut short: the bodies' own loops ("),
            "{strategy}: {message}"
        );
        eprintln!("{strategy}: {message}");
    }
}
