//! The lights as the megakernel reads them: [`LightData`] per light, with
//! where its shadow maps lie in `height_texels` and its shadow filter.

use glam::Vec4;

use super::shadow_maps::shadow_table_entry;
use crate::shading::PreparedLight;

/// One light, WGSL struct `Light`.
#[scheduler::item]
#[wgsl(name = "Light")]
#[derive(Debug)]
pub struct LightData {
    /// A distant light: the unit vector towards it; a point light or a
    /// spotlight: its position (reyes::shading::PreparedLight; w unused).
    pub to_light: Vec4,
    /// Intensity times colour (w unused).
    pub radiance: Vec4,
    /// A spotlight's unit axis (w unused).
    pub axis: Vec4,
    /// LIGHT_* ([`super::abi::light`]).
    pub kind: u32,
    /// A spotlight's `cos(coneangle)`.
    pub cos_outside: f32,
    /// A spotlight's `cos(coneangle - conedeltaangle)`.
    pub cos_inside: f32,
    /// A spotlight's `beamdistribution`.
    pub beam_distribution: f32,
    /// Float offset in height_texels of the table entry of the light's
    /// first shadow map ([`super::shadow_maps`]).
    pub shadow_table: u32,
    /// How many shadow maps the light looks up: 0, unshadowed.
    pub shadow_maps: u32,
    /// The shadow lookup's grid side
    /// ([`crate::shadow::ShadowFilter::grid_side`]).
    pub shadow_side: u32,
    /// Its filter width in texels.
    pub shadow_width: f32,
    /// Its blur, a fraction of the map's larger side.
    pub shadow_blur: f32,
    /// Its bias, in world units.
    pub shadow_bias: f32,
    /// Padding to 16 bytes.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
}

/// The [`LightData`] of `light`, the frame's `map_count` shadow maps'
/// table at float `shadow_table` of `height_texels`. A shadow whose maps
/// are not all there is none, as on the CPU
/// ([`crate::shading::PreparedShadow::maps`]).
pub(super) fn light_data(light: &PreparedLight, map_count: usize, shadow_table: u64) -> LightData {
    let shadow = light
        .shadow
        .filter(|s| s.map_count > 0 && s.first_map as usize + s.map_count as usize <= map_count);
    let filter = shadow.map(|s| s.filter).unwrap_or_default();
    LightData {
        to_light: light.to_light.extend(0.0),
        radiance: light.radiance.extend(0.0),
        axis: light.axis.extend(0.0),
        kind: super::abi::light::code(light.kind),
        cos_outside: light.cos_outside,
        cos_inside: light.cos_inside,
        beam_distribution: light.beam_distribution,
        shadow_table: shadow.map_or(0, |s| shadow_table_entry(shadow_table, s.first_map)),
        shadow_maps: shadow.map_or(0, |s| s.map_count),
        shadow_side: filter.grid_side(),
        shadow_width: filter.width,
        shadow_blur: filter.blur,
        shadow_bias: filter.bias,
        pad0: 0,
        pad1: 0,
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::shading::{PreparedLightKind, PreparedShadow};
    use crate::shadow::ShadowFilter;

    fn light(shadow: Option<PreparedShadow>) -> PreparedLight {
        PreparedLight {
            kind: PreparedLightKind::Distant,
            to_light: Vec3::Y,
            radiance: Vec3::ONE,
            axis: Vec3::ZERO,
            cos_outside: 0.0,
            cos_inside: 0.0,
            beam_distribution: 0.0,
            shadow,
        }
    }

    #[test]
    fn a_light_points_at_its_maps_and_a_shadow_without_its_maps_is_none() {
        let filter = ShadowFilter {
            samples: 9,
            width: 2.0,
            blur: 0.1,
            bias: 0.3,
        };
        let shadow = |first_map, map_count| {
            Some(PreparedShadow {
                first_map,
                map_count,
                filter,
            })
        };
        let data = light_data(&light(shadow(1, 2)), 3, 1000);
        assert_eq!((data.shadow_table, data.shadow_maps), (1024, 2));
        assert_eq!(data.shadow_side, 3);
        assert_eq!(
            (data.shadow_width, data.shadow_blur, data.shadow_bias),
            (2.0, 0.1, 0.3)
        );
        // Maps past the frame's (PreparedShadow::maps gives none) and no
        // shadow: unshadowed.
        for unshadowed in [shadow(2, 2), shadow(0, 0), None] {
            assert_eq!(light_data(&light(unshadowed), 3, 1000).shadow_maps, 0);
        }
    }
}
