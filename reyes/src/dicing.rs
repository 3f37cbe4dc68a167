//! Dicing to a shading rate: grid sizes from projected lengths, the
//! canonical vertices of every edge, and the grid classes the GPU packs.
//!
//! Every piece is a dyadic rectangle `(u0, v0, u1, v1)` of its input patch
//! (splits halve it), so each of its four edges is a dyadic interval of an
//! isoparametric line of the patch. An edge's vertices are not chosen by
//! the piece but by the edge: each edge carries an [`EdgeSpacing`], a
//! power-of-two vertex spacing along its line, that is a function of the
//! edge's own curve and of nothing else, and that its halves inherit once
//! it is set. The two pieces on either side of an edge therefore agree on
//! its vertices whatever their split depths, and evaluate them at the same
//! exact `(u, v)` of the same input patch ([`patch_position`]). Grid
//! points on a border between two of its edge's vertices are moved onto the
//! chord between them ([`BorderPoint`]), which the neighbour draws as one
//! micropolygon edge. The argument is written out in `docs/reyes.md`
//! ("Watertight dicing"). The GPU twin is `shaders/reyes/dicing.wgsl`.

use glam::{Vec2, Vec3};

use crate::bezier;
use crate::params::MAX_GRID_QUADS;

mod rule;
pub use rule::DicingRule;

/// The four edges of a piece, in the order of [`PieceEdges`]: the `v = v0`
/// row, the `v = v1` row (both along u), the `u = u0` column and the
/// `u = u1` column (both along v).
pub const EDGE_V0: usize = 0;
/// See [`EDGE_V0`].
pub const EDGE_V1: usize = 1;
/// See [`EDGE_V0`].
pub const EDGE_U0: usize = 2;
/// See [`EDGE_V0`].
pub const EDGE_U1: usize = 3;

/// The indices (`v * 4 + u`) of edge `edge`'s four control points, from
/// its `(u0, v0)` end.
pub fn edge_indices(edge: usize) -> [usize; 4] {
    match edge {
        EDGE_V0 => [0, 1, 2, 3],
        EDGE_V1 => [12, 13, 14, 15],
        EDGE_U0 => [0, 4, 8, 12],
        _ => [3, 7, 11, 15],
    }
}

/// The vertex spacing of one edge along its line: `2^-e` in the input
/// patch's parameter, or not yet fixed (the edge is longer than the largest
/// grid side: any piece that has it must split across it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct EdgeSpacing(u8);

impl EdgeSpacing {
    /// Not fixed yet.
    pub const UNFIXED: EdgeSpacing = EdgeSpacing(0);

    /// A spacing of `2^-exponent`.
    pub fn fixed(exponent: u32) -> EdgeSpacing {
        debug_assert!(exponent < 255);
        EdgeSpacing(exponent as u8 + 1)
    }

    /// `e` of a spacing `2^-e`, or `None` when not fixed.
    pub fn exponent(self) -> Option<u32> {
        (self.0 != 0).then(|| u32::from(self.0) - 1)
    }

    /// The code in a packed word (0: unfixed, else `e + 1`).
    pub fn code(self) -> u32 {
        u32::from(self.0)
    }

    /// Micropolygon edges this spacing puts along an edge of length
    /// `2^-level`: `2^(e - level)`, or 0 when the spacing is wider than the
    /// edge (every border point is then on a chord), `None` when unfixed.
    pub fn quads(self, level: u32) -> Option<u32> {
        let e = self.exponent()?;
        Some(if e >= level { 1 << (e - level) } else { 0 })
    }
}

/// The spacings of a piece's four edges, indexed by [`EDGE_V0`] etc.
pub type PieceEdges = [EdgeSpacing; 4];

/// Packs a piece's edges into one word, edge `k` in bits `8k..8k+8` (the
/// work item's `edges` field).
pub fn pack_edges(edges: &PieceEdges) -> u32 {
    edges
        .iter()
        .enumerate()
        .fold(0, |word, (k, e)| word | (e.code() << (8 * k)))
}

/// The inverse of [`pack_edges`].
pub fn unpack_edges(word: u32) -> PieceEdges {
    std::array::from_fn(|k| EdgeSpacing(((word >> (8 * k)) & 0xff) as u8))
}

