//! Fitting a frame to the device: [`GpuRenderer::plan`] checks it against
//! the buffer limits and splits it into screen tiles,
//! [`GpuRenderer::capacities`] sizes the queues and the batches of input
//! patches.

use scheduler::Capacities;

use super::GpuRenderer;
use crate::gpu::batches::{MIN_WORK_CAPACITY, plan_batch};
use crate::gpu::buffers::texel_buffer_bytes;
use crate::gpu::graph::{BOUND, DICE, SPLIT_U, SPLIT_V};
use crate::gpu::render_error::RenderError;
use crate::gpu::resolve::IMAGE_BYTES_PER_PIXEL;
use crate::gpu::tiles::{TILE_ALIGN, Tile, plan_tiles_with_margin};
use crate::prepare::PreparedScene;

/// Bytes of one stored input patch in the height-map buffer (48 floats of
/// control points, 8 of corner texture coordinates).
const PATCH_BYTES: u64 = 4 * (48 + 8);

impl GpuRenderer<'_> {
    /// Largest buffer the device binds as storage.
    pub(super) fn buffer_limit(&self) -> u64 {
        let limits = self.gpu.device.limits();
        limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    }

    /// Checks the frame against the device limits and splits it into screen
    /// tiles whose sample framebuffers fit one device buffer, the shaders'
    /// u32 sample index and
    /// [`GpuOptions::max_tile_samples`](super::GpuOptions::max_tile_samples).
    pub(super) fn plan(&self, scene: &PreparedScene) -> Result<Vec<Tile>, RenderError> {
        let (width, height, spp) = (scene.camera.width, scene.camera.height, scene.spp);
        let limit = self.buffer_limit();
        let too_large = |what, needed, limit| RenderError::TooLarge {
            what,
            width,
            height,
            spp,
            needed,
            limit,
        };
        // Only tiles are resolved on the device, but a frame whose whole RGBA
        // image exceeds one device buffer is still refused: it would need
        // thousands of tiles and gigabytes of host memory for the image.
        let pixels = u64::from(width) * u64::from(height);
        if 4 * pixels > limit {
            return Err(too_large("image", 4 * pixels, limit));
        }
        // The height maps, and the time/lens tables behind them.
        let needed = texel_buffer_bytes(scene);
        // The shaders index texels with u32.
        let texel_limit = limit.min(4 * u64::from(u32::MAX));
        if needed > texel_limit {
            // The megakernel reads every input patch from this buffer
            // whatever the batches: say how many patches would fit.
            let without_patches = texel_buffer_bytes(&PreparedScene {
                patches: Vec::new(),
                store: Default::default(),
                ..scene.clone()
            });
            if without_patches <= texel_limit {
                return Err(RenderError::TooManyPatches {
                    patches: scene.store.len as usize,
                    fit: (texel_limit - without_patches) / PATCH_BYTES,
                    needed,
                    limit: texel_limit,
                });
            }
            return Err(RenderError::HeightMapsTooLarge {
                needed,
                limit: texel_limit,
            });
        }
        // 8 bytes per sample in one buffer; the shaders index samples with u32.
        let device_samples = (limit / 8).min(u64::from(u32::MAX));
        let (max_samples, what) = match self.options.max_tile_samples {
            Some(cap) if cap < device_samples => (
                cap,
                "sample framebuffer of the smallest screen tile (capped by GpuOptions::max_tile_samples)",
            ),
            _ => (
                device_samples,
                "sample framebuffer of the smallest screen tile",
            ),
        };
        let spp64 = u64::from(spp.max(1));
        // A pixel filter wider than a pixel reads its neighbours' samples:
        // every tile renders that margin around it too. A tile's float
        // image must fit one buffer too (it is larger than the samples'
        // framebuffer below 2 spp).
        let margin = scene.pixel_filter.radius();
        let max_pixels = (max_samples / spp64).min(limit / IMAGE_BYTES_PER_PIXEL);
        plan_tiles_with_margin(width, height, max_pixels, margin).ok_or_else(|| {
            // The smallest tile with the margin its filter renders.
            let align = u64::from(TILE_ALIGN);
            let side = |extent: u32, margin: u32| {
                (u64::from(extent).min(align) + 2 * u64::from(margin)).min(u64::from(extent))
            };
            let smallest = side(width, margin[0]) * side(height, margin[1]) * spp64;
            too_large(what, 8 * smallest, 8 * max_samples)
        })
    }

    /// Queue capacities, and the input patches per batch, for a scene of
    /// `patches` input patches: the Bound queue holds one batch of seeds,
    /// the work queues get `work` items. The batch is every patch (or
    /// [`GpuOptions::max_batch_patches`](super::GpuOptions::max_batch_patches))
    /// unless the queues would then not fit into one device buffer
    /// (`memory_plan`); then it is the largest power of two that fits next
    /// to `work`, and `work` is halved (down to [`MIN_WORK_CAPACITY`]) only
    /// while a batch would be smaller than
    /// [`MIN_BATCH_PATCHES`](crate::gpu::batches::MIN_BATCH_PATCHES).
    pub(super) fn capacities(
        &self,
        patches: usize,
        work: u32,
    ) -> Result<(Capacities, u32), RenderError> {
        let limit = self.buffer_limit();
        let all = u32::try_from(patches.max(1))
            .unwrap_or(u32::MAX)
            .min(1 << 31);
        let wanted = self
            .options
            .max_batch_patches
            .map_or(all, |cap| all.min(cap.max(1)));
        let with = |bound: u32, work: u32| {
            DICE.into_iter().fold(
                Capacities::uniform(work)
                    .with(BOUND, bound)
                    .with(SPLIT_U, work)
                    .with(SPLIT_V, work),
                |capacities, dice| capacities.with(dice, work),
            )
        };
        let queue_bytes = |capacities: &Capacities| {
            let plan = self
                .compiled
                .memory_plan(&self.config(capacities.clone(), None));
            plan.queue_bytes.max(plan.control_bytes)
        };
        match plan_batch(wanted, work, limit, |bound, work| {
            queue_bytes(&with(bound, work))
        }) {
            Ok(plan) => Ok((with(plan.bound, plan.work), plan.batch)),
            Err(needed) => Err(RenderError::NoBatchFits {
                patches,
                work_capacity: MIN_WORK_CAPACITY.min(work),
                needed,
                limit,
            }),
        }
    }
}
