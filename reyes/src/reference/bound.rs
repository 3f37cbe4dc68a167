//! The bound test: decide whether a patch is culled, diced, split (and in
//! which direction) or dropped. With a displacement bound `b`, every control
//! point stands for the ball of radius `b` around it (the displaced surface
//! lies in the control points' convex hull grown by `b`).

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::bezier::{SplitDirection, split_direction_2d, split_direction_3d};
use crate::camera::Camera;
use crate::motion::{ObjectMotion, PreparedLens, cull_radius};
use crate::params::{DISPLACED_DICE_FRACTION, NEAR_EPS};

/// What grows a piece's control points in the bound test: its object's
/// displacement bound, motion and the lens (without motion or lens: a
/// sharp, still frame, whose bound test is exactly the plain one).
#[derive(Debug, Clone, Copy)]
pub struct Growth<'a> {
    /// The object's displacement bound in world units (0 without displacement).
    pub displacement_bound: f32,
    /// The object's motion, if it moves.
    pub motion: Option<&'a ObjectMotion>,
    /// The lens.
    pub lens: &'a PreparedLens,
}

impl Growth<'_> {
    /// Whether the piece moves or the lens blurs.
    pub fn blurs(&self) -> bool {
        self.motion.is_some() || self.lens.aperture > 0.0
    }
}

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

/// The clip planes that a ball is entirely outside of. The ball has clip
/// coordinates within `[lo, hi] = c -+ radius` (see [`Camera::clip_pad`]);
/// e.g. it is left of `x = -w` when even `hi.x + hi.w < 0`. With a zero
/// radius this is the plain outcode of `c`.
pub fn outcode(c: Vec4, radius: Vec4) -> u8 {
    let (lo, hi) = (c - radius, c + radius);
    let mut code = 0;
    if hi.x < -hi.w {
        code |= LEFT;
    }
    if lo.x > hi.w {
        code |= RIGHT;
    }
    if hi.y < -hi.w {
        code |= BOTTOM;
    }
    if lo.y > hi.w {
        code |= TOP;
    }
    if lo.z > hi.w {
        code |= FAR;
    }
    if hi.z < 0.0 {
        code |= NEAR;
    }
    code
}

/// How far, in pixels, the ball around a projectable point (clip `c`,
/// `w > NEAR_EPS`) with clip-space `radius` reaches beyond the point's own
/// pixel position on screen: over `w` in `[lo.w, hi.w]` and `x` in
/// `[lo.x, hi.x]`, `x / w` is extreme at the interval ends, so `ndc.x` lies
/// in `[min(lo.x/lo.w, lo.x/hi.w), max(hi.x/lo.w, hi.x/hi.w)]` (likewise y,
/// flipped on screen), and the growth is the largest distance from the
/// point to that box's sides. A ball that reaches the eye plane
/// (`lo.w <= NEAR_EPS`) has no bounded projection: its growth is taken as 0
/// (the dice test then sees the undisplaced size, and micropolygon corners
/// behind the eye are skipped at sampling). Without displacement
/// (`bound == 0`) the growth is 0.
pub fn pixel_growth(camera: &Camera, c: Vec4, bound: f32, radius: Vec4) -> f32 {
    if bound == 0.0 {
        return 0.0;
    }
    let (lo, hi) = (c - radius, c + radius);
    if lo.w <= NEAR_EPS {
        return 0.0;
    }
    let p = camera.to_pixel(c).truncate();
    let xl = (lo.x / lo.w).min(lo.x / hi.w);
    let xh = (hi.x / lo.w).max(hi.x / hi.w);
    let yl = (lo.y / lo.w).min(lo.y / hi.w);
    let yh = (hi.y / lo.w).max(hi.y / hi.w);
    let (width, height) = (camera.width as f32, camera.height as f32);
    let box_lo = Vec2::new((xl * 0.5 + 0.5) * width, (0.5 - yh * 0.5) * height);
    let box_hi = Vec2::new((xh * 0.5 + 0.5) * width, (0.5 - yl * 0.5) * height);
    (p.x - box_lo.x)
        .max(box_hi.x - p.x)
        .max(p.y - box_lo.y)
        .max(box_hi.y - p.y)
}

/// The dice test: the larger side `size` of the control points' pixel box,
/// grown on every side by `growth` (the largest [`pixel_growth`] of the
/// points), fits `threshold`; splitting shrinks `size` but not `growth`, so
/// the growth may take at most [`DISPLACED_DICE_FRACTION`] of the threshold:
/// `size <= max(threshold - 2 growth, threshold * DISPLACED_DICE_FRACTION)`.
/// Without displacement (`growth == 0`) this is `size <= threshold`.
pub fn fits(size: f32, growth: f32, threshold: f32) -> bool {
    size <= (threshold - 2.0 * growth).max(threshold * DISPLACED_DICE_FRACTION)
}

/// Runs the bound test on a patch's 16 world-space control points, each
/// grown by `growth.displacement_bound` (world units; 0 without displacement).
///
/// 1. Cull if all (grown) points are outside one clip plane. With motion or a lens,
///    each point is grown for culling by [`cull_radius`] instead: its
///    displacement, its motion and its lens shift, so that the piece is
///    culled only when it is outside at every time and lens position.
/// 2. If any point itself has `w <= NEAR_EPS` or `z < 0`, the patch cannot
///    be projected: split by world-space extents (or drop at
///    `max_split_depth`). The growth does not count here: a bound that
///    reaches the near plane would otherwise split a whole band of surface
///    to the depth guard.
/// 3. Otherwise project; dice if the points' pixel bounding box, grown by
///    the displacement bound, [`fits`] `dice_threshold`, else split by the
///    points' pixel-space extents (or drop).
pub fn bound(
    points: &[Vec3; 16],
    split_depth: u32,
    view_proj: &Mat4,
    camera: &Camera,
    dice_threshold: f32,
    max_split_depth: u32,
    growth: Growth<'_>,
) -> BoundDecision {
    let displacement_bound = growth.displacement_bound;
    let clip = points.map(|p| *view_proj * p.extend(1.0));
    let radius = if displacement_bound == 0.0 {
        Vec4::ZERO
    } else {
        camera.clip_pad() * displacement_bound
    };

    let mut outside_all = u8::MAX;
    let mut unprojectable = false;
    for (c, p) in clip.iter().zip(points) {
        // Culling sees every time and lens position: the ball also covers
        // the point's motion and lens shift (crate::motion::cull_radius).
        let cull = if growth.blurs() {
            let reach = cull_radius(*p, c.w, displacement_bound, growth.motion, growth.lens);
            camera.clip_pad() * reach
        } else {
            radius
        };
        outside_all &= outcode(*c, cull);
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
    let growth = clip.iter().fold(0.0f32, |g, &c| {
        g.max(pixel_growth(camera, c, displacement_bound, radius))
    });
    let size = hi - lo;
    if fits(size.x.max(size.y), growth, dice_threshold) {
        BoundDecision::Dice
    } else if split_depth >= max_split_depth {
        BoundDecision::Drop
    } else {
        BoundDecision::Split(split_direction_2d(&pixels))
    }
}
