//! Breadth-first search levels ([`workloads::bfs`]) on a random graph with
//! three sources, checked exactly against a CPU BFS.
//!
//! Run with `cargo run --release -p scheduler --example bfs [seed] [nodes]`.

use std::error::Error;

use scheduler::{ExecutorConfig, Gpu};
use workloads::bfs::{Problem, capacities, run};

fn main() -> Result<(), Box<dyn Error>> {
    let arg = |i: usize, default: u64| -> Result<u64, Box<dyn Error>> {
        Ok(std::env::args()
            .nth(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let seed = arg(1, 7)?;
    let nodes = u32::try_from(arg(2, 20_000)?)?;
    let gpu = Gpu::new(&Default::default())?;
    println!("device: {}", gpu.describe());
    let problem = Problem::random(seed, nodes, 3);
    let config = ExecutorConfig {
        capacities: capacities(&problem),
        ..Default::default()
    };
    let checked = run(&gpu, &problem, &config)?;
    println!("{}", checked.report);
    print!("{}", checked.summary);
    if checked.mismatches.is_empty() {
        println!("OK");
        Ok(())
    } else {
        for m in &checked.mismatches {
            eprintln!("MISMATCH: {m}");
        }
        std::process::exit(1);
    }
}
