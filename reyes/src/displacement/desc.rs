//! The `[objects.displacement]` table of a scene file: what it may say,
//! how it is checked, and how it becomes a [`PreparedDisplacement`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::DisplacementError;
use super::height_map::HeightMap;
use super::sines::SINES_MAX_HEIGHT;
use super::{HeightSource, PreparedDisplacement};
use crate::params::MAX_DISPLACEMENT_TILING;

/// `source` value of the embedded height map.
pub const SOURCE_BUMPS: &str = "bumps";
/// `source` value of the built-in procedural heights.
pub const SOURCE_SINES: &str = "sines";
/// `source` value of a user WGSL function (given in `wgsl`).
pub const SOURCE_WGSL: &str = "wgsl";
/// `source` value of a displacement shader (its file in `file`).
pub const SOURCE_SHADER: &str = "shader";
/// `source` value of a grey PNG height map named by `file` (a path that
/// need not be UTF-8, as a `source` string must).
pub const SOURCE_IMAGE: &str = "image";
pub use crate::user_wgsl::USER_FUNCTION_NAME;

/// An object's displacement as written in a scene file:
///
/// ```toml
/// [objects.displacement]
/// source = "bumps"     # "bumps", "sines", "wgsl", "shader", "image", or the path of a grey PNG
/// scale = 0.05         # world units per unit of height (negative: inwards)
/// bound = 0.05         # optional: default |scale| * max height
/// tiling = 2.0         # optional: source repeats per patch (default 1)
/// # wgsl = "fn displacement_user(u: f32, v: f32) -> f32 { ... }"   # for source = "wgsl"
/// # file = "ripples.wgsl"            # for source = "shader" (or a PNG for "image")
/// # parameters = { Km = 0.02 }       # the shader's parameters
/// ```
///
/// A displacement shader (`source = "shader"`, docs/shaders.md) computes
/// the displaced point itself; `scale` (default 1) multiplies its offset,
/// `P + scale * (displacement(ctx) - P)`, and `tiling` does not apply.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisplacementDesc {
    /// `"bumps"` (the embedded height map), `"sines"` (built-in procedural
    /// bumps), `"wgsl"` (the function in [`DisplacementDesc::wgsl`]),
    /// `"shader"` or `"image"` (the file in [`DisplacementDesc::file`]), or
    /// the path of an 8/16-bit grey PNG (relative to the scene file's
    /// directory; write `./sines` for a file of that name).
    pub source: String,
    /// World units of displacement per unit of height, along the surface
    /// normal `dP/du x dP/dv` (default 1). Must be finite; may be negative
    /// or zero. For a shader, the factor on its offset.
    #[serde(default = "default_scale")]
    pub scale: f32,
    /// The displacement bound in world units (>= 0). Default: `|scale|` times
    /// the source's largest `|height|`. Required for `"wgsl"`, whose heights
    /// are unknown to the host.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bound: Option<f32>,
    /// How many times the source repeats across each input patch, in
    /// `(0, 1024]` (default 1). Integers keep seams between patches continuous.
    #[serde(default = "default_tiling")]
    pub tiling: f32,
    /// The WGSL of `fn displacement_user(u: f32, v: f32) -> f32` (source `"wgsl"` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wgsl: Option<String>,
    /// The displacement shader's file (source `"shader"`; `builtin:bumpy`
    /// names the standard `bumpy`) or the grey PNG height map (source
    /// `"image"`), relative to the scene file's directory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<PathBuf>,
    /// The shader's parameters by name (source `"shader"` only).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, crate::surface_shader::ShaderValue>,
}

fn default_tiling() -> f32 {
    1.0
}

fn default_scale() -> f32 {
    1.0
}

/// The shader an object's displacement runs, as
/// [`DisplacementDesc::prepare`] hands it to the scene's shader table.
#[derive(Debug, Clone, Copy)]
pub enum ShaderSource<'a> {
    /// A displacement shader's file as the scene names it, with the
    /// object's parameters.
    File {
        /// The file (or `builtin:` name).
        file: &'a Path,
        /// The parameters by name.
        parameters: &'a BTreeMap<String, crate::surface_shader::ShaderValue>,
    },
    /// A WGSL height function, run as a displacement shader
    /// ([`super::height_shader`]).
    Height {
        /// WGSL defining `fn displacement_user(u: f32, v: f32) -> f32`.
        wgsl: &'a str,
        /// Its repetitions across each input patch.
        tiling: f32,
    },
}