/// The level `l` of a dyadic extent `2^-l` (a piece's `u1 - u0`), read from
/// its exponent bits so that both implementations get it exactly.
pub fn level(extent: f32) -> u32 {
    127u32.saturating_sub((extent.to_bits() >> 23) & 0xff)
}

/// `2^e` exactly, for `-126 <= e <= 127`, built from its bits.
pub fn exp2i(e: i32) -> f32 {
    f32::from_bits(((127 + e) as u32) << 23)
}

/// The micropolygons along a curve of projected `length`: the power of two
/// nearest `length / side` in ratio (the smallest `n >= 1` with
/// `n * RATE_ROUNDING >= length / side`), so that micropolygons are
/// `side / sqrt 2 .. side * sqrt 2` long; `None` when that exceeds
/// [`MAX_GRID_QUADS`] or the length is not finite.
pub fn rate_for(length: f32, side: f32) -> Option<u32> {
    let x = length / side;
    if !x.is_finite() {
        return None;
    }
    let mut n = 1u32;
    while (n as f32) * RATE_ROUNDING < x {
        n *= 2;
        if n > MAX_GRID_QUADS {
            return None;
        }
    }
    Some(n)
}

/// The rounding of [`rate_for`]: `sqrt 2`, the geometric middle between
/// two powers of two.
pub const RATE_ROUNDING: f32 = std::f32::consts::SQRT_2;

/// The estimated projected length of a cubic from its control points:
/// the mean of its chord and its control polygon (Gravesen's estimate; the
/// arc lies between the two), each summed so that the reversed curve gives
/// the same bits (two pieces may see a shared edge in opposite directions):
/// `0.5 * (|p3 - p0| + ((|p1 - p0| + |p3 - p2|) + |p2 - p1|))`.
pub fn polygon_length(p: [Vec2; 4]) -> f32 {
    let polygon = (p[0].distance(p[1]) + p[2].distance(p[3])) + p[1].distance(p[2]);
    0.5 * (p[0].distance(p[3]) + polygon)
}

/// The spacing of an edge that no ancestor fixed: from its own projected
/// control polygon (`None` when a control point cannot be projected), at
/// `level` (its length along its line is `2^-level`). Fixed as
/// `2^-(level + log2 n)` when [`rate_for`] gives `n`.
pub fn fresh_spacing(length: Option<f32>, level: u32, side: f32) -> EdgeSpacing {
    match length.and_then(|l| rate_for(l, side)) {
        Some(n) => EdgeSpacing::fixed(level + n.trailing_zeros()),
        None => EdgeSpacing::UNFIXED,
    }
}

/// A halved edge: it keeps its parent's spacing once that is fixed (so the
/// neighbour that still sees the whole edge keeps the same vertices), else
/// it is measured afresh.
pub fn halved_spacing(
    parent: EdgeSpacing,
    length: Option<f32>,
    level: u32,
    side: f32,
) -> EdgeSpacing {
    if parent.exponent().is_some() {
        parent
    } else {
        fresh_spacing(length, level, side)
    }
}

/// A grid of `nu x nv` micropolygons (`(nu + 1) x (nv + 1)` points).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct GridSize {
    /// Micropolygons along u.
    pub nu: u32,
    /// Micropolygons along v.
    pub nv: u32,
}

impl GridSize {
    /// The fixed dicer's grid: 16 x 16 points.
    pub const FIXED: GridSize = GridSize { nu: 15, nv: 15 };

    /// Micropolygons.
    pub fn quads(self) -> u32 {
        self.nu * self.nv
    }

    /// Grid points.
    pub fn points(self) -> u32 {
        (self.nu + 1) * (self.nv + 1)
    }

    /// The smallest dice procedure that holds the grid.
    pub fn class(self) -> GridClass {
        GridClass::ALL
            .into_iter()
            .find(|c| self.quads() <= c.threads() && self.points() <= c.max_points())
            .unwrap_or(GridClass::Large)
    }
}

/// The dice procedures, by the grids they hold: one thread per
/// micropolygon, and every grid point evaluated by some thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GridClass {
    /// Up to 16 micropolygons and 27 points (4 x 4, 8 x 2, 8 x 1, ...): 16 threads.
    Small,
    /// Up to 64 micropolygons (8 x 8, 16 x 4, ...): 64 threads.
    Medium,
    /// Up to 256 micropolygons (16 x 16, and the fixed 15 x 15): 256 threads.
    Large,
}

