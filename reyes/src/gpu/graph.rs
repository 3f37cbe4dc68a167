//! The Reyes procedure graph: the work items, the four procedures, their
//! connections, the shared WGSL library (with the displacement sources),
//! the frame's user shaders and the extra resources.
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
//! reference are declared as graph constants from [`crate::params`] and
//! [`super::abi`] (see `shared_constants.rs`) so the two cannot drift apart.

use scheduler::{
    Atomic, CompileError, CompileOptions, CompiledGraph, Graph, Policy, Procedure, Resource,
};

use super::abi::POINT_WORDS;
use std::sync::Arc;

use crate::surface_shader::{SurfaceShader, megakernel_wgsl};
use super::buffers::{FrameUniform, LightData};
use super::objects::ObjectData;
use super::shadow_maps::{shadow_host_wgsl, shadow_wgsl};
use super::shared_constants::{grid_colors_wgsl, shared_constants};
use super::variant::{DepthTest, KernelVariant};
use crate::dicing::GridClass;

pub use super::abi::{dicing, displace, non_finite, sampling, stat};
pub use super::patch_item::{InputPatch, PatchItem};

/// The shared library, in the order it is declared: helpers, patch access
/// and projection; the bound test; evaluation and shading; packing,
/// sampling and rasterization.
const LIBRARY_WGSL: [&str; 7] = [
    include_str!("../../../shaders/reyes/library_math.wgsl"),
    include_str!("../../../shaders/reyes/library.wgsl"),
    include_str!("../../../shaders/reyes/library_bound.wgsl"),
    include_str!("../../../shaders/reyes/surface_api.wgsl"),
    include_str!("../../../shaders/reyes/library_shading.wgsl"),
    include_str!("../../../shaders/reyes/surfaces_standard.wgsl"),
    include_str!("../../../shaders/reyes/library_raster.wgsl"),
];
/// The depth test ([`KernelVariant::depth_test`] chooses): the nearest
/// key per sample as one 64-bit word or as two 32-bit words over two
/// passes, or the nearest and second-nearest depths.
const OFFER_WGSL: &str = include_str!("../../../shaders/reyes/offer.wgsl");
const OFFER_TWO_PASS_WGSL: &str = include_str!("../../../shaders/reyes/offer_two_pass.wgsl");
const OFFER_SECOND_DEPTH_WGSL: &str = include_str!("../../../shaders/reyes/offer_second_depth.wgsl");
const BOUND_WGSL: &str = include_str!("../../../shaders/reyes/bound.wgsl");
const SPLIT_WGSL: &str = include_str!("../../../shaders/reyes/split.wgsl");
const DICE_WGSL: &str = include_str!("../../../shaders/reyes/dice_shade_sample.wgsl");
const DICING_WGSL: &str = include_str!("../../../shaders/reyes/dicing.wgsl");
const DISPLACEMENT_WGSL: &str = include_str!("../../../shaders/reyes/displacement.wgsl");
const QUAD_WGSL: &str = include_str!("../../../shaders/reyes/quad.wgsl");
const RASTER5D_WGSL: &str = include_str!("../../../shaders/reyes/raster5d.wgsl");
/// The textures' host side (`host_texture` and the table accessors).
const TEXTURE_HOST_WGSL: &str = include_str!("../../../shaders/reyes/library_texture_host.wgsl");

/// `shadow()` of the surface shader interface (`ShadowId` and the
/// function), compiled in with user shaders only.
const SURFACE_API_SHADOW_WGSL: &str = include_str!("../../../shaders/reyes/surface_api_shadow.wgsl");

/// `host_shadow` of frames with user shaders but no shadow maps.
const NO_SHADOW_MAPS_HOST_WGSL: &str = "// No shadow maps: shadow() finds nothing in the way.
fn host_shadow(id: ShadowId, p: vec3<f32>) -> f32 {
    return 0.0;
}
";

/// `host_texture` and `host_environment` of frames without user shaders,
/// which alone sample textures.
const NO_TEXTURES_WGSL: &str = "// No user shaders: nothing samples a texture.
fn host_texture(index: u32, st: vec2<f32>, axis_a: vec2<f32>, axis_b: vec2<f32>) -> vec4<f32> {
    return vec4<f32>(0.0);
}
fn host_environment(index: u32, R: vec3<f32>, dRdu: vec3<f32>, dRdv: vec3<f32>) -> vec4<f32> {
    return vec4<f32>(0.0);
}
";

