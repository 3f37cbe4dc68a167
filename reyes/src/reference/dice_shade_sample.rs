//! One diced grid, from the piece the bound test chose to dice to its
//! samples: dice, project, shade, place in time and lens, then sample each
//! micropolygon. The twin of `shaders/reyes/dice_shade_sample.wgsl`: each
//! step keeps the GPU's arithmetic in the GPU's order.

use glam::Vec3;

use super::ReferenceError;
use super::dice::surface_normal;
use super::dice::{Grid, dice};
use super::displace::{ContextPoint, Displacer, ShaderInputs, context_at};
use super::framebuffer::Framebuffer;
use super::limits::Budget;
use super::raster::{
    SampleGrid, ScreenPoint, micropolygon_corners, micropolygon_size, raster_nearest, raster_quad,
    raster_triangle, shows_front, still_quad,
};
use super::raster5d::{Mode5d, MovingPoint, Sampler, raster_quad_5d};
use super::shade::{Lighting, shade, shade_user};
use super::work::WorkItem;
use crate::aov::{self, Aov};
use crate::bezier;
use crate::color::{average_rgb10, pack_rgb10};
use crate::dicing::{GridSize, grid_param};
use crate::nonfinite::{Sources, camera_sources, close_sources};
use crate::prepare::{PreparedObject, PreparedScene};
use crate::scene::{Dicing, Sampling, ShadingInterpolation};
use crate::shading::PreparedSurface;
use crate::stats::RenderStats;
use crate::surface_shader::ShadingContext;

/// What stays fixed over a frame: the scene, its camera's view-projection,
/// the sample positions and the time-and-lens sampler.
pub(super) struct FrameContext<'a> {
    /// The scene being rendered.
    pub scene: &'a PreparedScene,
    /// The camera's view-projection matrix.
    pub view_proj: glam::Mat4,
    /// The per-pixel sample positions.
    pub samples: &'a SampleGrid,
    /// The time-and-lens sampler, when the scene samples time or lens.
    pub sampler: Option<&'a Sampler<'a>>,
    /// Sample each triangle's own box instead of the micropolygon's.
    pub triangle_boxes: bool,
}

/// What a frame writes to: the sample framebuffer, the statistics and the
/// work budget.
pub(super) struct FrameOutput<'a> {
    /// The sample framebuffer.
    pub framebuffer: &'a mut Framebuffer,
    /// The frame's statistics.
    pub stats: &'a mut RenderStats,
    /// The frame's work limits.
    pub budget: &'a mut Budget,
}

/// A grid with time and lens: every point at open and close, and the
/// algorithm that samples the grid.
struct MovingGrid<'a> {
    sampler: &'a Sampler<'a>,
    points: Vec<MovingPoint>,
    mode: Mode5d,
}

/// What stays fixed over one grid while its micropolygons are sampled.
struct GridContext<'a> {
    object: &'a PreparedObject,
    size: GridSize,
    /// The points' pixel positions at the shutter's open.
    screen: Vec<ScreenPoint>,
    /// The points' packed colours.
    colors: Vec<u32>,
    /// The points in time and lens, when the frame samples them.
    moving: Option<MovingGrid<'a>>,
}

/// Dices one piece into `size`, shades its grid points and samples its
/// micropolygons.
pub(super) fn dice_shade_sample(
    frame: &FrameContext<'_>,
    output: &mut FrameOutput<'_>,
    item: &WorkItem,
    size: GridSize,
) -> Result<(), ReferenceError> {
    count_grid(output.stats, size);
    let scene = frame.scene;
    let object = &scene.objects[item.object as usize];
    let grid = dice_piece(scene, item, size);
    output.stats.displacement_bound_exceeded += grid.bound_exceeded;
    // The stages that lost each point (see crate::nonfinite), counted once
    // all are known.
    let mut non_finite = grid.non_finite.clone();
    let screen = project(frame, &grid, &mut non_finite);
    let colors = shade_points(scene, object, item, &grid, &screen);
    let moving = frame
        .sampler
        .map(|sampler| place_in_time_and_lens(frame, sampler, object, &grid, &mut non_finite));
    for sources in non_finite {
        sources.count_into(output.stats);
    }
    if let Some(MovingGrid {
        mode: Mode5d::Interleave,
        ..
    }) = &moving
    {
        output.stats.interleave_grids += 1;
    }
    let context = GridContext {
        object,
        size,
        screen,
        colors,
        moving,
    };
    for j in 0..size.nv {
        for i in 0..size.nu {
            output.budget.samples(output.stats)?;
            sample_micropolygon(frame, &context, output, i, j);
        }
    }
    Ok(())
}

