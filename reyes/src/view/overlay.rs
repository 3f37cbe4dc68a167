//! The overlay: frame times, the renderer's counters, the settings and the
//! keys, drawn with egui onto the composite texture. While the driver
//! compiles the megakernel it says so, with the seconds it has taken.

use std::time::Instant;

use winit::event::WindowEvent;
use winit::window::Window;

use super::controls::Settings;
use super::shadow_cache::ShadowTime;
use super::worker::{Compiling, Frame, Quality};
use crate::progress::elapsed_label;
use crate::scene::Dicing;
use crate::stats::RenderStats;

/// What the overlay shows about the last frame.
#[derive(Debug, Clone)]
pub struct FrameInfo {
    /// Preview or full.
    pub quality: Quality,
    /// Its size in pixels.
    pub size: (u32, u32),
    /// Samples per pixel it was rendered with.
    pub spp: u32,
    /// Megakernel time on the GPU, when measured.
    pub gpu_ms: Option<f64>,
    /// Wall time in the render worker.
    pub wall_ms: f64,
    /// The renderer's counters.
    pub stats: RenderStats,
    /// The time of its shadow maps (automatic shadows).
    pub shadows: Option<ShadowTime>,
}

impl FrameInfo {
    /// The overlay's summary of `frame`.
    pub fn of(frame: &Frame) -> FrameInfo {
        FrameInfo {
            quality: frame.spec.quality,
            size: frame.image.dimensions(),
            spp: match frame.spec.quality {
                Quality::Preview => 1,
                Quality::Full => frame.spec.settings.spp,
            },
            gpu_ms: frame.gpu_ms,
            wall_ms: frame.wall_ms,
            stats: frame.stats.clone(),
            shadows: frame.shadows,
        }
    }
}

/// Everything the overlay draws.
#[derive(Debug, Clone)]
pub struct OverlayInfo<'a> {
    /// The adapter's description.
    pub adapter: &'a str,
    /// The last frame shown, if any.
    pub frame: Option<&'a FrameInfo>,
    /// The current settings.
    pub settings: &'a Settings,
    /// What the worker is doing (e.g. "rendering preview").
    pub status: &'a str,
    /// The driver's compile of the megakernel, while it lasts: shown
    /// instead of `status`.
    pub compiling: Option<&'a Compiling>,
}

/// The overlay's line for `compiling` at `now`:
/// `compiling the GPU program for llvmpipe (...) … 12 s`.
pub fn compiling_line(compiling: &Compiling, now: Instant) -> String {
    format!(
        "{} … {}",
        compiling.label,
        elapsed_label(now.saturating_duration_since(compiling.since))
    )
}

/// The egui context, its window-event translation and its renderer.
pub struct Overlay {
    ctx: egui::Context,
    state: egui_winit::State,
    renderer: egui_wgpu::Renderer,
    device: wgpu::Device,
    queue: wgpu::Queue,
}

impl std::fmt::Debug for Overlay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Overlay").finish_non_exhaustive()
    }
}

impl Overlay {
    /// An overlay for `window`, drawing in `format`.
    pub fn new(
        window: &Window,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        format: wgpu::TextureFormat,
    ) -> Overlay {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(device.limits().max_texture_dimension_2d as usize),
        );
        let renderer =
            egui_wgpu::Renderer::new(device, format, egui_wgpu::RendererOptions::default());
        Overlay {
            ctx,
            state,
            renderer,
            device: device.clone(),
            queue: queue.clone(),
        }
    }

    /// Passes a window event to egui; true when egui used it (a click on
    /// the overlay must not orbit the camera).
    pub fn on_window_event(&mut self, window: &Window, event: &WindowEvent) -> (bool, bool) {
        let response = self.state.on_window_event(window, event);
        (response.consumed, response.repaint)
    }

    /// Records the overlay's passes onto `target` (whose size is `size`).
    /// True when egui asks to be drawn again right away (it lays a new
    /// window out over two passes).
    pub fn draw(
        &mut self,
        window: &Window,
        encoder: &mut wgpu::CommandEncoder,
        target: &wgpu::TextureView,
        size: (u32, u32),
        info: &OverlayInfo<'_>,
    ) -> bool {
        let (device, queue) = (&self.device, &self.queue);
        let input = self.state.take_egui_input(window);
        let output = self.ctx.run_ui(input, |ui| panel(ui, info));
        self.state
            .handle_platform_output(window, output.platform_output);
        let jobs = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        for (id, deltas) in &output.textures_delta.set {
            for delta in deltas {
                self.renderer.update_texture(device, queue, *id, delta);
            }
        }
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [size.0, size.1],
            pixels_per_point: output.pixels_per_point,
        };
        let extra = self
            .renderer
            .update_buffers(device, queue, encoder, &jobs, &screen);
        if !extra.is_empty() {
            queue.submit(extra);
        }
        {
            let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("reyes view overlay"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            // egui's renderer takes a pass without the encoder's lifetime.
            let mut pass = pass.forget_lifetime();
            self.renderer.render(&mut pass, &jobs, &screen);
        }
        for id in &output.textures_delta.free {
            self.renderer.free_texture(id);
        }
        output
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .is_some_and(|v| v.repaint_delay.is_zero())
    }
}

