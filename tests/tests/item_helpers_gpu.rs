//! The item-wide helpers (reductions and broadcasts over the threads of one
//! item) and typed scratch, on a real adapter (lavapipe in CI), checked
//! against CPU computations with random inputs, full and partial batches.

use std::time::Duration;

use gpu_test::gpu_test;
use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Binding, CompileOptions, CompiledGraph, Executor, Graph, Procedure, ProcedureId, Resource,
    Seeds, Strategy, readback::read_buffer, wgpu,
};

/// One item: its index into the inputs and the outputs.
#[scheduler::item]
struct Job {
    index: u32,
}

/// Typed scratch: written by the first and the last thread of an item.
#[scheduler::item]
struct Ends {
    first: u32,
    last: u32,
}

/// Results per item, each written by every thread of the item.
const RESULTS: usize = 15;

/// A graph whose one procedure runs every helper on its threads' inputs and
/// has every thread write every result: `out[(index * RESULTS + k) *
/// threads + thread]`. Threads without an item pass values that would
/// change every result if they leaked into another item's.
fn helpers_graph(threads: u32) -> (Graph, ProcedureId<Job>) {
    let mut graph = Graph::new("item helpers");
    graph
        .constant("THREADS", threads)
        .constant("RESULTS", RESULTS as u32)
        .resource(Resource::storage_read::<[u32]>("words"))
        .resource(Resource::storage_read::<[f32]>("reals"))
        .resource(Resource::storage::<[u32]>("out"));
    let id = graph.procedure(
        Procedure::of::<Job>("Reduce")
            .initial(true)
            .threads_per_item(threads)
            .scratch::<Ends>()
            .body(
                "let at = item.index * THREADS + thread;
var word = 0u;
var real = -1e30;
if (valid) {
    word = words[at];
    real = reals[at];
} else {
    // Poison: would show in any other item's minimum, maximum or sum.
    word = select(0xffffffffu, 0u, thread % 2u == 0u);
    real = select(1e30, -1e30, thread % 2u == 0u);
}
let signed = bitcast<i32>(word);
var r: array<u32, RESULTS>;
r[0] = item_min_u32(word);
r[1] = item_max_u32(word);
r[2] = item_sum_u32(word);
r[3] = bitcast<u32>(item_min_i32(signed));
r[4] = bitcast<u32>(item_max_i32(signed));
r[5] = bitcast<u32>(item_sum_i32(signed));
r[6] = bitcast<u32>(item_min_f32(real));
r[7] = bitcast<u32>(item_max_f32(real));
r[8] = bitcast<u32>(item_sum_f32(real));
r[9] = select(0u, 1u, item_all_equal_u32(word));
r[10] = item_broadcast_u32(word);
r[11] = bitcast<u32>(item_broadcast_f32(real));
r[12] = select(0u, 1u, item_any(word % 7u == 0u));
r[13] = select(0u, 1u, item_all(word % 7u != 0u));
if (valid && thread == 0u) {
    scratch.first = word;
}
if (valid && thread == THREADS - 1u) {
    (*scratch).last = word;
}
workgroupBarrier();
r[14] = scratch.first ^ scratch.last;
if (valid) {
    for (var k = 0u; k < RESULTS; k += 1u) {
        out[(item.index * RESULTS + k) * THREADS + thread] = r[k];
    }
}",
            ),
    );
    (graph, id)
}

/// The tree order of the helpers: pairs `stride` apart, the stride halving.
fn tree<T: Copy>(values: &[T], op: impl Fn(T, T) -> T) -> T {
    let mut v = values.to_vec();
    let mut stride = v.len() / 2;
    while stride >= 1 {
        for t in 0..stride {
            v[t] = op(v[t], v[t + stride]);
        }
        stride /= 2;
    }
    v[0]
}

/// The CPU's results for one item, in the order of the body's `r`.
fn expected(words: &[u32], reals: &[f32]) -> [u32; RESULTS] {
    let signed: Vec<i32> = words.iter().map(|&w| w.cast_signed()).collect();
    let bool_word = |b: bool| u32::from(b);
    [
        *words.iter().min().unwrap(),
        *words.iter().max().unwrap(),
        words.iter().fold(0u32, |a, &b| a.wrapping_add(b)),
        *signed.iter().min().unwrap() as u32,
        *signed.iter().max().unwrap() as u32,
        signed.iter().fold(0i32, |a, &b| a.wrapping_add(b)) as u32,
        tree(reals, f32::min).to_bits(),
        tree(reals, f32::max).to_bits(),
        tree(reals, |a, b| a + b).to_bits(),
        bool_word(words.iter().all(|&w| w == words[0])),
        words[0],
        reals[0].to_bits(),
        bool_word(words.iter().any(|&w| w % 7 == 0)),
        bool_word(words.iter().all(|&w| w % 7 != 0)),
        words[0] ^ words[words.len() - 1],
    ]
}

