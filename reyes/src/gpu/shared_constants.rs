//! The constants the megakernel's WGSL shares with the CPU side
//! ([`crate::params`], the dicing, sampling and AOV codes, [`super::abi`]),
//! declared as graph constants so that the two cannot drift apart, and the
//! generated grid-colour table.

use scheduler::ConstantValue;

use super::abi::{
    PLANE_BITS, POINT_WORDS, UNPROJECTABLE, decide, dicing, displace, light, non_finite, sampling,
    stat, surface,
};
use crate::aov::Aov;
use crate::dicing::{
    EDGE_U0, EDGE_U1, EDGE_V0, EDGE_V1, EdgeSpacing, GridClass, GridSize, RATE_ROUNDING, pack_edges,
};
use crate::params::{
    ADAPTIVE_PLACE_COST, DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX, DEGENERATE_PARAM_MIN,
    DISPLACED_DICE_FRACTION, DISPLACEMENT_BOUND_TOLERANCE, HASH_MIX, HASH_MULTIPLIERS,
    MAX_GRID_QUADS, NEAR_EPS, POINT_LIGHT_MIN_DISTANCE_SQUARED, SINES_NORMALIZATION,
    SINES_OCTAVE_2_FREQUENCY, SINES_OCTAVE_2_WEIGHT, STRATUM_MARGIN,
};
use crate::uvt::TABLE_SIDE;

/// Items of the smallest dice procedure in one workgroup: the slots whose
/// grid extents `grid_extent` keeps.
fn dice_slots(workgroup_size: u32) -> u32 {
    workgroup_size / GridClass::Small.threads()
}

