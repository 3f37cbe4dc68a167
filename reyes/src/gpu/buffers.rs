//! GPU buffers of one frame: the frame uniform (`super::frame_uniform`),
//! the objects (albedo and displacement), the lights, the height-map
//! texels, the sample framebuffer and the statistics, plus their read-back.

use super::abi::stat;
pub use super::frame_uniform::FrameUniform;
pub use super::counters::GpuCounters;
use super::objects::{ObjectData, ObjectTables};
use super::lights::light_data;
pub use super::lights::LightData;
use super::shadow_maps::{shadow_floats, shadow_map_floats, shadow_table_entry};
use crate::prepare::PreparedScene;
use crate::uvt::UvtLayout;

/// Where the scene's floats lie in the `height_texels` buffer: the height
/// maps from float 0, then (when samples carry time and lens) the
/// [`crate::uvt::UvtTables`], then the stored input patches' control points
/// ([`crate::prepare::PatchStore`]: 48 floats each, which the dice
/// procedures evaluate), their corner texture coordinates
/// (8 floats each), the user shaders' parameter slots (4 floats each), and
/// the textures' tables ([`crate::texture::TextureSet::gpu_tables`], by
/// their bits: 8 words per texture, 2 per texel) and the shadow maps (a
/// table entry per map, then their depths: [`super::shadow_maps`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct FloatLayout {
    /// First float of the time/lens tables.
    uvt: u64,
    /// First float of the patches.
    patches: u64,
    /// First float of the patches' texture coordinates (8 each).
    st: u64,
    /// First float of the shader parameters.
    parameters: u64,
    /// First float of the texture table (8 words per texture).
    textures: u64,
    /// First float of the packed texels (2 words each).
    texels: u64,
    /// First float of the shadow maps' table, followed by their depths.
    shadow_maps: u64,
    /// Floats in all.
    total: u64,
}

impl FloatLayout {
    fn new(scene: &PreparedScene, tables: &ObjectTables) -> Self {
        let uvt = tables.texels as u64;
        let uvt_floats = if scene.samples_time_and_lens() {
            u64::from(
                UvtLayout::new(
                    scene.spp,
                    scene.interleave_tile,
                    scene.interleave_permutations,
                )
                .floats,
            )
        } else {
            0
        };
        let patches = uvt + uvt_floats;
        let stored = u64::from(scene.store.len);
        let st = patches + 48 * stored;
        let parameters = st + 8 * stored;
        let textures = parameters + 4 * scene.shaders.parameters.len() as u64;
        let texels = textures + 8 * scene.textures.len() as u64;
        let shadow_maps = texels + 2 * texel_words(scene) as u64;
        Self {
            uvt,
            patches,
            st,
            parameters,
            textures,
            texels,
            shadow_maps,
            total: shadow_maps + shadow_floats(scene),
        }
    }
}

/// Packed texels of `scene`'s textures (none without textures, although
/// [`crate::texture::TextureSet::gpu_tables`] then gives a dummy one).
pub(super) fn texel_words(scene: &PreparedScene) -> usize {
    if scene.textures.is_empty() {
        0
    } else {
        scene.textures.gpu_tables().1.len()
    }
}

/// Bytes of `height_texels` for `scene`: every float of `FloatLayout`
/// (its height maps, time/lens tables, patches, shader parameters,
/// textures and shadow maps; at least one float: a binding may not be
/// empty). The
/// renderer refuses scenes whose floats a u32 cannot index.
pub fn texel_buffer_bytes(scene: &PreparedScene) -> u64 {
    4 * FloatLayout::new(scene, &ObjectTables::new(scene))
        .total
        .max(1)
}

/// Bytes of the input patches the GPU stores for `scene` (control points
/// and corner texture coordinates, 224 bytes per stored patch): each
/// patch once, and once only for every object that shares a model
/// ([`crate::prepare::PatchStore`]).
pub fn patch_store_bytes(scene: &PreparedScene) -> u64 {
    4 * (48 + 8) * u64::from(scene.store.len)
}

