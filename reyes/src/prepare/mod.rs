//! Host-side scene preparation, shared by the CPU reference and the GPU path:
//! control points transformed to world space once, the camera built (or
//! framed automatically), lights normalized.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec2, Vec3};

use crate::aov::Aov;
use crate::camera::Camera;
use crate::dicing::DicingRule;
use crate::displacement::PreparedDisplacement;
use crate::filter::PixelFilter;
use crate::model::Model;
use crate::motion::{ObjectMotion, PreparedLens, camera_motion, interpolate_view};
use crate::params::DEGENERATE_NORMAL_REL_EPS;
use crate::quantize::Encoding;
use crate::scene::{
    CameraDesc, FramingError, Sampling, Scene, SceneError, ShadingInterpolation, Surface,
};
pub use crate::shading::{PreparedLight, PreparedShadow, PreparedSurface};
use crate::shadow::ShadowMap;

mod displacement;
mod lights;
mod patches;
mod shadow_passes;
mod unknown_parameters;

use self::displacement::ShaderTables;
pub use self::lights::PendingShadow;
pub use self::patches::{PatchStore, SharedPatch};
pub use self::shadow_passes::{
    DEPTH_PASS_SHADING_RATE_FACTOR, DepthPass, MAX_SPOT_MAP_FOV_DEGREES, PassStats, RenderedPass,
    depth_passes,
};
use self::unknown_parameters::UnknownParameters;
use crate::surface_shader::{ShaderKind, ShaderTable};
use crate::texture::TextureSet;
use crate::uvt::{InterleaveTiles, UvtTables};

/// Largest RGBA image of a frame, in bytes, for both renderers: 128 MiB,
/// WebGPU's default `max_storage_buffer_binding_size`, which is also what
/// lavapipe binds. The GPU path refuses a frame whose image exceeds its
/// device's buffer limit; the CPU reference, which has no device, takes
/// this one (see `crate::reference::limits`).
pub const MAX_IMAGE_BYTES: u64 = wgpu::Limits::defaults().max_storage_buffer_binding_size;

/// Whether a patch has no area: all control points equal, or all on one
/// line (up to `DEGENERATE_NORMAL_REL_EPS` relative to their spread).
/// Such a patch has no normal anywhere; rendered, it is float noise.
/// The points must be finite.
pub fn degenerate_patch(points: &[Vec3; 16]) -> bool {
    let origin = points[0];
    let spread = |p: Vec3| (p - origin).abs().max_element();
    let farthest = points
        .iter()
        .copied()
        .max_by(|a, b| spread(*a).total_cmp(&spread(*b)))
        .unwrap_or(origin);
    let scale = spread(farthest);
    if scale == 0.0 {
        return true;
    }
    // Scaled so that neither the cross products nor the squared lengths
    // overflow or underflow.
    let axis = (farthest - origin) / scale;
    points.iter().all(|&p| {
        let offset = (p - origin) / scale;
        offset.cross(axis).length_squared()
            <= DEGENERATE_NORMAL_REL_EPS * offset.length_squared() * axis.length_squared()
    })
}

/// One input patch in world space, with the object it belongs to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldPatch {
    /// Control points in world space, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
    /// Index of the object (in [`PreparedScene::objects`]).
    pub object: u32,
    /// The texture coordinates `s, t` at the corners `(u, v) = (0,0),
    /// (1,0), (0,1), (1,1)` ([`crate::model::Model::st`]; the unit square
    /// by default); inside the patch, their bilinear blend at `(u, v)`.
    pub st: [Vec2; 4],
    /// The index of the patch the GPU stores for it
    /// ([`PreparedScene::store`]): its own world-space points, or, when
    /// its object shares its model with others, the model's patch in model
    /// space, which [`PreparedObject::placement`] places.
    pub stored: u32,
}

