//! Scene descriptions in TOML.
//!
//! A scene names the models to render, where they are, how they are lit and
//! seen, and how finely the pipeline samples them. Every field except an
//! object's `model` has a default, so the smallest scene is
//!
//! ```toml
//! [[objects]]
//! model = "teapot"
//! ```
//!
//! (with no `[camera]` table the camera is framed automatically around the
//! objects when the scene is prepared; see [`crate::prepare::PreparedScene`]).
//!
//! A full example with every field (the values shown for optional fields are
//! the defaults, except where a comment says otherwise):
//!
//! ```toml
//! spp = 4                            # samples per pixel: 1, 4, 9, 16, 25, 36, 49 or 64
//! sampling = "bbox"                  # "bbox", "simple", "interleave", "interval", "adaptive" or "nearest"
//! interleave_tile = 2                # Interleave UVT's tile side in pixels: 2, 3 or 4
//! jitter = false                     # jitter samples within their strata
//! shutter = 1.0                      # fraction of the open-to-close motion the shutter sees
//! background = [0.05, 0.05, 0.07]    # linear RGB
//! ambient = 0.1                      # ambient light, multiplied by the albedo
//! dicing = "rate"                   # "rate" (to the shading rate) or "fixed" (16 x 16 points)
//! aov = "shaded"                     # what the image shows: "shaded", "grids", "depth" or "normal"
//! shading_rate = 1.0                 # target micropolygon area in pixels (rate dicing)
//! shading_interpolation = "smooth"   # "smooth" (blend corner colours) or "constant" (one per micropolygon)
//! dice_threshold = 16.0              # fixed dicing: dice when the projected patch fits in this many pixels
//! max_split_depth = 24               # drop patches that still need a split at this depth
//!
//! [resolution]
//! width = 800
//! height = 600
//!
//! [camera]                           # optional: framed automatically when absent
//! eye = [4.0, -12.0, 7.0]            # required in a [camera] table
//! target = [0.2, 0.0, 1.5]           # required in a [camera] table
//! up = [0.0, 0.0, 1.0]
//! fov_y_degrees = 40.0
//! near = 0.1
//! far = 1000.0
//!
//! [camera_close]                     # optional: the camera at shutter close (camera motion)
//! eye = [4.5, -12.0, 7.0]            # required in a [camera_close] table
//! target = [0.7, 0.0, 1.5]           # required in a [camera_close] table
//! up = [0.0, 0.0, 1.0]               # default: the [camera]'s up
//!
//! [lens]                             # depth of field (default: a pinhole)
//! aperture = 0.0                     # lens radius in world units
//! focus_distance = 12.5              # default: the distance from eye to target
//!
//! [specular]
//! strength = 0.25
//! shininess = 32.0
//!
//! [[objects]]
//! model = "teapot"                   # the embedded teapot, or a .bpt/.bez path
//! color = [0.8, 0.8, 0.8]            # linear RGB albedo
//! sides = 2                          # 1: only the front (dP/du x dP/dv towards the eye) is drawn
//! reverse_orientation = false        # the front is the other side
//! [objects.transform]
//! translate = [0.0, 0.0, 0.0]
//! rotate_degrees = [0.0, 0.0, 0.0]   # about x, then y, then z
//! scale = 1.0                        # uniform, or per axis: [1.0, 1.0, 2.0]
//! [objects.displacement]             # optional: no displacement when absent
//! source = "bumps"                   # "bumps", "sines", "wgsl" or a grey PNG path
//! scale = 0.05                       # required: world units per unit of height
//! bound = 0.05                       # default: |scale| * the source's max height
//! tiling = 1.0                       # repetitions of the source per patch
//! [objects.transform_close]          # optional: the placement at shutter close (motion blur)
//! rotate_degrees = [0.0, 0.0, 30.0]  # (not the default: the default is `transform`)
//!
//! [[objects]]
//! model = "models/killeroo.bpt"      # relative to the scene file's directory
//! color = [0.3, 0.5, 0.8]            # (not the default)
//! transform = { translate = [6.0, 0.0, 0.0], scale = 0.5 }
//!
//! [[lights]]                         # without any [[lights]]: one default light like this
//! direction = [0.4, 0.8, -1.0]       # the direction the light travels
//! color = [1.0, 1.0, 1.0]
//! intensity = 1.0
//!
//! [[lights]]                         # a point light: `position` instead of `direction`
//! position = [0.0, 3.0, 4.0]         # falls off as intensity / distance^2
//! intensity = 20.0
//! ```
//!
//! Parse with [`Scene::from_toml_str`] or [`Scene::load`]; both validate the
//! values (see [`Scene::validate`]) and report [`SceneError`].

use std::path::{Path, PathBuf};

