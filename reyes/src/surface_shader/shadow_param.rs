//! `ShadowId` parameters: a shadow map file the scene gives a user shader,
//! which the shader looks up with `shadow(id, P)` (RenderMan's
//! `shadow(name, P)`).
//!
//! A parameter's slot holds the map and the lookup's filter reduced to
//! what the lookup runs on ([`ShadowSlot`]): the map's index in the frame's
//! shadow maps (on the GPU, where its table entry lies: the renderer
//! rewrites it when it places the maps), the side of the lookup grid, the
//! filter region's width in texels (`filter_width` plus `blur` times the
//! map's larger side, known once the map is read) and the bias.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

use crate::shadow::{DEFAULT_SHADOW_BIAS, DEFAULT_SHADOW_SAMPLES, ShadowFilter, ShadowMap};

/// The map a `ShadowId` parameter holds when the scene gives none: past
/// every map, so that `shadow()` finds nothing in its way and returns 0.
pub const NO_SHADOW: u32 = u32::MAX;

/// A shadow map as a scene gives it to a `ShadowId` parameter: the file
/// and RenderMan's filter parameters (`{ path = "key.shad", blur = 0.01 }`;
/// a bare string is the file with the defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShadowDesc {
    /// The map: a float EXR depth image with the light's matrices, as
    /// `MakeShadow` or `reyes render --aov z` from the light write it.
    pub path: PathBuf,
    /// Lookups per point (`samples`), 16 by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<u32>,
    /// The filter region's width in texels (`width`), 1 by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter_width: Option<f32>,
    /// Added to the region as a fraction of the map's larger side
    /// (`blur`), 0 by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blur: Option<f32>,
    /// How far behind the nearest surface a point must lie to be in its
    /// shadow, in world units (`bias`), 0.01 by default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias: Option<f32>,
}

impl ShadowDesc {
    /// The map at `path` with the default filter.
    pub fn new(path: impl Into<PathBuf>) -> ShadowDesc {
        ShadowDesc {
            path: path.into(),
            samples: None,
            filter_width: None,
            blur: None,
            bias: None,
        }
    }

    /// The filter: the given parameters, RenderMan's defaults elsewhere.
    pub fn filter(&self) -> ShadowFilter {
        ShadowFilter {
            samples: self.samples.unwrap_or(DEFAULT_SHADOW_SAMPLES),
            width: self.filter_width.unwrap_or(1.0),
            blur: self.blur.unwrap_or(0.0),
            bias: self.bias.unwrap_or(DEFAULT_SHADOW_BIAS),
        }
    }
}

/// What a `ShadowId` parameter's slot holds, word for word the WGSL
/// `ShadowId` (`shaders/reyes/surface_api_shadow.wgsl`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowSlot {
    /// The map's index in the frame's shadow maps
    /// ([`crate::prepare::PreparedScene::shadow_maps`]); [`NO_SHADOW`]
    /// without one. On the GPU, the float offset of its table entry.
    pub map: u32,
    /// The lookup grid's side ([`ShadowFilter::grid_side`]).
    pub side: u32,
    /// The filter region's width in texels.
    pub region: f32,
    /// The bias, in world units.
    pub bias: f32,
}

impl ShadowSlot {
    /// The slot of no map: `shadow()` returns 0.
    pub const NONE: ShadowSlot = ShadowSlot {
        map: NO_SHADOW,
        side: 1,
        region: 1.0,
        bias: 0.0,
    };

    /// Map `index` of the frame, `map` itself, looked up with `filter`.
    /// The region is `filter.width + filter.blur` times the map's larger
    /// side, as [`ShadowMap::occlusion_at`] computes it.
    pub fn new(index: u32, map: &ShadowMap, filter: &ShadowFilter) -> ShadowSlot {
        ShadowSlot {
            map: index,
            side: filter.grid_side(),
            region: filter.width + filter.blur * map.width.max(map.height) as f32,
            bias: filter.bias,
        }
    }

    /// The slot as stored: integers by their bits.
    pub fn to_slot(self) -> [f32; 4] {
        [
            f32::from_bits(self.map),
            f32::from_bits(self.side),
            self.region,
            self.bias,
        ]
    }

    /// The slot stored as `slot` (what a shader's Rust twin is given).
    pub fn from_slot(slot: [f32; 4]) -> ShadowSlot {
        ShadowSlot {
            map: slot[0].to_bits(),
            side: slot[1].to_bits(),
            region: slot[2],
            bias: slot[3],
        }
    }

    /// The filter that looks the map up as this slot does: the region as
    /// its width, no blur (the map's size is in the region already).
    pub fn filter(self) -> ShadowFilter {
        ShadowFilter {
            samples: self.side.saturating_mul(self.side),
            width: self.region,
            blur: 0.0,
            bias: self.bias,
        }
    }

    /// RenderMan's `shadow(name, P)` on `maps`: the occluded fraction of
    /// the filter region around `p` (0 lit, 1 in shadow); 0 where the slot
    /// names no map of `maps` or `p` falls outside the map.
    pub fn occlusion(self, maps: &[ShadowMap], p: glam::Vec3) -> f32 {
        maps.get(self.map as usize)
            .map_or(0.0, |map| map.occlusion(p, &self.filter()))
    }
}
