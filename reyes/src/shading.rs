//! Surfaces and lights ready for shading: RenderMan's standard surface
//! shaders with their parameters resolved ([`PreparedSurface`]) and its
//! standard lights in world space ([`PreparedLight`]). The CPU reference
//! evaluates them in `crate::reference::shade`, the megakernel in
//! `shaders/reyes/library_shading.wgsl`, the same formulas on both sides
//! (docs/reyes.md, "Surfaces and lights").

use glam::Vec3;

use crate::params::POINT_LIGHT_MIN_DISTANCE_SQUARED;
use crate::scene::{Light, LightKind, Surface};
use crate::shadow::ShadowFilter;

pub use crate::params::MAX_SPECULAR_EXPONENT;

/// A standard surface shader with its parameters, as the shading formulas
/// take them. `null` has no prepared form: its objects are not drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PreparedSurface {
    /// `Ci = Cs`.
    Constant,
    /// `Ci = Cs * (Ka * ambient() + Kd * diffuse(Nf))`.
    Matte {
        /// `Ka`.
        ka: f32,
        /// `Kd`.
        kd: f32,
    },
    /// `Ci = Cs * (Ka * ambient() + Ks * specular(Nf, V, roughness))`.
    Metal {
        /// `Ka`.
        ka: f32,
        /// `Ks`.
        ks: f32,
        /// `roughness`: the highlight's exponent is [`specular_exponent`].
        roughness: f32,
    },
    /// `Ci = Cs * (Ka * ambient() + Kd * diffuse(Nf))
    ///  + specularcolor * Ks * specular(Nf, V, roughness)`.
    Plastic {
        /// `Ka`.
        ka: f32,
        /// `Kd`.
        kd: f32,
        /// `Ks`.
        ks: f32,
        /// `roughness`: the highlight's exponent is [`specular_exponent`].
        roughness: f32,
        /// `specularcolor`.
        specular_color: Vec3,
    },
    /// `Ci = Cs * (Ka + Kd * d^2)`, `d = normalize(I).normalize(N)`.
    DefaultSurface {
        /// `Ka`.
        ka: f32,
        /// `Kd`.
        kd: f32,
    },
    /// A user's WGSL shader: entry `shader` of
    /// [`crate::prepare::PreparedScene::shaders`], with the object's
    /// parameters from slot `parameters` on.
    User {
        /// The shader's index.
        shader: u32,
        /// The object's first parameter slot.
        parameters: u32,
    },
}

/// The highlight's exponent of `specular(N, V, roughness)`: `1 / roughness`,
/// at most [`MAX_SPECULAR_EXPONENT`] (0 for an infinite roughness: a
/// highlight as wide as the lit side). The WGSL `specular` computes the same.
pub fn specular_exponent(roughness: f32) -> f32 {
    (1.0 / roughness).min(MAX_SPECULAR_EXPONENT)
}

impl PreparedSurface {
    /// The prepared form of `surface`: `None` for `null`; a user shader
    /// is prepared by `user` (which loads it into the frame's shaders).
    pub fn new<E>(
        surface: &Surface,
        user: impl FnOnce(
            &std::path::Path,
            &std::collections::BTreeMap<String, crate::surface_shader::ShaderValue>,
        ) -> Result<Self, E>,
    ) -> Result<Option<Self>, E> {
        Ok(Some(match surface.clone() {
            Surface::Constant => PreparedSurface::Constant,
            Surface::Matte { ka, kd } => PreparedSurface::Matte { ka, kd },
            Surface::Metal { ka, ks, roughness } => PreparedSurface::Metal { ka, ks, roughness },
            Surface::Plastic {
                ka,
                kd,
                ks,
                roughness,
                specular_color,
            } => PreparedSurface::Plastic {
                ka,
                kd,
                ks,
                roughness,
                specular_color,
            },
            Surface::DefaultSurface { ka, kd } => PreparedSurface::DefaultSurface { ka, kd },
            Surface::Null => return Ok(None),
            Surface::Wgsl { file, parameters } => user(&file, &parameters)?,
        }))
    }
}