/// The user's WGSL a megakernel compiles in: the frame's surface and
/// displacement shaders (users' WGSL height functions among them,
/// [`crate::displacement::height_shader`]), in the order objects index
/// them.
#[derive(Debug, Clone, Copy, Default)]
pub struct UserCode<'a> {
    /// The surface and displacement shaders
    /// ([`crate::surface_shader::ShaderTable::shaders`]).
    pub surfaces: &'a [Arc<SurfaceShader>],
}

impl UserCode<'_> {
    /// No user code.
    pub const NONE: UserCode<'static> = UserCode { surfaces: &[] };
}

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

/// Features of the 64-bit depth test ([`DepthTest::Key64`]): 64-bit
/// integers for the sample keys and 64-bit `atomicMin`. Devices without
/// them render with [`DepthTest::TwoPass32`]
/// ([`KernelVariant::with_32_bit_atomics`]).
pub const WIDE_ATOMICS: wgpu::Features =
    wgpu::Features::SHADER_INT64.union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// The uniform that tells a [`DepthTest::TwoPass32`] megakernel which pass
/// it runs: [`DEPTH_PASS`] or [`COLOUR_PASS`].
pub const PASS_RESOURCE: &str = "depth_test_pass";
/// The pass of a [`DepthTest::TwoPass32`] frame that keeps each sample's
/// nearest depth.
pub const DEPTH_PASS: u32 = 0;
/// The pass of a [`DepthTest::TwoPass32`] frame that keeps, per sample,
/// the least colour at the nearest depth.
pub const COLOUR_PASS: u32 = 1;

/// Scratch words per item of each procedure (see the bodies' headers). The
/// split's 60 words times its 64 items per workgroup (15,360 bytes) are the
/// largest need and must stay within the 16 KiB of workgroup memory that
/// WebGPU guarantees, next to the scheduler's own words.
const BOUND_SCRATCH_WORDS: u32 = 5 * 16;
const SPLIT_SCRATCH_WORDS: u32 = 4 + 7 * 8;

/// The Reyes procedure graph of the default variant (the teapot's), with
/// the default (zero) user displacement function.
pub fn reyes_graph() -> Graph {
    reyes_graph_with(KernelVariant::default(), &UserCode::NONE)
}

