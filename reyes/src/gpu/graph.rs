//! The Reyes procedure graph: the work item, the four procedures, their
//! connections, the shared WGSL library (with the displacement sources and
//! the scene's user displacement function) and the extra resources.
//!
//! ```text
//!   Bound (16 threads, initial) --+--> SplitU (4 threads) --+
//!                                 +--> SplitV (4 threads) --+--> SplitU / SplitV / DiceShadeSample*
//!                                 +--> DiceShadeSample16  (16 threads: grids up to 16 micropolygons)
//!                                 +--> DiceShadeSample64  (64 threads: up to 64)
//!                                 +--> DiceShadeSample256 (256 threads: up to 256)
//! ```
//!
//! Bound and Split route each piece to the smallest dice procedure whose
//! items hold its grid ([`crate::dicing::GridClass`]), so one workgroup
//! dices 16 small pieces, or 4 medium ones, at once.
//!
//! The WGSL lives in `shaders/reyes/`; the constants it shares with the CPU
//! reference are generated here from [`crate::params`] so the two cannot
//! drift apart.

use scheduler::{
    Atomic, CompileError, CompileOptions, CompiledGraph, ConstantValue, Graph, Policy, Procedure,
    Resource,
};

use super::buffers::{FrameUniform, LightData};
use super::objects::ObjectData;
use crate::aov::Aov;
use crate::dicing::{
    EDGE_U0, EDGE_U1, EDGE_V0, EDGE_V1, GridClass, GridSize, RATE_ROUNDING, pack_edges,
};
use crate::params::{
    ADAPTIVE_PLACE_COST, DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX, DEGENERATE_PARAM_MIN,
    DISPLACED_DICE_FRACTION, DISPLACEMENT_BOUND_TOLERANCE, HASH_MIX, HASH_MULTIPLIERS,
    MAX_GRID_QUADS, NEAR_EPS, POINT_LIGHT_MIN_DISTANCE_SQUARED, SINES_NORMALIZATION,
    SINES_OCTAVE_2_FREQUENCY, SINES_OCTAVE_2_WEIGHT,
};
use crate::prepare::WorldPatch;
use crate::reference::quad::STRATUM_MARGIN;
use crate::uvt::{INTERLEAVE_PERIOD, INTERLEAVE_PERMUTATIONS, PERMUTATION_CHANNEL, TABLE_SIDE};

const LIBRARY_WGSL: &str = include_str!("../../../shaders/reyes/library.wgsl");
const BOUND_WGSL: &str = include_str!("../../../shaders/reyes/bound.wgsl");
const SPLIT_WGSL: &str = include_str!("../../../shaders/reyes/split.wgsl");
const DICE_WGSL: &str = include_str!("../../../shaders/reyes/dice_shade_sample.wgsl");
const DICING_WGSL: &str = include_str!("../../../shaders/reyes/dicing.wgsl");
const DISPLACEMENT_WGSL: &str = include_str!("../../../shaders/reyes/displacement.wgsl");
const QUAD_WGSL: &str = include_str!("../../../shaders/reyes/quad.wgsl");
const RASTER5D_WGSL: &str = include_str!("../../../shaders/reyes/raster5d.wgsl");
/// The `displacement_user` of scenes without a user function (returns 0).
pub const DEFAULT_USER_DISPLACEMENT_WGSL: &str =
    include_str!("../../../shaders/reyes/displacement_user_default.wgsl");

/// Procedure names (also the names of their queues in a [`scheduler::RunReport`]).
pub const BOUND: &str = "Bound";
/// See [`BOUND`].
pub const SPLIT_U: &str = "SplitU";
/// See [`BOUND`].
pub const SPLIT_V: &str = "SplitV";
/// The dice procedures, by [`GridClass`] (see [`dice_procedure`]).
pub const DICE: [&str; 3] = [
    "DiceShadeSample16",
    "DiceShadeSample64",
    "DiceShadeSample256",
];

/// The dice procedure of grids of `class`.
pub fn dice_procedure(class: GridClass) -> &'static str {
    DICE[class.index()]
}