/// How a [`PreparedLight`] shines on a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PreparedLightKind {
    /// Parallel rays: `to_light` is the unit vector towards the light.
    Distant,
    /// From `position`, falling off as `1 / d^2`.
    Point,
    /// From `position` along `axis`, within a cone, falling off as
    /// `cos^beam_distribution / d^2` and fading out at the cone's edge.
    Spot,
}

/// A light that illuminates surfaces (ambient lights are summed into
/// [`crate::prepare::PreparedScene::ambient`] instead).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedLight {
    /// The kind of light.
    pub kind: PreparedLightKind,
    /// A distant light: the unit vector from the surface towards it,
    /// `L = normalize(-direction)`. A point light or a spotlight: its
    /// position.
    pub to_light: Vec3,
    /// `intensity * color`.
    pub radiance: Vec3,
    /// A spotlight's unit axis, the direction it shines (zero otherwise).
    pub axis: Vec3,
    /// A spotlight's `cos(coneangle)`: no light where the angle from the
    /// axis has a smaller cosine.
    pub cos_outside: f32,
    /// A spotlight's `cos(coneangle - conedeltaangle)`: full light where the
    /// cosine is at least this.
    pub cos_inside: f32,
    /// A spotlight's `beamdistribution`.
    pub beam_distribution: f32,
    /// The light's shadow, if it casts one: its maps in
    /// [`crate::prepare::PreparedScene::shadow_maps`].
    pub shadow: Option<PreparedShadow>,
}

/// A light's shadow maps (`map_count` of them from `first_map` in
/// [`crate::prepare::PreparedScene::shadow_maps`]) and their lookup's filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedShadow {
    /// The first map.
    pub first_map: u32,
    /// How many maps (one, or up to six for a point light).
    pub map_count: u32,
    /// The lookup's filter.
    pub filter: ShadowFilter,
}

impl PreparedShadow {
    /// The maps of this shadow among `maps` (the frame's).
    pub fn maps<'a>(&self, maps: &'a [crate::shadow::ShadowMap]) -> &'a [crate::shadow::ShadowMap] {
        let first = self.first_map as usize;
        maps.get(first..first + self.map_count as usize)
            .unwrap_or(&[])
    }
}

impl PreparedLight {
    /// The light `light` as shading takes it, without its shadow (see
    /// [`PreparedLight::shadow`]); `None` for an ambient light.
    pub fn new(light: &Light) -> Option<Self> {
        let radiance = light.color * light.intensity;
        let mut prepared = PreparedLight {
            kind: PreparedLightKind::Distant,
            to_light: (-light.direction).normalize(),
            radiance,
            axis: Vec3::ZERO,
            cos_outside: 0.0,
            cos_inside: 0.0,
            beam_distribution: 0.0,
            shadow: None,
        };
        match light.kind {
            LightKind::Ambient => return None,
            LightKind::Distant => {}
            LightKind::Point => {
                prepared.kind = PreparedLightKind::Point;
                prepared.to_light = light.position.unwrap_or_default();
            }
            LightKind::Spot => {
                prepared.kind = PreparedLightKind::Spot;
                prepared.to_light = light.position.unwrap_or_default();
                prepared.axis = light.direction.normalize();
                let cone = light.cone_angle_degrees.to_radians();
                let delta = light.cone_delta_degrees.to_radians();
                prepared.cos_outside = cone.cos();
                prepared.cos_inside = (cone - delta).cos();
                prepared.beam_distribution = light.beam_distribution;
            }
        }
        Some(prepared)
    }

    /// A distant light shining along `direction` (not normalized).
    pub fn distant(direction: Vec3, radiance: Vec3) -> Self {
        PreparedLight::new(&Light {
            direction,
            color: radiance,
            ..Light::default()
        })
        .expect("a distant light")
    }

