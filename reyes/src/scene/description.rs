//! The scene itself: [`Scene`], its image size, and the constructors that
//! build one from a model and load its objects' models.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::aov::Aov;
use crate::budget::PatchBudget;
use crate::depth::DepthFilter;
use crate::filter::PixelFilter;
use crate::input::InputKind;
use crate::load::LoadError;
use crate::model::Model;
use crate::modes::{Dicing, Sampling, ShadingInterpolation};
#[cfg(doc)]
use crate::params::VALID_SPP;
use crate::params::{DEFAULT_DICE_THRESHOLD, DEFAULT_MAX_SPLIT_DEPTH, DEFAULT_SHADING_RATE};
use crate::quantize::{Exposure, Quantize};

use super::defaults::{
    default_ambient, default_background, default_dice_threshold, default_interleave_permutations,
    default_interleave_tile, default_lights, default_max_split_depth, default_one,
    default_shading_rate, default_spp,
};
use super::framing::box_corners;
use super::lines::SourceLines;
use super::{
    Animation, CameraDesc, CameraPose, Lens, Light, ModelSource, SceneError, SceneObject, Specular,
    Subdivision,
};

/// The model name that selects the embedded teapot instead of a file.
pub const TEAPOT_MODEL: &str = "teapot";

/// Image size in pixels (`[resolution]`, default 800 x 600).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resolution {
    /// Width in pixels (> 0).
    pub width: u32,
    /// Height in pixels (> 0).
    pub height: u32,
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution {
            width: 800,
            height: 600,
        }
    }
}

/// A scene: what to render and how. See the [module documentation](super) for
/// the TOML format.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Samples per pixel (default 4); one of `VALID_SPP`.
    #[serde(default = "default_spp")]
    pub spp: u32,
    /// Sampling mode (default bbox).
    #[serde(default)]
    pub sampling: Sampling,
    /// Side, in pixels, of Interleave UVT's tiles (default
    /// `crate::uvt::DEFAULT_INTERLEAVE_TILE`); one of
    /// `crate::uvt::INTERLEAVE_TILES`. Interleave UVT and Adaptive use it.
    #[serde(default = "default_interleave_tile")]
    pub interleave_tile: u32,
    /// Number of permutations of the pixel offsets Interleave UVT's tiles
    /// choose from (`P`, default
    /// `crate::uvt::DEFAULT_INTERLEAVE_PERMUTATIONS`, 1 to
    /// `crate::uvt::MAX_INTERLEAVE_PERMUTATIONS`); 1 repeats one pattern
    /// in every tile. Interleave UVT and Adaptive use it.
    #[serde(default = "default_interleave_permutations")]
    pub interleave_permutations: u32,
    /// Jitter samples within their strata (default false).
    #[serde(default)]
    pub jitter: bool,
    /// Fraction of the objects' open-to-close motion that happens while the
    /// shutter is open, in [0, 1] (default 1): the objects are seen from
    /// `transform` to the transform interpolated at this fraction.
    #[serde(default = "default_one")]
    pub shutter: f32,
    /// The lens (default: a pinhole).
    #[serde(default)]
    pub lens: Lens,
    /// Linear RGB background (default `[0.05, 0.05, 0.07]`).
    #[serde(default = "default_background")]
    pub background: Vec3,
    /// Ambient term (default 0.1).
    #[serde(default = "default_ambient")]
    pub ambient: f32,
    /// How pieces are diced (default [`Dicing::Rate`]).
    #[serde(default)]
    pub dicing: Dicing,
    /// What the image shows (default the shaded surface; see [`Aov`]).
    #[serde(default)]
    pub aov: Aov,
    /// How the `z` output makes a pixel's depth from its samples' (default
    /// [`DepthFilter::Min`]; RenderMan's `Hider "hidden" "depthfilter"`).
    #[serde(default)]
    pub depth_filter: DepthFilter,
    /// How colour varies over a micropolygon (default
    /// [`ShadingInterpolation::Smooth`]).
    #[serde(default)]
    pub shading_interpolation: ShadingInterpolation,
    /// How the resolve weights the samples around each pixel, RenderMan's
    /// `PixelFilter` (default `gaussian` 2 x 2, RenderMan's).
    #[serde(default)]
    pub pixel_filter: PixelFilter,
    /// RenderMan's `Exposure` of the 8-bit image (default gain 1, gamma
    /// 1); the EXR output is not exposed.
    #[serde(default)]
    pub exposure: Exposure,
    /// RenderMan's `Quantize "rgba"` of the 8-bit image (default one 255,
    /// min 0, max 255, dither 0.5, RenderMan's); the EXR output is not
    /// quantized.
    #[serde(default)]
    pub quantize: Quantize,
    /// The target area of a micropolygon in pixels, RenderMan's
    /// `ShadingRate` (default `DEFAULT_SHADING_RATE`); used by
    /// [`Dicing::Rate`].
    #[serde(default = "default_shading_rate")]
    pub shading_rate: f32,
    /// Dice threshold in pixels of [`Dicing::Fixed`] (default
    /// `DEFAULT_DICE_THRESHOLD`).
    #[serde(default = "default_dice_threshold")]
    pub dice_threshold: f32,
    /// Maximum split depth (default `DEFAULT_MAX_SPLIT_DEPTH`).
    #[serde(default = "default_max_split_depth")]
    pub max_split_depth: u32,
    /// Image size (default 800 x 600).
    #[serde(default)]
    pub resolution: Resolution,
    /// The camera; `None` frames the objects automatically.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraDesc>,
    /// The camera at shutter close (default: the camera does not move).
    /// Needs a `[camera]`: the view moves from `[camera]` to this pose, the
    /// eye linearly and the orientation by slerp (the shorter way), over
    /// the same `shutter` fraction as the objects.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera_close: Option<CameraPose>,
    /// Specular term.
    #[serde(default)]
    pub specular: Specular,
    /// The objects (default none).
    #[serde(default)]
    pub objects: Vec<SceneObject>,
    /// The lights (default: one [`Light::default`]; write `lights = []` for none).
    #[serde(default = "default_lights")]
    pub lights: Vec<Light>,
    /// The space the scene's shadow map files were rendered in: the matrix
    /// from it to this scene's world (default: the scene's world itself).
    /// 16 numbers in RenderMan's `ConcatTransform` order (glam's
    /// column-major). A RIB frame's maps are in the file's world space, its
    /// scene in the frame's camera space: [`crate::rib`] sets the matrix
    /// between them, and `reyes convert` writes it. The maps the lights
    /// and shaders read are moved by it into the scene's world, and a depth
    /// frame's map is written relative to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shadow_map_space: Option<glam::Mat4>,
    /// The animation's frame rate, default interpolation and camera keys
    /// (default none; objects carry their own keys). See
    /// [`Scene::frame`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub animation: Option<Animation>,
    /// The seed of the frame's time and lens samples: the frame number of
    /// a frame of a sequence ([`Scene::frame`]), 0 for a still. Not part of
    /// the TOML: a frame's samples follow from its number alone, so a
    /// frame renders the same alone or in any range.
    #[serde(skip)]
    pub sampling_seed: u32,
    /// Directory against which relative model paths are resolved: the scene
    /// file's directory for [`Scene::load`], `None` (the current directory)
    /// otherwise. Not part of the TOML.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
    /// Where the TOML text gave the objects' shader parameters, for
    /// messages (empty for a scene not read from TOML). Not part of the
    /// TOML, and not compared: see [`SourceLines`].
    #[serde(skip)]
    pub lines: SourceLines,
}

