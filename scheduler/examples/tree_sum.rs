//! The tree sum with joins ([`workloads::tree_sum`]): a random tree built
//! top-down and summed bottom-up in one run, checked node by node against
//! the CPU, under both strategies.
//!
//! Run with `cargo run --release -p scheduler --example tree_sum [depth]
//! [fan-out] [bush levels]`.

use std::error::Error;

use scheduler::{ExecutorConfig, Gpu, Strategy};
use workloads::tree_sum::{self, TreeParams};

fn main() -> Result<(), Box<dyn Error>> {
    let arg = |i: usize, default: u32| -> Result<u32, Box<dyn Error>> {
        Ok(std::env::args()
            .nth(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let params = TreeParams {
        depth: arg(1, 30)?,
        fan: arg(2, 16)?.clamp(1, tree_sum::MAX_FAN),
        bush_levels: arg(3, tree_sum::BUSH_LEVELS)?,
        root_key: 0x1234_5678,
    };
    let gpu = Gpu::new(&Default::default())?;
    println!("device: {}", gpu.describe());
    let (mut executor, tree) = tree_sum::executor(
        &gpu,
        &tree_sum::options(&gpu),
        &ExecutorConfig::default(),
        None,
    )?;
    let mut failed = false;
    for strategy in [Strategy::Megakernel, Strategy::rounds()] {
        // Up to two attempts: a pool too small for the tree grows once.
        let checked = tree_sum::run(&mut executor, &tree, &params, strategy, 2)?;
        println!("{}", checked.report);
        print!("{}", checked.summary);
        for m in &checked.mismatches {
            eprintln!("MISMATCH: {m}");
        }
        failed |= !checked.mismatches.is_empty();
    }
    if failed {
        std::process::exit(1);
    }
    println!("OK");
    Ok(())
}
