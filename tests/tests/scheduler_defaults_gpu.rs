//! What a default executor takes from its adapter (workgroups per strategy,
//! the iteration budget, `Strategy::Auto`), how a report counts
//! submissions, dispatches and rounds, a retry's reset through
//! `ResetContext`, and how far a retry grows a queue.

use gpu_test::gpu_test;
use scheduler::{
    Atomic, Capacities, CompileOptions, DEFAULT_ROUNDS_PER_BATCH, DEFAULT_WORKGROUPS, Executor,
    ExecutorConfig, Graph, Procedure, Quirks, Resource, Retry, Seeds, Strategy,
};
use tests::graphs::{Node, binary_tree};

fn root() -> [Node; 1] {
    [Node { depth: 0, id: 0 }]
}

/// One default executor serves both strategies with the adapter's values
/// for each, and `Strategy::Auto` runs the one the adapter's table picks.
#[gpu_test]
fn a_default_executor_takes_the_adapters_values_for_each_strategy() {
    let gpu = tests::gpu();
    let info = gpu.adapter.get_info();
    let quirks = Quirks::of(&info);
    let tree = binary_tree(8);
    let options = CompileOptions::for_adapter(&info);
    assert_eq!(options.chunks_per_batch, quirks.chunks_per_batch());
    let compiled = tree.graph.compile(&options).unwrap();
    let mut executor = Executor::new(
        &gpu.device,
        &gpu.queue,
        &compiled,
        &ExecutorConfig::default(),
    )
    .unwrap();
    assert_eq!(
        executor.workgroups(),
        quirks.megakernel_workgroups().unwrap_or(DEFAULT_WORKGROUPS)
    );
    assert_eq!(executor.round_workgroups(), DEFAULT_WORKGROUPS);
    assert_eq!(
        executor.iteration_budget(),
        quirks
            .default_iteration_budget(options.chunks_per_batch)
            .unwrap_or(u32::MAX)
    );
    let seeds = Seeds::new().add(&tree.ids, &root());

    let auto = executor.run(&seeds, &[]).unwrap();
    assert_eq!(auto.strategy, Strategy::Auto.resolve(&quirks), "{auto}");
    assert_eq!(auto.total_executed(), 511);
    eprintln!(
        "{} ({}): auto ran {}",
        info.name, quirks.persistent_threads.platform, auto.strategy
    );

    let megakernel = executor
        .run_with(Strategy::Megakernel, &seeds, &[])
        .unwrap();
    assert_eq!(megakernel.total_executed(), 511);
    assert_eq!(megakernel.workgroups, executor.workgroups());
    assert_eq!(
        megakernel.dispatches, megakernel.submissions,
        "{megakernel}"
    );
    assert_eq!(megakernel.rounds, 0);

    let rounds = executor.run_with(Strategy::rounds(), &seeds, &[]).unwrap();
    assert_eq!(rounds.total_executed(), 511);
    assert_eq!(rounds.workgroups, DEFAULT_WORKGROUPS);
    // Nine levels, one round each; every submission encodes a batch of
    // rounds (one indirect dispatch of the procedure and a prepare per
    // round), and the first starts with a prepare.
    assert_eq!(rounds.rounds, 9, "{rounds}");
    assert_eq!(rounds.submissions, 2, "{rounds}");
    assert_eq!(
        rounds.dispatches,
        1 + rounds.submissions * DEFAULT_ROUNDS_PER_BATCH * 2,
        "{rounds}"
    );
    assert!(
        rounds.to_string().contains(&format!(
            "{} submission(s), {} dispatch(es), 9 rounds",
            rounds.submissions, rounds.dispatches
        )),
        "{rounds}"
    );
}

/// Explicit settings win over the adapter's: `workgroups` for both
/// strategies, `round_workgroups` for Rounds alone.
#[gpu_test]
fn explicit_workgroups_win_over_the_adapters() {
    let gpu = tests::gpu();
    let compiled = binary_tree(4)
        .graph
        .compile(&CompileOptions::default())
        .unwrap();
    let executor = |config: ExecutorConfig| {
        Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap()
    };
    let both = executor(ExecutorConfig {
        workgroups: Some(3),
        ..ExecutorConfig::default()
    });
    assert_eq!((both.workgroups(), both.round_workgroups()), (3, 3));
    let apart = executor(ExecutorConfig {
        workgroups: Some(3),
        round_workgroups: Some(5),
        ..ExecutorConfig::default()
    });
    assert_eq!((apart.workgroups(), apart.round_workgroups()), (3, 5));
}

