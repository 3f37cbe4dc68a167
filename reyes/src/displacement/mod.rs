//! Displacement mapping: grid points move along the exact normal of the
//! undisplaced surface by `height(u, v) * scale`, or where a displacement
//! shader puts them (`P + scale * (displacement(ctx) - P)`,
//! [`ShaderDisplacement`]).
//!
//! * `desc`: the `[objects.displacement]` table of a scene and its checks;
//! * `height_map`: grey PNG height maps and their bilinear wrap-around lookup;
//! * `sines`: the built-in procedural source;
//! * `error`: why a source cannot be prepared ([`DisplacementError`]);
//! * [`height_shader`]: a user's WGSL height function run as a displacement
//!   shader.
//!
//! The checks on a user WGSL function are `crate::user_wgsl`'s.
//!
//! `(u, v)` are the parameters of the *input* patch: every split carries
//! its piece's rectangle of them (`WorkItem::uv` on the CPU, `PatchItem::uv`
//! on the GPU), so a grid point at `(s, t)` of a piece covering
//! `(u0, v0, u1, v1)` has `u = u0 + (u1 - u0) * s`, `v = v0 + (v1 - v0) * t`.
//! Each source is evaluated at `(tiling * u, tiling * v)`. How the pipeline
//! uses the result (the bound, the normals) is described in `docs/reyes.md`.

internal_modules! {
    desc;
    error;
    height_map;
    sines;
}
pub mod height_shader;

use std::fmt;
use std::sync::Arc;

pub use self::desc::{DisplacementDesc, ShaderSource};
pub use self::error::DisplacementError;
pub use self::height_map::HeightMap;

/// A Rust function of `(u, v)` that reproduces a user WGSL height function on
/// the CPU, so that the reference renderer can run it
/// ([`crate::prepare::PreparedScene::set_height_twin`]). Compared by
/// identity.
#[derive(Clone)]
pub struct CpuHeight(pub Arc<dyn Fn(f32, f32) -> f32 + Send + Sync>);

impl CpuHeight {
    /// Wraps a function.
    pub fn new(f: impl Fn(f32, f32) -> f32 + Send + Sync + 'static) -> CpuHeight {
        CpuHeight(Arc::new(f))
    }
}

impl fmt::Debug for CpuHeight {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("CpuHeight(<fn>)")
    }
}

impl PartialEq for CpuHeight {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// A displacement shader as an object runs it (docs/shaders.md): the
/// shader's context is the undisplaced point's, and it returns the
/// displaced point.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaderDisplacement {
    /// Where the shader and the object's parameters are in the scene's
    /// [`crate::surface_shader::ShaderTable`] (the CPU reference runs the
    /// shader's twin there,
    /// [`crate::surface_shader::SurfaceShader::cpu_displacement`]).
    pub reference: crate::surface_shader::ShaderRef,
    /// 1, or -1 for an object whose transform mirrors or whose orientation
    /// is reversed (not both): the context's `N` is `orientation *
    /// normalize(dP/du x dP/dv)`, the normal of the object's front, as
    /// RenderMan's `N` follows `Orientation`.
    pub orientation: f32,
}

/// Where an object's heights come from.
#[derive(Debug, Clone, PartialEq)]
pub enum HeightSource {
    /// A grey height map, heights in `[0, 1]`.
    Image(Arc<HeightMap>),
    /// The built-in `sines::sines`, heights in `[-1, 1]`.
    Sines,
    /// A displacement shader: not a height, a displaced point (a user's
    /// WGSL height function runs as one, [`height_shader`]).
    Shader(ShaderDisplacement),
}

/// An object's displacement, ready for rendering.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedDisplacement {
    /// The height source.
    pub source: HeightSource,
    /// World units per unit of height along the surface normal
    /// `dP/du x dP/dv`. Already negated for objects whose transform mirrors
    /// (negative determinant), so a positive scene `scale` keeps pushing
    /// along the model's own normal.
    pub scale: f32,
    /// The displacement bound in world units: no grid point moves further.
    /// Bound and split tests grow every control point by it.
    pub bound: f32,
    /// Repetitions of the source across each input patch.
    pub tiling: f32,
}

impl PreparedDisplacement {
    /// The height at patch parameters `(u, v)` (before the tiling is
    /// applied), or `None` for a shader (which gives a point, not a
    /// height).
    pub fn height(&self, u: f32, v: f32) -> Option<f32> {
        let (u, v) = (u * self.tiling, v * self.tiling);
        match &self.source {
            HeightSource::Image(map) => Some(map.sample(u, v)),
            HeightSource::Sines => Some(sines::sines(u, v)),
            HeightSource::Shader(_) => None,
        }
    }

    /// The displacement shader, if this displacement runs one.
    pub fn shader(&self) -> Option<&ShaderDisplacement> {
        match &self.source {
            HeightSource::Shader(shader) => Some(shader),
            _ => None,
        }
    }

    /// Whether the CPU reference can evaluate this displacement, whose
    /// shader (if it runs one) is in `shaders`.
    pub fn cpu_evaluable(&self, shaders: &crate::surface_shader::ShaderTable) -> bool {
        match &self.source {
            HeightSource::Shader(shader) => shaders
                .shaders
                .get(shader.reference.shader as usize)
                .is_some_and(|s| s.cpu_displacement.is_some()),
            HeightSource::Image(_) | HeightSource::Sines => true,
        }
    }

    /// Whether a displacement `offset = height * scale` leaves the bound
    /// (beyond a relative tolerance for rounding, see
    /// `crate::params::DISPLACEMENT_BOUND_TOLERANCE`).
    pub fn exceeds_bound(&self, offset: f32) -> bool {
        offset.abs() > self.bound * (1.0 + crate::params::DISPLACEMENT_BOUND_TOLERANCE)
    }
}