impl Default for Scene {
    /// A scene with every default and no objects.
    fn default() -> Self {
        Scene {
            spp: default_spp(),
            sampling: Sampling::default(),
            interleave_tile: default_interleave_tile(),
            interleave_permutations: default_interleave_permutations(),
            jitter: false,
            shutter: 1.0,
            lens: Lens::default(),
            background: default_background(),
            ambient: default_ambient(),
            dicing: Dicing::default(),
            aov: Aov::default(),
            depth_filter: DepthFilter::default(),
            shading_interpolation: ShadingInterpolation::default(),
            pixel_filter: PixelFilter::default(),
            exposure: Exposure::default(),
            quantize: Quantize::default(),
            shading_rate: DEFAULT_SHADING_RATE,
            dice_threshold: DEFAULT_DICE_THRESHOLD,
            max_split_depth: DEFAULT_MAX_SPLIT_DEPTH,
            resolution: Resolution::default(),
            camera: None,
            camera_close: None,
            specular: Specular::default(),
            objects: Vec::new(),
            lights: default_lights(),
            shadow_map_space: None,
            animation: None,
            sampling_seed: 0,
            base_dir: None,
            lines: SourceLines::default(),
        }
    }
}

impl Scene {
    /// Whether the scene may read or write shadow map files, so that
    /// [`Scene::shadow_map_space`] matters: a light reads maps, the frame
    /// writes depth (`aov = "z"`), or a WGSL shader may take a `ShadowId`.
    pub fn may_use_shadow_map_files(&self) -> bool {
        self.aov == Aov::Z
            || self.lights.iter().any(|l| {
                l.shadow
                    .as_ref()
                    .is_some_and(|s| matches!(s.maps, super::ShadowMaps::Files(_)))
            })
            || self.objects.iter().any(|o| {
                matches!(o.surface, Some(super::Surface::Wgsl { .. }))
                    || o.displacement.as_ref().is_some_and(|d| d.file.is_some())
            })
    }

    /// The default scene: the embedded teapot, 800 x 600, spp 4, framed from
    /// the front, a little to the right of the spout and above.
    pub fn default_teapot() -> Scene {
        let teapot = Model::teapot();
        let mut scene = Scene::for_model(TEAPOT_MODEL, &teapot);
        scene.objects[0].color = Vec3::new(0.80, 0.36, 0.18);
        scene
    }

