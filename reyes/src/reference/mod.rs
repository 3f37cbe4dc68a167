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

pub mod bound;
pub mod dice;
pub mod displace;
pub mod framebuffer;
pub mod raster;
pub mod raster5d;
pub mod resolve;
pub mod shade;
pub mod work;

use std::time::Instant;

use image::RgbaImage;

use self::bound::{BoundDecision, Growth, bound};
use self::dice::{GRID_LEN, dice};
use self::displace::dice_displaced;
use self::framebuffer::Framebuffer;
use self::raster::{
    SampleGrid, ScreenPoint, micropolygon_corners, micropolygon_size, raster_nearest,
    raster_triangle,
};
use self::raster5d::{Mode5d, MovingPoint, Sampler, raster_triangle_5d};
use self::shade::shade;
use self::work::WorkItem;
use crate::color::pack_rgb10;
use crate::params::{GRID_QUADS, MICROPOLYGONS_PER_GRID};
use crate::prepare::PreparedScene;
use crate::sampling::grid_size;
use crate::scene::{Sampling, Scene, SceneError};
use crate::stats::RenderStats;
use crate::uvt::UvtTables;

/// The result of a render.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The resolved image, 8-bit sRGB, alpha 255.
    pub image: RgbaImage,
    /// Per pixel (row-major): whether any sample was covered.
    pub coverage: Vec<bool>,
    /// Counters of the frame (`frame_time_ms` is the whole render, resolve included).
    pub stats: RenderStats,
}

/// Why the reference cannot render a scene.
#[derive(Debug, thiserror::Error)]
pub enum ReferenceError {
    /// An object is displaced by a user WGSL function without a Rust twin
    /// ([`crate::displacement::UserFunction::cpu`]): only the GPU can run it.
    #[error(
        "object {object} is displaced by a user WGSL function, which the CPU reference cannot run; render it on the GPU, or give a Rust twin through the API (UserFunction::cpu)"
    )]
    UserDisplacement {
        /// Index of the object.
        object: usize,
    },
}

/// Renders a prepared scene, or says why the reference cannot (see
/// [`ReferenceError`]).
pub fn try_render(scene: &PreparedScene) -> Result<Rendered, ReferenceError> {
    if let Some(object) = scene
        .objects
        .iter()
        .position(|o| o.displacement.as_ref().is_some_and(|d| !d.cpu_evaluable()))
    {
        return Err(ReferenceError::UserDisplacement { object });
    }
    Ok(render(scene))
}

/// Renders a prepared scene.
///
/// An object displaced by a user WGSL function without a Rust twin cannot be
/// displaced on the CPU: it is rendered undisplaced (with a logged warning).
/// Use [`try_render`] to get an error instead.
pub fn render(scene: &PreparedScene) -> Rendered {
    let start = Instant::now();
    let (framebuffer, mut stats) = render_samples(scene);
    let (image, coverage) = resolve::resolve(&framebuffer, scene.background);
    stats.frame_time_ms = Some(start.elapsed().as_secs_f64() * 1000.0);
    Rendered {
        image,
        coverage,
        stats,
    }
}

/// Loads the scene's models, prepares and renders it.
pub fn render_scene(scene: &Scene) -> Result<Rendered, SceneError> {
    Ok(render(&PreparedScene::load(scene)?))
}

/// Runs the pipeline up to (not including) the resolve: the filled sample
/// framebuffer and the statistics (`frame_time_ms` unset). Useful to compare
/// sample keys with another implementation.
pub fn render_samples(scene: &PreparedScene) -> (Framebuffer, RenderStats) {
    let camera = &scene.camera;
    let view_proj = camera.view_proj();
    let mut framebuffer = Framebuffer::new(camera.width, camera.height, scene.spp);
    let samples = SampleGrid::new(grid_size(scene.spp), scene.jitter);
    let uvt = scene
        .samples_time_and_lens()
        .then(|| UvtTables::new(scene.spp));
    let sampler = uvt.as_ref().map(|uvt| Sampler {
        samples: &samples,
        uvt,
    });
    let mut stats = RenderStats {
        input_patches: scene.patches.len() as u64,
        ..RenderStats::default()
    };

    for (index, object) in scene.objects.iter().enumerate() {
        if object
            .displacement
            .as_ref()
            .is_some_and(|d| !d.cpu_evaluable())
        {
            log::warn!(
                "object {index}: the CPU reference cannot run a user WGSL displacement; rendering it undisplaced"
            );
        }
    }
    // Depth-first: a stack keeps at most about max_split_depth pending
    // pieces per input patch. The order does not change the result, because
    // the framebuffer keeps the minimum key per sample.
    let mut stack: Vec<WorkItem> = scene
        .patches
        .iter()
        .rev()
        .map(|p| WorkItem::new(p.points, p.object))
        .collect();
    while let Some(item) = stack.pop() {
        match bound(
            &item.points,
            item.split_depth,
            &view_proj,
            camera,
            scene.dice_threshold,
            scene.max_split_depth,
            Growth {
                displacement_bound: scene.objects[item.object as usize].displacement_bound(),
                motion: scene.objects[item.object as usize].motion.as_ref(),
                lens: &scene.lens,
            },
        ) {
            BoundDecision::Cull => stats.culled_patches += 1,
            BoundDecision::Drop => stats.depth_guard_drops += 1,
            BoundDecision::Split(direction) => {
                stats.splits += 1;
                let [first, second] = item.split(direction);
                // Push the second half first so the first is processed next.
                stack.push(second);
                stack.push(first);
            }
            BoundDecision::Dice => {
                dice_shade_sample(
                    scene,
                    &item,
                    &view_proj,
                    &samples,
                    sampler.as_ref(),
                    &mut framebuffer,
                    &mut stats,
                );
            }
        }
    }
    (framebuffer, stats)
}

