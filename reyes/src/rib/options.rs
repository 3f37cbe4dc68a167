//! The interpreter's options: the requests that set up the camera and the
//! image (before `WorldBegin`, except `ShadingRate`), and the 8-bit
//! output's `Exposure` and `Quantize`.

use std::path::Path;

use super::interp::Interp;
use super::parser::Value;
use super::state;
use crate::depth::DepthFilter;
use crate::filter::{FilterKind, PixelFilter};
use crate::params::MAX_SHADING_RATE;
use crate::quantize::{Exposure, Quantize};

/// Options set before `WorldBegin`.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// `Format` width, height, pixel aspect.
    pub format: Option<(u32, u32, f64)>,
    /// `PixelSamples` x, y.
    pub pixel_samples: Option<(f64, f64)>,
    /// `ShadingRate`.
    pub shading_rate: Option<f64>,
    /// `Projection "perspective"` field of view in degrees (of the shorter side).
    pub fov: Option<f64>,
    /// Whether a perspective projection was requested (RenderMan's default
    /// is orthographic).
    pub perspective: bool,
    /// `ScreenWindow` left, right, bottom, top.
    pub screen_window: Option<[f64; 4]>,
    /// `FrameAspectRatio`.
    pub frame_aspect: Option<f64>,
    /// `Clipping` near, far.
    pub clipping: Option<(f64, f64)>,
    /// `Shutter` open, close.
    pub shutter: Option<(f64, f64)>,
    /// `DepthOfField` fstop, focal length, focal distance.
    pub dof: Option<(f64, f64, f64)>,
    /// `Display` file name.
    pub display: Option<String>,
    /// Whether that `Display`'s mode is `"z"`: the frame writes the depth
    /// output ([`crate::Aov::Z`]).
    pub depth_output: bool,
    /// `Hider "hidden" "depthfilter"` (min when absent).
    pub depth_filter: Option<DepthFilter>,
    /// `ShadingInterpolation`: `true` for `"smooth"`.
    pub smooth: Option<bool>,
    /// `PixelFilter` (RenderMan's default, `gaussian` 2 2, when absent).
    pub pixel_filter: Option<crate::filter::PixelFilter>,
    /// `Exposure` (RenderMan's default, gain 1 gamma 1, when absent).
    pub exposure: Option<crate::quantize::Exposure>,
    /// `Quantize "rgba"` (RenderMan's 8-bit default, 255 0 255 0.5, when
    /// absent).
    pub quantize: Option<crate::quantize::Quantize>,
    /// The times of the first `MotionBegin` block.
    pub motion_times: Option<(f64, f64)>,
}

/// RenderMan's default `Format`.
pub(super) const DEFAULT_FORMAT: (u32, u32) = (640, 480);

impl Options {
    /// The image size (`Format`, else RenderMan's default).
    pub fn image_size(&self) -> (u32, u32) {
        self.format.map_or(DEFAULT_FORMAT, |(w, h, _)| (w, h))
    }

    /// `ScreenWindow` left, right, bottom, top, or RenderMan's default for
    /// the image: the shorter side spans [-1, 1].
    pub fn screen_window_or_default(&self) -> [f64; 4] {
        let (width, height) = self.image_size();
        let aspect = f64::from(width) / f64::from(height);
        self.screen_window.unwrap_or(if aspect >= 1.0 {
            [-aspect, aspect, -1.0, 1.0]
        } else {
            [-1.0, 1.0, -1.0 / aspect, 1.0 / aspect]
        })
    }
}

