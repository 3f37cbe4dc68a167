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
//! Exactness. The escape-time iteration is plain `f32` arithmetic, written in
//! the same order on both sides, so the GPU's counts are compared with a CPU
//! Mariani–Silver that takes the same decisions ([`cpu_mariani_silver`]),
//! pixel for pixel, and the scheduler's counters with its tile counts. The
//! update is written `(zr - zi) * (zr + zi) + cr` rather than
//! `zr * zr - zi * zi + cr`, which lavapipe reassociates. The views keep the
//! pixel coordinates exact: [`View::whole_set`] steps by `3 / size` with
//! `size` a power of two. Mariani–Silver itself can differ from computing
//! every pixel (brute force, [`cpu_brute_force`]) where a border of one count
//! encloses a feature of another; [`Checked::differ_from_brute_force`] counts
//! those pixels.
//!
//! Run with `cargo run --release -p scheduler --example mandelbrot [size]
//! [max_iter] [out.ppm]`: it prints the report, the check and an ASCII
//! preview, and writes the image as a binary PPM when given a path.

use std::error::Error;
use std::fmt::Write as _;

use scheduler::{
    Capacities, CompileOptions, CompiledGraph, ConstantValue, Executor, ExecutorConfig, Gpu, Graph,
    LoopBudget, Procedure, ProcedureId, Quirks, Resource, RunError, RunReport, Seeds, Strategy,
};

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
pub struct Tile {
    pub x: u32,
    pub y: u32,
    pub size: u32,
}

/// A `MIN_SIZE × MIN_SIZE` square at `(x, y)`, computed pixel by pixel.
#[scheduler::item]
#[derive(Debug, PartialEq, Eq)]
pub struct Block {
    pub x: u32,
    pub y: u32,
}

/// What to render: pixel `(px, py)` is the point `c = (x0 + px step, y0 +
/// py step)`, iterated at most `max_iter` times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    pub width: u32,
    pub height: u32,
    pub max_iter: u32,
    pub x0: f32,
    pub y0: f32,
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

/// The escape count of pixel `(px, py)`: the iterations until `|z| > 2`, at
/// most `max_iter` (the points taken to be in the set). Mirrored by
/// `escape_count` in [`ESCAPE_WGSL`], operation for operation.
pub fn escape_count(view: &View, px: u32, py: u32) -> u32 {
    let cr = view.x0 + px as f32 * view.step;
    let ci = view.y0 + py as f32 * view.step;
    let (mut zr, mut zi) = (0.0f32, 0.0f32);
    let mut n = 0;
    while n < view.max_iter && zr * zr + zi * zi <= 4.0 {
        let next = (zr - zi) * (zr + zi) + cr;
        zi = 2.0 * zr * zi + ci;
        zr = next;
        n += 1;
    }
    n
}

/// The `i`-th pixel of `tile`'s border, clockwise from its top-left corner,
/// for `i < 4 (size - 1)`. Mirrored by `border_pixel` in [`BORDER_WGSL`].
pub fn border_pixel(tile: &Tile, i: u32) -> (u32, u32) {
    let e = tile.size - 1;
    let k = i % e;
    let (dx, dy) = match i / e {
        0 => (k, 0),
        1 => (e, k),
        2 => (e - k, e),
        _ => (0, e - k),
    };
    (tile.x + dx, tile.y + dy)
}

/// The per-pixel function, shared by both procedures (and by the flat
/// dispatch the benchmark compares with).
pub const ESCAPE_WGSL: &str = "
fn escape_count(px: u32, py: u32) -> u32 {
    let cr = X0 + f32(px) * STEP;
    let ci = Y0 + f32(py) * STEP;
    var zr = 0.0f;
    var zi = 0.0f;
    var n = 0u;
    while (n < MAX_ITER && zr * zr + zi * zi <= 4.0f) {
        // Not zr * zr - zi * zi + cr, which lavapipe reassociates.
        let next = (zr - zi) * (zr + zi) + cr;
        zi = 2.0f * zr * zi + ci;
        zr = next;
        n += 1u;
    }
    return n;
}
";

/// The border walk of `Tile`.
pub const BORDER_WGSL: &str = "
// The i-th pixel of the tile's border, clockwise from its top-left corner.
fn border_pixel(tile: Tile, i: u32) -> vec2<u32> {
    let e = tile.size - 1u;
    let k = i % e;
    var d: vec2<u32>;
    switch (i / e) {
        case 0u: { d = vec2<u32>(k, 0u); }
        case 1u: { d = vec2<u32>(e, k); }
        case 2u: { d = vec2<u32>(e - k, e); }
        default: { d = vec2<u32>(0u, e - k); }
    }
    return vec2<u32>(tile.x, tile.y) + d;
}
";

