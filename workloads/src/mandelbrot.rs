//! The Mandelbrot set by Mariani–Silver subdivision, as a scheduler workload
//! with two procedures of different widths:
//!
//! * `Tile` (32 threads per item) computes the escape counts of a square's
//!   border, the threads sharing its pixels, and agrees on their minimum and
//!   maximum through workgroup scratch. If the whole border has one count, it
//!   fills the square with it; otherwise it splits the square into four
//!   `Tile`s, or, at [`MIN_SIZE`], hands it to `Block`;
//! * `Block` (64 threads per item, one per pixel) computes every pixel of an
//!   8×8 square.
//!
//! Every pixel is written by exactly one item: a filled tile writes its whole
//! square, a split tile writes nothing (its children cover it), a block
//! writes its 64 pixels.
//!
//! Exactness. The escape-time iteration is `f32` arithmetic, written in
//! the same order on both sides, and the GPU's counts are compared exactly:
//! a scheduling bug (an item lost, run twice or read half-written) shows as
//! a few wrong pixels, which a tolerance would hide. The update is written
//! `(zr - zi) * (zr + zi) + cr` rather than `zr * zr - zi * zi + cr`, which
//! lavapipe reassociates. What WGSL cannot forbid is contraction: SPIR-V
//! lets a driver fuse a multiply and the add after it into one multiply-add
//! with a single rounding, and NVIDIA's driver does (an H200's flat
//! dispatch of the 512×512 benchmark image differed from the plain CPU in
//! 532 pixels, first at (366, 98) with 330 for 349, as a CPU fusing both
//! updates does), while the CPU never fuses unless asked. So the counts are compared with the
//! CPU under the [`Contraction`] that explains them: the plain arithmetic
//! first, then, only if that differs, each way of fusing the loop's four
//! multiply-add sites ([`escape_count_with`], with `f32::mul_add`), tried on
//! the differing pixels and then verified on all of them
//! ([`match_brute_force`], [`match_subdivision`]). The subdivision's
//! decisions depend on the counts, so a fused CPU Mariani–Silver
//! ([`cpu_mariani_silver_with`]) is recomputed under the contraction, and
//! the scheduler's counters are compared with its tile counts. A run that
//! no contraction explains is wrong, and its error lists the disagreements
//! with the plain reference. Each shader is matched on its own (the flat
//! kernel and the scheduler's module may be fused differently). The views
//! keep the pixel coordinates exact: [`View::whole_set`] steps by
//! `3 / size` with `size` a power of two, so fusing them changes nothing.
//! Mariani–Silver itself can differ from computing every pixel (brute
//! force, [`cpu_brute_force`]) where a border of one count encloses a
//! feature of another; [`Checked::differ_from_brute_force`] counts those
//! pixels.
//!
//! The parts live in their own files: the per-pixel and per-tile CPU
//! references ([`cpu_mariani_silver`]), the contractions ([`Contraction`])
//! and the matchers ([`match_subdivision`]), the WGSL bodies
//! ([`TILE_BODY`]), the graph and its executor configuration ([`graph`],
//! [`config`]), a checked GPU render ([`run`]) and the pictures ([`ppm`]).
//! The example `scheduler/examples/mandelbrot.rs` runs it from the command
//! line.

mod contraction;
mod cpu;
mod graph;
mod image;
mod matching;
mod render;
mod wgsl;

use scheduler::ConstantValue;
#[cfg(doc)]
use scheduler::Graph;

pub use contraction::{Contraction, Magnitude};
pub use cpu::{
    Decision, Subdivision, border_pixel, cpu_brute_force, cpu_brute_force_with, cpu_mariani_silver,
    cpu_mariani_silver_with, decide, decide_with, escape_count, escape_count_with, quarters,
};
pub use graph::{
    MandelbrotGraph, capacities, config, graph, loop_iterations_per_chunk,
    loop_safe_iteration_budget,
};
pub use image::{ascii_preview, colour, ppm};
pub use matching::{Matched, Unexplained, match_brute_force, match_subdivision, pixel_mismatches};
pub use render::{Checked, Mandelbrot, run};
pub use wgsl::{BLOCK_BODY, BORDER_WGSL, ESCAPE_WGSL, TILE_BODY};