impl Interp {
    /// Runs option request `name` (one of those matched by the caller).
    pub(super) fn option(
        &mut self,
        name: &str,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        let world = self.camera.is_some();
        match name {
            "Format" => {
                let n = state::all_nums(v, 3)?;
                let (w, h) = (n[0], n[1]);
                if !(1.0..=65536.0).contains(&w) || !(1.0..=65536.0).contains(&h) {
                    return Err(format!("resolution {w} x {h} is out of range"));
                }
                if w.fract() != 0.0 || h.fract() != 0.0 {
                    return Err(format!(
                        "resolution {w} x {h}: the width and height must be whole numbers of pixels"
                    ));
                }
                if n[2] != 1.0 && n[2] != -1.0 {
                    self.warn(
                        file,
                        line,
                        "Format: pixel aspect ratios other than 1 are not supported; using 1"
                            .into(),
                    );
                }
                self.opts.format = Some((w as u32, h as u32, n[2]));
            }
            "PixelSamples" => {
                let n = state::all_nums(v, 2)?;
                if !(n[0] > 0.0 && n[1] > 0.0) {
                    return Err(format!(
                        "{} {} is out of range: both counts must be > 0",
                        n[0], n[1]
                    ));
                }
                self.opts.pixel_samples = Some((n[0], n[1]));
            }
            "ShadingRate" => {
                // An attribute: before WorldBegin the frame's, inside the
                // world the current attribute block's (its objects').
                let r = state::all_nums(v, 1)?[0];
                if !(r.is_finite() && r > 0.0) {
                    return Err(format!(
                        "{r} is out of range: a shading rate is an area in pixels, > 0 (this renderer uses 0.01 to {MAX_SHADING_RATE})"
                    ));
                }
                let clamped = r.clamp(0.01, f64::from(MAX_SHADING_RATE));
                if clamped != r {
                    self.warn(
                        file,
                        line,
                        format!("ShadingRate {r} is out of range; using {clamped}"),
                    );
                }
                if world {
                    self.attrs.shading_rate = Some(clamped);
                } else {
                    self.opts.shading_rate = Some(clamped);
                }
            }
            "Projection" => {
                let (args, params, _) = state::split_params(v, 1, &self.declared)?;
                match state::arg_str(&args, 0, "the projection")? {
                    "perspective" => {
                        self.opts.perspective = true;
                        self.opts.fov = Some(state::param_f(&params, "fov", 90.0)?);
                    }
                    "orthographic" => self.opts.perspective = false,
                    other => {
                        self.warn(
                            file,
                            line,
                            format!("Projection {other:?} is not supported; using \"orthographic\" (RenderMan's default)"),
                        );
                        self.opts.perspective = false;
                    }
                }
            }
            "ScreenWindow" => {
                let n = state::all_nums(v, 4)?;
                let [l, r, b, t] = [n[0], n[1], n[2], n[3]];
                if !(l < r && b < t && [l, r, b, t].iter().all(|x| x.is_finite())) {
                    return Err(format!(
                        "ScreenWindow {l} {r} {b} {t}: needs left < right and bottom < top"
                    ));
                }
                let centre_x = (l + r) / 2.0;
                let centre_y = (b + t) / 2.0;
                if centre_x.abs() > 1e-9 * (r - l) || centre_y.abs() > 1e-9 * (t - b) {
                    self.warn(file, line, format!("ScreenWindow {l} {r} {b} {t} is off-centre, which the renderer's camera cannot show; centring it (same size)"));
                }
                self.opts.screen_window = Some([l, r, b, t]);
            }
            "FrameAspectRatio" => {
                let a = state::all_nums(v, 1)?[0];
                if !(a.is_finite() && a > 0.0) {
                    return Err(format!("FrameAspectRatio {a} must be > 0"));
                }
                self.opts.frame_aspect = Some(a);
            }
            "Clipping" => {
                let n = state::all_nums(v, 2)?;
                let (near, far) = (n[0], n[1]);
                if !(near > 0.0 && far > near) {
                    return Err(format!(
                        "{near} {far} is out of range: needs 0 < near < far"
                    ));
                }
                let eps = f64::from(crate::params::NEAR_EPS);
                if near < eps {
                    self.warn(
                        file,
                        line,
                        format!("Clipping near {near} is below the renderer's smallest near plane; using {eps}"),
                    );
                }
                self.opts.clipping = Some((near, far));
            }
            "Shutter" => {
                let n = state::all_nums(v, 2)?;
                self.opts.shutter = Some((n[0], n[1]));
            }
            "DepthOfField" => {
                let n = state::all_nums(v, 3)?;
                let (fstop, focal_length, focal_distance) = (n[0], n[1], n[2]);
                // Checked here, where the request is, rather than as the
                // scene's lens: the lens radius is derived, and the f32
                // overflow is this request's.
                if fstop > 0.0 && focal_length > 0.0 && focal_distance > 0.0 && fstop.is_finite() {
                    let aperture = focal_length / (2.0 * fstop);
                    if !((aperture as f32).is_finite() && (focal_distance as f32).is_finite()) {
                        return Err(format!(
                            "the lens radius (focallength / (2 fstop) = {aperture:e}) or the focal distance ({focal_distance:e}) is beyond f32"
                        ));
                    }
                }
                self.opts.dof = Some((fstop, focal_length, focal_distance));
            }
            "Display" => {
                let (args, _, _) = state::split_params(v, 3, &self.declared)?;
                let name = state::arg_str(&args, 0, "the file name")?;
                let depth = state::arg_str(&args, 2, "the mode")? == "z";
                if depth
                    && !world
                    && !name.starts_with('+')
                    && name.to_ascii_lowercase().ends_with(".png")
                {
                    return Err(format!(
                        "Display {:?} of mode \"z\": the depth output is 32-bit floats, which an 8-bit PNG cannot hold; name the file *.exr (or *.z, *.shad: written as a single-channel float EXR)",
                        crate::input::excerpt(name)
                    ));
                }
                if world {
                    self.warn(
                        file,
                        line,
                        "Display inside the world block is ignored (it is an option)".into(),
                    );
                } else if !name.starts_with('+') {
                    // The first name of the frame replaces the one given
                    // before it; outside frames the first name counts.
                    let first = match &mut self.frame {
                        Some(frame) => !std::mem::replace(&mut frame.display_set, true),
                        None => self.opts.display.is_none(),
                    };
                    if first {
                        self.opts.display = Some(name.to_owned());
                        self.opts.depth_output = depth;
                    }
                }
            }
            "PixelFilter" => {
                let name = state::arg_str(v, 0, "the filter")?;
                let xwidth = state::arg_f(v, 1, "the filter's x width")?;
                let ywidth = state::arg_f(v, 2, "the filter's y width")?;
                let Some(filter) = FilterKind::from_name(name) else {
                    return Err(format!(
                        "unknown filter {:?}; the renderer has {}",
                        crate::input::excerpt(name),
                        FilterKind::ALL.map(FilterKind::name).join(", ")
                    ));
                };
                let pixel_filter = PixelFilter {
                    filter,
                    xwidth: xwidth as f32,
                    ywidth: ywidth as f32,
                };
                if let Some(problem) = pixel_filter.problem() {
                    return Err(format!("PixelFilter {name:?}: {problem}"));
                }
                self.opts.pixel_filter = Some(pixel_filter);
            }
            "Hider" if world => self.warn(
                file,
                line,
                "Hider inside the world block is ignored (it is an option)".into(),
            ),
            "Hider" => self.hider(v, file, line)?,
            "Exposure" | "Quantize" if world => self.warn(
                file,
                line,
                format!("{name} inside the world block is ignored (it is an option)"),
            ),
            "Exposure" => {
                let n = state::all_nums(v, 2)?;
                let exposure = Exposure {
                    gain: n[0] as f32,
                    gamma: n[1] as f32,
                };
                if let Some(problem) = exposure.problem() {
                    return Err(format!("Exposure {} {}: {problem}", n[0], n[1]));
                }
                self.opts.exposure = Some(exposure);
            }
            "Quantize" => self.quantize(v, file, line)?,
            "ShadingInterpolation" => {
                let smooth = match state::arg_str(v, 0, "the interpolation")? {
                    "smooth" => true,
                    "constant" => false,
                    other => return Err(format!("unknown interpolation {other:?}")),
                };
                if self.opts.smooth.is_some_and(|old| old != smooth) {
                    self.warn(file, line, "ShadingInterpolation: the renderer has one for the whole scene; the last one is used".into());
                }
                self.opts.smooth = Some(smooth);
            }
            _ => unreachable!("only option requests"),
        }
        Ok(())
    }

