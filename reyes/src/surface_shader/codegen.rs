//! What the megakernel compiles in for a frame's user surface shaders: each
//! shader's text with its names prefixed, a loader of its parameters from
//! the `shader_parameters` buffer, and `user_surface`, which dispatches on
//! the object's shader index. A frame without user shaders gets only the
//! fallback `user_surface`.

use std::fmt::Write as _;
use std::sync::Arc;

use super::rename::{module_scope_names, prefix_names};
use super::{ENTRY, PARAMETERS, ParameterKind, SurfaceShader};

/// The prefix of shader `index`'s names in the megakernel.
fn prefix(index: usize) -> String {
    format!("surface{index}_")
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
    }
}

/// The library text for `shaders`, in index order (shader `k` is what an
/// object with `user_shader = k` runs).
pub fn megakernel_wgsl(shaders: &[Arc<SurfaceShader>]) -> String {
    let mut out = String::from(
        "// ------------------------------------------------------------ user surface shaders\n",
    );
    let mut dispatch = String::new();
    for (index, shader) in shaders.iter().enumerate() {
        let prefix = prefix(index);
        let names = module_scope_names(&shader.source);
        let _ = writeln!(
            out,
            "\n// ---- shader {index}: {}\n{}",
            shader.path.display(),
            prefix_names(&shader.source, &names, &prefix).trim_end()
        );
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
            format!("{prefix}{ENTRY}(ctx, {prefix}load_parameters(base))")
        } else {
            format!("{prefix}{ENTRY}(ctx)")
        };
        let _ = write!(
            dispatch,
            "        case {index}u: {{\n            out = {call};\n        }}\n"
        );
    }
    let _ = write!(
        out,
        "\n// The user shader `index` of an object, its parameters at `base`.\nfn user_surface(index: u32, ctx: ShadingContext, base: u32) -> SurfaceOutput {{\n    var out = constant(ctx);\n    switch index {{\n{dispatch}        default: {{}}\n    }}\n    return out;\n}}\n"
    );
    out
}
