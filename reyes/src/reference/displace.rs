//! Displacement: a diced point moves along the exact normal of the
//! undisplaced surface, or where the object's displacement shader puts it,
//! and a displaced grid takes its shading normals from its own displaced
//! points. The GPU does the same in `shaders/reyes/displacement.wgsl` and
//! `dice_shade_sample.wgsl`.

use glam::Vec3;

use super::dice::{degenerate, displacement_normal};
use crate::bezier;
use crate::camera::{HomogeneousEye, towards_eye};
use crate::dicing::{GridSize, patch_position};
use crate::displacement::{PreparedDisplacement, ShaderDisplacement};
use crate::prepare::WorldPatch;
use crate::surface_shader::{CpuDisplacement, ShadingContext, ShadingHost};

/// The parameter `a + (b - a) * s`, written once for both implementations.
pub fn lerp_param(a: f32, b: f32, s: f32) -> f32 {
    a + (b - a) * s
}

/// An object's displacement as the reference evaluates it.
#[derive(Debug)]
pub struct Displacer<'a> {
    /// The displacement.
    pub prepared: &'a PreparedDisplacement,
    /// What its shader's context needs, when it runs a shader.
    pub shader: Option<ShaderInputs<'a>>,
}

impl<'a> Displacer<'a> {
    /// A displacement by heights (no shader).
    pub fn heights(prepared: &'a PreparedDisplacement) -> Self {
        Displacer {
            prepared,
            shader: None,
        }
    }
}

/// What a displacement shader's context needs besides the patch and the
/// point's `(u, v)`.
pub struct ShaderInputs<'a> {
    /// The object's use of the shader.
    pub shader: &'a ShaderDisplacement,
    /// The shader's twin (`None`: the reference cannot displace).
    pub twin: Option<&'a CpuDisplacement>,
    /// The object's parameter slots.
    pub parameters: &'a [[f32; 4]],
    /// Lights and textures.
    pub host: &'a dyn ShadingHost,
    /// The input patch's texture coordinates.
    pub st: &'a WorldPatch,
    /// The viewer.
    pub eye: HomogeneousEye,
    /// The object's colour, `Cs`.
    pub color: Vec3,
}

impl std::fmt::Debug for ShaderInputs<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ShaderInputs")
            .field("shader", &self.shader)
            .field("parameters", &self.parameters)
            .field("eye", &self.eye)
            .field("color", &self.color)
            .finish_non_exhaustive()
    }
}

/// The context a displacement shader sees at `(u, v)` of `patch`, whose
/// undisplaced point is `position` (the WGSL `displacement_context`): `N =
/// Ng` the exact unit normal on the model's side, `du = dv = 0` (a
/// displaced point depends on `(u, v)` alone, so grids that share an edge
/// agree on it).
pub fn displacement_context(
    patch: &[Vec3; 16],
    inputs: &ShaderInputs<'_>,
    position: Vec3,
    u: f32,
    v: f32,
) -> ShadingContext {
    let normal = displacement_normal(patch, u, v) * inputs.shader.orientation;
    let point = ContextPoint {
        uv: (u, v),
        step: (0.0, 0.0),
        position,
        normals: (normal, normal),
    };
    context_at(patch, inputs.st, inputs.eye, inputs.color, point)
}

/// Where on an input patch a shading context is taken: the parameters,
/// the grid's step, the point and its normals `(N, Ng)`.
#[derive(Debug, Clone, Copy)]
pub(super) struct ContextPoint {
    pub(super) uv: (f32, f32),
    pub(super) step: (f32, f32),
    pub(super) position: Vec3,
    pub(super) normals: (Vec3, Vec3),
}

/// The shading context at `point` of the input patch `patch` (texture
/// coordinates from `st`), for an object of colour `cs` seen from `eye`:
/// what surface and displacement contexts share (the WGSL
/// `shading_context` and `displacement_context`).
pub(super) fn context_at(
    patch: &[Vec3; 16],
    st: &WorldPatch,
    eye: HomogeneousEye,
    cs: Vec3,
    point: ContextPoint,
) -> ShadingContext {
    let ContextPoint {
        uv: (u, v),
        step: (du, dv),
        position,
        normals: (n, ng),
    } = point;
    let to_eye = towards_eye(eye, position);
    let [st, dst_du, dst_dv] = st.st_frame(u, v);
    let surface = bezier::evaluate(patch, u, v);
    ShadingContext {
        p: position,
        n,
        ng,
        i: -to_eye,
        e: position + to_eye,
        u,
        v,
        du,
        dv,
        s: st.x,
        t: st.y,
        dp_du: surface.d_ds,
        dp_dv: surface.d_dt,
        dst_du,
        dst_dv,
        cs,
        os: Vec3::ONE,
        time: 0.0,
    }
}

