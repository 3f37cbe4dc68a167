//! `LightSource` and `Illuminate`: RenderMan's light list (`distantlight`,
//! `pointlight`, `spotlight` and `ambientlight`, and the shadowed
//! `shadowdistant`, `shadowpoint` and `shadowspot` of `super::shadow_lights`),
//! mapped onto the renderer's scene-wide lights.
//!
//! In RenderMan the set of lights that are on is an attribute: a light
//! defined inside `AttributeBegin`/`AttributeEnd` is off after the block, and
//! `Illuminate handle 0|1` switches a light for the geometry that follows.
//! The renderer lights every object with every light, so a light is kept
//! when it is on for at least one primitive (with a warning when it is off
//! for others) and dropped, with a warning, when it lights none.

use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};

use super::interp::{Interp, camera_to_world};
use super::parser::Value;
use super::state;
use crate::scene::Light;

/// Lights whose on/off state follows the attribute stack: the bits of
/// [`state::Attributes::lights_on`]. Later ones are on from their
/// definition to the end of the world block, with a warning.
pub const SWITCHABLE_LIGHTS: usize = 64;

/// A standard light, in world space.
#[derive(Debug, Clone)]
pub struct RibLight {
    /// The light as the scene holds it.
    pub light: Light,
    /// The handle it was declared with (a number or a string), if any.
    pub handle: Option<String>,
    /// Whether it is on for at least one primitive.
    pub lights_something: bool,
    /// Whether it is off for at least one primitive declared after it.
    pub dark_somewhere: bool,
    /// Where it was declared, for warnings.
    pub file: PathBuf,
    /// Its line.
    pub line: usize,
}

/// The handle argument of `LightSource` or `Illuminate`, as text.
fn handle_text(value: &Value) -> Option<String> {
    match value {
        Value::Num(n) => Some(format!("{n}")),
        other => other.str().map(str::to_owned),
    }
}

/// A light's camera-space `direction` as the scene's f32 vector: as it is
/// when f32 holds it (and its length), else its unit vector (only the
/// direction of a distant or spot light matters); `None` when it has none.
fn direction_f32(direction: DVec3) -> Option<glam::Vec3> {
    let d = direction.as_vec3();
    if d.is_finite() && d.length_squared().is_normal() {
        return Some(d);
    }
    let unit = direction.normalize_or_zero();
    (unit != DVec3::ZERO).then(|| unit.as_vec3())
}

impl Interp {
    /// Why a light from `from` to `to` has no direction in camera space.
    fn direction_problem(&self, from: DVec3, to: DVec3, direction: DVec3) -> String {
        if from == to {
            "with no direction (from = to)".to_owned()
        } else if direction.is_finite() {
            "whose direction vanishes in camera space (the transform scales it to 0)".to_owned()
        } else {
            format!(
                "whose direction is not finite in camera space ({})",
                self.overflow_cause()
            )
        }
    }

