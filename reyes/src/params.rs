//! Constants of the Reyes pipeline.
//!
//! The CPU reference renderer ([`crate::reference`]) and the GPU implementation
//! must use exactly these values, so that their statistics and images can be
//! compared. Each constant documents the pipeline stage that uses it.

/// Smallest clip-space `w` a point may have and still be projected.
///
/// The bound test splits (in object space) any patch with a control point at
/// `w <= NEAR_EPS`, and the rasterizer skips any micropolygon triangle with a
/// corner at `w <= NEAR_EPS`: dividing by a `w` this close to zero would give
/// meaningless pixel positions.
pub const NEAR_EPS: f32 = 1e-5;

/// Smallest squared distance a point light's falloff divides by: a surface
/// point (nearly) at the light gets the finite radiance `radiance / this`
/// instead of an infinity that a zero `n.L` would turn into NaN.
pub const POINT_LIGHT_MIN_DISTANCE_SQUARED: f32 = 1e-12;

/// Number of grid points along each side of a diced grid (16 x 16 points).
pub const GRID_POINTS: usize = 16;

/// Number of micropolygons along each side of a diced grid (15 x 15 quads).
pub const GRID_QUADS: usize = GRID_POINTS - 1;

/// Number of micropolygons in one diced grid (`GRID_QUADS * GRID_QUADS`).
pub const MICROPOLYGONS_PER_GRID: u64 = (GRID_QUADS * GRID_QUADS) as u64;

/// Default screen-space size (pixels) below which a patch is diced: a patch is
/// diced when the larger side of its projected control-point bounding box is
/// `<= dice_threshold`.
pub const DEFAULT_DICE_THRESHOLD: f32 = 16.0;

/// Default maximum number of splits from an input patch to a diced piece.
///
/// A patch that still needs splitting at this depth is dropped and counted in
/// `depth_guard_drops`; this bounds the work for patches that cross the eye
/// plane or never shrink (degenerate geometry).
pub const DEFAULT_MAX_SPLIT_DEPTH: u32 = 24;

/// Largest accepted `max_split_depth`: a depth above this could not be reached
/// in practice and would only hide a mistake in the scene file.
pub const MAX_SPLIT_DEPTH_LIMIT: u32 = 64;

/// Relative threshold of the degenerate-normal test: the normal
/// `n = dP/ds x dP/dt` is degenerate when
/// `|n|^2 <= DEGENERATE_NORMAL_REL_EPS * |dP/ds|^2 * |dP/dt|^2` (or `|n|^2 == 0`),
/// i.e. when the tangents are (nearly) parallel or one of them vanishes, as at
/// the collapsed edges of the teapot's lid and bottom.
pub const DEGENERATE_NORMAL_REL_EPS: f32 = 1e-12;

/// Lower clamp of the patch parameters `(s, t)` used to re-evaluate the
/// tangents when the normal is degenerate: moving slightly inside the patch
/// gets away from a collapsed edge, where the tangent vanishes.
pub const DEGENERATE_PARAM_MIN: f32 = 0.01;

/// Upper clamp of the patch parameters for the degenerate-normal fallback
/// (see [`DEGENERATE_PARAM_MIN`]).
pub const DEGENERATE_PARAM_MAX: f32 = 0.99;

/// Accepted samples-per-pixel counts. The samples of a pixel form a `k x k`
/// grid of strata (`k = sqrt(spp)`), so `spp` must be a perfect square; `k`
/// goes to 16 (256 samples): Sattlecker and Steinberger measure Simple UVT
/// up to 15 x 15, and McGuire et al. find defocus needs more than 64.
pub const VALID_SPP: [u32; 16] = [
    1, 4, 9, 16, 25, 36, 49, 64, 81, 100, 121, 144, 169, 196, 225, 256,
];

/// Multipliers of the jitter hash, one per input: pixel x, pixel y, sample
/// index, and channel (0 for the x offset, 1 for the y offset). See
/// [`crate::sampling::hash`].
pub const HASH_MULTIPLIERS: [u32; 4] = [0x8da6_b343, 0xd816_3841, 0xcb1a_b31f, 0x1656_67b1];

/// The two multipliers of the jitter hash's final mixing steps
/// (see [`crate::sampling::hash`]).
pub const HASH_MIX: [u32; 2] = [0x7feb_352d, 0x846c_a68b];