/// Dices one piece, shades its grid points and samples its micropolygons.
fn dice_shade_sample(
    scene: &PreparedScene,
    item: &WorkItem,
    view_proj: &glam::Mat4,
    samples: &SampleGrid,
    sampler: Option<&Sampler<'_>>,
    framebuffer: &mut Framebuffer,
    stats: &mut RenderStats,
) {
    stats.grids_diced += 1;
    stats.micropolygons += MICROPOLYGONS_PER_GRID;
    let object = &scene.objects[item.object as usize];
    let eye = scene.camera.eye;
    let displaced = object
        .displacement
        .as_ref()
        .and_then(|d| dice_displaced(&item.points, item.uv, eye, d));
    let grid = match displaced {
        Some(displaced) => {
            stats.displacement_bound_exceeded += displaced.bound_exceeded;
            displaced.grid
        }
        None => dice(&item.points, eye),
    };
    let albedo = object.albedo;

    let mut colors = [glam::Vec3::ZERO; GRID_LEN];
    let mut screen = [ScreenPoint {
        pixel: glam::Vec3::ZERO,
        w: 0.0,
    }; GRID_LEN];
    for (k, (&position, &normal)) in grid.positions.iter().zip(&grid.normals).enumerate() {
        colors[k] = shade(position, normal, albedo, scene);
        let clip = *view_proj * position.extend(1.0);
        screen[k] = ScreenPoint {
            pixel: scene.camera.to_pixel(clip),
            w: clip.w,
        };
    }

    // With time and lens: every point at open and close, and the grid's
    // algorithm (Adaptive decides per grid from its largest motion and blur).
    let moving = sampler.map(|sampler| {
        let motion = object.motion.as_ref();
        let points: [MovingPoint; GRID_LEN] = std::array::from_fn(|k| {
            let open = screen[k];
            let close_position = motion.map_or(grid.positions[k], |m| m.close(grid.positions[k]));
            let clip = *view_proj * close_position.extend(1.0);
            let close = scene.camera.to_pixel(clip);
            let coc = [scene.lens.coc(open.w), scene.lens.coc(clip.w)];
            MovingPoint::new(open.pixel, open.w, close, clip.w, coc)
        });
        let extent = |f: fn(&MovingPoint) -> f32| points.iter().map(f).fold(0.0f32, f32::max);
        let mode = Mode5d::for_grid(
            scene.sampling,
            extent(MovingPoint::motion),
            extent(MovingPoint::blur),
            scene.spp,
        )
        .unwrap_or(Mode5d::Bbox);
        (sampler, points, mode)
    });
    if let Some((_, _, Mode5d::Interleave)) = &moving {
        stats.interleave_grids += 1;
    }

    for j in 0..GRID_QUADS {
        for i in 0..GRID_QUADS {
            let corners = micropolygon_corners(&screen, i, j);
            let size = micropolygon_size(&corners);
            // f32::max ignores a NaN size (possible only for unprojectable corners).
            stats.largest_micropolygon_px = stats.largest_micropolygon_px.max(size);
            let corner_colors = micropolygon_corners_of(&colors, i, j);
            let color =
                (corner_colors[0] + corner_colors[1] + corner_colors[2] + corner_colors[3]) * 0.25;
            let packed = pack_rgb10(color);
            if let Some((sampler, points, mode)) = &moving {
                let [a, b, c, d] = micropolygon_corners_of(points, i, j);
                for triangle in [[a, b, c], [a, c, d]] {
                    raster_triangle_5d(framebuffer, sampler, *mode, triangle, packed, stats);
                }
                continue;
            }
            match scene.sampling {
                Sampling::Nearest => raster_nearest(framebuffer, samples.k, corners, packed, stats),
                _ => {
                    let [a, b, c, d] = corners;
                    raster_triangle(framebuffer, samples, [a, b, c], packed, stats);
                    raster_triangle(framebuffer, samples, [a, c, d], packed, stats);
                }
            }
        }
    }
}

/// The 4 corner values `(i, j), (i+1, j), (i+1, j+1), (i, j+1)` of micropolygon `(i, j)`.
fn micropolygon_corners_of<T: Copy>(values: &[T; GRID_LEN], i: usize, j: usize) -> [T; 4] {
    let n = crate::params::GRID_POINTS;
    [
        values[j * n + i],
        values[j * n + i + 1],
        values[(j + 1) * n + i + 1],
        values[(j + 1) * n + i],
    ]
}
