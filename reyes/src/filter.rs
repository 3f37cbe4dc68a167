//! Pixel filters: how the resolve weights the samples around a pixel,
//! RenderMan's `PixelFilter` (RenderMan Interface Specification 3.2,
//! `RiPixelFilter` and the standard filter functions). The CPU reference
//! (`crate::reference::resolve`) and the GPU resolve
//! (`shaders/reyes/resolve.wgsl`) evaluate the same weights.

use serde::{Deserialize, Serialize};

/// The standard filter functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FilterKind {
    /// 1 inside the window.
    Box,
    /// A tent falling to 0 at the window's edges: `(1 - |x| / (xwidth / 2))
    /// * (1 - |y| / (ywidth / 2))`.
    Triangle,
    /// `exp(-2 (x'^2 + y'^2))` with `x' = 2 x / xwidth`, `y' = 2 y /
    /// ywidth` (RenderMan's default, 2 x 2).
    Gaussian,
    /// The radial Catmull-Rom cubic of `r = sqrt(x^2 + y^2)`: `3 r^3 - 5 r^2
    /// + 2` below 1, `-r^3 + 5 r^2 - 8 r + 4` below 2, else 0.
    CatmullRom,
    /// `sinc` windowed by a cosine, per axis: `cos(0.5 pi x / xwidth) *
    /// sin(pi x) / (pi x)` (1 at 0), times the same in y.
    Sinc,
}

impl FilterKind {
    /// Every filter, in a fixed order.
    pub const ALL: [FilterKind; 5] = [
        FilterKind::Box,
        FilterKind::Triangle,
        FilterKind::Gaussian,
        FilterKind::CatmullRom,
        FilterKind::Sinc,
    ];

    /// The name RenderMan and the scene files use.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Box => "box",
            FilterKind::Triangle => "triangle",
            FilterKind::Gaussian => "gaussian",
            FilterKind::CatmullRom => "catmull-rom",
            FilterKind::Sinc => "sinc",
        }
    }

    /// The filter named `name` (RenderMan's names), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The code the GPU resolve switches on (`FILTER_*`).
    pub fn code(self) -> u32 {
        self as u32
    }
}

/// The widest filter window accepted, in pixels: the resolve reads
/// `(2 * radius + 1)^2` pixels' samples for each pixel.
pub const MAX_FILTER_WIDTH: f32 = 16.0;

/// A pixel filter and its window (`[pixel_filter]`; RIB `PixelFilter`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PixelFilter {
    /// The filter function (default `gaussian`).
    #[serde(default = "default_kind")]
    pub filter: FilterKind,
    /// The window's width in pixels (default 2).
    #[serde(default = "default_width")]
    pub xwidth: f32,
    /// The window's height in pixels (default 2).
    #[serde(default = "default_width")]
    pub ywidth: f32,
}

fn default_kind() -> FilterKind {
    FilterKind::Gaussian
}
fn default_width() -> f32 {
    2.0
}

impl Default for PixelFilter {
    /// RenderMan's default: `gaussian`, 2 x 2.
    fn default() -> Self {
        PixelFilter {
            filter: FilterKind::Gaussian,
            xwidth: 2.0,
            ywidth: 2.0,
        }
    }
}

impl PixelFilter {
    /// The box over exactly one pixel: each pixel averages its own samples
    /// with equal weights.
    pub const PIXEL_BOX: PixelFilter = PixelFilter {
        filter: FilterKind::Box,
        xwidth: 1.0,
        ywidth: 1.0,
    };

    /// Why the filter cannot be used, if it cannot: its widths must be
    /// finite and in `(0, MAX_FILTER_WIDTH]`.
    pub fn problem(&self) -> Option<String> {
        for (name, w) in [("xwidth", self.xwidth), ("ywidth", self.ywidth)] {
            if !(w > 0.0 && w <= MAX_FILTER_WIDTH) {
                return Some(format!(
                    "{name} {w} is outside (0, {MAX_FILTER_WIDTH}] pixels"
                ));
            }
        }
        None
    }