use glam::{Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::aov::Aov;
pub use crate::camera::Projection;
use crate::camera::{Camera, PoseProblem, pose_problem};
use crate::displacement::{DisplacementDesc, DisplacementError, desc::SourceKind};
use crate::input::{self, InputError, InputKind};
use crate::load::LoadError;
use crate::model::Model;
pub use crate::modes::{Dicing, Sampling, ShadingInterpolation};
use crate::params::{
    DEFAULT_DICE_THRESHOLD, DEFAULT_MAX_SPLIT_DEPTH, DEFAULT_SHADING_RATE, MAX_SHADING_RATE,
    MAX_SPLIT_DEPTH_LIMIT, NEAR_EPS, VALID_SPP,
};

/// The model name that selects the embedded teapot instead of a file.
pub const TEAPOT_MODEL: &str = "teapot";

/// Why a scene could not be loaded or is invalid.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be opened or read (missing, no permission, ...).
    #[error("cannot read scene file {}: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The scene file was refused before parsing: not a regular file, larger
    /// than the scene cap, or not UTF-8 (see [`crate::input`]).
    #[error(transparent)]
    Input(InputError),
    /// The text is not valid TOML or does not match the scene format.
    #[error("{}{}: {message}", path.as_ref().map(|p| format!("{}: ", p.display())).unwrap_or_default(), line.map(|l| format!("line {l}")).unwrap_or_else(|| "scene".to_string()))]
    Parse {
        /// The scene file, when parsing a file.
        path: Option<PathBuf>,
        /// 1-based line of the error, when the parser knows it.
        line: Option<usize>,
        /// The TOML/serde message.
        message: String,
    },
    /// Width or height is zero.
    #[error("invalid resolution {width}x{height}: width and height must be > 0")]
    InvalidResolution {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
    /// `spp` is not one of the supported perfect squares.
    #[error(
        "spp = {spp} is not supported: use one of 1, 4, 9, 16, 25, 36, 49, 64 (the samples form a k x k grid)"
    )]
    InvalidSpp {
        /// Requested samples per pixel.
        spp: u32,
    },
    /// A number is NaN or infinite.
    #[error("{field} must be finite")]
    NonFinite {
        /// The field, e.g. `objects[0].transform.translate`.
        field: String,
    },
    /// The camera cannot produce a projection.
    #[error("invalid camera: {reason}")]
    InvalidCamera {
        /// What is wrong.
        reason: String,
    },
    /// Any other out-of-range value.
    #[error("invalid {field}: {reason}")]
    InvalidValue {
        /// The field.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// An object's model could not be loaded.
    #[error("object {index} (model {model:?}): {source}")]
    Model {
        /// Index of the object in `objects`.
        index: usize,
        /// The object's `model` string.
        model: String,
        /// Why loading failed.
        #[source]
        source: LoadError,
    },
    /// An object's displacement could not be prepared (its height map could
    /// not be read, or its bound is too small for its source).
    #[error(
        "object {index} (displacement source {:?}): {source}",
        crate::input::excerpt(displacement)
    )]
    Displacement {
        /// Index of the object in `objects`.
        index: usize,
        /// The object's displacement `source` string.
        displacement: String,
        /// Why preparing failed.
        #[source]
        source: DisplacementError,
    },
    /// The scene has no camera and its objects cannot be framed
    /// automatically ([`CameraDesc::try_framing_points`]).
    #[error(
        "{} ({} to {}) {source}",
        if *objects == 1 { "the model's bounds".to_string() } else { format!("the bounds of the scene's {objects} models") },
        format_point(source.bounds().0),
        format_point(source.bounds().1)
    )]
    Framing {
        /// Number of objects framed together.
        objects: usize,
        /// Why framing fails.
        #[source]
        source: FramingError,
    },
    /// An object's transform maps its model's points (at shutter open or
    /// close) beyond `f32`: the product of the transform and the model's
    /// coordinates overflows.
    #[error(
        "objects[{index}].{field} maps model {model:?} beyond f32 range (the transformed control points are not finite: scale times the model's coordinates, plus translate, overflows); scale the model down"
    )]
    TransformOverflow {
        /// Index of the object.
        index: usize,
        /// `transform` or `transform_close`.
        field: &'static str,
        /// The object's `model` string.
        model: String,
    },
    /// A prepared scene was given a different number of models than objects.
    #[error("the scene has {objects} objects but {models} models were given")]
    ModelCountMismatch {
        /// Number of objects in the scene.
        objects: usize,
        /// Number of models given.
        models: usize,
    },
}

/// The thin lens of the camera (`[lens]`): depth of field.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Lens {
    /// Lens radius in world units, >= 0 (default 0: a pinhole, everything sharp).
    pub aperture: f32,
    /// Distance from the eye, along the view direction, of the plane in
    /// focus, > 0 (default: the distance from the eye to the camera target).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<f32>,
}

/// The camera of a scene (`[camera]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position.
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Up direction (default +z).
    #[serde(default = "default_up")]
    pub up: Vec3,
    /// Vertical field of view in degrees, in (0, 180) (default 40).
    #[serde(default = "default_fov")]
    pub fov_y_degrees: f32,
    /// Near plane distance, > 0 (default 0.1).
    #[serde(default = "default_near")]
    pub near: f32,
    /// Far plane distance, > near (default 1000).
    #[serde(default = "default_far")]
    pub far: f32,
    /// `"perspective"` (default, with `fov_y_degrees`) or `"orthographic"`
    /// (with `ortho_height`).
    #[serde(default, skip_serializing_if = "Projection::is_perspective")]
    pub projection: Projection,
    /// An orthographic view's height in world units, > 0. Default: the
    /// height the perspective field of view shows at the target,
    /// `2 |target - eye| tan(fov_y / 2)`, so that switching the projection
    /// keeps the target's plane framed the same.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ortho_height: Option<f32>,
}

/// The camera's pose at shutter close (`[camera_close]`): camera motion.
/// The field of view and the clipping planes stay those of `[camera]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraPose {
    /// Eye position at shutter close.
    pub eye: Vec3,
    /// Point looked at at shutter close.
    pub target: Vec3,
    /// Up direction at shutter close (default: the `[camera]`'s up).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3>,
}

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

/// A uniform or per-axis scale.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Scale {
    /// The same factor on every axis: `scale = 2.0`.
    Uniform(f32),
    /// One factor per axis: `scale = [1.0, 1.0, 2.0]`.
    PerAxis(Vec3),
}

impl Default for Scale {
    fn default() -> Self {
        Scale::Uniform(1.0)
    }
}

impl Scale {
    /// The per-axis factors.
    pub fn to_vec3(self) -> Vec3 {
        match self {
            Scale::Uniform(s) => Vec3::splat(s),
            Scale::PerAxis(v) => v,
        }
    }
}

/// An object's placement (`transform`): scale, then rotate about x, y, z
/// (in that order, degrees), then translate.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Transform {
    /// Translation (default zero).
    pub translate: Vec3,
    /// Euler angles in degrees, applied about x, then y, then z (default zero).
    pub rotate_degrees: Vec3,
    /// Scale (default 1).
    pub scale: Scale,
}

