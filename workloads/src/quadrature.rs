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
//! The parts live in their own files: the CPU reference ([`cpu_reference`]),
//! the WGSL of the body, and the graph with a checked GPU run ([`graph`],
//! [`run`]). The example `scheduler/examples/quadrature.rs` runs it from the
//! command line.

mod combined;
mod cpu;
mod run;
mod wgsl;

use rand::{Rng, SeedableRng, rngs::StdRng};

pub use crate::Checked;
pub use combined::{Combine, CombinedGraph, Span, combined_graph, run_combined};
pub use cpu::{Estimate, Tally, cpu_reference, dense_simpson, f, root_estimates, roots};
pub use run::{QuadratureGraph, graph, run};

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
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct\'s doc describes the fields"
)]
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
#[expect(
    missing_docs,
    reason = "field docs would become WGSL comments in the generated module; the struct\'s doc describes the fields"
)]
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
    /// The integrand: the sum of these bumps.
    pub bumps: Vec<Bump>,
    /// Accept when |T_l + T_r - 2 T| <= threshold (see `classify`, the
    /// decision [`cpu_reference`] takes).
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
