//! The generated megakernel as a product: deterministic, headed, valid under
//! naga for several feature sets, and snapshotted.

use scheduler::{CompileOptions, Graph, Policy, wgpu};
use tests::graphs::{binary_tree, ping_pong, scratch_sum};

fn graphs() -> Vec<(&'static str, Graph)> {
    vec![
        ("binary_tree", binary_tree(6)),
        ("scratch_sum", scratch_sum()),
        ("ping_pong", ping_pong(5)),
    ]
}

fn option_sets() -> Vec<(&'static str, CompileOptions)> {
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
    ]
}

#[test]
fn same_graph_same_bytes() {
    for (name, graph) in graphs() {
        for (options_name, options) in option_sets() {
            let a = graph.compile(&options).unwrap();
            let b = graph.clone().compile(&options).unwrap();
            assert_eq!(a.wgsl(), b.wgsl(), "{name} / {options_name}");
        }
    }
}

#[test]
fn output_starts_with_a_header_comment() {
    let wgsl = binary_tree(3)
        .compile(&CompileOptions::default())
        .unwrap()
        .wgsl()
        .to_owned();
    assert!(
        wgsl.starts_with("// Megakernel for graph `binary tree`"),
        "{}",
        &wgsl[..80]
    );
    assert!(wgsl.contains("Do not edit"));
}

/// The module is re-parsed and validated independently of the compiler's own
/// check, with every option set (the compiler validated it too; this guards
/// against the two drifting apart).
#[test]
fn every_generated_module_validates_with_naga() {
    for (name, graph) in graphs() {
        for (options_name, options) in option_sets() {
            let compiled = graph.compile(&options).unwrap();
            let module = naga::front::wgsl::parse_str(compiled.wgsl()).unwrap_or_else(|e| {
                panic!(
                    "{name} / {options_name}: {}",
                    e.emit_to_string(compiled.wgsl())
                )
            });
            let mut capabilities = naga::valid::Capabilities::default();
            if options
                .features
                .contains(wgpu::Features::MEMORY_DECORATION_COHERENT)
            {
                capabilities |= naga::valid::Capabilities::MEMORY_DECORATION_COHERENT;
            }
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
                .validate(&module)
                .unwrap_or_else(|e| {
                    panic!(
                        "{name} / {options_name}: {}",
                        e.emit_to_string(compiled.wgsl())
                    )
                });
        }
    }
}

#[test]
fn coherent_payload_needs_the_capability() {
    // Compiled for coherent memory, the module must not validate without it:
    // the feature really changes the code.
    let compiled = binary_tree(3)
        .compile(&CompileOptions::with_features(
            wgpu::Features::MEMORY_DECORATION_COHERENT,
        ))
        .unwrap();
    let module = naga::front::wgsl::parse_str(compiled.wgsl()).unwrap();
    let result = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module);
    assert!(result.is_err());
}

#[test]
fn snapshots_of_the_test_graphs() {
    for (name, graph) in graphs() {
        let compiled = graph.compile(&CompileOptions::default()).unwrap();
        insta::assert_snapshot!(name, compiled.wgsl());
    }
}

#[test]
fn snapshot_of_the_coherent_variant() {
    let compiled = binary_tree(6)
        .compile(&CompileOptions::with_features(
            wgpu::Features::MEMORY_DECORATION_COHERENT,
        ))
        .unwrap();
    insta::assert_snapshot!("binary_tree_coherent", compiled.wgsl());
}
