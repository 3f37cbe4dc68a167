//! Draws the queue fills of Chrome trace files as PNG charts.
//!
//! ```text
//! cargo run --release -p benches --bin trace-plot -- \
//!     TRACE.json OUT.png [--title TEXT] [--width 1200] [--height 500]
//! ```
//!
//! The traces come from `scheduler-bench --trace` or `reyes render --trace`
//! (docs/scheduler.md, "Seeing a run"): one line per queue, its fill (items
//! reserved and not yet claimed) over the logical clock.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

#[derive(Debug, Parser)]
#[command(about = "Draws the queue fills of a Chrome trace as a PNG chart")]
struct Args {
    /// The Chrome trace (Trace Event Format JSON).
    trace: PathBuf,
    /// The PNG to write.
    output: PathBuf,
    /// The chart's title (default: the trace's graph name).
    #[arg(long)]
    title: Option<String>,
    /// Width in pixels.
    #[arg(long, default_value_t = 1200)]
    width: u32,
    /// Height in pixels.
    #[arg(long, default_value_t = 500)]
    height: u32,
}

fn main() -> ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("trace-plot: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let trace: serde_json::Value = serde_json::from_slice(&std::fs::read(&args.trace)?)?;
    let series = benches::trace::fill_series(&trace);
    if series.is_empty() {
        return Err(format!("{} has no queue fill counters", args.trace.display()).into());
    }
    let title = args.title.clone().unwrap_or_else(|| {
        let graph = trace["otherData"]["graph"].as_str().unwrap_or("trace");
        format!("{graph}: queue fill")
    });
    benches::trace::plot_fills(&series, &title, &args.output, (args.width, args.height))?;
    println!("{} written", args.output.display());
    Ok(())
}