impl Transform {
    /// The rotation `Rz * Ry * Rx` as a quaternion.
    pub fn rotation(&self) -> Quat {
        let r = self.rotate_degrees;
        Quat::from_rotation_z(r.z.to_radians())
            * Quat::from_rotation_y(r.y.to_radians())
            * Quat::from_rotation_x(r.x.to_radians())
    }

    /// The placement a fraction `t` of the way from `self` to `other`:
    /// translation and scale interpolated linearly, rotation by slerp (the
    /// shorter way, so rotations of less than 180 degrees between the two).
    /// Interpolating the matrices instead would shrink a spinning object.
    /// `t = 0` gives exactly [`Transform::matrix`].
    pub fn interpolate(&self, other: &Transform, t: f32) -> Mat4 {
        if t == 0.0 {
            return self.matrix();
        }
        let translate = self.translate.lerp(other.translate, t);
        let scale = self.scale.to_vec3().lerp(other.scale.to_vec3(), t);
        let rotation = self.rotation().slerp(other.rotation(), t);
        Mat4::from_scale_rotation_translation(scale, rotation, translate)
    }

    /// The model-to-world matrix `T * Rz * Ry * Rx * S`.
    pub fn matrix(&self) -> Mat4 {
        let r = self.rotate_degrees;
        Mat4::from_translation(self.translate)
            * Mat4::from_rotation_z(r.z.to_radians())
            * Mat4::from_rotation_y(r.y.to_radians())
            * Mat4::from_rotation_x(r.x.to_radians())
            * Mat4::from_scale(self.scale.to_vec3())
    }
}

/// One object (`[[objects]]`): a model, its placement and its colour.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObject {
    /// `"teapot"` for the embedded teapot, or a `.bpt`/`.bez` path (relative
    /// paths are resolved against the scene file's directory).
    pub model: String,
    /// Placement (default identity).
    #[serde(default)]
    pub transform: Transform,
    /// Linear RGB albedo (default 0.8 grey).
    #[serde(default = "default_color")]
    pub color: Vec3,
    /// Displacement mapping (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement: Option<DisplacementDesc>,
    /// Placement at shutter close (default: `transform`, not moving). The
    /// object moves from `transform` to this one, interpolated as
    /// translation, rotation (slerp) and scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform_close: Option<Transform>,
    /// RenderMan's `Sides`: 2 (default) draws both faces; 1 draws only the
    /// front, where `dP/du x dP/dv` points towards the eye (see
    /// `reverse_orientation`): conservatively back-facing input patches are
    /// culled in Bound, back-facing micropolygons when sampled.
    #[serde(default = "default_sides")]
    pub sides: u8,
    /// RenderMan's `ReverseOrientation`: the front is the other side
    /// (default false). Patch parametrizations are not consistent between
    /// models.
    #[serde(default)]
    pub reverse_orientation: bool,
}

/// A light (`[[lights]]`): a distant light shining along `direction`, or,
/// when `position` is given, a point light (RenderMan's `pointlight`) whose
/// intensity falls off with the square of the distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "LightToml", into = "LightToml")]
pub struct Light {
    /// The direction a distant light travels (from the light towards the
    /// scene); must be non-zero. Default `[0.4, 0.8, -1.0]`. Unused by a
    /// point light.
    pub direction: Vec3,
    /// A point light's position in world space; `None` for a distant light.
    pub position: Option<Vec3>,
    /// Linear RGB colour (default white).
    pub color: Vec3,
    /// Intensity multiplier (default 1). A point light at distance `d`
    /// contributes `intensity * color / d^2`, as RenderMan's `pointlight`.
    pub intensity: f32,
}

impl Light {
    /// A point light at `position`.
    pub fn point(position: Vec3, color: Vec3, intensity: f32) -> Self {
        Light {
            direction: default_light_direction(),
            position: Some(position),
            color,
            intensity,
        }
    }
}

impl Default for Light {
    fn default() -> Self {
        Light {
            direction: default_light_direction(),
            position: None,
            color: default_white(),
            intensity: 1.0,
        }
    }
}

/// `[[lights]]` as written: `direction` and `position` exclude each other.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LightToml {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    direction: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    position: Option<Vec3>,
    #[serde(default = "default_white")]
    color: Vec3,
    #[serde(default = "default_one")]
    intensity: f32,
}

impl TryFrom<LightToml> for Light {
    type Error = String;

    fn try_from(light: LightToml) -> Result<Self, String> {
        if light.direction.is_some() && light.position.is_some() {
            return Err(
                "a light has `direction` (a distant light) or `position` (a point light), not both"
                    .into(),
            );
        }
        Ok(Light {
            direction: light.direction.unwrap_or_else(default_light_direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
        })
    }
}

impl From<Light> for LightToml {
    fn from(light: Light) -> Self {
        LightToml {
            direction: light.position.is_none().then_some(light.direction),
            position: light.position,
            color: light.color,
            intensity: light.intensity,
        }
    }
}

/// Blinn-Phong specular term (`[specular]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Specular {
    /// Specular weight (default 0.25).
    pub strength: f32,
    /// Blinn-Phong exponent, >= 0 (default 32).
    pub shininess: f32,
}

impl Default for Specular {
    fn default() -> Self {
        Specular {
            strength: 0.25,
            shininess: 32.0,
        }
    }
}

/// Where an object's model comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ModelSource {
    /// The embedded teapot ([`Model::teapot`]).
    Teapot,
    /// A model file.
    File(PathBuf),
}

