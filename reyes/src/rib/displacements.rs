//! `Displacement` and `Attribute "displacementbound"`: RenderMan's `bumpy`
//! runs as the built-in displacement shader `builtin:bumpy`, any other
//! name as the WGSL displacement shader `name.wgsl` beside the RIB file
//! (docs/shaders.md), and the bound is carried into world units.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DMat3, DMat4};

use super::interp::{Interp, camera_to_world};
use super::parser::Value;
use super::shader_files::ShaderRequest;
use super::state::{self, Param};
use super::surfaces::{shader_value, texture_name, wgsl_shader};
use crate::displacement::DisplacementDesc;
use crate::displacement::desc::SOURCE_SHADER;
use crate::scene::ShaderValue;
use crate::surface_shader::ShaderKind;
use crate::surface_shader::builtin::BUMPY;
use crate::texture::{ColorSpace, TextureDesc};

/// The parameters `bumpy` has (RenderMan Interface 3.2, appendix A).
const BUMPY_PARAMETERS: [&str; 2] = ["Km", "texturename"];

/// The largest factor by which the linear part of `m` stretches a length
/// (its largest singular value), by power iteration on `MᵀM`; never below
/// the true value by more than rounding, so a bound scaled by it still
/// bounds.
pub(super) fn stretch(m: DMat4) -> f64 {
    let linear = DMat3::from_mat4(m);
    let gram = linear.transpose() * linear;
    let mut x = glam::DVec3::new(1.0, 0.7, 0.3).normalize();
    let mut largest = 0.0;
    for _ in 0..64 {
        let y = gram * x;
        let length = y.length();
        if !(length.is_finite() && length > 0.0) {
            break;
        }
        largest = length;
        x = y / length;
    }
    // A margin for the iteration's slow convergence when the two largest
    // singular values are close: the Frobenius norm bounds from above.
    let frobenius = (gram.x_axis.x + gram.y_axis.y + gram.z_axis.z).sqrt();
    (largest.sqrt() * (1.0 + 1e-6))
        .min(frobenius)
        .max(largest.sqrt())
}

impl Interp {
    /// `Attribute "displacementbound" "sphere" r "coordinatesystem" space`:
    /// the bound in the renderer's world units, from `space` (`"object"`,
    /// the default, and `"shader"`: the current transform; `"world"`;
    /// `"camera"` or `"current"`; or a named `CoordinateSystem`).
    pub(super) fn displacement_bound(
        &mut self,
        radius: f64,
        space: Option<&str>,
        file: &Path,
        line: usize,
    ) {
        let camera = camera_to_world() * self.camera.unwrap_or(DMat4::IDENTITY);
        let to_world = match space.unwrap_or("object") {
            "object" | "shader" => camera * self.xf.open,
            "world" => camera,
            "camera" | "current" => camera_to_world(),
            name => match self.coordsys.get(name) {
                Some(xf) => camera * xf.open,
                None => {
                    self.warn(
                        file,
                        line,
                        format!(
                            "Attribute \"displacementbound\": unknown coordinate system {:?}; the bound is taken in object space",
                            crate::input::excerpt(name)
                        ),
                    );
                    camera * self.xf.open
                }
            },
        };
        self.attrs.displacement_bound = Some(radius * stretch(to_world));
    }

    /// `Displacement "shader" ...`: `bumpy` (with a texture) or a WGSL
    /// displacement shader beside the RIB file; `null` and unknown shaders
    /// leave the surface undisplaced (the latter with a warning).
    pub(super) fn displacement(
        &mut self,
        v: &[Value],
        file: &Path,
        line: usize,
    ) -> Result<(), String> {
        let (args, params, _) = state::split_params(v, 1, &self.declared)?;
        let shader = state::arg_str(&args, 0, "the shader")?.to_owned();
        let shown = crate::input::excerpt(&shader);
        self.attrs.displacement = match shader.as_str() {
            "" | "null" => None,
            "bumpy" => self.bumpy(&params, file, line)?,
            _ => match wgsl_shader(&shader, file) {
                Some(path) => {
                    let given = self.shader_parameters(&params);
                    let parameters = self.shader_parameters_checked(
                        ShaderRequest {
                            request: "Displacement",
                            shader: &shader,
                            path: &path,
                            kind: ShaderKind::Displacement,
                        },
                        given,
                        file,
                        line,
                    )?;
                    Some(DisplacementDesc {
                        file: Some(path),
                        parameters,
                        ..shader_desc()
                    })
                }
                None => {
                    self.warn(
                        file,
                        line,
                        format!(
                            "Displacement {shown:?} is not supported (no {}.wgsl beside the RIB file); the surface is not displaced",
                            crate::input::excerpt(shader.trim_end_matches(".wgsl"))
                        ),
                    );
                    None
                }
            },
        };
        Ok(())
    }

