//! The checks on a user's surface shader, made on naga's IR of the user's
//! source followed by the shader interface (with the renderer's side
//! stubbed out), and the reflection of its `Parameters` and `DEFAULTS`.
//! The user's text comes first, so naga's line numbers are the user's own.

use naga::{Expression, Handle, Literal, Module, Scalar, ScalarKind, TypeInner, VectorSize};

use super::{ParameterKind, ShaderKind, ShaderParameter, ShadowSlot, SurfaceShaderError};
use crate::params::MAX_SPECULAR_EXPONENT;
use crate::user_wgsl::{self, UserWgslError};

/// The name of the function a surface shader defines.
pub const ENTRY: &str = "surface";
/// The name of the function a displacement shader defines.
pub const DISPLACEMENT_ENTRY: &str = "displacement";
/// The name of its parameter struct.
pub const PARAMETERS: &str = "Parameters";
/// The name of the constant holding the parameters' defaults.
pub const DEFAULTS: &str = "DEFAULTS";
/// The id a `TextureId` parameter holds when the scene gives no texture:
/// past every texture, so that it reads (0, 0, 0, 0).
pub const NO_TEXTURE: u32 = u32::MAX;

/// The pure helpers, noise, the interface and its stubbed host side: what
/// a user shader may use besides WGSL's built-ins.
pub fn interface_wgsl() -> String {
    format!(
        "\n// ---- the surface shader interface\nconst MAX_SPECULAR_EXPONENT: f32 = {MAX_SPECULAR_EXPONENT:?};\n{}{}{}{}{}",
        include_str!("../../../shaders/reyes/library_math.wgsl"),
        crate::noise::noise_wgsl(),
        include_str!("../../../shaders/reyes/surface_api.wgsl"),
        include_str!("../../../shaders/reyes/surface_api_shadow.wgsl"),
        include_str!("../../../shaders/reyes/surface_host_stub.wgsl"),
    )
}

/// What the check learns of a shader.
#[derive(Debug)]
pub(super) struct Checked {
    /// Its parameters, in declaration order (empty without `Parameters`).
    pub(super) parameters: Vec<ShaderParameter>,
    /// Whether the entry takes the parameters as its second argument.
    pub(super) takes_parameters: bool,
    /// What the shader computes: the function it defines says.
    pub(super) kind: ShaderKind,
}

/// Checks `source` against the interface.
pub(super) fn check(source: &str) -> Result<Checked, SurfaceShaderError> {
    user_wgsl::check_statement_sizes(source)?;
    user_wgsl::check_directives(source)?;
    let text = format!("{source}\n{}", interface_wgsl());
    let user_end = source.len();
    let module = user_wgsl::parse(&text).map_err(|e| in_user_text(e, source))?;
    user_wgsl::check_globals(&module, &text, user_end)?;
    user_wgsl::check_memory(&module, &text, user_end)?;
    let defined = |name: &str| {
        module.functions.iter().find(|(handle, f)| {
            f.name.as_deref() == Some(name)
                && span_start(module.functions.get_span(*handle)) < user_end
        })
    };
    let (kind, entry) = match (defined(ENTRY), defined(DISPLACEMENT_ENTRY)) {
        (Some((_, entry)), None) => (ShaderKind::Surface, entry),
        (None, Some((_, entry))) => (ShaderKind::Displacement, entry),
        (Some(_), Some(_)) => return Err(SurfaceShaderError::TwoEntries),
        (None, None) => return Err(SurfaceShaderError::MissingEntry),
    };
    let parameters_type = module.types.iter().find(|(handle, ty)| {
        ty.name.as_deref() == Some(PARAMETERS)
            && span_start(module.types.get_span(*handle)) < user_end
    });
    let named = |ty: Handle<naga::Type>, name: &str| module.types[ty].name.as_deref() == Some(name);
    let signature = SurfaceShaderError::Signature { kind };
    let arguments: Vec<_> = entry.arguments.iter().map(|a| a.ty).collect();
    let takes_parameters = match (arguments.as_slice(), parameters_type) {
        ([ctx], _) if named(*ctx, "ShadingContext") => false,
        ([ctx, params], Some((parameters, _)))
            if named(*ctx, "ShadingContext") && *params == parameters =>
        {
            true
        }
        _ => return Err(signature),
    };
    let returns = entry.result.as_ref().map(|r| &module.types[r.ty]);
    let returns_right = match kind {
        ShaderKind::Surface => {
            returns.is_some_and(|ty| ty.name.as_deref() == Some("SurfaceOutput"))
        }
        ShaderKind::Displacement => returns.is_some_and(|ty| {
            ty.inner
                == TypeInner::Vector {
                    size: VectorSize::Tri,
                    scalar: Scalar::F32,
                }
        }),
    };
    if !returns_right {
        return Err(signature);
    }
    user_wgsl::check_barriers(&module, &text)?;
    user_wgsl::validate(&module, &text).map_err(|e| in_user_text(e, source))?;
    let parameters = match parameters_type {
        Some((handle, _)) => reflect(&module, handle, &text)?,
        None => Vec::new(),
    };
    Ok(Checked {
        parameters,
        takes_parameters,
        kind,
    })
}

fn span_start(span: naga::Span) -> usize {
    span.to_range().map_or(usize::MAX, |r| r.start)
}

