//! Megakernel vs. Rounds (kernel-by-kernel), under both queue policies, on
//! the synthetic spawn tree and on Reyes frames of the teapot and the
//! Killeroo.
//!
//! ```text
//! cargo run --release -p benches --bin strategy-bench -- [--items-log2 20] [--runs 5] [--no-reyes]
//! ```
//!
//! Prints one table measured in this one process. Per row, both strategies
//! run the same compiled graph, alternating run by run; the speedup is rounds
//! time over megakernel time (above 1: the megakernel is faster). Every
//! spawn-tree run is checked against the CPU reference; Reyes frames of both
//! strategies are compared pixel by pixel.

use std::process::ExitCode;

use benches::strategies::{
    StrategyRow, format_strategy_row, format_strategy_table, measure_spawn_tree,
};
use benches::workload::{FIXED_WORK, MAX_ITEMS_LOG2, Workload};
use clap::Parser;
use scheduler::{DeviceRequest, Gpu, Policy};

#[derive(Debug, Parser)]
#[command(about = "Megakernel vs. Rounds under both policies")]
struct Args {
    /// log2 of the number of spawn-tree items.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_ITEMS_LOG2)))]
    items_log2: u32,
    /// Timed runs per strategy (median reported), after one verified warm-up.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(3..))]
    runs: u32,
    /// Persistent workgroups (default: the scheduler's default).
    #[arg(long)]
    workgroups: Option<u32>,
    /// Only the spawn tree.
    #[arg(long)]
    no_reyes: bool,
}

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("strategy-bench: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let command_line = std::env::args().collect::<Vec<_>>().join(" ");
    let gpu = Gpu::new(&DeviceRequest::default())?;
    println!("command: {command_line}");
    println!("adapter: {}", gpu.describe());
    let mut rows: Vec<StrategyRow> = Vec::new();
    for work in [FIXED_WORK, 0] {
        let workload = Workload::new(args.items_log2, work)?;
        for policy in [Policy::Priority, Policy::RoundRobin] {
            let row = measure_spawn_tree(&gpu, workload, policy, args.workgroups, args.runs)?;
            eprintln!("  {}", format_strategy_row(&row));
            rows.push(row);
        }
    }
    if !args.no_reyes {
        drop(gpu);
        for row in benches::reyes_strategies::measure_frames(args.runs)? {
            eprintln!("  {}", format_strategy_row(&row));
            rows.push(row);
        }
    }
    println!();
    print!("{}", format_strategy_table(&rows));
    println!(
        "speedup = rounds ms / megakernel ms (above 1: the megakernel is faster); times are GPU \
         timestamps summed over submissions, median of {} runs; high-water = sum over procedures \
         of the most items each queue held at once (MK megakernel, R rounds); rounds = rounds \
         that found work",
        args.runs
    );
    Ok(())
}