/// The kind of `source`, parsed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SourceKind {
    /// The embedded bumps map.
    Bumps,
    /// Built-in sines.
    Sines,
    /// User WGSL.
    Wgsl,
    /// A displacement shader.
    Shader,
    /// A PNG file (not yet resolved against the scene's directory).
    Image(PathBuf),
}

/// A value problem in a displacement table: the field (relative to the
/// table, e.g. `scale`) and what is wrong. [`crate::scene::Scene::validate`]
/// turns it into a [`crate::scene::SceneError`] naming the object.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DescProblem {
    /// The field within `[objects.displacement]`.
    pub field: &'static str,
    /// What is wrong; `None` means "must be finite".
    pub reason: Option<String>,
}

impl DescProblem {
    fn not_finite(field: &'static str) -> Self {
        DescProblem {
            field,
            reason: None,
        }
    }

    fn invalid(field: &'static str, reason: impl Into<String>) -> Self {
        DescProblem {
            field,
            reason: Some(reason.into()),
        }
    }
}

impl DisplacementDesc {
    /// The kind of [`DisplacementDesc::source`].
    pub fn kind(&self) -> SourceKind {
        match self.source.as_str() {
            SOURCE_BUMPS => SourceKind::Bumps,
            SOURCE_SINES => SourceKind::Sines,
            SOURCE_WGSL => SourceKind::Wgsl,
            SOURCE_SHADER => SourceKind::Shader,
            // validate() refuses "image" without a file.
            SOURCE_IMAGE => SourceKind::Image(self.file.clone().unwrap_or_default()),
            path => SourceKind::Image(PathBuf::from(path)),
        }
    }

    /// Checks the values without reading files: `scale`, `bound` and
    /// `tiling` finite, `bound >= 0`, `0 < tiling <= 1024`, a non-empty
    /// `source`, `wgsl` given exactly when `source = "wgsl"` and then
    /// defining `displacement_user`, and a `bound` for `"wgsl"`.
    pub fn validate(&self) -> Result<(), DescProblem> {
        if !self.scale.is_finite() {
            return Err(DescProblem::not_finite("scale"));
        }
        if let Some(bound) = self.bound {
            if !bound.is_finite() {
                return Err(DescProblem::not_finite("bound"));
            }
            if bound < 0.0 {
                return Err(DescProblem::invalid("bound", "must be >= 0"));
            }
        }
        if !self.tiling.is_finite() {
            return Err(DescProblem::not_finite("tiling"));
        }
        if !(self.tiling > 0.0 && self.tiling <= MAX_DISPLACEMENT_TILING) {
            return Err(DescProblem::invalid(
                "tiling",
                format!("must be in (0, {MAX_DISPLACEMENT_TILING}]"),
            ));
        }
        if self.source.trim().is_empty() {
            return Err(DescProblem::invalid(
                "source",
                "must be \"bumps\", \"sines\", \"wgsl\", \"shader\", \"image\" or the path of a grey PNG",
            ));
        }
        let shader = self.kind() == SourceKind::Shader;
        if shader && self.file.is_none() {
            return Err(DescProblem::invalid(
                "file",
                "source = \"shader\" needs the shader's file in `file`",
            ));
        }
        let bounds_itself = self
            .file
            .as_deref()
            .is_some_and(crate::surface_shader::builtin::bounds_itself);
        if shader && self.bound.is_none() && !bounds_itself {
            return Err(DescProblem::invalid(
                "bound",
                "is required for source = \"shader\" (the host cannot know how far the shader moves points)",
            ));
        }
        let image_file = self.source == SOURCE_IMAGE;
        if image_file && self.file.is_none() {
            return Err(DescProblem::invalid(
                "file",
                "source = \"image\" needs the height map's path in `file`",
            ));
        }
        if !shader && !image_file && self.file.is_some() {
            return Err(DescProblem::invalid(
                "file",
                "is only used with source = \"shader\" or \"image\"",
            ));
        }
        if !shader && !self.parameters.is_empty() {
            return Err(DescProblem::invalid(
                "parameters",
                "are only used with source = \"shader\"",
            ));
        }
        match (self.kind(), &self.wgsl) {
            (SourceKind::Wgsl, None) => Err(DescProblem::invalid(
                "wgsl",
                "source = \"wgsl\" needs the function in `wgsl`",
            )),
            (SourceKind::Wgsl, Some(wgsl)) => {
                // On naga's IR of the function alone: its own line numbers,
                // the function found by name, nothing of the renderer's.
                crate::user_wgsl::check(wgsl)
                    .map_err(|e| DescProblem::invalid("wgsl", e.to_string()))?;
                if self.bound.is_none() {
                    return Err(DescProblem::invalid(
                        "bound",
                        "is required for source = \"wgsl\" (the host cannot know the function's largest height)",
                    ));
                }
                Ok(())
            }
            (_, Some(_)) => Err(DescProblem::invalid(
                "wgsl",
                "is only used with source = \"wgsl\"",
            )),
            (_, None) => Ok(()),
        }
    }