/// The body of `Tile`. Scratch holds each thread's (min, max) over its share
/// of the border; after the barrier (at the top level, reached by every
/// thread) all threads of the item read all of them, so they agree on the
/// decision without a second barrier.
pub const TILE_BODY: &str = "
var lo = 0xffffffffu;
var hi = 0u;
if (valid) {
    for (var i = thread; i < 4u * (item.size - 1u); i += TILE_THREADS) {
        let p = border_pixel(item, i);
        let n = escape_count(p.x, p.y);
        lo = min(lo, n);
        hi = max(hi, n);
    }
    scratch_store_u32(slot, 2u * thread, lo);
    scratch_store_u32(slot, 2u * thread + 1u, hi);
}
workgroupBarrier();
if (valid) {
    for (var t = 0u; t < TILE_THREADS; t += 1u) {
        lo = min(lo, scratch_load_u32(slot, 2u * t));
        hi = max(hi, scratch_load_u32(slot, 2u * t + 1u));
    }
    if (lo == hi) {
        // One count all around: fill the square with it.
        for (var i = thread; i < item.size * item.size; i += TILE_THREADS) {
            counts[(item.y + i / item.size) * WIDTH + item.x + i % item.size] = lo;
        }
    } else if (item.size > MIN_SIZE) {
        // Split in four, one child per thread.
        if (thread < 4u) {
            let half = item.size / 2u;
            enqueue_Tile(Tile(item.x + half * (thread & 1u), item.y + half * (thread >> 1u), half));
        }
    } else if (thread == 0u) {
        enqueue_Block(Block(item.x, item.y));
    }
}
";

/// The body of `Block`: one pixel per thread.
pub const BLOCK_BODY: &str = "
if (valid) {
    let x = item.x + thread % MIN_SIZE;
    let y = item.y + thread / MIN_SIZE;
    counts[y * WIDTH + x] = escape_count(x, y);
}
";

/// The graph of [`graph`], with the handles of its procedures.
#[derive(Debug)]
pub struct MandelbrotGraph {
    pub graph: Graph,
    pub tile: ProcedureId<Tile>,
    pub block: ProcedureId<Block>,
}

/// The two-procedure graph. `Block` has the higher priority, so finished
/// squares leave the queues first.
pub fn graph(view: &View) -> MandelbrotGraph {
    let mut graph = Graph::new("mandelbrot (Mariani-Silver)");
    for (name, value) in view.constants() {
        graph.constant(name, value);
    }
    graph.library(ESCAPE_WGSL).library(BORDER_WGSL);
    graph.resource(Resource::storage::<[u32]>("counts").min_len(view.pixels() as u64));
    let tile = graph.procedure(
        Procedure::of::<Tile>("Tile")
            .initial(true)
            .threads_per_item(TILE_THREADS)
            .scratch_bytes(2 * 4 * TILE_THREADS)
            .body(TILE_BODY),
    );
    let block = graph.procedure(
        Procedure::of::<Block>("Block")
            .threads_per_item(BLOCK_THREADS)
            .priority(1)
            .body(BLOCK_BODY),
    );
    graph.connect_with_fan_out(&tile, &tile, 4);
    graph.connect(&tile, &block);
    MandelbrotGraph { graph, tile, block }
}

/// Queue capacities no run can exceed: every tile of every size, and every
/// block, at once.
pub fn capacities(view: &View) -> Capacities {
    let squares = |side: u32| (view.width / side) * (view.height / side);
    let mut tiles = 0;
    let mut side = ROOT_SIZE;
    while side >= MIN_SIZE {
        tiles += squares(side);
        side /= 2;
    }
    Capacities::default()
        .with("Tile", tiles)
        .with("Block", squares(MIN_SIZE))
}

/// The most loop iterations one thread runs in one chunk of a batch: a root
/// tile's share of the border (each pixel up to `max_iter + 1` turns), its
/// share of the fill and the reduction; or a block's one pixel.
pub fn loop_iterations_per_chunk(view: &View) -> u32 {
    let border = (4 * (ROOT_SIZE - 1)).div_ceil(TILE_THREADS) * (view.max_iter + 1);
    let tile = border + (ROOT_SIZE * ROOT_SIZE).div_ceil(TILE_THREADS) + TILE_THREADS;
    tile.max(view.max_iter + 1)
}

