//! Renders the Mandelbrot set by Mariani–Silver subdivision
//! ([`workloads::mandelbrot`]) and checks every pixel against the CPU, under
//! the multiply-adds the driver fused (the summary names them).
//!
//! Run with `cargo run --release -p scheduler --example mandelbrot [size]
//! [max_iter] [out.ppm]`: it prints the report, the check and an ASCII
//! preview, and writes the image as a binary PPM when given a path.

use std::error::Error;

use scheduler::Gpu;
use workloads::mandelbrot::{View, ascii_preview, config, ppm, run};

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let size = args.next().map(|s| s.parse()).transpose()?.unwrap_or(512);
    let max_iter = args.next().map(|s| s.parse()).transpose()?.unwrap_or(256);
    let output = args.next();
    let gpu = Gpu::new(&Default::default())?;
    println!("device: {}", gpu.describe());
    let view = View::whole_set(size, max_iter);
    let checked = run(&gpu, &view, &config(&gpu, &view, 1))?;
    println!("{}", checked.report);
    print!("{}", checked.summary);
    print!("{}", ascii_preview(&view, &checked.counts, 72));
    if let Some(path) = output {
        std::fs::write(&path, ppm(&view, &checked.counts))?;
        println!("wrote {path}");
    }
    if checked.mismatches.is_empty() {
        match checked.contraction {
            Some(fused) if !fused.is_plain() => {
                println!(
                    "OK: every pixel equals the CPU's, computed with the same fused multiply-adds"
                );
            }
            _ => println!("OK: every pixel equals the CPU's"),
        }
        Ok(())
    } else {
        for m in &checked.mismatches {
            eprintln!("MISMATCH: {m}");
        }
        std::process::exit(1);
    }
}
