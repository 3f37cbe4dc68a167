//! Shading: RenderMan's standard surface shaders under its standard lights,
//! with `ambient()`, `diffuse()` and `specular()` as the RenderMan Interface
//! Specification 3.2 defines them (docs/reyes.md, "Surfaces and lights").
//! `shaders/reyes/library_shading.wgsl` mirrors it operation for operation.

use glam::{Vec2, Vec3, Vec4};

use crate::camera::{HomogeneousEye, towards_eye};
use crate::prepare::{PreparedLight, PreparedObject, PreparedScene, PreparedSurface};
use crate::shading::{pow_nonneg, specular_exponent};
use crate::surface_shader::{ShadingContext, ShadingHost, ShadowSlot};
use crate::shadow::{LightShadowMaps, ShadowMap};
use crate::texture::{TextureId, TextureSet};

/// What a surface sees of the scene: the eye, the lights and the ambient
/// light.
#[derive(Debug, Clone, Copy)]
pub struct Lighting<'a> {
    /// The viewer ([`crate::camera::Camera::homogeneous_eye`]).
    pub eye: HomogeneousEye,
    /// The lights that illuminate.
    pub lights: &'a [PreparedLight],
    /// `ambient()`: the sum of the ambient lights.
    pub ambient: Vec3,
    /// The frame's textures, if any.
    pub textures: Option<&'a TextureSet>,
    /// The shadow maps the lights' [`PreparedLight::shadow`] index.
    pub shadow_maps: &'a [ShadowMap],
}

impl<'a> Lighting<'a> {
    /// The lighting of `scene`.
    pub fn of(scene: &'a PreparedScene) -> Self {
        Lighting {
            eye: scene.camera.homogeneous_eye(),
            lights: &scene.lights,
            ambient: scene.ambient,
            textures: Some(&scene.textures),
            shadow_maps: &scene.shadow_maps,
        }
    }

    /// What `light` gives `position`: [`PreparedLight::at`], its colour
    /// scaled by the fraction of the light its shadow maps let through.
    /// The WGSL `light_at` computes the same.
    pub fn light_at(&self, light: &PreparedLight, position: Vec3) -> Option<(Vec3, Vec3)> {
        let (l, cl) = light.at(position)?;
        let Some(shadow) = light.shadow else {
            return Some((l, cl));
        };
        let maps = LightShadowMaps {
            maps: shadow.maps(self.shadow_maps),
            filter: shadow.filter,
        };
        Some((l, cl * maps.visibility(position)))
    }

    /// RenderMan's `diffuse(N)`: `sum Cl * normalize(L).N` over the lights
    /// within 90 degrees of `normal` (`illuminance(P, N, PI/2)`).
    pub fn diffuse(&self, position: Vec3, normal: Vec3) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for light in self.lights {
            if let Some((l, cl)) = self.light_at(light, position) {
                let cosine = normal.dot(l);
                if cosine > 0.0 {
                    sum += cl * cosine;
                }
            }
        }
        sum
    }

    /// RenderMan's `specular(N, V, roughness)`: `sum Cl * max(0, N.H)^(1 /
    /// roughness)` with `H = normalize(L + V)`, over the same lights as
    /// [`Lighting::diffuse`]; `exponent` is `1 / roughness`.
    pub fn specular(&self, position: Vec3, normal: Vec3, view: Vec3, exponent: f32) -> Vec3 {
        let mut sum = Vec3::ZERO;
        for light in self.lights {
            if let Some((l, cl)) = self.light_at(light, position)
                && normal.dot(l) > 0.0
            {
                let half = (l + view).normalize_or_zero();
                sum += cl * pow_nonneg(normal.dot(half).max(0.0), exponent);
            }
        }
        sum
    }
}