/// Side of the root tiles the host seeds.
pub const ROOT_SIZE: u32 = 64;
/// Side of the squares `Tile` hands to `Block` instead of splitting them.
pub const MIN_SIZE: u32 = 8;
/// Threads per `Tile` item: they share the border's `4 (size - 1)` pixels.
pub const TILE_THREADS: u32 = 32;
/// Threads per `Block` item: one per pixel.
pub const BLOCK_THREADS: u32 = MIN_SIZE * MIN_SIZE;
/// Value of a pixel no item wrote (the output is filled with it before a run).
pub const UNWRITTEN: u32 = u32::MAX;

/// A square `[x, x + size) × [y, y + size)` of pixels.
#[scheduler::item]
#[derive(Debug, PartialEq, Eq)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct\'s doc describes the fields"
)]
pub struct Tile {
    pub x: u32,
    pub y: u32,
    pub size: u32,
}

/// A `MIN_SIZE × MIN_SIZE` square at `(x, y)`, computed pixel by pixel.
#[scheduler::item]
#[derive(Debug, PartialEq, Eq)]
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct\'s doc describes the fields"
)]
pub struct Block {
    pub x: u32,
    pub y: u32,
}

/// What to render: pixel `(px, py)` is the point `c = (x0 + px step, y0 +
/// py step)`, iterated at most `max_iter` times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Most iterations per pixel; a pixel that reaches it is in the set.
    pub max_iter: u32,
    /// Real part of pixel `(0, 0)`.
    pub x0: f32,
    /// Imaginary part of pixel `(0, 0)`.
    pub y0: f32,
    /// Distance between neighbouring pixels in the complex plane.
    pub step: f32,
}

impl View {
    /// The whole set, `[-2.25, 0.75] × [-1.5, 1.5]`, on a `size × size` grid.
    /// With `size` a power of two the step `3 / size` and every coordinate are
    /// exact `f32`s, so no rounding (or fused multiply-add) can move a pixel.
    pub fn whole_set(size: u32, max_iter: u32) -> Self {
        assert!(
            size.is_power_of_two() && size >= ROOT_SIZE,
            "size {size} must be a power of two of at least {ROOT_SIZE}"
        );
        Self {
            width: size,
            height: size,
            max_iter,
            x0: -2.25,
            y0: -1.5,
            step: 3.0 / size as f32,
        }
    }

    /// Pixels in the image.
    pub fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// The root tiles, row by row.
    pub fn roots(&self) -> Vec<Tile> {
        assert!(
            self.width.is_multiple_of(ROOT_SIZE) && self.height.is_multiple_of(ROOT_SIZE),
            "the image must be a whole number of {ROOT_SIZE}-pixel root tiles"
        );
        (0..self.height / ROOT_SIZE)
            .flat_map(|ty| {
                (0..self.width / ROOT_SIZE).map(move |tx| Tile {
                    x: tx * ROOT_SIZE,
                    y: ty * ROOT_SIZE,
                    size: ROOT_SIZE,
                })
            })
            .collect()
    }

    /// The constants the WGSL uses, for [`Graph::constant`] (and for any
    /// other module that includes [`ESCAPE_WGSL`]).
    pub fn constants(&self) -> Vec<(&'static str, ConstantValue)> {
        vec![
            ("WIDTH", self.width.into()),
            ("MAX_ITER", self.max_iter.into()),
            ("X0", self.x0.into()),
            ("Y0", self.y0.into()),
            ("STEP", self.step.into()),
            ("MIN_SIZE", MIN_SIZE.into()),
            ("TILE_THREADS", TILE_THREADS.into()),
        ]
    }
}
