//! `joins-bench`: the tree sum with joins (one run: built top-down, summed
//! bottom-up by the joins' continuations) against the same work as separate
//! runs without joins (one run builds the tree, then one run per level sums
//! it from the deepest level up), under both strategies. Every run's sums
//! are checked against the CPU.
//!
//! ```text
//! cargo run --release -p benches --bin joins-bench -- [--depth 30] [--fan 16]
//!     [--bush-levels 3] [--runs 5] [--workgroups N]
//! ```

use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use scheduler::{Capacities, DeviceRequest, ExecutorConfig, Gpu, Strategy};
use workloads::tree_sum::{self, TreeParams, TwoPass};

#[derive(Debug, Parser)]
#[command(about = "Joins: the tree sum in one run against a top-down run and a run per level")]
struct Args {
    /// Depth of the tree's spine.
    #[arg(long, default_value_t = 30)]
    depth: u32,
    /// The most children per node (1 to 16).
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u32).range(1..=16))]
    fan: u32,
    /// Levels below the spine at which bushes end.
    #[arg(long, default_value_t = 3)]
    bush_levels: u32,
    /// The root's key.
    #[arg(long, default_value_t = 0x1234_5678)]
    root_key: u32,
    /// Timed runs per variant, after one warm-up run.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    runs: u32,
    /// Persistent workgroups (default: the adapter's).
    #[arg(long)]
    workgroups: Option<u32>,
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("joins-bench: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn median(mut times: Vec<Duration>) -> f64 {
    times.sort();
    times[times.len() / 2].as_secs_f64() * 1e3
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    let gpu = Gpu::new(&DeviceRequest::default())?;
    println!("command: {command_line}");
    println!("adapter: {}", gpu.describe());
    let params = TreeParams {
        depth: args.depth,
        fan: args.fan,
        bush_levels: args.bush_levels,
        root_key: args.root_key,
    };
    let totals = tree_sum::cpu_reference(&params);
    println!(
        "tree: depth {}, fan-out up to {}, bushes of {} levels: {} nodes, {} inner",
        totals.depth, params.fan, params.bush_levels, totals.nodes, totals.inner
    );
    let config = ExecutorConfig {
        workgroups: args.workgroups,
        capacities: Capacities::uniform(totals.nodes.next_power_of_two() as u32)
            .with_join_pool(totals.inner.next_power_of_two() as u32),
        timeout: Duration::from_secs(120),
        ..ExecutorConfig::default()
    };
    let (mut joined, tree) = tree_sum::executor(&gpu, &tree_sum::options(&gpu), &config, None)?;
    let mut two_pass = TwoPass::new(&gpu, &config)?;
    println!(
        "{:<10}{:<22}{:>6}{:>12}{:>12}",
        "variant", "strategy", "runs", "gpu ms", "wall ms"
    );
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        let (mut gpu_times, mut walls, mut runs) = (Vec::new(), Vec::new(), 0);
        for attempt in 0..=args.runs {
            let checked = tree_sum::run(&mut joined, &tree, &params, strategy, 1)?;
            if !checked.mismatches.is_empty() {
                return Err(format!("joins, {strategy}: {:?}", checked.mismatches).into());
            }
            if attempt > 0 {
                gpu_times.push(checked.report.gpu_time.unwrap_or_default());
                walls.push(checked.report.wall_time);
                runs = 1;
            }
        }
        println!(
            "{:<10}{:<22}{:>6}{:>12.3}{:>12.3}",
            "joins",
            strategy.to_string(),
            runs,
            median(gpu_times),
            median(walls)
        );
        let (mut gpu_times, mut walls, mut runs) = (Vec::new(), Vec::new(), 0);
        for attempt in 0..=args.runs {
            let result = two_pass.run(&gpu, &params, strategy)?;
            if !result.mismatches.is_empty() {
                return Err(format!("two runs, {strategy}: {:?}", result.mismatches).into());
            }
            if attempt > 0 {
                gpu_times.push(result.gpu_time.unwrap_or_default());
                walls.push(result.wall_time);
                runs = result.runs;
            }
        }
        println!(
            "{:<10}{:<22}{:>6}{:>12.3}{:>12.3}",
            "two-pass",
            strategy.to_string(),
            runs,
            median(gpu_times),
            median(walls)
        );
    }
    Ok(())
}
