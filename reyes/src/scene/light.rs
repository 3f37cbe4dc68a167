//! Lights (RenderMan's standard lights) and the scene-wide specular term.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::defaults::{default_light_direction, default_one, default_white};

/// What kind of light a [`Light`] is: RenderMan's standard lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum LightKind {
    /// `distantlight`: parallel rays along `direction`.
    #[default]
    Distant,
    /// `pointlight`: from `position`, falling off as `1 / d^2`.
    Point,
    /// `spotlight`: from `position` along `direction`, within a cone.
    Spot,
    /// `ambientlight`: light from nowhere in particular, added by the
    /// surfaces' `ambient()`.
    Ambient,
}

/// A light (`[[lights]]`): one of RenderMan's standard lights
/// ([`LightKind`]). Without a `kind`, a light with a `position` is a point
/// light and one without is a distant light.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LightToml", into = "LightToml")]
pub struct Light {
    /// The kind of light.
    pub kind: LightKind,
    /// The direction a distant light or a spotlight shines (from the light
    /// towards the scene); must be non-zero. Default `[0.4, 0.8, -1.0]`.
    pub direction: Vec3,
    /// A point light's or a spotlight's position in world space.
    pub position: Option<Vec3>,
    /// Linear RGB colour (default white).
    pub color: Vec3,
    /// Intensity multiplier (default 1). A point light or a spotlight at
    /// distance `d` contributes `intensity * color / d^2`, as RenderMan's.
    pub intensity: f32,
    /// A spotlight's `coneangle` in degrees (default 30): no light beyond
    /// this angle from its axis.
    pub cone_angle_degrees: f32,
    /// A spotlight's `conedeltaangle` in degrees (default 5): the light
    /// fades out (a smoothstep) over this angle inside the cone's edge.
    pub cone_delta_degrees: f32,
    /// A spotlight's `beamdistribution` (default 2): the light falls off as
    /// `cos^beamdistribution` of the angle from its axis.
    pub beam_distribution: f32,
}

impl Light {
    /// A point light at `position`.
    pub fn point(position: Vec3, color: Vec3, intensity: f32) -> Self {
        Light {
            kind: LightKind::Point,
            position: Some(position),
            color,
            intensity,
            ..Light::default()
        }
    }

    /// A spotlight at `position` shining along `direction`, with
    /// RenderMan's default cone (30 degrees, fading over the last 5) and
    /// beam distribution (2).
    pub fn spot(position: Vec3, direction: Vec3, color: Vec3, intensity: f32) -> Self {
        Light {
            kind: LightKind::Spot,
            direction,
            position: Some(position),
            color,
            intensity,
            ..Light::default()
        }
    }

    /// An ambient light.
    pub fn ambient(color: Vec3, intensity: f32) -> Self {
        Light {
            kind: LightKind::Ambient,
            color,
            intensity,
            ..Light::default()
        }
    }
}

impl Default for Light {
    fn default() -> Self {
        Light {
            kind: LightKind::Distant,
            direction: default_light_direction(),
            position: None,
            color: default_white(),
            intensity: 1.0,
            cone_angle_degrees: DEFAULT_CONE_ANGLE_DEGREES,
            cone_delta_degrees: DEFAULT_CONE_DELTA_DEGREES,
            beam_distribution: DEFAULT_BEAM_DISTRIBUTION,
        }
    }
}

/// RenderMan's `spotlight` default `coneangle`, `radians(30)`.
pub const DEFAULT_CONE_ANGLE_DEGREES: f32 = 30.0;
/// RenderMan's `spotlight` default `conedeltaangle`, `radians(5)`.
pub const DEFAULT_CONE_DELTA_DEGREES: f32 = 5.0;
/// RenderMan's `spotlight` default `beamdistribution`.
pub const DEFAULT_BEAM_DISTRIBUTION: f32 = 2.0;

/// `[[lights]]` as written.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightToml {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    kind: Option<LightKind>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    direction: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<Vec3>,
    #[serde(default = "default_white")]
    color: Vec3,
    #[serde(default = "default_one")]
    intensity: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cone_angle_degrees: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    cone_delta_degrees: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    beam_distribution: Option<f32>,
}

impl TryFrom<LightToml> for Light {
    type Error = String;

    fn try_from(light: LightToml) -> Result<Self, String> {
        let kind = match light.kind {
            Some(kind) => kind,
            None if light.direction.is_some() && light.position.is_some() => {
                return Err(
                    "a light has `direction` (a distant light) or `position` (a point light), not both; a spotlight has both and `kind = \"spot\"`"
                        .into(),
                );
            }
            None if light.position.is_some() => LightKind::Point,
            None => LightKind::Distant,
        };
        let spot_only = light.cone_angle_degrees.is_some()
            || light.cone_delta_degrees.is_some()
            || light.beam_distribution.is_some();
        match kind {
            LightKind::Distant if light.position.is_some() => {
                return Err("a distant light has no `position`".into());
            }
            LightKind::Point if light.position.is_none() => {
                return Err("a point light needs a `position`".into());
            }
            LightKind::Point if light.direction.is_some() => {
                return Err("a point light has no `direction`".into());
            }
            LightKind::Spot if light.position.is_none() || light.direction.is_none() => {
                return Err("a spotlight needs a `position` and a `direction`".into());
            }
            LightKind::Ambient if light.position.is_some() || light.direction.is_some() => {
                return Err("an ambient light has no `position` or `direction`".into());
            }
            _ => {}
        }
        if spot_only && kind != LightKind::Spot {
            return Err(
                "`cone_angle_degrees`, `cone_delta_degrees` and `beam_distribution` belong to a spotlight (`kind = \"spot\"`)"
                    .into(),
            );
        }
        Ok(Light {
            kind,
            direction: light.direction.unwrap_or_else(default_light_direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
            cone_angle_degrees: light
                .cone_angle_degrees
                .unwrap_or(DEFAULT_CONE_ANGLE_DEGREES),
            cone_delta_degrees: light
                .cone_delta_degrees
                .unwrap_or(DEFAULT_CONE_DELTA_DEGREES),
            beam_distribution: light.beam_distribution.unwrap_or(DEFAULT_BEAM_DISTRIBUTION),
        })
    }
}

impl From<Light> for LightToml {
    fn from(light: Light) -> Self {
        let spot = light.kind == LightKind::Spot;
        let has_direction = matches!(light.kind, LightKind::Distant | LightKind::Spot);
        LightToml {
            kind: Some(light.kind),
            direction: has_direction.then_some(light.direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
            cone_angle_degrees: spot.then_some(light.cone_angle_degrees),
            cone_delta_degrees: spot.then_some(light.cone_delta_degrees),
            beam_distribution: spot.then_some(light.beam_distribution),
        }
    }
}

/// Blinn-Phong specular term (`[specular]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Specular {
    /// Specular weight (default 0.25).
    pub strength: f32,
    /// Blinn-Phong exponent, >= 0 (default 32).
    pub shininess: f32,
}

impl Default for Specular {
    fn default() -> Self {
        Specular {
            strength: 0.25,
            shininess: 32.0,
        }
    }
}