impl ShadingHost for Lighting<'_> {
    fn ambient(&self) -> Vec3 {
        self.ambient
    }

    fn diffuse(&self, ctx: &ShadingContext, n: Vec3) -> Vec3 {
        Lighting::diffuse(self, ctx.p, n)
    }

    fn specular(&self, ctx: &ShadingContext, n: Vec3, v: Vec3, roughness: f32) -> Vec3 {
        Lighting::specular(self, ctx.p, n, v, specular_exponent(roughness))
    }

    fn texture_footprint(&self, index: u32, st: Vec2, axis_a: Vec2, axis_b: Vec2) -> Vec4 {
        self.textures.map_or(Vec4::ZERO, |set| set.sample(TextureId(index), st, axis_a, axis_b))
    }

    fn environment_footprint(&self, index: u32, r: Vec3, dr_du: Vec3, dr_dv: Vec3) -> Vec4 {
        self.textures.map_or(Vec4::ZERO, |set| {
            set.environment(TextureId(index), r, dr_du, dr_dv)
        })
    }

    fn shadow(&self, id: [f32; 4], p: Vec3) -> f32 {
        ShadowSlot::from_slot(id).occlusion(self.shadow_maps, p)
    }

    fn light_count(&self) -> u32 {
        self.lights.len() as u32
    }

    fn light(&self, i: u32, p: Vec3) -> (Vec3, Vec3) {
        self.lights
            .get(i as usize)
            .and_then(|light| self.light_at(light, p))
            .unwrap_or((Vec3::ZERO, Vec3::ZERO))
    }
}

/// `Ci` of a grid point of an object with the user shader `shader` (its
/// parameters from slot `parameters`) through the shader's Rust twin,
/// clamped to `[0, 1]`; `None` when the shader has no twin.
pub fn shade_user(
    ctx: &ShadingContext,
    shader: u32,
    parameters: u32,
    scene: &PreparedScene,
) -> Option<Vec3> {
    let shader = scene.shaders.shaders.get(shader as usize)?;
    let twin = shader.cpu.as_ref()?;
    let slots = scene.shaders.slots(parameters, shader);
    let out = (twin.0)(ctx, &Lighting::of(scene), slots);
    Some(out.ci.clamp(Vec3::ZERO, Vec3::ONE))
}

/// The linear RGB colour `Ci` of a grid point of `object`, each channel
/// clamped to `[0, 1]`. `normal` is the unit normal facing the eye
/// (RenderMan's `Nf = faceforward(normalize(N), I)`).
pub fn shade(position: Vec3, normal: Vec3, object: &PreparedObject, scene: &PreparedScene) -> Vec3 {
    match object.surface {
        Some(surface) => shade_surface(position, normal, object.color, &surface, &Lighting::of(scene)),
        // A `null` object has no patches to shade.
        None => Vec3::ZERO,
    }
}

