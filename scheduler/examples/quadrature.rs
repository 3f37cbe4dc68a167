//! Adaptive Simpson quadrature as a scheduler workload: an interval either is
//! accepted (its Richardson-corrected Simpson value is accumulated) or splits
//! into two halves that the same procedure refines further. The refinement is
//! data-dependent: intervals split only near the narrow bumps of the integrand.
//!
//! Exactness. GPU and CPU must take the *same* accept/split decision for every
//! interval, otherwise the set of intervals (and the count) differs. In f32
//! that cannot be guaranteed: Vulkan lets drivers contract `a * b + c` into an
//! fma and allows 2.5 ulp for division, so a decision close to the threshold
//! may flip. The integrand and the estimates are therefore evaluated in
//! fixed point on the grid `x = k / 2^20` with u32/i32 arithmetic, which is
//! bit-identical on every device. The per-depth sums are accumulated as 64-bit
//! integers (two u32 words with a carry), so the order in which workgroups add
//! them does not matter either: the GPU's counts and sums must equal the CPU's
//! exactly, and so must the integral computed from them.
//!
//! Run with `cargo run --release -p scheduler --example quadrature`.

use std::error::Error;
use std::fmt::Write as _;

use rand::{Rng, SeedableRng, rngs::StdRng};
use scheduler::{
    Atomic, CompileOptions, Executor, ExecutorConfig, Gpu, Graph, Procedure, ProcedureId, Resource,
    RunReport, Seeds,
};

/// Grid points per unit length: x = k / 2^20, the domain is [0, 1].
pub const GRID: u32 = 1 << 20;
/// Width of a root interval in grid units; the host seeds `GRID / ROOT_WIDTH`.
pub const ROOT_WIDTH: u32 = 1 << 10;
/// Deepest refinement: a depth-8 interval is 4 grid units wide, the narrowest
/// whose quarter points are still grid points. It is accepted regardless.
pub const MAX_DEPTH: u32 = 8;
/// Fixed-point scale of function values: a bump of height h peaks at h * 2^16.
pub const VALUE_SCALE: f64 = 65536.0;
/// Most summed height of bumps covering one point (keeps f <= 2^24).
const MAX_STACK: u32 = 256;
/// Tally words per depth: accepted, forced (accepted at `MAX_DEPTH` although
/// the error test failed), and a 64-bit sum as (low, high).
const TALLY_STRIDE: u32 = 4;

/// An interval [a, a + ROOT_WIDTH >> depth] with the integrand at its ends
/// and midpoint, so children never evaluate a point twice.
#[scheduler::item]
#[derive(Debug)]
pub struct Interval {
    pub a: u32,
    pub depth: u32,
    pub fa: u32,
    pub fm: u32,
    pub fb: u32,
}

/// A bump `(height * g^2) >> shift` with `g = width^2 - d^2` for a distance
/// `d < width` from `center`: a smooth (C1) quartic `(1 - (d / width)^2)^2`
/// peaking at `height * width^4 / 2^shift`, between `height * 2^12` and
/// `height * 2^16`. See [`f`].
#[scheduler::item]
#[derive(Debug, PartialEq, Eq)]
pub struct Bump {
    pub center: u32,
    pub width: u32,
    pub height: u32,
    pub shift: u32,
}

impl Bump {
    /// A bump whose shift makes its peak at most `height * 2^16`.
    pub fn new(center: u32, width: u32, height: u32) -> Self {
        let log2_ceil = u32::BITS - (width - 1).leading_zeros();
        Self {
            center,
            width,
            height,
            shift: 4 * log2_ceil - 16,
        }
    }
}

/// One quadrature problem.
#[derive(Clone, Debug)]
pub struct Problem {
    pub bumps: Vec<Bump>,
    /// Accept when |T_l + T_r - 2 T| <= threshold (see [`classify`]).
    pub threshold: u32,
}

impl Problem {
    /// `count` narrow bumps (half-width 128..=1024 grid units, 0.01 % to 0.1 %
    /// of the domain; the root intervals' quarter points, 256 apart, see every
    /// one) with heights 1..=16 at random positions. A bump that would stack
    /// too high on its neighbours (see [`Self::assert_in_range`]) is redrawn.
    pub fn random(seed: u64, count: usize, threshold: u32) -> Self {
        let mut rng = StdRng::seed_from_u64(seed);
        let mut problem = Self {
            bumps: Vec::with_capacity(count),
            threshold,
        };
        while problem.bumps.len() < count {
            problem.bumps.push(Bump::new(
                rng.random_range(0..GRID),
                rng.random_range(128..=1024),
                rng.random_range(1..=16),
            ));
            if problem.stack_height() > MAX_STACK {
                problem.bumps.pop();
            }
        }
        problem.assert_in_range();
        problem
    }

