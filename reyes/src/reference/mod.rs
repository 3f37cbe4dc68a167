//! The CPU reference renderer: a direct, single-threaded implementation of
//! the pipeline described in `docs/reyes.md`, in `f32` like a GPU. It is the
//! independent check for the GPU implementation of the same algorithm.
//!
//! ```no_run
//! use reyes::{prepare::PreparedScene, reference, scene::Scene};
//!
//! let scene = Scene::default_teapot();
//! let prepared = PreparedScene::load(&scene)?;
//! let rendered = reference::render(&prepared);
//! reyes::output::write_png(&rendered.image, "teapot.png")?;
//! println!("{}", serde_json::to_string_pretty(&rendered.stats)?);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

internal_modules! {
    bound;
    dice;
    displace;
    framebuffer;
    limits;
    quad;
    raster;
    raster5d;
    resolve;
    resolve_depth;
    shade;
    work;
}
mod dice_shade_sample;
mod shutter;

use std::time::{Duration, Instant};

use image::{Rgba32FImage, RgbaImage};

use self::bound::{
    BoundDecision, DiceRule, Growth, ScreenPiece, back_facing, bound, input_edges, split_edges,
};
use self::dice_shade_sample::{FrameContext, FrameOutput, dice_shade_sample};
use self::framebuffer::Framebuffer;
use self::limits::Budget;
pub use self::limits::ReferenceOptions;
use self::raster::SampleGrid;
use self::raster5d::Sampler;
use self::work::WorkItem;
use crate::dicing::EdgeSpacing;
use crate::prepare::PreparedScene;
use crate::sampling::grid_size;
use crate::scene::{Dicing, Scene, SceneError};
use crate::stats::RenderStats;
use crate::uvt::PixelTuples;

/// The result of a render.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The 8-bit image: [`Rendered::linear`] exposed, encoded as sRGB and
    /// quantized ([`PreparedScene::encoding`], see [`crate::quantize`]).
    pub image: RgbaImage,
    /// The resolve's filtered linear RGB, alpha 1: not clamped, not
    /// exposed, not quantized (what the EXR output holds).
    pub linear: Rgba32FImage,
    /// Per pixel (row-major): whether any sample was covered.
    pub coverage: Vec<bool>,
    /// Per pixel (row-major): how many of its samples were covered (up to
    /// 256, so not a byte).
    pub covered_samples: Vec<u16>,
    /// Counters of the frame (`frame_time_ms` is the whole render, resolve included).
    pub stats: RenderStats,
}

