//! The Rounds strategy's round kernels: their batch functions leave out the
//! megakernel's queue fences, a workgroup that runs several batches of a
//! round keeps every child it staged, and a procedure that shares nothing
//! between threads runs without any barrier.

use std::time::Duration;

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Binding, CompileOptions, Executor, Graph, Procedure, Resource, Seeds, Strategy,
    readback::read_buffer, wgpu,
};
use tests::config;
use tests::graphs::{Node, binary_tree, hash_rounds, hashing_tree, ping_pong, scratch_sum};

/// The text of the generated function `name`, up to its closing brace.
fn function<'a>(wgsl: &'a str, name: &str) -> &'a str {
    let start = wgsl
        .find(&format!("fn {name}("))
        .unwrap_or_else(|| panic!("no `{name}` in the module"));
    let len = wgsl[start..]
        .find("\n}\n")
        .unwrap_or_else(|| panic!("`{name}` does not end"));
    &wgsl[start..start + len]
}

#[test]
fn round_batches_leave_out_the_queue_fences() {
    let chunks = StdRng::seed_from_u64(tests::seed("round_fences")).random_range(2..=4);
    let graphs = [
        (binary_tree(5).graph, vec![("Grow", true)]),
        (scratch_sum().graph, vec![("Sum", false)]),
        (ping_pong(4).graph, vec![("Ping", true), ("Pong", true)]),
    ];
    for (graph, procedures) in &graphs {
        for chunks_per_batch in [1, chunks] {
            let options = CompileOptions {
                chunks_per_batch,
                ..CompileOptions::default()
            };
            let compiled = graph.compile(&options).unwrap();
            let wgsl = compiled.wgsl();
            for &(procedure, enqueues) in procedures {
                let context = format!("{procedure}, {chunks_per_batch} chunk(s) per batch");
                let batch = function(wgsl, &format!("sched_batch_{procedure}"));
                // Neither the acquire and release fences around the slots read,
                // nor released ranges or publication.
                for absent in ["sched_receive_done", "sched_publish", "sched_flush_share"] {
                    assert!(!batch.contains(absent), "{context}: {absent} in\n{batch}");
                }
                let count = |what: &str| batch.matches(what).count();
                // The flush: the staging complete, then the reservations shared;
                // the chunk loop's own barrier when there is one.
                let chunk_barriers = usize::from(chunks_per_batch > 1);
                let (workgroup, storage, uniform) = if enqueues {
                    (1 + chunk_barriers, 1, 1)
                } else {
                    (chunk_barriers, 0, 0)
                };
                assert_eq!(
                    count("workgroupBarrier()"),
                    workgroup,
                    "{context}:\n{batch}"
                );
                assert_eq!(count("storageBarrier()"), storage, "{context}:\n{batch}");
                assert_eq!(
                    count("workgroupUniformLoad("),
                    uniform,
                    "{context}:\n{batch}"
                );
                // The round kernel runs it; the megakernel keeps its own runner.
                let round = function(wgsl, &format!("sched_round_{procedure}"));
                assert!(
                    round.contains(&format!("sched_batch_{procedure}(")),
                    "{round}"
                );
                let runner = function(wgsl, &format!("sched_run_{procedure}"));
                assert!(runner.contains("sched_receive_done"), "{runner}");
            }
        }
    }
}

/// One workgroup strides over every batch of a round, so it reuses its
/// staging area batch after batch: every item still runs once with its own
/// id, which the hash written to `out[id]` shows.
#[gpu_test]
fn one_workgroup_reusing_its_staging_keeps_every_child() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("round_staging_reuse"));
    // From depth 10 on, a round whose items have children spans several
    // batches of 256 items.
    let depth = rng.random_range(10..=12);
    let chunks_per_batch = rng.random_range(1..=2);
    let items = (1u32 << (depth + 1)) - 1;
    let tree = hashing_tree(depth);
    let options = CompileOptions {
        chunks_per_batch,
        ..CompileOptions::default()
    };
    let compiled = tree.compile(&options).unwrap();
    let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("out"),
        size: 4 * (u64::from(items) + 1),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &config(1, items + 1)).unwrap();
    let report = executor
        .run_with(
            Strategy::rounds(),
            &Seeds::new().add(&tree.ids, &[Node { depth: 0, id: 1 }]),
            &[Binding::buffer("out", &out)],
        )
        .unwrap();
    let grow = report.procedure(&tree.ids).unwrap();
    assert_eq!(grow.executed, u64::from(items), "{report}");
    assert_eq!(report.rounds, depth + 1, "{report}");
    let bytes = read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(30)).unwrap();
    let values: &[u32] = bytemuck::cast_slice(&bytes);
    for id in 1..=items {
        assert_eq!(
            values[id as usize],
            hash_rounds(id),
            "item {id} of {items} (depth {depth}, {chunks_per_batch} chunk(s) per batch)"
        );
    }
}

