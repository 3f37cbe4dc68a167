//! The Reyes procedure graph: the work item, the four procedures, their
//! connections, the shared WGSL library and the extra resources.
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
    CompileError, CompileOptions, CompiledGraph, Graph, Procedure, Resource, item_type,
};

use crate::params::{
    DEGENERATE_NORMAL_REL_EPS, DEGENERATE_PARAM_MAX, DEGENERATE_PARAM_MIN, GRID_POINTS, GRID_QUADS,
    HASH_MIX, HASH_MULTIPLIERS, NEAR_EPS,
};
use crate::prepare::WorldPatch;

const PATCH_ITEM_WGSL: &str = include_str!("../../../shaders/reyes/patch_item.wgsl");
const LIBRARY_WGSL: &str = include_str!("../../../shaders/reyes/library.wgsl");
const BOUND_WGSL: &str = include_str!("../../../shaders/reyes/bound.wgsl");
const SPLIT_U_WGSL: &str = include_str!("../../../shaders/reyes/split_u.wgsl");
const SPLIT_V_WGSL: &str = include_str!("../../../shaders/reyes/split_v.wgsl");
const DICE_WGSL: &str = include_str!("../../../shaders/reyes/dice_shade_sample.wgsl");

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

/// Scratch words per item of each procedure (see the bodies' headers).
const BOUND_SCRATCH_WORDS: u32 = 3 * 16;
const SPLIT_SCRATCH_WORDS: u32 = 8 + 6 * 8;
const DICE_SCRATCH_WORDS: u32 = 7 * (GRID_POINTS * GRID_POINTS) as u32;

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
    /// Words in the buffer.
    pub const WORDS: u32 = 13;
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
",
        decide::CULL,
        decide::DICE,
        decide::SPLIT_U,
        decide::SPLIT_V,
        decide::DROP,
        sampling::BBOX,
        sampling::NEAREST,
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
    )
}

/// The Reyes procedure graph.
///
/// Priorities make the scheduler work depth-first (leaves first), which
/// keeps the split queues short: DiceShadeSample > SplitU = SplitV > Bound.
/// Fan-outs: Bound routes its one patch to exactly one target; a split
/// routes each of its two halves to one target, so at most 2 per target.
pub fn reyes_graph() -> Graph {
    let patch = item_type!(
        PatchItem,
        PATCH_ITEM_WGSL,
        [p, uv, object, split_depth, pad0, pad1]
    );
    let mut graph = Graph::new("reyes");
    graph.library(&constants_wgsl());
    graph.library(LIBRARY_WGSL);
    // Declaration order = binding order in group 1 (see `buffers.rs`).
    graph.resource(Resource::uniform("frame", "Frame"));
    graph.resource(Resource::storage_read("objects", "array<vec4<f32>>"));
    graph.resource(Resource::storage_read("lights", "array<Light>"));
    graph.resource(Resource::storage("framebuffer", "array<atomic<u64>>"));
    graph.resource(Resource::storage("stats", "array<atomic<u32>>"));
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
            .body(SPLIT_U_WGSL),
    );
    graph.procedure(
        Procedure::new(SPLIT_V, patch.clone())
            .threads_per_item(4)
            .scratch_bytes(4 * SPLIT_SCRATCH_WORDS)
            .priority(1)
            .body(SPLIT_V_WGSL),
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

/// Compile options for a device with `features`: the scheduler's recommended
/// features plus [`REQUIRED_FEATURES`]. Pass `wgpu::Features::empty()` for
/// the machine-independent module (as the snapshot test does).
pub fn compile_options(recommended: wgpu::Features) -> CompileOptions {
    CompileOptions::with_features(recommended | REQUIRED_FEATURES)
}

/// Compiles the Reyes graph with [`compile_options`].
pub fn compile(recommended: wgpu::Features) -> Result<CompiledGraph, CompileError> {
    reyes_graph().compile(&compile_options(recommended))
}
