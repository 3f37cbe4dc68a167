//! Every kind of WGSL module the workspace hands to wgpu, generated here by
//! name: the test graphs under each option set, the example workloads, the
//! Reyes megakernel in every variant (with and without a user's function),
//! and the Reyes clear-and-resolve pass. `generated_wgsl` validates the
//! graphs' modules with naga; `shader_languages` puts every module through
//! naga's SPIR-V, MSL, HLSL and GLSL writers.

use scheduler::{CompileOptions, Graph, Policy, TraceOptions, wgpu};

use crate::graphs::{binary_tree, ping_pong, scratch_sum};

/// One generated module.
#[derive(Debug, Clone)]
pub struct GeneratedModule {
    /// What it is: the graph or variant, and its options.
    pub name: String,
    /// The WGSL text, as wgpu receives it.
    pub wgsl: String,
    /// The device features it is compiled for.
    pub features: wgpu::Features,
}

/// The small test graphs of the scheduler's own tests.
pub fn test_graphs() -> Vec<(&'static str, Graph)> {
    vec![
        ("binary_tree", binary_tree(6).graph),
        ("scratch_sum", scratch_sum().graph),
        ("ping_pong", ping_pong(5).graph),
        // Joins: generated only for a graph that declares them.
        ("tree_sum_joins", workloads::tree_sum::graph(None).graph),
    ]
}

/// The compile options the generated-code tests cover.
pub fn option_sets() -> Vec<(&'static str, CompileOptions)> {
    vec![
        ("atomic payload", CompileOptions::default()),
        (
            "coherent payload",
            CompileOptions::with_features(wgpu::Features::MEMORY_DECORATION_COHERENT),
        ),
        (
            "round robin",
            CompileOptions {
                policy: Policy::RoundRobin,
                ..CompileOptions::default()
            },
        ),
        (
            "workgroup 64",
            CompileOptions {
                workgroup_size: 64,
                ..CompileOptions::default()
            },
        ),
        (
            "4 chunks per batch",
            CompileOptions {
                chunks_per_batch: 4,
                ..CompileOptions::with_features(wgpu::Features::MEMORY_DECORATION_COHERENT)
            },
        ),
        (
            "traced",
            CompileOptions::default().traced(TraceOptions { capacity: 1024 }),
        ),
    ]
}

impl GeneratedModule {
    /// What naga's validator must allow for it (as the scheduler's compile
    /// decides it, [`scheduler::validation_capabilities`]).
    pub fn capabilities(&self) -> naga::valid::Capabilities {
        scheduler::validation_capabilities(self.features)
    }
}

/// A user's displacement (height) function, as a scene would give it.
pub const USER_HEIGHT: &str =
    "fn displacement_user(u: f32, v: f32) -> f32 {\n    return 0.1 * sin(6.0 * u) * v;\n}\n";

/// Every module: the test graphs under every option set, the examples, the
/// Reyes variants without and with a user's function, and the resolve pass.
pub fn all() -> Vec<GeneratedModule> {
    let mut modules = Vec::new();
    for (graph_name, graph) in test_graphs() {
        for (options_name, options) in option_sets() {
            let compiled = graph
                .compile(&options)
                .unwrap_or_else(|e| panic!("{graph_name} / {options_name} compiles: {e}"));
            modules.push(GeneratedModule {
                name: format!("{graph_name} / {options_name}"),
                wgsl: compiled.wgsl().to_owned(),
                features: options.features,
            });
        }
    }
    modules.extend(examples());
    modules.extend(reyes_variants());
    modules.push(GeneratedModule {
        name: "reyes resolve".into(),
        wgsl: reyes::gpu::resolve::resolve_wgsl(),
        features: wgpu::Features::empty(),
    });
    modules
}

/// The example workloads' megakernels, at small problem sizes.
pub fn examples() -> Vec<GeneratedModule> {
    use workloads::{bfs, mandelbrot, quadrature};
    let options = CompileOptions::default();
    let graphs = [
        (
            "mandelbrot",
            mandelbrot::graph(&mandelbrot::View::whole_set(64, 64)).graph,
        ),
        (
            "quadrature",
            quadrature::graph(&quadrature::Problem::random(1, 100, 16)).graph,
        ),
        ("bfs", bfs::graph(&bfs::Problem::random(1, 200, 3)).graph),
    ];
    graphs
        .into_iter()
        .map(|(name, graph)| GeneratedModule {
            name: name.into(),
            wgsl: graph
                .compile(&options)
                .unwrap_or_else(|e| panic!("{name} compiles: {e}"))
                .wgsl()
                .to_owned(),
            features: options.features,
        })
        .collect()
}

/// The shader table of a frame whose object 0 has the height function
/// `user` as its displacement shader (empty without one).
pub fn user_height_shaders(
    user: Option<&str>,
) -> Vec<std::sync::Arc<reyes::surface_shader::SurfaceShader>> {
    user.map(|wgsl| {
        std::sync::Arc::new(
            reyes::displacement::height_shader::shader(wgsl, 0).expect("the function checks"),
        )
    })
    .into_iter()
    .collect()
}

/// The Reyes megakernel in every [`reyes::gpu::KernelVariant`], without and
/// with a user's height function (as displacement shader 0).
pub fn reyes_variants() -> Vec<GeneratedModule> {
    use reyes::gpu::KernelVariant;
    use reyes::gpu::graph::{UserCode, compile_variant};
    let mut modules = Vec::new();
    for variant in KernelVariant::ALL {
        for user in [None, Some(USER_HEIGHT)] {
            let shaders = user_height_shaders(user);
            let code = UserCode { surfaces: &shaders };
            let compiled = compile_variant(wgpu::Features::empty(), variant, &code)
                .unwrap_or_else(|e| panic!("{variant} compiles: {e}"));
            modules.push(GeneratedModule {
                name: format!(
                    "reyes {variant}{}",
                    if user.is_some() {
                        " + user function"
                    } else {
                        ""
                    }
                ),
                wgsl: compiled.wgsl().to_owned(),
                features: variant.features(),
            });
        }
    }
    modules
}