/// `Root` hands each item to `Leaf`, which writes `out[id]` and enqueues
/// nothing: `Leaf` needs no barrier, `Root` does (its flush).
fn root_and_leaf(leaf_body: &str) -> Graph {
    let mut graph = Graph::new("root and leaf");
    graph.resource(Resource::storage::<[u32]>("out"));
    let root = graph.procedure(
        Procedure::of::<Node>("Root")
            .initial(true)
            .body("if (valid) { enqueue_Leaf(item); }"),
    );
    let leaf = graph.procedure(Procedure::of::<Node>("Leaf").body(leaf_body));
    graph.connect(&root, &leaf);
    graph
}

#[test]
fn a_procedure_that_shares_nothing_gets_a_round_kernel_without_barriers() {
    let chunks = StdRng::seed_from_u64(tests::seed("round_barrier_free")).random_range(1..=4);
    let options = CompileOptions {
        chunks_per_batch: chunks,
        ..CompileOptions::default()
    };
    let barriers = ["Barrier(", "workgroupUniformLoad("];
    let plain = root_and_leaf("if (valid) { out[item.id] = item.depth; }")
        .compile(&options)
        .unwrap();
    let wgsl = plain.wgsl();
    for name in ["sched_batch_Leaf", "sched_round_Leaf"] {
        let text = function(wgsl, name);
        for barrier in barriers {
            assert!(!text.contains(barrier), "{chunks} chunk(s):\n{text}");
        }
    }
    // Root flushes, and a body that synchronizes keeps its barriers.
    assert!(function(wgsl, "sched_round_Root").contains("workgroupUniformLoad("));
    let synchronizing = root_and_leaf("workgroupBarrier();\nif (valid) { out[item.id] = 1u; }")
        .compile(&options)
        .unwrap();
    assert!(function(synchronizing.wgsl(), "sched_round_Leaf").contains("workgroupUniformLoad("));
}

/// The barrier-free round kernel computes what the megakernel computes, with
/// one workgroup striding over many batches.
#[gpu_test]
fn a_round_kernel_without_barriers_runs_every_item_once() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("round_barrier_free_run"));
    let count = rng.random_range(600..5000u32);
    let chunks_per_batch = rng.random_range(1..=4);
    let graph = root_and_leaf("if (valid) { out[item.id] += item.depth + 1u; }");
    let options = CompileOptions {
        chunks_per_batch,
        ..CompileOptions::default()
    };
    let compiled = graph.compile(&options).unwrap();
    let root = compiled.procedure_id::<Node>("Root").unwrap();
    let seeds: Vec<Node> = (0..count).map(|id| Node { depth: id % 7, id }).collect();
    for workgroups in [1, 3] {
        let out = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("out"),
            size: 4 * u64::from(count),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut executor = Executor::new(
            &gpu.device,
            &gpu.queue,
            &compiled,
            &config(workgroups, count),
        )
        .unwrap();
        let report = executor
            .run_with(
                Strategy::rounds(),
                &Seeds::new().add(&root, &seeds),
                &[Binding::buffer("out", &out)],
            )
            .unwrap();
        assert_eq!(report.rounds, 2, "{report}");
        let bytes = read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(30)).unwrap();
        let values: &[u32] = bytemuck::cast_slice(&bytes);
        for (id, &value) in values.iter().enumerate() {
            assert_eq!(
                value,
                id as u32 % 7 + 1,
                "item {id} of {count}, {workgroups} workgroup(s), {chunks_per_batch} chunk(s)"
            );
        }
    }
}
