//! The frame's rendering modes: how micropolygons are sampled, how pieces
//! are diced and how colour varies over a micropolygon.
//!
//! They sit below both the scene description ([`crate::scene`]) and the
//! sample tables (`crate::uvt`), which both read them. With the `cli`
//! feature each derives `clap::ValueEnum`, so the command line takes the
//! same names as scene files.

use serde::{Deserialize, Serialize};

/// How micropolygons are sampled. Every mode but `Nearest` handles motion
/// blur and depth of field: a sample then has a time and a lens position as
/// well as a screen position (see `crate::uvt` and `docs/reyes.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Sampling {
    /// Bounding box: one screen box per micropolygon, over its positions at
    /// shutter open and close and grown by its largest circle of confusion;
    /// every sample in the pixel strata the box touches is tested against
    /// the micropolygon's two triangles, at the sample's own time and lens
    /// position (default).
    #[default]
    Bbox,
    /// Simple UVT: the `spp` time/lens tuples are shared by every pixel;
    /// tuple `s` positions the micropolygon once and tests sample `s` of
    /// each pixel in its box (an accumulation buffer in one pass).
    Simple,
    /// Interleave UVT (Fatahalian et al. 2009): tiles of `interleave_tile`
    /// pixels a side (`--interleave-tile` 2, 3 or 4; default 2) with
    /// `tile * tile * spp` distinct time/lens tuples each; a micropolygon
    /// positioned at a tuple tests the one sample of that tuple in every
    /// tile its box overlaps.
    Interleave,
    /// INTERVAL: `spp` time intervals, one box per interval; a box tests
    /// the samples whose time lies in its interval.
    Interval,
    /// Adaptive: INTERVAL or Interleave UVT per grid, whichever the grid's
    /// motion and circle of confusion make cheaper.
    Adaptive,
    /// Baseline: each micropolygon writes only the sample nearest its
    /// centroid (no motion blur or depth of field).
    Nearest,
}

/// How pieces are diced into grids of micropolygons (see `docs/reyes.md`,
/// "Dicing").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum Dicing {
    /// To the shading rate: each piece gets a grid of up to 16 x 16
    /// micropolygons sized by its projected rows and columns, with edges
    /// shared watertight between neighbours (default).
    #[default]
    Rate,
    /// Every piece that fits `dice_threshold` pixels gets the same 16 x 16
    /// points (15 x 15 micropolygons), whatever its size.
    Fixed,
}

/// How a micropolygon's colour varies over it: RenderMan's
/// `ShadingInterpolation` (see `docs/reyes.md`, "Shading interpolation").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum ShadingInterpolation {
    /// Each sample blends the colours shaded at its triangle's three
    /// corners by its barycentric weights (Gouraud), so that a picture at
    /// shading rate 1 shows no facets (default).
    #[default]
    Smooth,
    /// One colour per micropolygon, the mean of its four corners'.
    Constant,
}

impl ShadingInterpolation {
    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ShadingInterpolation::Smooth => "smooth",
            ShadingInterpolation::Constant => "constant",
        }
    }
}

impl Dicing {
    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Dicing::Rate => "rate",
            Dicing::Fixed => "fixed",
        }
    }
}

impl Sampling {
    /// The modes that sample time and lens (every mode but
    /// [`Sampling::Nearest`]), in declaration order.
    pub const TIME_AND_LENS: [Sampling; 5] = [
        Sampling::Bbox,
        Sampling::Simple,
        Sampling::Interleave,
        Sampling::Interval,
        Sampling::Adaptive,
    ];

    /// Every mode, in the order of the docs and the benchmark tables.
    pub const ALL: [Sampling; 6] = [
        Sampling::Bbox,
        Sampling::Simple,
        Sampling::Interleave,
        Sampling::Interval,
        Sampling::Adaptive,
        Sampling::Nearest,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Sampling::Bbox => "bbox",
            Sampling::Simple => "simple",
            Sampling::Interleave => "interleave",
            Sampling::Interval => "interval",
            Sampling::Adaptive => "adaptive",
            Sampling::Nearest => "nearest",
        }
    }

    /// Whether the mode samples time and lens (everything but `Nearest`).
    pub fn supports_blur(self) -> bool {
        self != Sampling::Nearest
    }
}
