//! Which multiply-adds of the escape loop a driver fused.
//!
//! SPIR-V lets a driver contract a multiply followed by an add into one
//! fused multiply-add, rounded once instead of twice, and some do (NVIDIA's
//! Vulkan driver does; lavapipe does not). WGSL cannot forbid it. The
//! escape loop ([`ESCAPE_WGSL`]) has four sites where that can happen; a
//! [`Contraction`] says which of them were fused, so that the CPU can
//! compute the same bits ([`escape_count_with`]) and the checks stay exact.
//!
//! Sites whose fusing changes no count cannot be told apart from unfused
//! ones: on a view with exact pixel coordinates ([`View::whole_set`]) the
//! coordinate site never changes anything. [`Contraction::all`] lists the
//! variants by the number of fused sites, so the matcher names the one with
//! the fewest that explains the counts.

use std::fmt;

#[cfg(doc)]
use super::{ESCAPE_WGSL, View, escape_count_with};

/// How the loop condition's `zr * zr + zi * zi` is evaluated.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Magnitude {
    /// Both products rounded, then their sum rounded.
    #[default]
    Plain,
    /// `fma(zr, zr, zi * zi)`: the real square fused into the sum.
    FusedReal,
    /// `fma(zi, zi, zr * zr)`: the imaginary square fused into the sum.
    FusedImaginary,
}

/// Which of the escape loop's multiply-add sites a driver fused. The
/// default is [`Contraction::PLAIN`], the arithmetic as written (what the
/// CPU does unless asked otherwise).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Contraction {
    /// The pixel coordinates: `X0 + f32(px) * STEP` as `fma(f32(px), STEP,
    /// X0)`, and the same for `y`.
    pub coordinates: bool,
    /// The loop condition `zr * zr + zi * zi`.
    pub magnitude: Magnitude,
    /// The real update `(zr - zi) * (zr + zi) + cr` as `fma(zr - zi, zr +
    /// zi, cr)`.
    pub real: bool,
    /// The imaginary update `2.0 * zr * zi + ci` as `fma(2.0 * zr, zi, ci)`
    /// (`2.0 * zr` is exact, so that is the only fused form).
    pub imaginary: bool,
}

impl Contraction {
    /// Nothing fused: every product and sum rounded on its own.
    pub const PLAIN: Self = Self {
        coordinates: false,
        magnitude: Magnitude::Plain,
        real: false,
        imaginary: false,
    };

    /// Every variant, once: [`Self::PLAIN`] first, then by the number of
    /// fused sites (so the first that explains some counts is the one with
    /// the fewest).
    pub fn all() -> Vec<Self> {
        let mut all: Vec<Self> = [false, true]
            .into_iter()
            .flat_map(|coordinates| {
                [
                    Magnitude::Plain,
                    Magnitude::FusedReal,
                    Magnitude::FusedImaginary,
                ]
                .into_iter()
                .flat_map(move |magnitude| {
                    [false, true].into_iter().flat_map(move |real| {
                        [false, true].into_iter().map(move |imaginary| Self {
                            coordinates,
                            magnitude,
                            real,
                            imaginary,
                        })
                    })
                })
            })
            .collect();
        // Stable: among equally many fused sites, the enumeration order.
        all.sort_by_key(|c| c.fused_sites().len());
        all
    }

    /// Whether nothing is fused.
    pub fn is_plain(&self) -> bool {
        *self == Self::PLAIN
    }

    /// The fused sites, each as the fused operation, in loop order.
    pub fn fused_sites(&self) -> Vec<&'static str> {
        let mut sites = Vec::new();
        if self.coordinates {
            sites.push("the pixel coordinates (fma(f32(px), STEP, X0))");
        }
        match self.magnitude {
            Magnitude::Plain => {}
            Magnitude::FusedReal => sites.push("the loop condition (fma(zr, zr, zi * zi))"),
            Magnitude::FusedImaginary => {
                sites.push("the loop condition (fma(zi, zi, zr * zr))");
            }
        }
        if self.real {
            sites.push("the real update (fma(zr - zi, zr + zi, cr))");
        }
        if self.imaginary {
            sites.push("the imaginary update (fma(2 zr, zi, ci))");
        }
        sites
    }
}

/// `nothing` for [`Contraction::PLAIN`], else the fused sites.
impl fmt::Display for Contraction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.is_plain() {
            f.write_str("nothing")
        } else {
            f.write_str(&self.fused_sites().join(", "))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_lists_every_variant_once_plain_first() {
        let all = Contraction::all();
        // 2 (coordinates) x 3 (condition) x 2 (real) x 2 (imaginary).
        assert_eq!(all.len(), 24);
        assert_eq!(all[0], Contraction::PLAIN);
        for (i, a) in all.iter().enumerate() {
            assert!(all[i + 1..].iter().all(|b| b != a), "{a:?} twice");
        }
        let fused: Vec<usize> = all.iter().map(|c| c.fused_sites().len()).collect();
        assert!(fused.windows(2).all(|w| w[0] <= w[1]), "{fused:?}");
        assert_eq!(fused.last(), Some(&4));
    }

    #[test]
    fn display_names_the_fused_sites() {
        assert_eq!(Contraction::PLAIN.to_string(), "nothing");
        let c = Contraction {
            real: true,
            imaginary: true,
            ..Contraction::PLAIN
        };
        assert_eq!(
            c.to_string(),
            "the real update (fma(zr - zi, zr + zi, cr)), the imaginary update (fma(2 zr, zi, ci))"
        );
    }
}