/// With a displacement bound, a piece's screen box grows by the bound's
/// projection `g` on every side, and the piece is diced when its undisplaced
/// box fits `dice_threshold - 2 g`. Splitting shrinks the surface but not
/// the growth, so the growth may take at most this fraction of the
/// threshold: the undisplaced box must fit
/// `max(dice_threshold - 2 g, dice_threshold * DISPLACED_DICE_FRACTION)`.
/// Without the floor a bound wider than a quarter of the threshold on screen
/// would split forever. Undisplaced objects have `g = 0`.
pub const DISPLACED_DICE_FRACTION: f32 = 0.5;

/// Relative tolerance of the displacement-bound check: a grid point counts in
/// `displacement_bound_exceeded` when `|height * scale| > bound * (1 + this)`,
/// so that a bilinear blend of texels that rounds one ulp above the largest
/// texel is not reported.
pub const DISPLACEMENT_BOUND_TOLERANCE: f32 = 1e-5;

/// Largest side of an accepted height map, in texels. With
/// [`MAX_DISPLACEMENT_TILING`] it keeps texel coordinates below 2^23, where
/// `f32` still holds every integer and both implementations pick the same texels.
pub const MAX_HEIGHT_MAP_SIDE: u32 = 4096;

/// Largest accepted displacement `tiling`.
pub const MAX_DISPLACEMENT_TILING: f32 = 1024.0;

/// Frequency of the second octave of the built-in `"sines"` heights.
pub const SINES_OCTAVE_2_FREQUENCY: f32 = 3.0;

/// Weight of the second octave of the built-in `"sines"` heights.
pub const SINES_OCTAVE_2_WEIGHT: f32 = 0.5;

/// Normalization of the built-in `"sines"` heights: `1 / (1 + weight)`, so
/// the largest `|height|` is exactly 1.
pub const SINES_NORMALIZATION: f32 = 2.0 / 3.0;

/// What placing a micropolygon at one time and lens position costs, in
/// sample tests, in Adaptive's cost model
/// (`reyes::reference::raster5d::adaptive_costs`): four corner positions
/// against one five-edge test, about the same work. On lavapipe it keeps
/// Adaptive at most 1% slower than the better mode in every cell of the
/// Killeroo check (docs/performance.md, "Adaptive with the cost model").
pub const ADAPTIVE_PLACE_COST: f32 = 1.0;

/// Default shading rate: the target area of a micropolygon in pixels
/// (RenderMan's `ShadingRate`), used by [`crate::scene::Dicing::Rate`].
pub const DEFAULT_SHADING_RATE: f32 = 1.0;

/// Largest accepted shading rate: micropolygons 32 pixels on a side. Larger
/// ones would make every grid a few quads that bbox sampling tests pixel by
/// pixel, beyond any use of a micropolygon renderer.
pub const MAX_SHADING_RATE: f32 = 1024.0;

/// Micropolygons along each side of the largest grid that dicing to a
/// shading rate makes (`nu`, `nv` are powers of two up to this); a piece
/// that needs more is split. The largest grid's points,
/// `(MAX_GRID_QUADS + 1)^2`, must fit the large dice procedure's scratch.
pub const MAX_GRID_QUADS: u32 = 16;

/// How far past a box the strata it touches are looked for, in pixels:
/// a sample's position is computed in f32 and may stray past its stratum
/// by a few ulps (at most about 0.002 pixels in a frame 16,384 pixels
/// wide). Shared by the reference's stratum boxes and the WGSL
/// `STRATUM_MARGIN`.
pub const STRATUM_MARGIN: f32 = 1.0 / 256.0;

/// Default host-side limit of one megakernel run, and the reference's
/// default time limit. It includes the driver's compilation of the pipeline
/// on its first dispatch, which lavapipe does lazily: over a minute for the
/// Reyes megakernel on a cold shader cache.
pub const DEFAULT_RENDER_TIMEOUT: std::time::Duration = std::time::Duration::from_secs(600);

/// The largest exponent of a highlight (`1 / roughness`): a smaller
/// roughness gives this one, a highlight of well under a pixel.
pub const MAX_SPECULAR_EXPONENT: f32 = 1.0e4;
