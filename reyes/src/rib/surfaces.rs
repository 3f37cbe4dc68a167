//! `Surface`: RenderMan's standard surface shaders, per attribute block.
//!
//! Each primitive keeps the surface of its attribute block, and the scene
//! gives each object its own ([`crate::scene::Surface`]): `constant`,
//! `matte`, `metal`, `plastic`, `defaultsurface` (RenderMan's default for
//! geometry with no `Surface`) and `null` are rendered as the specification
//! defines them. `paintedplastic` and `shinymetal` with a `texturename`
//! run the built-in WGSL `paintedplastic` and `shinymetal`
//! (`crate::surface_shader::builtin`); without one they are `plastic` and
//! `metal`, which they then equal. Any other name is a user's WGSL
//! surface shader when `name.wgsl` lies beside the RIB file (its parameters
//! go to the shader's `Parameters`); otherwise it warns and renders as
//! `defaultsurface`. `docs/rib.md` lists what cannot be followed.

use std::path::Path;

use glam::DVec3;

use super::interp::Interp;
use super::parser::Value;
use super::shader_files::ShaderRequest;
use super::state::{self, Param};
use crate::scene::{ShaderValue, Surface};
use crate::surface_shader::ShaderKind;
use crate::texture::TextureDesc;

/// The smallest `roughness` used: the highlight's exponent `1 / roughness`
/// is at most `crate::shading::MAX_SPECULAR_EXPONENT`.
const MIN_ROUGHNESS: f64 = 1e-4;

/// The parameters each standard shader reads; `None` for other shaders.
fn known_params(shader: &str) -> Option<&'static [&'static str]> {
    Some(match shader {
        "constant" | "null" => &[],
        "matte" | "defaultsurface" => &["Ka", "Kd"],
        "metal" => &["Ka", "Ks", "roughness"],
        "shinymetal" => &["Ka", "Ks", "Kr", "roughness", "texturename"],
        "plastic" => &["Ka", "Kd", "Ks", "roughness", "specularcolor"],
        "paintedplastic" => &[
            "Ka",
            "Kd",
            "Ks",
            "roughness",
            "specularcolor",
            "texturename",
        ],
        _ => return None,
    })
}

/// The WGSL surface shader file a `Surface` request names: `name.wgsl` (or
/// `name` itself when it ends in `.wgsl`) in the directory of the RIB
/// file that makes the request, if it is there.
pub(super) fn wgsl_shader(name: &str, rib: &Path) -> Option<std::path::PathBuf> {
    let file = if name.ends_with(".wgsl") {
        name.to_owned()
    } else {
        format!("{name}.wgsl")
    };
    let path = rib.parent().unwrap_or(Path::new("")).join(file);
    path.is_file().then_some(path)
}

/// The `texturename` a `paintedplastic` request gives, if any (an empty
/// name is none, as in RenderMan).
pub(super) fn texture_name(params: &[Param]) -> Option<&str> {
    params
        .iter()
        .find(|p| p.name == "texturename")
        .and_then(|p| match &p.value {
            Value::Str(s) => Some(s.as_str()),
            Value::Strs(v) if v.len() == 1 => Some(v[0].as_str()),
            _ => None,
        })
        .filter(|name| !name.is_empty())
}

/// A RIB parameter value as a user shader's parameter value: one number,
/// several, or a string.
pub(super) fn shader_value(value: &Value) -> Option<ShaderValue> {
    Some(match value {
        Value::Num(n) => ShaderValue::Number(*n),
        Value::Nums(v) if v.len() == 1 => ShaderValue::Number(v[0]),
        Value::Nums(v) => ShaderValue::Numbers(v.clone()),
        Value::Str(s) => ShaderValue::Text(s.clone()),
        Value::Strs(v) if v.len() == 1 => ShaderValue::Text(v[0].clone()),
        _ => return None,
    })
}

