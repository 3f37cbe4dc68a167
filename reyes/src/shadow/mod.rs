//! Shadow maps: a depth image rendered from a light ([`crate::Aov::Z`])
//! with the light's projection, and RenderMan's `shadow()` lookup on it,
//! percentage-closer filtered.
//!
//! A [`ShadowMap`] keeps, per texel, the camera-space depth of the nearest
//! surface the light sees (+inf where it sees none) and the matrices that
//! put a world-space point into the map: the world-to-clip matrix (where
//! the point falls in the image) and the world-to-camera matrix (its
//! depth, the distance along the light's view axis). [`ShadowMap::occlusion`]
//! is the fraction of the filter region around the point whose surfaces lie
//! nearer the light than the point, less the bias: 0 lit, 1 in shadow.
//!
//! The filter ([`ShadowFilter`]) is RenderMan's: `samples` lookups over a
//! square region `width` texels wide plus `blur` (a fraction of the map's
//! size), each lookup comparing the four texels around it and weighting
//! them bilinearly (percentage-closer filtering). A region narrower than
//! the samples' grid takes one lookup per side more than the texels it
//! spans: 2 x 2 for the default one-texel region. The samples lie on a
//! fixed square grid, the same for every point, so the CPU reference and
//! the megakernel (`shaders/reyes/library_shadow.wgsl`) compute the same
//! value, operation for operation.
//!
//! Files: [`file`](mod@file) writes and reads maps as single-channel float EXR with
//! the matrices as attributes; [`crate::output::make_shadow`] (RIB
//! `MakeShadow`) turns the depth output of a frame rendered from a light
//! into a map.

pub mod file;
#[cfg(test)]
mod tests;

use glam::{Mat4, Vec3, Vec4};

pub use self::file::{ShadowFileError, read_shadow_map};

/// The most lookups one `shadow()` takes ([`ShadowFilter::samples`] is
/// clamped to it): a 16 x 16 grid.
pub const MAX_SHADOW_SAMPLES: u32 = 256;

/// RenderMan's `shadowspot` default `samples`.
pub const DEFAULT_SHADOW_SAMPLES: u32 = 16;

/// The default `bias`, in world units: how far a surface must lie behind
/// the nearest one the light sees to be shadowed by it. Maps of the
/// `midpoint` depth filter need next to none; `min` maps need about the
/// depth a surface spans across one texel.
pub const DEFAULT_SHADOW_BIAS: f32 = 0.01;

/// How a shadow lookup filters: RenderMan's `shadow()` parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowFilter {
    /// Lookups per point (`"samples"`): the filter takes `n x n` on a
    /// square grid, `n = round(sqrt(samples))`, at least 1 and at most 16.
    pub samples: u32,
    /// The region's width in texels (`"width"`, RenderMan's `swidth` and
    /// `twidth`): 1 filters over one texel.
    pub width: f32,
    /// Added to the region's width as a fraction of the map's larger side
    /// (`"blur"`): soft shadows.
    pub blur: f32,
    /// World units a point must lie behind the nearest surface to be in
    /// its shadow (`"bias"`).
    pub bias: f32,
}

impl Default for ShadowFilter {
    fn default() -> Self {
        ShadowFilter {
            samples: DEFAULT_SHADOW_SAMPLES,
            width: 1.0,
            blur: 0.0,
            bias: DEFAULT_SHADOW_BIAS,
        }
    }
}

impl ShadowFilter {
    /// The side of the lookup grid: `round(sqrt(samples))` in `1..=16`.
    pub fn grid_side(&self) -> u32 {
        ((self.samples.min(MAX_SHADOW_SAMPLES) as f32).sqrt().round() as u32).clamp(1, 16)
    }

    /// What makes the filter unusable, if anything: a non-finite or
    /// negative width, blur or bias.
    pub fn problem(&self) -> Option<String> {
        for (name, value) in [
            ("width", self.width),
            ("blur", self.blur),
            ("bias", self.bias),
        ] {
            if !value.is_finite() || value < 0.0 {
                return Some(format!(
                    "the shadow {name} must be finite and >= 0, not {value}"
                ));
            }
        }
        None
    }
}

