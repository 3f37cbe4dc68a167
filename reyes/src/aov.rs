//! Arbitrary output variables: pictures of what the pipeline did instead
//! of the shaded image. `grids` colours every micropolygon by the size of
//! its grid (and checkers the micropolygons of a grid), so it shows at a
//! glance where the micropolygons go; `depth` and `normal` show the view
//! depth and the shading normal of every grid point. `z` is not a picture
//! but data: the camera-space depth per pixel ([`crate::depth`]).

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::camera::Camera;
use crate::color::pack_rgb10;

/// What the image shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Aov {
    /// The shaded surface (default).
    #[default]
    Shaded,
    /// Each micropolygon in the colour of its grid's size ([`grid_color`]).
    #[cfg_attr(
        feature = "cli",
        value(help = "Each micropolygon in the colour of its grid's size")
    )]
    Grids,
    /// Grey by view depth ([`depth_color`]).
    #[cfg_attr(feature = "cli", value(help = "Grey by view depth"))]
    Depth,
    /// The shading normal as a colour ([`normal_color`]).
    #[cfg_attr(feature = "cli", value(help = "The shading normal as a colour"))]
    Normal,
    /// Camera-space depth per pixel as 32-bit floats, not a picture
    /// ([`crate::depth`]): written only as a single-channel (`Z`) EXR.
    #[cfg_attr(
        feature = "cli",
        value(help = "Camera-space depth per pixel (f32, +inf where empty); .exr only")
    )]
    Z,
}

impl Aov {
    /// Its name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Aov::Shaded => "shaded",
            Aov::Grids => "grids",
            Aov::Depth => "depth",
            Aov::Normal => "normal",
            Aov::Z => "z",
        }
    }

    /// Its code in the GPU's frame uniform.
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// Linear RGB of grids of 1, 2, 4, ... 256 micropolygons (by `floor(log2)`
/// of the count: the fixed dicer's 225 is the 128 colour): from dark blue
/// for the smallest through green and yellow to red for the largest.
pub const GRID_PALETTE: [[f32; 3]; 9] = [
    [0.05, 0.05, 0.45],
    [0.0, 0.25, 0.9],
    [0.0, 0.6, 0.9],
    [0.0, 0.7, 0.35],
    [0.35, 0.8, 0.0],
    [0.9, 0.85, 0.0],
    [1.0, 0.5, 0.0],
    [0.9, 0.1, 0.05],
    [0.6, 0.0, 0.3],
];

/// The brightness of every other micropolygon of a grid (a checkerboard),
/// so that single micropolygons can be told apart.
pub const CHECKER_SHADE: f32 = 0.65;

/// The packed colours of [`grid_color`]: entry `2 * size + checker`.
pub fn grid_colors() -> [u32; 18] {
    std::array::from_fn(|k| {
        let base = Vec3::from_array(GRID_PALETTE[k / 2]);
        pack_rgb10(if k % 2 == 1 {
            base * CHECKER_SHADE
        } else {
            base
        })
    })
}

/// The packed colour of micropolygon `(i, j)` of a grid of `quads`
/// micropolygons.
pub fn grid_color(quads: u32, i: u32, j: u32) -> u32 {
    grid_colors()[grid_color_index(quads, i, j)]
}

/// The index into [`grid_colors`] of micropolygon `(i, j)` of a grid of
/// `quads` micropolygons.
pub fn grid_color_index(quads: u32, i: u32, j: u32) -> usize {
    let size = (31 - quads.max(1).leading_zeros()).min(8);
    (2 * size + ((i + j) & 1)) as usize
}

/// The view depth at which [`depth_color`] reaches black: twice the
/// distance from the eye to the camera's target.
pub fn depth_range(camera: &Camera) -> f32 {
    2.0 * camera.eye.distance(camera.target)
}

/// Grey for a point at view depth (clip `w`) `w`: white at the eye, black
/// from `range` on.
pub fn depth_color(w: f32, range: f32) -> Vec3 {
    Vec3::splat((1.0 - w / range).clamp(0.0, 1.0))
}

/// A unit normal as a colour: `n * 0.5 + 0.5`.
pub fn normal_color(n: Vec3) -> Vec3 {
    n * 0.5 + Vec3::splat(0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_sizes_get_their_own_colours() {
        let colors = grid_colors();
        assert_eq!(grid_color_index(1, 0, 0), 0);
        assert_eq!(grid_color_index(1, 1, 0), 1);
        assert_eq!(grid_color_index(256, 0, 0), 16);
        assert_eq!(grid_color_index(225, 0, 0), 14);
        for k in 0..9 {
            assert_ne!(colors[2 * k], colors[2 * k + 1], "checker of size {k}");
            for other in 0..k {
                assert_ne!(colors[2 * k], colors[2 * other]);
            }
        }
    }

    #[test]
    fn depth_fades_to_black() {
        assert_eq!(depth_color(0.0, 10.0), Vec3::ONE);
        assert_eq!(depth_color(5.0, 10.0), Vec3::splat(0.5));
        assert_eq!(depth_color(20.0, 10.0), Vec3::ZERO);
    }
}