impl Interp {
    /// The surface of a `Surface` request for `shader` with `params`.
    pub(super) fn surface(
        &mut self,
        shader: &str,
        params: &[Param],
        file: &Path,
        line: usize,
    ) -> Result<Surface, String> {
        let shown = crate::input::excerpt(shader);
        // An unknown shader warns below; its parameters are not judged.
        let known = known_params(shader);
        for p in params {
            if known.is_some_and(|k| !k.contains(&p.name.as_str())) {
                self.warn_once(
                    &format!("#surface-param {shader} {}", p.name),
                    file,
                    line,
                    format!(
                        "Surface {shown:?} has no parameter {:?}; ignored",
                        crate::input::excerpt(&p.name)
                    ),
                );
            }
        }
        let surface = match shader {
            "constant" => Surface::Constant,
            "null" => Surface::Null,
            "matte" => Surface::Matte {
                ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                kd: self.weight(params, "Kd", 1.0, &shown, file, line)?,
            },
            "defaultsurface" => Surface::DefaultSurface {
                ka: self.weight(params, "Ka", 0.2, &shown, file, line)?,
                kd: self.weight(params, "Kd", 0.8, &shown, file, line)?,
            },
            "shinymetal" if texture_name(params).is_some() => {
                let name = texture_name(params).unwrap_or_default();
                let picture = self.texture(name, file);
                let world = self.world_axes(file, line);
                let number = |x: f32| ShaderValue::Number(f64::from(x));
                let vector = |v: DVec3| ShaderValue::Numbers(v.to_array().to_vec());
                Surface::Wgsl {
                    file: crate::surface_shader::builtin::SHINY_METAL.into(),
                    parameters: [
                        (
                            "Ka",
                            number(self.weight(params, "Ka", 1.0, &shown, file, line)?),
                        ),
                        (
                            "Ks",
                            number(self.weight(params, "Ks", 1.0, &shown, file, line)?),
                        ),
                        (
                            "Kr",
                            number(self.weight(params, "Kr", 1.0, &shown, file, line)?),
                        ),
                        (
                            "roughness",
                            number(self.roughness(params, &shown, file, line)?),
                        ),
                        ("texturename", ShaderValue::Texture(picture.clone())),
                        ("world_x", vector(world[0])),
                        ("world_y", vector(world[1])),
                        ("world_z", vector(world[2])),
                    ]
                    .into_iter()
                    .map(|(k, v)| (k.to_owned(), v))
                    .collect(),
                }
            }
            // shinymetal without an environment map is metal exactly (its
            // environment() of "" is black).
            "metal" | "shinymetal" => Surface::Metal {
                ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                ks: self.weight(params, "Ks", 1.0, &shown, file, line)?,
                roughness: self.roughness(params, &shown, file, line)?,
            },
            "paintedplastic" if texture_name(params).is_some() => {
                let name = texture_name(params).unwrap_or_default();
                let picture = self.texture(name, file);
                let tint = self.tint(params, &shown, file, line)?;
                let number = |x: f32| ShaderValue::Number(f64::from(x));
                Surface::Wgsl {
                    file: crate::surface_shader::builtin::PAINTED_PLASTIC.into(),
                    parameters: [
                        (
                            "Ka",
                            number(self.weight(params, "Ka", 1.0, &shown, file, line)?),
                        ),
                        (
                            "Kd",
                            number(self.weight(params, "Kd", 0.5, &shown, file, line)?),
                        ),
                        (
                            "Ks",
                            number(self.weight(params, "Ks", 0.5, &shown, file, line)?),
                        ),
                        (
                            "roughness",
                            number(self.roughness(params, &shown, file, line)?),
                        ),
                        (
                            "specularcolor",
                            ShaderValue::Numbers(tint.to_array().map(f64::from).to_vec()),
                        ),
                        ("texturename", ShaderValue::Texture(picture.clone())),
                    ]
                    .into_iter()
                    .map(|(k, v)| (k.to_owned(), v))
                    .collect(),
                }
            }
            // paintedplastic without a texture is plastic exactly.
            "plastic" | "paintedplastic" => Surface::Plastic {
                ka: self.weight(params, "Ka", 1.0, &shown, file, line)?,
                kd: self.weight(params, "Kd", 0.5, &shown, file, line)?,
                ks: self.weight(params, "Ks", 0.5, &shown, file, line)?,
                roughness: self.roughness(params, &shown, file, line)?,
                specular_color: self.tint(params, &shown, file, line)?,
            },
            _ => match wgsl_shader(shader, file) {
                Some(path) => {
                    let given = self.shader_parameters(params);
                    let parameters = self.shader_parameters_checked(
                        ShaderRequest {
                            request: "Surface",
                            shader,
                            path: &path,
                            kind: ShaderKind::Surface,
                        },
                        given,
                        file,
                        line,
                    )?;
                    Surface::Wgsl {
                        file: path,
                        parameters,
                    }
                }
                None => {
                    self.warn(
                        file,
                        line,
                        format!(
                            "Surface {shown:?} is not supported (no {}.wgsl beside the RIB file); shading as \"defaultsurface\"",
                            crate::input::excerpt(shader.trim_end_matches(".wgsl"))
                        ),
                    );
                    Surface::DEFAULT_SURFACE
                }
            },
        };
        Ok(surface)
    }