impl GridClass {
    /// Every class, smallest first (the order of the statistics).
    pub const ALL: [GridClass; 3] = [GridClass::Small, GridClass::Medium, GridClass::Large];

    /// Threads per item of its dice procedure.
    pub fn threads(self) -> u32 {
        match self {
            GridClass::Small => 16,
            GridClass::Medium => 64,
            GridClass::Large => 256,
        }
    }

    /// Grid points its scratch holds.
    pub fn max_points(self) -> u32 {
        match self {
            GridClass::Small => 27,
            GridClass::Medium => 85,
            GridClass::Large => (MAX_GRID_QUADS + 1) * (MAX_GRID_QUADS + 1),
        }
    }

    /// Index in [`GridClass::ALL`].
    pub fn index(self) -> usize {
        self as usize
    }
}

/// Evaluates a cubic `c(t)` as `((c0 w0 + c1 w1) + c2 w2) + c3 w3`.
fn curve(c: [Vec3; 4], t: f32) -> Vec3 {
    let w = bezier::bernstein(t);
    ((c[0] * w[0] + c[1] * w[1]) + c[2] * w[2]) + c[3] * w[3]
}

/// Whether `a < b` in (x, y, z) order.
fn lexicographic_less(a: Vec3, b: Vec3) -> bool {
    a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)))
}

/// A cubic evaluated from its lexicographically smaller end: the reversed
/// curve at `1 - t` when `c3 < c0`. Two patches that share a boundary curve
/// but run along it in opposite directions get the same bits (for the
/// dyadic `t` of rate dicing, `1 - t` is exact).
pub fn curve_canonical(c: [Vec3; 4], t: f32) -> Vec3 {
    if lexicographic_less(c[3], c[0]) {
        curve([c[3], c[2], c[1], c[0]], 1.0 - t)
    } else {
        curve(c, t)
    }
}

/// The position of an input patch at `(u, v)`: on the patch's boundary the
/// boundary curve's [`curve_canonical`] (so that neighbouring patches with
/// the same boundary control points agree to the bit), elsewhere the tensor
/// product ([`bezier::position`]).
pub fn patch_position(patch: &[Vec3; 16], u: f32, v: f32) -> Vec3 {
    if u == 0.0 || u == 1.0 {
        let c = if u == 0.0 { 0 } else { 3 };
        return curve_canonical([patch[c], patch[4 + c], patch[8 + c], patch[12 + c]], v);
    }
    if v == 0.0 || v == 1.0 {
        let r = if v == 0.0 { 0 } else { 12 };
        return curve_canonical([patch[r], patch[r + 1], patch[r + 2], patch[r + 3]], u);
    }
    bezier::position(patch, u, v)
}

/// Where a grid point on a piece's border goes: at its own `(u, v)`, on
/// the chord between the two vertices of its edge around it (a corner), or
/// at the nearer of those vertices (any other border point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BorderPoint {
    /// A vertex of its edge (or an interior point): evaluated in place.
    Vertex,
    /// A corner of the piece between the edge's vertices at `a` and `b`
    /// (each a `(u, v)`), at fraction `f` of the way from `a`.
    Chord {
        /// The vertex below.
        a: (f32, f32),
        /// The vertex above.
        b: (f32, f32),
        /// Fraction from `a` to `b`.
        f: f32,
    },
    /// A point inside an edge, between two of its vertices: evaluated at
    /// the nearer vertex `at` (the upper one at the middle).
    Snapped {
        /// The vertex's `(u, v)`.
        at: (f32, f32),
    },
}

