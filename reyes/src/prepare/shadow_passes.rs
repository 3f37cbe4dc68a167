//! Automatic shadows (`[[lights]] shadows = true`): the depth passes that
//! render a light's shadow maps before the frame, and the frame that
//! looks them up.
//!
//! A depth pass is an ordinary frame ([`PreparedScene`]) of the same
//! world-space patches seen from the light, with the depth output
//! ([`Aov::Z`], [`DepthFilter::Midpoint`], 1 sample per texel at its
//! centre): either renderer renders it as any other frame. What changes
//! from the frame:
//!
//! * the camera: a spotlight looks along its axis through a perspective of
//!   twice its cone angle; a distant light looks along its direction
//!   through an orthographic view fitted to the bounds of all patches; a
//!   point light looks along the six axes through 90-degree perspectives.
//!   Near and far enclose the patches' control points (their convex hull
//!   holds the surface), grown by each object's displacement bound and
//!   taken at shutter open and close. Maps are square, `map_size` texels.
//! * a pinhole (no depth of field) and no camera motion: the light does
//!   not move with the camera, so the objects keep only their own motion.
//!   With motion blur the pass samples the scene's shutter like the frame,
//!   one time per texel: a moving caster leaves a dithered trail in the
//!   map, which the filtered lookup turns into a partial shadow along its
//!   path, darkest where it spends the most time.
//! * both sides of every surface (no back-face culling): the midpoint
//!   between the nearest and second-nearest surfaces needs the back of a
//!   closed caster.
//! * constant surfaces and no lights: only depths are kept, so shading is
//!   the cheapest there is. Displacement stays (displaced casters cast
//!   displaced shadows).
//! * a coarser shading rate, [`DEPTH_PASS_SHADING_RATE_FACTOR`] times the
//!   frame's (and each object's own): a map needs where the surfaces are,
//!   not how they are shaded, and the samples still test each
//!   micropolygon's exact bilinear shape, so silhouettes stay sharp; only
//!   curved surfaces are held by flat pieces twice as wide.

use glam::{Mat4, Vec3};

use super::{PreparedObject, PreparedScene};
use crate::aov::Aov;
use crate::camera::Camera;
use crate::depth::DepthFilter;
use crate::dicing::DicingRule;
use crate::filter::PixelFilter;
use crate::motion::{ObjectMotion, PreparedLens};
use crate::quantize::Encoding;
use crate::shading::{PreparedLight, PreparedLightKind, PreparedShadow, PreparedSurface};
use crate::shadow::ShadowMap;

pub use crate::stats::PassStats;

/// The widest field of view a spotlight's map takes, in degrees: a
/// perspective cannot reach 180. A wider cone is lit beyond the map's
/// edge without shadows.
pub const MAX_SPOT_MAP_FOV_DEGREES: f32 = 170.0;

/// How much coarser a depth pass dices than the frame: its shading rate
/// (texels per micropolygon) is the frame's times this, micropolygons 2
/// texels on a side at the default rate. Dicing is most of a depth pass's
/// cost, and a depth pass of a map as large as the frame would otherwise
/// cost as much as the frame.
pub const DEPTH_PASS_SHADING_RATE_FACTOR: f32 = 4.0;

/// The margin around the fitted bounds: this fraction of their extent on
/// every side (so that a caster at the edge of the bounds is not on the
/// map's border texels, and the near plane does not clip the nearest one).
const FIT_MARGIN: f32 = 0.02;

/// One depth pass: a frame rendered from a light to one of its maps.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthPass {
    /// What it renders, for statistics: `"shadow of light 1 (spot)"`, a
    /// point light's passes with their axis (`"... (point, -z)"`).
    pub name: String,
    /// The pending shadow it belongs to (in
    /// [`PreparedScene::pending_shadows`]).
    pub shadow: usize,
    /// The frame to render with the depth output; its camera is the map's.
    pub scene: PreparedScene,
}

