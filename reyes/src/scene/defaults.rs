//! The default values of the scene's fields, as functions for
//! `#[serde(default = "...")]`.

use glam::Vec3;

use crate::params::{DEFAULT_DICE_THRESHOLD, DEFAULT_MAX_SPLIT_DEPTH, DEFAULT_SHADING_RATE};

use super::Light;

pub(super) fn default_up() -> Vec3 {
    Vec3::Z
}
pub(super) fn default_fov() -> f32 {
    40.0
}
pub(super) fn default_near() -> f32 {
    0.1
}
pub(super) fn default_far() -> f32 {
    1000.0
}
pub(super) fn default_color() -> Vec3 {
    Vec3::splat(0.8)
}
pub(super) fn default_white() -> Vec3 {
    Vec3::ONE
}
pub(super) fn default_one() -> f32 {
    1.0
}
pub(super) fn default_light_direction() -> Vec3 {
    Vec3::new(0.4, 0.8, -1.0)
}
pub(super) fn default_spp() -> u32 {
    4
}
pub(super) fn default_interleave_tile() -> u32 {
    crate::uvt::DEFAULT_INTERLEAVE_TILE
}
pub(super) fn default_interleave_permutations() -> u32 {
    crate::uvt::DEFAULT_INTERLEAVE_PERMUTATIONS
}
pub(super) fn default_background() -> Vec3 {
    Vec3::new(0.05, 0.05, 0.07)
}
pub(super) fn default_ambient() -> f32 {
    0.1
}
pub(super) fn default_sides() -> u8 {
    2
}
pub(super) fn default_shading_rate() -> f32 {
    DEFAULT_SHADING_RATE
}
pub(super) fn default_dice_threshold() -> f32 {
    DEFAULT_DICE_THRESHOLD
}
pub(super) fn default_max_split_depth() -> u32 {
    DEFAULT_MAX_SPLIT_DEPTH
}
pub(super) fn default_lights() -> Vec<Light> {
    vec![Light::default()]
}