/// The overlay's one window.
fn panel(ui: &mut egui::Ui, info: &OverlayInfo<'_>) {
    egui::Window::new("reyes view")
        .default_pos([8.0, 8.0])
        .resizable(false)
        .show(ui.ctx(), |ui| {
            ui.label(info.adapter);
            match info.compiling {
                Some(compiling) => ui.label(compiling_line(compiling, Instant::now())),
                None => ui.label(info.status),
            };
            ui.separator();
            match info.frame {
                Some(frame) => frame_rows(ui, frame),
                None => {
                    ui.label("no frame yet\n(the first one compiles the megakernel)");
                }
            }
            ui.separator();
            let s = info.settings;
            let dicing = match s.dicing {
                Dicing::Rate => format!("shading rate {} px", s.shading_rate),
                Dicing::Fixed => format!("dice threshold {} px", s.dice_threshold),
            };
            ui.label(format!(
                "{} sampling, {} spp\n{dicing}\nmotion blur {}, aperture {:.4}\nAOV {}, shadows {}",
                s.sampling.name(),
                s.spp,
                if s.motion_blur { "on" } else { "off" },
                s.aperture,
                s.aov.name(),
                if s.shadows { "on" } else { "off" }
            ));
            egui::CollapsingHeader::new("keys")
                .default_open(false)
                .show(ui, |ui| {
                    ui.label(
                        "left drag: orbit, right/middle drag: pan\nwheel: zoom, F: frame\n\
                         M: sampling, +/-: spp\n[/]: finer/coarser dicing\n\
                         B: motion blur, A/Z: aperture\nS: shadows, V: AOV\nP: save PNG, \
                         H: overlay, Esc: quit",
                    );
                });
        });
}

fn frame_rows(ui: &mut egui::Ui, frame: &FrameInfo) {
    let quality = match frame.quality {
        Quality::Preview => "preview",
        Quality::Full => "refined",
    };
    let gpu = frame
        .gpu_ms
        .map_or_else(|| "-".to_owned(), |ms| format!("{ms:.1} ms"));
    let stats = &frame.stats;
    ui.label(format!(
        "{quality} frame {}x{}, {} spp\nGPU {gpu}, wall {:.1} ms\n\
         micropolygons {}\nsamples tested {}\nsamples hit {}\nsample test efficiency {:.4}",
        frame.size.0,
        frame.size.1,
        frame.spp,
        frame.wall_ms,
        stats.micropolygons,
        stats.samples_tested,
        stats.samples_hit,
        stats.sample_test_efficiency()
    ));
    if let Some(shadows) = frame.shadows {
        ui.label(format!(
            "shadow maps {:.1} ms ({})",
            shadows.passes_ms,
            if shadows.reused { "reused" } else { "rendered" }
        ));
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    #[test]
    fn the_compile_line_counts_whole_seconds() {
        let since = Instant::now();
        let compiling = Compiling {
            label: "compiling the GPU program for llvmpipe (cached after the first run)".into(),
            since,
        };
        assert_eq!(
            compiling_line(&compiling, since + Duration::from_millis(12_400)),
            "compiling the GPU program for llvmpipe (cached after the first run) … 12 s"
        );
        assert!(compiling_line(&compiling, since).ends_with("… 0 s"));
    }
}
