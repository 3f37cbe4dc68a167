//! Adaptive Simpson quadrature ([`workloads::quadrature`]) on a random
//! problem, checked exactly against the CPU reference.
//!
//! Run with `cargo run --release -p scheduler --example quadrature [seed]
//! [threshold]`.

use std::error::Error;

use scheduler::{ExecutorConfig, Gpu};
use workloads::quadrature::{Problem, run};

fn main() -> Result<(), Box<dyn Error>> {
    let arg = |i: usize, default: u64| -> Result<u64, Box<dyn Error>> {
        Ok(std::env::args()
            .nth(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let seed = arg(1, 7)?;
    let threshold = u32::try_from(arg(2, 16)?)?;
    let gpu = Gpu::new(&Default::default())?;
    println!("device: {}", gpu.describe());
    let problem = Problem::random(seed, 100, threshold);
    let checked = run(&gpu, &problem, &ExecutorConfig::default())?;
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