const NAMES: [&str; RESULTS] = [
    "min u32",
    "max u32",
    "sum u32",
    "min i32",
    "max i32",
    "sum i32",
    "min f32",
    "max f32",
    "sum f32",
    "all equal u32",
    "broadcast u32",
    "broadcast f32",
    "any",
    "all",
    "typed scratch",
];

fn storage(gpu: &scheduler::Gpu, label: &str, contents: &[u8]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    gpu.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        })
}

/// Inputs for `count` items of `threads` threads: random words (a third of
/// the items with all words equal, small words now and then so that `any`
/// and `all` vary) and random reals.
fn inputs(rng: &mut StdRng, count: u32, threads: u32) -> (Vec<u32>, Vec<f32>) {
    let n = (count * threads) as usize;
    let mut words: Vec<u32> = (0..n).map(|_| rng.random()).collect();
    for item in words.chunks_mut(threads as usize) {
        match rng.random_range(0..3) {
            0 => {
                let w = rng.random();
                item.fill(w);
            }
            1 => item.iter_mut().for_each(|w| *w %= 64),
            _ => {}
        }
    }
    let reals = (0..n)
        .map(|_| rng.random_range(-1000.0f32..1000.0))
        .collect();
    (words, reals)
}

fn check_run(
    gpu: &scheduler::Gpu,
    compiled: &CompiledGraph,
    id: &ProcedureId<Job>,
    rng: &mut StdRng,
    threads: u32,
    strategy: Strategy,
) {
    let per_chunk = compiled.workgroup_size() / threads;
    // A count that leaves the last batch partly filled (its last chunk too
    // when a chunk holds several items).
    let batch = compiled.queues()[0].items_per_batch;
    let count = loop {
        let n = rng.random_range(1..=(4 * batch).max(40));
        if batch == 1 || (n % batch != 0 && (per_chunk == 1 || n % per_chunk != 0)) {
            break n;
        }
    };
    let (words, reals) = inputs(rng, count, threads);
    let words_buffer = storage(gpu, "words", bytemuck::cast_slice(&words));
    let reals_buffer = storage(gpu, "reals", bytemuck::cast_slice(&reals));
    let out_words = vec![0xdeadbeefu32; count as usize * RESULTS * threads as usize];
    let out = storage(gpu, "out", bytemuck::cast_slice(&out_words));
    let mut executor = Executor::new(
        &gpu.device,
        &gpu.queue,
        compiled,
        &tests::config(rng.random_range(1..=3), 4096),
    )
    .unwrap();
    let jobs: Vec<Job> = (0..count).map(|index| Job { index }).collect();
    eprintln!("  {count} items, {strategy:?}");
    let report = executor
        .run_with(
            strategy,
            &Seeds::new().add(id, &jobs),
            &[
                Binding::buffer("words", &words_buffer),
                Binding::buffer("reals", &reals_buffer),
                Binding::buffer("out", &out),
            ],
        )
        .unwrap();
    assert_eq!(report.procedure(id).unwrap().executed, u64::from(count));
    let bytes = read_buffer(&gpu.device, &gpu.queue, &out, Duration::from_secs(60)).unwrap();
    let got: &[u32] = bytemuck::cast_slice(&bytes);
    let t = threads as usize;
    for item in 0..count as usize {
        let want = expected(&words[item * t..][..t], &reals[item * t..][..t]);
        for (k, &value) in want.iter().enumerate() {
            for thread in 0..t {
                let at = (item * RESULTS + k) * t + thread;
                assert_eq!(
                    got[at],
                    value,
                    "{}: item {item} of {count}, thread {thread} of {threads}, {} chunk(s), {strategy:?}",
                    NAMES[k],
                    compiled.queues()[0].items_per_batch / per_chunk,
                );
            }
        }
    }
}