/// A scene: what to render and how. See the [module documentation](self) for
/// the TOML format.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Samples per pixel (default 4); one of [`VALID_SPP`].
    #[serde(default = "default_spp")]
    pub spp: u32,
    /// Sampling mode (default bbox).
    #[serde(default)]
    pub sampling: Sampling,
    /// Side, in pixels, of Interleave UVT's tiles (default
    /// [`crate::uvt::DEFAULT_INTERLEAVE_TILE`]); one of
    /// [`crate::uvt::INTERLEAVE_TILES`]. Interleave UVT and Adaptive use it.
    #[serde(default = "default_interleave_tile")]
    pub interleave_tile: u32,
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
    /// How colour varies over a micropolygon (default
    /// [`ShadingInterpolation::Smooth`]).
    #[serde(default)]
    pub shading_interpolation: ShadingInterpolation,
    /// The target area of a micropolygon in pixels, RenderMan's
    /// `ShadingRate` (default [`DEFAULT_SHADING_RATE`]); used by
    /// [`Dicing::Rate`].
    #[serde(default = "default_shading_rate")]
    pub shading_rate: f32,
    /// Dice threshold in pixels of [`Dicing::Fixed`] (default
    /// [`DEFAULT_DICE_THRESHOLD`]).
    #[serde(default = "default_dice_threshold")]
    pub dice_threshold: f32,
    /// Maximum split depth (default [`DEFAULT_MAX_SPLIT_DEPTH`]).
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
    /// Directory against which relative model paths are resolved: the scene
    /// file's directory for [`Scene::load`], `None` (the current directory)
    /// otherwise. Not part of the TOML.
    #[serde(skip)]
    pub base_dir: Option<PathBuf>,
}

fn default_up() -> Vec3 {
    Vec3::Z
}
fn default_fov() -> f32 {
    40.0
}
fn default_near() -> f32 {
    0.1
}
fn default_far() -> f32 {
    1000.0
}
fn default_color() -> Vec3 {
    Vec3::splat(0.8)
}
fn default_white() -> Vec3 {
    Vec3::ONE
}
fn default_one() -> f32 {
    1.0
}
fn default_light_direction() -> Vec3 {
    Vec3::new(0.4, 0.8, -1.0)
}
fn default_spp() -> u32 {
    4
}
fn default_interleave_tile() -> u32 {
    crate::uvt::DEFAULT_INTERLEAVE_TILE
}
fn default_background() -> Vec3 {
    Vec3::new(0.05, 0.05, 0.07)
}
fn default_ambient() -> f32 {
    0.1
}
fn default_sides() -> u8 {
    2
}
fn default_shading_rate() -> f32 {
    DEFAULT_SHADING_RATE
}
fn default_dice_threshold() -> f32 {
    DEFAULT_DICE_THRESHOLD
}
fn default_max_split_depth() -> u32 {
    DEFAULT_MAX_SPLIT_DEPTH
}
fn default_lights() -> Vec<Light> {
    vec![Light::default()]
}

impl Default for Scene {
    /// A scene with every default and no objects.
    fn default() -> Self {
        Scene {
            spp: default_spp(),
            sampling: Sampling::default(),
            interleave_tile: default_interleave_tile(),
            jitter: false,
            shutter: 1.0,
            lens: Lens::default(),
            background: default_background(),
            ambient: default_ambient(),
            dicing: Dicing::default(),
            aov: Aov::default(),
            shading_interpolation: ShadingInterpolation::default(),
            shading_rate: DEFAULT_SHADING_RATE,
            dice_threshold: DEFAULT_DICE_THRESHOLD,
            max_split_depth: DEFAULT_MAX_SPLIT_DEPTH,
            resolution: Resolution::default(),
            camera: None,
            camera_close: None,
            specular: Specular::default(),
            objects: Vec::new(),
            lights: default_lights(),
            base_dir: None,
        }
    }
}

/// 1-based line of a byte offset in `text`.
fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

fn parse_toml(text: &str, path: Option<&Path>) -> Result<Scene, SceneError> {
    toml::from_str::<Scene>(text).map_err(|e| SceneError::Parse {
        path: path.map(Path::to_path_buf),
        line: e.span().map(|span| line_of(text, span.start)),
        // serde quotes offending string values whole: bound the message.
        message: input::excerpt_to(e.message(), input::MESSAGE_CHARS),
    })
}

impl Scene {
    /// Parses and validates a TOML scene. Relative model paths will be
    /// resolved against the current directory (set [`Scene::base_dir`] to change that).
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        let scene = parse_toml(text, None)?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads, parses and validates a TOML scene file; relative model paths are
    /// resolved against the file's directory. The file is read through
    /// [`crate::input`]: a regular file of at most the scene cap (16 MiB by
    /// default), else [`SceneError::Input`].
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, SceneError> {
        let path = path.as_ref();
        // A regular file of at most the scene cap, byte-order mark removed.
        let text = input::read_text(path, InputKind::Scene, InputKind::Scene.limit()).map_err(
            |error| match error {
                InputError::Io { path, source, .. } => SceneError::Io { path, source },
                other => SceneError::Input(other),
            },
        )?;
        let mut scene = parse_toml(&text, Some(path))?;
        scene.base_dir = Some(
            path.parent()
                .map(Path::to_path_buf)
                .unwrap_or_else(|| PathBuf::from(".")),
        );
        scene.validate()?;
        Ok(scene)
    }