/// The depth passes of `scene`'s pending shadows, in order, each shadow's
/// maps together. A light with nothing in front of it has no pass (its
/// points are then lit).
pub fn depth_passes(scene: &PreparedScene) -> Vec<DepthPass> {
    let bounds = bound_points(scene);
    let mut passes = Vec::new();
    for (index, pending) in scene.pending_shadows.iter().enumerate() {
        let light = &scene.lights[pending.light];
        let size = pending.map_size;
        let kind = match light.kind {
            PreparedLightKind::Distant => "distant",
            PreparedLightKind::Point => "point",
            PreparedLightKind::Spot => "spot",
        };
        for (axis, camera) in light_cameras(light, &bounds, size) {
            let name = match axis {
                Some(axis) => format!("shadow of light {} ({kind}, {axis})", pending.scene_light),
                None => format!("shadow of light {} ({kind})", pending.scene_light),
            };
            passes.push(DepthPass {
                name,
                shadow: index,
                scene: depth_scene(scene, camera),
            });
        }
    }
    passes
}

/// A frame a renderer rendered, as [`PreparedScene::render_with_shadows`]
/// reads it: its depths (a depth pass's) and its statistics.
pub trait RenderedPass {
    /// The resolved linear image (a depth pass's depths in its red channel).
    fn linear(&self) -> &image::Rgba32FImage;
    /// The frame's statistics.
    fn stats_mut(&mut self) -> &mut crate::stats::RenderStats;
}

impl PreparedScene {
    /// Renders this frame with `render` (how a renderer renders one frame,
    /// given the frame and, for a depth pass, the pass's name): without
    /// pending shadows, the frame alone; with them, each depth pass first
    /// ([`PreparedScene::with_shadow_maps`]), then the frame with the maps,
    /// its [`crate::stats::RenderStats::passes`] counting every pass.
    pub fn render_with_shadows<R: RenderedPass, E>(
        &self,
        mut render: impl FnMut(&PreparedScene, Option<&str>) -> Result<R, E>,
    ) -> Result<R, E> {
        if self.pending_shadows.is_empty() {
            return render(self, None);
        }
        let mut passes = Vec::new();
        let mut counted = |name: String, scene: &PreparedScene, rendered: &mut R| {
            let camera = &scene.camera;
            passes.push(PassStats::of(
                name,
                camera.width,
                camera.height,
                rendered.stats_mut(),
            ));
        };
        let frame = self.with_shadow_maps(|pass| {
            let mut rendered = render(&pass.scene, Some(&pass.name))?;
            counted(pass.name.clone(), &pass.scene, &mut rendered);
            Ok(crate::depth::depths(rendered.linear()))
        })?;
        let mut rendered = render(&frame, None)?;
        counted("frame".into(), &frame, &mut rendered);
        rendered.stats_mut().passes = passes;
        Ok(rendered)
    }

    /// This frame with its pending shadows rendered: each [`depth_passes`]
    /// pass rendered by `render` to its depths (row-major, +inf where no
    /// surface is, as [`crate::depth::depths`] reads a depth image), the
    /// maps in [`PreparedScene::shadow_maps`] and their lights'
    /// [`PreparedLight::shadow`] set. `render` is how a renderer renders a
    /// frame; its first error ends the passes.
    pub fn with_shadow_maps<E>(
        &self,
        mut render: impl FnMut(&DepthPass) -> Result<Vec<f32>, E>,
    ) -> Result<PreparedScene, E> {
        let passes = depth_passes(self);
        let mut frame = self.clone();
        frame.pending_shadows.clear();
        for (index, pending) in self.pending_shadows.iter().enumerate() {
            let first_map = frame.shadow_maps.len() as u32;
            for pass in passes.iter().filter(|p| p.shadow == index) {
                let depths = render(pass)?;
                frame
                    .shadow_maps
                    .push(ShadowMap::from_camera(&pass.scene.camera, depths));
            }
            frame.lights[pending.light].shadow = Some(PreparedShadow {
                first_map,
                map_count: frame.shadow_maps.len() as u32 - first_map,
                filter: pending.filter,
            });
        }
        Ok(frame)
    }

    /// This frame without shadows: no light looks up a map and none is
    /// pending (the viewer's shadows toggle).
    pub fn without_shadows(&self) -> PreparedScene {
        let mut frame = self.clone();
        frame.pending_shadows.clear();
        frame.shadow_maps.clear();
        for light in &mut frame.lights {
            light.shadow = None;
        }
        frame
    }
}

/// A point that bounds the scene's surfaces: a control point at shutter
/// open or close, and how far the surface can stray from it.
#[derive(Debug, Clone, Copy)]
struct BoundPoint {
    at: Vec3,
    radius: f32,
}