    /// An upper bound on the summed heights of the bumps covering any one
    /// point: every bump covering x overlaps the support of each other one
    /// covering x, so the largest "height of a bump plus all bumps whose
    /// support meets its support" bounds it.
    pub fn stack_height(&self) -> u32 {
        let overlaps = |a: &Bump, b: &Bump| a.center.abs_diff(b.center) < a.width + b.width;
        self.bumps
            .iter()
            .map(|a| {
                self.bumps
                    .iter()
                    .filter(|b| overlaps(a, b))
                    .map(|b| b.height)
                    .sum()
            })
            .max()
            .unwrap_or(0)
    }

    /// The bounds that keep every u32/i32 expression below exact: height <= 32
    /// and g <= 2^20 keep height * g <= 2^25 and height * g^2 <= 2^45 (split
    /// into two words); each bump peaks at most at height * 2^16, so
    /// f <= stack height * 2^16 <= 2^24, T <= 6 * 2^24, T_l + T_r < 2^28 and
    /// the accumulated 8 (T_l + T_r) - T < 2^31.
    pub fn assert_in_range(&self) {
        let stack = self.stack_height();
        assert!(
            stack <= MAX_STACK,
            "bumps stack {stack} high > {MAX_STACK}: f could exceed 2^24"
        );
        for b in &self.bumps {
            assert!(
                (64..=1024).contains(&b.width),
                "width {} out of 64..=1024",
                b.width
            );
            assert!(b.height <= 32, "height {} > 32", b.height);
            assert_eq!(b.shift, Bump::new(b.center, b.width, b.height).shift);
        }
        assert!(self.threshold < 1 << 28);
    }

    /// The exact integral of the continuous bumps (a whole one integrates to
    /// its peak * width * 16/15 in grid units), clipped at the domain's ends.
    /// Only a plausibility check: the fixed-point integrand truncates.
    pub fn analytic_integral(&self) -> f64 {
        self.bumps
            .iter()
            .map(|b| {
                let lo = f64::from(b.center.saturating_sub(b.width));
                let hi = f64::from((b.center + b.width).min(GRID));
                // Integral of (1 - t^2)^2 from t0 to t1 is t - 2t^3/3 + t^5/5.
                let g = |x: f64| {
                    let t = (x - f64::from(b.center)) / f64::from(b.width);
                    t - 2.0 * t.powi(3) / 3.0 + t.powi(5) / 5.0
                };
                let peak =
                    f64::from(b.height) * f64::from(b.width).powi(4) / f64::from(b.shift).exp2();
                peak * f64::from(b.width) * (g(hi) - g(lo)) / f64::from(GRID) / VALUE_SCALE
            })
            .sum()
    }
}

/// The integrand at grid point `x` (fixed point, scale [`VALUE_SCALE`]).
/// Integer arithmetic with one truncation per bump, so it is exact and the
/// WGSL `f` in [`WGSL_LIBRARY`] (which forms the 45-bit product from 16-bit
/// halves) returns the same value on every device.
pub fn f(bumps: &[Bump], x: u32) -> u32 {
    let mut total = 0u32;
    for b in bumps {
        let d = b.center.abs_diff(x);
        if d < b.width {
            let g = u64::from(b.width * b.width - d * d);
            total += ((u64::from(b.height) * g * g) >> b.shift) as u32;
        }
    }
    total
}

/// Per-depth outcome of a quadrature: what both the GPU and the CPU produce.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Tally {
    /// Accepted intervals per depth.
    pub accepted: Vec<u32>,
    /// Intervals accepted at `MAX_DEPTH` although their error test failed.
    pub forced: Vec<u32>,
    /// Sum of 8 (T_l + T_r) - T over the accepted intervals per depth.
    pub sums: Vec<u64>,
}

impl Tally {
    fn new() -> Self {
        let n = MAX_DEPTH as usize + 1;
        Self {
            accepted: vec![0; n],
            forced: vec![0; n],
            sums: vec![0; n],
        }
    }