/// `Spawn` enqueues four `Count`s per item; each `Count` adds one to the
/// executor's own `sink`.
fn spawn_count_graph() -> (
    scheduler::CompiledGraph,
    scheduler::ProcedureId<Node>,
    scheduler::ProcedureId<Node>,
) {
    let mut graph = Graph::new("spawn_count");
    graph.resource(Resource::storage::<[Atomic<u32>]>("sink"));
    let spawn = graph.procedure(Procedure::of::<Node>("Spawn").initial(true).body(
        "if (valid) {
    for (var c = 0u; c < 4u; c += 1u) { enqueue_Count(Node(1u, 4u * item.id + c)); }
}",
    ));
    let count = graph
        .procedure(Procedure::of::<Node>("Count").body("if (valid) { atomicAdd(&sink[0], 1u); }"));
    graph.connect_with_fan_out(&spawn, &count, 4);
    (
        graph.compile(&CompileOptions::default()).unwrap(),
        spawn,
        count,
    )
}

/// A reset clears the executor's own buffer through its `ResetContext`
/// while the executor is busy retrying: the retried run counts each item
/// once.
#[gpu_test]
fn a_reset_clears_the_executors_own_buffers_through_its_context() {
    let gpu = tests::gpu();
    let (compiled, spawn, count) = spawn_count_graph();
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let config = ExecutorConfig {
            capacities: Capacities::uniform(64).with("Count", 8),
            ..ExecutorConfig::default()
        };
        let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
        executor.create_buffer("sink", 1).unwrap();
        let resets = std::cell::Cell::new(0);
        let retry = Retry::with_context(6, |context| {
            resets.set(resets.get() + 1);
            context.clear("sink").unwrap();
        });
        let seeds = Seeds::new().add(
            &spawn,
            &(0..32).map(|id| Node { depth: 0, id }).collect::<Vec<_>>(),
        );
        let report = executor
            .run_with_retry(strategy, &seeds, &[], retry)
            .unwrap();
        assert!(report.retries.overflow > 0, "{strategy}: {report}");
        assert_eq!(resets.get(), report.attempts - 1);
        assert_eq!(report.procedure(&count).unwrap().executed, 128);
        assert_eq!(executor.read::<u32>("sink").unwrap(), [128], "{strategy}");
    }
}

/// A retry grows an overflowing queue to its measured need plus a capped
/// margin: never past twice the need of the attempt it grew for, which the
/// report gives as `grown_for` (a megakernel's high-water mark varies from
/// run to run, so the run that succeeds may need less). The tree's depth is drawn afresh (seed printed).
#[gpu_test]
fn retry_grows_a_queue_within_twice_what_the_run_needs() {
    let seed = tests::seed("retry_grows_a_queue_within_twice_what_the_run_needs");
    let depth = 8 + u32::try_from(seed % 3).unwrap();
    let gpu = tests::gpu();
    let tree = binary_tree(depth);
    let compiled = tree.graph.compile(&CompileOptions::default()).unwrap();
    let seeds = Seeds::new().add(&tree.ids, &root());
    for strategy in [Strategy::rounds(), Strategy::Megakernel] {
        let config = ExecutorConfig {
            capacities: Capacities::uniform(16),
            ..ExecutorConfig::default()
        };
        let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
        let report = executor
            .run_with_retry(strategy, &seeds, &[], Retry::without_reset(8))
            .unwrap();
        let grow = report.procedure(&tree.ids).unwrap();
        eprintln!(
            "depth {depth}, {strategy}: {} attempt(s), capacity {}, grown for {}, high-water {}",
            report.attempts, grow.capacity, grow.grown_for, grow.high_water
        );
        assert_eq!(grow.executed, (1 << (depth + 1)) - 1);
        assert!(
            report.attempts > 1,
            "{strategy}: the queue overflowed first"
        );
        assert!(grow.grown_for > 16, "{strategy}: the queue was grown");
        assert!(
            u64::from(grow.capacity) <= 2 * grow.grown_for,
            "depth {depth}, {strategy}: capacity {} grown for a need of {}",
            grow.capacity,
            grow.grown_for
        );
    }
}
