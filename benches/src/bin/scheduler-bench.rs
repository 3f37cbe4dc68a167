//! Megakernel vs. flat dispatch on a synthetic binary spawn tree.
//!
//! ```text
//! cargo run --release -p benches --bin scheduler-bench -- \
//!     [--items-log2 20] [--runs 7] [--workgroups N ...] [--chunks N ...] \
//!     [--rounds-workgroups N ...] [--capacity N] \
//!     [--mandelbrot-size 512] [--mandelbrot-max-iter 1024] [--json FILE] \
//!     [--trace FILE [--trace-rounds] [--trace-capacity N]]
//! ```
//!
//! With `--trace FILE` it measures nothing: it runs the Mandelbrot example
//! once, traced and verified (the first `--chunks`, the default workgroup
//! count, the megakernel or with `--trace-rounds` the Rounds strategy), and
//! writes the run's Chrome trace to FILE (docs/scheduler.md, "Seeing a run"),
//! then prints what tracing costs: `--runs` untraced and traced megakernel
//! runs side by side.
//!
//! Prints two tables measured in this one process. The spawn tree: for work
//! 64 and work 0, the flat dispatch, the megakernel at the default
//! workgroup count plus any `--workgroups` given, and the Rounds strategy at
//! each `--rounds-workgroups`. The Mandelbrot set by
//! Mariani–Silver subdivision (`scheduler/examples/mandelbrot.rs`): a flat
//! per-pixel dispatch, the megakernel at the same workgroup counts and the
//! Rounds strategy, for each `--chunks`. Every variant is verified against a
//! CPU reference; a mismatch exits with an error.

use std::path::PathBuf;
use std::process::ExitCode;

use benches::mandelbrot::{
    MandelbrotConfig, format_mandelbrot_header, format_mandelbrot_row, format_mandelbrot_table,
    run_mandelbrot,
};
use benches::suite::{BenchConfig, recommended_iteration_budget, run_suite};
use benches::table::{format_row, format_table};
use benches::workload::{FIXED_WORK, MAX_ITEMS_LOG2};
use clap::Parser;
use scheduler::{DEFAULT_WORKGROUPS, DeviceRequest, Gpu, Strategy, TraceOptions};