/// Why the reference cannot render a scene.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReferenceError {
    /// An object is displaced by a user WGSL height function without a
    /// Rust twin ([`crate::prepare::PreparedScene::set_height_twin`]): only
    /// the GPU can run it.
    #[error(
        "object {object} is displaced by a user WGSL function, which the CPU reference cannot run; render it on the GPU, or give a Rust twin through the API (PreparedScene::set_height_twin)"
    )]
    UserDisplacement {
        /// Index of the object.
        object: usize,
    },
    /// An object runs a user WGSL surface shader without a Rust twin
    /// ([`crate::surface_shader::SurfaceShader::cpu`]): only the GPU can run it.
    #[error(
        "object {object} runs the WGSL surface shader {}, which the CPU reference cannot run; render it on the GPU (without --cpu), or give a Rust twin through the API (SurfaceShader::cpu)",
        file.display()
    )]
    UserSurface {
        /// Index of the object.
        object: usize,
        /// The shader file.
        file: std::path::PathBuf,
    },
    /// An object runs a WGSL displacement shader without a Rust twin
    /// ([`crate::surface_shader::SurfaceShader::cpu_displacement`]).
    #[error(
        "object {object} runs the WGSL displacement shader {}, which the CPU reference cannot run; render it on the GPU (without --cpu), or give a Rust twin through the API (SurfaceShader::cpu_displacement)",
        file.display()
    )]
    UserDisplacementShader {
        /// Index of the object.
        object: usize,
        /// The shader file.
        file: std::path::PathBuf,
    },
    /// The RGBA image is larger than the renderers allow
    /// ([`ReferenceOptions::max_image_bytes`], by default
    /// [`limits::MAX_IMAGE_BYTES`], the GPU path's limit too).
    #[error(
        "{width}x{height} needs a {needed}-byte RGBA image but at most {limit} bytes are allowed (reyes::prepare::MAX_IMAGE_BYTES, lavapipe's per-buffer limit, which the CPU reference shares with the GPU path); lower the resolution (--width/--height)"
    )]
    ImageTooLarge {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The depth pass of an automatic shadow map is larger than the
    /// reference allows ([`ReferenceError::ImageTooLarge`] or
    /// [`ReferenceError::FramebufferTooLarge`] of the pass).
    #[error(
        "the depth pass \"{pass}\": {width}x{height} needs {needed} bytes but the CPU reference allows at most {limit}; lower the light's map_size, or render on the GPU, which renders large frames in tiles"
    )]
    DepthPassTooLarge {
        /// The pass (its light and side).
        pass: String,
        /// Map width.
        width: u32,
        /// Map height.
        height: u32,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The sample framebuffer (8 bytes per sample) is larger than
    /// [`ReferenceOptions::max_framebuffer_bytes`].
    #[error(
        "{width}x{height} at {spp} spp needs a {needed}-byte sample framebuffer but the CPU reference allows at most {limit} bytes; lower the resolution or spp, raise ReferenceOptions::max_framebuffer_bytes through the API, or render on the GPU, which renders large frames in tiles"
    )]
    FramebufferTooLarge {
        /// Image width.
        width: u32,
        /// Image height.
        height: u32,
        /// Samples per pixel.
        spp: u32,
        /// Bytes needed.
        needed: u64,
        /// Bytes allowed.
        limit: u64,
    },
    /// The host could not allocate the sample framebuffer.
    #[error(
        "the host could not allocate the {bytes}-byte sample framebuffer of the CPU reference; lower the resolution or spp"
    )]
    OutOfMemory {
        /// Bytes asked for.
        bytes: u64,
    },
    /// The frame needs more work than the options allow.
    #[error(
        "the CPU reference stopped after {limit} {what} (ReferenceOptions::{field}, a bound on the work of one frame); the scene needs more: raise dice_threshold or shading_rate, lower max_split_depth or the resolution, or raise ReferenceOptions::{field} through the API"
    )]
    WorkLimit {
        /// What was counted.
        what: &'static str,
        /// The bound.
        limit: u64,
        /// The option that sets it.
        field: &'static str,
    },
    /// The frame took longer than [`ReferenceOptions::timeout`].
    #[error(
        "the CPU render timed out after {elapsed:.1?} (limit {timeout:?}, {items} work items processed); raise --timeout (ReferenceOptions::timeout), or make the frame cheaper: raise dice_threshold or shading_rate, lower max_split_depth, spp or the resolution"
    )]
    Timeout {
        /// The limit.
        timeout: Duration,
        /// Work items processed when it expired.
        items: u64,
        /// Time taken until the check that found it expired.
        elapsed: Duration,
    },
}

impl ReferenceError {
    /// This error as it happened in the depth pass `pass` of an automatic
    /// shadow map: a frame too large becomes [`ReferenceError::DepthPassTooLarge`],
    /// which suggests the map size rather than the image size.
    fn in_depth_pass(self, pass: &str) -> ReferenceError {
        let pass = pass.to_owned();
        match self {
            ReferenceError::ImageTooLarge {
                width,
                height,
                needed,
                limit,
            }
            | ReferenceError::FramebufferTooLarge {
                width,
                height,
                needed,
                limit,
                ..
            } => ReferenceError::DepthPassTooLarge {
                pass,
                width,
                height,
                needed,
                limit,
            },
            other => other,
        }
    }
}

/// Renders a prepared scene within the default [`ReferenceOptions`], or
/// says why the reference cannot (see [`ReferenceError`]).
pub fn try_render(scene: &PreparedScene) -> Result<Rendered, ReferenceError> {
    try_render_with(scene, &ReferenceOptions::default())
}

/// Renders a prepared scene within `options`, or says why the reference
/// cannot (see [`ReferenceError`]): a user WGSL displacement without a
/// Rust twin, a frame too large, too much work or too much time.
pub fn try_render_with(
    scene: &PreparedScene,
    options: &ReferenceOptions,
) -> Result<Rendered, ReferenceError> {
    if let Some(object) = scene.objects.iter().position(|o| {
        o.displacement
            .as_ref()
            .is_some_and(|d| !d.cpu_evaluable(&scene.shaders))
    }) {
        let displacement = scene.objects[object].displacement.as_ref();
        let shader = displacement
            .and_then(|d| d.shader())
            .and_then(|s| scene.shaders.shaders.get(s.reference.shader as usize));
        return Err(match shader {
            Some(shader) if !crate::displacement::height_shader::is_height_shader(&shader.path) => {
                ReferenceError::UserDisplacementShader {
                    object,
                    file: shader.path.clone(),
                }
            }
            _ => ReferenceError::UserDisplacement { object },
        });
    }
    for (object, prepared) in scene.objects.iter().enumerate() {
        if let Some(crate::shading::PreparedSurface::User { shader, .. }) = prepared.surface
            && let Some(shader) = scene.shaders.shaders.get(shader as usize)
            && shader.cpu.is_none()
        {
            return Err(ReferenceError::UserSurface {
                object,
                file: shader.path.clone(),
            });
        }
    }
    render_bounded(scene, options)
}

