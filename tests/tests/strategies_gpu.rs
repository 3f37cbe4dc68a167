//! The Rounds strategy against the megakernel and against CPU counts, and the
//! opt-in retry after an overflow.

use std::cell::Cell;
use std::time::Duration;

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Binding, CompileOptions, Executor, Policy, Retry, RunError, Seeds, Strategy,
    readback::read_buffer, wgpu,
};
use tests::config;
use tests::graphs::{Node, binary_tree, ping_pong, ping_pong_counts, scratch_sum};

fn strategies() -> [Strategy; 3] {
    [
        Strategy::Megakernel,
        Strategy::rounds(),
        Strategy::Rounds {
            rounds_per_batch: 1,
        },
    ]
}

#[gpu_test]
fn rounds_run_one_tree_level_per_round_with_exact_counts() {
    let gpu = tests::gpu();
    let depth = StdRng::seed_from_u64(tests::seed("rounds_tree")).random_range(6..=12);
    let tree = binary_tree(depth);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    // One workgroup forces the round kernels to stride over many batches.
    for workgroups in [1, 2, 64] {
        let mut executor = Executor::new(
            &gpu.device,
            &gpu.queue,
            &compiled,
            &config(workgroups, 1 << 14),
        )
        .unwrap();
        let report = executor
            .run_with(
                Strategy::rounds(),
                &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
                &[],
            )
            .unwrap();
        let grow = report.procedure(&tree.ids).unwrap();
        assert_eq!(grow.executed, (1 << (depth + 1)) - 1, "{report}");
        assert_eq!(report.rounds, depth + 1, "{report}");
        // Rounds hold a level and its children: the last two levels.
        assert_eq!(grow.high_water, 3 << (depth - 1), "{report}");
    }
}

#[gpu_test]
fn both_strategies_and_policies_give_the_cpu_counts_on_a_cycle() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("strategies_cycle"));
    let depth = rng.random_range(5..=8);
    let seeds: Vec<Node> = (0..rng.random_range(1..30))
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
        let mut executor =
            Executor::new(&gpu.device, &gpu.queue, &compiled, &config(3, 1 << 15)).unwrap();
        for strategy in strategies() {
            let report = executor
                .run_with(strategy, &Seeds::new().add(&graph.ids.ping, &seeds), &[])
                .unwrap();
            let ping = report.procedure(&graph.ids.ping).unwrap();
            let pong = report.procedure(&graph.ids.pong).unwrap();
            assert_eq!(
                (ping.executed, pong.executed),
                (pings, pongs),
                "{policy:?} {strategy}"
            );
            assert_eq!(ping.enqueued + ping.seeded, pings, "{policy:?} {strategy}");
            assert_eq!(pong.enqueued, pongs, "{policy:?} {strategy}");
        }
    }
}

#[gpu_test]
fn rounds_keep_barriers_and_outputs_of_the_megakernel() {
    let gpu = tests::gpu();
    let count = StdRng::seed_from_u64(tests::seed("rounds_scratch")).random_range(65..3000u32) | 1;
    let sum = scratch_sum();
    let compiled = sum.compile(&CompileOptions::default()).unwrap();
    let seeds: Vec<Node> = (0..count).map(|id| Node { depth: 0, id }).collect();
    let mut outputs = Vec::new();
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("out"),
            size: 4 * u64::from(count),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut executor =
            Executor::new(&gpu.device, &gpu.queue, &compiled, &config(2, 4096)).unwrap();
        let report = executor
            .run_with(
                strategy,
                &Seeds::new().add(&sum.ids, &seeds),
                &[Binding::buffer("out", &out)],
            )
            .unwrap();
        assert_eq!(
            report.procedure(&sum.ids).unwrap().executed,
            u64::from(count)
        );
        outputs.push(read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(30)).unwrap());
    }
    let values: &[u32] = bytemuck::cast_slice(&outputs[1]);
    for (id, &value) in values.iter().enumerate() {
        assert_eq!(value, 256 * id as u32 + 136, "item {id} of {count}");
    }
    assert_eq!(outputs[0], outputs[1]);
}