    /// The scene as TOML text (without [`Scene::base_dir`]).
    pub fn to_toml_string(&self) -> String {
        // Every field is representable in TOML (no maps with non-string keys,
        // no None inside arrays), so serialization cannot fail.
        toml::to_string(self).expect("a scene always serializes to TOML")
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
            objects: vec![SceneObject {
                model: model_name.into(),
                transform: Transform::default(),
                color: default_color(),
                displacement: None,
                transform_close: None,
                sides: 2,
                reverse_orientation: false,
            }],
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

    /// Loads every object's model, in object order.
    pub fn load_models(&self) -> Result<Vec<Model>, SceneError> {
        self.objects
            .iter()
            .enumerate()
            .map(|(index, object)| match self.model_source(object) {
                ModelSource::Teapot => Ok(Model::teapot()),
                ModelSource::File(path) => Model::load(&path).map_err(|source| SceneError::Model {
                    index,
                    model: object.model.clone(),
                    source,
                }),
            })
            .collect()
    }

    /// Checks every value: resolution > 0, spp in [`VALID_SPP`], all numbers
    /// finite, `near > 0`, `far > near`, fov in (0, 180), `eye != target`,
    /// `up` not parallel to the view direction (at open, and at close for a
    /// `camera_close`, which needs a `camera`), no motion or lens with
    /// `nearest` sampling, `dice_threshold > 0`, `shading_rate` in `(0, 1024]`, `max_split_depth <= 64`,
    /// `shininess >= 0`, non-zero light directions, and every displacement table ([`DisplacementDesc::validate`]), with at
    /// most one distinct user WGSL function per scene (it becomes part of
    /// the one megakernel).
    ///
    /// What the camera derives is checked too, not only what is written:
    /// the eye's and target's squared lengths and the squared distance
    /// between them must fit `f32` without overflow or underflow, so that
    /// the view direction can be normalized
    /// ([`crate::camera::pose_problem`]), and the view, projection and
    /// world-to-clip matrices must be finite
    /// ([`Camera::matrix_problem`]). What depends on the models (the
    /// transformed control points, an automatically framed camera) is
    /// checked when the scene is prepared ([`crate::prepare::PreparedScene::new`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        let Resolution { width, height } = self.resolution;
        if width == 0 || height == 0 {
            return Err(SceneError::InvalidResolution { width, height });
        }
        if !VALID_SPP.contains(&self.spp) {
            return Err(SceneError::InvalidSpp { spp: self.spp });
        }
        if !crate::uvt::INTERLEAVE_TILES.contains(&self.interleave_tile) {
            return Err(invalid(
                "interleave_tile",
                "must be 2, 3 or 4 (Interleave UVT's tile side in pixels)",
            ));
        }
        finite("background", self.background.to_array())?;
        finite("shutter", [self.shutter])?;
        if !(0.0..=1.0).contains(&self.shutter) {
            return Err(invalid("shutter", "must be in [0, 1]"));
        }
        finite("lens.aperture", [self.lens.aperture])?;
        if self.lens.aperture < 0.0 {
            return Err(invalid(
                "lens.aperture",
                "must be >= 0 (a lens radius in world units)",
            ));
        }
        if self.lens.aperture > 0.0
            && self
                .camera
                .is_some_and(|c| c.projection == Projection::Orthographic)
        {
            return Err(invalid(
                "lens.aperture",
                "must be 0 with an orthographic camera (the thin lens needs a perspective one)",
            ));
        }
        if let Some(focus) = self.lens.focus_distance {
            finite("lens.focus_distance", [focus])?;
            if focus <= 0.0 {
                return Err(invalid("lens.focus_distance", "must be > 0"));
            }
        }
        let moving =
            self.camera_close.is_some() || self.objects.iter().any(|o| o.transform_close.is_some());
        if !self.sampling.supports_blur() && (moving || self.lens.aperture > 0.0) {
            return Err(invalid(
                "sampling",
                "\"nearest\" samples neither time nor lens: use another mode for motion blur or depth of field",
            ));
        }
        finite("ambient", [self.ambient])?;
        finite("dice_threshold", [self.dice_threshold])?;
        finite("specular.strength", [self.specular.strength])?;
        finite("specular.shininess", [self.specular.shininess])?;
        if self.dice_threshold <= 0.0 {
            return Err(invalid("dice_threshold", "must be > 0 pixels"));
        }
        finite("shading_rate", [self.shading_rate])?;
        if !(self.shading_rate > 0.0 && self.shading_rate <= MAX_SHADING_RATE) {
            return Err(invalid(
                "shading_rate",
                &format!("must be in (0, {MAX_SHADING_RATE}] square pixels"),
            ));
        }
        if self.max_split_depth > MAX_SPLIT_DEPTH_LIMIT {
            return Err(invalid(
                "max_split_depth",
                &format!("must be <= {MAX_SPLIT_DEPTH_LIMIT}"),
            ));
        }
        if self.specular.shininess < 0.0 {
            return Err(invalid("specular.shininess", "must be >= 0"));
        }
        if let Some(camera) = &self.camera {
            camera.validate()?;
            // What the camera derives must be finite too: its matrices.
            let built = camera.camera(width, height);
            if let Some(reason) = built.matrix_problem() {
                return Err(SceneError::InvalidCamera {
                    reason: reason.to_string(),
                });
            }
            // Non-finite fields of the pose at close are named below, each
            // by its own field; this checks what finite fields derive.
            if let Some(close) = self
                .camera_close
                .as_ref()
                .filter(|c| c.eye.is_finite() && c.target.is_finite())
            {
                let up = close.up.unwrap_or(camera.up);
                if let Some(reason) = built.looking(close.eye, close.target, up).matrix_problem() {
                    return Err(invalid("camera_close", reason));
                }
            }
        }
        if let Some(close) = &self.camera_close {
            let Some(camera) = &self.camera else {
                return Err(invalid(
                    "camera_close",
                    "needs a [camera] table: the camera at shutter open",
                ));
            };
            finite("camera_close.eye", close.eye.to_array())?;
            finite("camera_close.target", close.target.to_array())?;
            let up = close.up.unwrap_or(camera.up);
            finite("camera_close.up", up.to_array())?;
            if let Some(problem) = pose_problem(close.eye, close.target, up) {
                return Err(invalid("camera_close", &problem.reason("camera_close")));
            }
        }
        for (i, object) in self.objects.iter().enumerate() {
            let t = &object.transform;
            finite(
                &format!("objects[{i}].transform.translate"),
                t.translate.to_array(),
            )?;
            finite(
                &format!("objects[{i}].transform.rotate_degrees"),
                t.rotate_degrees.to_array(),
            )?;
            finite(
                &format!("objects[{i}].transform.scale"),
                t.scale.to_vec3().to_array(),
            )?;
            finite(&format!("objects[{i}].color"), object.color.to_array())?;
            if !matches!(object.sides, 1 | 2) {
                return Err(invalid(&format!("objects[{i}].sides"), "must be 1 or 2"));
            }
            if let Some(t) = &object.transform_close {
                finite(
                    &format!("objects[{i}].transform_close.translate"),
                    t.translate.to_array(),
                )?;
                finite(
                    &format!("objects[{i}].transform_close.rotate_degrees"),
                    t.rotate_degrees.to_array(),
                )?;
                finite(
                    &format!("objects[{i}].transform_close.scale"),
                    t.scale.to_vec3().to_array(),
                )?;
                let degenerate = |t: &Transform| t.scale.to_vec3().cmpeq(Vec3::ZERO).any();
                if degenerate(t) || degenerate(&object.transform) {
                    return Err(invalid(
                        &format!("objects[{i}].transform_close"),
                        "a moving object needs non-zero scales at open and close",
                    ));
                }
            }
            if let Some(displacement) = &object.displacement {
                displacement.validate().map_err(|problem| {
                    let field = format!("objects[{i}].displacement.{}", problem.field);
                    match problem.reason {
                        None => SceneError::NonFinite { field },
                        Some(reason) => SceneError::InvalidValue { field, reason },
                    }
                })?;
            }
        }
        let mut user_wgsl = self
            .objects
            .iter()
            .enumerate()
            .filter_map(|(i, o)| o.displacement.as_ref().map(|d| (i, d)))
            .filter(|(_, d)| d.kind() == SourceKind::Wgsl)
            .filter_map(|(i, d)| d.wgsl.as_deref().map(|w| (i, w)));
        if let Some((_, first)) = user_wgsl.next()
            && let Some((i, _)) = user_wgsl.find(|(_, w)| *w != first)
        {
            return Err(invalid(
                &format!("objects[{i}].displacement.wgsl"),
                "differs from an earlier object's: a scene may use one user WGSL function (it is compiled into the megakernel)",
            ));
        }
        for (i, light) in self.lights.iter().enumerate() {
            finite(&format!("lights[{i}].color"), light.color.to_array())?;
            finite(&format!("lights[{i}].intensity"), [light.intensity])?;
            if let Some(position) = light.position {
                finite(&format!("lights[{i}].position"), position.to_array())?;
                continue;
            }
            finite(
                &format!("lights[{i}].direction"),
                light.direction.to_array(),
            )?;
            if light.direction.length_squared() == 0.0 {
                return Err(invalid(
                    &format!("lights[{i}].direction"),
                    "must be non-zero",
                ));
            }
        }
        Ok(())
    }
}

