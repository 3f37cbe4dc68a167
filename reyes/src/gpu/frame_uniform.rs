//! The frame uniform: what every procedure of a frame reads of the
//! camera, the sampling, the dicing and the tables' places, declared in
//! WGSL from this struct.

use glam::{Mat4, Vec4};

use super::abi::sampling;
use super::buffers::texel_words;
use crate::prepare::PreparedScene;
use crate::sampling::grid_size;
use crate::uvt::{PixelTuples, UvtLayout};

/// The frame uniform, WGSL struct `Frame` (declared from this struct in the
/// generated module, its layout checked when this crate compiles).
#[scheduler::item]
#[wgsl(name = "Frame")]
#[derive(Debug)]
pub struct FrameUniform {
    /// World-to-clip matrix.
    pub view_proj: Mat4,
    /// The eye for shading and culling (reyes::camera::HomogeneousEye):
    /// (position, 1) for a perspective camera, (unit direction towards
    /// the viewer, 0) for an orthographic one.
    pub eye: Vec4,
    /// Image width: the frame's, or a screen tile's.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Samples per pixel side: spp = k * k.
    pub k: u32,
    /// Split-depth guard.
    pub max_split_depth: u32,
    /// SAMPLING_BBOX, ... ([`sampling`]).
    pub sampling: u32,
    /// 1 when samples are jittered.
    pub jitter: u32,
    /// Lights used from the lights buffer.
    pub light_count: u32,
    /// `ambient()`'s red ([`PreparedScene::ambient`]).
    pub ambient_red: f32,
    /// Its green.
    pub ambient_green: f32,
    /// Its blue.
    pub ambient_blue: f32,
    /// DICING_FIXED or DICING_RATE.
    pub dicing: u32,
    /// How far each clip coordinate moves per world unit
    /// (reyes::camera::Camera::clip_pad): a ball of radius b lies within
    /// c +- b * clip_pad.
    pub clip_pad: Vec4,
    /// The window of the full image this image covers, as a clip-space
    /// scale and translate (reyes::camera::Camera::window): what culling
    /// tests against. `(1, 1, 0, 0)` for the whole frame.
    pub window: Vec4,
    /// The thin lens (reyes::motion::PreparedLens): its radius.
    pub aperture: f32,
    /// View depth in focus.
    pub focus: f32,
    /// Pixels per unit of x / w.
    pub pixel_scale: f32,
    /// 1 when samples carry a time and a lens position (the 5D path).
    pub time_lens: u32,
    /// Float offset in height_texels of the time/lens tables
    /// (reyes::uvt::UvtTables): the simple tuples.
    pub uvt_simple: u32,
    /// The interleave tuples.
    pub uvt_interleave: u32,
    /// INTERVAL's lens box per time stratum.
    pub uvt_interval_lens: u32,
    /// The per-pixel table.
    pub uvt_pixel: u32,
    /// The interleave inverses.
    pub uvt_inverse: u32,
    /// The Interleave slot of each pixel offset of a tile, per
    /// permutation (reyes::uvt::UvtTables::slot_of_pixel).
    pub uvt_slot_of_pixel: u32,
    /// Each Interleave slot's sample per time stratum.
    pub uvt_slot_sample: u32,
    /// Each Interleave slot's time stratum per sample.
    pub uvt_slot_stratum: u32,
    /// 1 when the bounding box and INTERVAL give each sample the Interleave
    /// tuple it carries (reyes::uvt::PixelTuples::Interleave, Adaptive);
    /// 0 when they read the per-pixel table.
    pub interleave_pixel_tuples: u32,
    /// Interleave UVT tuples per tile.
    pub interleave_tuples: u32,
    /// This image's pixel (0, 0) in the full frame (a screen tile's
    /// origin): sampling hashes absolute pixel coordinates.
    pub origin_x: u32,
    /// Its y.
    pub origin_y: u32,
    /// Width of the full image, in whose pixels grid points and samples
    /// are placed (a screen tile's too, see `origin_x`).
    pub full_width: u32,
    /// Height of the full image.
    pub full_height: u32,
    /// sqrt(shading_rate): a micropolygon's side in pixels (rate dicing).
    pub micropolygon_side: f32,
    /// Float offset in height_texels of the input patches (48 floats each).
    pub patch_floats: u32,
    /// AOV_SHADED, AOV_GRIDS, AOV_DEPTH or AOV_NORMAL (reyes::aov).
    pub aov: u32,
    /// reyes::aov::depth_range of the camera.
    pub depth_range: f32,
    /// 1: a sample blends its triangle's corner colours
    /// (reyes::scene::ShadingInterpolation::Smooth); 0: one per micropolygon.
    pub smooth_shading: u32,
    /// Dice threshold in pixels.
    pub dice_threshold: f32,
    /// Side, in pixels, of Interleave UVT's tiles (K: 2, 3 or 4).
    pub interleave_tile: u32,
    /// Permutations Interleave UVT's tiles choose from (P,
    /// reyes::uvt::InterleaveTiles::permutations).
    pub interleave_permutations: u32,
    /// Interleave tiles in a row of the full image
    /// (reyes::uvt::InterleaveTiles::row_tiles).
    pub interleave_row_tiles: u32,
    /// The micropolygon side in pixels that Adaptive's cost model assumes
    /// (reyes::prepare::PreparedScene::nominal_micropolygon_px).
    pub adaptive_micropolygon: f32,
    /// Float offset in height_texels of the user shaders' parameter slots
    /// (4 floats each, reyes::surface_shader::ShaderTable::parameters).
    pub parameter_floats: u32,
    /// Float offset in height_texels of the input patches' corner texture
    /// coordinates (8 floats each: s, t at (u, v) = (0,0), (1,0), (0,1), (1,1)).
    pub st_floats: u32,
    /// Float offset in height_texels of the textures' TextureInfo entries
    /// (8 words each, stored by their bits).
    pub texture_floats: u32,
    /// Float offset in height_texels of the textures' packed texels (2
    /// words each, by their bits).
    pub texel_floats: u32,
    /// Textures in the frame.
    pub texture_count: u32,
    /// Packed texels of all textures.
    pub texel_count: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
}