/// Counts a grid of `size` diced.
fn count_grid(stats: &mut RenderStats, size: GridSize) {
    let class = size.class();
    stats.grids_diced += 1;
    stats.micropolygons += u64::from(size.quads());
    stats.grids_by_class[class.index()] += 1;
    stats.dice_threads += u64::from(class.threads());
}

/// The piece's grid, displaced when its displacement evaluates, else
/// undisplaced.
fn dice_piece(scene: &PreparedScene, item: &WorkItem, size: GridSize) -> Grid {
    let object = &scene.objects[item.object as usize];
    let eye = scene.camera.homogeneous_eye();
    let world = &scene.patches[item.patch as usize];
    let patch = &world.points;
    let edges = (scene.dicing.mode() == Dicing::Rate).then_some(&item.edges);
    let lighting = Lighting::of(scene);
    let table = &scene.shaders;
    let displacer = object.displacement.as_ref().map(|prepared| Displacer {
        prepared,
        shader: prepared.shader().map(|shader| {
            let code = table.shaders.get(shader.reference.shader as usize);
            ShaderInputs {
                shader,
                twin: code.and_then(|c| c.cpu_displacement.as_ref()),
                parameters: code.map_or(&[], |c| table.slots(shader.reference.parameters, c)),
                host: &lighting,
                st: world,
                eye,
                color: object.color,
            }
        }),
    });
    let displacement = displacer.as_ref();
    dice(patch, item.uv, size, edges, eye, displacement)
        .or_else(|| dice(patch, item.uv, size, edges, eye, None))
        .expect("an undisplaced grid always evaluates")
}

/// The grid points' pixel positions, adding the camera's losses to
/// `non_finite`.
fn project(frame: &FrameContext<'_>, grid: &Grid, non_finite: &mut [Sources]) -> Vec<ScreenPoint> {
    grid.positions
        .iter()
        .zip(non_finite)
        .map(|(&position, sources)| {
            let clip = frame.view_proj * position.extend(1.0);
            let pixel = frame.scene.camera.to_pixel(clip);
            *sources = sources.union(camera_sources(position, clip, pixel));
            ScreenPoint { pixel, w: clip.w }
        })
        .collect()
}

/// The grid points' packed colours for the scene's AOV.
fn shade_points(
    scene: &PreparedScene,
    object: &PreparedObject,
    item: &WorkItem,
    grid: &Grid,
    screen: &[ScreenPoint],
) -> Vec<u32> {
    let depth_range = aov::depth_range(&scene.camera);
    let columns = grid.size.nu + 1;
    grid.positions
        .iter()
        .zip(&grid.normals)
        .zip(screen)
        .enumerate()
        .map(|(k, ((&position, &normal), point))| {
            pack_rgb10(match scene.aov {
                // The z output keeps only the depth; its colours are the shaded
                // ones, as the megakernel's default case makes them.
                Aov::Shaded | Aov::Grids | Aov::Z => match object.surface {
                    Some(PreparedSurface::User { shader, parameters }) => {
                        let (i, j) = (k as u32 % columns, k as u32 / columns);
                        let ctx = shading_context(
                            scene,
                            object,
                            item,
                            grid.size,
                            (i, j),
                            position,
                            normal,
                        );
                        shade_user(&ctx, shader, parameters, scene).unwrap_or(object.color)
                    }
                    _ => shade(position, normal, object, scene),
                },
                Aov::Depth => aov::depth_color(point.w, depth_range),
                Aov::Normal => aov::normal_color(normal),
            })
        })
        .collect()
}

/// The shading context of grid point `(i, j)` of `item`, moved to
/// `position` with the eye-facing unit `normal` (the WGSL
/// `shading_context`).
fn shading_context(
    scene: &PreparedScene,
    object: &PreparedObject,
    item: &WorkItem,
    size: GridSize,
    (i, j): (u32, u32),
    position: Vec3,
    normal: Vec3,
) -> ShadingContext {
    let world = &scene.patches[item.patch as usize];
    let patch = &world.points;
    let uv = item.uv;
    let (u, v) = (
        grid_param(uv.x, uv.z, i, size.nu),
        grid_param(uv.y, uv.w, j, size.nv),
    );
    let eye = scene.camera.homogeneous_eye();
    let ng = if object.displacement.is_some() {
        surface_normal(patch, u, v, bezier::evaluate(patch, u, v).position, eye)
    } else {
        normal
    };
    let point = ContextPoint {
        uv: (u, v),
        step: (
            (uv.z - uv.x) / size.nu as f32,
            (uv.w - uv.y) / size.nv as f32,
        ),
        position,
        normals: (normal, ng),
    };
    context_at(patch, world, eye, object.color, point)
}

