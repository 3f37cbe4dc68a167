//! The executor's pipeline cache on disk, with the adaptive quadrature
//! graph (quick to compile): a second executor for the same module finds
//! the first one's file, a garbage file and another module's file are
//! rejected and replaced, every run stays correct, and nothing is written
//! unless a directory is configured.

use std::path::{Path, PathBuf};
use std::time::Duration;

use gpu_test::gpu_test;
use scheduler::{
    CompileOptions, CompiledGraph, Executor, ExecutorConfig, Gpu, PipelineCacheState, Seeds,
    Strategy, pipeline_cache,
};
use workloads::quadrature::{self, QuadratureGraph};

fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("pipeline-cache-gpu-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn config(dir: Option<&Path>) -> ExecutorConfig {
    ExecutorConfig {
        workgroups: Some(2),
        timeout: Duration::from_secs(30),
        pipeline_cache_dir: dir.map(Path::to_path_buf),
        ..Default::default()
    }
}

fn quadrature_problem(threshold: u32) -> quadrature::Problem {
    quadrature::Problem::random(7, 20, threshold)
}

fn compile(gpu: &Gpu, problem: &quadrature::Problem) -> CompiledGraph {
    quadrature::graph(problem)
        .graph
        .compile(&CompileOptions::with_features(
            scheduler::recommended_features(&gpu.device),
        ))
        .expect("the quadrature graph compiles")
}

fn state(gpu: &Gpu, compiled: &CompiledGraph, dir: Option<&Path>) -> PipelineCacheState {
    let executor = Executor::new(&gpu.device, &gpu.queue, compiled, &config(dir))
        .expect("the executor is created");
    eprintln!(
        "{:?}: {:?}",
        executor.pipeline_cache(),
        executor.compile_timings()
    );
    assert!(
        executor.compile_timings().first_dispatch.is_some(),
        "the first dispatch runs in Executor::new"
    );
    executor.pipeline_cache().clone()
}

/// A checked run with the cache directory, through both strategies.
fn check_runs(gpu: &Gpu, problem: &quadrature::Problem, dir: &Path) {
    let checked = quadrature::run(gpu, problem, &config(Some(dir))).expect("the run succeeds");
    assert!(checked.mismatches.is_empty(), "{:?}", checked.mismatches);
    eprintln!("first megakernel run: {:?}", checked.report.wall_time);
    let QuadratureGraph { graph, refine } = quadrature::graph(problem);
    let compiled = graph
        .compile(&CompileOptions::with_features(
            scheduler::recommended_features(&gpu.device),
        ))
        .unwrap();
    let mut executor =
        Executor::new(&gpu.device, &gpu.queue, &compiled, &config(Some(dir))).unwrap();
    executor.write("bumps", &problem.bumps).unwrap();
    // Four words per depth: the quadrature's tally.
    let words = (4 * (quadrature::MAX_DEPTH + 1)) as usize;
    executor.write("tally", &vec![0u32; words]).unwrap();
    let seeds = Seeds::new().add(&refine, &quadrature::roots(problem));
    let rounds = executor
        .run_with(Strategy::rounds(), &seeds, &[])
        .expect("the Rounds run succeeds");
    eprintln!("first Rounds run: {:?}", rounds.wall_time);
    assert_eq!(
        rounds.procedure(&refine).unwrap().executed,
        checked.report.procedure(&refine).unwrap().executed
    );
}

#[gpu_test]
fn a_second_executor_hits_and_bad_files_are_replaced() {
    let gpu = tests::gpu();
    let dir = temp_dir("hit");
    let problem = quadrature_problem(16);
    let compiled = compile(gpu, &problem);

    // Nothing configured: nothing is written.
    assert_eq!(state(gpu, &compiled, None), PipelineCacheState::Off);

    let first = state(gpu, &compiled, Some(&dir));
    if first == PipelineCacheState::Unsupported {
        eprintln!("the device cannot cache pipelines; nothing more to check");
        return;
    }
    assert_eq!(first, PipelineCacheState::Miss);
    let name = pipeline_cache::file_name(&gpu.device.adapter_info(), compiled.wgsl()).unwrap();
    let file = dir.join(&name);
    assert!(file.exists(), "{} was written", file.display());
    assert_eq!(state(gpu, &compiled, Some(&dir)), PipelineCacheState::Hit);
    check_runs(gpu, &problem, &dir);

    // Garbage: rejected, then replaced by a good file.
    std::fs::write(&file, b"not a pipeline cache, not even close").unwrap();
    assert!(matches!(
        state(gpu, &compiled, Some(&dir)),
        PipelineCacheState::Rejected(_)
    ));
    assert_eq!(state(gpu, &compiled, Some(&dir)), PipelineCacheState::Hit);

    // A valid file of another module copied under this module's name.
    let other_problem = quadrature_problem(9);
    let other = compile(gpu, &other_problem);
    assert_ne!(other.wgsl(), compiled.wgsl());
    let other_name = pipeline_cache::file_name(&gpu.device.adapter_info(), other.wgsl()).unwrap();
    std::fs::copy(&file, dir.join(&other_name)).unwrap();
    match state(gpu, &other, Some(&dir)) {
        PipelineCacheState::Rejected(reason) => {
            assert!(reason.contains("another module"), "{reason}")
        }
        state => panic!("a foreign file was not rejected: {state:?}"),
    }
    check_runs(gpu, &other_problem, &dir);
    assert_eq!(state(gpu, &other, Some(&dir)), PipelineCacheState::Hit);

    // The module's own file is still its own.
    assert_eq!(state(gpu, &compiled, Some(&dir)), PipelineCacheState::Hit);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[gpu_test]
fn an_unwritable_directory_is_a_warning() {
    let gpu = tests::gpu();
    let dir = temp_dir("unwritable");
    std::fs::create_dir_all(&dir).unwrap();
    // A file where the directory should be.
    let blocked = dir.join("blocked");
    std::fs::write(&blocked, b"a file").unwrap();
    let problem = quadrature_problem(16);
    let compiled = compile(gpu, &problem);
    let state = state(gpu, &compiled, Some(&blocked));
    assert!(
        matches!(
            state,
            PipelineCacheState::Miss
                | PipelineCacheState::Rejected(_)
                | PipelineCacheState::Unsupported
        ),
        "{state:?}"
    );
    let checked = quadrature::run(gpu, &problem, &config(Some(&blocked))).unwrap();
    assert!(checked.mismatches.is_empty(), "{:?}", checked.mismatches);
    std::fs::remove_dir_all(&dir).unwrap();
}
