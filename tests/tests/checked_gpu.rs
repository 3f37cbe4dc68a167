//! Checked mode (`CompileOptions::checked`): the examples give the same
//! results with every resource index guarded, and a body or library
//! function that indexes past a buffer's end fails the run with
//! `RunError::OutOfBounds` naming the procedure, the resource, the index and
//! the bound. Without checked mode the same programs are undefined
//! behaviour, so no test runs them unchecked.

use std::time::Duration;

use gpu_test::gpu_test;
use scheduler::{
    Binding, CompileOptions, Executor, ExecutorConfig, Graph, Procedure, Resource, RunError, Seeds,
    Strategy,
};
use tests::graphs::Node;

use workloads::{bfs, mandelbrot};

fn checked_options(gpu: &scheduler::Gpu) -> CompileOptions {
    CompileOptions::with_features(scheduler::recommended_features(&gpu.device)).checked()
}

#[gpu_test]
fn the_mandelbrot_example_is_exact_in_checked_mode() {
    let gpu = tests::gpu();
    let view = mandelbrot::View::whole_set(256, 256);
    let cpu = mandelbrot::cpu_mariani_silver(&view);
    let config = mandelbrot::config(gpu, &view, 1);
    let mut renderer =
        mandelbrot::Mandelbrot::new(gpu, view, &checked_options(gpu), &config).unwrap();
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let report = renderer.render(strategy).unwrap();
        assert!(report.bounds_violations.is_empty(), "{report:?}");
        let counts = renderer.counts().unwrap();
        // Exact, under the multiply-adds the driver fused.
        if let Err(e) = renderer.check(&report, &counts, &cpu) {
            panic!("{strategy}: {e}");
        }
    }
}

#[gpu_test]
fn the_bfs_example_is_exact_in_checked_mode() {
    let gpu = tests::gpu();
    let problem = bfs::Problem::random(tests::seed("bfs checked"), 5_000, 3);
    let graph = bfs::graph(&problem);
    let compiled = graph.graph.compile(&checked_options(gpu)).unwrap();
    assert!(
        compiled
            .wgsl()
            .contains("fn sched_checked_levels(index: u32) -> u32")
    );
    let config = ExecutorConfig {
        capacities: bfs::capacities(&problem),
        ..ExecutorConfig::default()
    };
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config).unwrap();
    let nodes = problem.graph.nodes() as usize;
    executor
        .write("row_start", &problem.graph.row_start)
        .unwrap();
    let mut adjacency = problem.graph.adjacency.clone();
    adjacency.push(0);
    executor.write("adjacency", &adjacency).unwrap();
    executor
        .write("levels", &vec![bfs::UNREACHED; nodes])
        .unwrap();
    executor.write("counters", &[0u32; 3]).unwrap();
    let seeds: Vec<bfs::Hop> = problem
        .sources
        .iter()
        .map(|&node| bfs::Hop { node, level: 0 })
        .collect();
    let report = executor
        .run(&Seeds::new().add(&graph.visit, &seeds), &[])
        .unwrap();
    assert!(report.bounds_violations.is_empty(), "{report:?}");
    assert_eq!(
        executor.read::<u32>("levels").unwrap(),
        bfs::cpu_levels(&problem)
    );
}

/// Pixels of the image `Paint` writes.
const WIDTH: u32 = 16;
const HEIGHT: u32 = 8;

/// `Paint` writes its pixel's count one whole image too far
/// (`counts[idx + W*H]`); `Fill` calls a library function that does the
/// same.
fn off_by_an_image() -> (
    scheduler::CompiledGraph,
    scheduler::ProcedureId<Node>,
    scheduler::ProcedureId<Node>,
) {
    let mut graph = Graph::new("off by an image");
    graph.constant("W", WIDTH).constant("H", HEIGHT);
    graph.resource(Resource::storage::<[u32]>("counts").min_len(u64::from(WIDTH * HEIGHT)));
    graph.library(
        "fn paint_far(idx: u32) {
    counts[idx + 2u * W * H] = 1u;
}",
    );
    let paint = graph.procedure(
        Procedure::of::<Node>("Paint")
            .initial(true)
            .body("if (valid) {\n    let idx = item.id;\n    counts[idx + W*H] = 1u;\n}"),
    );
    let fill = graph.procedure(
        Procedure::of::<Node>("Fill")
            .initial(true)
            .body("if (valid) { paint_far(item.id); }"),
    );
    let compiled = graph.compile(&CompileOptions::default().checked()).unwrap();
    (compiled, paint, fill)
}