/// The objects' own motion, without the camera's.
fn world_motion(scene: &PreparedScene, object: &PreparedObject) -> Option<ObjectMotion> {
    let motion = object.motion?;
    let Some(camera) = scene.camera_motion else {
        return Some(motion);
    };
    let own = camera.inverse() * motion.matrix;
    if own.abs_diff_eq(Mat4::IDENTITY, 1e-6) {
        None
    } else {
        ObjectMotion::new(Mat4::IDENTITY, own)
    }
}

/// Every control point at open and close with its object's displacement
/// bound (stretched by the motion).
fn bound_points(scene: &PreparedScene) -> Vec<BoundPoint> {
    let motions: Vec<_> = scene
        .objects
        .iter()
        .map(|o| world_motion(scene, o))
        .collect();
    let mut points = Vec::new();
    for patch in &scene.patches {
        let object = &scene.objects[patch.object as usize];
        let motion = motions[patch.object as usize];
        let stretch = motion.map_or(1.0, |m| m.stretch);
        let radius = object.displacement_bound() * stretch;
        for &at in &patch.points {
            points.push(BoundPoint { at, radius });
            if let Some(motion) = motion {
                points.push(BoundPoint {
                    at: motion.close(at),
                    radius,
                });
            }
        }
    }
    points
}

/// An up vector not parallel to `forward`.
fn up_for(forward: Vec3) -> Vec3 {
    if forward.normalize().z.abs() > 0.9 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// The cameras of `light`'s maps, each with the axis it looks along (a
/// point light's), `size` texels square.
fn light_cameras(
    light: &PreparedLight,
    bounds: &[BoundPoint],
    size: u32,
) -> Vec<(Option<&'static str>, Camera)> {
    match light.kind {
        PreparedLightKind::Distant => distant_camera(-light.to_light, bounds, size)
            .map(|c| (None, c))
            .into_iter()
            .collect(),
        PreparedLightKind::Spot => {
            let cone = light.cos_outside.clamp(-1.0, 1.0).acos();
            let fov = (2.0 * cone).clamp(1e-3, MAX_SPOT_MAP_FOV_DEGREES.to_radians());
            perspective_camera(light.to_light, light.axis, fov, bounds, size)
                .map(|c| (None, c))
                .into_iter()
                .collect()
        }
        PreparedLightKind::Point => [
            ("+x", Vec3::X),
            ("-x", Vec3::NEG_X),
            ("+y", Vec3::Y),
            ("-y", Vec3::NEG_Y),
            ("+z", Vec3::Z),
            ("-z", Vec3::NEG_Z),
        ]
        .into_iter()
        .filter_map(|(name, axis)| {
            let fov = std::f32::consts::FRAC_PI_2;
            perspective_camera(light.to_light, axis, fov, bounds, size).map(|c| (Some(name), c))
        })
        .collect(),
    }
}

/// An orthographic camera looking along `direction` over all of
/// `bounds`; `None` without bounds.
fn distant_camera(direction: Vec3, bounds: &[BoundPoint], size: u32) -> Option<Camera> {
    let direction = direction.normalize();
    let up = up_for(direction);
    // The light's frame with its eye at the origin: x right, y up, z back.
    let rotation = Mat4::look_at_rh(Vec3::ZERO, direction, up);
    let (lo, hi) = bounds
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), point| {
            let q = rotation.transform_point3(point.at);
            (lo.min(q - point.radius), hi.max(q + point.radius))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return None;
    }
    let span = hi - lo;
    let extent = span.max_element().max(f32::MIN_POSITIVE.sqrt());
    let margin = FIT_MARGIN * extent;
    let height = span.x.max(span.y) + 2.0 * margin;
    // The eye sits in front of the nearest point (largest z), centred.
    let eye_local = Vec3::new(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), hi.z + margin);
    let eye = rotation.inverse().transform_point3(eye_local);
    let near = 0.5 * margin;
    let far = span.z + 1.5 * margin;
    let camera = Camera::new(eye, eye + direction, up, 1.0, size, size, near, far);
    Some(camera.orthographic(height))
}