/// The iteration budget on a driver that caps loops (`budget`, llvmpipe:
/// every loop of an invocation ends once they ran 65,535 iterations
/// together, docs/scheduler.md "Loop limits"): a workgroup leaves after as
/// many batches as keep the bodies' loops within 60% of the driver's
/// budget, and never later than the scheduler's default would.
pub fn loop_safe_iteration_budget(view: &View, chunks_per_batch: u32, budget: &LoopBudget) -> u32 {
    (budget.driver_iterations / 5 * 3 / (loop_iterations_per_chunk(view) * chunks_per_batch.max(1)))
        .clamp(1, budget.batches)
}

/// The executor configuration for `chunks_per_batch`: [`capacities`], and
/// on drivers that cap loops [`loop_safe_iteration_budget`].
pub fn config(gpu: &Gpu, view: &View, chunks_per_batch: u32) -> ExecutorConfig {
    let quirks = Quirks::of(&gpu.adapter.get_info());
    ExecutorConfig {
        capacities: capacities(view),
        iteration_budget: quirks
            .loop_budget
            .map(|budget| loop_safe_iteration_budget(view, chunks_per_batch, &budget)),
        ..ExecutorConfig::default()
    }
}

/// What one tile does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Decision {
    /// Fill the square with this count.
    Fill(u32),
    /// Enqueue the four quarters.
    Split,
    /// Hand the square to `Block`.
    Block,
}

/// The decision for one tile, mirrored by [`TILE_BODY`].
pub fn decide(view: &View, tile: &Tile) -> Decision {
    let mut counts = (0..4 * (tile.size - 1)).map(|i| {
        let (x, y) = border_pixel(tile, i);
        escape_count(view, x, y)
    });
    let first = counts.next().expect("a tile has a border");
    let (lo, hi) = counts.fold((first, first), |(lo, hi), n| (lo.min(n), hi.max(n)));
    if lo == hi {
        Decision::Fill(lo)
    } else if tile.size > MIN_SIZE {
        Decision::Split
    } else {
        Decision::Block
    }
}

/// The quarters of a split tile.
pub fn quarters(tile: &Tile) -> [Tile; 4] {
    let half = tile.size / 2;
    [0, 1, 2, 3].map(|k| Tile {
        x: tile.x + half * (k & 1),
        y: tile.y + half * (k >> 1),
        size: half,
    })
}

/// The result of a Mariani–Silver subdivision, and what it took.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Subdivision {
    /// Escape count per pixel, row by row.
    pub counts: Vec<u32>,
    /// Tiles processed (the roots included).
    pub tiles: u64,
    /// Tiles filled from their border.
    pub filled: u64,
    /// Tiles split in four.
    pub split: u64,
    /// Tiles handed to `Block`.
    pub blocks: u64,
    /// Pixels whose escape count was iterated (borders and blocks; a pixel
    /// on several borders counts each time).
    pub escape_pixels: u64,
    /// Their escape counts summed: the iterations of the per-pixel loop.
    pub iterations: u64,
}

/// The CPU reference: the same subdivision, with the same decisions, on an
/// explicit stack.
pub fn cpu_mariani_silver(view: &View) -> Subdivision {
    let mut out = Subdivision {
        counts: vec![UNWRITTEN; view.pixels()],
        ..Subdivision::default()
    };
    let width = view.width as usize;
    let mut stack = view.roots();
    while let Some(tile) = stack.pop() {
        out.tiles += 1;
        out.escape_pixels += u64::from(4 * (tile.size - 1));
        out.iterations += (0..4 * (tile.size - 1))
            .map(|i| {
                let (x, y) = border_pixel(&tile, i);
                u64::from(escape_count(view, x, y))
            })
            .sum::<u64>();
        match decide(view, &tile) {
            Decision::Fill(n) => {
                for y in tile.y..tile.y + tile.size {
                    let row = y as usize * width;
                    out.counts[row + tile.x as usize..row + (tile.x + tile.size) as usize].fill(n);
                }
                out.filled += 1;
            }
            Decision::Split => {
                stack.extend(quarters(&tile));
                out.split += 1;
            }
            Decision::Block => {
                for y in tile.y..tile.y + MIN_SIZE {
                    for x in tile.x..tile.x + MIN_SIZE {
                        let n = escape_count(view, x, y);
                        out.counts[y as usize * width + x as usize] = n;
                        out.iterations += u64::from(n);
                    }
                }
                out.blocks += 1;
                out.escape_pixels += u64::from(BLOCK_THREADS);
            }
        }
    }
    out
}

