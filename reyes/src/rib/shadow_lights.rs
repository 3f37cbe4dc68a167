//! The shadows of PRMan's shadowed standard lights: `shadowspot` and
//! `shadowdistant` (`shadowname`) and `shadowpoint` (`sfpx` ... `sfnz`,
//! one map per direction), with the `shadow()` lookup's `samples`, `width`
//! (or `swidth` and `twidth`), `blur` and `bias`.
//!
//! A map's name is relative to the current directory, as `MakeShadow`'s
//! output is ([`super::requests`]): the name `MakeShadow` wrote is the name
//! a light reads. An empty name is no map (RenderMan's default): a
//! `shadowspot` without one is a `spotlight`.

use std::path::{Path, PathBuf};

use super::interp::Interp;
use super::parser::Value;
use super::state::{self, Param};
use crate::scene::{LightShadow, ShadowMaps};
use crate::shadow::{
    DEFAULT_SHADOW_BIAS, DEFAULT_SHADOW_SAMPLES, MAX_SHADOW_SAMPLES, ShadowFilter,
};

/// `shadowpoint`'s maps, one per direction: +x, -x, +y, -y, +z, -z.
pub(super) const POINT_MAPS: [&str; 6] = ["sfpx", "sfnx", "sfpy", "sfny", "sfpz", "sfnz"];

/// Parameter `name` as one string, if given (`"name"` or `["name"]`).
fn param_str<'a>(params: &'a [Param], name: &str) -> Result<Option<&'a str>, String> {
    let Some(param) = params.iter().find(|p| p.name == name) else {
        return Ok(None);
    };
    match &param.value {
        Value::Str(s) => Ok(Some(s.as_str())),
        Value::Strs(v) if v.len() == 1 => Ok(Some(v[0].as_str())),
        _ => Err(format!("parameter {name:?} must be one string")),
    }
}

impl Interp {
    /// The shadow of a shadowed light whose maps are the parameters `maps`
    /// (those given and not empty, in that order); `None`, with a warning
    /// for `shadowpoint`, when none names a map.
    pub(super) fn light_shadow(
        &mut self,
        params: &[Param],
        maps: &[&str],
        file: &Path,
        line: usize,
    ) -> Result<Option<LightShadow>, String> {
        let mut files = Vec::new();
        for name in maps {
            if let Some(map) = param_str(params, name)?.filter(|m| !m.is_empty()) {
                files.push(PathBuf::from(map));
            }
        }
        let filter = self.shadow_filter(params, file, line)?;
        if files.is_empty() {
            if maps.len() > 1 {
                self.warn(
                    file,
                    line,
                    format!(
                        "shadowpoint names no shadow map ({}): it lights as a pointlight, unshadowed",
                        maps.join(", ")
                    ),
                );
            }
            return Ok(None);
        }
        Ok(Some(LightShadow {
            maps: ShadowMaps::Files(files),
            filter,
        }))
    }

    /// `samples`, `width` (`swidth`, `twidth`), `blur` and `bias`; a value
    /// out of range is replaced, with a warning.
    fn shadow_filter(
        &mut self,
        params: &[Param],
        file: &Path,
        line: usize,
    ) -> Result<ShadowFilter, String> {
        let defaults = ShadowFilter::default();
        let samples = state::param_f(params, "samples", f64::from(DEFAULT_SHADOW_SAMPLES))?;
        let samples_used = if samples.is_finite() {
            samples.round().clamp(1.0, f64::from(MAX_SHADOW_SAMPLES))
        } else {
            f64::from(DEFAULT_SHADOW_SAMPLES)
        };
        if samples_used != samples {
            self.warn(
                file,
                line,
                format!("shadow samples {samples}; using {samples_used}"),
            );
        }
        let width = state::param_f(params, "width", f64::from(defaults.width))?;
        let swidth = state::param_f(params, "swidth", width)?;
        let twidth = state::param_f(params, "twidth", width)?;
        if swidth != twidth {
            self.warn(
                file,
                line,
                format!(
                    "shadow swidth {swidth} and twidth {twidth}: the filter's region is square; using the larger"
                ),
            );
        }
        let mut value = |name: &str, given: f64, default: f32| {
            let as_f32 = given as f32;
            if as_f32.is_finite() && as_f32 >= 0.0 {
                return as_f32;
            }
            self.warn(
                file,
                line,
                format!("shadow {name} {given} (it is >= 0); using {default}"),
            );
            default
        };
        let width = value("width", swidth.max(twidth), defaults.width);
        let blur = state::param_f(params, "blur", 0.0)?;
        let blur = value("blur", blur, 0.0);
        let bias = state::param_f(params, "bias", f64::from(DEFAULT_SHADOW_BIAS))?;
        let bias = value("bias", bias, DEFAULT_SHADOW_BIAS);
        Ok(ShadowFilter {
            samples: samples_used as u32,
            width,
            blur,
            bias,
        })
    }
}