/// The stored patches' control points (48 floats each) and corner texture
/// coordinates (8 each), by stored index: a shared patch in model space,
/// any other in world space.
fn stored_patch_floats(scene: &PreparedScene) -> (Vec<f32>, Vec<f32>) {
    let stored = scene.store.len as usize;
    let mut points = vec![0.0f32; 48 * stored];
    let mut st = vec![0.0f32; 8 * stored];
    let mut put = |index: u32, patch_points: &[glam::Vec3; 16], corners: &[glam::Vec2; 4]| {
        let index = index as usize;
        for (k, point) in patch_points.iter().enumerate() {
            points[48 * index + 3 * k..48 * index + 3 * k + 3].copy_from_slice(&point.to_array());
        }
        for (k, corner) in corners.iter().enumerate() {
            st[8 * index + 2 * k..8 * index + 2 * k + 2].copy_from_slice(&corner.to_array());
        }
    };
    for patch in &scene.patches {
        if scene.objects[patch.object as usize].placement.is_none() {
            put(patch.stored, &patch.points, &patch.st);
        }
    }
    for shared in &scene.store.shared {
        put(shared.stored, &shared.points, &shared.st);
    }
    (points, st)
}

/// The buffers the megakernel binds (see the resources in
/// [`super::graph::reyes_graph`]).
#[derive(Debug)]
pub struct FrameBuffers {
    /// `frame`: the [`FrameUniform`].
    pub frame: wgpu::Buffer,
    /// `objects`: [`ObjectData`] per object.
    pub objects: wgpu::Buffer,
    /// `lights`.
    pub lights: wgpu::Buffer,
    /// `framebuffer`: one 64-bit key per sample.
    pub framebuffer: wgpu::Buffer,
    /// `stats`: [`stat::WORDS`] counters.
    pub stats: wgpu::Buffer,
    /// `height_texels`: the height maps' texels (f32), concatenated.
    pub height_texels: wgpu::Buffer,
    /// The statistics before the batch of input patches now running
    /// ([`FrameBuffers::save_stats`]): a retried run restores them, since
    /// the statistics are sums that a run adds to.
    stats_before_batch: wgpu::Buffer,
    /// Samples in `framebuffer`.
    pub samples: u64,
    objects_len: usize,
    lights_len: usize,
    /// The tables last written (their maps are in `height_texels`).
    tables: Option<ObjectTables>,
    /// The sample count, Interleave tile side and permutations and float
    /// offset of the time/lens tables last uploaded to `height_texels`
    /// (they stay valid while all four do).
    uvt: Option<(u32, u32, u32, u32, u32)>,
    /// The texture set's revision and float offset last uploaded to
    /// `height_texels` (they stay valid while both do).
    textures: Option<(u64, u64)>,
}