/// Every pixel's escape count, computed directly.
pub fn cpu_brute_force(view: &View) -> Vec<u32> {
    (0..view.height)
        .flat_map(|y| (0..view.width).map(move |x| (x, y)))
        .map(|(x, y)| escape_count(view, x, y))
        .collect()
}

/// A compiled graph and an executor, which owns the output buffer, for
/// repeated runs.
#[derive(Debug)]
pub struct Mandelbrot {
    pub view: View,
    pub tile: ProcedureId<Tile>,
    pub block: ProcedureId<Block>,
    executor: Executor,
    seeds: Seeds,
}

impl Mandelbrot {
    /// Compiles the graph with `options` and creates the executor and buffers.
    pub fn new(
        gpu: &Gpu,
        view: View,
        options: &CompileOptions,
        config: &ExecutorConfig,
    ) -> Result<Self, Box<dyn Error>> {
        let MandelbrotGraph { graph, tile, block } = graph(&view);
        let compiled: CompiledGraph = graph.compile(options)?;
        let executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;
        let seeds = Seeds::new().add(&tile, &view.roots());
        Ok(Self {
            view,
            tile,
            block,
            executor,
            seeds,
        })
    }

    /// Fills the output with [`UNWRITTEN`] and renders the image once. The
    /// executor binds its own `counts` buffer, so the run names no binding.
    pub fn render(&mut self, strategy: Strategy) -> Result<RunReport, RunError> {
        let unwritten = vec![UNWRITTEN; self.view.pixels()];
        self.executor.write("counts", &unwritten)?;
        self.executor.run_with(strategy, &self.seeds, &[])
    }

    /// The escape counts of the last render, row by row.
    pub fn counts(&self) -> Result<Vec<u32>, RunError> {
        self.executor.read::<u32>("counts")
    }
}

/// A checked run: the report, the image and every disagreement with the CPU
/// (none when the run is correct).
#[derive(Debug)]
pub struct Checked {
    pub report: RunReport,
    pub counts: Vec<u32>,
    pub mismatches: Vec<String>,
    /// Pixels where Mariani–Silver (on the CPU) differs from brute force.
    pub differ_from_brute_force: usize,
    /// A human-readable summary of the result.
    pub summary: String,
}

impl Mandelbrot {
    /// Every disagreement of a render's counts and report with the CPU
    /// subdivision `cpu` (none when the render is correct).
    pub fn compare(&self, report: &RunReport, counts: &[u32], cpu: &Subdivision) -> Vec<String> {
        let view = &self.view;
        let mut mismatches = Vec::new();
        let wrong: Vec<usize> = (0..view.pixels())
            .filter(|&i| counts[i] != cpu.counts[i])
            .collect();
        if !wrong.is_empty() {
            let width = view.width as usize;
            let examples: Vec<String> = wrong
                .iter()
                .take(8)
                .map(|&i| {
                    format!(
                        "({}, {}): GPU {}, CPU {}",
                        i % width,
                        i / width,
                        counts[i],
                        cpu.counts[i]
                    )
                })
                .collect();
            mismatches.push(format!(
                "{} of {} pixels differ, e.g. {}",
                wrong.len(),
                view.pixels(),
                examples.join("; ")
            ));
        }
        let mut expect = |what: &str, gpu: Option<u64>, cpu: u64| {
            if gpu != Some(cpu) {
                mismatches.push(format!("{what}: GPU {gpu:?}, CPU {cpu}"));
            }
        };
        let tile = report.procedure(&self.tile);
        let block = report.procedure(&self.block);
        expect("Tile executed", tile.map(|s| s.executed), cpu.tiles);
        expect(
            "Tile enqueued (4 per split)",
            tile.map(|s| s.enqueued),
            4 * cpu.split,
        );
        expect("Block executed", block.map(|s| s.executed), cpu.blocks);
        expect("Block enqueued", block.map(|s| s.enqueued), cpu.blocks);
        mismatches
    }
}

