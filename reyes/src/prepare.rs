//! Host-side scene preparation, shared by the CPU reference and the GPU path:
//! control points transformed to world space once, the camera built (or
//! framed automatically), lights normalized.

use glam::Vec3;

use crate::aov::Aov;
use crate::camera::Camera;
use crate::displacement::PreparedDisplacement;
use crate::model::Model;
use crate::motion::{ObjectMotion, PreparedLens, camera_motion, interpolate_view};
use crate::params::MAX_GRID_QUADS;
use crate::scene::{CameraDesc, Dicing, Sampling, Scene, SceneError, ShadingInterpolation};

/// One input patch in world space, with the object it belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldPatch {
    /// Control points in world space, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
    /// Index of the object (in [`PreparedScene::objects`]).
    pub object: u32,
}

/// Per-object shading and displacement data.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedObject {
    /// Linear RGB albedo.
    pub albedo: Vec3,
    /// Displacement mapping, if any.
    pub displacement: Option<PreparedDisplacement>,
    /// How the object moves during the shutter (`None`: it does not).
    pub motion: Option<ObjectMotion>,
    /// One-sided objects (`sides = 1`): the sign `s` such that the front
    /// faces along `s * (dP/du x dP/dv)` in world space (negative with
    /// `reverse_orientation`, and again for a mirroring transform); `None`
    /// for two-sided objects, which are never culled as back-facing.
    pub front: Option<f32>,
}

impl PreparedObject {
    /// The displacement bound in world units (0 without displacement).
    pub fn displacement_bound(&self) -> f32 {
        self.displacement.as_ref().map_or(0.0, |d| d.bound)
    }
}

/// A directional light ready for shading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedLight {
    /// Unit vector from the surface towards the light: `L = normalize(-direction)`.
    pub to_light: Vec3,
    /// `intensity * color`.
    pub radiance: Vec3,
}

/// Everything a renderer needs for one frame, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedScene {
    /// The camera (image size included).
    pub camera: Camera,
    /// All objects' patches, in object order.
    pub patches: Vec<WorldPatch>,
    /// Shading data per object.
    pub objects: Vec<PreparedObject>,
    /// The lights.
    pub lights: Vec<PreparedLight>,
    /// Ambient term.
    pub ambient: f32,
    /// Specular weight.
    pub specular_strength: f32,
    /// Blinn-Phong exponent.
    pub shininess: f32,
    /// Samples per pixel (a perfect square).
    pub spp: u32,
    /// Sampling mode.
    pub sampling: Sampling,
    /// Whether samples are jittered within their strata.
    pub jitter: bool,
    /// Linear RGB background.
    pub background: Vec3,
    /// How pieces are diced.
    pub dicing: Dicing,
    /// The side of a micropolygon at the shading rate, `sqrt(shading_rate)`
    /// pixels (rate dicing).
    pub micropolygon_side: f32,
    /// Dice when the projected bound's larger side is `<=` this (pixels):
    /// the scene's `dice_threshold` for fixed dicing, the largest grid's
    /// side at the shading rate (`MAX_GRID_QUADS * micropolygon_side`) for
    /// rate dicing, where it only bounds a piece's box with its
    /// displacement (see [`crate::reference::bound::fits`]).
    pub dice_threshold: f32,
    /// Drop patches that still need a split at this depth.
    pub max_split_depth: u32,
    /// The thin lens (aperture 0: a pinhole).
    pub lens: PreparedLens,
    /// What the image shows.
    pub aov: Aov,
    /// How colour varies over a micropolygon.
    pub shading_interpolation: ShadingInterpolation,
}