/// Features the Reyes megakernel needs: 64-bit integers for the sample keys
/// and 64-bit `atomicMin` for the depth test.
pub const REQUIRED_FEATURES: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// Scratch words per item of each procedure (see the bodies' headers). The
/// split's 60 words times its 64 items per workgroup (15,360 bytes) are the
/// largest need and must stay within the 16 KiB of workgroup memory that
/// WebGPU guarantees, next to the scheduler's own words.
const BOUND_SCRATCH_WORDS: u32 = 5 * 16;
const SPLIT_SCRATCH_WORDS: u32 = 4 + 7 * 8;
/// Scratch words per grid point of the dice procedures (see
/// `dice_shade_sample.wgsl`): open px, py, depth, clip w, packed colour,
/// close px, py, depth, clip w. Their items hold `POINT_WORDS *
/// class.max_points()` words: 16 small items take 3,888 words.
const POINT_WORDS: u32 = 9;

/// Items of the smallest dice procedure in one workgroup: the slots whose
/// grid extents `grid_extent` keeps.
fn dice_slots(workgroup_size: u32) -> u32 {
    workgroup_size / GridClass::Small.threads()
}

/// Indices into the statistics buffer (`array<atomic<u32>>`). 64-bit
/// counters take two words (low, high).
pub mod stat {
    /// Input patches (Bound items).
    pub const INPUT_PATCHES: u32 = 0;
    /// Split decisions.
    pub const SPLITS: u32 = 1;
    /// Culled pieces.
    pub const CULLED: u32 = 2;
    /// Pieces dropped by the split-depth guard.
    pub const DEPTH_GUARD_DROPS: u32 = 3;
    /// Grids diced.
    pub const GRIDS_DICED: u32 = 4;
    /// Micropolygons (64-bit: words 5, 6).
    pub const MICROPOLYGONS: u32 = 5;
    /// Samples tested (64-bit: words 7, 8).
    pub const SAMPLES_TESTED: u32 = 7;
    /// Samples hit (64-bit: words 9, 10).
    pub const SAMPLES_HIT: u32 = 9;
    /// Bits of the largest micropolygon side in pixels (an f32 >= 0).
    pub const LARGEST_MICROPOLYGON: u32 = 11;
    /// Rasterization loops the driver ended early (must stay 0).
    pub const LOOPS_CUT: u32 = 12;
    /// Displaced grid points that left their object's displacement bound.
    pub const DISPLACEMENT_BOUND_EXCEEDED: u32 = 13;
    /// Grids sampled with Interleave UVT.
    pub const INTERLEAVE_GRIDS: u32 = 14;
    /// Grids diced per class (words 15, 16, 17: small, medium, large).
    pub const GRIDS_BY_CLASS: u32 = 15;
    /// Threads of the dice items (64-bit: words 18, 19).
    pub const DICE_THREADS: u32 = 18;
    /// Grid points whose position turned infinite or NaN, by the stage that
    /// turned it (words 20, 21, 22: [`super::non_finite`]'s displacement,
    /// transform, camera).
    pub const NON_FINITE: u32 = 20;
    /// Samples a box's loop reached and skipped untested (64-bit: words
    /// 23, 24).
    pub const SAMPLES_SKIPPED: u32 = 23;
    /// Words in the buffer.
    pub const WORDS: u32 = 25;
}

/// The stages that can turn a grid point's position non-finite, as bits of
/// the per-point mask of `dice_shade_sample.wgsl`; bit `b` is counted in
/// stats word [`stat::NON_FINITE`] + `b`, as [`crate::nonfinite::Source`]
/// orders them.
pub mod non_finite {
    /// The displacement (height times scale, or the displaced point).
    pub const DISPLACEMENT: u32 = 1 << crate::nonfinite::Source::Displacement as u32;
    /// The object's transform (the patch evaluated at a finite
    /// transform's points near the `f32` limit, or the shutter-close motion).
    pub const TRANSFORM: u32 = 1 << crate::nonfinite::Source::Transform as u32;
    /// The camera (clip or pixel position of a finite world position).
    pub const CAMERA: u32 = 1 << crate::nonfinite::Source::Camera as u32;
}

