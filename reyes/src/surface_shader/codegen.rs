//! What the megakernel compiles in for a frame's user shaders: each
//! shader's text with its names prefixed, a loader of its parameters from
//! the parameter slots, and the dispatchers on the object's shader index:
//! `user_surface` over the surface shaders, `user_displacement` over the
//! displacement shaders. `DISPLACEMENT_SHADERS` says whether there are any
//! of the latter, so that a frame without them folds their call away. A
//! frame without user shaders gets only the fallbacks.

use std::fmt::Write as _;
use std::sync::Arc;

use super::rename::{module_scope_names, prefix_names};
use super::{PARAMETERS, ParameterKind, ShaderKind, SurfaceShader};

/// The prefix of shader `index`'s names in the megakernel.
fn prefix(index: usize, kind: ShaderKind) -> String {
    format!("{}{index}_", kind.name())
}

/// The WGSL expression that reads slot `slot` of a block at `base` as `kind`.
fn load_expression(kind: ParameterKind, slot: usize) -> String {
    let word = format!("shader_parameter(base + {slot}u)");
    match kind {
        ParameterKind::Float => format!("{word}.x"),
        ParameterKind::Int => format!("bitcast<i32>({word}.x)"),
        ParameterKind::Uint => format!("bitcast<u32>({word}.x)"),
        ParameterKind::Bool => format!("{word}.x != 0.0"),
        ParameterKind::Vec2 => format!("{word}.xy"),
        ParameterKind::Vec3 => format!("{word}.xyz"),
        ParameterKind::Vec4 => word,
        ParameterKind::Texture => format!("TextureId(bitcast<u32>({word}.x))"),
        ParameterKind::Shadow => {
            format!("ShadowId(bitcast<u32>({word}.x), bitcast<u32>({word}.y), {word}.z, {word}.w)")
        }
    }
}

/// The library text for `shaders`, in index order (shader `k` is what an
/// object with `user_shader = k`, or `displace_shader = k`, runs).
pub fn megakernel_wgsl(shaders: &[Arc<SurfaceShader>]) -> String {
    let mut out = String::from(
        "// ------------------------------------------------------------ user shaders\n",
    );
    let mut surfaces = String::new();
    let mut displacements = String::new();
    for (index, shader) in shaders.iter().enumerate() {
        let prefix = prefix(index, shader.kind);
        let names = module_scope_names(&shader.source);
        let _ = writeln!(
            out,
            "\n// ---- {} shader {index}: {}\n{}",
            shader.kind.name(),
            shader.path.display(),
            prefix_names(&shader.source, &names, &prefix).trim_end()
        );
        let entry = shader.kind.entry();
        let call = if shader.takes_parameters {
            let fields: Vec<String> = shader
                .parameters
                .iter()
                .enumerate()
                .map(|(slot, p)| load_expression(p.kind, slot))
                .collect();
            let _ = writeln!(
                out,
                "\n// Shader {index}'s parameters from an object's slots (shader_parameter).\nfn {prefix}load_parameters(base: u32) -> {prefix}{PARAMETERS} {{\n    return {prefix}{PARAMETERS}({});\n}}",
                fields.join(", ")
            );
            format!("{prefix}{entry}(ctx, {prefix}load_parameters(base))")
        } else {
            format!("{prefix}{entry}(ctx)")
        };
        let dispatch = match shader.kind {
            ShaderKind::Surface => &mut surfaces,
            ShaderKind::Displacement => &mut displacements,
        };
        let _ = write!(
            dispatch,
            "        case {index}u: {{\n            out = {call};\n        }}\n"
        );
    }
    let _ = write!(
        out,
        "\n// The user surface shader `index` of an object, its parameters at `base`.\nfn user_surface(index: u32, ctx: ShadingContext, base: u32) -> SurfaceOutput {{\n    var out = constant(ctx);\n    switch index {{\n{surfaces}        default: {{}}\n    }}\n    return out;\n}}\n"
    );
    let _ = write!(
        out,
        "\n// Whether the frame has displacement shaders.\nconst DISPLACEMENT_SHADERS: bool = {};\n\n// The user displacement shader `index` of an object, its parameters at\n// `base`: the displaced P.\nfn user_displacement(index: u32, ctx: ShadingContext, base: u32) -> vec3<f32> {{\n    var out = ctx.P;\n    switch index {{\n{displacements}        default: {{}}\n    }}\n    return out;\n}}\n",
        !displacements.is_empty()
    );
    out
}