impl PreparedScene {
    /// Prepares `scene` with its models already loaded (`models[i]` belongs to
    /// `scene.objects[i]`). The scene is validated first; height maps named
    /// by displacement tables are read here. Without a camera in
    /// the scene, the camera is framed around the world-space bounds of all
    /// patches ([`CameraDesc::framing_points`]).
    pub fn new(scene: &Scene, models: &[Model]) -> Result<PreparedScene, SceneError> {
        scene.validate()?;
        if models.len() != scene.objects.len() {
            return Err(SceneError::ModelCountMismatch {
                objects: scene.objects.len(),
                models: models.len(),
            });
        }
        let mut patches = Vec::with_capacity(models.iter().map(|m| m.patches.len()).sum());
        for (index, (object, model)) in scene.objects.iter().zip(models).enumerate() {
            let matrix = object.transform.matrix();
            patches.extend(model.patches.iter().map(|patch| WorldPatch {
                points: patch.points.map(|p| matrix.transform_point3(p)),
                object: index as u32,
            }));
        }
        let (width, height) = (scene.resolution.width, scene.resolution.height);
        let desc = scene.camera.unwrap_or_else(|| {
            CameraDesc::framing_points(
                patches.iter().flat_map(|p| p.points.iter().copied()),
                width as f32 / height as f32,
            )
        });
        let camera = Camera::new(
            desc.eye,
            desc.target,
            desc.up,
            desc.fov_y_degrees.to_radians(),
            width,
            height,
            desc.near,
            desc.far,
        );
        // A moving camera becomes a motion of the whole world (see
        // `crate::motion`); validation guarantees a `[camera]` with it, so
        // `camera` is that camera here.
        let camera_motion = scene.camera_close.and_then(|close| {
            let at_close = camera.looking(close.eye, close.target, close.up.unwrap_or(camera.up));
            camera_motion(
                camera.view,
                interpolate_view(camera.view, at_close.view, scene.shutter),
            )
        });
        let mut prepared_objects = Vec::with_capacity(scene.objects.len());
        for (index, object) in scene.objects.iter().enumerate() {
            let open = object.transform.matrix();
            let mirrored = open.determinant() < 0.0;
            let displacement = object
                .displacement
                .as_ref()
                .map(|desc| {
                    desc.prepare(scene.base_dir.as_deref(), mirrored)
                        .map_err(|source| SceneError::Displacement {
                            index,
                            displacement: desc.source.clone(),
                            source,
                        })
                })
                .transpose()?;
            let close = object.transform_close.as_ref().map_or(open, |close| {
                object.transform.interpolate(close, scene.shutter)
            });
            let motion = ObjectMotion::new(open, camera_motion.map_or(close, |c| c * close));
            let front = (object.sides == 1).then(|| {
                let flipped = object.reverse_orientation != mirrored;
                if flipped { -1.0 } else { 1.0 }
            });
            prepared_objects.push(PreparedObject {
                albedo: object.color,
                displacement,
                motion,
                front,
            });
        }
        let lens = PreparedLens::new(&camera, scene.lens.aperture, scene.lens.focus_distance);
        let micropolygon_side = scene.shading_rate.sqrt();
        Ok(PreparedScene {
            lens,
            camera,
            patches,
            objects: prepared_objects,
            lights: scene
                .lights
                .iter()
                .map(|l| PreparedLight {
                    to_light: (-l.direction).normalize(),
                    radiance: l.color * l.intensity,
                })
                .collect(),
            ambient: scene.ambient,
            specular_strength: scene.specular.strength,
            shininess: scene.specular.shininess,
            spp: scene.spp,
            sampling: scene.sampling,
            jitter: scene.jitter,
            background: scene.background,
            dicing: scene.dicing,
            micropolygon_side,
            dice_threshold: match scene.dicing {
                Dicing::Fixed => scene.dice_threshold,
                Dicing::Rate => MAX_GRID_QUADS as f32 * micropolygon_side,
            },
            max_split_depth: scene.max_split_depth,
            aov: scene.aov,
            shading_interpolation: scene.shading_interpolation,
        })
    }

    /// Whether any object moves during the shutter (relative to the camera:
    /// with camera motion, every object does).
    pub fn has_motion(&self) -> bool {
        self.objects.iter().any(|o| o.motion.is_some())
    }

    /// Whether samples carry a time and a lens position: with motion, with a
    /// lens, or with a sampling mode other than the plain bounding box (which
    /// is then also used for a stationary, pinhole frame, as a check).
    pub fn samples_time_and_lens(&self) -> bool {
        match self.sampling {
            Sampling::Nearest => false,
            Sampling::Bbox => self.has_motion() || self.lens.aperture > 0.0,
            _ => true,
        }
    }

    /// The one user WGSL displacement function of the scene, if any object
    /// uses one (the GPU renderer compiles it into the megakernel).
    pub fn user_displacement_wgsl(&self) -> Option<&str> {
        self.objects
            .iter()
            .find_map(|o| o.displacement.as_ref().and_then(|d| d.user_wgsl()))
    }

    /// Loads the scene's models ([`Scene::load_models`]) and prepares it.
    pub fn load(scene: &Scene) -> Result<PreparedScene, SceneError> {
        let models = scene.load_models()?;
        PreparedScene::new(scene, &models)
    }
}