/// Displacement sources, as [`super::objects::ObjectData::displace_kind`]
/// encodes them.
pub mod displace {
    /// No displacement.
    pub const NONE: u32 = 0;
    /// A height map in the `height_texels` buffer.
    pub const IMAGE: u32 = 1;
    /// The built-in sines.
    pub const SINES: u32 = 2;
    /// The user's WGSL `displacement_user`.
    pub const USER: u32 = 3;
}

/// Dicing modes, as the frame uniform encodes them.
pub mod dicing {
    /// [`crate::scene::Dicing::Fixed`].
    pub const FIXED: u32 = 0;
    /// [`crate::scene::Dicing::Rate`].
    pub const RATE: u32 = 1;

    /// The code of `dicing`.
    pub fn code(dicing: crate::scene::Dicing) -> u32 {
        match dicing {
            crate::scene::Dicing::Fixed => FIXED,
            crate::scene::Dicing::Rate => RATE,
        }
    }
}

/// Bound decisions, as the WGSL `decide` returns them.
mod decide {
    pub const CULL: u32 = 0;
    pub const DICE: u32 = 1;
    pub const SPLIT_U: u32 = 2;
    pub const SPLIT_V: u32 = 3;
    pub const DROP: u32 = 4;
}

/// Sampling modes, as the frame uniform encodes them.
pub mod sampling {
    /// Bounding-box sampling of the two triangles.
    pub const BBOX: u32 = 0;
    /// The sample nearest the micropolygon's centroid.
    pub const NEAREST: u32 = 1;
    /// Simple UVT.
    pub const SIMPLE: u32 = 2;
    /// Interleave UVT.
    pub const INTERLEAVE: u32 = 3;
    /// INTERVAL.
    pub const INTERVAL: u32 = 4;
    /// Adaptive (INTERVAL or Interleave UVT per grid).
    pub const ADAPTIVE: u32 = 5;

    /// The code of `mode`.
    pub fn code(mode: crate::scene::Sampling) -> u32 {
        use crate::scene::Sampling;
        match mode {
            Sampling::Bbox => BBOX,
            Sampling::Nearest => NEAREST,
            Sampling::Simple => SIMPLE,
            Sampling::Interleave => INTERLEAVE,
            Sampling::Interval => INTERVAL,
            Sampling::Adaptive => ADAPTIVE,
        }
    }
}

/// The work item of Bound, SplitU, SplitV and DiceShadeSample: one (piece
/// of a) bicubic Bezier patch, WGSL struct `PatchItem`.
#[scheduler::item]
#[derive(Debug, PartialEq)]
pub struct PatchItem {
    /// The 16 world-space control points, point `v * 4 + u` at words
    /// `3 * (v * 4 + u) .. + 3`. Flat f32 words rather than vec3 because a
    /// vec3 array would pad every point to 16 bytes.
    pub p: [f32; 48],
    /// The piece's rectangle (u0, v0, u1, v1) in the input patch's parameters.
    pub uv: glam::Vec4,
    /// Index into `objects`.
    pub object: u32,
    /// Splits from the input patch to this piece (the depth guard's input).
    pub split_depth: u32,
    /// Index of the input patch, whose control points rate dicing evaluates.
    pub input_patch: u32,
    /// The spacings of the piece's four edges (dicing.wgsl,
    /// reyes::dicing::pack_edges), 8 bits each.
    pub edges: u32,
    /// The grid Bound or Split chose: nu | nv << 8.
    pub grid: u32,
    /// Padding to the struct's 16-byte alignment.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
    /// Padding.
    pub pad2: u32,
}