/// `Ci` of `surface` with colour `cs` at `position` (see [`shade`]).
pub fn shade_surface(
    position: Vec3,
    normal: Vec3,
    cs: Vec3,
    surface: &PreparedSurface,
    lighting: &Lighting<'_>,
) -> Vec3 {
    // V = -normalize(I): towards the eye.
    let view = towards_eye(lighting.eye, position).normalize_or_zero();
    let color = match *surface {
        PreparedSurface::Constant => cs,
        PreparedSurface::Matte { ka, kd } => {
            cs * (lighting.ambient * ka + lighting.diffuse(position, normal) * kd)
        }
        PreparedSurface::Metal { ka, ks, roughness } => {
            let exponent = specular_exponent(roughness);
            cs * (lighting.ambient * ka + lighting.specular(position, normal, view, exponent) * ks)
        }
        PreparedSurface::Plastic {
            ka,
            kd,
            ks,
            roughness,
            specular_color,
        } => {
            let exponent = specular_exponent(roughness);
            cs * (lighting.ambient * ka + lighting.diffuse(position, normal) * kd)
                + specular_color * lighting.specular(position, normal, view, exponent) * ks
        }
        PreparedSurface::DefaultSurface { ka, kd } => {
            // d = normalize(I).normalize(N); I = -V, and d is squared.
            let d = view.dot(normal);
            cs * (ka + kd * d * d)
        }
        // A user shader runs through its Rust twin with the full context
        // (`shade_user`); the reference refuses one without a twin first.
        PreparedSurface::User { .. } => cs,
    };
    color.clamp(Vec3::ZERO, Vec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Light;

    fn lighting(lights: &[PreparedLight], ambient: f32) -> Lighting<'_> {
        Lighting {
            // A viewer straight above the origin.
            eye: Vec3::new(0.0, 0.0, 10.0).extend(1.0),
            lights,
            ambient: Vec3::splat(ambient),
            textures: None,
            shadow_maps: &[],
        }
    }

    /// A point light straight above a surface point, against the formula
    /// worked by hand: `n.L = 1` and `radiance / d^2` at distance `d`.
    #[test]
    fn a_point_light_falls_off_with_the_squared_distance() {
        let light = PreparedLight::new(&Light::point(
            Vec3::new(1.0, 2.0, 7.0),
            Vec3::new(8.0, 4.0, 2.0),
            1.0,
        ))
        .unwrap();
        let surface = Vec3::new(1.0, 2.0, 3.0);
        let (towards, cl) = light.at(surface).unwrap();
        assert_eq!(towards, Vec3::Z);
        assert_eq!(cl, Vec3::new(0.5, 0.25, 0.125));
        let lights = [light];
        let matte = PreparedSurface::Matte { ka: 0.0, kd: 1.0 };
        let color = shade_surface(surface, Vec3::Z, Vec3::ONE, &matte, &lighting(&lights, 0.0));
        assert_eq!(color, Vec3::new(0.5, 0.25, 0.125));
        // From the side, at 45 degrees and distance sqrt(32): cos / 32.
        let side = Vec3::new(5.0, 2.0, 3.0);
        let color = shade_surface(side, Vec3::Z, Vec3::ONE, &matte, &lighting(&lights, 0.0));
        let expected = Vec3::new(8.0, 4.0, 2.0) * (std::f32::consts::FRAC_1_SQRT_2 / 32.0);
        assert!(
            (color - expected).abs().max_element() < 1e-6,
            "{color} vs {expected}"
        );
    }

    /// At the light itself the falloff is large but finite and the colour
    /// is a number, not NaN.
    #[test]
    fn a_surface_point_at_a_point_light_stays_finite() {
        let light = PreparedLight::new(&Light::point(Vec3::ONE, Vec3::splat(f32::MAX), 1.0)).unwrap();
        let (towards, cl) = light.at(Vec3::ONE).unwrap();
        assert_eq!(towards, Vec3::ZERO);
        assert!(!cl.is_nan());
        let lights = [light];
        let color = shade_surface(
            Vec3::ONE,
            Vec3::Z,
            Vec3::ONE,
            &PreparedSurface::Plastic {
                ka: 1.0,
                kd: 1.0,
                ks: 0.5,
                roughness: 0.125,
                specular_color: Vec3::ONE,
            },
            &lighting(&lights, 0.1),
        );
        assert!(color.is_finite(), "{color}");
    }

    /// A distant light is unchanged by the position.
    #[test]
    fn a_distant_light_ignores_the_position() {
        let light = PreparedLight::distant(-Vec3::Y, Vec3::ONE);
        assert_eq!(light.at(Vec3::new(9.0, -3.0, 1e6)), Some((Vec3::Y, Vec3::ONE)));
    }

    /// Each standard surface against its formula from the specification,
    /// worked here with the numbers of one light at 60 degrees from the
    /// normal, a viewer on the normal and an ambient light of 0.25.
    #[test]
    fn the_standard_surfaces_follow_the_specification() {
        // A distant light travelling along -L, L at 60 degrees from +z.
        let l = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
        let lights = [PreparedLight::distant(-l, Vec3::new(1.0, 0.5, 0.25))];
        let lit = lighting(&lights, 0.25);
        let cs = Vec3::new(0.8, 0.6, 0.4);
        let shade = |surface| shade_surface(Vec3::ZERO, Vec3::Z, cs, &surface, &lit);
        let cl = Vec3::new(1.0, 0.5, 0.25);
        // diffuse(N) = Cl cos 60 = Cl / 2.
        let diffuse = cl * 0.5;
        // H halves the 60 degrees between L and V = +z: N.H = cos 30.
        let n_dot_h = 30f32.to_radians().cos();
        let specular = |exponent: f32| cl * n_dot_h.powf(exponent);
        let close = |a: Vec3, b: Vec3| assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");

        close(shade(PreparedSurface::Constant), cs);
        close(
            shade(PreparedSurface::Matte { ka: 0.5, kd: 0.9 }),
            cs * (Vec3::splat(0.25 * 0.5) + diffuse * 0.9),
        );
        close(
            shade(PreparedSurface::Metal {
                ka: 1.0,
                ks: 0.7,
                roughness: 0.1,
            }),
            cs * (Vec3::splat(0.25) + specular(10.0) * 0.7),
        );
        let tint = Vec3::new(1.0, 0.9, 0.2);
        close(
            shade(PreparedSurface::Plastic {
                ka: 1.0,
                kd: 0.5,
                ks: 0.5,
                roughness: 0.1,
                specular_color: tint,
            }),
            cs * (Vec3::splat(0.25) + diffuse * 0.5) + tint * specular(10.0) * 0.5,
        );
        // The viewer is on the normal: d = 1.
        close(
            shade(PreparedSurface::DefaultSurface { ka: 0.2, kd: 0.8 }),
            cs * (0.2 + 0.8),
        );
    }

    /// A light behind the surface adds neither diffuse nor highlight,
    /// although `N.H` can be positive there (`illuminance`'s cone).
    #[test]
    fn lights_behind_the_surface_add_nothing() {
        // L 100 degrees from the normal, the viewer at grazing 80 degrees
        // on the other side: H is within 90 degrees of N.
        let a = 100f32.to_radians();
        let l = Vec3::new(a.sin(), 0.0, a.cos());
        let lights = [PreparedLight::distant(-l, Vec3::ONE)];
        let v = Vec3::new(-(80f32.to_radians().sin()), 0.0, 80f32.to_radians().cos());
        let lit = Lighting {
            eye: (v * 10.0).extend(1.0),
            lights: &lights,
            ambient: Vec3::ZERO,
            textures: None,
            shadow_maps: &[],
        };
        assert!(Vec3::Z.dot((l + v).normalize()) > 0.0);
        let plastic = PreparedSurface::Plastic {
            ka: 1.0,
            kd: 1.0,
            ks: 1.0,
            roughness: 1.0,
            specular_color: Vec3::ONE,
        };
        assert_eq!(
            shade_surface(Vec3::ZERO, Vec3::Z, Vec3::ONE, &plastic, &lit),
            Vec3::ZERO
        );
    }

    /// `defaultsurface` shades by the angle to the viewer alone:
    /// `Cs * (Ka + Kd cos^2)`, with no lights at all.
    #[test]
    fn defaultsurface_needs_no_lights() {
        let lit = Lighting {
            eye: Vec3::new(0.0, 10.0, 10.0).extend(1.0),
            lights: &[],
            ambient: Vec3::ZERO,
            textures: None,
            shadow_maps: &[],
        };
        let c = shade_surface(
            Vec3::ZERO,
            Vec3::Z,
            Vec3::ONE,
            &PreparedSurface::DefaultSurface { ka: 0.2, kd: 0.8 },
            &lit,
        );
        // 45 degrees: cos^2 = 1/2.
        assert!((c - Vec3::splat(0.2 + 0.8 * 0.5)).abs().max_element() < 1e-6);
    }
}
