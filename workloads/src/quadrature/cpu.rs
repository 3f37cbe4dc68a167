//! The CPU side: the fixed-point integrand, each interval's accept/split
//! decision (mirrored by the WGSL body), the reference refinement the GPU's
//! tally is checked against, and a dense Simpson sum for comparison.

use super::{Bump, GRID, Interval, MAX_DEPTH, Problem, ROOT_WIDTH, VALUE_SCALE};

/// The integrand at grid point `x` (fixed point, scale [`VALUE_SCALE`]).
/// Integer arithmetic with one truncation per bump, so it is exact and the
/// WGSL `f` in `WGSL_LIBRARY` (which forms the 45-bit product from 16-bit
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
    pub(super) fn new() -> Self {
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
    Accept {
        forced: bool,
        contribution: u32,
        error: u32,
    },
    Split {
        fl: u32,
        fr: u32,
    },
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
    let diff = (tl + tr).cast_signed() - 2 * t.cast_signed();
    let ok = diff.unsigned_abs() <= problem.threshold;
    if ok || item.depth == MAX_DEPTH {
        Decision::Accept {
            forced: !ok,
            contribution: 8 * (tl + tr) - t,
            error: diff.unsigned_abs(),
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
                ..
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

/// What the accepted intervals under one root add up to: their Richardson
/// contributions (in 1/180 grid-units of `VALUE_SCALE`, as the tally sums)
/// and their error estimates `|T_l + T_r - 2 T|`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Estimate {
    /// The sum of the accepted intervals' contributions.
    pub value: u64,
    /// The sum of their error estimates.
    pub error: u64,
}

/// Per root interval (in the order of [`roots`]), the estimate of its
/// accepted intervals: what combining them bottom-up must give.
pub fn root_estimates(problem: &Problem) -> Vec<Estimate> {
    roots(problem)
        .into_iter()
        .map(|root| {
            let mut estimate = Estimate::default();
            let mut stack = vec![root];
            while let Some(item) = stack.pop() {
                match classify(problem, &item) {
                    Decision::Accept {
                        contribution,
                        error,
                        ..
                    } => {
                        estimate.value += u64::from(contribution);
                        estimate.error += u64::from(error);
                    }
                    Decision::Split { fl, fr } => stack.extend(children(&item, fl, fr)),
                }
            }
            estimate
        })
        .collect()
}