    /// `LightSource name [handle] params...`.
    pub(super) fn light_source(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        // The light handle (a number or a string) is optional; parameters
        // come in pairs.
        let positional = if v.len().is_multiple_of(2) { 2 } else { 1 };
        let (args, params, _) = state::split_params(v, positional, &self.declared)?;
        let handle = args.get(1).and_then(handle_text);
        let m = camera_to_world() * self.camera.unwrap_or(DMat4::IDENTITY) * self.xf.open;
        let intensity = state::param_f(&params, "intensity", 1.0)?;
        let color = state::param_v3(&params, "lightcolor", DVec3::ONE)?;
        let color = color.as_vec3();
        let intensity = intensity as f32;
        if !(color.is_finite() && intensity.is_finite()) {
            self.warn(
                file,
                line,
                "LightSource whose intensity or lightcolor is beyond f32; ignored".into(),
            );
            return Ok(());
        }
        let shader = state::arg_str(&args, 0, "the shader")?;
        let shadow = match shader {
            "shadowspot" | "shadowdistant" => self.light_shadow(&params, &["shadowname"], file, line)?,
            "shadowpoint" => self.light_shadow(&params, &super::shadow_lights::POINT_MAPS, file, line)?,
            _ => None,
        };

        let light = |light: Light| RibLight {
            light: Light {
                color,
                intensity,
                shadow: shadow.clone(),
                ..light
            },
            handle: handle.clone(),
            lights_something: false,
            dark_somewhere: false,
            file: file.to_path_buf(),
            line,
        };
        match shader {
            "distantlight" | "shadowdistant" => {
                let from = state::param_v3(&params, "from", DVec3::ZERO)?;
                let to = state::param_v3(&params, "to", DVec3::Z)?;
                let direction = m.transform_point3(to) - m.transform_point3(from);
                match direction_f32(direction) {
                    Some(direction) => {
                        let distant = Light {
                            direction,
                            ..Light::default()
                        };
                        self.add_light(light(distant), file, line);
                    }
                    None => {
                        let why = self.direction_problem(from, to, direction);
                        self.warn(file, line, format!("distantlight {why}; ignored"));
                    }
                }
            }
            "pointlight" | "shadowpoint" => {
                let from = state::param_v3(&params, "from", DVec3::ZERO)?;
                let position = m.transform_point3(from);
                if position.as_vec3().is_finite() {
                    let point = Light::point(position.as_vec3(), color, intensity);
                    self.add_light(light(point), file, line);
                } else {
                    let cause = self.overflow_cause();
                    self.warn(
                        file,
                        line,
                        format!("pointlight whose position is beyond f32 in camera space ({cause}); ignored"),
                    );
                }
            }
            "spotlight" | "shadowspot" => self.spotlight(&params, m, file, line, light)?,
            "ambientlight" => {
                let ambient = Light::ambient(color, intensity);
                self.add_light(light(ambient), file, line);
            }
            other => self.warn(
                file,
                line,
                format!("LightSource {other:?} is not supported; ignored"),
            ),
        }
        Ok(())
    }