impl WorldPatch {
    /// `s, t` at `(u, v)`: the bilinear blend of the corners' (the WGSL
    /// `patch_st`).
    pub fn st_at(&self, u: f32, v: f32) -> Vec2 {
        let [a, b, c, d] = self.st;
        let bottom = a + (b - a) * u;
        let top = c + (d - c) * u;
        bottom + (top - bottom) * v
    }

    /// `s, t` at `(u, v)` with their derivatives along `u` and `v` (the
    /// WGSL `patch_st_frame`).
    pub fn st_frame(&self, u: f32, v: f32) -> [Vec2; 3] {
        [
            self.st_at(u, v),
            self.st_at(1.0, v) - self.st_at(0.0, v),
            self.st_at(u, 1.0) - self.st_at(u, 0.0),
        ]
    }
}

/// Per-object shading and displacement data.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedObject {
    /// Linear RGB colour, RenderMan's `Cs`.
    pub color: Vec3,
    /// The surface shader; `None` for `null`, whose patches are not drawn
    /// (the scene's patches hold none of them).
    pub surface: Option<PreparedSurface>,
    /// Displacement mapping, if any.
    pub displacement: Option<PreparedDisplacement>,
    /// The object's own shading rate (RenderMan's `ShadingRate` attribute),
    /// if it has one; `None` takes the frame's
    /// ([`PreparedScene::object_dicing`]).
    pub shading_rate: Option<f32>,
    /// How the object moves during the shutter (`None`: it does not).
    pub motion: Option<ObjectMotion>,
    /// One-sided objects (`sides = 1`): the sign `s` such that the front
    /// faces along `s * (dP/du x dP/dv)` in world space (negative with
    /// `reverse_orientation`, and again for a mirroring transform); `None`
    /// for two-sided objects, which are never culled as back-facing.
    pub front: Option<f32>,
    /// The model-to-world matrix of an object that shares its model's
    /// patches with other objects ([`PatchStore::shared`]); `None` when its
    /// patches are stored in world space.
    pub placement: Option<glam::Mat4>,
}

impl PreparedObject {
    /// The displacement bound in world units (0 without displacement).
    pub fn displacement_bound(&self) -> f32 {
        self.displacement.as_ref().map_or(0.0, |d| d.bound)
    }
}

