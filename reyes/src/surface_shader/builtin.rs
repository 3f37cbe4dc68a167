//! Standard shaders written in WGSL against the surface shader interface
//! and run as user shaders are, each with its Rust twin so that the CPU
//! reference runs it too: `paintedplastic` (RenderMan Interface 3.2,
//! "Standard RenderMan Shaders").

use std::path::Path;

use glam::Vec3;

use super::{CpuSurface, ShadingContext, ShadingHost, SurfaceOutput, SurfaceShader};

/// The file name that stands for a built-in shader (`builtin:NAME`).
pub const PREFIX: &str = "builtin:";

/// `paintedplastic`'s path.
pub const PAINTED_PLASTIC: &str = "builtin:paintedplastic";

/// The built-in shader `path` names, checked, with its twin; `None` when
/// `path` names none.
pub fn shader(path: &Path) -> Option<Result<SurfaceShader, super::SurfaceShaderError>> {
    let name = path.to_str()?.strip_prefix(PREFIX)?;
    let (source, twin): (&str, CpuSurface) = match name {
        "paintedplastic" => (
            include_str!("../../../shaders/reyes/standard/paintedplastic.wgsl"),
            CpuSurface::new(painted_plastic),
        ),
        _ => return None,
    };
    Some(
        SurfaceShader::from_source(path, source.to_owned()).map(|mut shader| {
            shader.cpu = Some(twin);
            shader
        }),
    )
}

/// The twin of `shaders/reyes/standard/paintedplastic.wgsl`, term for term.
fn painted_plastic(
    ctx: &ShadingContext,
    host: &dyn ShadingHost,
    slots: &[[f32; 4]],
) -> SurfaceOutput {
    let word = |k: usize| slots.get(k).copied().unwrap_or_default();
    let (ka, kd, ks, roughness) = (word(0)[0], word(1)[0], word(2)[0], word(3)[0]);
    let specular_color = Vec3::from_slice(&word(4)[..3]);
    let paint = host
        .texture(ctx, word(5)[0].to_bits(), ctx.s, ctx.t)
        .truncate();
    let v = (-ctx.i).normalize_or_zero();
    let ci = ctx.cs * paint * (ka * host.ambient() + kd * host.diffuse(ctx, ctx.n))
        + specular_color * ks * host.specular(ctx, ctx.n, v, roughness);
    SurfaceOutput {
        ci: ctx.os * ci,
        oi: ctx.os,
    }
}
