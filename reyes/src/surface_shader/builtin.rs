//! Standard shaders written in WGSL against the surface shader interface
//! and run as user shaders are, each with its Rust twin so that the CPU
//! reference runs it too: `paintedplastic`, `shinymetal` and `bumpy` (RenderMan
//! Interface 3.2, "Standard RenderMan Shaders").

use std::path::Path;

use glam::Vec3;

use super::{
    CpuDisplacement, CpuSurface, ShadingContext, ShadingHost, SurfaceOutput, SurfaceShader,
};
use crate::texture::{TextureId, TextureSet};

/// The file name that stands for a built-in shader (`builtin:NAME`).
pub const PREFIX: &str = "builtin:";

/// `paintedplastic`'s path.
pub const PAINTED_PLASTIC: &str = "builtin:paintedplastic";

/// `shinymetal`'s path.
pub const SHINY_METAL: &str = "builtin:shinymetal";

/// `bumpy`'s path.
pub const BUMPY: &str = "builtin:bumpy";

/// A built-in shader's source and its twin.
enum Twin {
    Surface(CpuSurface),
    Displacement(CpuDisplacement),
}

/// The built-in shader `path` names, checked, with its twin; `None` when
/// `path` names none.
pub fn shader(path: &Path) -> Option<Result<SurfaceShader, super::SurfaceShaderError>> {
    let name = path.to_str()?.strip_prefix(PREFIX)?;
    let (source, twin) = match name {
        "paintedplastic" => (
            include_str!("../../../shaders/reyes/standard/paintedplastic.wgsl"),
            Twin::Surface(CpuSurface::new(painted_plastic)),
        ),
        "bumpy" => (
            include_str!("../../../shaders/reyes/standard/bumpy.wgsl"),
            Twin::Displacement(CpuDisplacement::new(bumpy)),
        ),
        "shinymetal" => (
            include_str!("../../../shaders/reyes/standard/shinymetal.wgsl"),
            Twin::Surface(CpuSurface::new(shiny_metal)),
        ),
        _ => return None,
    };
    Some(
        SurfaceShader::from_source(path, source.to_owned()).map(|mut shader| {
            match twin {
                Twin::Surface(twin) => shader.cpu = Some(twin),
                Twin::Displacement(twin) => shader.cpu_displacement = Some(twin),
            }
            shader
        }),
    )
}

/// Whether `path` names a built-in shader.
pub fn is_builtin(path: &Path) -> bool {
    path.to_str().is_some_and(|p| p.starts_with(PREFIX))
}

/// Whether the built-in displacement shader `path` knows its own bound
/// ([`displacement_bound`]), so that a scene need not give one.
pub fn bounds_itself(path: &Path) -> bool {
    path.to_str() == Some(BUMPY)
}

/// The bound of the built-in displacement shader `path` with the
/// parameter `slots`: for `bumpy`, `|Km|` times the largest `|value|` of
/// its texture's first channel (no filtered lookup exceeds it). `None` for
/// other shaders.
pub fn displacement_bound(path: &Path, slots: &[[f32; 4]], textures: &TextureSet) -> Option<f32> {
    if !bounds_itself(path) {
        return None;
    }
    let word = |k: usize| slots.get(k).copied().unwrap_or_default();
    let km = word(0)[0];
    // A texture the scene does not give reads zero.
    let largest = textures
        .largest_magnitude(TextureId(word(1)[0].to_bits()), 0)
        .unwrap_or(0.0);
    Some(km.abs() * largest)
}

/// The twin of `shaders/reyes/standard/bumpy.wgsl`, term for term.
fn bumpy(ctx: &ShadingContext, host: &dyn ShadingHost, slots: &[[f32; 4]]) -> Vec3 {
    let word = |k: usize| slots.get(k).copied().unwrap_or_default();
    let amp = word(0)[0] * host.texture(ctx, word(1)[0].to_bits(), ctx.s, ctx.t).x;
    ctx.p + amp * ctx.n
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

/// The twin of `shaders/reyes/standard/shinymetal.wgsl`, term for term.
fn shiny_metal(ctx: &ShadingContext, host: &dyn ShadingHost, slots: &[[f32; 4]]) -> SurfaceOutput {
    let word = |k: usize| slots.get(k).copied().unwrap_or_default();
    let (ka, ks, kr, roughness) = (word(0)[0], word(1)[0], word(2)[0], word(3)[0]);
    let v = (-ctx.i).normalize_or_zero();
    let world = |k: usize| Vec3::from_slice(&word(k)[..3]);
    let r = ctx.i - 2.0 * ctx.n.dot(ctx.i) * ctx.n;
    let d = r.x * world(5) + r.y * world(6) + r.z * world(7);
    let ci = ctx.cs
        * (ka * host.ambient()
            + ks * host.specular(ctx, ctx.n, v, roughness)
            + kr * host.environment(ctx, word(4)[0].to_bits(), d).truncate());
    SurfaceOutput {
        ci: ctx.os * ci,
        oi: ctx.os,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each built-in checks against the interface, has its twin, and
    /// declares the standard shader's parameters.
    #[test]
    fn the_built_ins_check_with_their_twins_and_parameters() {
        for (path, names) in [
            (
                PAINTED_PLASTIC,
                &[
                    "Ka",
                    "Kd",
                    "Ks",
                    "roughness",
                    "specularcolor",
                    "texturename",
                ][..],
            ),
            (
                SHINY_METAL,
                &[
                    "Ka",
                    "Ks",
                    "Kr",
                    "roughness",
                    "texturename",
                    "world_x",
                    "world_y",
                    "world_z",
                ][..],
            ),
        ] {
            let shader = shader(Path::new(path))
                .expect("a built-in")
                .unwrap_or_else(|e| panic!("{path}: {e}"));
            assert!(shader.cpu.is_some(), "{path}");
            let declared: Vec<&str> = shader.parameters.iter().map(|p| p.name.as_str()).collect();
            assert_eq!(declared, names, "{path}");
        }
        assert!(shader(Path::new("builtin:nothing")).is_none());
    }
}