/// Places grid point `(i, j)`, at `(u, v)`, of a piece diced at `grid` on
/// its edges' vertices: the first edge (in [`EDGE_V0`] order) through the
/// point whose spacing does not have it as a vertex moves it. (At most one
/// can: a piece's corner is always a vertex of the later-made of its two
/// lines, whose first segment ends there.)
///
/// A point inside the edge (a finer grid's extra point at a T-junction, or
/// any point of an edge shorter than its spacing) snaps to the nearer of
/// the two vertices around it, which the neighbour across evaluates at the
/// same `(u, v)` to the same bits. Why not onto the chord between them:
/// the neighbour draws that chord as one micropolygon edge, and a point
/// placed on it in floating point lies a rounding off it, so the two sides'
/// edge functions no longer cancel exactly and a sample on the chord (it
/// happens: a pixel short of one sample in about one of a hundred random
/// 400 x 300 views at 16 spp, `tests/tests/reyes_watertight_random.rs`)
/// falls between them. Snapped, the finer side's border is made of the very
/// vertices of the coarser side's edge, and its micropolygons there
/// degenerate to triangles (whose zero-area halves draw nothing).
///
/// A corner moves onto the chord instead: snapping it would move it up
/// to half a chord away from where the pieces along its other line, which
/// evaluate it in place as a vertex, expect it.
pub fn border_point(
    grid: GridSize,
    edges: &PieceEdges,
    i: u32,
    j: u32,
    u: f32,
    v: f32,
) -> BorderPoint {
    let on_edge = [j == 0, j == grid.nv, i == 0, i == grid.nu];
    let corner = (on_edge[0] || on_edge[1]) && (on_edge[2] || on_edge[3]);
    for (k, &on) in on_edge.iter().enumerate() {
        let Some(e) = edges[k].exponent().filter(|_| on) else {
            continue;
        };
        let along_u = k < EDGE_U0;
        let q = if along_u { u } else { v };
        let scaled = q * exp2i(e.cast_signed());
        let below = scaled.floor();
        if below == scaled {
            continue;
        }
        let h = exp2i(-e.cast_signed());
        let (q0, q1) = (below * h, (below + 1.0) * h);
        let f = scaled - below;
        let (a, b) = if along_u {
            ((q0, v), (q1, v))
        } else {
            ((u, q0), (u, q1))
        };
        if corner {
            return BorderPoint::Chord { a, b, f };
        }
        return BorderPoint::Snapped {
            at: if f < 0.5 { a } else { b },
        };
    }
    BorderPoint::Vertex
}

/// The point at fraction `f` of the chord from `a` to `b`: `a + (b - a) f`.
pub fn chord_point(a: Vec3, b: Vec3, f: f32) -> Vec3 {
    a + (b - a) * f
}