impl FrameBuffers {
    /// Creates the buffers for `scene` and fills the scene's data. The
    /// framebuffer and the statistics start uninitialized: clear them with
    /// [`super::resolve::Resolver::clear`] and [`FrameBuffers::reset_stats`].
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &PreparedScene) -> Self {
        use wgpu::BufferUsages as U;
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage,
                mapped_at_creation: false,
            })
        };
        let samples = framebuffer_samples(scene);
        let buffers = Self {
            frame: buffer(
                "reyes frame",
                std::mem::size_of::<FrameUniform>() as u64,
                U::UNIFORM | U::COPY_DST,
            ),
            // A binding may not be empty: an object-less or light-less scene
            // still gets one (unused) element.
            objects: buffer(
                "reyes objects",
                std::mem::size_of::<ObjectData>() as u64 * scene.objects.len().max(1) as u64,
                U::STORAGE | U::COPY_DST,
            ),
            lights: buffer(
                "reyes lights",
                std::mem::size_of::<LightData>() as u64 * scene.lights.len().max(1) as u64,
                U::STORAGE | U::COPY_DST,
            ),
            framebuffer: buffer("reyes framebuffer", 8 * samples, U::STORAGE | U::COPY_SRC),
            stats: buffer(
                "reyes stats",
                4 * u64::from(stat::WORDS),
                U::STORAGE | U::COPY_SRC | U::COPY_DST,
            ),
            height_texels: buffer(
                "reyes height texels",
                texel_buffer_bytes(scene),
                U::STORAGE | U::COPY_DST,
            ),
            stats_before_batch: buffer(
                "reyes stats before batch",
                4 * u64::from(stat::WORDS),
                U::COPY_SRC | U::COPY_DST,
            ),
            samples,
            objects_len: scene.objects.len(),
            lights_len: scene.lights.len(),
            tables: None,
            uvt: None,
            textures: None,
        };
        let mut buffers = buffers;
        buffers.write(queue, scene);
        buffers
    }

    /// Whether these buffers have the sizes `scene` needs (then
    /// [`FrameBuffers::write`] suffices instead of new buffers).
    pub fn fits(&self, scene: &PreparedScene) -> bool {
        self.samples == framebuffer_samples(scene)
            && self.objects_len == scene.objects.len()
            && self.lights_len == scene.lights.len()
            && self.height_texels.size() == texel_buffer_bytes(scene)
    }

    /// Writes the frame uniform, the objects, the lights, the shadow maps
    /// and (when they changed) the height maps and textures of `scene`.
    pub fn write(&mut self, queue: &wgpu::Queue, scene: &PreparedScene) {
        let tables = ObjectTables::new(scene);
        let layout = FloatLayout::new(scene, &tables);
        let lights: Vec<LightData> = scene
            .lights
            .iter()
            .map(|l| light_data(l, scene.shadow_maps.len(), layout.shadow_maps))
            .collect();
        let mut frame = FrameUniform::new(scene);
        // The renderer checks that every offset fits a u32 (texel_buffer_bytes).
        frame.patch_floats = layout.patches as u32;
        frame.parameter_floats = layout.parameters as u32;
        frame.st_floats = layout.st as u32;
        frame.texture_floats = layout.textures as u32;
        frame.texel_floats = layout.texels as u32;
        let (points, st) = stored_patch_floats(scene);
        if !points.is_empty() {
            queue.write_buffer(
                &self.height_texels,
                4 * layout.patches,
                bytemuck::cast_slice(&points),
            );
            queue.write_buffer(&self.height_texels, 4 * layout.st, bytemuck::cast_slice(&st));
        }
        // Uploaded once per texture set and place in the buffer: a large set
        // is not sent again with every frame.
        let texture_key = (scene.textures.revision(), layout.textures);
        if !scene.textures.is_empty() && self.textures != Some(texture_key) {
            self.textures = Some(texture_key);
            let (infos, texels) = scene.textures.gpu_tables();
            queue.write_buffer(
                &self.height_texels,
                4 * layout.textures,
                bytemuck::cast_slice(&infos),
            );
            queue.write_buffer(&self.height_texels, 4 * layout.texels, bytemuck::cast_slice(texels));
        }
        // Sent with every frame: the maps may change between frames with
        // the same textures and sizes.
        if !scene.shadow_maps.is_empty() {
            queue.write_buffer(
                &self.height_texels,
                4 * layout.shadow_maps,
                bytemuck::cast_slice(&shadow_map_floats(&scene.shadow_maps, layout.shadow_maps)),
            );
        }
        // A ShadowId finds its map where the maps are placed.
        let parameters = scene
            .shaders
            .gpu_parameters(scene.shadow_maps.len(), |map| {
                shadow_table_entry(layout.shadow_maps, map)
            });
        if !parameters.is_empty() {
            // Integer parameters are stored by their bits, which the loads
            // (bitcast from f32) keep: storage loads do not canonicalize.
            queue.write_buffer(
                &self.height_texels,
                4 * layout.parameters,
                bytemuck::cast_slice(&parameters),
            );
        }
        if scene.samples_time_and_lens() {
            let base = layout.uvt as u32;
            // Built and uploaded once per sample count, tile side, number of
            // permutations, seed and place in the buffer; the buffer keeps
            // them between frames (the image width is in the frame uniform).
            let key = (
                scene.spp,
                scene.sampling_seed,
                scene.interleave_tile,
                scene.interleave_permutations,
                base,
            );
            if self.uvt != Some(key) {
                queue.write_buffer(
                    &self.height_texels,
                    4 * u64::from(base),
                    bytemuck::cast_slice(&scene.uvt_tables().to_floats()),
                );
                self.uvt = Some(key);
            }
            frame = frame.with_uvt(base);
        }
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&frame));
        if !tables.objects.is_empty() {
            queue.write_buffer(&self.objects, 0, bytemuck::cast_slice(&tables.objects));
        }
        if !lights.is_empty() {
            queue.write_buffer(&self.lights, 0, bytemuck::cast_slice(&lights));
        }
        if !self.tables.as_ref().is_some_and(|w| w.same_maps(&tables)) {
            let mut offset = 0u64;
            for map in &tables.maps {
                queue.write_buffer(
                    &self.height_texels,
                    offset,
                    bytemuck::cast_slice(&map.texels),
                );
                offset += 4 * map.texels.len() as u64;
            }
        }
        self.tables = Some(tables);
    }

    /// Zeroes the statistics.
    pub fn reset_stats(&self, queue: &wgpu::Queue) {
        queue.write_buffer(&self.stats, 0, &[0u8; 4 * stat::WORDS as usize]);
    }

    /// Keeps a copy of the statistics as they are before a batch runs, for
    /// [`FrameBuffers::restore_stats`].
    ///
    /// Of the buffers the megakernel writes, only the statistics need it:
    /// the framebuffer keeps the nearest sample per slot (an atomicMin on
    /// depth and colour keys), so running a batch again writes nothing a
    /// first, cut-short run would not have kept; the statistics are sums
    /// (and one maximum) that every run adds to.
    pub fn save_stats(&self, device: &wgpu::Device, queue: &wgpu::Queue) {
        copy_whole(device, queue, &self.stats, &self.stats_before_batch);
    }

    /// Restores the statistics [`FrameBuffers::save_stats`] kept, before a
    /// batch runs again.
    pub fn restore_stats(&self, device: &wgpu::Device, queue: &wgpu::Queue) {
        copy_whole(device, queue, &self.stats_before_batch, &self.stats);
    }

    /// The bindings of the megakernel's resources, by name.
    pub fn bindings(&self) -> [scheduler::Binding<'_>; 6] {
        [
            scheduler::Binding::buffer("frame", &self.frame),
            scheduler::Binding::buffer("objects", &self.objects),
            scheduler::Binding::buffer("lights", &self.lights),
            scheduler::Binding::buffer("framebuffer", &self.framebuffer),
            scheduler::Binding::buffer("stats", &self.stats),
            scheduler::Binding::buffer("height_texels", &self.height_texels),
        ]
    }
}

/// Copies all of `from` into `to` (of the same size) on the device.
fn copy_whole(device: &wgpu::Device, queue: &wgpu::Queue, from: &wgpu::Buffer, to: &wgpu::Buffer) {
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("reyes stats copy"),
    });
    encoder.copy_buffer_to_buffer(from, 0, to, 0, from.size());
    queue.submit([encoder.finish()]);
}

/// Samples in the framebuffer of `scene`: `width * height * spp`.
pub fn framebuffer_samples(scene: &PreparedScene) -> u64 {
    u64::from(scene.camera.width) * u64::from(scene.camera.height) * u64::from(scene.spp)
}
