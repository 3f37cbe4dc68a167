//! Camera poses that `f32` view math cannot handle: [`pose_problem`] says
//! why an eye, target and up direction make no view.

use glam::Vec3;

/// Why an eye, target and up direction (all finite) cannot make a view in
/// `f32` ([`pose_problem`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseProblem {
    /// The eye and the target are the same point.
    Coincident,
    /// The eye's squared length overflows `f32` (a coordinate beyond about
    /// 1e19), so view-space math overflows.
    EyeTooLarge,
    /// The target's squared length overflows `f32`.
    TargetTooLarge,
    /// The squared distance from the eye to the target overflows `f32`: the
    /// view direction cannot be normalized.
    TooFarApart,
    /// The squared distance from the eye to the target underflows `f32`'s
    /// normal range although they differ: the view direction cannot be
    /// normalized.
    TooClose,
    /// `up` is zero or parallel to the view direction.
    UpParallel,
}

impl PoseProblem {
    /// What is wrong, naming the fields of the pose as `{table}.eye`,
    /// `{table}.target` and `{table}.up` (e.g. `table = "camera"`).
    pub fn reason(self, table: &str) -> String {
        let (eye, target, up) = (
            format!("{table}.eye"),
            format!("{table}.target"),
            format!("{table}.up"),
        );
        match self {
            PoseProblem::Coincident => format!("{eye} and {target} must differ"),
            PoseProblem::EyeTooLarge => format!(
                "{eye} is too large: its squared length overflows f32; keep its coordinates below about 1e19 (move the scene closer to the origin)"
            ),
            PoseProblem::TargetTooLarge => format!(
                "{target} is too large: its squared length overflows f32; keep its coordinates below about 1e19 (move the scene closer to the origin)"
            ),
            PoseProblem::TooFarApart => format!(
                "{eye} and {target} are too far apart: the squared distance between them overflows f32, so the view direction cannot be computed; keep them within about 1e19 of each other"
            ),
            PoseProblem::TooClose => format!(
                "{eye} and {target} are too close together: the squared distance between them underflows f32, so the view direction cannot be computed; move them further apart (or scale the scene up)"
            ),
            PoseProblem::UpParallel => {
                format!("{up} must be non-zero and not parallel to the view direction")
            }
        }
    }
}

/// `v` scaled to unit length without overflow or underflow in the squared
/// length (zero for a zero vector).
pub fn unit(v: Vec3) -> Vec3 {
    let m = v.abs().max_element();
    if m > 0.0 && m.is_finite() {
        (v / m).normalize_or_zero()
    } else {
        Vec3::ZERO
    }
}

/// What keeps a finite `eye`, `target` and `up` from making a view in
/// `f32`, if anything: the view direction and `up` must be normalizable and
/// not parallel, and the squared lengths used by the view math must fit.
pub fn pose_problem(eye: Vec3, target: Vec3, up: Vec3) -> Option<PoseProblem> {
    if eye == target {
        return Some(PoseProblem::Coincident);
    }
    if !eye.length_squared().is_finite() {
        return Some(PoseProblem::EyeTooLarge);
    }
    if !target.length_squared().is_finite() {
        return Some(PoseProblem::TargetTooLarge);
    }
    let along = target - eye;
    let squared = along.length_squared();
    if !squared.is_finite() {
        return Some(PoseProblem::TooFarApart);
    }
    if squared < f32::MIN_POSITIVE {
        return Some(PoseProblem::TooClose);
    }
    if along.normalize().cross(unit(up)).length_squared() < 1e-12 {
        return Some(PoseProblem::UpParallel);
    }
    None
}
