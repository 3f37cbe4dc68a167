//! GPU runs of the scheduler's example workloads (adaptive quadrature and BFS
//! levels) on freshly drawn inputs, each compared exactly with its CPU
//! reference, at 1, 2 and 64 persistent workgroups: one workgroup alone must
//! drain recursive and cross-procedure work, two exercise contention, and 64
//! (more than lavapipe runs at once) exercise workgroups that are not all
//! resident. A run with an iteration budget also covers re-dispatching.

use std::time::Duration;

use gpu_test::gpu_test;
use scheduler::ExecutorConfig;

use workloads::{bfs, quadrature};

/// Bumps per quadrature problem, as in the example.
const BUMPS: usize = 100;
/// Acceptance threshold, as in the example.
const THRESHOLD: u32 = 16;
/// Nodes per BFS graph, as in the example.
const NODES: u32 = 20_000;

fn config(workgroups: u32, iteration_budget: Option<u32>) -> ExecutorConfig {
    ExecutorConfig {
        workgroups: Some(workgroups),
        iteration_budget,
        // Each run takes well under a second on lavapipe; a hang fails fast.
        timeout: Duration::from_secs(30),
        ..Default::default()
    }
}

fn quadrature_at(name: &str, workgroups: u32, iteration_budget: Option<u32>) {
    let gpu = tests::gpu();
    let problem = quadrature::Problem::random(tests::seed(name), BUMPS, THRESHOLD);
    let checked = quadrature::run(gpu, &problem, &config(workgroups, iteration_budget))
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    eprintln!("{}\n{}", checked.report, checked.summary);
    assert!(
        checked.mismatches.is_empty(),
        "{name}: GPU and CPU disagree:\n{}\n{}",
        checked.mismatches.join("\n"),
        checked.report
    );
    assert_eq!(checked.report.workgroups, workgroups);
}

fn bfs_at(name: &str, workgroups: u32, iteration_budget: Option<u32>) {
    let gpu = tests::gpu();
    let problem = bfs::Problem::random(tests::seed(name), NODES, 3);
    let config = ExecutorConfig {
        capacities: bfs::capacities(&problem),
        ..config(workgroups, iteration_budget)
    };
    let checked = bfs::run(gpu, &problem, &config).unwrap_or_else(|e| panic!("{name}: {e}"));
    eprintln!("{}\n{}", checked.report, checked.summary);
    assert!(
        checked.mismatches.is_empty(),
        "{name}: GPU and CPU disagree:\n{}\n{}",
        checked.mismatches.join("\n"),
        checked.report
    );
    assert_eq!(checked.report.workgroups, workgroups);
}

#[gpu_test]
fn quadrature_one_workgroup() {
    quadrature_at("quadrature_one_workgroup", 1, None);
}

#[gpu_test]
fn quadrature_two_workgroups() {
    quadrature_at("quadrature_two_workgroups", 2, None);
}

#[gpu_test]
fn quadrature_64_workgroups() {
    quadrature_at("quadrature_64_workgroups", 64, None);
}

#[gpu_test]
fn quadrature_with_iteration_budget() {
    quadrature_at("quadrature_with_iteration_budget", 2, Some(4));
}

#[gpu_test]
fn bfs_one_workgroup() {
    bfs_at("bfs_one_workgroup", 1, None);
}

#[gpu_test]
fn bfs_two_workgroups() {
    bfs_at("bfs_two_workgroups", 2, None);
}

#[gpu_test]
fn bfs_64_workgroups() {
    bfs_at("bfs_64_workgroups", 64, None);
}

#[gpu_test]
fn bfs_with_iteration_budget() {
    bfs_at("bfs_with_iteration_budget", 2, Some(4));
}

/// The CPU references on a case small enough to check by hand.
#[test]
fn cpu_references_on_known_inputs() {
    // A path 0 - 1 - 2 - 3 plus an isolated node 4, source 0.
    let problem = bfs::Problem {
        graph: bfs::Csr {
            row_start: vec![0, 1, 3, 5, 6, 6],
            adjacency: vec![1, 0, 2, 1, 3, 2],
        },
        sources: vec![0],
    };
    assert_eq!(bfs::cpu_levels(&problem), [0, 1, 2, 3, bfs::UNREACHED]);

    // Without bumps every root interval is accepted at depth 0 with sum 0.
    let empty = quadrature::Problem {
        bumps: Vec::new(),
        threshold: THRESHOLD,
    };
    let (tally, processed) = quadrature::cpu_reference(&empty);
    let roots = u64::from(quadrature::GRID / quadrature::ROOT_WIDTH);
    assert_eq!((tally.intervals(), processed), (roots, roots));
    assert_eq!(tally.integral(), 0.0);

    // The adaptive integral of random bumps agrees with the dense one.
    let problem = quadrature::Problem::random(1, BUMPS, THRESHOLD);
    let (tally, _) = quadrature::cpu_reference(&problem);
    let dense = quadrature::dense_simpson(&problem);
    assert!((tally.integral() - dense).abs() <= 1e-5 * dense);
}

/// Snapshots of the examples' megakernels, for fixed problems (the generated
/// code depends on the problem only through constants such as the fan-out).
#[test]
fn snapshots_of_the_example_graphs() {
    let options = scheduler::CompileOptions::with_features(
        scheduler::wgpu::Features::MEMORY_DECORATION_COHERENT,
    );
    let quadrature = quadrature::graph(&quadrature::Problem::random(1, 100, 16))
        .graph
        .compile(&options)
        .unwrap();
    insta::assert_snapshot!("quadrature_megakernel", quadrature.wgsl());
    let bfs = bfs::graph(&bfs::Problem::random(1, 2000, 3))
        .graph
        .compile(&options)
        .unwrap();
    insta::assert_snapshot!("bfs_megakernel", bfs.wgsl());
}

