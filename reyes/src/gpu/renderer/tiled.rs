//! Frames in screen tiles: [`GpuRenderer::render_tiles`] renders the tiles
//! one after another, each with the margin the pixel filter reaches beyond
//! it, and pastes them, and their counters, into the frame. The counters of
//! a tiled frame include the margins' work.

use std::time::Instant;

use image::{Rgba32FImage, RgbaImage};

use super::GpuRenderer;
use crate::gpu::options::{FrameTimings, GpuRendered};
use crate::gpu::render_error::RenderError;
use crate::gpu::tiles::Tile;
use crate::prepare::PreparedScene;
use crate::progress::ProgressEvent;
use crate::stats::RenderStats;

/// Adds a tile's counters to a frame's: counts are summed, the largest
/// micropolygon is the largest of any tile. `input_patches` (the scene's,
/// not the tile's) and the frame time are set by the caller.
fn add_tile_stats(total: &mut RenderStats, tile: &RenderStats) {
    // Destructured without `..` so that a new counter has to be placed here.
    let RenderStats {
        input_patches: _,
        splits,
        culled_patches,
        depth_guard_drops,
        grids_diced,
        micropolygons,
        samples_tested,
        samples_hit,
        samples_skipped,
        largest_micropolygon_px,
        displacement_bound_exceeded,
        non_finite_displacement,
        non_finite_transform,
        non_finite_camera,
        interleave_grids,
        grids_by_class,
        dice_threads,
        frame_time_ms: _,
        // A tile is one pass.
        passes: _,
    } = tile;
    for (sum, n) in total.grids_by_class.iter_mut().zip(grids_by_class) {
        *sum += n;
    }
    total.dice_threads += dice_threads;
    total.splits += splits;
    total.culled_patches += culled_patches;
    total.depth_guard_drops += depth_guard_drops;
    total.grids_diced += grids_diced;
    total.micropolygons += micropolygons;
    total.samples_tested += samples_tested;
    total.samples_hit += samples_hit;
    total.samples_skipped += samples_skipped;
    total.largest_micropolygon_px = total.largest_micropolygon_px.max(*largest_micropolygon_px);
    total.displacement_bound_exceeded += displacement_bound_exceeded;
    total.non_finite_displacement += non_finite_displacement;
    total.non_finite_transform += non_finite_transform;
    total.non_finite_camera += non_finite_camera;
    total.interleave_grids += interleave_grids;
}

impl GpuRenderer<'_> {
    /// Renders `scene` tile by tile and pastes the tiles together.
    pub(super) fn render_tiles(
        &mut self,
        scene: &PreparedScene,
        tiles: &[Tile],
    ) -> Result<GpuRendered, RenderError> {
        let start = Instant::now();
        let (width, height) = (scene.camera.width, scene.camera.height);
        log::info!(
            "{width}x{height} at {} spp exceeds one framebuffer: rendering {} screen tiles",
            scene.spp,
            tiles.len()
        );
        // Only the camera differs between tiles: everything else the frame
        // uniform and the tables derive from the scene stays the frame's.
        let mut tile_scene = scene.clone();
        let mut image = RgbaImage::new(width, height);
        let mut linear = Rgba32FImage::new(width, height);
        let mut coverage = vec![false; width as usize * height as usize];
        let mut covered_samples = vec![0u16; width as usize * height as usize];
        let mut stats = RenderStats {
            input_patches: scene.patches.len() as u64,
            ..RenderStats::default()
        };
        let (mut report, mut overflow_retries, mut loop_retries, mut batches) = (None, 0, 0, 0);
        let mut megakernel_gpu_ms = Some(0.0);
        let mut megakernel_wall_ms = 0.0;
        // Each tile renders the margin its pixel filter reaches beyond it,
        // so that its pixels are filtered from the samples they have in
        // the whole frame (the samples follow absolute pixel coordinates).
        let margin = scene.pixel_filter.radius();
        for (index, tile) in tiles.iter().enumerate() {
            let rendered_tile = tile.expanded(margin, width, height);
            tile_scene.camera = scene.camera.crop(
                rendered_tile.x0,
                rendered_tile.y0,
                rendered_tile.width,
                rendered_tile.height,
            );
            self.options.progress.send(|| ProgressEvent::TileStarted {
                tile: index as u32 + 1,
                tiles: tiles.len() as u32,
            });
            let rendered = self.render_tile(&tile_scene)?;
            // Progress: a tiled frame is the longest work the renderer does.
            log::info!(
                "tile {}/{} (x {}..{}, y {}..{}): {:.1} s, {} grids",
                index + 1,
                tiles.len(),
                tile.x0,
                tile.x0 + tile.width,
                tile.y0,
                tile.y0 + tile.height,
                rendered.timings.total_wall_ms / 1e3,
                rendered.stats.grids_diced
            );
            let (tw, x0) = (tile.width as usize, tile.x0 as usize);
            // The tile's pixels within the rendered (expanded) tile.
            let rendered_width = rendered_tile.width as usize;
            let (dx, dy) = (
                (tile.x0 - rendered_tile.x0) as usize,
                (tile.y0 - rendered_tile.y0) as usize,
            );
            for row in 0..tile.height as usize {
                let y = tile.y0 as usize + row;
                let start = (row + dy) * rendered_width + dx;
                let source = start..start + tw;
                let target = y * width as usize + x0..y * width as usize + x0 + tw;
                coverage[target.clone()].copy_from_slice(&rendered.coverage[source.clone()]);
                covered_samples[target.clone()]
                    .copy_from_slice(&rendered.covered_samples[source.clone()]);
                image.as_mut()[4 * target.start..4 * target.end]
                    .copy_from_slice(&rendered.image.as_raw()[4 * source.start..4 * source.end]);
                linear.as_mut()[4 * target.start..4 * target.end]
                    .copy_from_slice(&rendered.linear.as_raw()[4 * source.start..4 * source.end]);
            }
            add_tile_stats(&mut stats, &rendered.stats);
            megakernel_gpu_ms = megakernel_gpu_ms
                .zip(rendered.timings.megakernel_gpu_ms)
                .map(|(a, b)| a + b);
            megakernel_wall_ms += rendered.timings.megakernel_wall_ms;
            overflow_retries += rendered.overflow_retries;
            loop_retries += rendered.loop_retries;
            batches += rendered.batches;
            report = rendered.report.or(report);
        }
        // The tiles' frame times plus the pasting.
        let total_wall_ms = start.elapsed().as_secs_f64() * 1e3;
        stats.frame_time_ms = Some(megakernel_gpu_ms.unwrap_or(total_wall_ms));
        Ok(GpuRendered {
            image,
            linear,
            coverage,
            covered_samples,
            stats,
            report,
            overflow_retries,
            loop_retries,
            timings: FrameTimings {
                megakernel_gpu_ms,
                megakernel_wall_ms,
                total_wall_ms,
            },
            tiles: tiles.len() as u32,
            batches,
        })
    }
}
