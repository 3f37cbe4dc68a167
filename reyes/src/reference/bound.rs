//! The bound test: decide whether a patch is culled, diced, split (and in
//! which direction) or dropped.

use glam::{Mat4, Vec2, Vec3};

use crate::bezier::{SplitDirection, split_direction_2d, split_direction_3d};
use crate::camera::Camera;
use crate::params::NEAR_EPS;

/// The outcome of the bound test for one patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundDecision {
    /// All control points are outside the same clip plane.
    Cull,
    /// The projected bound is small enough: dice it.
    Dice,
    /// Split in this direction.
    Split(SplitDirection),
    /// It needs a split but is already at the maximum split depth.
    Drop,
}

// One bit per clip plane, for the "all points outside the same plane" test.
const LEFT: u8 = 1; // x < -w
const RIGHT: u8 = 2; // x > w
const BOTTOM: u8 = 4; // y < -w
const TOP: u8 = 8; // y > w
const FAR: u8 = 16; // z > w
const NEAR: u8 = 32; // z < 0 (wgpu depth range)

/// Runs the bound test on a patch's 16 world-space control points.
///
/// 1. Cull if all points are outside one clip plane.
/// 2. If any point has `w <= NEAR_EPS` or `z < 0`, the patch cannot be
///    projected: split by world-space extents (or drop at `max_split_depth`).
/// 3. Otherwise project; dice if the pixel bounding box's larger side is
///    `<= dice_threshold`, else split by pixel-space extents (or drop).
pub fn bound(
    points: &[Vec3; 16],
    split_depth: u32,
    view_proj: &Mat4,
    camera: &Camera,
    dice_threshold: f32,
    max_split_depth: u32,
) -> BoundDecision {
    let clip = points.map(|p| *view_proj * p.extend(1.0));

    let mut outside_all = u8::MAX;
    let mut unprojectable = false;
    for c in &clip {
        let mut code = 0;
        if c.x < -c.w {
            code |= LEFT;
        }
        if c.x > c.w {
            code |= RIGHT;
        }
        if c.y < -c.w {
            code |= BOTTOM;
        }
        if c.y > c.w {
            code |= TOP;
        }
        if c.z > c.w {
            code |= FAR;
        }
        if c.z < 0.0 {
            code |= NEAR;
        }
        outside_all &= code;
        unprojectable |= c.w <= NEAR_EPS || c.z < 0.0;
    }
    if outside_all != 0 {
        return BoundDecision::Cull;
    }

    if unprojectable {
        if split_depth >= max_split_depth {
            return BoundDecision::Drop;
        }
        return BoundDecision::Split(split_direction_3d(points));
    }

    let pixels: [Vec2; 16] = clip.map(|c| camera.to_pixel(c).truncate());
    let (lo, hi) = pixels.iter().fold((pixels[0], pixels[0]), |(lo, hi), &p| {
        (lo.min(p), hi.max(p))
    });
    let size = hi - lo;
    if size.x.max(size.y) <= dice_threshold {
        BoundDecision::Dice
    } else if split_depth >= max_split_depth {
        BoundDecision::Drop
    } else {
        BoundDecision::Split(split_direction_2d(&pixels))
    }
}