    /// What the light gives the surface point `position`: the unit vector
    /// `L` towards the light and the light's colour there, `Cl`; `None`
    /// where it gives nothing (outside a spotlight's cone). As RenderMan's
    /// `distantlight`, `pointlight` and `spotlight` compute `Cl`; the WGSL
    /// `light_at` mirrors it.
    pub fn at(&self, position: Vec3) -> Option<(Vec3, Vec3)> {
        if self.kind == PreparedLightKind::Distant {
            return Some((self.to_light, self.radiance));
        }
        let toward = self.to_light - position;
        let distance_squared = toward.dot(toward).max(POINT_LIGHT_MIN_DISTANCE_SQUARED);
        let l = toward.normalize_or_zero();
        let mut attenuation = 1.0 / distance_squared;
        if self.kind == PreparedLightKind::Spot {
            // RenderMan's spotlight: cosangle = L.A / length(L), with L
            // from the light to the point.
            let cos_angle = -l.dot(self.axis);
            // NaN (a point at the light) is outside too.
            if cos_angle.is_nan() || cos_angle < self.cos_outside {
                return None;
            }
            attenuation *= pow_nonneg(cos_angle, self.beam_distribution)
                * smoothstep(self.cos_outside, self.cos_inside, cos_angle);
        }
        Some((l, self.radiance * attenuation))
    }
}

/// `x^y` for `x >= 0` as Rust's `powf` computes it (`0^0 = 1`); the WGSL
/// `pow_nonneg` mirrors it (WGSL leaves `pow(0, y)` undefined).
pub fn pow_nonneg(x: f32, y: f32) -> f32 {
    if x <= 0.0 {
        return if y == 0.0 { 1.0 } else { 0.0 };
    }
    x.powf(y)
}

/// RenderMan's `smoothstep(min, max, value)`: 0 below `min`, 1 from `max`
/// on, the Hermite curve between (a step at `min` when `min == max`). The
/// WGSL `smoothstep_rm` mirrors it (WGSL's own is undefined for
/// `min >= max`).
pub fn smoothstep(min: f32, max: f32, value: f32) -> f32 {
    if value < min {
        return 0.0;
    }
    if value >= max {
        return 1.0;
    }
    let t = (value - min) / (max - min);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spotlight_is_full_inside_fades_at_the_edge_and_is_dark_outside() {
        // RenderMan's defaults: cone 30 degrees, delta 5, beam 2.
        let light = PreparedLight::new(&Light::spot(Vec3::ZERO, -Vec3::Z, Vec3::ONE, 1.0)).unwrap();
        let at_angle = |degrees: f32| {
            let a = degrees.to_radians();
            light
                .at(Vec3::new(a.sin(), 0.0, -a.cos()))
                .map(|(_, cl)| cl.x)
        };
        // On the axis at distance 1: cos^2 = 1, 1 / d^2 = 1.
        assert_eq!(at_angle(0.0), Some(1.0));
        // Inside the full cone (below 25 degrees): cos^2 only.
        let c = 20f32.to_radians().cos();
        assert!((at_angle(20.0).unwrap() - c * c).abs() < 1e-6);
        // Half-way through the fade, in cosine: the smoothstep's 1/2.
        let (outside, inside) = (30f32.to_radians().cos(), 25f32.to_radians().cos());
        let mid = ((outside + inside) / 2.0).acos().to_degrees();
        let expected = (outside + inside) / 2.0;
        assert!((at_angle(mid).unwrap() - expected * expected * 0.5).abs() < 1e-4);
        // Beyond the cone: nothing.
        assert_eq!(at_angle(31.0), None);
    }

    #[test]
    fn smoothstep_is_a_step_when_its_edges_meet() {
        assert_eq!(smoothstep(0.5, 0.5, 0.49), 0.0);
        assert_eq!(smoothstep(0.5, 0.5, 0.5), 1.0);
        assert_eq!(smoothstep(0.0, 1.0, 0.5), 0.5);
    }
}
