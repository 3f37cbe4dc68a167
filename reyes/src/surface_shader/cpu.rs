//! The Rust side of the surface shader interface: the shading context and
//! output as the CPU reference builds them, and the Rust twin of a user's
//! WGSL shader, through which the reference renders it (tests compare the
//! GPU against it). Scene files cannot give a twin: the API can.

use std::fmt;
use std::sync::Arc;

use glam::{Vec2, Vec3, Vec4};

/// What a surface shader sees at a shading point: the WGSL
/// `ShadingContext`, field for field (RenderMan's names in the WGSL;
/// snake case here).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ShadingContext {
    /// `P`: the point, in world space.
    pub p: Vec3,
    /// `N`: the unit shading normal, facing the eye.
    pub n: Vec3,
    /// `Ng`: the unit normal of the undisplaced surface, facing the eye.
    pub ng: Vec3,
    /// `I`: from the eye to `P`.
    pub i: Vec3,
    /// `E`: the eye.
    pub e: Vec3,
    /// `u`.
    pub u: f32,
    /// `v`.
    pub v: f32,
    /// `du`: the grid's step in `u`.
    pub du: f32,
    /// `dv`.
    pub dv: f32,
    /// `s`.
    pub s: f32,
    /// `t`.
    pub t: f32,
    /// `dPdu`.
    pub dp_du: Vec3,
    /// `dPdv`.
    pub dp_dv: Vec3,
    /// `dstdu`: the derivative of `(s, t)` along `u`.
    pub dst_du: Vec2,
    /// `dstdv`.
    pub dst_dv: Vec2,
    /// `Cs`: the object's colour.
    pub cs: Vec3,
    /// `Os`: its opacity.
    pub os: Vec3,
    /// `time`: 0 at shutter open.
    pub time: f32,
}

/// What a surface shader returns: `Ci` and `Oi`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfaceOutput {
    /// `Ci`.
    pub ci: Vec3,
    /// `Oi`.
    pub oi: Vec3,
}

/// The interface's lighting and texture functions, as the CPU reference
/// provides them.
pub trait ShadingHost {
    /// `ambient()`.
    fn ambient(&self) -> Vec3;
    /// `diffuse(ctx, N)`.
    fn diffuse(&self, ctx: &ShadingContext, n: Vec3) -> Vec3;
    /// `specular(ctx, N, V, roughness)`.
    fn specular(&self, ctx: &ShadingContext, n: Vec3, v: Vec3, roughness: f32) -> Vec3;
    /// `light_count()`.
    fn light_count(&self) -> u32;
    /// Light `i` seen from `p`: `(L, Cl)`, `Cl` zero where it gives nothing.
    fn light(&self, i: u32, p: Vec3) -> (Vec3, Vec3);

    /// `texture_footprint(id, st, axis_a, axis_b)`: texture `index`'s
    /// filtered RGBA.
    fn texture_footprint(&self, index: u32, st: Vec2, axis_a: Vec2, axis_b: Vec2) -> Vec4;

    /// `texture(ctx, id, s, t)`: over the context's footprint in `(s, t)`.
    fn texture(&self, ctx: &ShadingContext, index: u32, s: f32, t: f32) -> Vec4 {
        self.texture_footprint(
            index,
            Vec2::new(s, t),
            ctx.dst_du * ctx.du,
            ctx.dst_dv * ctx.dv,
        )
    }

    /// `environment_footprint(id, R, dRdu, dRdv)`: texture `index` as a
    /// latitude-longitude environment map along `r`, over the footprint of
    /// `r`'s changes (`crate::texture::TextureSet::environment`).
    fn environment_footprint(&self, index: u32, r: Vec3, dr_du: Vec3, dr_dv: Vec3) -> Vec4;

    /// `environment(ctx, id, R)`: bilinear in the finest level.
    fn environment(&self, _ctx: &ShadingContext, index: u32, r: Vec3) -> Vec4 {
        self.environment_footprint(index, r, Vec3::ZERO, Vec3::ZERO)
    }

    /// `shadow(id, P)`: the occluded fraction of the filter region around
    /// `p` in the shadow map of the `ShadowId` parameter whose slot is
    /// `id` (as the twin is given it), 0 lit, 1 in shadow
    /// ([`super::ShadowSlot::occlusion`]).
    fn shadow(&self, id: [f32; 4], p: Vec3) -> f32;

    /// `illuminance(i, P, axis, angle)`: light `i`'s `(L, Cl)`, with `Cl`
    /// zero unless `L` lies within `angle` radians of `axis`.
    fn illuminance(&self, i: u32, p: Vec3, axis: Vec3, angle: f32) -> (Vec3, Vec3) {
        let (l, cl) = self.light(i, p);
        if l.dot(axis) <= angle.cos() * axis.length() {
            (l, Vec3::ZERO)
        } else {
            (l, cl)
        }
    }
}

/// The signature of a twin: the context, the lighting, and the object's
/// parameter slots (as [`super::pack_parameters`] packs them).
pub type CpuSurfaceFn =
    dyn Fn(&ShadingContext, &dyn ShadingHost, &[[f32; 4]]) -> SurfaceOutput + Send + Sync;

/// A Rust function that reproduces a user's WGSL surface shader on the CPU.
/// Compared by identity.
#[derive(Clone)]
pub struct CpuSurface(pub Arc<CpuSurfaceFn>);

impl CpuSurface {
    /// Wraps a function.
    pub fn new(
        f: impl Fn(&ShadingContext, &dyn ShadingHost, &[[f32; 4]]) -> SurfaceOutput
        + Send
        + Sync
        + 'static,
    ) -> Self {
        CpuSurface(Arc::new(f))
    }
}

impl fmt::Debug for CpuSurface {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("CpuSurface(<fn>)")
    }
}

impl PartialEq for CpuSurface {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The signature of a displacement shader's twin: the context (of the
/// undisplaced point), the host, and the object's parameter slots; it
/// returns the displaced `P`.
pub type CpuDisplacementFn =
    dyn Fn(&ShadingContext, &dyn ShadingHost, &[[f32; 4]]) -> Vec3 + Send + Sync;

/// A Rust function that reproduces a user's WGSL displacement shader on the
/// CPU. Compared by identity.
#[derive(Clone)]
pub struct CpuDisplacement(pub Arc<CpuDisplacementFn>);

impl CpuDisplacement {
    /// Wraps a function.
    pub fn new(
        f: impl Fn(&ShadingContext, &dyn ShadingHost, &[[f32; 4]]) -> Vec3 + Send + Sync + 'static,
    ) -> Self {
        CpuDisplacement(Arc::new(f))
    }
}

impl fmt::Debug for CpuDisplacement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("CpuDisplacement(<fn>)")
    }
}

impl PartialEq for CpuDisplacement {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}