/// A shadow map: the depths a light sees and its projection.
#[derive(Debug, Clone, PartialEq)]
pub struct ShadowMap {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Per texel, row-major from the top-left, the camera-space depth of
    /// the nearest surface (+inf where there is none).
    pub depths: Vec<f32>,
    /// The light's world-to-camera matrix (right-handed, looking down -z).
    pub world_to_camera: Mat4,
    /// The light's world-to-clip matrix: a point is in the image where
    /// `-w < x, y < w` (x right, y up).
    pub world_to_clip: Mat4,
}

/// Where a world-space point falls in a map: its continuous texel
/// coordinates (top-left origin, y down) and its camera-space depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPoint {
    /// Texel coordinates: texel `(i, j)` spans `[i, i + 1) x [j, j + 1)`.
    pub texel: glam::Vec2,
    /// The distance along the light's view axis.
    pub depth: f32,
}

impl ShadowMap {
    /// The map of `depths` (row-major, `width * height`) seen through
    /// `camera` (its full image, not a crop).
    pub fn from_camera(camera: &crate::camera::Camera, depths: Vec<f32>) -> ShadowMap {
        ShadowMap {
            width: camera.width,
            height: camera.height,
            depths,
            world_to_camera: camera.view,
            world_to_clip: camera.view_proj(),
        }
    }

    /// What makes the map unusable, if anything: no texels, a texel count
    /// that is not `width * height`, a NaN or negative depth, or a
    /// non-finite matrix.
    pub fn problem(&self) -> Option<String> {
        if self.width == 0 || self.height == 0 {
            return Some(format!("it has no texels ({}x{})", self.width, self.height));
        }
        if self.depths.len() as u64 != u64::from(self.width) * u64::from(self.height) {
            return Some(format!(
                "it holds {} depths for {}x{} texels",
                self.depths.len(),
                self.width,
                self.height
            ));
        }
        if let Some(bad) = self.depths.iter().find(|d| d.is_nan() || **d < 0.0) {
            return Some(format!(
                "it holds the depth {bad} (depths are >= 0 or +inf)"
            ));
        }
        if !self.world_to_camera.is_finite() || !self.world_to_clip.is_finite() {
            return Some("its matrices are not finite".into());
        }
        None
    }

    /// Where `p` falls in the map; `None` behind the light or outside its
    /// image.
    pub fn locate(&self, p: Vec3) -> Option<MapPoint> {
        let clip = self.world_to_clip * p.extend(1.0);
        // NaN (a point at the light's eye) is behind it too.
        if clip.w.is_nan() || clip.w <= 0.0 {
            return None;
        }
        let (x, y) = (clip.x / clip.w, clip.y / clip.w);
        let texel = glam::Vec2::new(
            (x * 0.5 + 0.5) * self.width as f32,
            (0.5 - y * 0.5) * self.height as f32,
        );
        let inside = texel.x >= 0.0
            && texel.x <= self.width as f32
            && texel.y >= 0.0
            && texel.y <= self.height as f32;
        if !inside {
            return None;
        }
        Some(MapPoint {
            texel,
            depth: -camera_z(self.world_to_camera, p),
        })
    }

    /// The nearest depth of texel `(x, y)`, clamped to the map's edges.
    fn depth_at(&self, x: i64, y: i64) -> f32 {
        let x = x.clamp(0, i64::from(self.width) - 1) as usize;
        let y = y.clamp(0, i64::from(self.height) - 1) as usize;
        self.depths[y * self.width as usize + x]
    }