/// Renders a prepared scene.
///
/// An object displaced by a user WGSL function without a Rust twin cannot be
/// displaced on the CPU: it is rendered undisplaced (with a logged warning).
/// The work and time are not bounded ([`ReferenceOptions::unbounded_work`]).
///
/// # Panics
///
/// When the frame is larger than the reference allows
/// ([`ReferenceOptions::check_frame`]) or its framebuffer cannot be
/// allocated. Use [`try_render`] or [`try_render_with`] to get an error
/// instead.
pub fn render(scene: &PreparedScene) -> Rendered {
    render_bounded(scene, &ReferenceOptions::unbounded_work())
        .unwrap_or_else(|error| panic!("the reference cannot render this scene: {error}"))
}

/// Renders `scene`, its pending shadows first ([`PreparedScene::with_shadow_maps`]):
/// each depth pass and then the frame, within `options` each.
fn render_bounded(
    scene: &PreparedScene,
    options: &ReferenceOptions,
) -> Result<Rendered, ReferenceError> {
    scene.render_with_shadows(|pass, depth_pass| {
        render_pass(pass, options).map_err(|error| match depth_pass {
            Some(name) => error.in_depth_pass(name),
            None => error,
        })
    })
}

impl crate::prepare::RenderedPass for Rendered {
    fn linear(&self) -> &Rgba32FImage {
        &self.linear
    }
    fn stats_mut(&mut self) -> &mut RenderStats {
        &mut self.stats
    }
}

/// Renders one pass: `scene` as it is (its maps already there).
fn render_pass(
    scene: &PreparedScene,
    options: &ReferenceOptions,
) -> Result<Rendered, ReferenceError> {
    let start = Instant::now();
    let (framebuffer, mut stats) = try_render_samples(scene, options)?;
    let layout = resolve::SampleLayout {
        k: crate::sampling::grid_size(scene.spp),
        jitter: scene.jitter,
    };
    let (linear, covered_samples) = if scene.aov == crate::Aov::Z {
        resolve_depth::resolve_depth(
            &framebuffer,
            crate::depth::DepthProjection::of(&scene.camera),
            scene.depth_filter,
        )
    } else {
        resolve::resolve(&framebuffer, scene.background, &scene.pixel_filter, layout)
    };
    let coverage = covered_samples.iter().map(|&n| n != 0).collect();
    let image = scene.encoding.encode(&linear, scene.camera.origin);
    stats.frame_time_ms = Some(start.elapsed().as_secs_f64() * 1000.0);
    Ok(Rendered {
        image,
        linear,
        coverage,
        covered_samples,
        stats,
    })
}

/// Loads the scene's models, prepares and renders it.
pub fn render_scene(scene: &Scene) -> Result<Rendered, SceneError> {
    Ok(render(&PreparedScene::load(scene)?))
}

/// Runs the pipeline up to (not including) the resolve: the filled sample
/// framebuffer and the statistics (`frame_time_ms` unset). Useful to compare
/// sample keys with another implementation.
///
/// # Panics
///
/// Like [`render`]; [`try_render_samples`] returns the error instead.
pub fn render_samples(scene: &PreparedScene) -> (Framebuffer, RenderStats) {
    try_render_samples(scene, &ReferenceOptions::unbounded_work())
        .unwrap_or_else(|error| panic!("the reference cannot render this scene: {error}"))
}