/// Renders `view` once with the megakernel and checks it against the CPU.
pub fn run(gpu: &Gpu, view: &View, config: &ExecutorConfig) -> Result<Checked, Box<dyn Error>> {
    let options = CompileOptions::with_features(scheduler::recommended_features(&gpu.device));
    let mut mandelbrot = Mandelbrot::new(gpu, *view, &options, config)?;
    let report = mandelbrot.render(Strategy::Megakernel)?;
    let counts = mandelbrot.counts()?;

    let cpu = cpu_mariani_silver(view);
    let mismatches = mandelbrot.compare(&report, &counts, &cpu);
    let brute = cpu_brute_force(view);
    let differ_from_brute_force = (0..view.pixels())
        .filter(|&i| cpu.counts[i] != brute[i])
        .count();

    let mut summary = String::new();
    let inside = counts.iter().filter(|&&n| n == view.max_iter).count();
    writeln!(
        summary,
        "{}x{} pixels, at most {} iterations: {inside} pixels in the set",
        view.width, view.height, view.max_iter
    )?;
    writeln!(
        summary,
        "{} tiles: {} filled from their border, {} split, {} handed to blocks of {MIN_SIZE}x{MIN_SIZE}",
        cpu.tiles, cpu.filled, cpu.split, cpu.blocks
    )?;
    let brute_iterations: u64 = brute.iter().map(|&n| u64::from(n)).sum();
    writeln!(
        summary,
        "escape counts iterated for {} pixels, {} iterations ({:.1}% of brute force's {} pixels, {:.1}% of its {} iterations)",
        cpu.escape_pixels,
        cpu.iterations,
        100.0 * cpu.escape_pixels as f64 / view.pixels() as f64,
        view.pixels(),
        100.0 * cpu.iterations as f64 / brute_iterations as f64,
        brute_iterations
    )?;
    writeln!(
        summary,
        "pixels where Mariani-Silver differs from brute force: {differ_from_brute_force}"
    )?;
    Ok(Checked {
        report,
        counts,
        mismatches,
        differ_from_brute_force,
        summary,
    })
}

/// An ASCII preview, `columns` characters wide.
pub fn ascii_preview(view: &View, counts: &[u32], columns: u32) -> String {
    const RAMP: &[u8] = b" .:-=+*%@";
    let columns = columns.min(view.width);
    // Characters are about twice as tall as wide.
    let rows = (view.height * columns / view.width / 2).max(1);
    let mut s = String::new();
    for r in 0..rows {
        for c in 0..columns {
            let x = c * view.width / columns;
            let y = r * view.height / rows;
            let n = counts[(y * view.width + x) as usize];
            let ch = if n >= view.max_iter {
                '#'
            } else {
                let t = ((n + 1) as f32).ln() / ((view.max_iter + 1) as f32).ln();
                RAMP[((t * (RAMP.len() - 1) as f32) as usize).min(RAMP.len() - 1)] as char
            };
            s.push(ch);
        }
        s.push('\n');
    }
    s
}

/// The colour of an escape count: black in the set, and outside a ramp from
/// deep blue through white to orange over the logarithm of the count.
pub fn colour(view: &View, n: u32) -> [u8; 3] {
    if n >= view.max_iter {
        return [0, 0, 0];
    }
    let t = ((n + 1) as f32).ln() / ((view.max_iter + 1) as f32).ln();
    let stops: [(f32, [f32; 3]); 4] = [
        (0.0, [0.0, 7.0, 100.0]),
        (0.4, [32.0, 107.0, 203.0]),
        (0.7, [237.0, 255.0, 255.0]),
        (1.0, [255.0, 170.0, 0.0]),
    ];
    let k = stops
        .iter()
        .rposition(|&(at, _)| at <= t)
        .unwrap_or(0)
        .min(2);
    let ((a, ca), (b, cb)) = (stops[k], stops[k + 1]);
    let u = ((t - a) / (b - a)).clamp(0.0, 1.0);
    [0, 1, 2].map(|i| (ca[i] + u * (cb[i] - ca[i])).round() as u8)
}

/// The image as a binary PPM (`P6`), which most image viewers open.
pub fn ppm(view: &View, counts: &[u32]) -> Vec<u8> {
    let mut bytes = format!("P6\n{} {}\n255\n", view.width, view.height).into_bytes();
    bytes.extend(counts.iter().flat_map(|&n| colour(view, n)));
    bytes
}

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
        println!("OK: every pixel equals the CPU's");
        Ok(())
    } else {
        for m in &checked.mismatches {
            eprintln!("MISMATCH: {m}");
        }
        std::process::exit(1);
    }
}