    /// `Displacement "bumpy"`: the built-in shader, its texture read as
    /// linear data (heights, not colours); without a texture it displaces
    /// nothing, as RenderMan's does.
    fn bumpy(
        &mut self,
        params: &[Param],
        file: &Path,
        line: usize,
    ) -> Result<Option<DisplacementDesc>, String> {
        for p in params {
            if !BUMPY_PARAMETERS.contains(&p.name.as_str()) {
                self.warn_once(
                    &format!("#displacement-param bumpy {}", p.name),
                    file,
                    line,
                    format!(
                        "Displacement \"bumpy\" has no parameter {:?}; ignored",
                        crate::input::excerpt(&p.name)
                    ),
                );
            }
        }
        let Some(name) = texture_name(params) else {
            self.warn_once(
                "#displacement-bumpy-no-texture",
                file,
                line,
                "Displacement \"bumpy\" without a \"texturename\" displaces nothing".into(),
            );
            return Ok(None);
        };
        let km = match params.iter().find(|p| p.name == "Km") {
            None => 1.0,
            Some(p) => match p.value.nums().as_deref() {
                Some([km]) if km.is_finite() => *km,
                _ => return Err("Displacement \"bumpy\": \"Km\" takes one finite number".into()),
            },
        };
        let texture = TextureDesc {
            color_space: ColorSpace::Linear,
            ..self.texture(name, file)
        };
        Ok(Some(DisplacementDesc {
            file: Some(BUMPY.into()),
            parameters: BTreeMap::from([
                ("Km".to_owned(), ShaderValue::Number(km)),
                ("texturename".to_owned(), ShaderValue::Texture(texture)),
            ]),
            ..shader_desc()
        }))
    }

    /// A user shader's parameters from the request's, textures made by
    /// `MakeTexture` read through their pictures with their wrap modes.
    pub(super) fn shader_parameters(&self, params: &[Param]) -> BTreeMap<String, ShaderValue> {
        params
            .iter()
            .filter_map(|p| {
                let value = match shader_value(&p.value)? {
                    ShaderValue::Text(name) => match self.made_textures.get(&name) {
                        Some(made) => ShaderValue::Texture(made.clone()),
                        None => ShaderValue::Text(name),
                    },
                    other => other,
                };
                Some((p.name.clone(), value))
            })
            .collect()
    }
}

/// A shader displacement with no file yet, scale 1 and no bound (the
/// primitive's `displacementbound` fills it in, see `convert`).
fn shader_desc() -> DisplacementDesc {
    DisplacementDesc {
        source: SOURCE_SHADER.to_owned(),
        scale: 1.0,
        bound: None,
        tiling: 1.0,
        wgsl: None,
        file: None,
        parameters: BTreeMap::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stretch_is_the_largest_singular_value() {
        let m = DMat4::from_scale(glam::DVec3::new(2.0, -3.0, 0.5));
        assert!((stretch(m) - 3.0).abs() < 1e-5, "{}", stretch(m));
        let rotated = DMat4::from_rotation_z(0.7) * m * DMat4::from_rotation_x(1.1);
        assert!(
            (stretch(rotated) - 3.0).abs() < 1e-5,
            "{}",
            stretch(rotated)
        );
        // A shear stretches more than any column's length.
        let shear = DMat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        let golden = (1.0 + 5f64.sqrt()) / 2.0;
        assert!(stretch(shear) >= golden - 1e-9, "{}", stretch(shear));
        assert!(stretch(shear) < golden + 1e-5);
    }
}