/// A perspective camera at `eye` looking along `axis` with the field of
/// view `fov`, its near and far planes around the `bounds` in front of it;
/// `None` when nothing is in front.
fn perspective_camera(
    eye: Vec3,
    axis: Vec3,
    fov: f32,
    bounds: &[BoundPoint],
    size: u32,
) -> Option<Camera> {
    let axis = axis.normalize();
    let (nearest, farthest) = bounds
        .iter()
        .map(|p| {
            let depth = (p.at - eye).dot(axis);
            (depth - p.radius, depth + p.radius)
        })
        .filter(|&(_, far)| far > 0.0)
        .fold((f32::INFINITY, 0.0f32), |(lo, hi), (near, far)| {
            (lo.min(near), hi.max(far))
        });
    if !(farthest > 0.0 && farthest.is_finite()) {
        return None;
    }
    let far = farthest * (1.0 + FIT_MARGIN);
    // A near plane too close to the eye spends the depth precision there:
    // casters nearer than a thousandth of the far plane are clipped.
    let near = (nearest * (1.0 - FIT_MARGIN)).max(far * 1e-3);
    let up = up_for(axis);
    Some(Camera::new(eye, eye + axis, up, fov, size, size, near, far))
}

/// A depth pass's shading rate for the frame's `rate`
/// ([`DEPTH_PASS_SHADING_RATE_FACTOR`] times it, within the largest rate).
fn coarser_rate(rate: f32) -> f32 {
    (rate * DEPTH_PASS_SHADING_RATE_FACTOR).min(crate::params::MAX_SHADING_RATE)
}

/// The depth pass of `frame` through `camera` (see the module
/// documentation).
fn depth_scene(frame: &PreparedScene, camera: Camera) -> PreparedScene {
    let objects = frame
        .objects
        .iter()
        .map(|object| PreparedObject {
            surface: object.surface.map(|_| PreparedSurface::Constant),
            motion: world_motion(frame, object),
            front: None,
            shading_rate: object.shading_rate.map(coarser_rate),
            ..object.clone()
        })
        .collect();
    let dicing = DicingRule::new(
        frame.dicing.mode(),
        coarser_rate(frame.dicing.shading_rate()),
        frame.dicing.fixed_threshold(),
    );
    PreparedScene {
        camera,
        camera_motion: None,
        lens: PreparedLens::new(&camera, 0.0, None),
        objects,
        lights: Vec::new(),
        shadow_maps: Vec::new(),
        pending_shadows: Vec::new(),
        dicing,
        spp: 1,
        jitter: false,
        aov: Aov::Z,
        depth_filter: DepthFilter::Midpoint,
        pixel_filter: PixelFilter::PIXEL_BOX,
        encoding: Encoding::PLAIN,
        ..frame.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{CameraPose, LightShadow, Scene, ShadowMaps};

    /// The default teapot with its light's shadow automatic and `edit`
    /// applied, prepared.
    fn teapot(edit: impl FnOnce(&mut Scene)) -> PreparedScene {
        let mut scene = Scene::default_teapot();
        scene.lights[0].shadow = Some(LightShadow {
            maps: ShadowMaps::Automatic { map_size: 64 },
            filter: Default::default(),
        });
        edit(&mut scene);
        PreparedScene::load(&scene).unwrap()
    }

    #[test]
    fn a_distant_light_s_map_holds_every_control_point_between_its_planes() {
        let scene = teapot(|_| {});
        let [pass] = &depth_passes(&scene)[..] else {
            panic!("one pass for a distant light");
        };
        let camera = &pass.scene.camera;
        assert_eq!((camera.width, camera.height), (64, 64));
        assert!(!camera.projection.is_perspective());
        let map = ShadowMap::from_camera(camera, vec![0.0; 64 * 64]);
        for point in scene.patches.iter().flat_map(|p| p.points) {
            let at = map.locate(point).expect("inside the map");
            assert!(
                at.depth > camera.near && at.depth < camera.far,
                "{point}: depth {} outside {}..{}",
                at.depth,
                camera.near,
                camera.far
            );
        }
    }

    #[test]
    fn a_depth_pass_keeps_the_objects_own_motion_but_not_the_camera_s() {
        let scene = teapot(|scene| {
            let camera = scene.camera.unwrap();
            scene.camera_close = Some(CameraPose {
                eye: camera.eye + glam::Vec3::new(1.0, 0.0, 0.0),
                target: camera.target,
                up: None,
            });
        });
        assert!(scene.objects[0].motion.is_some(), "the camera moves");
        let pass = &depth_passes(&scene)[0].scene;
        assert_eq!(pass.objects[0].motion, None);
        assert_eq!(pass.camera_motion, None);
        assert_eq!((pass.aov, pass.spp, pass.lens.aperture), (Aov::Z, 1, 0.0));
        assert_eq!(pass.depth_filter, DepthFilter::Midpoint);
        assert_eq!(pass.objects[0].front, None);
    }
}
