//! The 8-bit output encoding: RenderMan's `Exposure` and `Quantize`
//! (RenderMan Interface Specification 3.2, `RiExposure` and `RiQuantize`),
//! applied to the resolve's linear float image.
//!
//! Each colour channel `c` of a resolved pixel becomes the 8-bit value
//!
//! ```text
//! c' = max(c * gain, 0) ^ (1 / gamma)                    Exposure
//! s  = sRGB(c')                                          the PNG's colour space
//! v  = clamp(round(one * s + dither * r), min, max)      Quantize
//! ```
//!
//! where `sRGB` is the IEC 61966-2-1 transfer function (continued above 1
//! by the same formula, so that `one < max` leaves room above white) and
//! `round` rounds halves up. Alpha (1 for every resolved pixel) is
//! quantized the same way without exposure or sRGB, as RenderMan's
//! `"rgba"` quantization does; with the defaults it is 255.
//!
//! The dither `r` in `[-1, 1)` is a hash of the pixel's absolute
//! coordinates and the channel, the same on every run, in every screen
//! tile and for both renderers:
//!
//! ```text
//! r = 2 * (hash(x, y, DITHER_STREAM, channel) >> 8) / 2^24 - 1
//! ```
//!
//! with `hash` the sample jitter's hash (`reyes::sampling::hash`) and
//! `channel` 0, 1, 2, 3 for r, g, b, a. The GPU renderer reads its float
//! image back and the CPU reference resolves into one; both encode it
//! here, on the host, so equal float values give equal 8-bit images. The EXR output is the float
//! image itself: neither exposure nor quantization touches it.

use image::{Rgba32FImage, RgbaImage};
use serde::{Deserialize, Serialize};

use crate::sampling::hash;

/// The `s` argument of the dither's `hash`: sample indices are below 64,
/// so no sample's jitter shares the dither's values.
pub const DITHER_STREAM: u32 = u32::MAX;

/// The largest `Quantize` dither amplitude accepted, in output codes: a
/// wider dither is noise over the whole range.
pub const MAX_DITHER: f32 = 255.0;

/// The largest `Quantize` `one` accepted: far beyond any useful scale of an
/// 8-bit output, and small enough that `one * s` stays exact to a code.
pub const MAX_ONE: f32 = 65_535.0;

/// RenderMan's `Exposure gain gamma`: `c' = (c * gain) ^ (1 / gamma)` on
/// each colour channel before quantization (`exposure = { gain, gamma }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Exposure {
    /// Scale of the linear value (default 1); `>= 0`.
    #[serde(default = "one_f32")]
    pub gain: f32,
    /// The output is raised to `1 / gamma` (default 1); `> 0`.
    #[serde(default = "one_f32")]
    pub gamma: f32,
}

fn one_f32() -> f32 {
    1.0
}

impl Default for Exposure {
    /// RenderMan's default: gain 1, gamma 1 (no change).
    fn default() -> Self {
        Exposure {
            gain: 1.0,
            gamma: 1.0,
        }
    }
}

impl Exposure {
    /// Why the exposure cannot be used, if it cannot: `gain` finite and
    /// `>= 0`, `gamma` finite and `> 0`. The message names the value and
    /// its valid range.
    pub fn problem(&self) -> Option<String> {
        if !(self.gain.is_finite() && self.gain >= 0.0) {
            return Some(format!("gain {} is outside [0, inf)", self.gain));
        }
        if !(self.gamma.is_finite() && self.gamma > 0.0) {
            return Some(format!("gamma {} is outside (0, inf)", self.gamma));
        }
        None
    }

    /// `max(c * gain, 0) ^ (1 / gamma)`; gamma 1 is no power at all, so
    /// that the default leaves every value exactly as it is.
    pub fn apply(&self, c: f32) -> f32 {
        let scaled = (c * self.gain).max(0.0);
        if self.gamma == 1.0 {
            scaled
        } else {
            scaled.powf(1.0 / self.gamma)
        }
    }
}

/// RenderMan's `Quantize "rgba" one min max ditheramplitude`:
/// `v = clamp(round(one * c + dither * r), min, max)` with `r` in `[-1, 1)`
/// (`quantize = { one, min, max, dither }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantize {
    /// The code of 1.0 (default 255); in `(0, MAX_ONE]`.
    #[serde(default = "default_one")]
    pub one: f32,
    /// The smallest code (default 0); a whole number in `[0, 255]`.
    #[serde(default)]
    pub min: f32,
    /// The largest code (default 255); a whole number in `[min, 255]`.
    #[serde(default = "default_max")]
    pub max: f32,
    /// The dither's amplitude in codes (default 0.5); in `[0, MAX_DITHER]`.
    #[serde(default = "default_dither", rename = "dither")]
    pub dither_amplitude: f32,
}

fn default_one() -> f32 {
    255.0
}
fn default_max() -> f32 {
    255.0
}
fn default_dither() -> f32 {
    0.5
}

impl Default for Quantize {
    /// RenderMan's default for 8-bit output: one 255, min 0, max 255,
    /// dither 0.5.
    fn default() -> Self {
        Quantize {
            one: default_one(),
            min: 0.0,
            max: default_max(),
            dither_amplitude: default_dither(),
        }
    }
}

impl Quantize {
    /// 8-bit codes without dither: `round(255 * c)` clamped to `[0, 255]`.
    pub const NO_DITHER: Quantize = Quantize {
        one: 255.0,
        min: 0.0,
        max: 255.0,
        dither_amplitude: 0.0,
    };

