//! [`DicingRule`]: how a frame decides when and how finely a piece is
//! diced, computed once from the scene (or the viewer's settings) so that
//! every consumer reads the same `f32`s.

use std::fmt;

use crate::dicing::GridSize;
use crate::modes::Dicing;
use crate::params::MAX_GRID_QUADS;

/// The dicing mode of a frame with the sizes that follow from it: the
/// shading rate, the micropolygon side `sqrt(shading_rate)` (taken once,
/// here) and the dice threshold of the Bound test.
///
/// The shading rate and the side are kept with fixed dicing too: the GPU
/// uniform carries them whatever the mode, and the viewer switches modes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DicingRule {
    mode: Dicing,
    shading_rate: f32,
    micropolygon_side: f32,
    dice_threshold: f32,
    fixed_threshold: f32,
}

impl DicingRule {
    /// The rule of a frame diced in `mode` at `shading_rate` (pixels per
    /// micropolygon), with `fixed_threshold` (pixels) the dice threshold
    /// of fixed dicing; rate dicing derives its own threshold.
    pub fn new(mode: Dicing, shading_rate: f32, fixed_threshold: f32) -> Self {
        // The one square root of the frame: every consumer reads this side.
        let side = shading_rate.sqrt();
        let dice_threshold = match mode {
            Dicing::Fixed => fixed_threshold,
            Dicing::Rate => MAX_GRID_QUADS as f32 * side,
        };
        Self {
            mode,
            shading_rate,
            micropolygon_side: side,
            dice_threshold,
            fixed_threshold,
        }
    }

    /// How pieces are diced.
    pub fn mode(self) -> Dicing {
        self.mode
    }

    /// The target micropolygon area in pixels, as the scene gives it.
    pub fn shading_rate(self) -> f32 {
        self.shading_rate
    }

    /// The side of a micropolygon at the shading rate,
    /// `sqrt(shading_rate)` pixels (rate dicing sizes grids by it).
    pub fn micropolygon_side(self) -> f32 {
        self.micropolygon_side
    }

    /// Dice when the projected bound's larger side is `<=` this (pixels):
    /// the scene's `dice_threshold` for fixed dicing, the largest grid's
    /// side at the shading rate (`MAX_GRID_QUADS` micropolygon sides) for
    /// rate dicing, where it only bounds a piece's box with its
    /// displacement (see `crate::reference::bound::fits`).
    pub fn dice_threshold(self) -> f32 {
        self.dice_threshold
    }

    /// The scene's dice threshold for fixed dicing (pixels), kept in both
    /// modes so that a switch to fixed dicing (the viewer's) uses it.
    pub fn fixed_threshold(self) -> f32 {
        self.fixed_threshold
    }

    /// The side of a micropolygon, in pixels, that Adaptive sampling's cost
    /// model assumes: the side at the shading rate with rate dicing; with
    /// fixed dicing, the side of a fixed grid's micropolygon in a piece as
    /// large as the dice threshold allows.
    pub fn nominal_micropolygon_px(self) -> f32 {
        match self.mode {
            Dicing::Rate => self.micropolygon_side,
            Dicing::Fixed => self.dice_threshold / GridSize::FIXED.nu as f32,
        }
    }
}

/// `rate, shading rate R` or `fixed, threshold T px`.
impl fmt::Display for DicingRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.mode {
            Dicing::Rate => write!(f, "rate, shading rate {}", self.shading_rate),
            Dicing::Fixed => write!(f, "fixed, threshold {} px", self.dice_threshold),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_side_is_the_square_root_of_the_rate_in_both_modes() {
        for mode in [Dicing::Rate, Dicing::Fixed] {
            let rule = DicingRule::new(mode, 2.0, 8.0);
            assert_eq!(rule.micropolygon_side().to_bits(), 2.0f32.sqrt().to_bits());
            assert_eq!(rule.shading_rate(), 2.0);
            assert_eq!(rule.mode(), mode);
        }
    }

    #[test]
    fn rate_dicing_bounds_pieces_by_the_largest_grid() {
        let rule = DicingRule::new(Dicing::Rate, 4.0, 8.0);
        assert_eq!(rule.dice_threshold(), MAX_GRID_QUADS as f32 * 2.0);
        assert_eq!(rule.fixed_threshold(), 8.0);
        assert_eq!(rule.nominal_micropolygon_px(), 2.0);
        assert_eq!(rule.to_string(), "rate, shading rate 4");
    }

    #[test]
    fn fixed_dicing_keeps_the_scene_threshold() {
        let rule = DicingRule::new(Dicing::Fixed, 4.0, 8.0);
        assert_eq!(rule.dice_threshold(), 8.0);
        assert_eq!(
            rule.nominal_micropolygon_px(),
            8.0 / GridSize::FIXED.nu as f32
        );
        assert_eq!(rule.to_string(), "fixed, threshold 8 px");
    }
}