    /// A scene with one object, `model_name` (a path, or `"teapot"`), using
    /// `model` (already loaded) to frame the camera around it
    /// ([`CameraDesc::framing_points`] over its control points): z up, eye in
    /// front of and above the model, the whole model in view with a margin; one light from over the camera's left shoulder. Other fields
    /// are defaults.
    ///
    /// A model that cannot be framed (its bounds too large or too small for
    /// `f32` view math) gets no camera and the default light: preparing the
    /// scene then reports why automatic framing fails
    /// ([`SceneError::Framing`]), naming the model's bounds.
    pub fn for_model(model_name: impl Into<String>, model: &Model) -> Scene {
        let resolution = Resolution::default();
        let (lo, hi) = model.bounds();
        let corners = box_corners(lo, hi);
        let camera = CameraDesc::try_framing_points(
            corners,
            resolution.width as f32 / resolution.height as f32,
        )
        .ok();
        let light = match &camera {
            Some(camera) => Light {
                direction: camera.shoulder_light_direction(),
                ..Light::default()
            },
            None => Light::default(),
        };
        Scene {
            resolution,
            camera,
            objects: vec![SceneObject::new(model_name)],
            lights: vec![light],
            ..Scene::default()
        }
    }

    /// Where object `object`'s model comes from.
    pub fn model_source(&self, object: &SceneObject) -> ModelSource {
        if object.model == TEAPOT_MODEL {
            return ModelSource::Teapot;
        }
        let path = Path::new(&object.model);
        match &self.base_dir {
            Some(dir) if path.is_relative() => ModelSource::File(dir.join(path)),
            _ => ModelSource::File(path.to_path_buf()),
        }
    }

    /// The model files [`Scene::load_models`] reads (not the embedded
    /// teapot), in object order; one model may appear more than once.
    pub fn model_files(&self) -> Vec<PathBuf> {
        self.objects
            .iter()
            .filter_map(|object| match self.model_source(object) {
                ModelSource::File(path) => Some(path),
                ModelSource::Teapot => None,
            })
            .collect()
    }

    /// The height-map PNGs the objects' displacements read when the scene
    /// is prepared, in object order.
    pub fn height_map_files(&self) -> Vec<PathBuf> {
        self.objects
            .iter()
            .filter_map(|object| object.displacement.as_ref())
            .filter_map(|desc| desc.height_map_path(self.base_dir.as_deref()))
            .collect()
    }

    /// The shadow map files the lights read when the scene is prepared
    /// (resolved against the scene's directory), in light order.
    pub fn shadow_map_files(&self) -> Vec<PathBuf> {
        self.lights
            .iter()
            .filter_map(|light| light.shadow.as_ref())
            .filter_map(|shadow| match &shadow.maps {
                super::ShadowMaps::Files(files) => Some(files),
                super::ShadowMaps::Automatic { .. } => None,
            })
            .flatten()
            .map(|file| match &self.base_dir {
                Some(dir) => dir.join(file),
                None => file.clone(),
            })
            .collect()
    }

    /// Loads every object's model, in object order, within one patch
    /// budget for the whole scene ([`crate::budget`]): each file's declared
    /// count is taken before it is read, so an object that would pass the
    /// budget is refused before its patches are made (the same model named
    /// by many objects counts each time: each object holds its copy).
    pub fn load_models(&self) -> Result<Vec<Model>, SceneError> {
        let mut budget = PatchBudget::from_setting();
        // A model several objects use is read once and kept until its last
        // object takes it; each object still takes its patches from the
        // budget, as each holds them in world space once prepared.
        let key = |object: &SceneObject| {
            (
                self.model_source(object),
                object.subdivision.unwrap_or_default(),
            )
        };
        let mut uses: HashMap<(ModelSource, Subdivision), usize> = HashMap::new();
        for object in &self.objects {
            *uses.entry(key(object)).or_default() += 1;
        }
        let mut loaded: HashMap<(ModelSource, Subdivision), Model> = HashMap::new();
        let mut models = Vec::with_capacity(self.objects.len());
        for (index, object) in self.objects.iter().enumerate() {
            let error = |source| SceneError::Model {
                index,
                model: object.model.clone(),
                source,
            };
            let key = key(object);
            let model = match loaded.remove(&key) {
                Some(model) => {
                    budget
                        .take(model.patches.len() as u64)
                        .map_err(|source| error(LoadError::PatchBudget { line: 1, source }))?;
                    model
                }
                None => match &key.0 {
                    ModelSource::Teapot => {
                        let teapot = Model::teapot();
                        budget
                            .take(teapot.patches.len() as u64)
                            .map_err(|source| error(LoadError::PatchBudget { line: 1, source }))?;
                        teapot
                    }
                    ModelSource::File(path) => Model::load_subdivided_within(
                        path,
                        InputKind::Model.limit(),
                        &mut budget,
                        key.1.scheme(),
                    )
                    .map_err(error)?,
                },
            };
            let left = uses.get_mut(&key).expect("counted above");
            *left -= 1;
            if *left > 0 {
                loaded.insert(key, model.clone());
            }
            models.push(model);
        }
        Ok(models)
    }
}
