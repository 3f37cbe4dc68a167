//! The frame's shadow maps as the megakernel reads them from
//! `height_texels` (`shaders/reyes/library_shadow.wgsl`): a table of
//! [`SHADOW_MAP_FLOATS`] floats per map, then every map's depths, and the
//! WGSL library a frame compiles in (the lookup where some light has a
//! shadow, a stub otherwise).

use crate::prepare::PreparedScene;
use crate::shadow::{ShadowMap, camera_z_row};

/// Floats per map in the table: the world-to-clip matrix (16, by
/// columns), the world-to-camera z row (4), then width, height and the
/// float offset of the first texel (by their bits) and one unused float.
pub const SHADOW_MAP_FLOATS: u32 = 24;

/// What an empty texel (+inf: no surface) holds on the GPU: WGSL has no
/// infinity, and drivers may assume none. No finite depth exceeds it, so
/// `map_depth < depth` is false for it as for +inf (the lookup keeps its
/// own depth at most this).
pub const SHADOW_NO_DEPTH: f32 = f32::MAX;

/// The shadow lookup (its constants are prepended by [`shadow_wgsl`]).
const SHADOW_WGSL: &str = include_str!("../../../shaders/reyes/library_shadow.wgsl");

/// `host_shadow`: the user shaders' `shadow()` on the same lookup.
const SHADOW_HOST_WGSL: &str = include_str!("../../../shaders/reyes/library_shadow_host.wgsl");

/// `light_visibility` of frames without shadows.
const NO_SHADOWS_WGSL: &str = "// No light has a shadow: every light reaches every point.
fn light_visibility(light: Light, p: vec3<f32>) -> f32 {
    return 1.0;
}
";

/// The WGSL that defines `light_visibility` (which `light_at` scales each
/// light by): the lookup when the frame has shadows, else a stub.
pub fn shadow_wgsl(shadowed: bool) -> String {
    if shadowed {
        format!(
            "const SHADOW_MAP_FLOATS: u32 = {SHADOW_MAP_FLOATS}u;\n// f32::MAX, exactly.\nconst SHADOW_NO_DEPTH: f32 = 0x1.fffffep+127f;\n{SHADOW_WGSL}"
        )
    } else {
        NO_SHADOWS_WGSL.to_owned()
    }
}

/// The user shaders' `host_shadow` on the frame's maps (after
/// [`shadow_wgsl`]`(true)`), with the `NO_SHADOW` it tests for.
pub fn shadow_host_wgsl() -> String {
    format!(
        "// reyes::surface_shader::NO_SHADOW.\nconst NO_SHADOW: u32 = {}u;\n{SHADOW_HOST_WGSL}",
        crate::surface_shader::NO_SHADOW
    )
}

/// Floats of `scene`'s shadow maps: the table and the depths.
pub fn shadow_floats(scene: &PreparedScene) -> u64 {
    scene
        .shadow_maps
        .iter()
        .map(|map| u64::from(SHADOW_MAP_FLOATS) + map.depths.len() as u64)
        .sum()
}

/// The table and the depths of `maps`, to be placed at float `base` of
/// `height_texels` (the texel offsets in the table are absolute).
pub fn shadow_map_floats(maps: &[ShadowMap], base: u64) -> Vec<f32> {
    let table = u64::from(SHADOW_MAP_FLOATS) * maps.len() as u64;
    let mut floats = Vec::with_capacity(
        (table + maps.iter().map(|m| m.depths.len() as u64).sum::<u64>()) as usize,
    );
    let mut texel = base + table;
    for map in maps {
        floats.extend_from_slice(&map.world_to_clip.to_cols_array());
        floats.extend_from_slice(&camera_z_row(map.world_to_camera).to_array());
        // The renderer refuses scenes whose floats a u32 cannot index.
        for word in [map.width, map.height, texel as u32, 0] {
            floats.push(f32::from_bits(word));
        }
        texel += map.depths.len() as u64;
    }
    for map in maps {
        floats.extend(map.depths.iter().map(|&d| d.min(SHADOW_NO_DEPTH)));
    }
    floats
}

/// The float offset in `height_texels` of entry `map` of the table at
/// float `table`.
pub fn shadow_table_entry(table: u64, map: u32) -> u32 {
    (table + u64::from(SHADOW_MAP_FLOATS) * u64::from(map)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Mat4;

    #[test]
    fn the_table_points_at_each_maps_depths_and_infinity_becomes_the_largest_float() {
        let map = |width: u32, height: u32, depth: f32| ShadowMap {
            width,
            height,
            depths: vec![depth; (width * height) as usize],
            world_to_camera: Mat4::from_translation(glam::Vec3::new(1.0, 2.0, 3.0)),
            world_to_clip: Mat4::from_scale(glam::Vec3::splat(2.0)),
        };
        let maps = [map(2, 3, 1.5), map(4, 1, f32::INFINITY)];
        let base = 100;
        let floats = shadow_map_floats(&maps, base);
        assert_eq!(floats.len(), 2 * 24 + 6 + 4);
        let word = |i: usize| floats[i].to_bits();
        assert_eq!((word(20), word(21), word(22)), (2, 3, 100 + 48));
        assert_eq!((word(24 + 20), word(24 + 21), word(24 + 22)), (4, 1, 100 + 48 + 6));
        assert_eq!(&floats[16..20], &[0.0, 0.0, 1.0, 3.0]);
        assert_eq!(floats[48..54], [1.5; 6]);
        assert_eq!(floats[54..58], [f32::MAX; 4]);
        assert_eq!(shadow_table_entry(base, 1), 124);
    }
}
