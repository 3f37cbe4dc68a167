//! Typed resources on a real adapter (lavapipe in CI): the executor creates,
//! fills, clears and reads them, checked against a CPU computation with
//! random inputs; buffers below a declared minimum are refused before the
//! run, and misuse gives typed errors.

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Atomic, Binding, CompileOptions, CompiledGraph, Executor, Graph, Procedure, ProcedureId,
    Resource, RunError, Seeds, wgpu,
};

#[scheduler::item]
struct Job {
    index: u32,
}

/// A uniform, stated once: its WGSL struct is derived.
#[scheduler::item]
struct Params {
    scale: u32,
    buckets: u32,
}

const BUCKETS: u64 = 16;

/// `sums[index % buckets] += input[index] * scale` for every job.
fn graph(inputs: u64) -> (CompiledGraph, ProcedureId<Job>) {
    let mut graph = Graph::new("typed resources");
    graph
        .resource(Resource::uniform::<Params>("params"))
        .resource(Resource::storage_read::<[u32]>("input").min_len(inputs))
        .resource(Resource::storage::<[Atomic<u32>]>("sums").min_len(BUCKETS))
        // Declared by its WGSL type: the executor cannot size it.
        .resource(Resource::storage_wgsl("untyped", "array<u32>"));
    let job = graph.procedure(Procedure::of::<Job>("Sum").initial(true).body(
        "if (valid) {
    atomicAdd(&sums[item.index % params.buckets], input[item.index] * params.scale);
    untyped[0] = 1u;
}",
    ));
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    (compiled, job)
}

fn untyped_buffer(gpu: &scheduler::Gpu) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("untyped"),
        size: 4,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

#[gpu_test]
fn typed_resources_are_created_written_cleared_and_read_back() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("typed_resources"));
    let inputs: Vec<u32> = (0..rng.random_range(1..3000))
        .map(|_| rng.random_range(0..1000))
        .collect();
    let scale = rng.random_range(1..5);
    let (compiled, job) = graph(inputs.len() as u64);
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &tests::config(2, 4096)).unwrap();
    executor
        .write(
            "params",
            &[Params {
                scale,
                buckets: BUCKETS as u32,
            }],
        )
        .unwrap();
    executor.write("input", &inputs).unwrap();
    executor.create_buffer("sums", BUCKETS).unwrap();
    let untyped = untyped_buffer(gpu);
    let jobs: Vec<Job> = (0..inputs.len() as u32)
        .map(|index| Job { index })
        .collect();
    let seeds = Seeds::new().add(&job, &jobs);

    let mut expected = vec![0u32; BUCKETS as usize];
    for (i, x) in inputs.iter().enumerate() {
        expected[i % BUCKETS as usize] += x * scale;
    }
    // The executor binds its own buffers; the untyped one is the user's.
    executor
        .run(&seeds, &[Binding::buffer("untyped", &untyped)])
        .unwrap();
    assert_eq!(executor.read::<u32>("sums").unwrap(), expected);
    // Without a clear the sums add up; after one they start again.
    executor
        .run(&seeds, &[Binding::buffer("untyped", &untyped)])
        .unwrap();
    let doubled: Vec<u32> = expected.iter().map(|x| 2 * x).collect();
    assert_eq!(executor.read::<u32>("sums").unwrap(), doubled);
    executor.clear("sums").unwrap();
    assert_eq!(executor.read::<u32>("sums").unwrap(), vec![0; 16]);
    executor
        .run(&seeds, &[Binding::buffer("untyped", &untyped)])
        .unwrap();
    assert_eq!(executor.read::<u32>("sums").unwrap(), expected);
    // The uniform reads back as what was written.
    let params = executor.read::<Params>("params").unwrap();
    assert_eq!((params[0].scale, params[0].buckets), (scale, 16));
}

#[gpu_test]
fn a_buffer_below_the_declared_minimum_is_refused_before_the_run() {
    let gpu = tests::gpu();
    let (compiled, job) = graph(64);
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &tests::config(2, 4096)).unwrap();
    executor
        .write(
            "params",
            &[Params {
                scale: 1,
                buckets: 16,
            }],
        )
        .unwrap();
    executor.create_buffer("sums", BUCKETS).unwrap();
    let untyped = untyped_buffer(gpu);
    let jobs: Vec<Job> = (0..64).map(|index| Job { index }).collect();
    let seeds = Seeds::new().add(&job, &jobs);

    // The executor's own buffer: creating one too short is refused.
    let short = executor.create_buffer("input", 16);
    assert!(
        matches!(&short, Err(RunError::BufferTooSmall { resource, bytes: 64, needed: 256 }) if resource == "input"),
        "{short:?}"
    );
    // A user's buffer a quarter of the size: refused, and nothing ran.
    let quarter = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("quarter"),
        size: 64,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let result = executor.run(
        &seeds,
        &[
            Binding::buffer("input", &quarter),
            Binding::buffer("untyped", &untyped),
        ],
    );
    assert!(
        matches!(&result, Err(RunError::BufferTooSmall { resource, bytes: 64, needed: 256 }) if resource == "input"),
        "{result:?}"
    );
    assert_eq!(executor.read::<u32>("sums").unwrap(), vec![0; 16]);
    // A range of a large enough buffer that is itself too short, likewise.
    let large = gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("large"),
        size: 1024,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let range = Binding {
        name: "input",
        resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &large,
            offset: 256,
            size: wgpu::BufferSize::new(128),
        }),
    };
    let result = executor.run(&seeds, &[range, Binding::buffer("untyped", &untyped)]);
    assert!(
        matches!(
            &result,
            Err(RunError::BufferTooSmall {
                bytes: 128,
                needed: 256,
                ..
            })
        ),
        "{result:?}"
    );
    // The full buffer passes, and the run does its work.
    executor
        .run(
            &seeds,
            &[
                Binding::buffer("input", &large),
                Binding::buffer("untyped", &untyped),
            ],
        )
        .unwrap();
    assert_eq!(executor.read::<u32>("sums").unwrap(), vec![0; 16]);
}

#[gpu_test]
fn misuse_of_typed_buffers_gives_typed_errors() {
    let gpu = tests::gpu();
    let (compiled, job) = graph(4);
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &tests::config(2, 4096)).unwrap();
    let binding_error = |result: Result<_, RunError>, words: &[&str]| match result {
        Err(RunError::Binding(message)) => assert!(
            words.iter().all(|w| message.contains(w)),
            "{message} lacks {words:?}"
        ),
        other => panic!(
            "expected a binding error with {words:?}, got {:?}",
            other.err()
        ),
    };
    binding_error(
        executor.read::<u32>("sums").map(|_| ()),
        &["no buffer", "sums"],
    );
    executor.create_buffer("sums", BUCKETS).unwrap();
    binding_error(
        executor.read::<u64>("sums").map(|_| ()),
        &["4 bytes per element", "u64"],
    );
    binding_error(
        executor.create_buffer("untyped", 4).map(|_| ()),
        &["untyped", "WGSL type"],
    );
    binding_error(
        executor.create_buffer("params", 2).map(|_| ()),
        &["params", "single"],
    );
    binding_error(
        executor.clear("nothing").map(|_| ()),
        &["nothing", "not a declared"],
    );
    // A run with a resource neither bound nor created names it.
    let seeds = Seeds::new().add(&job, &[Job { index: 0 }]);
    binding_error(
        executor.run(&seeds, &[]).map(|_| ()),
        &["`params` is not bound"],
    );
}