impl FrameUniform {
    /// The uniform of `scene`.
    pub fn new(scene: &PreparedScene) -> Self {
        let camera = &scene.camera;
        let tiles = scene.interleave_tiles();
        Self {
            // The same f32 matrix the reference multiplies with.
            view_proj: camera.view_proj(),
            eye: camera.homogeneous_eye(),
            dice_threshold: scene.dicing.dice_threshold(),
            width: camera.width,
            height: camera.height,
            full_width: camera.full_width,
            full_height: camera.full_height,
            spp: scene.spp,
            k: grid_size(scene.spp),
            max_split_depth: scene.max_split_depth,
            sampling: sampling::code(scene.sampling),
            jitter: u32::from(scene.jitter),
            light_count: scene.lights.len() as u32,
            ambient_red: scene.ambient.x,
            ambient_green: scene.ambient.y,
            ambient_blue: scene.ambient.z,
            dicing: super::abi::dicing::code(scene.dicing.mode()),
            clip_pad: camera.clip_pad(),
            window: camera.window(),
            aperture: scene.lens.aperture,
            focus: scene.lens.focus,
            pixel_scale: scene.lens.pixel_scale,
            time_lens: u32::from(scene.samples_time_and_lens()),
            uvt_simple: 0,
            uvt_interleave: 0,
            uvt_interval_lens: 0,
            uvt_pixel: 0,
            uvt_inverse: 0,
            uvt_slot_of_pixel: 0,
            uvt_slot_sample: 0,
            uvt_slot_stratum: 0,
            interleave_pixel_tuples: u32::from(
                PixelTuples::for_sampling(scene.sampling) == PixelTuples::Interleave,
            ),
            interleave_tuples: 0,
            origin_x: camera.origin[0],
            origin_y: camera.origin[1],
            micropolygon_side: scene.dicing.micropolygon_side(),
            patch_floats: 0,
            parameter_floats: 0,
            st_floats: 0,
            texture_floats: 0,
            texel_floats: 0,
            texture_count: scene.textures.len() as u32,
            texel_count: texel_words(scene) as u32,
            pad0: 0,
            pad1: 0,
            aov: scene.aov.code(),
            depth_range: crate::aov::depth_range(camera),
            smooth_shading: u32::from(
                scene.shading_interpolation == crate::scene::ShadingInterpolation::Smooth,
            ),
            interleave_tile: tiles.tile,
            interleave_permutations: tiles.permutations,
            interleave_row_tiles: tiles.row_tiles,
            adaptive_micropolygon: scene.nominal_micropolygon_px(),
        }
    }

    /// Points the uniform at the time/lens tables stored at float `base` of
    /// `height_texels`.
    pub(super) fn with_uvt(mut self, base: u32) -> Self {
        let layout = UvtLayout::new(self.spp, self.interleave_tile, self.interleave_permutations);
        self.uvt_simple = base + layout.simple;
        self.uvt_interleave = base + layout.interleave;
        self.uvt_interval_lens = base + layout.interval_lens;
        self.uvt_pixel = base + layout.pixel;
        self.uvt_inverse = base + layout.inverse;
        self.uvt_slot_of_pixel = base + layout.slot_of_pixel;
        self.uvt_slot_sample = base + layout.slot_sample;
        self.uvt_slot_stratum = base + layout.slot_stratum;
        self.interleave_tuples = self.spp * self.interleave_tile * self.interleave_tile;
        self
    }
}