/// The point of the input patch at `(u, v)` ([`patch_position`]), displaced
/// when the object is: `P + n * h(u, v) * scale` with `n` the
/// [`displacement_normal`], or `P + scale * (displacement(ctx) - P)` for a
/// shader; and whether it moved beyond the bound. `None` when the
/// displacement cannot be evaluated on the CPU (a user WGSL function or
/// shader without a Rust twin).
pub fn displaced_point(
    patch: &[Vec3; 16],
    u: f32,
    v: f32,
    displacement: Option<&Displacer<'_>>,
) -> Option<(Vec3, bool)> {
    let position = patch_position(patch, u, v);
    let Some(displacer) = displacement else {
        return Some((position, false));
    };
    let prepared = displacer.prepared;
    let moved = match &displacer.shader {
        Some(inputs) => {
            let twin = inputs.twin?;
            let ctx = displacement_context(patch, inputs, position, u, v);
            let moved = (twin.0)(&ctx, inputs.host, inputs.parameters);
            position + (moved - position) * prepared.scale
        }
        None => {
            let offset = prepared.height(u, v)? * prepared.scale;
            position + displacement_normal(patch, u, v) * offset
        }
    };
    Some((moved, prepared.exceeds_bound((moved - position).length())))
}

/// The unit normal of a displaced grid at `(i, j)`, not yet facing the
/// eye: `normalize(dS x dT)` with `dS = Q(i+1, j) - Q(i-1, j)` (central
/// differences), one-sided at the grid's edges, `dT` likewise along j;
/// `None` when degenerate (e.g. on a collapsed patch edge).
pub fn grid_normal(positions: &[Vec3], size: GridSize, i: u32, j: u32) -> Option<Vec3> {
    let at = |i: u32, j: u32| positions[(j * (size.nu + 1) + i) as usize];
    let d_s = at((i + 1).min(size.nu), j) - at(i.saturating_sub(1), j);
    let d_t = at(i, (j + 1).min(size.nv)) - at(i, j.saturating_sub(1));
    let n = d_s.cross(d_t);
    if degenerate(n, d_s, d_t) {
        return None;
    }
    let n = n.normalize_or_zero();
    (n != Vec3::ZERO).then_some(n)
}

#[cfg(test)]
mod tests {
    use glam::Vec4;

    use super::*;
    use crate::dicing::GridSize;
    use crate::displacement::HeightSource;
    use crate::reference::dice::dice;

    /// A flat unit square in the z = 0 plane, normal +z.
    fn square() -> [Vec3; 16] {
        std::array::from_fn(|k| Vec3::new((k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0, 0.0))
    }

    fn sines(scale: f32) -> PreparedDisplacement {
        PreparedDisplacement {
            source: HeightSource::Sines,
            scale,
            bound: scale.abs(),
            tiling: 1.0,
        }
    }

    const WHOLE: Vec4 = Vec4::new(0.0, 0.0, 1.0, 1.0);

    #[test]
    fn points_move_along_the_normal_by_height_times_scale() {
        let d = sines(0.5);
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let size = GridSize::FIXED;
        let out = dice(&square(), WHOLE, size, None, eye, Some(&Displacer::heights(&d))).unwrap();
        for j in 0..=size.nv {
            for i in 0..=size.nu {
                let (s, t) = (i as f32 / 15.0, j as f32 / 15.0);
                let p = out.positions[out.index(i, j)];
                assert!((p.x - s).abs() < 1e-6 && (p.y - t).abs() < 1e-6);
                let expected = crate::displacement::sines::sines(s, t) * 0.5;
                assert!((p.z - expected).abs() < 1e-6, "{p} {expected}");
            }
        }
        assert_eq!(out.bound_exceeded, 0);
        // A flat, undisplaced grid keeps the plane's normal.
        let flat = dice(&square(), WHOLE, size, None, eye, Some(&Displacer::heights(&sines(0.0)))).unwrap();
        for n in flat.normals {
            assert!((n - Vec3::Z).length() < 1e-6, "{n}");
        }
    }

    #[test]
    fn a_piece_uses_its_rectangle_of_the_patch_parameters() {
        let d = sines(1.0);
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let uv = Vec4::new(0.5, 0.25, 0.75, 0.5);
        let size = GridSize { nu: 4, nv: 8 };
        let out = dice(&square(), uv, size, None, eye, Some(&Displacer::heights(&d))).unwrap();
        let corner = out.positions[out.index(4, 8)];
        let expected = crate::displacement::sines::sines(0.75, 0.5);
        assert!((corner.z - expected).abs() < 1e-6);
        assert!((corner.x - 0.75).abs() < 1e-6 && (corner.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn a_small_bound_is_counted() {
        let mut d = sines(1.0);
        d.bound = 0.5;
        let eye = Vec3::new(0.5, 0.5, 5.0).extend(1.0);
        let out = dice(&square(), WHOLE, GridSize::FIXED, None, eye, Some(&Displacer::heights(&d))).unwrap();
        assert!(out.bound_exceeded > 0);
    }
}