    /// `Quantize type one min max ditheramplitude`: `"rgba"` sets the
    /// 8-bit image's quantization; `"z"` is accepted and ignored with a
    /// warning (no depth image is written); any other type is an error.
    fn quantize(&mut self, v: &[Value], file: &Path, line: usize) -> Result<(), String> {
        let kind = state::arg_str(v, 0, "the quantization type")?;
        let n = state::all_nums(&v[1..], 4)?;
        match kind {
            "rgba" => {
                let quantize = Quantize {
                    one: n[0] as f32,
                    min: n[1] as f32,
                    max: n[2] as f32,
                    dither_amplitude: n[3] as f32,
                };
                if let Some(problem) = quantize.problem() {
                    return Err(format!(
                        "Quantize \"rgba\" {} {} {} {}: {problem}",
                        n[0], n[1], n[2], n[3]
                    ));
                }
                self.opts.quantize = Some(quantize);
            }
            "z" => self.warn(
                file,
                line,
                "Quantize \"z\": the depth output is written as floats, never quantized; ignored"
                    .into(),
            ),
            other => {
                return Err(format!(
                    "unknown quantization type {:?}; RenderMan's are \"rgba\" and \"z\"",
                    crate::input::excerpt(other)
                ));
            }
        }
        Ok(())
    }

    /// `Hider "hidden" "depthfilter" name`: how the depth output makes a
    /// pixel's depth ([`DepthFilter`]). An unknown filter warns and the
    /// default, min, is used; another hider, and other parameters, warn and
    /// are ignored.
    fn hider(&mut self, v: &[Value], file: &Path, line: usize) -> Result<(), String> {
        let (args, params, _) = state::split_params(v, 1, &self.declared)?;
        let kind = state::arg_str(&args, 0, "the hider")?;
        if kind != "hidden" {
            self.warn(
                file,
                line,
                format!(
                    "Hider {:?}: the renderer has the \"hidden\" hider only; used instead",
                    crate::input::excerpt(kind)
                ),
            );
        }
        for param in params {
            if param.name != "depthfilter" {
                self.warn(
                    file,
                    line,
                    format!(
                        "Hider parameter {:?} is not supported; ignored",
                        crate::input::excerpt(&param.name)
                    ),
                );
                continue;
            }
            let name = match &param.value {
                Value::Str(name) => name.as_str(),
                Value::Strs(names) if names.len() == 1 => names[0].as_str(),
                _ => return Err("Hider \"depthfilter\" must be one string".into()),
            };
            let filter = DepthFilter::from_name(name).unwrap_or_else(|| {
                self.warn(
                    file,
                    line,
                    format!(
                        "Hider \"depthfilter\" {:?} is unknown; \"min\" is used (the renderer has {})",
                        crate::input::excerpt(name),
                        DepthFilter::ALL.map(DepthFilter::name).join(", ")
                    ),
                );
                DepthFilter::Min
            });
            self.opts.depth_filter = Some(filter);
        }
        Ok(())
    }
}