    /// The texture a name stands for: the picture (and wrap modes)
    /// `MakeTexture` or `MakeLatLongEnvironment` made it from, else the file
    /// of that name beside the RIB file, periodic.
    pub(super) fn texture(&self, name: &str, file: &Path) -> TextureDesc {
        match self.made_textures.get(name) {
            Some(made) => made.clone(),
            None => TextureDesc::new(file.parent().unwrap_or(Path::new("")).join(name)),
        }
    }

    /// A weight (`Ka`, `Kd`, `Ks`): a negative one is taken as 0, with a
    /// warning (the standard shaders' terms only add light), as is one
    /// beyond `f32`.
    fn weight(
        &mut self,
        params: &[Param],
        name: &str,
        default: f64,
        shader: &str,
        file: &Path,
        line: usize,
    ) -> Result<f32, String> {
        let k = state::param_f(params, name, default)?;
        if !(k >= 0.0 && (k as f32).is_finite()) {
            self.warn(
                file,
                line,
                format!("Surface {shader:?}: {name} {k} is negative or beyond f32; using 0"),
            );
            return Ok(0.0);
        }
        Ok(k as f32)
    }

    fn roughness(
        &mut self,
        params: &[Param],
        shader: &str,
        file: &Path,
        line: usize,
    ) -> Result<f32, String> {
        let r = state::param_f(params, "roughness", 0.1)?;
        // NaN is below too.
        if r.is_nan() || r < MIN_ROUGHNESS {
            self.warn(
                file,
                line,
                format!(
                    "Surface {shader:?}: roughness {r} is below {MIN_ROUGHNESS}; using {MIN_ROUGHNESS}"
                ),
            );
            return Ok(MIN_ROUGHNESS as f32);
        }
        Ok((r as f32).min(f32::MAX))
    }

    /// `specularcolor`, each channel as a weight.
    fn tint(
        &mut self,
        params: &[Param],
        shader: &str,
        file: &Path,
        line: usize,
    ) -> Result<glam::Vec3, String> {
        let c = state::param_v3(params, "specularcolor", DVec3::ONE)?;
        let c32 = c.as_vec3();
        if !(c.min_element() >= 0.0 && c32.is_finite()) {
            self.warn(
                file,
                line,
                format!(
                    "Surface {shader:?}: specularcolor [{} {} {}] is negative or beyond f32; using white",
                    c.x, c.y, c.z
                ),
            );
            return Ok(glam::Vec3::ONE);
        }
        Ok(c32)
    }
}

/// Whether `surface` reads the lights (`ambient()`, `diffuse()` or
/// `specular()`).
pub(super) fn is_lit(surface: &Surface) -> bool {
    matches!(
        surface,
        Surface::Matte { .. } | Surface::Metal { .. } | Surface::Plastic { .. }
    )
}
