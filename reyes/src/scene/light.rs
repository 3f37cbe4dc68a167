//! Lights (RenderMan's standard lights) and the scene-wide specular term.

use std::path::PathBuf;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::shadow::{DEFAULT_SHADOW_BIAS, DEFAULT_SHADOW_SAMPLES, ShadowFilter};

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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// The light's shadow, if it casts one (not for ambient lights).
    pub shadow: Option<LightShadow>,
}

/// Where a light's shadow maps come from.
#[derive(Debug, Clone, PartialEq)]
pub enum ShadowMaps {
    /// Shadow map files (RenderMan's `shadowname`; a point light's six
    /// maps, one per direction), relative to the scene file's directory.
    Files(Vec<PathBuf>),
    /// The renderer renders the map from the light itself before the
    /// frame: `map_size` texels on the longer side.
    Automatic {
        /// The map's larger side in texels.
        map_size: u32,
    },
}

/// The default side of an automatic shadow map.
pub const DEFAULT_SHADOW_MAP_SIZE: u32 = 1024;
/// The largest side of an automatic shadow map.
pub const MAX_SHADOW_MAP_SIZE: u32 = 8192;

/// A light's shadow: its maps and how they are looked up.
#[derive(Debug, Clone, PartialEq)]
pub struct LightShadow {
    /// The maps.
    pub maps: ShadowMaps,
    /// The lookup's filter (`samples`, `width`, `blur`, `bias`).
    pub filter: ShadowFilter,
}

impl LightKind {
    /// Its name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            LightKind::Distant => "distant",
            LightKind::Point => "point",
            LightKind::Spot => "spot",
            LightKind::Ambient => "ambient",
        }
    }
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
            shadow: None,
        }
    }
}

/// RenderMan's `spotlight` default `coneangle`, `radians(30)`.
pub const DEFAULT_CONE_ANGLE_DEGREES: f32 = 30.0;
/// RenderMan's `spotlight` default `conedeltaangle`, `radians(5)`.
pub const DEFAULT_CONE_DELTA_DEGREES: f32 = 5.0;
/// RenderMan's `spotlight` default `beamdistribution`.
pub const DEFAULT_BEAM_DISTRIBUTION: f32 = 2.0;

/// A light's `shadow_map`: one file, or a point light's several.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(untagged)]
enum ShadowMapFiles {
    One(PathBuf),
    Several(Vec<PathBuf>),
}

/// `[[lights]]` as written.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
    /// Automatic shadows: the renderer renders the map.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    shadows: Option<bool>,
    /// Shadow map files instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    shadow_map: Option<ShadowMapFiles>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    map_size: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    bias: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    blur: Option<f32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    samples: Option<u32>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    filter_width: Option<f32>,
}

impl LightToml {
    /// The shadow its fields describe, if any.
    fn shadow(&self) -> Result<Option<LightShadow>, String> {
        let automatic = self.shadows.unwrap_or(false);
        let filter_given = self.bias.is_some()
            || self.blur.is_some()
            || self.samples.is_some()
            || self.filter_width.is_some();
        let maps = match (automatic, &self.shadow_map) {
            (true, Some(_)) => {
                return Err(
                    "a light has `shadows = true` (the renderer renders its map) or `shadow_map` (map files), not both"
                        .into(),
                );
            }
            (true, None) => ShadowMaps::Automatic {
                map_size: self.map_size.unwrap_or(DEFAULT_SHADOW_MAP_SIZE),
            },
            (false, Some(files)) => {
                if self.map_size.is_some() {
                    return Err("`map_size` belongs to automatic shadows (`shadows = true`), not to `shadow_map` files".into());
                }
                ShadowMaps::Files(match files.clone() {
                    ShadowMapFiles::One(file) => vec![file],
                    ShadowMapFiles::Several(files) => files,
                })
            }
            (false, None) => {
                if filter_given || self.map_size.is_some() {
                    return Err(
                        "`map_size`, `bias`, `blur`, `samples` and `filter_width` belong to a light with shadows (`shadows = true` or `shadow_map`)"
                            .into(),
                    );
                }
                return Ok(None);
            }
        };
        Ok(Some(LightShadow {
            maps,
            filter: ShadowFilter {
                samples: self.samples.unwrap_or(DEFAULT_SHADOW_SAMPLES),
                width: self.filter_width.unwrap_or(1.0),
                blur: self.blur.unwrap_or(0.0),
                bias: self.bias.unwrap_or(DEFAULT_SHADOW_BIAS),
            },
        }))
    }
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
        let shadow = light.shadow()?;
        if shadow.is_some() && kind == LightKind::Ambient {
            return Err("an ambient light casts no shadow".into());
        }
        Ok(Light {
            kind,
            shadow,
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
        let shadow = light.shadow.as_ref();
        let filter = shadow.map(|s| s.filter);
        let (shadows, shadow_map, map_size) = match shadow.map(|s| &s.maps) {
            None => (None, None, None),
            Some(ShadowMaps::Automatic { map_size }) => (Some(true), None, Some(*map_size)),
            Some(ShadowMaps::Files(files)) => (
                None,
                Some(match files.as_slice() {
                    [one] => ShadowMapFiles::One(one.clone()),
                    several => ShadowMapFiles::Several(several.to_vec()),
                }),
                None,
            ),
        };
        LightToml {
            shadows,
            shadow_map,
            map_size,
            bias: filter.map(|f| f.bias),
            blur: filter.map(|f| f.blur),
            samples: filter.map(|f| f.samples),
            filter_width: filter.map(|f| f.width),
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
