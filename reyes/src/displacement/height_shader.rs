//! A scene's height function (`source = "wgsl"`, `fn displacement_user(u:
//! f32, v: f32) -> f32`) run as a displacement shader: the user's text
//! followed by a `displacement` that moves `P` along the context's `N` by
//! the height at the tiled `(u, v)`. The function goes through the same
//! checks, the same renaming into the megakernel and the same isolation as
//! every displacement shader (docs/shaders.md), and a frame may hold as
//! many different ones as it has objects.

use std::path::{Path, PathBuf};

use crate::surface_shader::{
    CpuDisplacement, ShaderValue, ShadingContext, SurfaceShader, SurfaceShaderError,
};

use super::CpuHeight;

/// The name of the wrapper's one parameter: repetitions of the function
/// across each input patch ([`super::DisplacementDesc::tiling`]).
pub const TILING_PARAMETER: &str = "tiling";

/// Appended to the user's text: the displacement shader around it. The
/// user's lines keep their numbers, so errors name them as written.
const WRAPPER: &str = "
// reyes: the height function above, run as a displacement shader: P moves
// along N (the surface's own normal) by the height at the tiled (u, v).
struct Parameters {
    tiling: f32,
}

const DEFAULTS = Parameters(1.0);

fn displacement(ctx: ShadingContext, params: Parameters) -> vec3<f32> {
    return ctx.P + ctx.N * displacement_user(params.tiling * ctx.u, params.tiling * ctx.v);
}
";

/// How the names of height functions' shaders begin ([`shader_name`]).
pub const NAME_PREFIX: &str = "wgsl:";

/// The name the height function of scene object `object` goes by in the
/// frame's [`crate::surface_shader::ShaderTable`], in the megakernel's
/// text and in messages: where the scene gives it. Objects with equal
/// texts share the first one's shader
/// ([`crate::surface_shader::ShaderTable::add_made`]).
pub fn shader_name(object: usize) -> PathBuf {
    PathBuf::from(format!("{NAME_PREFIX}objects[{object}].displacement.wgsl"))
}

/// Whether the shader `name` is a height function's ([`shader_name`]).
pub fn is_height_shader(name: &Path) -> bool {
    name.to_string_lossy().starts_with(NAME_PREFIX)
}

/// The displacement shader of the height function `wgsl` of scene object
/// `object` (checked first on its own text by [`crate::user_wgsl::check`],
/// so that its errors name the function's lines and signature).
pub fn shader(wgsl: &str, object: usize) -> Result<SurfaceShader, SurfaceShaderError> {
    crate::user_wgsl::check(wgsl)?;
    SurfaceShader::from_source(&shader_name(object), format!("{wgsl}\n{WRAPPER}"))
}

/// The wrapper's parameter values for `tiling`.
pub fn parameters(tiling: f32) -> std::collections::BTreeMap<String, ShaderValue> {
    [(
        TILING_PARAMETER.to_owned(),
        ShaderValue::Number(tiling.into()),
    )]
    .into()
}

/// The CPU twin of a height function's shader, from the height function's
/// own Rust twin: the wrapper's arithmetic, operation for operation.
pub fn twin(height: CpuHeight) -> CpuDisplacement {
    CpuDisplacement::new(move |ctx: &ShadingContext, _host, slots| {
        let tiling = slots.first().map_or(1.0, |slot| slot[0]);
        ctx.p + ctx.n * (height.0)(tiling * ctx.u, tiling * ctx.v)
    })
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};

    use super::*;
    use crate::surface_shader::ShaderKind;
    use crate::user_wgsl::UserWgslError;

    const RIPPLES: &str =
        "fn displacement_user(u: f32, v: f32) -> f32 {\n    return sin(u) * v;\n}\n";

    #[test]
    fn a_height_function_becomes_a_displacement_shader_with_a_tiling() {
        let shader = shader(RIPPLES, 3).expect("checks");
        assert_eq!(shader.kind, ShaderKind::Displacement);
        assert!(shader.takes_parameters);
        let names: Vec<_> = shader.parameters.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, [TILING_PARAMETER]);
        assert_eq!(shader.parameters[0].default[0], 1.0);
        assert_eq!(shader.path, Path::new("wgsl:objects[3].displacement.wgsl"));
        assert!(is_height_shader(&shader.path));
        assert!(!is_height_shader(Path::new("ripples.wgsl")));
        // The user's text comes first, so its lines keep their numbers.
        assert!(shader.source.starts_with(RIPPLES));
    }

    #[test]
    fn errors_name_the_line_of_the_users_own_text() {
        let broken = "fn displacement_user(u: f32, v: f32) -> f32 {\n    return u + ;\n}\n";
        match shader(broken, 0) {
            Err(SurfaceShaderError::Wgsl(UserWgslError::Invalid { line, .. })) => {
                assert_eq!(line, 2)
            }
            other => panic!("expected an error at line 2, got {other:?}"),
        }
        let missing = "fn height(u: f32, v: f32) -> f32 { return u; }";
        assert!(matches!(
            shader(missing, 0),
            Err(SurfaceShaderError::Wgsl(UserWgslError::Missing { .. }))
        ));
    }

    /// A host with no lights, textures or maps: a height function uses
    /// none of them.
    struct Dark;

    impl crate::surface_shader::ShadingHost for Dark {
        fn ambient(&self) -> Vec3 {
            Vec3::ZERO
        }
        fn diffuse(&self, _: &ShadingContext, _: Vec3) -> Vec3 {
            Vec3::ZERO
        }
        fn specular(&self, _: &ShadingContext, _: Vec3, _: Vec3, _: f32) -> Vec3 {
            Vec3::ZERO
        }
        fn light_count(&self) -> u32 {
            0
        }
        fn light(&self, _: u32, _: Vec3) -> (Vec3, Vec3) {
            (Vec3::ZERO, Vec3::ZERO)
        }
        fn texture_footprint(&self, _: u32, _: Vec2, _: Vec2, _: Vec2) -> Vec4 {
            Vec4::ZERO
        }
        fn environment_footprint(&self, _: u32, _: Vec3, _: Vec3, _: Vec3) -> Vec4 {
            Vec4::ZERO
        }
        fn shadow(&self, _: [f32; 4], _: Vec3) -> f32 {
            0.0
        }
    }

    #[test]
    fn the_twin_moves_p_along_n_by_the_tiled_height() {
        let height = CpuHeight::new(|u, v| u - 2.0 * v);
        let twin = twin(height);
        let ctx = ShadingContext {
            p: Vec3::new(1.0, 2.0, 3.0),
            n: Vec3::new(0.0, 0.6, 0.8),
            u: 0.25,
            v: 0.5,
            ..ShadingContext::default()
        };
        let moved = (twin.0)(&ctx, &Dark, &[[3.0, 0.0, 0.0, 0.0]]);
        // h(3 * 0.25, 3 * 0.5) = 0.75 - 3 = -2.25.
        let expected = Vec3::new(1.0, 2.0 - 0.6 * 2.25, 3.0 - 0.8 * 2.25);
        assert!(
            (moved - expected).length() < 1e-6,
            "{moved} against {expected}"
        );
    }
}