    /// The height-map PNG [`DisplacementDesc::prepare`] reads for this
    /// source with `base_dir`, if the source is a file.
    pub fn height_map_path(&self, base_dir: Option<&Path>) -> Option<PathBuf> {
        match self.kind() {
            SourceKind::Image(path) => Some(resolve_height_map(path, base_dir)),
            _ => None,
        }
    }

    /// Loads the source (reading a PNG relative to `base_dir`), computes the
    /// default bound and checks a declared one against the source's largest
    /// height. `mirrored` is whether the object's transform has a negative
    /// determinant (the scale is then negated, see
    /// [`PreparedDisplacement::scale`]). A shader source, and a WGSL height
    /// function (which runs as a displacement shader,
    /// [`super::height_shader`]), are added to the scene's shaders by
    /// `add_shader`, which also gives the bound a built-in shader knows for
    /// itself (per unit of scale) and sets the shader's orientation. Call
    /// [`DisplacementDesc::validate`] first.
    pub fn prepare(
        &self,
        base_dir: Option<&Path>,
        mirrored: bool,
        add_shader: impl FnOnce(
            ShaderSource<'_>,
        ) -> Result<(super::ShaderDisplacement, Option<f32>), DisplacementError>,
    ) -> Result<PreparedDisplacement, DisplacementError> {
        let (source, max_height) = match self.kind() {
            SourceKind::Bumps => {
                let map = HeightMap::bumps();
                let max = map.max_height;
                (HeightSource::Image(map), Some(max))
            }
            SourceKind::Sines => (HeightSource::Sines, Some(SINES_MAX_HEIGHT)),
            SourceKind::Wgsl => {
                let (shader, _) = add_shader(ShaderSource::Height {
                    wgsl: self.wgsl.as_deref().unwrap_or_default(),
                    tiling: self.tiling,
                })?;
                // The shader's N is the model's own normal, turned by a
                // mirroring transform as the scale of the other height
                // sources is, so the scale stays as written.
                return Ok(PreparedDisplacement {
                    source: HeightSource::Shader(shader),
                    scale: self.scale,
                    bound: self.bound_for(None)?,
                    tiling: 1.0,
                });
            }
            SourceKind::Shader => {
                let file = self.file.as_deref().unwrap_or(Path::new(""));
                let (shader, own_bound) = add_shader(ShaderSource::File {
                    file,
                    parameters: &self.parameters,
                })?;
                return Ok(PreparedDisplacement {
                    source: HeightSource::Shader(shader),
                    scale: self.scale,
                    bound: self.bound_for(own_bound)?,
                    tiling: 1.0,
                });
            }
            SourceKind::Image(path) => {
                let path = resolve_height_map(path, base_dir);
                let map = HeightMap::load(&path)?;
                let max = map.max_height;
                (HeightSource::Image(std::sync::Arc::new(map)), Some(max))
            }
        };
        Ok(PreparedDisplacement {
            source,
            scale: if mirrored { -self.scale } else { self.scale },
            bound: self.bound_for(max_height)?,
            tiling: self.tiling,
        })
    }

    /// The bound: the declared one, which must hold `|scale|` times the
    /// source's largest height when the host knows it, else that product.
    /// Without either (validate() requires a declared bound then), 0.
    fn bound_for(&self, max_height: Option<f32>) -> Result<f32, DisplacementError> {
        let needed = max_height.map(|max| self.scale.abs() * max);
        match (self.bound, needed) {
            (Some(bound), Some(needed)) if bound < needed => {
                Err(DisplacementError::BoundTooSmall { bound, needed })
            }
            (Some(bound), _) => Ok(bound),
            (None, Some(needed)) => Ok(needed),
            (None, None) => Ok(0.0),
        }
    }
}

/// A height map's `path` as read: relative to `base_dir` (the scene file's
/// directory) when it is relative and there is one.
fn resolve_height_map(path: PathBuf, base_dir: Option<&Path>) -> PathBuf {
    match base_dir {
        Some(dir) if path.is_relative() => dir.join(path),
        _ => path,
    }
}