    /// Total accepted intervals.
    pub fn intervals(&self) -> u64 {
        self.accepted.iter().map(|&c| u64::from(c)).sum()
    }

    /// The integral over [0, 1]. An accepted interval of width h (grid
    /// units) contributes S_2 + (S_2 - S) / 15 = h (8 (T_l + T_r) - T) / 90
    /// where S = h T / 6 and S_2 = h (T_l + T_r) / 12. The exact integer sum
    /// is rescaled once, so equal tallies give bit-identical integrals.
    pub fn integral(&self) -> f64 {
        let units: u128 = self
            .sums
            .iter()
            .enumerate()
            .map(|(depth, &s)| u128::from(s) * u128::from(ROOT_WIDTH >> depth))
            .sum();
        units as f64 / 90.0 / f64::from(GRID) / VALUE_SCALE
    }
}

/// What one interval does: accept (with its contribution) or split (with the
/// integrand at its quarter points, which the children inherit).
enum Decision {
    Accept { forced: bool, contribution: u32 },
    Split { fl: u32, fr: u32 },
}

/// The decision for one interval, mirrored by the WGSL body. With
/// S = h T / 6 and S_2 = h (T_l + T_r) / 12 the classic test
/// |S_2 - S| <= 15 * eps * h (tolerance halved with the width) becomes
/// |T_l + T_r - 2 T| <= 180 eps: a depth-independent integer threshold.
fn classify(problem: &Problem, item: &Interval) -> Decision {
    let h = ROOT_WIDTH >> item.depth;
    let q = h / 4;
    let fl = f(&problem.bumps, item.a + q);
    let fr = f(&problem.bumps, item.a + 3 * q);
    let t = item.fa + 4 * item.fm + item.fb;
    let tl = item.fa + 4 * fl + item.fm;
    let tr = item.fm + 4 * fr + item.fb;
    let diff = (tl + tr) as i32 - 2 * t as i32;
    let ok = diff.unsigned_abs() <= problem.threshold;
    if ok || item.depth == MAX_DEPTH {
        Decision::Accept {
            forced: !ok,
            contribution: 8 * (tl + tr) - t,
        }
    } else {
        Decision::Split { fl, fr }
    }
}

/// The root intervals the host seeds.
pub fn roots(problem: &Problem) -> Vec<Interval> {
    (0..GRID / ROOT_WIDTH)
        .map(|i| {
            let a = i * ROOT_WIDTH;
            Interval {
                a,
                depth: 0,
                fa: f(&problem.bumps, a),
                fm: f(&problem.bumps, a + ROOT_WIDTH / 2),
                fb: f(&problem.bumps, a + ROOT_WIDTH),
            }
        })
        .collect()
}

/// Children of a split interval.
fn children(item: &Interval, fl: u32, fr: u32) -> [Interval; 2] {
    let half = (ROOT_WIDTH >> item.depth) / 2;
    [
        Interval {
            a: item.a,
            depth: item.depth + 1,
            fa: item.fa,
            fm: fl,
            fb: item.fm,
        },
        Interval {
            a: item.a + half,
            depth: item.depth + 1,
            fa: item.fm,
            fm: fr,
            fb: item.fb,
        },
    ]
}

/// The CPU reference: the same decisions on an explicit stack. Also returns
/// the number of intervals processed (accepted + split), which must equal the
/// procedure's executed count.
pub fn cpu_reference(problem: &Problem) -> (Tally, u64) {
    let mut tally = Tally::new();
    let mut stack = roots(problem);
    let mut processed = 0u64;
    while let Some(item) = stack.pop() {
        processed += 1;
        match classify(problem, &item) {
            Decision::Accept {
                forced,
                contribution,
            } => {
                let d = item.depth as usize;
                tally.accepted[d] += 1;
                tally.forced[d] += u32::from(forced);
                tally.sums[d] += u64::from(contribution);
            }
            Decision::Split { fl, fr } => stack.extend(children(&item, fl, fr)),
        }
    }
    (tally, processed)
}

