//! Shading: Lambert diffuse plus Blinn-Phong specular from distant and point
//! lights.

use glam::Vec3;

use crate::camera::{HomogeneousEye, towards_eye};
use crate::prepare::{PreparedLight, PreparedScene};

/// Linear RGB colour of a grid point, each channel clamped to `[0, 1]`:
///
/// `c = albedo * (ambient + sum_l radiance_l * max(0, n.L_l))
///    + specular_strength * sum_l radiance_l * max(0, n.H_l)^shininess`
///
/// with `V = normalize(eye - P)` and `H_l = normalize(L_l + V)`. A point
/// light's `radiance_l` is divided by its squared distance
/// ([`PreparedLight::at`]).
pub fn shade(position: Vec3, normal: Vec3, albedo: Vec3, scene: &PreparedScene) -> Vec3 {
    shade_with(
        position,
        normal,
        albedo,
        scene.camera.homogeneous_eye(),
        &scene.lights,
        scene.ambient,
        scene.specular_strength,
        scene.shininess,
    )
}

/// [`shade`] with every input explicit.
#[expect(
    clippy::too_many_arguments,
    reason = "the shading formula's inputs, kept explicit so tests can vary each"
)]
pub fn shade_with(
    position: Vec3,
    normal: Vec3,
    albedo: Vec3,
    eye: HomogeneousEye,
    lights: &[PreparedLight],
    ambient: f32,
    specular_strength: f32,
    shininess: f32,
) -> Vec3 {
    let view = towards_eye(eye, position).normalize_or_zero();
    let mut diffuse = Vec3::ZERO;
    let mut specular = Vec3::ZERO;
    for light in lights {
        let (to_light, falloff) = light.at(position);
        diffuse += light.radiance * (normal.dot(to_light).max(0.0) * falloff);
        let half = (to_light + view).normalize_or_zero();
        specular += light.radiance * (normal.dot(half).max(0.0).powf(shininess) * falloff);
    }
    let color = albedo * (Vec3::splat(ambient) + diffuse) + specular * specular_strength;
    color.clamp(Vec3::ZERO, Vec3::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point light straight above a surface point, against the formula
    /// worked by hand: `n.L = 1` and `radiance / d^2` at distance `d`.
    #[test]
    fn a_point_light_falls_off_with_the_squared_distance() {
        let light = PreparedLight {
            to_light: Vec3::new(1.0, 2.0, 7.0),
            point: true,
            radiance: Vec3::new(8.0, 4.0, 2.0),
        };
        let surface = Vec3::new(1.0, 2.0, 3.0);
        let (towards, falloff) = light.at(surface);
        assert_eq!(towards, Vec3::Z);
        assert_eq!(falloff, 1.0 / 16.0);
        // Diffuse only (no ambient, no specular), albedo 1: radiance / 16.
        let color = shade_with(
            surface,
            Vec3::Z,
            Vec3::ONE,
            (surface + Vec3::Z).extend(1.0),
            &[light],
            0.0,
            0.0,
            1.0,
        );
        assert_eq!(color, Vec3::new(0.5, 0.25, 0.125));
        // From the side, at 45 degrees and distance sqrt(32): cos / 32.
        let side = Vec3::new(5.0, 2.0, 3.0);
        let color = shade_with(
            side,
            Vec3::Z,
            Vec3::ONE,
            (side + Vec3::Z).extend(1.0),
            &[light],
            0.0,
            0.0,
            1.0,
        );
        let expected = light.radiance * (std::f32::consts::FRAC_1_SQRT_2 / 32.0);
        assert!(
            (color - expected).abs().max_element() < 1e-6,
            "{color} vs {expected}"
        );
    }

    /// At the light itself the falloff is large but finite and the colour
    /// is a number, not NaN.
    #[test]
    fn a_surface_point_at_a_point_light_stays_finite() {
        let light = PreparedLight {
            to_light: Vec3::ONE,
            point: true,
            radiance: Vec3::splat(f32::MAX),
        };
        let (towards, falloff) = light.at(Vec3::ONE);
        assert_eq!(towards, Vec3::ZERO);
        assert!(falloff.is_finite());
        let color = shade_with(
            Vec3::ONE,
            Vec3::Z,
            Vec3::ONE,
            Vec3::ZERO.extend(1.0),
            &[light],
            0.1,
            0.5,
            8.0,
        );
        assert!(color.is_finite(), "{color}");
    }

    /// A distant light is unchanged by the position.
    #[test]
    fn a_distant_light_ignores_the_position() {
        let light = PreparedLight {
            to_light: Vec3::Y,
            point: false,
            radiance: Vec3::ONE,
        };
        assert_eq!(light.at(Vec3::new(9.0, -3.0, 1e6)), (Vec3::Y, 1.0));
    }
}
