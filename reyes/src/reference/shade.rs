//! Shading: Lambert diffuse plus Blinn-Phong specular from directional lights.

use glam::Vec3;

use crate::prepare::{PreparedLight, PreparedScene};

/// Linear RGB colour of a grid point, each channel clamped to `[0, 1]`:
///
/// `c = albedo * (ambient + sum_l radiance_l * max(0, n.L_l))
///    + specular_strength * sum_l radiance_l * max(0, n.H_l)^shininess`
///
/// with `V = normalize(eye - P)` and `H_l = normalize(L_l + V)`.
pub fn shade(position: Vec3, normal: Vec3, albedo: Vec3, scene: &PreparedScene) -> Vec3 {
    shade_with(
        position,
        normal,
        albedo,
        scene.camera.eye,
        &scene.lights,
        scene.ambient,
        scene.specular_strength,
        scene.shininess,
    )
}

/// [`shade`] with every input explicit.
#[allow(
    clippy::too_many_arguments,
    reason = "the shading formula's inputs, kept explicit so tests can vary each"
)]
pub fn shade_with(
    position: Vec3,
    normal: Vec3,
    albedo: Vec3,
    eye: Vec3,
    lights: &[PreparedLight],
    ambient: f32,
    specular_strength: f32,
    shininess: f32,
) -> Vec3 {
    let view = (eye - position).normalize_or_zero();
    let mut diffuse = Vec3::ZERO;
    let mut specular = Vec3::ZERO;
    for light in lights {
        diffuse += light.radiance * normal.dot(light.to_light).max(0.0);
        let half = (light.to_light + view).normalize_or_zero();
        specular += light.radiance * normal.dot(half).max(0.0).powf(shininess);
    }
    let color = albedo * (Vec3::splat(ambient) + diffuse) + specular * specular_strength;
    color.clamp(Vec3::ZERO, Vec3::ONE)
}
