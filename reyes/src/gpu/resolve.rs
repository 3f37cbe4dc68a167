//! The clear and resolve passes: a plain compute shader
//! (`shaders/reyes/resolve.wgsl`) run before and after the megakernel.

use std::time::Duration;

use scheduler::RunError;
use scheduler::readback::read_buffer;

use super::RenderError;
use scheduler::wgpu::util::DeviceExt as _;

use scheduler::Item as _;

use crate::filter::FilterKind;
use crate::params::{HASH_MIX, HASH_MULTIPLIERS};
use crate::prepare::PreparedScene;

const RESOLVE_WGSL: &str = include_str!("../../../shaders/reyes/resolve.wgsl");
/// The megakernel's sampling library, whose `jitter_hash` the resolve
/// shares.
const LIBRARY_RASTER_WGSL: &str = include_str!("../../../shaders/reyes/library_raster.wgsl");
/// Threads per workgroup of the clear entry point (`CLEAR_WORKGROUP`, which
/// [`resolve_wgsl`] declares from it).
const CLEAR_WORKGROUP: u64 = 256;

/// The resolve passes' uniform, WGSL struct `ResolveParams`.
#[scheduler::item]
#[derive(Debug)]
pub struct ResolveParams {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Samples per pixel side, `k = sqrt(spp)`.
    pub k: u32,
    /// 1 when samples are jittered.
    pub jitter: u32,
    /// The frame's left column in the full image (the jitter follows
    /// absolute pixel coordinates).
    pub origin_x: u32,
    /// The frame's top row in the full image.
    pub origin_y: u32,
    /// FILTER_* ([`crate::filter::FilterKind::code`]).
    pub filter_kind: u32,
    /// The filter window's width in pixels.
    pub xwidth: f32,
    /// Its height.
    pub ywidth: f32,
    /// Neighbour columns on each side within the window
    /// ([`crate::filter::PixelFilter::radius`]).
    pub radius_x: u32,
    /// Neighbour rows on each side.
    pub radius_y: u32,
    /// The near plane's distance ([`crate::depth::DepthProjection`], for
    /// the depth resolve).
    pub depth_near: f32,
    /// The far plane's distance.
    pub depth_far: f32,
    /// 1 for a perspective camera, 0 for an orthographic one.
    pub depth_perspective: u32,
    /// DEPTH_FILTER_* ([`crate::depth::DepthProjection::code`]).
    pub depth_filter: u32,
    /// Linear RGB background (w unused).
    pub background: glam::Vec4,
}

impl ResolveParams {
    /// The parameters of `scene`'s frame.
    pub fn of(scene: &PreparedScene) -> Self {
        let camera = &scene.camera;
        let filter = scene.pixel_filter;
        let [radius_x, radius_y] = filter.radius();
        let depth = crate::depth::DepthProjection::of(camera);
        Self {
            width: camera.width,
            height: camera.height,
            spp: scene.spp,
            k: crate::sampling::grid_size(scene.spp),
            jitter: u32::from(scene.jitter),
            origin_x: camera.origin[0],
            origin_y: camera.origin[1],
            filter_kind: filter.filter.code(),
            xwidth: filter.xwidth,
            ywidth: filter.ywidth,
            radius_x,
            radius_y,
            depth_near: depth.near,
            depth_far: depth.far,
            depth_perspective: u32::from(depth.perspective),
            depth_filter: crate::depth::DepthProjection::code(scene.depth_filter),
            background: scene.background.extend(0.0),
        }
    }
}

/// The text of the WGSL function `name` in `source`: from its `fn` to the
/// first line that closes it (`}` at the start of a line).
fn wgsl_function<'a>(source: &'a str, name: &str) -> &'a str {
    let start = source
        .find(&format!("fn {name}("))
        .unwrap_or_else(|| panic!("`{name}` is in the WGSL library"));
    let end = source[start..]
        .find("\n}\n")
        .map(|i| start + i + 3)
        .unwrap_or_else(|| panic!("`{name}` ends with `}}` on its own line"));
    &source[start..end]
}

