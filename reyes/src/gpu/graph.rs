//! The Reyes procedure graph: the work item, the four procedures, their
//! connections, the shared WGSL library (with the displacement sources and
//! the scene's user displacement function) and the extra resources.
//!
//! ```text
//!   Bound (16 threads, initial) --+--> SplitU (4 threads) --+
//!                                 +--> SplitV (4 threads) --+--> SplitU / SplitV / DiceShadeSample
//!                                 +--> DiceShadeSample (256 threads)
//! ```
//!
//! The WGSL lives in `shaders/reyes/`; the constants it shares with the CPU
//! reference are generated here from [`crate::params`] so the two cannot
//! drift apart.

use scheduler::{
    CompileError, CompileOptions, CompiledGraph, Graph, Policy, Procedure, Resource, item_type,
};

use crate::params::{
    ADAPTIVE_INTERLEAVE_BIAS, DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX,
    DEGENERATE_PARAM_MIN, DISPLACED_DICE_FRACTION, DISPLACEMENT_BOUND_TOLERANCE, GRID_POINTS,
    GRID_QUADS, HASH_MIX, HASH_MULTIPLIERS, NEAR_EPS, SINES_NORMALIZATION,
    SINES_OCTAVE_2_FREQUENCY, SINES_OCTAVE_2_WEIGHT,
};
use crate::prepare::WorldPatch;
use crate::uvt::{INTERLEAVE_PERMUTATIONS, INTERLEAVE_TILE, PERMUTATION_CHANNEL, TABLE_SIDE};

const PATCH_ITEM_WGSL: &str = include_str!("../../../shaders/reyes/patch_item.wgsl");
const LIBRARY_WGSL: &str = include_str!("../../../shaders/reyes/library.wgsl");
const BOUND_WGSL: &str = include_str!("../../../shaders/reyes/bound.wgsl");
const SPLIT_WGSL: &str = include_str!("../../../shaders/reyes/split.wgsl");
const DICE_WGSL: &str = include_str!("../../../shaders/reyes/dice_shade_sample.wgsl");
const DISPLACEMENT_WGSL: &str = include_str!("../../../shaders/reyes/displacement.wgsl");
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
/// See [`BOUND`].
pub const DICE: &str = "DiceShadeSample";

/// Features the Reyes megakernel needs: 64-bit integers for the sample keys
/// and 64-bit `atomicMin` for the depth test.
pub const REQUIRED_FEATURES: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// Scratch words per item of each procedure (see the bodies' headers). The
/// split's 60 words times its 64 items per workgroup (15,360 bytes) are the
/// largest need and must stay within the 16 KiB of workgroup memory that
/// WebGPU guarantees, next to the scheduler's own words.
const BOUND_SCRATCH_WORDS: u32 = 4 * 16;
const SPLIT_SCRATCH_WORDS: u32 = 4 + 7 * 8;
const DICE_SCRATCH_WORDS: u32 = (3 + 3 + 8) * (GRID_POINTS * GRID_POINTS) as u32;

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
    /// Words in the buffer.
    pub const WORDS: u32 = 15;
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

/// The work item of every procedure; twin of `shaders/reyes/patch_item.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PatchItem {
    /// Control points in world space, `p[3 * (v * 4 + u) ..][..3]`.
    pub p: [f32; 48],
    /// `(u0, v0, u1, v1)` within the input patch's parameter square.
    pub uv: [f32; 4],
    /// Object index.
    pub object: u32,
    /// Splits from the input patch.
    pub split_depth: u32,
    /// Padding to the WGSL struct's 16-byte alignment.
    pub pad0: u32,
    /// Padding.
    pub pad1: u32,
}

impl PatchItem {
    /// An input patch: the whole parameter square at split depth 0.
    pub fn input(patch: &WorldPatch) -> Self {
        let mut p = [0.0; 48];
        for (i, point) in patch.points.iter().enumerate() {
            p[3 * i..3 * i + 3].copy_from_slice(&point.to_array());
        }
        Self {
            p,
            uv: [0.0, 0.0, 1.0, 1.0],
            object: patch.object,
            split_depth: 0,
            pad0: 0,
            pad1: 0,
        }
    }
}

