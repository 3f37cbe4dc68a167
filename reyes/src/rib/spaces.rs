//! Coordinate systems (`CoordinateSystem`, `CoordSysTransform`) and
//! `Skew`.

use glam::{DMat4, DVec3};

use super::interp::Interp;
use super::parser::Value;
use super::state;

impl Interp {
    /// `CoordinateSystem "name"` (saves the current transform) and
    /// `CoordSysTransform "name"` (makes a saved one, or the predefined
    /// `"world"` or `"camera"`, the current transform).
    pub(super) fn coordinate_system(&mut self, name: &str, v: &[Value]) -> Result<(), String> {
        let (args, _, _) = state::split_params(v, 1, &self.declared)?;
        let space = state::arg_str(&args, 0, "the coordinate system name")?;
        if name == "CoordinateSystem" {
            self.coordsys.insert(space.to_owned(), self.xf);
            return Ok(());
        }
        if self.motion.is_some() {
            return Err("inside MotionBegin (not a motion sample)".into());
        }
        self.xf = match (self.coordsys.get(space), space) {
            (Some(xf), _) => *xf,
            (None, "world") => state::Xform::default(),
            (None, "camera") => {
                let camera = self.camera.unwrap_or(DMat4::IDENTITY).inverse();
                if !camera.is_finite() {
                    return Err("the camera transform is singular".into());
                }
                state::Xform {
                    open: camera,
                    close: camera,
                    overflow: None,
                }
            }
            (None, other) => return Err(format!("unknown coordinate system {other:?}")),
        };
        Ok(())
    }
}

/// RenderMan's `Skew angle d1 d2` (RI 3.2): shears along
/// `d2` so that `d1` turns by `angle` degrees towards `d2`. With `e2 = d2 /
/// |d2|`, `e1` the unit part of `d1` perpendicular to `d2` and `b` the angle
/// from `d1` to `d2`: `p + k (p . e1) e2` with `k = cot(b - angle) - cot b`.
pub(super) fn skew(angle: f64, d1: DVec3, d2: DVec3) -> Result<DMat4, String> {
    if d1.length_squared() == 0.0 || d2.length_squared() == 0.0 {
        return Err("the axes must be non-zero".into());
    }
    let e2 = d2.normalize();
    let along = d1.normalize().dot(e2).clamp(-1.0, 1.0);
    let perp = d1 - e2 * d1.dot(e2);
    let b = along.acos();
    let a = angle.to_radians();
    if perp.length() <= 1e-12 * d1.length() {
        return Err("the axes are parallel".into());
    }
    if a >= b || a <= b - std::f64::consts::PI {
        return Err(format!(
            "the angle {angle} is not between {} and {} (the angle between the axes)",
            b.to_degrees() - 180.0,
            b.to_degrees()
        ));
    }
    let e1 = perp.normalize();
    let k = 1.0 / (b - a).tan() - 1.0 / b.tan();
    let shear = glam::DMat3::from_cols(e2 * (k * e1.x), e2 * (k * e1.y), e2 * (k * e1.z));
    Ok(DMat4::from_mat3(glam::DMat3::IDENTITY + shear))
}
