//! A scene's values for a shader's parameters, typed against the shader's
//! `Parameters` and packed into its slots.

use std::collections::BTreeMap;

use super::{ParameterKind, ShaderValue, ShadowDesc, SurfaceShader, SurfaceShaderError};
use crate::texture::{ColorSpace, TextureDesc, Wrap};

/// A value the scene gives that the shader has no parameter for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParameterWarning {
    /// The name given.
    pub name: String,
}

/// The slots of `shader`'s parameters (one `[f32; 4]` each, in declaration
/// order): `given`'s values where it has them, the shader's defaults
/// elsewhere. Names the shader does not declare come back as warnings.
/// A texture parameter's file is handed to `texture` (with the
/// parameter's name), which gives the texture's index; a shadow map
/// parameter's to `shadow`, which gives its slot
/// ([`super::ShadowSlot::to_slot`]).
pub fn pack_parameters(
    shader: &SurfaceShader,
    given: &BTreeMap<String, ShaderValue>,
    mut texture: impl FnMut(&str, &TextureDesc) -> Result<u32, SurfaceShaderError>,
    mut shadow: impl FnMut(&str, &ShadowDesc) -> Result<[f32; 4], SurfaceShaderError>,
) -> Result<(Vec<[f32; 4]>, Vec<ParameterWarning>), SurfaceShaderError> {
    let mut slots: Vec<[f32; 4]> = shader.parameters.iter().map(|p| p.default).collect();
    let mut warnings = Vec::new();
    for (name, value) in given {
        match shader.parameter(name) {
            Some((slot, parameter)) if parameter.kind == ParameterKind::Texture => {
                let desc = match value {
                    ShaderValue::Text(file) => TextureDesc::new(file),
                    ShaderValue::Texture(desc) => desc.clone(),
                    _ => {
                        return Err(SurfaceShaderError::Value {
                            name: name.clone(),
                            expected: "TextureId (the texture's file, or a texture table)",
                            given: describe(value),
                        });
                    }
                };
                slots[slot] = [f32::from_bits(texture(name, &desc)?), 0.0, 0.0, 0.0];
            }
            Some((slot, parameter)) if parameter.kind == ParameterKind::Shadow => {
                let desc = shadow_desc(value).ok_or_else(|| SurfaceShaderError::Value {
                    name: name.clone(),
                    expected: "ShadowId (the shadow map's file, or a shadow table)",
                    given: describe(value),
                })?;
                if let Some(problem) = desc.filter().problem() {
                    return Err(SurfaceShaderError::ShadowFilter {
                        name: name.clone(),
                        problem,
                    });
                }
                slots[slot] = shadow(name, &desc)?;
            }
            Some((slot, parameter)) => {
                slots[slot] =
                    slot_of(parameter.kind, value).ok_or_else(|| SurfaceShaderError::Value {
                        name: name.clone(),
                        expected: parameter.kind.wgsl(),
                        given: describe(value),
                    })?
            }
            None => warnings.push(ParameterWarning { name: name.clone() }),
        }
    }
    Ok((slots, warnings))
}

/// `value` as a shadow map: a file, a shadow table, or a table of the
/// file alone (which reads as a texture table with the defaults).
fn shadow_desc(value: &ShaderValue) -> Option<ShadowDesc> {
    match value {
        ShaderValue::Text(file) => Some(ShadowDesc::new(file)),
        ShaderValue::Shadow(desc) => Some(desc.clone()),
        ShaderValue::Texture(TextureDesc {
            path,
            color_space: ColorSpace::Auto,
            wrap_s: Wrap::Periodic,
            wrap_t: Wrap::Periodic,
        }) => Some(ShadowDesc::new(path)),
        _ => None,
    }
}

/// `value` as a slot of `kind`, if it fits.
fn slot_of(kind: ParameterKind, value: &ShaderValue) -> Option<[f32; 4]> {
    let mut slot = [0.0f32; 4];
    match (kind, value) {
        (ParameterKind::Float, ShaderValue::Number(x)) => slot[0] = finite(*x)?,
        (ParameterKind::Int, ShaderValue::Number(x)) => {
            slot[0] = f32::from_bits(integral::<i32>(*x)? as u32);
        }
        (ParameterKind::Uint, ShaderValue::Number(x)) => {
            slot[0] = f32::from_bits(integral::<u32>(*x)?)
        }
        (ParameterKind::Bool, ShaderValue::Bool(b)) => slot[0] = f32::from(u8::from(*b)),
        (
            ParameterKind::Vec2 | ParameterKind::Vec3 | ParameterKind::Vec4,
            ShaderValue::Numbers(xs),
        ) => {
            let n = match kind {
                ParameterKind::Vec2 => 2,
                ParameterKind::Vec3 => 3,
                _ => 4,
            };
            if xs.len() != n {
                return None;
            }
            for (word, &x) in slot.iter_mut().zip(xs) {
                *word = finite(x)?;
            }
        }
        _ => return None,
    }
    Some(slot)
}

/// `x` as a finite f32.
fn finite(x: f64) -> Option<f32> {
    let y = x as f32;
    y.is_finite().then_some(y)
}

/// `x` as an integer of type `T`, if it is one exactly.
fn integral<T: TryFrom<i64>>(x: f64) -> Option<T> {
    if x.fract() != 0.0 || !x.is_finite() || x.abs() > 9.0e15 {
        return None;
    }
    T::try_from(x as i64).ok()
}

/// What the scene gave, for messages.
fn describe(value: &ShaderValue) -> String {
    match value {
        ShaderValue::Bool(b) => format!("the boolean {b}"),
        ShaderValue::Number(x) => format!("the number {x}"),
        ShaderValue::Numbers(xs) => format!("{} numbers", xs.len()),
        ShaderValue::Text(text) => format!("the string {text:?}"),
        ShaderValue::Texture(desc) => format!("the texture {}", desc.path.display()),
        ShaderValue::Shadow(desc) => format!("the shadow map {}", desc.path.display()),
    }
}