/// The Reyes procedure graph of `variant` (its switches are graph
/// constants, so that specialization keeps only the code it runs) with the
/// frame's user shaders.
///
/// Priorities make the scheduler work depth-first (leaves first), which
/// keeps the split queues short: DiceShadeSample > SplitU = SplitV > Bound.
/// Fan-outs: Bound routes its one patch to exactly one target; a split
/// routes each of its two halves to one target, so at most 2 per target.
pub fn reyes_graph_with(variant: KernelVariant, user: &UserCode<'_>) -> Graph {
    // The renderer compiles with the default workgroup size
    // ([`compile_options`]); the dice slots follow from it.
    let workgroup_size = CompileOptions::default().workgroup_size;
    let mut graph = Graph::new("reyes");
    for (name, value) in shared_constants(workgroup_size) {
        graph.constant(name, value);
    }
    for (name, value) in variant.constants() {
        graph.constant(name, value);
    }
    graph.library(&grid_colors_wgsl());
    for part in LIBRARY_WGSL {
        graph.library(part);
    }
    // Only frames with shadow maps compile the lookup in.
    graph.library(&shadow_wgsl(variant.shadowed));
    match variant.depth_test {
        DepthTest::Key64 => graph.library(OFFER_WGSL),
        DepthTest::TwoPass32 => {
            for (name, value) in [("DEPTH_PASS", DEPTH_PASS), ("COLOUR_PASS", COLOUR_PASS)] {
                graph.constant(name, value);
            }
            graph.library(OFFER_TWO_PASS_WGSL)
        }
        DepthTest::SecondDepth => graph.library(OFFER_SECOND_DEPTH_WGSL),
    };
    graph.library(DICING_WGSL);
    graph.library(QUAD_WGSL);
    graph.library(RASTER5D_WGSL);
    graph.library(DISPLACEMENT_WGSL);
    if user.surfaces.is_empty() {
        graph.library(NO_TEXTURES_WGSL);
    } else {
        // Only user shaders sample textures and call noise.
        graph.library(&<crate::texture::TextureInfo as scheduler::Item>::wgsl_declarations());
        graph.library(crate::texture::TEXTURE_WGSL);
        graph.library(TEXTURE_HOST_WGSL);
        graph.library(&crate::noise::noise_wgsl());
        graph.library(SURFACE_API_SHADOW_WGSL);
        if variant.shadowed {
            graph.library(&shadow_host_wgsl());
        } else {
            graph.library(NO_SHADOW_MAPS_HOST_WGSL);
        }
    }
    graph.library(&megakernel_wgsl(user.surfaces));
    // Declaration order = binding order in group 1 (see `buffers.rs`).
    graph.resource(Resource::uniform::<FrameUniform>("frame"));
    graph.resource(Resource::storage_read::<[ObjectData]>("objects"));
    graph.resource(Resource::storage_read::<[LightData]>("lights"));
    // Without the 64-bit key, two 32-bit words per sample (the key's low and
    // high word, or the midpoint filter's two depths).
    graph.resource(Resource::storage_wgsl(
        "framebuffer",
        if variant.depth_test.uses_32_bit_words() {
            "array<atomic<u32>>"
        } else {
            "array<atomic<u64>>"
        },
    ));
    graph.resource(Resource::storage::<[Atomic<u32>]>("stats"));
    graph.resource(Resource::storage_read::<[f32]>("height_texels"));
    if variant.depth_test == DepthTest::TwoPass32 {
        // Last, so that the other resources keep their bindings.
        graph.resource(Resource::uniform::<u32>(PASS_RESOURCE));
    }
    let bound = graph.procedure(
        Procedure::of::<InputPatch>(BOUND)
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

/// Compile options of the default variant for a device with `features`:
/// the scheduler's recommended features plus [`WIDE_ATOMICS`]. Pass
/// `wgpu::Features::empty()` for the machine-independent module (as the
/// snapshot test does).
pub fn compile_options(recommended: wgpu::Features) -> CompileOptions {
    compile_options_for(recommended, KernelVariant::default())
}

/// Compile options of `variant` for a device with `features`: the
/// scheduler's recommended features plus what the variant's depth test
/// needs ([`KernelVariant::features`]).
pub fn compile_options_for(recommended: wgpu::Features, variant: KernelVariant) -> CompileOptions {
    CompileOptions::with_features(recommended | variant.features())
}

/// Compiles the Reyes graph of the default variant with [`compile_options`].
pub fn compile(recommended: wgpu::Features) -> Result<CompiledGraph, CompileError> {
    compile_variant(recommended, KernelVariant::default(), &UserCode::NONE)
}

/// Compiles the Reyes graph of `variant` with the frame's user shaders
/// (see [`reyes_graph_with`]).
pub fn compile_variant(
    recommended: wgpu::Features,
    variant: KernelVariant,
    user: &UserCode<'_>,
) -> Result<CompiledGraph, CompileError> {
    compile_for(recommended, variant, user, Policy::Priority, 1)
}

/// Like [`compile_variant`], with the given queue policy and chunks per
/// batch ([`CompileOptions::chunks_per_batch`]). The graph's priorities
/// (DiceShadeSample > SplitU = SplitV > Bound) count under
/// [`Policy::Priority`] only.
pub fn compile_for(
    recommended: wgpu::Features,
    variant: KernelVariant,
    user: &UserCode<'_>,
    policy: Policy,
    chunks_per_batch: u32,
) -> Result<CompiledGraph, CompileError> {
    compile_traced(
        recommended,
        variant,
        user,
        (policy, chunks_per_batch),
        None,
    )
}

/// Like [`compile_for`] (with its policy and chunks per batch), traced
/// when `trace` is given ([`CompileOptions::trace`]).
pub fn compile_traced(
    recommended: wgpu::Features,
    variant: KernelVariant,
    user: &UserCode<'_>,
    (policy, chunks_per_batch): (Policy, u32),
    trace: Option<scheduler::TraceOptions>,
) -> Result<CompiledGraph, CompileError> {
    let options = CompileOptions {
        policy,
        chunks_per_batch,
        trace,
        ..compile_options_for(recommended, variant)
    };
    reyes_graph_with(variant, user).compile(&options)
}