/// The parameter of grid line `i` of `n` across `[a, b]`: `a + (b - a) * (i / n)`.
pub fn grid_param(a: f32, b: f32, i: u32, n: u32) -> f32 {
    a + (b - a) * (i as f32 / n as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::fresh_rng;
    use rand::Rng;

    #[test]
    fn spacings_pack_and_round_trip() {
        let edges = [
            EdgeSpacing::UNFIXED,
            EdgeSpacing::fixed(0),
            EdgeSpacing::fixed(7),
            EdgeSpacing::fixed(40),
        ];
        assert_eq!(unpack_edges(pack_edges(&edges)), edges);
        assert_eq!(EdgeSpacing::fixed(7).quads(3), Some(16));
        assert_eq!(EdgeSpacing::fixed(7).quads(9), Some(0));
        assert_eq!(EdgeSpacing::UNFIXED.quads(0), None);
    }

    #[test]
    fn levels_and_powers_of_two_are_exact() {
        for l in 0..40 {
            assert_eq!(level(exp2i(-l)), l as u32);
            assert_eq!(exp2i(-l), 2f32.powi(-l));
        }
    }

    #[test]
    fn rates_are_the_nearest_power_of_two_up_to_the_largest_grid() {
        assert_eq!(rate_for(0.0, 1.0), Some(1));
        assert_eq!(rate_for(1.4, 1.0), Some(1));
        assert_eq!(rate_for(1.5, 1.0), Some(2));
        assert_eq!(rate_for(22.5, 1.0), Some(16));
        assert_eq!(rate_for(22.7, 1.0), None);
        assert_eq!(rate_for(8.0, 2.0), Some(4));
        assert_eq!(rate_for(f32::NAN, 1.0), None);
        assert_eq!(rate_for(f32::INFINITY, 1.0), None);
    }

    #[test]
    fn reversed_curves_give_the_same_bits() {
        let (seed, mut rng) = fresh_rng("reversed_curves_give_the_same_bits");
        for _ in 0..1000 {
            let c: [Vec3; 4] = std::array::from_fn(|_| {
                Vec3::new(rng.random(), rng.random(), rng.random()) * 10.0 - 5.0
            });
            let reversed = [c[3], c[2], c[1], c[0]];
            let k = rng.random_range(0..=64u32);
            let t = k as f32 / 64.0;
            assert_eq!(
                curve_canonical(c, t),
                curve_canonical(reversed, 1.0 - t),
                "seed {seed}"
            );
            let pixels = c.map(|p| p.truncate());
            let back = reversed.map(|p| p.truncate());
            assert_eq!(polygon_length(pixels), polygon_length(back), "seed {seed}");
        }
    }

    #[test]
    fn grids_go_to_the_smallest_class_that_holds_them() {
        let class = |nu, nv| GridSize { nu, nv }.class();
        assert_eq!(class(1, 1), GridClass::Small);
        assert_eq!(class(4, 4), GridClass::Small);
        assert_eq!(class(8, 1), GridClass::Small);
        assert_eq!(class(8, 2), GridClass::Small);
        assert_eq!(class(16, 1), GridClass::Medium);
        assert_eq!(class(8, 8), GridClass::Medium);
        assert_eq!(class(16, 4), GridClass::Medium);
        assert_eq!(class(16, 8), GridClass::Large);
        assert_eq!(class(16, 16), GridClass::Large);
        assert_eq!(GridSize::FIXED.class(), GridClass::Large);
        for nu in [1, 2, 4, 8, 16] {
            for nv in [1, 2, 4, 8, 16] {
                let g = GridSize { nu, nv };
                assert!(g.quads() <= g.class().threads() && g.points() <= g.class().max_points());
            }
        }
    }

    #[test]
    fn border_points_between_vertices_snap_and_corners_go_on_the_chord() {
        let uv = [0.5, 0.25, 0.75, 0.5];
        let grid = GridSize { nu: 4, nv: 2 };
        // Edge v0 with spacing 1/8 (a quarter of the piece's width of 1/4
        // has two vertices): points 1 and 3 of 4 lie between vertices.
        let edges = [
            EdgeSpacing::fixed(3),
            EdgeSpacing::fixed(4),
            EdgeSpacing::fixed(2),
            EdgeSpacing::fixed(2),
        ];
        let at = |i: u32, j: u32| {
            let u = grid_param(uv[0], uv[2], i, grid.nu);
            let v = grid_param(uv[1], uv[3], j, grid.nv);
            border_point(grid, &edges, i, j, u, v)
        };
        assert_eq!(at(0, 0), BorderPoint::Vertex);
        assert_eq!(at(2, 0), BorderPoint::Vertex);
        // Inside the edge, halfway between vertices: snapped to the upper.
        assert_eq!(at(1, 0), BorderPoint::Snapped { at: (0.625, 0.25) });
        // The top edge has spacing 1/16: every point of 4 is a vertex.
        for i in 0..=4 {
            assert_eq!(at(i, 2), BorderPoint::Vertex);
        }
        // The columns have spacing 1/4, the piece's whole height: the middle
        // point (v = 0.375) snaps to the upper corner.
        assert_eq!(at(0, 1), BorderPoint::Snapped { at: (0.5, 0.5) });
        // Interior points are never moved.
        assert_eq!(at(2, 1), BorderPoint::Vertex);
        // Edge v0 with spacing 1, wider than the piece: its corner moves
        // onto the chord, its other points snap to the nearer vertex.
        let wide = [EdgeSpacing::fixed(0), edges[1], edges[2], edges[3]];
        let at_wide = |i: u32, j: u32| {
            let u = grid_param(uv[0], uv[2], i, grid.nu);
            let v = grid_param(uv[1], uv[3], j, grid.nv);
            border_point(grid, &wide, i, j, u, v)
        };
        assert_eq!(
            at_wide(0, 0),
            BorderPoint::Chord {
                a: (0.0, 0.25),
                b: (1.0, 0.25),
                f: 0.5
            }
        );
        assert_eq!(at_wide(1, 0), BorderPoint::Snapped { at: (1.0, 0.25) });
    }
}