/// A fine composite Simpson sum over every grid point: the integral of the
/// fixed-point integrand up to O(grid^4), to show what the adaptive rule
/// achieves with far fewer points.
pub fn dense_simpson(problem: &Problem) -> f64 {
    // f is a sum of bumps, so the sum is taken bump by bump over its support.
    let weighted: u128 = problem
        .bumps
        .iter()
        .map(|b| {
            let lo = b.center.saturating_sub(b.width - 1);
            let hi = (b.center + b.width - 1).min(GRID);
            (lo..=hi)
                .map(|x| {
                    let w = if x == 0 || x == GRID {
                        1
                    } else if x % 2 == 1 {
                        4
                    } else {
                        2
                    };
                    w * u128::from(f(std::slice::from_ref(b), x))
                })
                .sum::<u128>()
        })
        .sum();
    weighted as f64 / 3.0 / f64::from(GRID) / VALUE_SCALE
}

/// WGSL shared by the body: the integrand and a 64-bit atomic accumulator.
const WGSL_LIBRARY: &str = "
// The full 64-bit product a * b as (low, high), from 16-bit halves.
fn mul_wide(a: u32, b: u32) -> vec2<u32> {
    let a0 = a & 0xffffu;
    let a1 = a >> 16u;
    let b0 = b & 0xffffu;
    let b1 = b >> 16u;
    let p00 = a0 * b0;
    let p01 = a0 * b1;
    let p10 = a1 * b0;
    let mid = (p00 >> 16u) + (p01 & 0xffffu) + (p10 & 0xffffu);
    let low = (p00 & 0xffffu) | (mid << 16u);
    let high = a1 * b1 + (p01 >> 16u) + (p10 >> 16u) + (mid >> 16u);
    return vec2<u32>(low, high);
}

fn f(x: u32) -> u32 {
    var total = 0u;
    for (var j = 0u; j < arrayLength(&bumps); j += 1u) {
        let b = bumps[j];
        let d = select(x - b.center, b.center - x, b.center >= x);
        if (d < b.width) {
            let g = b.width * b.width - d * d;
            // height * g <= 2^25, so this is height * g^2 exactly; the shift
            // (8..=24, never 0 or 32) leaves at most height * 2^16.
            let p = mul_wide(b.height * g, g);
            total += (p.x >> b.shift) | (p.y << (32u - b.shift));
        }
    }
    return total;
}

// Adds `value` to the 64-bit counter (low, high) at tally[index]. Every wrap
// of the low word is seen by exactly one adder, which carries it, so the
// result is independent of the order of the additions.
fn add_u64(index: u32, value: u32) {
    let old = atomicAdd(&tally[index], value);
    if (old + value < old) {
        atomicAdd(&tally[index + 1u], 1u);
    }
}
";

/// The body of `Refine`, mirroring [`classify`].
const REFINE_BODY: &str = "
if (valid) {
    let h = ROOT_WIDTH >> item.depth;
    let q = h / 4u;
    let fl = f(item.a + q);
    let fr = f(item.a + 3u * q);
    let t = item.fa + 4u * item.fm + item.fb;
    let tl = item.fa + 4u * fl + item.fm;
    let tr = item.fm + 4u * fr + item.fb;
    let diff = i32(tl + tr) - 2i * i32(t);
    let ok = u32(abs(diff)) <= THRESHOLD;
    if (ok || item.depth == MAX_DEPTH) {
        let base = TALLY_STRIDE * item.depth;
        atomicAdd(&tally[base], 1u);
        if (!ok) {
            atomicAdd(&tally[base + 1u], 1u);
        }
        add_u64(base + 2u, 8u * (tl + tr) - t);
    } else {
        enqueue_Refine(Interval(item.a, item.depth + 1u, item.fa, fl, item.fm));
        enqueue_Refine(Interval(item.a + h / 2u, item.depth + 1u, item.fm, fr, item.fb));
    }
}
";

/// The graph of [`graph`], with the handle of its procedure.
#[derive(Debug)]
pub struct QuadratureGraph {
    pub graph: Graph,
    pub refine: ProcedureId<Interval>,
}

/// The one-procedure graph: `Refine` enqueues into itself.
pub fn graph(problem: &Problem) -> QuadratureGraph {
    let mut graph = Graph::new("adaptive quadrature");
    graph
        .constant("ROOT_WIDTH", ROOT_WIDTH)
        .constant("MAX_DEPTH", MAX_DEPTH)
        .constant("THRESHOLD", problem.threshold)
        .constant("TALLY_STRIDE", TALLY_STRIDE);
    graph.library(WGSL_LIBRARY);
    // The typed resource declares `struct Bump` from the Rust type.
    graph.resource(Resource::storage_read::<[Bump]>("bumps"));
    graph.resource(
        Resource::storage::<[Atomic<u32>]>("tally")
            .min_len(u64::from(TALLY_STRIDE * (MAX_DEPTH + 1))),
    );
    let refine = graph.procedure(
        Procedure::of::<Interval>("Refine")
            .initial(true)
            .body(REFINE_BODY),
    );
    graph.connect_with_fan_out(&refine, &refine, 2);
    QuadratureGraph { graph, refine }
}