    /// `LightSource "spotlight"`: `from`, `to`, `coneangle` and
    /// `conedeltaangle` (radians, as RenderMan's) and `beamdistribution`.
    fn spotlight(
        &mut self,
        params: &[state::Param],
        m: DMat4,
        file: &Path,
        line: usize,
        light: impl Fn(Light) -> RibLight,
    ) -> Result<(), String> {
        let from = state::param_v3(params, "from", DVec3::ZERO)?;
        let to = state::param_v3(params, "to", DVec3::Z)?;
        let position = m.transform_point3(from);
        let direction = m.transform_point3(to) - position;
        let cone = state::param_f(params, "coneangle", 30f64.to_radians())?;
        let delta = state::param_f(params, "conedeltaangle", 5f64.to_radians())?;
        let beam = state::param_f(params, "beamdistribution", 2.0)?;
        // Values no spotlight can have are errors; angles past what this
        // renderer draws are clamped below, with a warning.
        for (name, value) in [
            ("coneangle", cone),
            ("conedeltaangle", delta),
            ("beamdistribution", beam),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(format!(
                    "spotlight {name} {value} is out of range: it must be a finite number >= 0"
                ));
            }
        }
        let (cone, delta) = (cone.to_degrees(), delta.to_degrees());
        if !position.as_vec3().is_finite() {
            let cause = self.overflow_cause();
            self.warn(
                file,
                line,
                format!("spotlight whose position is beyond f32 in camera space ({cause}); ignored"),
            );
            return Ok(());
        }
        let Some(direction) = direction_f32(direction) else {
            let why = self.direction_problem(from, to, direction);
            self.warn(file, line, format!("spotlight {why}; ignored"));
            return Ok(());
        };
        let cone_clamped = cone.clamp(1e-3, 90.0);
        if cone_clamped != cone {
            self.warn(
                file,
                line,
                format!("spotlight coneangle of {cone} degrees; using {cone_clamped}"),
            );
        }
        let delta_clamped = delta.clamp(0.0, cone_clamped);
        if delta_clamped != delta {
            self.warn(
                file,
                line,
                format!("spotlight conedeltaangle of {delta} degrees; using {delta_clamped}"),
            );
        }
        let beam_clamped = if beam.is_finite() { beam.max(0.0) } else { 2.0 };
        if beam_clamped != beam {
            self.warn(
                file,
                line,
                format!("spotlight beamdistribution {beam}; using {beam_clamped}"),
            );
        }
        let mut spot = Light::spot(
            position.as_vec3(),
            direction,
            glam::Vec3::ONE,
            1.0,
        );
        spot.cone_angle_degrees = cone_clamped as f32;
        spot.cone_delta_degrees = delta_clamped as f32;
        spot.beam_distribution = beam_clamped as f32;
        self.add_light(light(spot), file, line);
        Ok(())
    }

    /// Adds `light` and turns it on in the current attribute block.
    fn add_light(&mut self, light: RibLight, file: &Path, line: usize) {
        let index = self.lights.len();
        self.lights.push(light);
        if index < SWITCHABLE_LIGHTS {
            self.attrs.lights_on |= 1 << index;
        } else {
            self.warn_once(
                "switchable lights",
                file,
                line,
                format!(
                    "more than {SWITCHABLE_LIGHTS} lights: the later ones stay on to the end of the world block (AttributeEnd and Illuminate do not switch them)"
                ),
            );
        }
    }

    /// `Illuminate handle onoff`.
    pub(super) fn illuminate(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        if v.len() != 2 {
            return Err("Illuminate takes a light handle and 0 or 1".into());
        }
        let handle =
            handle_text(&v[0]).ok_or("Illuminate: the light handle is a number or a string")?;
        let on = state::arg_f(v, 1, "the on/off flag")? != 0.0;
        let Some(index) = self
            .lights
            .iter()
            .rposition(|l| l.handle.as_deref() == Some(handle.as_str()))
        else {
            self.warn(
                file,
                line,
                format!(
                    "Illuminate {handle:?}: no light has this handle; ignored"
                ),
            );
            return Ok(());
        };
        if index >= SWITCHABLE_LIGHTS {
            return Ok(()); // Warned when it was added.
        }
        if on {
            self.attrs.lights_on |= 1 << index;
        } else {
            self.attrs.lights_on &= !(1 << index);
        }
        Ok(())
    }

    /// Records which lights are on for a primitive being emitted.
    pub(super) fn lights_for_primitive(&mut self) {
        let on = self.attrs.lights_on;
        for (index, light) in self.lights.iter_mut().enumerate() {
            if index >= SWITCHABLE_LIGHTS || on & (1 << index) != 0 {
                light.lights_something = true;
            } else {
                light.dark_somewhere = true;
            }
        }
    }

    /// The lights the scene keeps: those that light at least one primitive
    /// (all of them when there is no geometry), with warnings for the ones
    /// dropped or lighting more than RenderMan would.
    pub(super) fn scene_lights(&mut self) -> Vec<RibLight> {
        let any_geometry = !self.prims.is_empty();
        let lights = std::mem::take(&mut self.lights);
        let mut kept = Vec::new();
        for light in lights {
            let name = light
                .handle
                .as_deref()
                .map_or_else(|| "a light".to_owned(), |h| format!("light {h:?}"));
            if any_geometry && !light.lights_something {
                self.warn(
                    &light.file,
                    light.line,
                    format!(
                        "{name} is off (AttributeEnd or Illuminate) for every primitive; ignored"
                    ),
                );
                continue;
            }
            if light.dark_somewhere {
                self.warn(
                    &light.file,
                    light.line,
                    format!("{name} is off for some primitives, but the renderer's lights are scene-wide: it lights them all"),
                );
            }
            kept.push(light);
        }
        kept
    }
}