fn config() -> ExecutorConfig {
    ExecutorConfig {
        timeout: Duration::from_secs(60),
        ..tests::config(2, 64)
    }
}

#[gpu_test]
fn an_index_past_the_end_is_reported_with_its_procedure_resource_and_index() {
    let gpu = tests::gpu();
    let (compiled, paint, fill) = off_by_an_image();
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config()).unwrap();
        executor
            .create_buffer("counts", u64::from(WIDTH * HEIGHT))
            .unwrap();
        let result = executor.run_with(
            strategy,
            &Seeds::new().add(&paint, &[Node { depth: 0, id: 5 }]),
            &[],
        );
        let Err(RunError::OutOfBounds {
            procedure,
            resource,
            index,
            bound,
            report,
            ..
        }) = &result
        else {
            panic!("{strategy}: expected OutOfBounds, got {result:?}");
        };
        assert_eq!(
            (procedure.as_str(), resource.as_str(), *index, *bound),
            ("Paint", "counts", 5 + WIDTH * HEIGHT, WIDTH * HEIGHT),
            "{strategy}"
        );
        assert_eq!(report.bounds_violations.len(), 1, "{report:?}");
        let message = result.unwrap_err().to_string();
        assert!(
            message.contains(
                "procedure `Paint` indexed resource `counts` out of bounds: index 133, bound 128"
            ),
            "{message}"
        );
        // Nothing beyond the buffer was written, and the redirected write
        // went to the last element.
        let counts = executor.read::<u32>("counts").unwrap();
        assert_eq!(counts.iter().sum::<u32>(), 1);
        assert_eq!(counts[(WIDTH * HEIGHT - 1) as usize], 1);

        // The library's access is counted for the procedure that called it.
        let result = executor.run_with(
            strategy,
            &Seeds::new().add(&fill, &[Node { depth: 0, id: 3 }]),
            &[],
        );
        assert!(
            matches!(
                &result,
                Err(RunError::OutOfBounds { procedure, index, .. })
                    if procedure == "Fill" && *index == 3 + 2 * WIDTH * HEIGHT
            ),
            "{strategy}: {result:?}"
        );
    }
}

#[gpu_test]
fn the_bound_is_the_bound_buffer_s_real_length() {
    let gpu = tests::gpu();
    let (compiled, paint, _) = off_by_an_image();
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, &config()).unwrap();
    // Twice the declared minimum: pixel 5 lands in the second image, within
    // the buffer, and is no violation; pixel 200 is past its end.
    let buffer = gpu
        .device
        .create_buffer(&scheduler::wgpu::BufferDescriptor {
            label: Some("counts"),
            size: 4 * 2 * u64::from(WIDTH * HEIGHT),
            usage: scheduler::wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
    let bindings = [Binding::buffer("counts", &buffer)];
    let report = executor
        .run(
            &Seeds::new().add(&paint, &[Node { depth: 0, id: 5 }]),
            &bindings,
        )
        .unwrap();
    assert!(report.bounds_violations.is_empty(), "{report:?}");
    let result = executor.run(
        &Seeds::new().add(&paint, &[Node { depth: 0, id: 200 }]),
        &bindings,
    );
    assert!(
        matches!(
            &result,
            Err(RunError::OutOfBounds { index, bound, .. })
                if *index == 200 + WIDTH * HEIGHT && *bound == 2 * WIDTH * HEIGHT
        ),
        "{result:?}"
    );
}

/// The checked module of [`off_by_an_image`]: the guards, the recorder, the
/// runner setting the running procedure and the rewritten indices, in the
/// body and in the library.
#[test]
fn snapshot_of_a_checked_module() {
    let (compiled, _, _) = off_by_an_image();
    let wgsl = compiled.wgsl();
    assert!(wgsl.contains("counts[sched_checked_counts(u32(idx + W*H))] = 1u;"));
    assert!(wgsl.contains("counts[sched_checked_counts(u32(idx + 2u * W * H))] = 1u;"));
    insta::assert_snapshot!("checked_off_by_an_image", wgsl);
}