/// Everything a renderer needs for one frame, in world space.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedScene {
    /// The camera (image size included).
    pub camera: Camera,
    /// All objects' patches, in object order.
    pub patches: Vec<WorldPatch>,
    /// The patches the GPU stores, each once: [`WorldPatch::stored`]
    /// indexes them.
    pub store: PatchStore,
    /// Shading data per object.
    pub objects: Vec<PreparedObject>,
    /// The lights that illuminate (distant, point and spot lights).
    pub lights: Vec<PreparedLight>,
    /// The shadow maps the lights look up ([`PreparedLight::shadow`]) and
    /// the user shaders' `ShadowId`s name, in the scene's world.
    pub shadow_maps: Vec<ShadowMap>,
    /// The space the scene's map files were rendered in
    /// ([`Scene::shadow_map_space`]): a depth frame's map is written
    /// relative to it.
    pub shadow_map_space: Option<Mat4>,
    /// The shadows still to render from their lights before the frame
    /// (`shadows = true`); their lights have no
    /// [`PreparedLight::shadow`] until then.
    pub pending_shadows: Vec<PendingShadow>,
    /// What the surfaces' `ambient()` returns: the scene's `ambient` (a
    /// white ambient light) plus every ambient light's colour times
    /// intensity.
    pub ambient: Vec3,
    /// Samples per pixel (a perfect square).
    pub spp: u32,
    /// The seed of the time and lens samples ([`Scene::sampling_seed`]: a
    /// sequence's frame number, else 0).
    pub sampling_seed: u32,
    /// Sampling mode.
    pub sampling: Sampling,
    /// Side, in pixels, of Interleave UVT's tiles (2, 3 or 4).
    pub interleave_tile: u32,
    /// Number of permutations Interleave UVT's tiles choose from (`P`).
    pub interleave_permutations: u32,
    /// Whether samples are jittered within their strata.
    pub jitter: bool,
    /// Linear RGB background.
    pub background: Vec3,
    /// How pieces are diced, with the shading rate, the micropolygon side
    /// and the dice threshold that follow.
    pub dicing: DicingRule,
    /// Drop patches that still need a split at this depth.
    pub max_split_depth: u32,
    /// Input patches left out because they have no area
    /// ([`degenerate_patch`]: all control points equal, or collinear); each
    /// preparation logs the count as a warning.
    pub skipped_degenerate_patches: usize,
    /// The thin lens (aperture 0: a pinhole).
    pub lens: PreparedLens,
    /// The camera's motion during the shutter as a motion of the world
    /// (`crate::motion::camera_motion`; `None`: the camera is still).
    /// Every object's [`PreparedObject::motion`] includes it; a pass from
    /// a light, which does not move with the camera, takes it out.
    pub camera_motion: Option<glam::Mat4>,
    /// What the image shows.
    pub aov: Aov,
    /// How the `z` output makes a pixel's depth from its samples'.
    pub depth_filter: crate::depth::DepthFilter,
    /// How colour varies over a micropolygon.
    pub shading_interpolation: ShadingInterpolation,
    /// The pixel filter of the resolve: the scene's, except for the `grids`
    /// picture, whose pixels average their own samples (a box over one
    /// pixel) so that its colours stay the grid classes'.
    pub pixel_filter: PixelFilter,
    /// The user surface shaders the objects run, with their parameters.
    pub shaders: ShaderTable,
    /// The textures the shaders' parameters name.
    pub textures: TextureSet,
    /// How the resolved linear image becomes the 8-bit one: the scene's
    /// exposure and quantization, except for the pictures of data (every
    /// [`Aov`] but `shaded`), whose colours are encoded plainly
    /// ([`Encoding::PLAIN`]: no exposure, no dither).
    pub encoding: Encoding,
}