/// An error located past the user's text lies in the interface: most
/// likely the user redefined one of its names.
fn in_user_text(error: UserWgslError, source: &str) -> SurfaceShaderError {
    let user_lines = source.lines().count() as u32;
    match error {
        UserWgslError::Invalid { line, message, .. } if line > user_lines => {
            SurfaceShaderError::Interface { message }
        }
        other => other.into(),
    }
}

/// The fields of `Parameters` with their defaults from `DEFAULTS` (zero
/// without it).
fn reflect(
    module: &Module,
    parameters: Handle<naga::Type>,
    text: &str,
) -> Result<Vec<ShaderParameter>, SurfaceShaderError> {
    let TypeInner::Struct { members, .. } = &module.types[parameters].inner else {
        return Err(SurfaceShaderError::ParametersNotStruct);
    };
    let line = module.types.get_span(parameters).location(text).line_number;
    let mut out = Vec::with_capacity(members.len());
    for member in members {
        let name = member.name.clone().unwrap_or_default();
        let kind =
            parameter_kind(module, member.ty).ok_or_else(|| SurfaceShaderError::ParameterType {
                name: name.clone(),
                line,
            })?;
        // A texture the scene does not give reads nothing: an id past
        // every texture reads (0, 0, 0, 0), where id 0 would be another
        // parameter's texture. Likewise a shadow map: no map, no shadow.
        let default = match kind {
            ParameterKind::Texture => [f32::from_bits(NO_TEXTURE), 0.0, 0.0, 0.0],
            ParameterKind::Shadow => ShadowSlot::NONE.to_slot(),
            _ => [0.0; 4],
        };
        out.push(ShaderParameter {
            name,
            kind,
            default,
        });
    }
    let defaults = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(DEFAULTS));
    if let Some((handle, constant)) = defaults {
        let line = module.constants.get_span(handle).location(text).line_number;
        let not_literal = || SurfaceShaderError::Defaults { line };
        if constant.ty != parameters {
            return Err(not_literal());
        }
        let Expression::Compose { components, .. } = resolve(module, constant.init) else {
            return Err(not_literal());
        };
        for (parameter, &component) in out.iter_mut().zip(components) {
            let value = slot_value(module, component).ok_or_else(not_literal)?;
            // A file comes from the scene alone.
            if !matches!(
                parameter.kind,
                ParameterKind::Texture | ParameterKind::Shadow
            ) {
                parameter.default = value;
            }
        }
    }
    Ok(out)
}

/// The kind of a parameter field of type `ty`, if parameters may have it.
fn parameter_kind(module: &Module, ty: Handle<naga::Type>) -> Option<ParameterKind> {
    let float = Scalar::F32;
    match module.types[ty].inner {
        TypeInner::Scalar(s) if s == float => Some(ParameterKind::Float),
        TypeInner::Scalar(Scalar {
            kind: ScalarKind::Sint,
            width: 4,
        }) => Some(ParameterKind::Int),
        TypeInner::Scalar(Scalar {
            kind: ScalarKind::Uint,
            width: 4,
        }) => Some(ParameterKind::Uint),
        TypeInner::Scalar(Scalar {
            kind: ScalarKind::Bool,
            ..
        }) => Some(ParameterKind::Bool),
        TypeInner::Struct { .. } if module.types[ty].name.as_deref() == Some("TextureId") => {
            Some(ParameterKind::Texture)
        }
        TypeInner::Struct { .. } if module.types[ty].name.as_deref() == Some("ShadowId") => {
            Some(ParameterKind::Shadow)
        }
        TypeInner::Vector { size, scalar } if scalar == float => Some(match size {
            VectorSize::Bi => ParameterKind::Vec2,
            VectorSize::Tri => ParameterKind::Vec3,
            VectorSize::Quad => ParameterKind::Vec4,
        }),
        _ => None,
    }
}

/// The global expression `handle`, through named constants.
fn resolve(module: &Module, handle: Handle<Expression>) -> &Expression {
    match &module.global_expressions[handle] {
        Expression::Constant(c) => resolve(module, module.constants[*c].init),
        other => other,
    }
}

/// The slot (four words, as f32 bits) of a constant scalar or vector.
fn slot_value(module: &Module, handle: Handle<Expression>) -> Option<[f32; 4]> {
    let mut slot = [0.0f32; 4];
    match resolve(module, handle) {
        Expression::Literal(literal) => slot[0] = literal_bits(*literal)?,
        Expression::ZeroValue(_) => {}
        Expression::Splat { size, value } => {
            let value = slot_value(module, *value)?[0];
            slot[..*size as usize].fill(value);
        }
        Expression::Compose { components, .. } => {
            if components.len() > 4 {
                return None;
            }
            for (word, &component) in slot.iter_mut().zip(components) {
                *word = slot_value(module, component)?[0];
            }
        }
        _ => return None,
    }
    Some(slot)
}

/// A literal as the f32 word its slot stores (integers by their bits).
fn literal_bits(literal: Literal) -> Option<f32> {
    Some(match literal {
        Literal::F32(x) => x,
        Literal::AbstractFloat(x) => x as f32,
        Literal::I32(x) => f32::from_bits(x as u32),
        Literal::U32(x) => f32::from_bits(x),
        Literal::AbstractInt(x) => f32::from_bits(i32::try_from(x).ok()? as u32),
        Literal::Bool(b) => f32::from(u8::from(b)),
        _ => return None,
    })
}
