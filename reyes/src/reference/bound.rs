//! The bound test: decide whether a patch is culled, diced, split (and in
//! which direction) or dropped. With a displacement bound `b`, every control
//! point stands for the ball of radius `b` around it (the displaced surface
//! lies in the control points' convex hull grown by `b`).

use glam::{Mat4, Vec2, Vec3, Vec4};

use crate::bezier::{SplitDirection, split_direction_2d, split_direction_3d};
use crate::camera::{Camera, HomogeneousEye, towards_eye};
use crate::dicing::{
    EDGE_U0, EDGE_U1, EDGE_V0, EDGE_V1, GridSize, PieceEdges, edge_indices, fresh_spacing,
    halved_spacing, level, polygon_length, rate_for,
};
use crate::motion::{ObjectMotion, PreparedLens, cull_radius};
use crate::params::{DISPLACED_DICE_FRACTION, MAX_GRID_QUADS, NEAR_EPS};

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
    /// The projected bound is small enough: dice it into this grid.
    Dice(GridSize),
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

/// How the bound test decides that a piece is diced, and into what grid.
#[derive(Debug, Clone, Copy)]
pub enum DiceRule<'a> {
    /// A piece that fits the threshold gets [`GridSize::FIXED`].
    Fixed,
    /// A piece is diced to the shading rate (see [`rate_grid`]).
    Rate {
        /// The spacings of the piece's edges.
        edges: &'a PieceEdges,
        /// The piece's rectangle in its input patch's parameters.
        uv: Vec4,
        /// The side of a micropolygon at the shading rate, in pixels.
        side: f32,
    },
}

/// The length rate dicing measures a line of 4 control points by: its
/// projected [`polygon_length`] plus twice the largest screen growth of the
/// object's displacement bound at its points ([`pixel_growth`]; 0 without
/// displacement), since the displaced line may wander that far to either
/// side. Splitting shrinks the polygon but not the growth, so (as in
/// [`fits`]) the growth adds at most [`DISPLACED_DICE_FRACTION`] of the
/// largest grid's side, `MAX_GRID_QUADS * side` pixels.
pub fn line_length(pixels: [Vec2; 4], growths: [f32; 4], side: f32) -> f32 {
    let growth = growths[0].max(growths[1]).max(growths[2]).max(growths[3]);
    let cap = DISPLACED_DICE_FRACTION * MAX_GRID_QUADS as f32 * side;
    polygon_length(pixels) + (2.0 * growth).min(cap)
}

/// A piece's control points on screen: pixel positions, the growth of the
/// displacement bound at each, and which can be projected (`w > NEAR_EPS`
/// and `z >= 0`).
#[derive(Debug, Clone, Copy)]
pub struct ScreenPiece {
    /// Pixel positions.
    pub pixels: [Vec2; 16],
    /// [`pixel_growth`] of each point (0 for an unprojectable one).
    pub growths: [f32; 16],
    /// Whether each point can be projected.
    pub projectable: [bool; 16],
}

impl ScreenPiece {
    /// Projects `points` with a displacement bound of `bound` world units.
    pub fn new(view_proj: &Mat4, camera: &Camera, points: &[Vec3; 16], bound: f32) -> Self {
        Self::from_clip(camera, &points.map(|p| *view_proj * p.extend(1.0)), bound)
    }

    /// The points already in clip space.
    pub fn from_clip(camera: &Camera, clip: &[Vec4; 16], bound: f32) -> Self {
        let radius = camera.clip_pad() * bound;
        let projectable = clip.map(|c| !(c.w <= NEAR_EPS || c.z < 0.0));
        ScreenPiece {
            pixels: clip.map(|c| camera.to_pixel(c).truncate()),
            growths: std::array::from_fn(|k| {
                if projectable[k] {
                    pixel_growth(camera, clip[k], bound, radius)
                } else {
                    0.0
                }
            }),
            projectable,
        }
    }

    /// [`line_length`] of the points `indices`.
    fn length(&self, indices: [usize; 4], side: f32) -> f32 {
        line_length(
            indices.map(|i| self.pixels[i]),
            indices.map(|i| self.growths[i]),
            side,
        )
    }

    /// [`line_length`] of edge `edge`, `None` when a point cannot be projected.
    pub fn edge(&self, edge: usize, side: f32) -> Option<f32> {
        let indices = edge_indices(edge);
        let projects = indices.iter().all(|&i| self.projectable[i]);
        projects.then(|| self.length(indices, side))
    }
}

/// The edge spacings of an input patch: each edge measured afresh at level 0.
pub fn input_edges(screen: &ScreenPiece, side: f32) -> PieceEdges {
    std::array::from_fn(|edge| fresh_spacing(screen.edge(edge, side), 0, side))
}