impl PreparedScene {
    /// Prepares `scene` with its models already loaded (`models[i]` belongs to
    /// `scene.objects[i]`). The scene is validated first; height maps named
    /// by displacement tables are read here. Without a camera in
    /// the scene, the camera is framed around the world-space bounds of all
    /// patches ([`CameraDesc::try_framing_points`]).
    ///
    /// Besides [`Scene::validate`], this checks what the models derive:
    /// every transformed control point (at shutter open and close) must be
    /// finite ([`SceneError::TransformOverflow`]), and an automatically
    /// framed camera must be usable in `f32` ([`SceneError::Framing`],
    /// naming the models' bounds). Patches without area
    /// ([`degenerate_patch`]) are left out and counted in
    /// [`PreparedScene::skipped_degenerate_patches`], with a logged warning.
    pub fn new(scene: &Scene, models: &[Model]) -> Result<PreparedScene, SceneError> {
        scene.validate()?;
        if models.len() != scene.objects.len() {
            return Err(SceneError::ModelCountMismatch {
                objects: scene.objects.len(),
                models: models.len(),
            });
        }
        let patches::Placed {
            patches,
            store,
            placements,
            skipped_degenerate: skipped_degenerate_patches,
        } = patches::place_patches(scene, models)?;
        if skipped_degenerate_patches > 0 {
            log::warn!(
                "skipped {skipped_degenerate_patches} degenerate patch(es) without area (all control points equal or on one line)"
            );
        }
        let (width, height) = (scene.resolution.width, scene.resolution.height);
        let desc = match scene.camera {
            Some(desc) => desc,
            None => {
                let framing = |source| SceneError::Framing {
                    objects: scene.objects.len(),
                    source,
                };
                let mut desc = CameraDesc::try_framing_points(
                    patches.iter().flat_map(|p| p.points.iter().copied()),
                    width as f32 / height as f32,
                )
                .map_err(framing)?;
                desc.far = far_plane_covering_motion(&desc, scene, models);
                if let Some(reason) = desc.camera(width, height).matrix_problem() {
                    let (lo, hi) = patches
                        .iter()
                        .flat_map(|p| p.points)
                        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
                            (lo.min(p), hi.max(p))
                        });
                    return Err(framing(FramingError::TooLarge {
                        lo,
                        hi,
                        detail: format!("for the camera that would frame them, {reason}"),
                    }));
                }
                desc
            }
        };
        let camera = desc.camera(width, height);
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
        // The lights first: user shaders' shadow maps follow the lights'.
        let mut lights = lights::prepare_lights(scene)?;
        let mut prepared_objects = Vec::with_capacity(scene.objects.len());
        let mut shaders = ShaderTable::default();
        let mut textures = TextureSet::default();
        let mut unknown_parameters = UnknownParameters::new(scene.lines.clone());
        for (index, object) in scene.objects.iter().enumerate() {
            let open = object.transform.matrix();
            let mirrored = open.determinant() < 0.0;
            let displacement = object
                .displacement
                .as_ref()
                .map(|desc| {
                    let tables = ShaderTables {
                        shaders: &mut shaders,
                        textures: &mut textures,
                        shadow_maps: &mut lights.shadow_maps,
                        base_dir: scene.base_dir.as_deref(),
                        unknown_parameters: &mut unknown_parameters,
                    };
                    displacement::prepare(desc, index, object, mirrored, tables)
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
            let surface = object.surface.clone().unwrap_or_else(|| {
                Surface::scene_default(scene.specular.strength, scene.specular.shininess)
            });
            let surface = PreparedSurface::new(&surface, |file, values| {
                let path = shader_path(scene.base_dir.as_deref(), file);
                let (reference, warnings) = shaders
                    .add(
                        &path,
                        ShaderKind::Surface,
                        values,
                        &mut textures,
                        &mut lights.shadow_maps,
                        scene.base_dir.as_deref(),
                    )
                    .map_err(|source| SceneError::SurfaceShader {
                        index,
                        file: path.clone(),
                        source,
                    })?;
                unknown_parameters.warn(index, "surface", &path, &warnings);
                Ok(PreparedSurface::User {
                    shader: reference.shader,
                    parameters: reference.parameters,
                })
            })?;
            prepared_objects.push(PreparedObject {
                color: object.color,
                surface,
                shading_rate: object.shading_rate,
                displacement,
                motion,
                front,
                placement: placements[index],
            });
        }
        // The maps read from files are in the space they were rendered in.
        if let Some(space) = scene.shadow_map_space {
            let into_scene = space.inverse();
            for map in &mut lights.shadow_maps {
                map.world_to_camera *= into_scene;
                map.world_to_clip *= into_scene;
            }
        }
        let lens = PreparedLens::new(&camera, scene.lens.aperture, scene.lens.focus_distance);
        Ok(PreparedScene {
            lens,
            camera,
            camera_motion,
            patches,
            store,
            objects: prepared_objects,
            lights: lights.lights,
            ambient: lights.ambient,
            shadow_maps: lights.shadow_maps,
            shadow_map_space: scene.shadow_map_space,
            pending_shadows: lights.pending_shadows,
            spp: scene.spp,
            sampling_seed: scene.sampling_seed,
            sampling: scene.sampling,
            interleave_tile: scene.interleave_tile,
            interleave_permutations: scene.interleave_permutations,
            jitter: scene.jitter,
            background: scene.background,
            dicing: DicingRule::new(scene.dicing, scene.shading_rate, scene.dice_threshold),
            max_split_depth: scene.max_split_depth,
            skipped_degenerate_patches,
            aov: scene.aov,
            depth_filter: scene.depth_filter,
            shading_interpolation: scene.shading_interpolation,
            // The grids picture's colours are categories: not blended.
            pixel_filter: if scene.aov == Aov::Grids {
                PixelFilter::PIXEL_BOX
            } else {
                scene.pixel_filter
            },
            shaders,
            textures,
            encoding: if scene.aov == Aov::Shaded {
                Encoding {
                    exposure: scene.exposure,
                    quantize: scene.quantize,
                }
            } else {
                Encoding::PLAIN
            },
        })
    }

    /// Whether any object moves during the shutter (relative to the camera:
    /// with camera motion, every object does).
    pub fn has_motion(&self) -> bool {
        self.objects.iter().any(|o| o.motion.is_some())
    }

    /// How `object` is diced: the frame's rule ([`PreparedScene::dicing`]),
    /// at the object's own shading rate where it has one.
    pub fn object_dicing(&self, object: &PreparedObject) -> DicingRule {
        match object.shading_rate {
            Some(rate) => DicingRule::new(self.dicing.mode(), rate, self.dicing.fixed_threshold()),
            None => self.dicing,
        }
    }

    /// The side of a micropolygon, in pixels, that Adaptive sampling's cost
    /// model assumes ([`DicingRule::nominal_micropolygon_px`]).
    pub fn nominal_micropolygon_px(&self) -> f32 {
        self.dicing.nominal_micropolygon_px()
    }

    /// Interleave UVT's tiles over the full image (a screen tile's camera
    /// keeps the full image's width, along whose rows tiles are numbered).
    pub fn interleave_tiles(&self) -> InterleaveTiles {
        InterleaveTiles::new(
            self.interleave_tile,
            self.interleave_permutations,
            self.camera.full_width,
        )
    }

    /// The time/lens tables of this frame's sample count and Interleave
    /// tiles.
    pub fn uvt_tables(&self) -> UvtTables {
        UvtTables::seeded(self.spp, self.interleave_tiles(), self.sampling_seed)
    }

    /// Whether the sample framebuffer keeps each sample's second-nearest key
    /// too: only for the z output with the midpoint depth filter.
    pub fn keeps_second_depth(&self) -> bool {
        self.aov == Aov::Z && self.depth_filter == crate::depth::DepthFilter::Midpoint
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

    /// Loads the scene's models ([`Scene::load_models`]) and prepares it.
    pub fn load(scene: &Scene) -> Result<PreparedScene, SceneError> {
        let models = scene.load_models()?;
        PreparedScene::new(scene, &models)
    }
}

/// A shader file as the scene names it, relative to the scene file's
/// directory (`base_dir`); a built-in shader's name stays as it is.
fn shader_path(base_dir: Option<&Path>, file: &Path) -> PathBuf {
    let builtin = file
        .to_str()
        .is_some_and(|f| f.starts_with(crate::surface_shader::builtin::PREFIX));
    match base_dir {
        Some(dir) if file.is_relative() && !builtin => dir.join(file),
        _ => file.to_path_buf(),
    }
}

/// The far plane of the automatically framed camera `desc`, pushed back
/// so that it also covers the control points of `scene`'s moving objects
/// (`models`, one per object) at shutter close: the framing looks at the
/// objects at open, and a point past the far plane is not seen. The
/// margin beyond the farthest point is the one the framing leaves beyond
/// the objects' centre. `reyes render` applies it to a framed model that
/// `--move` or `--spin` sets in motion.
pub fn far_plane_covering_motion(desc: &CameraDesc, scene: &Scene, models: &[Model]) -> f32 {
    let forward = (desc.target - desc.eye).normalize();
    let margin = desc.far - (desc.target - desc.eye).length();
    let farthest = scene
        .objects
        .iter()
        .zip(models)
        .filter_map(|(object, model)| {
            let close = object.transform_close.as_ref()?;
            Some((object.transform.interpolate(close, scene.shutter), model))
        })
        .flat_map(|(close, model)| {
            model
                .patches
                .iter()
                .flat_map(move |patch| patch.points.map(|p| close.transform_point3(p)))
        })
        .map(|p| (p - desc.eye).dot(forward))
        .fold(f32::NEG_INFINITY, f32::max);
    let far = farthest + margin;
    // A non-finite depth (or nothing moving) keeps the framing's plane.
    if far.is_finite() {
        desc.far.max(far)
    } else {
        desc.far
    }
}