impl PatchItem {
    /// Input patch `index`: the whole parameter square at split depth 0
    /// (Bound measures its edges and grid).
    pub fn input(patch: &WorldPatch, index: u32) -> Self {
        let mut p = [0.0; 48];
        for (i, point) in patch.points.iter().enumerate() {
            p[3 * i..3 * i + 3].copy_from_slice(&point.to_array());
        }
        Self {
            p,
            uv: glam::Vec4::new(0.0, 0.0, 1.0, 1.0),
            object: patch.object,
            split_depth: 0,
            input_patch: index,
            edges: pack_edges(&[Default::default(); 4]),
            grid: 0,
            pad0: 0,
            pad1: 0,
            pad2: 0,
        }
    }
}

/// Bits of a point's clip-plane flags (WGSL only: they never leave the GPU).
const PLANE_BITS: u32 = 0x3f;
/// The flag of a point behind the near plane.
const UNPROJECTABLE: u32 = 0x100;

/// The WGSL constants shared with the CPU side ([`crate::params`] and this
/// module), each name stated next to its value so that no list of
/// positional arguments can pair them wrongly, in declaration order.
fn shared_constants(workgroup_size: u32) -> Vec<(&'static str, ConstantValue)> {
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
        (
            "INTERLEAVE_PERMUTATIONS",
            ConstantValue::U32(INTERLEAVE_PERMUTATIONS),
        ),
        (
            "PERMUTATION_CHANNEL",
            ConstantValue::U32(PERMUTATION_CHANNEL),
        ),
        ("TABLE_SIDE", ConstantValue::U32(TABLE_SIDE)),
        ("INTERLEAVE_PERIOD", ConstantValue::U32(INTERLEAVE_PERIOD)),
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
        ("DISPLACE_NONE", ConstantValue::U32(displace::NONE)),
        ("DISPLACE_IMAGE", ConstantValue::U32(displace::IMAGE)),
        ("DISPLACE_SINES", ConstantValue::U32(displace::SINES)),
        ("DISPLACE_USER", ConstantValue::U32(displace::USER)),
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

/// The WGSL declarations of [`shared_constants`] (written as
/// [`ConstantValue`] writes graph constants) and the grid colours.
fn constants_wgsl(workgroup_size: u32) -> String {
    let mut text = String::from("// Generated from reyes::params and reyes::gpu::graph.\n");
    for (name, value) in shared_constants(workgroup_size) {
        let literal = value
            .wgsl_literal()
            .expect("the shared constants are finite");
        text.push_str(&format!(
            "const {name}: {} = {literal};\n",
            value.wgsl_type()
        ));
    }
    text + &grid_colors_wgsl()
}

/// The WGSL `grid_color(quads, i, j)`: [`crate::aov::grid_color`], its
/// table generated from [`crate::aov::grid_colors`].
fn grid_colors_wgsl() -> String {
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

/// The Reyes procedure graph, with the default (zero) user displacement function.
pub fn reyes_graph() -> Graph {
    reyes_graph_with(None)
}

/// The Reyes procedure graph with the scene's user displacement function
/// (WGSL defining `fn displacement_user(u: f32, v: f32) -> f32`), or the
/// default one for `None`.
///
/// Priorities make the scheduler work depth-first (leaves first), which
/// keeps the split queues short: DiceShadeSample > SplitU = SplitV > Bound.
/// Fan-outs: Bound routes its one patch to exactly one target; a split
/// routes each of its two halves to one target, so at most 2 per target.
pub fn reyes_graph_with(user_displacement: Option<&str>) -> Graph {
    // The renderer compiles with the default workgroup size
    // ([`compile_options`]); the dice slots follow from it.
    let workgroup_size = CompileOptions::default().workgroup_size;
    let mut graph = Graph::new("reyes");
    graph.library(&constants_wgsl(workgroup_size));
    graph.library(LIBRARY_WGSL);
    graph.library(DICING_WGSL);
    graph.library(QUAD_WGSL);
    graph.library(RASTER5D_WGSL);
    graph.library(DISPLACEMENT_WGSL);
    graph.library(user_displacement.unwrap_or(DEFAULT_USER_DISPLACEMENT_WGSL));
    // Declaration order = binding order in group 1 (see `buffers.rs`).
    graph.resource(Resource::uniform::<FrameUniform>("frame"));
    graph.resource(Resource::storage_read::<[ObjectData]>("objects"));
    graph.resource(Resource::storage_read::<[LightData]>("lights"));
    graph.resource(Resource::storage_wgsl("framebuffer", "array<atomic<u64>>"));
    graph.resource(Resource::storage::<[Atomic<u32>]>("stats"));
    graph.resource(Resource::storage_read::<[f32]>("height_texels"));
    let bound = graph.procedure(
        Procedure::of::<PatchItem>(BOUND)
            .initial(true)
            .threads_per_item(16)
            .scratch_bytes(4 * BOUND_SCRATCH_WORDS)
            .priority(0)
            .body(BOUND_WGSL),
    );
    let split_u = graph.procedure(
        Procedure::of::<PatchItem>(SPLIT_U)
            .threads_per_item(4)
            .scratch_bytes(4 * SPLIT_SCRATCH_WORDS)
            .priority(1)
            .body(split_body(true)),
    );
    let split_v = graph.procedure(
        Procedure::of::<PatchItem>(SPLIT_V)
            .threads_per_item(4)
            .scratch_bytes(4 * SPLIT_SCRATCH_WORDS)
            .priority(1)
            .body(split_body(false)),
    );
    let mut targets = vec![split_u.clone(), split_v.clone()];
    for class in GridClass::ALL {
        targets.push(
            graph.procedure(
                Procedure::of::<PatchItem>(dice_procedure(class))
                    .threads_per_item(class.threads())
                    .scratch_bytes(4 * POINT_WORDS * class.max_points())
                    .priority(2)
                    .body(dice_body(class)),
            ),
        );
    }
    for target in &targets {
        graph.connect_with_fan_out(&bound, target, 1);
        graph.connect_with_fan_out(&split_u, target, 2);
        graph.connect_with_fan_out(&split_v, target, 2);
    }
    graph
}

/// The body of the dice procedure of `class`: the shared dice body with its
/// thread count prepended.
fn dice_body(class: GridClass) -> String {
    format!("let DICE_THREADS = {}u;\n{DICE_WGSL}", class.threads())
}

/// The body of SplitU (`along_u`) or SplitV: the shared split body with its
/// direction prepended.
fn split_body(along_u: bool) -> String {
    format!("let along_u = {along_u};\n{SPLIT_WGSL}")
}

/// Compile options for a device with `features`: the scheduler's recommended
/// features plus [`REQUIRED_FEATURES`]. Pass `wgpu::Features::empty()` for
/// the machine-independent module (as the snapshot test does).
pub fn compile_options(recommended: wgpu::Features) -> CompileOptions {
    CompileOptions::with_features(recommended | REQUIRED_FEATURES)
}

/// Compiles the Reyes graph with [`compile_options`].
pub fn compile(recommended: wgpu::Features) -> Result<CompiledGraph, CompileError> {
    compile_with(recommended, None)
}

/// Compiles the Reyes graph with a user displacement function (see
/// [`reyes_graph_with`]).
pub fn compile_with(
    recommended: wgpu::Features,
    user_displacement: Option<&str>,
) -> Result<CompiledGraph, CompileError> {
    compile_for(recommended, user_displacement, Policy::Priority, 1)
}

/// Like [`compile_with`], with the given queue policy and chunks per batch
/// ([`CompileOptions::chunks_per_batch`]). The graph's priorities
/// (DiceShadeSample > SplitU = SplitV > Bound) count under
/// [`Policy::Priority`] only.
pub fn compile_for(
    recommended: wgpu::Features,
    user_displacement: Option<&str>,
    policy: Policy,
    chunks_per_batch: u32,
) -> Result<CompiledGraph, CompileError> {
    let options = CompileOptions {
        policy,
        chunks_per_batch,
        ..compile_options(recommended)
    };
    reyes_graph_with(user_displacement).compile(&options)
}