/// The 8 corners of the box `[lo, hi]`.
fn box_corners(lo: Vec3, hi: Vec3) -> impl Iterator<Item = Vec3> + Clone {
    (0..8).map(move |i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The smallest view depth at which automatic framing places a point
/// (twice [`NEAR_EPS`], the clip `w` below which the renderers cannot project
/// a point): a model framed closer is too small for `f32` view math.
pub const MIN_FRAMED_DEPTH: f32 = 2.0 * NEAR_EPS;

/// Why points cannot be framed automatically
/// ([`CameraDesc::try_framing_points`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FramingError {
    /// The bounds are too large (or not finite) for `f32` view math.
    #[error(
        "are too large to frame automatically ({detail}); give the scene a [camera] (or --eye and --target), or scale the model down (objects[].transform.scale)"
    )]
    TooLarge {
        /// Smallest corner of the bounds.
        lo: Vec3,
        /// Largest corner of the bounds.
        hi: Vec3,
        /// What overflows.
        detail: String,
    },
    /// The bounds are too small: the framing camera would be too close.
    #[error(
        "are too small to frame automatically: the camera would be {nearest:e} from the nearest point, below the {MIN_FRAMED_DEPTH:e} that f32 view math resolves; scale the model up (objects[].transform.scale)"
    )]
    TooSmall {
        /// Smallest corner of the bounds.
        lo: Vec3,
        /// Largest corner of the bounds.
        hi: Vec3,
        /// The nearest point's view depth.
        nearest: f32,
    },
}

impl FramingError {
    /// The bounds that could not be framed.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        match self {
            FramingError::TooLarge { lo, hi, .. } | FramingError::TooSmall { lo, hi, .. } => {
                (*lo, *hi)
            }
        }
    }
}

/// A point in short scientific notation, e.g. `[1e19, -2.5e-30, 0e0]`.
pub fn format_point(p: Vec3) -> String {
    format!("[{:e}, {:e}, {:e}]", p.x, p.y, p.z)
}

fn finite<const N: usize>(field: &str, values: [f32; N]) -> Result<(), SceneError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(SceneError::NonFinite {
            field: field.to_string(),
        })
    }
}

fn invalid(field: &str, reason: &str) -> SceneError {
    SceneError::InvalidValue {
        field: field.to_string(),
        reason: reason.to_string(),
    }
}