    /// Why the quantization cannot be used for 8-bit output, if it cannot:
    /// `one` finite in `(0, MAX_ONE]`, `min` and `max` whole numbers with
    /// `0 <= min <= max <= 255`, `dither` finite in `[0, MAX_DITHER]`. The
    /// message names the value and its valid range.
    pub fn problem(&self) -> Option<String> {
        let Quantize {
            one,
            min,
            max,
            dither_amplitude: dither,
        } = *self;
        if !(one > 0.0 && one <= MAX_ONE) {
            return Some(format!("one {one} is outside (0, {MAX_ONE}]"));
        }
        for (name, v) in [("min", min), ("max", max)] {
            if !((0.0..=255.0).contains(&v) && v.fract() == 0.0) {
                return Some(format!(
                    "{name} {v} is not a whole number in [0, 255] (the output has 8 bits)"
                ));
            }
        }
        if min > max {
            return Some(format!("min {min} is above max {max}: needs min <= max"));
        }
        if !(0.0..=MAX_DITHER).contains(&dither) {
            return Some(format!("dither {dither} is outside [0, {MAX_DITHER}]"));
        }
        None
    }

    /// The code of the already exposed and encoded value `s` at dither
    /// `r` (in `[-1, 1)`): `clamp(round(one * s + dither * r), min, max)`,
    /// halves rounded up. NaN gives `min`.
    pub fn code(&self, s: f32, r: f32) -> u8 {
        let x = self.one * s + self.dither_amplitude * r;
        let f = x.floor();
        let rounded = if x - f >= 0.5 { f + 1.0 } else { f };
        // `max` of NaN is the other operand: NaN becomes `min`.
        rounded.max(self.min).min(self.max) as u8
    }
}

/// The IEC 61966-2-1 transfer function (as [`crate::color::linear_to_srgb`]
/// on `[0, 1]`, operation for operation), continued above 1 by the same
/// formula; `c` must be `>= 0`.
fn srgb_encode(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The dither of channel `channel` of the pixel at absolute coordinates
/// `(x, y)`, in `[-1, 1)` (see the [module documentation](self)).
pub fn dither(x: u32, y: u32, channel: u32) -> f32 {
    const TWO_POW_24: f32 = 16_777_216.0;
    let u = (hash(x, y, DITHER_STREAM, channel) >> 8) as f32 / TWO_POW_24;
    2.0 * u - 1.0
}

/// How the resolve's linear values become 8-bit codes: an exposure and a
/// quantization.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Encoding {
    /// Applied to the colour channels first.
    pub exposure: Exposure,
    /// Applied to every channel last.
    pub quantize: Quantize,
}

impl Encoding {
    /// No exposure, no dither: the linear value encoded as sRGB and
    /// rounded to the nearest code (the pictures of data, [`crate::Aov`],
    /// whose colours are not to be changed).
    pub const PLAIN: Encoding = Encoding {
        exposure: Exposure {
            gain: 1.0,
            gamma: 1.0,
        },
        quantize: Quantize::NO_DITHER,
    };

    /// The 8-bit code of colour channel `channel` (0, 1 or 2) of value `c`
    /// at absolute pixel `(x, y)`.
    pub fn color_code(&self, c: f32, x: u32, y: u32, channel: u32) -> u8 {
        let s = srgb_encode(self.exposure.apply(c));
        self.quantize.code(s, self.dither_at(x, y, channel))
    }

    /// The 8-bit code of alpha `a` at absolute pixel `(x, y)`: quantized
    /// only.
    pub fn alpha_code(&self, a: f32, x: u32, y: u32) -> u8 {
        self.quantize.code(a, self.dither_at(x, y, 3))
    }

    /// The dither, or exactly 0 without one (no hash to compute).
    fn dither_at(&self, x: u32, y: u32, channel: u32) -> f32 {
        if self.quantize.dither_amplitude == 0.0 {
            0.0
        } else {
            dither(x, y, channel)
        }
    }

    /// Encodes a linear RGBA image whose top-left pixel is at absolute
    /// coordinates `origin` (a screen tile's corner; `[0, 0]` for a whole
    /// frame). Large images are encoded in bands of rows on several
    /// threads; every pixel is a function of its value and coordinates
    /// alone, so the result does not depend on the split.
    pub fn encode(&self, linear: &Rgba32FImage, origin: [u32; 2]) -> RgbaImage {
        let (width, height) = linear.dimensions();
        let mut image = RgbaImage::new(width, height);
        let row_len = 4 * width as usize;
        if row_len == 0 || height == 0 {
            return image;
        }
        let encode_rows = |first_row: u32, out: &mut [u8], input: &[f32]| {
            for (i, (out, pixel)) in out
                .chunks_exact_mut(4)
                .zip(input.chunks_exact(4))
                .enumerate()
            {
                let x = origin[0] + (i % width as usize) as u32;
                let y = origin[1] + first_row + (i / width as usize) as u32;
                for c in 0..3 {
                    out[c] = self.color_code(pixel[c], x, y, c as u32);
                }
                out[3] = self.alpha_code(pixel[3], x, y);
            }
        };
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
        // Below about a quarter million pixels a thread costs more than it saves.
        let bands = threads.min((width as usize * height as usize).div_ceil(1 << 18));
        let rows_per_band = (height as usize).div_ceil(bands.max(1));
        let out = image.as_mut();
        let input = linear.as_raw().as_slice();
        if bands <= 1 {
            encode_rows(0, out, input);
            return image;
        }
        std::thread::scope(|scope| {
            for (band, (out, input)) in out
                .chunks_mut(rows_per_band * row_len)
                .zip(input.chunks(rows_per_band * row_len))
                .enumerate()
            {
                let first_row = (band * rows_per_band) as u32;
                scope.spawn(move || encode_rows(first_row, out, input));
            }
        });
        image
    }
}

#[cfg(test)]
mod tests;