use workloads::mandelbrot;

/// Side of the Mandelbrot test image, and its iteration limit: lavapipe
/// renders it in well under a second.
const MANDELBROT_SIZE: u32 = 256;
const MANDELBROT_MAX_ITER: u32 = 256;

/// Renders the Mandelbrot set by Mariani–Silver subdivision and compares
/// every pixel with the CPU's subdivision, and the scheduler's counters with
/// its tile counts, under the multiply-adds the driver fused.
fn mandelbrot_at(name: &str, workgroups: u32, strategy: scheduler::Strategy) {
    let gpu = tests::gpu();
    let view = mandelbrot::View::whole_set(MANDELBROT_SIZE, MANDELBROT_MAX_ITER);
    let config = ExecutorConfig {
        workgroups: Some(workgroups),
        ..mandelbrot::config(gpu, &view, 1)
    };
    let options =
        scheduler::CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
    let mut renderer = mandelbrot::Mandelbrot::new(gpu, view, &options, &config)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let report = renderer
        .render(strategy)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let counts = renderer.counts().unwrap();
    let plain = mandelbrot::cpu_mariani_silver(&view);
    let matched = renderer
        .check(&report, &counts, &plain)
        .unwrap_or_else(|e| panic!("{name}: GPU and CPU disagree: {e}\n{report}"));
    let cpu = &matched.reference;
    eprintln!(
        "{report}\n{} tiles, {} filled, {} split, {} blocks; the driver fused: {}",
        cpu.tiles, cpu.filled, cpu.split, cpu.blocks, matched.contraction
    );
    assert_eq!(report.workgroups, workgroups);
}

#[gpu_test]
fn mandelbrot_one_workgroup() {
    mandelbrot_at(
        "mandelbrot_one_workgroup",
        1,
        scheduler::Strategy::Megakernel,
    );
}

#[gpu_test]
fn mandelbrot_64_workgroups() {
    mandelbrot_at(
        "mandelbrot_64_workgroups",
        64,
        scheduler::Strategy::Megakernel,
    );
}

#[gpu_test]
fn mandelbrot_rounds() {
    mandelbrot_at("mandelbrot_rounds", 64, scheduler::Strategy::rounds());
}

/// The example's own checked run (default workgroups), which also counts the
/// pixels where Mariani–Silver differs from brute force.
#[gpu_test]
fn mandelbrot_example_run() {
    let gpu = tests::gpu();
    let view = mandelbrot::View::whole_set(MANDELBROT_SIZE, MANDELBROT_MAX_ITER);
    let checked = mandelbrot::run(gpu, &view, &mandelbrot::config(gpu, &view, 1)).unwrap();
    eprintln!("{}\n{}", checked.report, checked.summary);
    assert!(
        checked.mismatches.is_empty(),
        "GPU and CPU disagree:\n{}",
        checked.mismatches.join("\n")
    );
    assert_eq!(checked.counts.len(), view.pixels());
}

/// The Mandelbrot CPU references on cases checked by hand.
#[test]
fn mandelbrot_cpu_references() {
    let view = mandelbrot::View::whole_set(64, 100);
    // Pixel (48, 32) is c = 0, in the set; pixel (0, 32) is c = -2.25, which
    // leaves the disc after one step.
    assert_eq!(view.x0 + 48.0 * view.step, 0.0);
    assert_eq!(mandelbrot::escape_count(&view, 48, 32), 100);
    assert_eq!(mandelbrot::escape_count(&view, 0, 32), 1);

    // The border walk visits every border pixel once.
    let tile = mandelbrot::Tile {
        x: 8,
        y: 16,
        size: 8,
    };
    let mut border: Vec<(u32, u32)> = (0..4 * 7)
        .map(|i| mandelbrot::border_pixel(&tile, i))
        .collect();
    border.sort_unstable();
    border.dedup();
    assert_eq!(border.len(), 28);
    assert!(border.iter().all(|&(x, y)| {
        (x == 8 || x == 15 || y == 16 || y == 23) && (8..16).contains(&x) && (16..24).contains(&y)
    }));

    // The quarters cover their tile exactly.
    let mut covered = vec![0u32; 64];
    for q in mandelbrot::quarters(&tile) {
        for y in q.y..q.y + q.size {
            for x in q.x..q.x + q.size {
                covered[((y - 16) * 8 + x - 8) as usize] += 1;
            }
        }
    }
    assert!(covered.iter().all(|&c| c == 1));

    // The subdivision writes every pixel, and on the test view it equals
    // brute force.
    let view = mandelbrot::View::whole_set(MANDELBROT_SIZE, MANDELBROT_MAX_ITER);
    let cpu = mandelbrot::cpu_mariani_silver(&view);
    assert!(cpu.counts.iter().all(|&n| n <= MANDELBROT_MAX_ITER));
    assert_eq!(cpu.counts, mandelbrot::cpu_brute_force(&view));
    assert_eq!(cpu.tiles, 16 + 4 * cpu.split);
    assert_eq!(cpu.tiles, cpu.filled + cpu.split + cpu.blocks);
}

/// A snapshot of the Mandelbrot example's megakernel.
#[test]
fn snapshot_of_the_mandelbrot_graph() {
    let options = scheduler::CompileOptions::with_features(
        scheduler::wgpu::Features::MEMORY_DECORATION_COHERENT,
    );
    let view = mandelbrot::View::whole_set(MANDELBROT_SIZE, MANDELBROT_MAX_ITER);
    let compiled = mandelbrot::graph(&view).graph.compile(&options).unwrap();
    insta::assert_snapshot!("mandelbrot_megakernel", compiled.wgsl());
}