/// [`render_samples`] within `options` (see [`try_render_with`]; a user
/// WGSL displacement is rendered undisplaced here, with a warning). Pending
/// shadows are rendered first, as [`render`] renders them; the statistics
/// are the frame's alone.
pub fn try_render_samples(
    scene: &PreparedScene,
    options: &ReferenceOptions,
) -> Result<(Framebuffer, RenderStats), ReferenceError> {
    if !scene.pending_shadows.is_empty() {
        let frame = scene.with_shadow_maps(|pass| {
            render_pass(&pass.scene, options)
                .map(|rendered| crate::depth::depths(&rendered.linear))
                .map_err(|error| error.in_depth_pass(&pass.name))
        })?;
        return try_render_samples(&frame, options);
    }
    let camera = &scene.camera;
    options.check_frame(camera.width, camera.height, scene.spp)?;
    let mut budget = Budget::new(options);
    let view_proj = camera.view_proj();
    let layers = if scene.keeps_second_depth() { 2 } else { 1 };
    let out_of_memory = || ReferenceError::OutOfMemory {
        bytes: u64::from(camera.width)
            .saturating_mul(u64::from(camera.height))
            .saturating_mul(u64::from(scene.spp))
            .saturating_mul(8 * layers),
    };
    let mut framebuffer =
        Framebuffer::try_new(camera.width, camera.height, scene.spp).ok_or_else(out_of_memory)?;
    if layers == 2 {
        framebuffer = framebuffer.keep_second().ok_or_else(out_of_memory)?;
    }
    let samples = SampleGrid::new(grid_size(scene.spp), scene.jitter);
    let uvt = scene.samples_time_and_lens().then(|| scene.uvt_tables());
    let sampler = uvt.as_ref().map(|uvt| Sampler {
        samples: &samples,
        uvt,
        pixel_tuples: PixelTuples::for_sampling(scene.sampling),
        micropolygon_px: scene.nominal_micropolygon_px(),
    });
    let mut stats = RenderStats {
        input_patches: scene.patches.len() as u64,
        ..RenderStats::default()
    };

    for (index, object) in scene.objects.iter().enumerate() {
        if object
            .displacement
            .as_ref()
            .is_some_and(|d| !d.cpu_evaluable(&scene.shaders))
        {
            log::warn!(
                "object {index}: the CPU reference cannot run a user WGSL displacement (function or shader) without its Rust twin; rendering it undisplaced"
            );
        }
    }
    // Depth-first: a stack keeps at most about max_split_depth pending
    // pieces per input patch. The order does not change the result, because
    // the framebuffer keeps the minimum key per sample.
    let rate = scene.dicing.mode() == Dicing::Rate;
    let mut stack: Vec<WorkItem> = scene
        .patches
        .iter()
        .enumerate()
        .rev()
        .map(|(index, p)| {
            let edges = if rate {
                let object = &scene.objects[p.object as usize];
                let side = scene.object_dicing(object).micropolygon_side();
                input_edges(
                    &ScreenPiece::new(&view_proj, camera, &p.points, object.displacement_bound()),
                    side,
                )
            } else {
                [EdgeSpacing::UNFIXED; 4]
            };
            WorkItem::new(p.points, p.object, index as u32, edges)
        })
        .collect();
    let frame = FrameContext {
        scene,
        view_proj,
        samples: &samples,
        sampler: sampler.as_ref(),
        triangle_boxes: options.triangle_boxes,
    };
    while let Some(item) = stack.pop() {
        budget.item()?;
        let object = &scene.objects[item.object as usize];
        let dicing = scene.object_dicing(object);
        let side = dicing.micropolygon_side();
        // One-sided, still, sharp and undisplaced input patches that face
        // away everywhere are culled here (split pieces are culled
        // micropolygon by micropolygon when sampled).
        let cull_back = object.front.filter(|_| {
            item.split_depth == 0
                && object.motion.is_none()
                && scene.lens.aperture == 0.0
                && object.displacement.is_none()
        });
        if cull_back.is_some_and(|front| back_facing(&item.points, camera.homogeneous_eye(), front))
        {
            stats.culled_patches += 1;
            continue;
        }
        let rule = if rate {
            DiceRule::Rate {
                edges: &item.edges,
                uv: item.uv,
                side,
            }
        } else {
            DiceRule::Fixed
        };
        match bound(
            &item.points,
            item.split_depth,
            &view_proj,
            camera,
            dicing.dice_threshold(),
            scene.max_split_depth,
            Growth {
                displacement_bound: object.displacement_bound(),
                motion: object.motion.as_ref(),
                lens: &scene.lens,
            },
            rule,
        ) {
            BoundDecision::Cull => stats.culled_patches += 1,
            BoundDecision::Drop => stats.depth_guard_drops += 1,
            BoundDecision::Split(direction) => {
                stats.splits += 1;
                let mut halves = item.split(direction);
                if rate {
                    let bound = object.displacement_bound();
                    for (half, piece) in halves.iter_mut().enumerate() {
                        let screen = ScreenPiece::new(&view_proj, camera, &piece.points, bound);
                        piece.edges =
                            split_edges(&item.edges, direction, half, &screen, piece.uv, side);
                    }
                }
                let [first, second] = halves;
                // Push the second half first so the first is processed next.
                stack.push(second);
                stack.push(first);
            }
            BoundDecision::Dice(size) => {
                budget.grid(&stats, size.quads())?;
                let mut output = FrameOutput {
                    framebuffer: &mut framebuffer,
                    stats: &mut stats,
                    budget: &mut budget,
                };
                dice_shade_sample(&frame, &mut output, &item, size)?;
            }
        }
    }
    Ok((framebuffer, stats))
}
