//! Objects as written: their model, placement and appearance.

use std::path::PathBuf;

use glam::{Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};

use crate::displacement::DisplacementDesc;
#[cfg(doc)]
use crate::model::Model;
#[cfg(doc)]
use crate::scene::Scene;
use crate::subdiv::Scheme;

use super::defaults::{default_color, default_sides};
use super::{Surface, TransformKey};

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
/// (in that order, degrees), then translate, then the general `matrix` if
/// there is one.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Transform {
    /// Translation (default zero).
    pub translate: Vec3,
    /// Euler angles in degrees, applied about x, then y, then z (default zero).
    pub rotate_degrees: Vec3,
    /// Scale (default 1).
    pub scale: Scale,
    /// A general affine model-to-world matrix applied after the others
    /// (default none): 16 numbers in RenderMan's `ConcatTransform` order,
    /// which is glam's column-major order (the translation is numbers 13
    /// to 15). RIB instances are placed with it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<Mat4>,
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
    /// `t = 0` gives exactly [`Transform::matrix`]. A placement with a
    /// general `matrix` is interpolated through its scale, rotation and
    /// translation (a shear is not interpolated).
    pub fn interpolate(&self, other: &Transform, t: f32) -> Mat4 {
        if t == 0.0 {
            return self.matrix();
        }
        if self.matrix.is_some() || other.matrix.is_some() {
            let (scale_a, rotation_a, translate_a) = self.matrix().to_scale_rotation_translation();
            let (scale_b, rotation_b, translate_b) = other.matrix().to_scale_rotation_translation();
            return Mat4::from_scale_rotation_translation(
                scale_a.lerp(scale_b, t),
                rotation_a.slerp(rotation_b, t),
                translate_a.lerp(translate_b, t),
            );
        }
        let translate = self.translate.lerp(other.translate, t);
        let scale = self.scale.to_vec3().lerp(other.scale.to_vec3(), t);
        let rotation = self.rotation().slerp(other.rotation(), t);
        Mat4::from_scale_rotation_translation(scale, rotation, translate)
    }

    /// The model-to-world matrix `M * T * Rz * Ry * Rx * S`, where `M` is
    /// the general `matrix` (identity without one).
    pub fn matrix(&self) -> Mat4 {
        let r = self.rotate_degrees;
        let placed = Mat4::from_translation(self.translate)
            * Mat4::from_rotation_z(r.z.to_radians())
            * Mat4::from_rotation_y(r.y.to_radians())
            * Mat4::from_rotation_x(r.x.to_radians())
            * Mat4::from_scale(self.scale.to_vec3());
        match self.matrix {
            Some(matrix) => matrix * placed,
            None => placed,
        }
    }
}

/// One object (`[[objects]]`): a model, its placement and its colour.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneObject {
    /// `"teapot"` for the embedded teapot, or a `.bpt`/`.bez`/`.obj` path
    /// (relative paths are resolved against the scene file's directory).
    pub model: String,
    /// How an `.obj` model's mesh becomes patches (default
    /// [`Subdivision::CatmullClark`]). Only `.obj` models have a mesh: the
    /// key on any other model is an error ([`Scene::validate`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subdivision: Option<Subdivision>,
    /// Placement (default identity).
    #[serde(default)]
    pub transform: Transform,
    /// Linear RGB colour, RenderMan's `Cs` (default 0.8 grey).
    #[serde(default = "default_color")]
    pub color: Vec3,
    /// The surface shader (default: `plastic` lit by the scene's `ambient`
    /// and `[specular]`, [`Surface::scene_default`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface>,
    /// The object's own shading rate, RenderMan's `ShadingRate` attribute
    /// (default: the scene's `shading_rate`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shading_rate: Option<f32>,
    /// Displacement mapping (default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement: Option<DisplacementDesc>,
    /// Placement at shutter close (default: `transform`, not moving). The
    /// object moves from `transform` to this one, interpolated as
    /// translation, rotation (slerp) and scale.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transform_close: Option<Transform>,
    /// Keys of the placement (`[[objects.keys]]`, default none): the
    /// object's translation, rotation and scale over time; the values no
    /// key gives stay `transform`'s. See [`Scene::frame`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub keys: Vec<TransformKey>,
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

impl SceneObject {
    /// The object `model` with every other key at its scene-file default,
    /// as `[[objects]]` with only `model` reads.
    pub fn new(model: impl Into<String>) -> SceneObject {
        SceneObject {
            model: model.into(),
            subdivision: None,
            transform: Transform::default(),
            color: default_color(),
            surface: None,
            shading_rate: None,
            displacement: None,
            transform_close: None,
            keys: Vec::new(),
            sides: default_sides(),
            reverse_orientation: false,
        }
    }
}

/// The subdivision scheme of an object's mesh (`subdivision`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Subdivision {
    /// `"catmull-clark"`: the smooth limit surface ([`Scheme::CatmullClark`]).
    #[default]
    CatmullClark,
    /// `"bilinear"`: every face flat ([`Scheme::Bilinear`]).
    Bilinear,
}

impl Subdivision {
    /// The mesh scheme.
    pub fn scheme(self) -> Scheme {
        match self {
            Subdivision::CatmullClark => Scheme::CatmullClark,
            Subdivision::Bilinear => Scheme::Bilinear,
        }
    }
}

/// Whether `model` names an OBJ file (extension `.obj`, any case): the
/// models that have a mesh to subdivide.
pub fn is_obj_model(model: &str) -> bool {
    std::path::Path::new(model)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}

/// Where an object's model comes from.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ModelSource {
    /// The embedded teapot ([`Model::teapot`]).
    Teapot,
    /// A model file.
    File(PathBuf),
}