/// WGSL constants shared with the CPU side, generated from [`crate::params`].
fn constants_wgsl() -> String {
    let [mx, my, ms, mc] = HASH_MULTIPLIERS;
    let [m0, m1] = HASH_MIX;
    // The same f32 value the reference multiplies with in
    // PreparedDisplacement::exceeds_bound.
    let bound_slack = 1.0f32 + DISPLACEMENT_BOUND_TOLERANCE;
    let tau = std::f32::consts::TAU;
    format!(
        "// Generated from reyes::params and reyes::gpu::graph.
const NEAR_EPS: f32 = {NEAR_EPS:e};
const GRID_POINTS: u32 = {GRID_POINTS}u;
const GRID_QUADS: u32 = {GRID_QUADS}u;
const DEGENERATE_NORMAL_REL_EPS: f32 = {DEGENERATE_NORMAL_REL_EPS:e};
const DEGENERATE_PARAM_MIN: f32 = {DEGENERATE_PARAM_MIN:?};
const DEGENERATE_PARAM_MAX: f32 = {DEGENERATE_PARAM_MAX:?};
const HASH_MUL_X: u32 = {mx:#x}u;
const HASH_MUL_Y: u32 = {my:#x}u;
const HASH_MUL_S: u32 = {ms:#x}u;
const HASH_MUL_C: u32 = {mc:#x}u;
const HASH_MIX_0: u32 = {m0:#x}u;
const HASH_MIX_1: u32 = {m1:#x}u;
const PLANE_BITS: u32 = 0x3fu;
const UNPROJECTABLE: u32 = 0x100u;
const FLAGS_IDENTITY: u32 = PLANE_BITS;
const DECIDE_CULL: u32 = {}u;
const DECIDE_DICE: u32 = {}u;
const DECIDE_SPLIT_U: u32 = {}u;
const DECIDE_SPLIT_V: u32 = {}u;
const DECIDE_DROP: u32 = {}u;
const SAMPLING_BBOX: u32 = {}u;
const SAMPLING_NEAREST: u32 = {}u;
const SAMPLING_SIMPLE: u32 = {}u;
const SAMPLING_INTERLEAVE: u32 = {}u;
const SAMPLING_INTERVAL: u32 = {}u;
const SAMPLING_ADAPTIVE: u32 = {}u;
const INTERLEAVE_TILE: u32 = {INTERLEAVE_TILE}u;
const INTERLEAVE_PERMUTATIONS: u32 = {INTERLEAVE_PERMUTATIONS}u;
const PERMUTATION_CHANNEL: u32 = {PERMUTATION_CHANNEL}u;
const TABLE_SIDE: u32 = {TABLE_SIDE}u;
const ADAPTIVE_INTERLEAVE_BIAS: f32 = {ADAPTIVE_INTERLEAVE_BIAS:?};
const STAT_INPUT_PATCHES: u32 = {}u;
const STAT_SPLITS: u32 = {}u;
const STAT_CULLED: u32 = {}u;
const STAT_DEPTH_GUARD_DROPS: u32 = {}u;
const STAT_GRIDS_DICED: u32 = {}u;
const STAT_MICROPOLYGONS: u32 = {}u;
const STAT_SAMPLES_TESTED: u32 = {}u;
const STAT_SAMPLES_HIT: u32 = {}u;
const STAT_LARGEST_MICROPOLYGON: u32 = {}u;
const STAT_LOOPS_CUT: u32 = {}u;
const STAT_DISPLACEMENT_BOUND_EXCEEDED: u32 = {}u;
const STAT_INTERLEAVE_GRIDS: u32 = {}u;
const DISPLACE_NONE: u32 = {}u;
const DISPLACE_IMAGE: u32 = {}u;
const DISPLACE_SINES: u32 = {}u;
const DISPLACE_USER: u32 = {}u;
const DISPLACED_DICE_FRACTION: f32 = {DISPLACED_DICE_FRACTION:?};
const DISPLACEMENT_BOUND_SLACK: f32 = {bound_slack:?};
const TAU: f32 = {tau:?};
const SINES_OCTAVE_2_FREQUENCY: f32 = {SINES_OCTAVE_2_FREQUENCY:?};
const SINES_OCTAVE_2_WEIGHT: f32 = {SINES_OCTAVE_2_WEIGHT:?};
const SINES_NORMALIZATION: f32 = {SINES_NORMALIZATION:?};
",
        decide::CULL,
        decide::DICE,
        decide::SPLIT_U,
        decide::SPLIT_V,
        decide::DROP,
        sampling::BBOX,
        sampling::NEAREST,
        sampling::SIMPLE,
        sampling::INTERLEAVE,
        sampling::INTERVAL,
        sampling::ADAPTIVE,
        stat::INPUT_PATCHES,
        stat::SPLITS,
        stat::CULLED,
        stat::DEPTH_GUARD_DROPS,
        stat::GRIDS_DICED,
        stat::MICROPOLYGONS,
        stat::SAMPLES_TESTED,
        stat::SAMPLES_HIT,
        stat::LARGEST_MICROPOLYGON,
        stat::LOOPS_CUT,
        stat::DISPLACEMENT_BOUND_EXCEEDED,
        stat::INTERLEAVE_GRIDS,
        displace::NONE,
        displace::IMAGE,
        displace::SINES,
        displace::USER,
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
    let patch = item_type!(
        PatchItem,
        PATCH_ITEM_WGSL,
        [p, uv, object, split_depth, pad0, pad1]
    );
    let mut graph = Graph::new("reyes");
    graph.library(&constants_wgsl());
    graph.library(LIBRARY_WGSL);
    graph.library(RASTER5D_WGSL);
    graph.library(DISPLACEMENT_WGSL);
    graph.library(user_displacement.unwrap_or(DEFAULT_USER_DISPLACEMENT_WGSL));
    // Declaration order = binding order in group 1 (see `buffers.rs`).
    graph.resource(Resource::uniform("frame", "Frame"));
    graph.resource(Resource::storage_read("objects", "array<Object>"));
    graph.resource(Resource::storage_read("lights", "array<Light>"));
    graph.resource(Resource::storage("framebuffer", "array<atomic<u64>>"));
    graph.resource(Resource::storage("stats", "array<atomic<u32>>"));
    graph.resource(Resource::storage_read("height_texels", "array<f32>"));
    graph.procedure(
        Procedure::new(BOUND, patch.clone())
            .initial(true)
            .threads_per_item(16)
            .scratch_bytes(4 * BOUND_SCRATCH_WORDS)
            .priority(0)
            .body(BOUND_WGSL),
    );
    graph.procedure(
        Procedure::new(SPLIT_U, patch.clone())
            .threads_per_item(4)
            .scratch_bytes(4 * SPLIT_SCRATCH_WORDS)
            .priority(1)
            .body(split_body(true)),
    );
    graph.procedure(
        Procedure::new(SPLIT_V, patch.clone())
            .threads_per_item(4)
            .scratch_bytes(4 * SPLIT_SCRATCH_WORDS)
            .priority(1)
            .body(split_body(false)),
    );
    graph.procedure(
        Procedure::new(DICE, patch)
            .threads_per_item(256)
            .scratch_bytes(4 * DICE_SCRATCH_WORDS)
            .priority(2)
            .body(DICE_WGSL),
    );
    for target in [SPLIT_U, SPLIT_V, DICE] {
        graph.connect_with_fan_out(BOUND, target, 1);
        graph.connect_with_fan_out(SPLIT_U, target, 2);
        graph.connect_with_fan_out(SPLIT_V, target, 2);
    }
    graph
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