#[gpu_test]
fn rounds_overflow_is_typed_and_loses_nothing_silently() {
    let gpu = tests::gpu();
    let tree = binary_tree(10);
    let compiled = tree.compile(&CompileOptions::default()).unwrap();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config(4, 64)).unwrap();
    match executor.run_with(
        Strategy::rounds(),
        &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
        &[],
    ) {
        Err(RunError::QueueOverflow {
            procedure,
            capacity,
            needed_at_least,
            report,
            ..
        }) => {
            assert_eq!((procedure.as_str(), capacity), ("Grow", 64));
            // Levels 5 and 6 (32 + 64 items) are the first that do not fit.
            assert!(needed_at_least > 64, "{needed_at_least}");
            let grow = report.procedure(&tree.ids).unwrap();
            assert_eq!(grow.executed, grow.seeded + grow.enqueued);
            assert!(grow.high_water <= 64);
        }
        other => panic!("expected an overflow, got {other:?}"),
    }
}

#[gpu_test]
fn retry_grows_the_queues_and_matches_a_large_enough_run() {
    let gpu = tests::gpu();
    let graph = binary_tree(9);
    let tree = graph.compile(&CompileOptions::default()).unwrap();
    // Also the seeds of `counted_tree`, whose `Grow` takes `Node`s as well.
    let root = Seeds::new().add(&graph.ids, &[Node { depth: 0, id: 1 }]);
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        // Counts: a tree that overflows a 16-item queue.
        let mut small = Executor::new(&gpu.device, &gpu.queue, &tree, &config(2, 16)).unwrap();
        let retried = small
            .run_with_retry(strategy, &root, &[], Retry::without_reset(8))
            .unwrap();
        let mut large = Executor::new(&gpu.device, &gpu.queue, &tree, &config(2, 4096)).unwrap();
        let reference = large.run_with(strategy, &root, &[]).unwrap();
        assert!(retried.attempts > 1, "{retried}");
        assert_eq!(
            retried.procedure(&graph.ids).unwrap().executed,
            reference.procedure(&graph.ids).unwrap().executed
        );
        assert!(small.capacities()[0] > 16);
        // Too few attempts: the last overflow comes back.
        let mut small = Executor::new(&gpu.device, &gpu.queue, &tree, &config(2, 16)).unwrap();
        assert!(matches!(
            small.run_with_retry(strategy, &root, &[], Retry::without_reset(1)),
            Err(RunError::QueueOverflow { .. })
        ));

        // The user's reset runs before every retry, so the output equals
        // that of a run that fitted from the start; without it the first
        // attempt's partial counts would be added in.
        let depth = 9;
        let counted = counted_tree(depth)
            .compile(&CompileOptions::default())
            .unwrap();
        let levels = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("levels"),
            size: 4 * u64::from(depth + 1),
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let zeros = vec![0u8; 4 * (depth as usize + 1)];
        gpu.queue.write_buffer(&levels, 0, &zeros);
        let resets = Cell::new(0);
        let mut executor =
            Executor::new(&gpu.device, &gpu.queue, &counted, &config(2, 16)).unwrap();
        let report = executor
            .run_with_retry(
                strategy,
                &root,
                &[Binding::buffer("levels", &levels)],
                Retry::new(8, |_, queue| {
                    resets.set(resets.get() + 1);
                    queue.write_buffer(&levels, 0, &zeros);
                }),
            )
            .unwrap();
        assert!(report.attempts > 1, "{report}");
        assert_eq!(resets.get(), report.attempts - 1);
        let bytes = read_buffer(&gpu.device, &gpu.queue, &levels, Duration::from_secs(30)).unwrap();
        let per_level: &[u32] = bytemuck::cast_slice(&bytes);
        let expected: Vec<u32> = (0..=depth).map(|d| 1 << d).collect();
        assert_eq!(per_level, expected, "{strategy}");
    }
}

/// A binary tree whose nodes count themselves per level in `levels`.
fn counted_tree(depth: u32) -> scheduler::Graph {
    let mut graph = scheduler::Graph::new("counted tree");
    graph.constant("DEPTH", depth);
    graph.resource(scheduler::Resource::storage::<[scheduler::Atomic<u32>]>(
        "levels",
    ));
    let grow = graph.procedure(scheduler::Procedure::of::<Node>("Grow").initial(true).body(
        "if (valid) {
    atomicAdd(&levels[item.depth], 1u);
}
if (valid && item.depth < DEPTH) {
    enqueue_Grow(Node(item.depth + 1u, item.id * 2u));
    enqueue_Grow(Node(item.depth + 1u, item.id * 2u + 1u));
}",
    ));
    graph.connect_with_fan_out(&grow, &grow, 2);
    graph
}