#[derive(Debug, Parser)]
#[command(
    about = "Megakernel vs. flat dispatch on a synthetic binary spawn tree and on the Mandelbrot set"
)]
struct Args {
    /// log2 of the number of items (tree nodes).
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_ITEMS_LOG2)))]
    items_log2: u32,
    /// Timed runs per variant (median reported), after one verified warm-up.
    #[arg(long, default_value_t = 7, value_parser = clap::value_parser!(u32).range(5..))]
    runs: u32,
    /// Extra megakernel workgroup counts (the default count is always measured).
    #[arg(long, num_args = 1..)]
    workgroups: Vec<u32>,
    /// Megakernel iteration budgets, one row each; 0 = none (persistent until
    /// done). Default: 256 on llvmpipe (its shader loop cap, see
    /// `benches::suite::recommended_iteration_budget`), none elsewhere.
    #[arg(long, num_args = 1..)]
    iteration_budget: Vec<u32>,
    /// Chunks per batch to compile the megakernel with, one row each
    /// (`scheduler::CompileOptions::chunks_per_batch`).
    #[arg(long, num_args = 1.., default_values_t = [1, 4])]
    chunks: Vec<u32>,
    /// Most workgroups per round dispatch, one Rounds row each per `--chunks`.
    #[arg(long, num_args = 1.., default_values_t = [DEFAULT_WORKGROUPS])]
    rounds_workgroups: Vec<u32>,
    /// Megakernel queue capacity in items (default: the item count).
    #[arg(long)]
    capacity: Option<u32>,
    /// Side of the Mandelbrot image (a power of two, at least 64); 0 skips it.
    #[arg(long, default_value_t = 512)]
    mandelbrot_size: u32,
    /// Most iterations per Mandelbrot pixel.
    #[arg(long, default_value_t = 1024)]
    mandelbrot_max_iter: u32,
    /// Also write the results as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Instead of measuring, write the Chrome trace (Trace Event Format) of
    /// one traced Mandelbrot run to this file.
    #[arg(long)]
    trace: Option<PathBuf>,
    /// With `--trace`: trace the Rounds strategy instead of the megakernel.
    #[arg(long)]
    trace_rounds: bool,
    /// With `--trace`: records the trace buffer holds (the first batches).
    #[arg(long, default_value_t = TraceOptions::default().capacity)]
    trace_capacity: u32,
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scheduler-bench: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    let gpu = Gpu::new(&DeviceRequest::default())?;
    if let Some(path) = &args.trace {
        return write_trace(&gpu, args, path);
    }
    let mut workgroups = vec![DEFAULT_WORKGROUPS];
    for &w in &args.workgroups {
        if !workgroups.contains(&w) {
            workgroups.push(w);
        }
    }
    let adapter = gpu.describe();
    let iteration_budgets: Vec<Option<u32>> = if args.iteration_budget.is_empty() {
        vec![recommended_iteration_budget(&adapter)]
    } else {
        args.iteration_budget
            .iter()
            .map(|&b| (b > 0).then_some(b))
            .collect()
    };
    let config = BenchConfig {
        items_log2: args.items_log2,
        runs: args.runs,
        works: vec![FIXED_WORK, 0],
        workgroups,
        iteration_budgets,
        capacity: args.capacity,
        chunks: args.chunks.clone(),
        rounds_workgroups: args.rounds_workgroups.clone(),
    };
    println!("command: {command_line}");
    println!("adapter: {adapter}");
    println!(
        "workload: binary spawn tree, 2^{} = {} items of 32 bytes, root id 0, heap-numbered; \
         median of {} timed runs after a verified warm-up",
        args.items_log2,
        1u64 << args.items_log2,
        args.runs
    );
    eprintln!("measuring (each variant verified against the CPU reference)...");
    let report = run_suite(&gpu, &config, |row| eprintln!("  {}", format_row(row)))?;
    println!();
    print!("{}", format_table(&report));
    println!(
        "ratio = items/s of the row / items/s of the flat dispatch with the same work; \
         timer gpu-ts = timestamp queries around the compute pass(es), summed over dispatches; \
         wall ms = host submission..completion incl. round trips between dispatches"
    );
    println!(
        "high-water = most items the megakernel queue held at once (median run); \
         all variants verified: OK"
    );
    let mandelbrot = if args.mandelbrot_size == 0 {
        None
    } else {
        let config = MandelbrotConfig {
            size: args.mandelbrot_size,
            max_iter: args.mandelbrot_max_iter,
            runs: args.runs,
            workgroups: report.config.workgroups.clone(),
            chunks: args.chunks.clone(),
            rounds_workgroups: args.rounds_workgroups.clone(),
        };
        println!();
        println!(
            "workload: Mandelbrot set [-2.25, 0.75] x [-1.5, 1.5], {0}x{0} pixels, at most {1} \
             iterations; Mariani-Silver subdivision (scheduler/examples/mandelbrot.rs) vs. a \
             flat dispatch of the same per-pixel function; median of {2} timed runs after a \
             verified warm-up",
            config.size, config.max_iter, config.runs
        );
        eprintln!("measuring (each variant verified against the CPU reference)...");
        eprintln!("  {}", format_mandelbrot_header());
        let mandelbrot = run_mandelbrot(&gpu, &config, |row| {
            eprintln!("  {}", format_mandelbrot_row(row));
        })?;
        println!();
        print!("{}", format_mandelbrot_table(&mandelbrot));
        println!(
            "ratio = flat median / row median (above 1: faster than the flat dispatch); \
             escape px = pixels whose escape count was iterated, iterations = their counts \
             summed; {} pixel(s) where Mariani-Silver differs from brute force (plain \
             arithmetic); all variants verified: OK",
            mandelbrot.differ_from_brute_force
        );
        Some(mandelbrot)
    };
    if let Some(path) = &args.json {
        let json = serde_json::json!({
            "command": command_line,
            "report": report,
            "mandelbrot": mandelbrot,
        });
        std::fs::write(path, serde_json::to_string_pretty(&json)?)?;
        println!("JSON written to {}", path.display());
    }
    Ok(())
}

/// `--trace`: one traced, verified Mandelbrot run, written as a Chrome trace.
fn write_trace(
    gpu: &Gpu,
    args: &Args,
    path: &std::path::Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let strategy = if args.trace_rounds {
        Strategy::rounds()
    } else {
        Strategy::Megakernel
    };
    let chunks = args.chunks.first().copied().unwrap_or(1);
    let size = if args.mandelbrot_size == 0 {
        512
    } else {
        args.mandelbrot_size
    };
    let (report, contraction) = benches::trace::mandelbrot(
        gpu,
        size,
        args.mandelbrot_max_iter,
        chunks,
        strategy,
        TraceOptions {
            capacity: args.trace_capacity,
        },
    )?;
    let trace = report.trace().ok_or("the traced run returned no trace")?;
    trace.write_chrome_trace(path)?;
    println!("adapter: {}", gpu.describe());
    println!("{report}");
    if !contraction.is_plain() {
        println!("the driver fused: {contraction}; verified against the CPU fusing the same");
    }
    println!(
        "trace: Mandelbrot {size}x{size}, {chunks} chunk(s) per batch: {} batches, {} recorded, \
         {} dropped; Chrome trace written to {}",
        trace.batches,
        trace.records.len(),
        trace.dropped(),
        path.display()
    );
    let (untraced, traced) =
        benches::trace::mandelbrot_cost(gpu, size, args.mandelbrot_max_iter, chunks, args.runs)?;
    println!(
        "tracing cost (megakernel, median of {} runs each, interleaved): untraced {untraced:.1} ms, \
         traced {traced:.1} ms, ratio {:.2}",
        args.runs,
        traced / untraced.max(1e-9)
    );
    Ok(())
}