/// The clear and resolve shader: `shaders/reyes/resolve.wgsl` after the
/// declarations it shares with this module ([`ResolveParams`] and
/// `CLEAR_WORKGROUP`).
pub fn resolve_wgsl() -> String {
    let [mx, my, ms, mc] = HASH_MULTIPLIERS;
    let [m0, m1] = HASH_MIX;
    let mut filters: String = FilterKind::ALL
        .iter()
        .map(|k| {
            format!(
                "const FILTER_{}: u32 = {}u;\n",
                k.name().to_uppercase().replace('-', "_"),
                k.code()
            )
        })
        .collect();
    for filter in crate::depth::DepthFilter::ALL {
        filters += &format!(
            "const DEPTH_FILTER_{}: u32 = {}u;\n",
            filter.name().to_uppercase(),
            crate::depth::DepthProjection::code(filter)
        );
    }
    format!(
        "// The clear and resolve passes of the Reyes renderer (reyes::gpu::resolve).\n\n{}\n\n\
         const CLEAR_WORKGROUP: u32 = {CLEAR_WORKGROUP}u;\n\
         const PI: f32 = {:?};\n{filters}\
         const HASH_MUL_X: u32 = {mx}u;\nconst HASH_MUL_Y: u32 = {my}u;\n\
         const HASH_MUL_S: u32 = {ms}u;\nconst HASH_MUL_C: u32 = {mc}u;\n\
         const HASH_MIX_0: u32 = {m0}u;\nconst HASH_MIX_1: u32 = {m1}u;\n\n\
         // reyes::sampling::hash, as the megakernel's library_raster.wgsl has it.\n{}\n\n{RESOLVE_WGSL}",
        ResolveParams::wgsl_struct(),
        std::f32::consts::PI,
        wgsl_function(LIBRARY_RASTER_WGSL, "jitter_hash"),
    )
}

/// The clear and resolve pipelines (created once per renderer).
#[derive(Debug)]
pub struct Resolver {
    layout: wgpu::BindGroupLayout,
    clear: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    resolve_depth: wgpu::ComputePipeline,
}

/// Bytes per pixel of the resolved image: linear RGBA, one `f32` each.
pub const IMAGE_BYTES_PER_PIXEL: u64 = 16;

/// The resolved frame, read back.
#[derive(Debug)]
pub struct Resolved {
    /// Linear RGBA floats, row-major (alpha 1): the filtered values, not
    /// clamped or encoded.
    pub linear: Vec<f32>,
    /// Per pixel: any sample covered.
    pub coverage: Vec<bool>,
    /// Per pixel: how many samples were covered.
    pub covered_samples: Vec<u16>,
}

fn entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Resolver {
    /// Creates the pipelines.
    pub fn new(device: &wgpu::Device) -> Self {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("reyes resolve"),
            source: wgpu::ShaderSource::Wgsl(resolve_wgsl().into()),
        });
        let storage = wgpu::BufferBindingType::Storage { read_only: false };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("reyes resolve"),
            entries: &[
                entry(0, wgpu::BufferBindingType::Uniform),
                entry(1, storage),
                entry(2, storage),
                entry(3, storage),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("reyes resolve"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry_point: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Self {
            clear: pipeline("clear"),
            resolve: pipeline("resolve"),
            resolve_depth: pipeline("resolve_depth"),
            layout,
        }
    }

    fn bind_group(
        &self,
        device: &wgpu::Device,
        target: &ResolveTarget,
        framebuffer: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("reyes resolve"),
            layout: &self.layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: target.params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: framebuffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: target.image.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: target.coverage.as_entire_binding(),
                },
            ],
        })
    }

    /// Sets every sample key of `framebuffer` to `CLEAR_KEY` (submitted at
    /// once; in a frame of the midpoint depth filter, both depths' words to
    /// `u32::MAX`). One thread per sample, the workgroups spread over two
    /// dimensions (`flat_index` in the shader).
    pub fn clear(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &ResolveTarget,
        framebuffer: &wgpu::Buffer,
        samples: u64,
    ) -> Result<(), RenderError> {
        let workgroups = samples.div_ceil(CLEAR_WORKGROUP).max(1);
        let (x, y) = target.grid(device, "clear", workgroups)?;
        submit_checked(device, queue, |encoder| {
            let group = self.bind_group(device, target, framebuffer);
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&self.clear);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        })?;
        Ok(())
    }

    /// Resolves `framebuffer` into the target's image and coverage and reads
    /// them back: the filtered colours, or with `depth` the camera-space
    /// depths ([`crate::depth`], raw: [`crate::depth::finish_depths`] makes
    /// them the depth output).
    pub fn resolve(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &ResolveTarget,
        framebuffer: &wgpu::Buffer,
        depth: bool,
        timeout: Duration,
    ) -> Result<Resolved, RenderError> {
        // One workgroup per 8x8 tile, the tiles numbered row by row over a
        // two-dimensional dispatch (a 1,000,000-pixel-wide frame has 125,000
        // tiles in a row, more than one dimension allows).
        let tiles = u64::from(target.width.div_ceil(8)) * u64::from(target.height.div_ceil(8));
        let (x, y) = target.grid(device, "resolve", tiles.max(1))?;
        submit_checked(device, queue, |encoder| {
            let group = self.bind_group(device, target, framebuffer);
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(if depth {
                &self.resolve_depth
            } else {
                &self.resolve
            });
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(x, y, 1);
        })?;
        let bytes = read_buffer(device, queue, &target.image, timeout)?;
        let linear = bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        let coverage_words = read_buffer(device, queue, &target.coverage, timeout)?;
        // At most 256 samples per pixel: the count is the low half-word.
        let covered_samples: Vec<u16> = coverage_words
            .chunks_exact(4)
            .map(|w| u16::from_le_bytes([w[0], w[1]]))
            .collect();
        let coverage = covered_samples.iter().map(|&n| n != 0).collect();
        Ok(Resolved {
            linear,
            coverage,
            covered_samples,
        })
    }
}