impl CameraDesc {
    /// Checks the camera (see [`Scene::validate`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        finite("camera.eye", self.eye.to_array())?;
        finite("camera.target", self.target.to_array())?;
        finite("camera.up", self.up.to_array())?;
        finite("camera.fov_y_degrees", [self.fov_y_degrees])?;
        finite("camera.near", [self.near])?;
        finite("camera.far", [self.far])?;
        if let Some(height) = self.ortho_height {
            finite("camera.ortho_height", [height])?;
        }
        // All values are finite here (checked above), so plain comparisons suffice.
        let reason = if self.near <= 0.0 {
            "near must be > 0".to_string()
        } else if self.far <= self.near {
            "far must be > near".to_string()
        } else if !(self.fov_y_degrees > 0.0 && self.fov_y_degrees < 180.0) {
            "fov_y_degrees must be in (0, 180)".to_string()
        } else if let Some(problem) = pose_problem(self.eye, self.target, self.up) {
            // Derived: the view direction must be computable in f32.
            problem.reason("camera")
        } else if self.projection == Projection::Orthographic
            && !(self.view_height() > 0.0 && self.view_height().is_finite())
        {
            // Derived when not given: from the distance and the fov.
            format!(
                "the orthographic view height {} must be finite and > 0{}",
                self.view_height(),
                if self.ortho_height.is_some() {
                    ""
                } else {
                    " (from the eye-target distance and fov_y_degrees: set ortho_height)"
                }
            )
        } else {
            return Ok(());
        };
        Err(SceneError::InvalidCamera { reason })
    }

    /// The camera this description makes for an image of `width x height`.
    pub fn camera(&self, width: u32, height: u32) -> Camera {
        let camera = Camera::new(
            self.eye,
            self.target,
            self.up,
            self.fov_y_degrees.to_radians(),
            width,
            height,
            self.near,
            self.far,
        );
        match self.projection {
            Projection::Perspective => camera,
            Projection::Orthographic => camera.orthographic(self.view_height()),
        }
    }

    /// The orthographic view height: `ortho_height`, or its default (the
    /// field of view's height at the target).
    pub fn view_height(&self) -> f32 {
        self.ortho_height.unwrap_or_else(|| {
            2.0 * self.eye.distance(self.target) * (0.5 * self.fov_y_degrees.to_radians()).tan()
        })
    }

    /// This camera's pose at shutter close after it moves by `by` and pans
    /// by `pan_degrees` about its up axis through the (moved) eye; a
    /// positive pan turns the view counterclockwise seen from above, so
    /// the scene sweeps to the right across the image. The up direction
    /// stays the same.
    pub fn moved(&self, by: Vec3, pan_degrees: f32) -> CameraPose {
        let pan = Quat::from_axis_angle(self.up.normalize_or_zero(), pan_degrees.to_radians());
        let eye = self.eye + by;
        CameraPose {
            eye,
            target: eye + pan * (self.target - self.eye),
            up: None,
        }
    }

    /// A camera (z up, fov 40 degrees) looking at the centre of the box
    /// `[lo, hi]` from in front and above, at the smallest distance at which
    /// all 8 box corners fall within 90% of the half-width and half-height of
    /// an image of the given aspect ratio (width / height).
    ///
    /// "In front" is -y when the box is at least as wide in x as in y
    /// (the teapot), and +x otherwise (the Killeroo, which is long in y), so
    /// the longer horizontal side faces the camera; the view is turned about
    /// 17 degrees off axis for a three-quarter view.
    pub fn framing(lo: Vec3, hi: Vec3, aspect: f32) -> CameraDesc {
        CameraDesc::framing_points(box_corners(lo, hi), aspect)
    }

    /// Like [`CameraDesc::framing`], but the distance is fitted to the given
    /// points (e.g. all control points, which contain the surface) rather than
    /// to their bounding box's corners: a tighter fit for rounded models. The
    /// view direction and target still come from the points' bounding box.
    /// With no points, frames the unit box around the origin.
    ///
    /// Points too far apart or too far out for `f32` view math give a
    /// camera that does not validate; [`CameraDesc::try_framing_points`]
    /// says so instead.
    pub fn framing_points(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> CameraDesc {
        Self::framing_fit(points, aspect).0
    }

    /// [`CameraDesc::framing_points`], or why the points cannot be framed
    /// in `f32`: the bounds are non-finite or too large for the view math
    /// (the squared distances overflow), or so small that the nearest point
    /// would lie closer to the eye than [`MIN_FRAMED_DEPTH`] (the renderers
    /// cannot project points at clip `w <= NEAR_EPS`).
    pub fn try_framing_points(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> Result<CameraDesc, FramingError> {
        let (desc, lo, hi, nearest) = Self::framing_fit(points, aspect);
        let too_large = |detail: String| FramingError::TooLarge { lo, hi, detail };
        if !(lo.is_finite() && hi.is_finite()) {
            return Err(too_large("they are not finite".into()));
        }
        let fields = [desc.eye, desc.target, Vec3::new(desc.near, desc.far, 0.0)];
        let usable =
            fields.iter().all(|v| v.is_finite()) && desc.near > 0.0 && desc.far > desc.near;
        if !usable {
            return Err(too_large(
                "the camera that would frame them is not finite in f32".into(),
            ));
        }
        if let Some(problem) = pose_problem(desc.eye, desc.target, desc.up) {
            return Err(match problem {
                PoseProblem::TooClose => FramingError::TooSmall { lo, hi, nearest },
                _ => too_large(
                    "the camera that would frame them lies too far out for f32 view math: its squared distances overflow"
                        .into(),
                ),
            });
        }
        // Also refuses a NaN depth.
        if nearest.is_nan() || nearest < MIN_FRAMED_DEPTH {
            return Err(FramingError::TooSmall { lo, hi, nearest });
        }
        Ok(desc)
    }

    /// The framing camera, the points' bounds and the view depth of the
    /// nearest point.
    fn framing_fit(
        points: impl IntoIterator<Item = Vec3> + Clone,
        aspect: f32,
    ) -> (CameraDesc, Vec3, Vec3, f32) {
        const MARGIN: f32 = 0.9;
        let fov_y_degrees = default_fov();
        let (lo, hi) = points
            .clone()
            .into_iter()
            .fold(None, |acc: Option<(Vec3, Vec3)>, p| match acc {
                None => Some((p, p)),
                Some((lo, hi)) => Some((lo.min(p), hi.max(p))),
            })
            .unwrap_or((Vec3::splat(-0.5), Vec3::splat(0.5)));
        let mut center = (lo + hi) * 0.5;
        if !center.is_finite() {
            // lo + hi overflowed.
            center = lo * 0.5 + hi * 0.5;
        }
        let extent = hi - lo;
        let length = extent.length();
        let radius = if length > 0.0 && length.is_finite() && length >= 1e-18 {
            length * 0.5
        } else if extent.max_element() > 0.0 {
            // The squared length underflows or overflows: scale first.
            let m = extent.max_element();
            (extent / m).length() * m * 0.5
        } else {
            // One point: frame a small ball around it.
            1e-3f32.max(center.abs().max_element() * 1e-3)
        };
        // Direction from the target to the eye.
        let to_eye = if extent.x >= extent.y {
            Vec3::new(0.3, -1.0, 0.55)
        } else {
            Vec3::new(1.0, 0.3, 0.55)
        }
        .normalize();
        let forward = -to_eye;
        let right = forward.cross(Vec3::Z).normalize();
        let up = right.cross(forward);
        let tan_y = (fov_y_degrees.to_radians() * 0.5).tan() * MARGIN;
        let tan_x = tan_y * aspect;
        // A point at offset q from the centre has depth (dist - q.to_eye) and
        // must satisfy |q.right| <= depth * tan_x and |q.up| <= depth * tan_y.
        let mut distance = radius * 0.1;
        for point in points.clone() {
            let q = point - center;
            let along = q.dot(to_eye);
            distance = distance
                .max(along + q.dot(right).abs() / tan_x)
                .max(along + q.dot(up).abs() / tan_y);
        }
        let near = ((distance - radius) * 0.5).max(distance * 1e-3);
        let far = distance + radius * 4.0;
        let farthest_along = points
            .clone()
            .into_iter()
            .map(|p| (p - center).dot(to_eye))
            .fold(f32::NEG_INFINITY, f32::max);
        let nearest = distance - farthest_along.max(-distance);
        (
            CameraDesc {
                eye: center + to_eye * distance,
                target: center,
                up: Vec3::Z,
                fov_y_degrees,
                near,
                far,
                projection: Projection::Perspective,
                ortho_height: None,
            },
            lo,
            hi,
            nearest,
        )
    }

    /// The travel direction of a light coming from over the camera's left
    /// shoulder (above and to the left of the eye, as seen from the eye).
    pub fn shoulder_light_direction(&self) -> Vec3 {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        (forward + right * 0.6 - up * 0.8).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::{fresh_rng, random_vec3};

    /// The full example in this module's documentation stays valid.
    #[test]
    fn module_doc_example_parses() {
        let source = include_str!("scene.rs");
        let marker = "//! ```toml\n//! spp = 4";
        let start = source.find(marker).expect("the full example") + "//! ```toml\n".len();
        let end = start + source[start..].find("//! ```").unwrap();
        let text: String = source[start..end]
            .lines()
            .map(|l| {
                l.strip_prefix("//!")
                    .unwrap_or(l)
                    .strip_prefix(' ')
                    .unwrap_or("")
            })
            .collect::<Vec<_>>()
            .join("\n");
        let scene = Scene::from_toml_str(&text).unwrap();
        assert_eq!(scene.objects.len(), 2);
        assert_eq!(
            scene.lights,
            vec![
                Light::default(),
                Light::point(Vec3::new(0.0, 3.0, 4.0), Vec3::ONE, 20.0)
            ]
        );
        assert_eq!(scene.specular, Specular::default());
    }

    /// A moved and panned camera (fresh random poses, the seed printed):
    /// the eye moves by the vector, the view direction keeps its length and
    /// its component along up and turns by the pan about up, and for a
    /// positive pan the point the camera looked at lands right of the
    /// image's centre, at the angle's tangent on the image plane.
    #[test]
    fn a_moved_camera_pans_about_its_up_axis() {
        use rand::Rng;
        let (seed, mut rng) = fresh_rng("a_moved_camera_pans_about_its_up_axis");
        for _ in 0..50 {
            let eye = random_vec3(&mut rng, 10.0);
            let by = random_vec3(&mut rng, 3.0);
            // Level views (target at the eye's height), so that the
            // image's horizontal axis is the pan's plane.
            let ahead =
                random_vec3(&mut rng, 5.0) * Vec3::new(1.0, 1.0, 0.0) + Vec3::new(0.3, 0.0, 0.0);
            let camera = CameraDesc {
                eye,
                target: eye + ahead,
                up: Vec3::Z,
                fov_y_degrees: 50.0,
                near: 0.1,
                far: 100.0,
                projection: Projection::Perspective,
                ortho_height: None,
            };
            let pan = rng.random_range(1.0f32..40.0);
            let close = camera.moved(by, pan);
            assert!(close.eye.abs_diff_eq(eye + by, 1e-5), "seed {seed}");
            assert_eq!(close.up, None, "seed {seed}");
            let turned = close.target - close.eye;
            assert!((turned.length() - ahead.length()).abs() < 1e-4 * ahead.length());
            assert!(turned.z.abs() < 1e-4, "seed {seed}: {turned}");
            let turn = ahead.angle_between(turned).to_degrees();
            assert!((turn - pan).abs() < 1e-2, "seed {seed}: {turn} vs {pan}");
            assert!(ahead.cross(turned).z > 0.0, "seed {seed}: counterclockwise");

            let (width, height) = (200, 100);
            let fov = camera.fov_y_degrees.to_radians();
            let at_close = Camera::new(
                close.eye,
                close.target,
                Vec3::Z,
                fov,
                width,
                height,
                0.1,
                100.0,
            );
            let old_target = close.eye + ahead;
            let pixel = at_close.to_pixel(at_close.to_clip(old_target));
            let focal = height as f32 / 2.0 / (fov / 2.0).tan();
            let want = width as f32 / 2.0 + focal * pan.to_radians().tan();
            assert!(
                (pixel.x - want).abs() < 0.05,
                "seed {seed}: x {} vs {want}",
                pixel.x
            );
            assert!(
                (pixel.y - height as f32 / 2.0).abs() < 0.05,
                "seed {seed}: y {}",
                pixel.y
            );
        }
    }
}
