//! Putting frames on the window: the rendered image is uploaded to a
//! texture, drawn (scaled to the window) into an offscreen composite
//! texture together with the overlay, and the composite is blitted to the
//! surface. The composite is what the window shows, and it can be read
//! back, so a screenshot is exactly the presented image on any surface
//! (whether or not the surface allows copies).
//!
//! All colour passes work on the sRGB-encoded bytes as they are (`Unorm`
//! views), so an image drawn at its own size reaches the window and the
//! screenshot byte for byte.

use std::sync::Arc;
use std::time::Duration;

use image::RgbaImage;
use winit::window::Window;

use super::error::ViewError;

/// The composite's format, which egui also draws in (gamma-space output).
pub const COMPOSITE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

const BLIT_WGSL: &str = r"
@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var source_sampler: sampler;

struct Varyings {
    @builtin(position) position: vec4f,
    @location(0) uv: vec2f,
};

// One triangle covering the target; uv (0, 0) is the top-left corner.
@vertex
fn vs(@builtin(vertex_index) index: u32) -> Varyings {
    let uv = vec2f(f32((index << 1u) & 2u), f32(index & 2u));
    var out: Varyings;
    out.position = vec4f(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

@fragment
fn fs(in: Varyings) -> @location(0) vec4f {
    return textureSample(source, source_sampler, in.uv);
}
";

/// A texture with the view drawn from it.
#[derive(Debug)]
struct Target {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
}

impl Target {
    fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        usage: wgpu::TextureUsages,
    ) -> Self {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: COMPOSITE_FORMAT,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Target { texture, view }
    }

    fn size(&self) -> (u32, u32) {
        (self.texture.width(), self.texture.height())
    }
}

/// The window's surface and the textures and pipelines that fill it.
#[derive(Debug)]
pub struct Presenter {
    /// The window the surface belongs to.
    pub window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The surface format drawn in: the configured one without its sRGB
    /// suffix (bytes pass through unchanged).
    draw_format: wgpu::TextureFormat,
    device: wgpu::Device,
    queue: wgpu::Queue,
    to_composite: wgpu::RenderPipeline,
    to_surface: wgpu::RenderPipeline,
    nearest: wgpu::Sampler,
    linear: wgpu::Sampler,
    /// The last frame uploaded, with its bind groups (nearest, linear).
    frame: Option<(Target, wgpu::BindGroup, wgpu::BindGroup)>,
    composite: Target,
    composite_group: wgpu::BindGroup,
}

impl Presenter {
    /// Configures `surface` for `window` on the device.
    pub fn new(
        window: Arc<Window>,
        surface: wgpu::Surface<'static>,
        adapter: &wgpu::Adapter,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
    ) -> Result<Presenter, ViewError> {
        let size = window.inner_size();
        let (width, height) = (size.width.max(1), size.height.max(1));
        let caps = surface.get_capabilities(adapter);
        let format = *caps.formats.first().ok_or(ViewError::SurfaceUnsupported)?;
        let mut config = surface
            .get_default_config(adapter, width, height)
            .ok_or(ViewError::SurfaceUnsupported)?;
        let draw_format = format.remove_srgb_suffix();
        config.format = format;
        config.view_formats = if draw_format == format {
            vec![]
        } else {
            vec![draw_format]
        };
        // Fifo is always supported; frames arrive far slower than vsync.
        config.present_mode = wgpu::PresentMode::AutoVsync;
        surface.configure(device, &config);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("reyes view blit"),
            source: wgpu::ShaderSource::Wgsl(BLIT_WGSL.into()),
        });
        let pipeline = |format: wgpu::TextureFormat| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("reyes view blit"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let to_composite = pipeline(COMPOSITE_FORMAT);
        let to_surface = pipeline(draw_format);
        let sampler = |filter: wgpu::FilterMode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("reyes view"),
                mag_filter: filter,
                min_filter: filter,
                ..Default::default()
            })
        };
        let nearest = sampler(wgpu::FilterMode::Nearest);
        let linear = sampler(wgpu::FilterMode::Linear);
        let composite = composite_target(device, (width, height));
        let composite_group = bind(device, &to_surface, &composite.view, &nearest);
        Ok(Presenter {
            window,
            surface,
            config,
            draw_format,
            device: device.clone(),
            queue: queue.clone(),
            to_composite,
            to_surface,
            nearest,
            linear,
            frame: None,
            composite,
            composite_group,
        })
    }

    /// The surface's size in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follows a window resize (a zero size, when minimised, is skipped:
    /// nothing is drawn until the window has an area again). True when
    /// the size changed.
    pub fn resize(&mut self, width: u32, height: u32) -> bool {
        if width == 0 || height == 0 || (width, height) == self.size() {
            return false;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
        self.composite = composite_target(&self.device, (width, height));
        self.composite_group = bind(
            &self.device,
            &self.to_surface,
            &self.composite.view,
            &self.nearest,
        );
        true
    }

    /// Uploads a rendered frame; it is drawn scaled to the window (nearest
    /// at its own size, so its bytes reach the window unchanged).
    pub fn upload(&mut self, image: &RgbaImage) {
        let size = image.dimensions();
        if self.frame.as_ref().is_none_or(|(t, _, _)| t.size() != size) {
            let target = Target::new(
                &self.device,
                "reyes view frame",
                size,
                wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            );
            let nearest = bind(
                &self.device,
                &self.to_composite,
                &target.view,
                &self.nearest,
            );
            let linear = bind(&self.device, &self.to_composite, &target.view, &self.linear);
            self.frame = Some((target, nearest, linear));
        }
        let Some((target, _, _)) = &self.frame else {
            return;
        };
        self.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &target.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            image.as_raw(),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * size.0),
                rows_per_image: None,
            },
            target.texture.size(),
        );
    }

    /// Draws the frame and the overlay (`overlay` records its passes into
    /// the encoder, drawing onto the composite) and presents. Returns
    /// false when no surface texture could be had this time (the caller
    /// tries again on the next redraw).
    pub fn present(
        &mut self,
        overlay: impl FnOnce(&mut wgpu::CommandEncoder, &wgpu::TextureView),
    ) -> Result<bool, ViewError> {
        let surface_texture = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t)
            | wgpu::CurrentSurfaceTexture::Suboptimal(t) => t,
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Outdated => {
                // Configure again at the window's current size and retry
                // on the next redraw.
                let size = self.window.inner_size();
                self.config.width = size.width.max(1);
                self.config.height = size.height.max(1);
                self.surface.configure(&self.device, &self.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Lost => return Err(ViewError::SurfaceLost),
            other => return Err(ViewError::Surface(format!("{other:?}"))),
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reyes view present"),
            });
        {
            let mut pass = begin(&mut encoder, &self.composite.view, "reyes view composite");
            if let Some((target, nearest, linear)) = &self.frame {
                // A preview at a lower resolution is smoothed, not blocky.
                let group = if target.size() == self.composite.size() {
                    nearest
                } else {
                    linear
                };
                pass.set_pipeline(&self.to_composite);
                pass.set_bind_group(0, group, &[]);
                pass.draw(0..3, 0..1);
            }
        }
        overlay(&mut encoder, &self.composite.view);
        let surface_view = surface_texture
            .texture
            .create_view(&wgpu::TextureViewDescriptor {
                format: Some(self.draw_format),
                ..Default::default()
            });
        {
            let mut pass = begin(&mut encoder, &surface_view, "reyes view to surface");
            pass.set_pipeline(&self.to_surface);
            pass.set_bind_group(0, &self.composite_group, &[]);
            pass.draw(0..3, 0..1);
        }
        self.queue.submit([encoder.finish()]);
        self.window.pre_present_notify();
        self.queue.present(surface_texture);
        Ok(true)
    }

    /// Reads the composite (the image last presented) back.
    pub fn read_composite(&self) -> Result<RgbaImage, ViewError> {
        let (width, height) = self.composite.size();
        let row = (4 * width).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let buffer = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reyes view screenshot"),
            size: u64::from(row) * u64::from(height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("reyes view screenshot"),
            });
        encoder.copy_texture_to_buffer(
            self.composite.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row),
                    rows_per_image: None,
                },
            },
            self.composite.texture.size(),
        );
        let submission = self.queue.submit([encoder.finish()]);
        let bytes = scheduler::readback::map_read(
            &self.device,
            &buffer,
            submission,
            Duration::from_secs(60),
        )
        .map_err(|e| ViewError::Screenshot(e.to_string()))?;
        let mut pixels = Vec::with_capacity((4 * width * height) as usize);
        for y in 0..height as usize {
            let start = y * row as usize;
            pixels.extend_from_slice(&bytes[start..start + 4 * width as usize]);
        }
        RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| ViewError::Screenshot("readback size mismatch".into()))
    }
}

fn composite_target(device: &wgpu::Device, size: (u32, u32)) -> Target {
    Target::new(
        device,
        "reyes view composite",
        size,
        wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
    )
}

fn bind(
    device: &wgpu::Device,
    pipeline: &wgpu::RenderPipeline,
    view: &wgpu::TextureView,
    sampler: &wgpu::Sampler,
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("reyes view blit"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(sampler),
            },
        ],
    })
}

/// A render pass clearing `view` to black.
fn begin<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    label: &str,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