/// The edge spacings of half `half` (0: the lower parameters) of a piece
/// split in `direction`, whose rectangle is `uv` and whose points are on
/// screen as `screen`: the two edges the split halves inherit the parent's
/// fixed spacings ([`halved_spacing`]), the edge on the new split line is
/// measured afresh, the fourth is the parent's.
pub fn split_edges(
    parent: &PieceEdges,
    direction: SplitDirection,
    half: usize,
    screen: &ScreenPiece,
    uv: Vec4,
    side: f32,
) -> PieceEdges {
    let (lu, lv) = (level(uv.z - uv.x), level(uv.w - uv.y));
    let measure = |edge| screen.edge(edge, side);
    let mut edges = *parent;
    let (halved, level_halved, split_line, level_split) = match direction {
        SplitDirection::U => ([EDGE_V0, EDGE_V1], lu, [EDGE_U1, EDGE_U0][half], lv),
        SplitDirection::V => ([EDGE_U0, EDGE_U1], lv, [EDGE_V1, EDGE_V0][half], lu),
    };
    for edge in halved {
        edges[edge] = halved_spacing(parent[edge], measure(edge), level_halved, side);
    }
    edges[split_line] = fresh_spacing(measure(split_line), level_split, side);
    edges
}

/// Rate dicing's grid for a projectable piece whose control points are on
/// screen as `screen`: along u, `nu` is [`rate_for`] the longest row's
/// [`line_length`], and at least the
/// micropolygons its two u edges' spacings put along them; likewise `nv`
/// with the columns. `None` in a direction whose edges are not fixed yet
/// or that needs more than [`MAX_GRID_QUADS`]: the piece
/// must be split across it.
pub fn rate_grid(
    screen: &ScreenPiece,
    edges: &PieceEdges,
    uv: Vec4,
    side: f32,
) -> (Option<u32>, Option<u32>) {
    let row = |k: usize| screen.length([4 * k, 4 * k + 1, 4 * k + 2, 4 * k + 3], side);
    let column = |k: usize| screen.length([k, 4 + k, 8 + k, 12 + k], side);
    let longest = |f: &dyn Fn(usize) -> f32| f(0).max(f(1)).max(f(2)).max(f(3));
    let direction = |length: f32, a: usize, b: usize, level: u32| -> Option<u32> {
        let need = rate_for(length, side)?;
        let n = need.max(edges[a].quads(level)?).max(edges[b].quads(level)?);
        (n <= MAX_GRID_QUADS).then_some(n)
    };
    (
        direction(longest(&row), EDGE_V0, EDGE_V1, level(uv.z - uv.x)),
        direction(longest(&column), EDGE_U0, EDGE_U1, level(uv.w - uv.y)),
    )
}

/// Whether a patch faces away from `eye` everywhere, for an object whose
/// front faces along `front * (dP/du x dP/dv)`. Conservative: with `a` the
/// 12 differences of neighbours along u, `b` those along v, every `P - eye`
/// a convex combination of `p - eye` over the control points and `dP/du x
/// dP/dv` a positive combination of the `a x b`, the patch is back-facing
/// (or edge-on) everywhere when `front * ((p - eye) x a) . b >= 0` for all
/// 2,304 triples.
pub fn back_facing(points: &[Vec3; 16], eye: HomogeneousEye, front: f32) -> bool {
    let along_u: [Vec3; 12] = std::array::from_fn(|k| {
        let (v, u) = (k / 3, k % 3);
        points[v * 4 + u + 1] - points[v * 4 + u]
    });
    let along_v: [Vec3; 12] = std::array::from_fn(|k| points[k + 4] - points[k]);
    points.iter().all(|&p| {
        // p - eye for a perspective camera, exactly.
        let r = -towards_eye(eye, p);
        along_u.iter().all(|&a| {
            let c = r.cross(a);
            along_v.iter().all(|&b| front * c.dot(b) >= 0.0)
        })
    })
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
///    the displacement bound, [`fits`] `dice_threshold` (and, for rate
///    dicing, [`rate_grid`] has a grid in both directions), else split (or
///    drop): for rate dicing across the one direction that has no grid, if
///    only one lacks it, else by the points' pixel-space extents.
#[expect(
    clippy::too_many_arguments,
    reason = "the reference mirrors the GPU's `decide`, input for input"
)]
pub fn bound(
    points: &[Vec3; 16],
    split_depth: u32,
    view_proj: &Mat4,
    camera: &Camera,
    dice_threshold: f32,
    max_split_depth: u32,
    growth: Growth<'_>,
    rule: DiceRule<'_>,
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

    // Every point projects here: pixels and growths for the box and the grid.
    let screen = ScreenPiece::from_clip(camera, &clip, displacement_bound);
    let pixels = screen.pixels;
    let (lo, hi) = pixels.iter().fold((pixels[0], pixels[0]), |(lo, hi), &p| {
        (lo.min(p), hi.max(p))
    });
    let growth = screen.growths.iter().fold(0.0f32, |g, &p| g.max(p));
    let size = hi - lo;
    let fits = fits(size.x.max(size.y), growth, dice_threshold);
    let (nu, nv) = match rule {
        DiceRule::Fixed => (Some(GridSize::FIXED.nu), Some(GridSize::FIXED.nv)),
        DiceRule::Rate { edges, uv, side } => rate_grid(&screen, edges, uv, side),
    };
    match (nu, nv) {
        (Some(nu), Some(nv)) if fits => BoundDecision::Dice(GridSize { nu, nv }),
        _ if split_depth >= max_split_depth => BoundDecision::Drop,
        (None, Some(_)) => BoundDecision::Split(SplitDirection::U),
        (Some(_), None) => BoundDecision::Split(SplitDirection::V),
        _ => BoundDecision::Split(split_direction_2d(&pixels)),
    }
}