/// `workgroups` spread over two dimensions of at most `limit` each: `x` as
/// wide as allowed, `y` rows of it (the shaders skip the excess of the last
/// row). `None` when more than `limit * limit` are needed.
pub fn dispatch_grid(workgroups: u64, limit: u32) -> Option<(u32, u32)> {
    let limit = u64::from(limit.max(1));
    let x = workgroups.clamp(1, limit);
    let y = workgroups.div_ceil(x);
    (y <= limit).then_some((x as u32, y as u32))
}

/// Encodes the commands `record` writes and submits them inside a
/// validation error scope: a validation error (a dispatch or a binding the
/// device refuses) is returned instead of reaching the device's
/// uncaptured-error handler.
fn submit_checked(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    record: impl FnOnce(&mut wgpu::CommandEncoder),
) -> Result<(), RunError> {
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut encoder = device.create_command_encoder(&Default::default());
    record(&mut encoder);
    queue.submit([encoder.finish()]);
    match pollster::block_on(scope.pop()) {
        Some(error) => Err(RunError::Gpu(error.to_string())),
        None => Ok(()),
    }
}

/// The resolve's per-frame buffers (parameters, image, coverage).
#[derive(Debug)]
pub struct ResolveTarget {
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    params: wgpu::Buffer,
    image: wgpu::Buffer,
    coverage: wgpu::Buffer,
}

impl ResolveTarget {
    /// The two-dimensional dispatch of `workgroups` for `pass`, checked
    /// against the device's limit per dimension before anything is encoded.
    fn grid(
        &self,
        device: &wgpu::Device,
        pass: &'static str,
        workgroups: u64,
    ) -> Result<(u32, u32), RenderError> {
        let limit = device.limits().max_compute_workgroups_per_dimension;
        dispatch_grid(workgroups, limit).ok_or(RenderError::TooManyWorkgroups {
            pass,
            width: self.width,
            height: self.height,
            workgroups,
            limit,
        })
    }

    /// Rewrites the parameters of `scene`'s frame (of this target's size:
    /// the background, the filter and the samples may change between
    /// frames).
    pub fn write_params(&self, queue: &wgpu::Queue, scene: &PreparedScene) {
        let params = ResolveParams::of(scene);
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Buffers for the image of `scene`'s frame.
    pub fn new(device: &wgpu::Device, scene: &PreparedScene) -> Self {
        use wgpu::BufferUsages as U;
        let params = ResolveParams::of(scene);
        let (width, height) = (params.width, params.height);
        let pixels = u64::from(width) * u64::from(height);
        let buffer = |label: &str, bytes_per_pixel: u64| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes_per_pixel * pixels,
                usage: U::STORAGE | U::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        Self {
            width,
            height,
            params: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("reyes resolve params"),
                contents: bytemuck::bytes_of(&params),
                usage: U::UNIFORM | U::COPY_DST,
            }),
            image: buffer("reyes image", IMAGE_BYTES_PER_PIXEL),
            coverage: buffer("reyes coverage", 4),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::dispatch_grid;

    #[test]
    fn a_dispatch_is_spread_over_two_dimensions_within_the_limit() {
        assert_eq!(dispatch_grid(1, 65_535), Some((1, 1)));
        assert_eq!(dispatch_grid(65_535, 65_535), Some((65_535, 1)));
        // 1,000,000 x 1 pixels: 125,000 tiles of 8x8.
        let (x, y) = dispatch_grid(125_000, 65_535).unwrap();
        assert_eq!((x, y), (65_535, 2));
        assert!(u64::from(x) * u64::from(y) >= 125_000);
        let limit = 65_535_u64;
        assert_eq!(
            dispatch_grid(limit * limit, 65_535),
            Some((65_535, 65_535))
        );
        assert_eq!(dispatch_grid(limit * limit + 1, 65_535), None);
        // A small limit, as a device may have.
        assert_eq!(dispatch_grid(10, 4), Some((4, 3)));
        assert_eq!(dispatch_grid(17, 4), None);
        assert_eq!(dispatch_grid(16, 4), Some((4, 4)));
    }
}