    /// The fraction of the four texels around `texel` (bilinearly
    /// weighted) whose nearest surface lies nearer than `depth`.
    fn compare_bilinear(&self, texel: glam::Vec2, depth: f32) -> f32 {
        let at = texel - 0.5;
        let (x0, y0) = (at.x.floor(), at.y.floor());
        let (fx, fy) = (at.x - x0, at.y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let occludes = |x, y| {
            if self.depth_at(x, y) < depth {
                1.0
            } else {
                0.0
            }
        };
        let top = occludes(x0, y0) * (1.0 - fx) + occludes(x0 + 1, y0) * fx;
        let bottom = occludes(x0, y0 + 1) * (1.0 - fx) + occludes(x0 + 1, y0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// RenderMan's `shadow(map, P)`: the fraction of the filter region
    /// around `p` in shadow, 0 (lit) to 1; 0 where `p` is behind the light
    /// or outside the map. The WGSL `shadow_occlusion` computes the same.
    pub fn occlusion(&self, p: Vec3, filter: &ShadowFilter) -> f32 {
        self.locate(p)
            .map_or(0.0, |at| self.occlusion_at(at, filter))
    }

    /// [`ShadowMap::occlusion`] of a point already located.
    pub fn occlusion_at(&self, at: MapPoint, filter: &ShadowFilter) -> f32 {
        let region = filter.width + filter.blur * self.width.max(self.height) as f32;
        let side = filter.grid_side().min(region_grid_side(region));
        let depth = at.depth - filter.bias;
        let step = region / side as f32;
        let (cos, sin) = grid_rotation(side);
        let half = 0.5 * (side - 1) as f32;
        let mut sum = 0.0;
        for j in 0..side {
            for i in 0..side {
                // The grid's offset from the point, turned by the grid's
                // angle (the WGSL repeats these operations in this order).
                let u = step * (i as f32 - half);
                let v = step * (j as f32 - half);
                let texel = glam::Vec2::new(
                    at.texel.x + (cos * u - sin * v),
                    at.texel.y + (sin * u + cos * v),
                );
                sum += self.compare_bilinear(texel, depth);
            }
        }
        sum / (side * side) as f32
    }
}

/// The cosine and sine of the angle the lookups' `side x side` grid is
/// turned by, `atan(1 / side)`: turned so, the `side^2` lookups lie at
/// `side^2` different distances from any edge that runs along the map's
/// rows or columns, so a soft edge there falls in `side^2` steps instead of
/// `side` (a rotated grid, as in rotated-grid supersampling). The WGSL
/// computes the same in f32.
fn grid_rotation(side: u32) -> (f32, f32) {
    let norm = 1.0 / ((side * side + 1) as f32).sqrt();
    (side as f32 * norm, norm)
}

/// The most lookups per side a region `region` texels wide needs: one more
/// than the texels it spans (bilinear compares closer than a texel apart
/// add little), so a region of one texel takes 2 x 2 however many
/// `samples` are asked for. The WGSL computes the same in f32.
fn region_grid_side(region: f32) -> u32 {
    (region.ceil() + 1.0).min(16.0) as u32
}

/// The camera-space z of `p` under `world_to_camera` (negative in front),
/// summed in a fixed order (glam's `dot` differs between its SIMD
/// backends) that the WGSL `shadow_camera_z` repeats.
fn camera_z(world_to_camera: Mat4, p: Vec3) -> f32 {
    let row = camera_z_row(world_to_camera);
    ((row.x * p.x + row.y * p.y) + row.z * p.z) + row.w
}

/// The row of `world_to_camera` that gives a point's camera-space z.
pub fn camera_z_row(world_to_camera: Mat4) -> Vec4 {
    Vec4::new(
        world_to_camera.x_axis.z,
        world_to_camera.y_axis.z,
        world_to_camera.z_axis.z,
        world_to_camera.w_axis.z,
    )
}

/// A light's shadow: the maps it looks up (one for a spotlight or a distant
/// light, up to six for a point light) and the filter.
#[derive(Debug, Clone, PartialEq)]
pub struct LightShadowMaps<'a> {
    /// The maps, in order: a point takes the first whose image holds it.
    pub maps: &'a [ShadowMap],
    /// The lookup's filter.
    pub filter: ShadowFilter,
}

impl LightShadowMaps<'_> {
    /// The fraction of the light that reaches `p`: `1 - occlusion` in the
    /// first map whose image holds `p`, 1 where none does.
    pub fn visibility(&self, p: Vec3) -> f32 {
        self.maps
            .iter()
            .find_map(|map| map.locate(p).map(|at| map.occlusion_at(at, &self.filter)))
            .map_or(1.0, |occlusion| 1.0 - occlusion)
    }
}