/// A checked run: the report and every disagreement with the CPU (none when
/// the run is correct).
#[derive(Debug)]
pub struct Checked {
    pub report: RunReport,
    pub mismatches: Vec<String>,
    /// A human-readable summary of the result.
    pub summary: String,
}

/// Builds the graph, runs it on `gpu` with `config`, and compares the tally
/// and the scheduler's counters with the CPU reference exactly.
pub fn run(
    gpu: &Gpu,
    problem: &Problem,
    config: &ExecutorConfig,
) -> Result<Checked, Box<dyn Error>> {
    problem.assert_in_range();
    let QuadratureGraph { graph, refine } = graph(problem);
    let compiled = graph.compile(&CompileOptions::with_features(
        scheduler::recommended_features(&gpu.device),
    ))?;
    let mut executor = Executor::new(&gpu.device, &gpu.queue, &compiled, config)?;

    // The executor creates, fills and reads the typed resources' buffers.
    executor.write("bumps", &problem.bumps)?;
    let tally_words = (TALLY_STRIDE * (MAX_DEPTH + 1)) as usize;
    executor.write("tally", &vec![0u32; tally_words])?;
    let roots = roots(problem);
    let report = executor.run(&Seeds::new().add(&refine, &roots), &[])?;
    let words = executor.read::<u32>("tally")?;
    let mut gpu_tally = Tally::new();
    for (d, chunk) in words.chunks_exact(TALLY_STRIDE as usize).enumerate() {
        gpu_tally.accepted[d] = chunk[0];
        gpu_tally.forced[d] = chunk[1];
        gpu_tally.sums[d] = u64::from(chunk[2]) | u64::from(chunk[3]) << 32;
    }

    let (cpu_tally, processed) = cpu_reference(problem);
    let mut mismatches = Vec::new();
    for d in 0..=MAX_DEPTH as usize {
        let (g, c) = (&gpu_tally, &cpu_tally);
        if (g.accepted[d], g.forced[d], g.sums[d]) != (c.accepted[d], c.forced[d], c.sums[d]) {
            mismatches.push(format!(
                "depth {d}: GPU accepted {} (forced {}) sum {}, CPU accepted {} (forced {}) sum {}",
                g.accepted[d], g.forced[d], g.sums[d], c.accepted[d], c.forced[d], c.sums[d]
            ));
        }
    }
    let stats = report.procedure(&refine).ok_or("no Refine stats")?;
    if stats.executed != processed {
        mismatches.push(format!(
            "Refine executed {} intervals, the CPU processed {processed}",
            stats.executed
        ));
    }
    // Every split enqueues two children: processed = roots + 2 * splits.
    let splits = processed - cpu_tally.intervals();
    if stats.enqueued != 2 * splits {
        mismatches.push(format!(
            "Refine enqueued {} intervals, expected 2 x {splits} splits",
            stats.enqueued
        ));
    }

    let mut summary = String::new();
    let (gi, ci) = (gpu_tally.integral(), cpu_tally.integral());
    writeln!(
        summary,
        "{} bumps, threshold {}: {} accepted intervals ({} forced at depth {MAX_DEPTH}) of {} processed",
        problem.bumps.len(),
        problem.threshold,
        gpu_tally.intervals(),
        gpu_tally.forced.iter().sum::<u32>(),
        stats.executed
    )?;
    writeln!(summary, "accepted per depth: {:?}", gpu_tally.accepted)?;
    writeln!(summary, "integral: GPU {gi:.9}, CPU {ci:.9}")?;
    let dense = dense_simpson(problem);
    writeln!(
        summary,
        "dense Simpson over all {} points: {dense:.9} (adaptive relative error {:.2e}); continuous bumps: {:.9}",
        GRID + 1,
        (gi - dense).abs() / dense,
        problem.analytic_integral()
    )?;
    if gpu_tally == cpu_tally && gi != ci {
        mismatches.push(format!("equal tallies but integrals {gi} != {ci}"));
    }
    Ok(Checked {
        report,
        mismatches,
        summary,
    })
}

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