/// Every point at open and close, adding the motion's and the close
/// camera's losses to `non_finite`, and the grid's algorithm (Adaptive
/// decides per grid from its largest motion and blur).
fn place_in_time_and_lens<'a>(
    frame: &FrameContext<'_>,
    sampler: &'a Sampler<'a>,
    object: &PreparedObject,
    grid: &Grid,
    non_finite: &mut [Sources],
) -> MovingGrid<'a> {
    let scene = frame.scene;
    let motion = object.motion.as_ref();
    let points: Vec<MovingPoint> = grid
        .positions
        .iter()
        .zip(non_finite)
        .map(|(&position, sources)| {
            let close_position = motion.map_or(position, |m| m.close(position));
            let clip_open = frame.view_proj * position.extend(1.0);
            let clip_close = frame.view_proj * close_position.extend(1.0);
            let close = scene.camera.to_pixel(clip_close);
            *sources = sources.union(close_sources(position, close_position, clip_close, close));
            MovingPoint::new(clip_open, clip_close, &scene.camera, &scene.lens)
        })
        .collect();
    let extent = |f: fn(&MovingPoint) -> f32| points.iter().map(f).fold(0.0f32, f32::max);
    let mode = Mode5d::for_grid(
        scene.sampling,
        extent(MovingPoint::motion),
        extent(MovingPoint::blur),
        sampler,
    )
    .unwrap_or(Mode5d::Bbox);
    MovingGrid {
        sampler,
        points,
        mode,
    }
}

/// Samples micropolygon `(i, j)` of the grid into the framebuffer.
fn sample_micropolygon(
    frame: &FrameContext<'_>,
    grid: &GridContext<'_>,
    output: &mut FrameOutput<'_>,
    i: u32,
    j: u32,
) {
    let scene = frame.scene;
    let (size, stats) = (grid.size, &mut *output.stats);
    let corners = micropolygon_corners(&grid.screen, size, i, j);
    let micropolygon = micropolygon_size(&corners);
    // f32::max ignores a NaN size (possible only for unprojectable corners).
    stats.largest_micropolygon_px = stats.largest_micropolygon_px.max(micropolygon);
    // The corners' colours, or one colour for the whole micropolygon.
    let corner_colors = micropolygon_corners(&grid.colors, size, i, j);
    let packed = match scene.aov {
        Aov::Grids => aov::grid_color(size.quads(), i, j),
        _ => average_rgb10(corner_colors),
    };
    let [ca, cb, cc, cd] = match (scene.aov, scene.shading_interpolation) {
        (Aov::Grids, _) | (_, ShadingInterpolation::Constant) => [packed; 4],
        (_, ShadingInterpolation::Smooth) => corner_colors,
    };
    let quad_colors = [ca, cb, cc, cd];
    // Which of the two triangles to sample: a one-sided object's
    // back-facing ones are culled.
    let object = grid.object;
    let front = |[p, q, r]: [glam::Vec2; 3]| object.front.is_none_or(|s| shows_front(p, q, r, s));
    let drawn = |[a, b, c, d]: [glam::Vec2; 4]| [front([a, b, c]), front([a, c, d])];
    let framebuffer = &mut *output.framebuffer;
    if let Some(moving) = &grid.moving {
        let corners = micropolygon_corners(&moving.points, size, i, j);
        // A face is culled only when it faces away at both ends of the
        // interval its corners are seen in (Fatahalian et al.): one that
        // turns towards the camera during the shutter is drawn.
        let at_open = drawn(corners.map(|c| c.open.truncate()));
        let at_close = drawn(corners.map(|c| c.close.truncate()));
        let drawn = [at_open[0] || at_close[0], at_open[1] || at_close[1]];
        raster_quad_5d(
            framebuffer,
            moving.sampler,
            moving.mode,
            corners,
            quad_colors,
            drawn,
            stats,
        );
        return;
    }
    let samples = frame.samples;
    let drawn = drawn(corners.map(|c| c.pixel.truncate()));
    let quad = still_quad(corners, quad_colors, drawn);
    match scene.sampling {
        Sampling::Nearest => raster_nearest(framebuffer, samples, corners, &quad, stats),
        _ if frame.triangle_boxes => {
            let [a, b, c, d] = corners;
            for ((triangle, colors), drawn) in [[a, b, c], [a, c, d]]
                .into_iter()
                .zip([[ca, cb, cc], [ca, cc, cd]])
                .zip(drawn)
            {
                if drawn {
                    raster_triangle(framebuffer, samples, triangle, colors, stats);
                }
            }
        }
        _ => raster_quad(framebuffer, samples, &quad, stats),
    }
}