#[gpu_test]
fn reductions_and_broadcasts_match_the_cpu_for_every_thread_count() {
    let gpu = tests::gpu();
    let mut rng = StdRng::seed_from_u64(tests::seed("item_helpers"));
    for threads in [1, 4, 32, 64] {
        let (graph, id) = helpers_graph(threads);
        for options in [
            CompileOptions::default(),
            CompileOptions {
                workgroup_size: 64,
                chunks_per_batch: rng.random_range(2..=4),
                ..CompileOptions::default()
            },
        ] {
            let compiled = graph.compile(&options).unwrap();
            eprintln!(
                "{threads} thread(s) per item, workgroup {}, {} chunk(s)",
                options.workgroup_size, options.chunks_per_batch
            );
            check_run(gpu, &compiled, &id, &mut rng, threads, Strategy::Megakernel);
            check_run(
                gpu,
                &compiled,
                &id,
                &mut rng,
                threads,
                Strategy::Rounds {
                    rounds_per_batch: 4,
                },
            );
        }
    }
}

#[test]
fn the_generated_module_validates_and_declares_helpers_only_when_used() {
    let (graph, _) = helpers_graph(32);
    for options in [
        CompileOptions::default(),
        CompileOptions {
            workgroup_size: 64,
            ..CompileOptions::default()
        },
    ] {
        let compiled = graph.compile(&options).unwrap();
        let wgsl = compiled.wgsl();
        let module = naga::front::wgsl::parse_str(wgsl).unwrap();
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap();
        let items = options.workgroup_size / 32;
        let scratch = format!("var<workgroup> sched_scratch_Reduce: array<Ends, {items}>;");
        for needed in [
            "var<workgroup> sched_wg_item: array<u32,",
            "fn sched_item_reduce(",
            "fn item_sum_f32(",
            &scratch,
            "struct Ends { first: u32, last: u32 }",
            "    let scratch = &sched_scratch_Reduce[slot];",
            "sched_item_threads = 32u;",
        ] {
            let near: Vec<&str> = wgsl.lines().filter(|l| l.contains("scratch")).collect();
            assert!(wgsl.contains(needed), "missing `{needed}` in {near:#?}");
        }
        // One word per thread, rounded to 16 bytes, plus the typed scratch.
        let without = {
            let mut plain = Graph::new("plain");
            plain.resource(Resource::storage::<[u32]>("out"));
            plain.procedure(
                Procedure::of::<Job>("Reduce")
                    .initial(true)
                    .threads_per_item(32)
                    .body("if (valid) { out[item.index] = thread; }"),
            );
            plain.compile(&options).unwrap()
        };
        assert!(!without.wgsl().contains("sched_wg_item"));
        assert!(!without.wgsl().contains("item_sum_u32"));
        assert_eq!(
            compiled.workgroup_memory_bytes() - without.workgroup_memory_bytes(),
            4 * options.workgroup_size + (8 * items).next_multiple_of(16),
        );
    }
}

#[test]
fn the_generated_helpers_read_well() {
    let (graph, _) = helpers_graph(4);
    let compiled = graph
        .compile(&CompileOptions {
            workgroup_size: 16,
            ..CompileOptions::default()
        })
        .unwrap();
    let wgsl = compiled.wgsl();
    let start = wgsl.find("// Reduces `value`").unwrap();
    let end = start + wgsl[start..].find("\n}\n").unwrap() + 3;
    insta::assert_snapshot!("item_reduce_workgroup_16", &wgsl[start..end]);
}

#[test]
fn typed_scratch_counts_against_the_workgroup_limit() {
    #[scheduler::item]
    struct Big {
        words: [u32; 256],
    }
    let mut graph = Graph::new("big scratch");
    graph.procedure(
        Procedure::of::<Job>("Heavy")
            .initial(true)
            .scratch::<Big>()
            .body("if (valid) { scratch.words[0] = item.index; }"),
    );
    match graph.compile(&CompileOptions::default()) {
        Err(scheduler::CompileError::ScratchTooLarge {
            procedure,
            per_item,
            items,
            ..
        }) => {
            assert_eq!(procedure, "Heavy");
            assert_eq!(per_item, 1024);
            assert_eq!(items, 256);
        }
        other => panic!("expected ScratchTooLarge, got {other:?}"),
    }
}

/// The generated `let scratch = ...;` line ahead of a body does not shift the
/// body's own line numbers in error messages.
#[test]
fn errors_in_a_body_with_typed_scratch_keep_the_body_line() {
    let mut graph = Graph::new("bad body");
    graph.procedure(
        Procedure::of::<Job>("Broken")
            .initial(true)
            .scratch::<Ends>()
            .body("scratch.first = item.index;\nscratch.missing = 1u;"),
    );
    match graph.compile(&CompileOptions::default()) {
        Err(scheduler::CompileError::Wgsl { origin, line, .. }) => {
            assert_eq!(origin, scheduler::SourceOrigin::Body("Broken".into()));
            assert_eq!(line, 2);
        }
        other => panic!("expected a WGSL error, got {other:?}"),
    }
}