    /// How many pixels around a pixel hold samples within its window: a
    /// sample of pixel `q` lies in `[q, q + 1)`, the window is centred on
    /// `p + 0.5`, so the neighbours `p - r ..= p + r` with `r = ceil(width /
    /// 2 - 0.5)` in each axis.
    pub fn radius(&self) -> [u32; 2] {
        [self.xwidth, self.ywidth].map(|w| (w / 2.0 - 0.5).max(0.0).ceil() as u32)
    }

    /// The weight of a sample `(x, y)` pixels from the pixel's centre; 0
    /// outside the window. `shaders/reyes/resolve.wgsl`'s `filter_weight`
    /// mirrors it operation for operation.
    pub fn weight(&self, x: f32, y: f32) -> f32 {
        let (hx, hy) = (0.5 * self.xwidth, 0.5 * self.ywidth);
        if x.abs() > hx || y.abs() > hy {
            return 0.0;
        }
        match self.filter {
            FilterKind::Box => 1.0,
            FilterKind::Triangle => (1.0 - x.abs() / hx) * (1.0 - y.abs() / hy),
            FilterKind::Gaussian => {
                let (u, v) = (x / hx, y / hy);
                (-2.0 * (u * u + v * v)).exp()
            }
            FilterKind::CatmullRom => {
                let r2 = x * x + y * y;
                let r = r2.sqrt();
                if r < 1.0 {
                    3.0 * r * r2 - 5.0 * r2 + 2.0
                } else if r < 2.0 {
                    -r * r2 + 5.0 * r2 - 8.0 * r + 4.0
                } else {
                    0.0
                }
            }
            FilterKind::Sinc => windowed_sinc(x, self.xwidth) * windowed_sinc(y, self.ywidth),
        }
    }
}

/// RenderMan's `RiSincFilter` in one axis: `cos(0.5 pi x / width) *
/// sin(pi x) / (pi x)`, 1 at 0.
fn windowed_sinc(x: f32, width: f32) -> f32 {
    if x == 0.0 {
        return 1.0;
    }
    let px = std::f32::consts::PI * x;
    (0.5 * px / width).cos() * px.sin() / px
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_cover_the_window() {
        assert_eq!(PixelFilter::PIXEL_BOX.radius(), [0, 0]);
        assert_eq!(PixelFilter::default().radius(), [1, 1]);
        let catmull_rom = PixelFilter {
            filter: FilterKind::CatmullRom,
            xwidth: 3.0,
            ywidth: 4.0,
        };
        assert_eq!(catmull_rom.radius(), [1, 2]);
    }

    #[test]
    fn weights_follow_the_definitions() {
        let g = PixelFilter::default();
        assert_eq!(g.weight(0.0, 0.0), 1.0);
        // x' = 2 * 0.5 / 2 = 0.5: exp(-2 * 0.25).
        assert!((g.weight(0.5, 0.0) - (-0.5f32).exp()).abs() < 1e-7);
        assert_eq!(g.weight(1.01, 0.0), 0.0);
        let c = PixelFilter {
            filter: FilterKind::CatmullRom,
            xwidth: 4.0,
            ywidth: 4.0,
        };
        assert_eq!(c.weight(0.0, 0.0), 2.0);
        assert!(c.weight(1.5, 0.0) < 0.0, "the negative lobe");
        assert_eq!(c.weight(0.0, 1.0), 0.0);
        let t = PixelFilter {
            filter: FilterKind::Triangle,
            xwidth: 2.0,
            ywidth: 2.0,
        };
        assert_eq!(t.weight(0.5, 0.5), 0.25);
        for kind in FilterKind::ALL {
            assert_eq!(FilterKind::from_name(kind.name()), Some(kind));
        }
    }
}