/// The WGSL constants shared with the CPU side ([`crate::params`] and
/// [`super::abi`]), each name stated next to its value so that no list of
/// positional arguments can pair them wrongly, in declaration order.
pub(super) fn shared_constants(workgroup_size: u32) -> Vec<(&'static str, ConstantValue)> {
    let [mx, my, ms, mc] = HASH_MULTIPLIERS;
    let [m0, m1] = HASH_MIX;
    // The same f32 value the reference multiplies with in
    // PreparedDisplacement::exceeds_bound.
    let bound_slack = 1.0f32 + DISPLACEMENT_BOUND_TOLERANCE;
    let tau = std::f32::consts::TAU;
    let fixed = GridSize::FIXED.nu;
    let [small, medium, large] = GridClass::ALL.map(|c| c.index());
    let (small_threads, small_points) = (GridClass::Small.threads(), GridClass::Small.max_points());
    let (medium_threads, medium_points) =
        (GridClass::Medium.threads(), GridClass::Medium.max_points());
    let slots = dice_slots(workgroup_size);
    let [aov_shaded, aov_grids, aov_depth, aov_normal] =
        [Aov::Shaded, Aov::Grids, Aov::Depth, Aov::Normal].map(Aov::code);
    let extent_words = 2 * slots;
    vec![
        ("NEAR_EPS", ConstantValue::F32(NEAR_EPS)),
        (
            "POINT_LIGHT_MIN_DISTANCE_SQUARED",
            ConstantValue::F32(POINT_LIGHT_MIN_DISTANCE_SQUARED),
        ),
        ("MAX_GRID_QUADS", ConstantValue::U32(MAX_GRID_QUADS)),
        ("FIXED_GRID_QUADS", ConstantValue::U32(fixed)),
        ("RATE_ROUNDING", ConstantValue::F32(RATE_ROUNDING)),
        ("EDGE_V0", index(EDGE_V0)),
        ("EDGE_V1", index(EDGE_V1)),
        ("EDGE_U0", index(EDGE_U0)),
        ("EDGE_U1", index(EDGE_U1)),
        (
            "EDGES_UNFIXED",
            ConstantValue::U32(pack_edges(&[EdgeSpacing::UNFIXED; 4])),
        ),
        ("DICING_FIXED", ConstantValue::U32(dicing::FIXED)),
        ("DICING_RATE", ConstantValue::U32(dicing::RATE)),
        ("GRID_CLASS_SMALL", index(small)),
        ("GRID_CLASS_MEDIUM", index(medium)),
        ("GRID_CLASS_LARGE", index(large)),
        (
            "GRID_CLASS_SMALL_THREADS",
            ConstantValue::U32(small_threads),
        ),
        ("GRID_CLASS_SMALL_POINTS", ConstantValue::U32(small_points)),
        (
            "GRID_CLASS_MEDIUM_THREADS",
            ConstantValue::U32(medium_threads),
        ),
        (
            "GRID_CLASS_MEDIUM_POINTS",
            ConstantValue::U32(medium_points),
        ),
        ("POINT_WORDS", ConstantValue::U32(POINT_WORDS)),
        ("DICE_SLOTS", ConstantValue::U32(slots)),
        ("GRID_EXTENT_WORDS", ConstantValue::U32(extent_words)),
        (
            "DEGENERATE_NORMAL_REL_EPS",
            ConstantValue::F32(DEGENERATE_NORMAL_REL_EPS),
        ),
        (
            "DEGENERATE_PARAM_MIN",
            ConstantValue::F32(DEGENERATE_PARAM_MIN),
        ),
        (
            "DEGENERATE_PARAM_MAX",
            ConstantValue::F32(DEGENERATE_PARAM_MAX),
        ),
        ("HASH_MUL_X", ConstantValue::U32(mx)),
        ("HASH_MUL_Y", ConstantValue::U32(my)),
        ("HASH_MUL_S", ConstantValue::U32(ms)),
        ("HASH_MUL_C", ConstantValue::U32(mc)),
        ("HASH_MIX_0", ConstantValue::U32(m0)),
        ("HASH_MIX_1", ConstantValue::U32(m1)),
        ("PLANE_BITS", ConstantValue::U32(PLANE_BITS)),
        ("UNPROJECTABLE", ConstantValue::U32(UNPROJECTABLE)),
        ("FLAGS_IDENTITY", ConstantValue::U32(PLANE_BITS)),
        ("DECIDE_CULL", ConstantValue::U32(decide::CULL)),
        ("DECIDE_DICE", ConstantValue::U32(decide::DICE)),
        ("DECIDE_SPLIT_U", ConstantValue::U32(decide::SPLIT_U)),
        ("DECIDE_SPLIT_V", ConstantValue::U32(decide::SPLIT_V)),
        ("DECIDE_DROP", ConstantValue::U32(decide::DROP)),
        ("SAMPLING_BBOX", ConstantValue::U32(sampling::BBOX)),
        ("SAMPLING_NEAREST", ConstantValue::U32(sampling::NEAREST)),
        ("SAMPLING_SIMPLE", ConstantValue::U32(sampling::SIMPLE)),
        (
            "SAMPLING_INTERLEAVE",
            ConstantValue::U32(sampling::INTERLEAVE),
        ),
        ("SAMPLING_INTERVAL", ConstantValue::U32(sampling::INTERVAL)),
        ("SAMPLING_ADAPTIVE", ConstantValue::U32(sampling::ADAPTIVE)),
        ("TABLE_SIDE", ConstantValue::U32(TABLE_SIDE)),
        (
            "ADAPTIVE_PLACE_COST",
            ConstantValue::F32(ADAPTIVE_PLACE_COST),
        ),
        ("STRATUM_MARGIN", ConstantValue::F32(STRATUM_MARGIN)),
        ("AOV_SHADED", ConstantValue::U32(aov_shaded)),
        ("AOV_GRIDS", ConstantValue::U32(aov_grids)),
        ("AOV_DEPTH", ConstantValue::U32(aov_depth)),
        ("AOV_NORMAL", ConstantValue::U32(aov_normal)),
        (
            "STAT_INPUT_PATCHES",
            ConstantValue::U32(stat::INPUT_PATCHES),
        ),
        ("STAT_SPLITS", ConstantValue::U32(stat::SPLITS)),
        ("STAT_CULLED", ConstantValue::U32(stat::CULLED)),
        (
            "STAT_DEPTH_GUARD_DROPS",
            ConstantValue::U32(stat::DEPTH_GUARD_DROPS),
        ),
        ("STAT_GRIDS_DICED", ConstantValue::U32(stat::GRIDS_DICED)),
        (
            "STAT_MICROPOLYGONS",
            ConstantValue::U32(stat::MICROPOLYGONS),
        ),
        (
            "STAT_SAMPLES_TESTED",
            ConstantValue::U32(stat::SAMPLES_TESTED),
        ),
        ("STAT_SAMPLES_HIT", ConstantValue::U32(stat::SAMPLES_HIT)),
        (
            "STAT_SAMPLES_SKIPPED",
            ConstantValue::U32(stat::SAMPLES_SKIPPED),
        ),
        (
            "STAT_LARGEST_MICROPOLYGON",
            ConstantValue::U32(stat::LARGEST_MICROPOLYGON),
        ),
        ("STAT_LOOPS_CUT", ConstantValue::U32(stat::LOOPS_CUT)),
        (
            "STAT_DISPLACEMENT_BOUND_EXCEEDED",
            ConstantValue::U32(stat::DISPLACEMENT_BOUND_EXCEEDED),
        ),
        (
            "STAT_INTERLEAVE_GRIDS",
            ConstantValue::U32(stat::INTERLEAVE_GRIDS),
        ),
        (
            "STAT_GRIDS_BY_CLASS",
            ConstantValue::U32(stat::GRIDS_BY_CLASS),
        ),
        ("STAT_DICE_THREADS", ConstantValue::U32(stat::DICE_THREADS)),
        ("STAT_NON_FINITE", ConstantValue::U32(stat::NON_FINITE)),
        (
            "NON_FINITE_DISPLACEMENT",
            ConstantValue::U32(non_finite::DISPLACEMENT),
        ),
        (
            "NON_FINITE_TRANSFORM",
            ConstantValue::U32(non_finite::TRANSFORM),
        ),
        ("NON_FINITE_CAMERA", ConstantValue::U32(non_finite::CAMERA)),
        ("SURFACE_CONSTANT", ConstantValue::U32(surface::CONSTANT)),
        ("SURFACE_MATTE", ConstantValue::U32(surface::MATTE)),
        ("SURFACE_METAL", ConstantValue::U32(surface::METAL)),
        ("SURFACE_PLASTIC", ConstantValue::U32(surface::PLASTIC)),
        ("SURFACE_USER", ConstantValue::U32(surface::USER)),
        (
            "MAX_SPECULAR_EXPONENT",
            ConstantValue::F32(crate::params::MAX_SPECULAR_EXPONENT),
        ),
        (
            "SURFACE_DEFAULT_SURFACE",
            ConstantValue::U32(surface::DEFAULT_SURFACE),
        ),
        ("LIGHT_DISTANT", ConstantValue::U32(light::DISTANT)),
        ("LIGHT_POINT", ConstantValue::U32(light::POINT)),
        ("LIGHT_SPOT", ConstantValue::U32(light::SPOT)),
        ("DISPLACE_NONE", ConstantValue::U32(displace::NONE)),
        ("DISPLACE_IMAGE", ConstantValue::U32(displace::IMAGE)),
        ("DISPLACE_SINES", ConstantValue::U32(displace::SINES)),
        ("DISPLACE_SHADER", ConstantValue::U32(displace::SHADER)),
        (
            "DISPLACED_DICE_FRACTION",
            ConstantValue::F32(DISPLACED_DICE_FRACTION),
        ),
        ("DISPLACEMENT_BOUND_SLACK", ConstantValue::F32(bound_slack)),
        ("TAU", ConstantValue::F32(tau)),
        (
            "SINES_OCTAVE_2_FREQUENCY",
            ConstantValue::F32(SINES_OCTAVE_2_FREQUENCY),
        ),
        (
            "SINES_OCTAVE_2_WEIGHT",
            ConstantValue::F32(SINES_OCTAVE_2_WEIGHT),
        ),
        (
            "SINES_NORMALIZATION",
            ConstantValue::F32(SINES_NORMALIZATION),
        ),
    ]
}

/// A `usize` index (an edge, a grid class) as a WGSL `u32` constant.
fn index(i: usize) -> ConstantValue {
    ConstantValue::U32(u32::try_from(i).expect("indices are small"))
}

/// The WGSL `grid_color(quads, i, j)`: [`crate::aov::grid_color`], its
/// table generated from [`crate::aov::grid_colors`].
pub(super) fn grid_colors_wgsl() -> String {
    let colors: Vec<String> = crate::aov::grid_colors()
        .iter()
        .map(|c| format!("{c:#x}u"))
        .collect();
    format!(
        "// reyes::aov::grid_color: entry 2 * floor(log2(quads)) + checker.
fn grid_color(quads: u32, i: u32, j: u32) -> u32 {{
    var colors = array<u32, {}>({});
    let size = min(31u - countLeadingZeros(max(quads, 1u)), 8u);
    return colors[2u * size + ((i + j) & 1u)];
}}
",
        colors.len(),
        colors.join(", ")
    )
}
