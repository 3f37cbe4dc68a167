//! Lights and the specular term.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::defaults::{default_light_direction, default_one, default_white};

/// A light (`[[lights]]`): a distant light shining along `direction`, or,
/// when `position` is given, a point light (RenderMan's `pointlight`) whose
/// intensity falls off with the square of the distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LightToml", into = "LightToml")]
pub struct Light {
    /// The direction a distant light travels (from the light towards the
    /// scene); must be non-zero. Default `[0.4, 0.8, -1.0]`. Unused by a
    /// point light.
    pub direction: Vec3,
    /// A point light's position in world space; `None` for a distant light.
    pub position: Option<Vec3>,
    /// Linear RGB colour (default white).
    pub color: Vec3,
    /// Intensity multiplier (default 1). A point light at distance `d`
    /// contributes `intensity * color / d^2`, as RenderMan's `pointlight`.
    pub intensity: f32,
}

impl Light {
    /// A point light at `position`.
    pub fn point(position: Vec3, color: Vec3, intensity: f32) -> Self {
        Light {
            direction: default_light_direction(),
            position: Some(position),
            color,
            intensity,
        }
    }
}

impl Default for Light {
    fn default() -> Self {
        Light {
            direction: default_light_direction(),
            position: None,
            color: default_white(),
            intensity: 1.0,
        }
    }
}

/// `[[lights]]` as written: `direction` and `position` exclude each other.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightToml {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    direction: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<Vec3>,
    #[serde(default = "default_white")]
    color: Vec3,
    #[serde(default = "default_one")]
    intensity: f32,
}

impl TryFrom<LightToml> for Light {
    type Error = String;

    fn try_from(light: LightToml) -> Result<Self, String> {
        if light.direction.is_some() && light.position.is_some() {
            return Err(
                "a light has `direction` (a distant light) or `position` (a point light), not both"
                    .into(),
            );
        }
        Ok(Light {
            direction: light.direction.unwrap_or_else(default_light_direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
        })
    }
}

impl From<Light> for LightToml {
    fn from(light: Light) -> Self {
        LightToml {
            direction: light.position.is_none().then_some(light.direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
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
