//! The Reyes megakernel specialized per frame ([`KernelVariant`]): every
//! variant compiles, validates and is deterministic, and each one holds the
//! code its frames run and nothing of the switched-off features.

use reyes::gpu::graph::{UserCode, compile_variant, reyes_graph_with};
use reyes::gpu::{DepthTest, KernelVariant};
use scheduler::CompileOptions;
use scheduler::wgpu::Features;

/// A user displacement (height) function, as a scene would give it.
use tests::generated_modules::USER_HEIGHT as USER;

/// Functions that only the 5D rasterizers and the motion and lens paths use.
const BLURRED_ONLY: [&str; 6] = [
    "raster_quad_5d",
    "raster_interleave",
    "raster_interval",
    "raster_simple",
    "adaptive_choice",
    "moving_point",
];

/// Functions that only displacement uses.
const DISPLACED_ONLY: [&str; 4] = [
    "displacement_height",
    "displaced_grid_normal",
    "height_sines",
    "height_image",
];

fn declares(wgsl: &str, function: &str) -> bool {
    wgsl.contains(&format!("\nfn {function}("))
}

#[test]
fn every_variant_holds_what_it_runs_and_nothing_it_does_not() {
    for variant in KernelVariant::ALL {
        for user in [None, Some(USER)] {
            let shaders = tests::generated_modules::user_height_shaders(user);
            let code = UserCode { surfaces: &shaders };
            let compiled = compile_variant(Features::empty(), variant, &code)
                .unwrap_or_else(|e| panic!("{variant} compiles: {e}"));
            let wgsl = compiled.wgsl();
            for function in BLURRED_ONLY {
                assert_eq!(
                    declares(wgsl, function),
                    variant.blurred,
                    "{variant}: {function}"
                );
            }
            for function in DISPLACED_ONLY {
                assert_eq!(
                    declares(wgsl, function),
                    variant.displaced,
                    "{variant}: {function}"
                );
            }
            // The second-nearest depth's atomic only where the midpoint
            // depth filter reads it, the pass uniform only in the two-pass
            // test, and 64-bit integers only in the 64-bit one.
            assert_eq!(
                wgsl.contains("max(old, bits)"),
                variant.depth_test == DepthTest::SecondDepth,
                "{variant}: the second-nearest depth"
            );
            assert_eq!(
                wgsl.contains("var<uniform> depth_test_pass: u32;"),
                variant.depth_test == DepthTest::TwoPass32,
                "{variant}: the pass of the two-pass test"
            );
            assert_eq!(
                wgsl.contains("u64"),
                variant.depth_test == DepthTest::Key64,
                "{variant}: 64-bit integers"
            );
            // The shadow lookup only where some light has shadow maps.
            assert_eq!(
                declares(wgsl, "shadow_occlusion_at"),
                variant.shadowed,
                "{variant}: the shadow lookup"
            );
            // The user's function (as displacement shader 0) is compiled
            // in only where displacement is.
            assert_eq!(
                declares(wgsl, "displacement0_displacement_user"),
                variant.displaced && user.is_some(),
                "{variant} with user function {}",
                user.is_some()
            );
            // The same inputs give the same text.
            let again = compile_variant(Features::empty(), variant, &code).unwrap();
            assert_eq!(wgsl, again.wgsl(), "{variant} is deterministic");
        }
    }
}

#[test]
fn specialization_shrinks_every_variant() {
    let mut rows = Vec::new();
    for variant in KernelVariant::ALL {
        let graph = reyes_graph_with(variant, &UserCode::NONE);
        let full = graph
            .compile(&CompileOptions {
                specialize: false,
                ..reyes::gpu::graph::compile_options(Features::empty())
            })
            .unwrap();
        let specialized = graph
            .compile(&reyes::gpu::graph::compile_options(Features::empty()))
            .unwrap();
        let (full_lines, full_functions) = full.module_size();
        let (lines, functions) = specialized.module_size();
        rows.push(format!(
            "{variant}: {lines} lines, {functions} functions (unspecialized {full_lines}, {full_functions})"
        ));
        assert!(lines < full_lines, "{variant}");
        assert!(functions < full_functions, "{variant}");
        // The unspecialized module is the same for every variant but the
        // constants' values: it holds every feature.
        assert!(declares(full.wgsl(), "raster_interleave"));
        assert!(declares(full.wgsl(), "displaced_grid_normal"));
    }
    println!("{}", rows.join("\n"));
}

/// The megakernel of a blurred, displaced frame, for review (the default,
/// still variant is `reyes_gpu`'s snapshot).
#[test]
fn blurred_displaced_megakernel_wgsl_snapshot() {
    let variant = KernelVariant {
        blurred: true,
        displaced: true,
        depth_test: DepthTest::Key64,
        shadowed: false,
    };
    let compiled = compile_variant(Features::empty(), variant, &UserCode::NONE)
        .expect("the Reyes graph compiles");
    insta::assert_snapshot!(compiled.wgsl());
}

/// The megakernel of a still frame with shadow maps, for review: the
/// shadow lookup (library_shadow.wgsl) where the other frames have a stub.
#[test]
fn shadowed_megakernel_wgsl_snapshot() {
    let variant = KernelVariant {
        shadowed: true,
        ..KernelVariant::default()
    };
    let compiled = compile_variant(Features::empty(), variant, &UserCode::NONE)
        .expect("the Reyes graph compiles");
    insta::assert_snapshot!(compiled.wgsl());
}

/// What the megakernel compiles in for a user surface shader: its text with
/// its names prefixed, its parameter loader and the dispatch, for review.
#[test]
fn user_surface_library_wgsl_snapshot() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders/every_input.wgsl");
    let shader = reyes::surface_shader::SurfaceShader::load(&path).expect("the shader checks");
    let library = reyes::surface_shader::megakernel_wgsl(&[std::sync::Arc::new(shader)]);
    // The path is the machine's; the snapshot names the file alone.
    let library = library.replace(&path.display().to_string(), "shaders/every_input.wgsl");
    insta::assert_snapshot!(library);
}

/// The environment lookup is compiled in only for frames whose shaders call
/// `environment()` (`shinymetal`); a textured shader without it
/// (`paintedplastic`) gets the texture code alone, and a frame without user
/// shaders neither.
#[test]
fn only_frames_that_read_an_environment_map_compile_its_lookup() {
    let builtin = |name: &str| {
        std::sync::Arc::new(
            reyes::surface_shader::builtin::shader(std::path::Path::new(name))
                .expect("a built-in")
                .expect("it checks"),
        )
    };
    let painted = [builtin(reyes::surface_shader::builtin::PAINTED_PLASTIC)];
    let shiny = [builtin(reyes::surface_shader::builtin::SHINY_METAL)];
    for (surfaces, textures, environment) in [
        (&[][..], false, false),
        (&painted[..], true, false),
        (&shiny[..], true, true),
    ] {
        let code = UserCode { surfaces };
        let compiled = compile_variant(Features::empty(), KernelVariant::default(), &code)
            .unwrap_or_else(|e| panic!("compiles: {e}"));
        let wgsl = compiled.wgsl();
        let names: Vec<_> = surfaces
            .iter()
            .map(|s| s.path.display().to_string())
            .collect();
        assert_eq!(declares(wgsl, "texture_filter"), textures, "{names:?}");
        for function in [
            "texture_environment",
            "texture_latlong_st",
            "texture_latlong_axis",
        ] {
            assert_eq!(
                declares(wgsl, function),
                environment,
                "{names:?}: {function}"
            );
        }
    }
}
