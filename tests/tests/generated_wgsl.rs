//! The generated megakernel as a product: deterministic, headed, valid under
//! naga for several feature sets, and snapshotted.

use scheduler::{CompileOptions, TraceOptions, wgpu};
use tests::generated_modules::{option_sets, test_graphs as graphs};
use tests::graphs::{binary_tree, ping_pong};

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
            naga::valid::Validator::new(
                naga::valid::ValidationFlags::all(),
                scheduler::validation_capabilities(options.features),
            )
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

/// Tracing adds its buffer, constants, two functions and their calls, and
/// nothing else.
#[test]
fn snapshot_of_a_traced_module() {
    let compiled = ping_pong(5)
        .compile(&CompileOptions::default().traced(TraceOptions { capacity: 1024 }))
        .unwrap();
    insta::assert_snapshot!("ping_pong_traced", compiled.wgsl());
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

/// Two item types sharing a nested item, with a glam vector, arrays and
/// explicit padding: the WGSL the derive writes for them.
mod derived {
    use scheduler::{CompileOptions, Graph, Item, ItemType, Procedure, WgslType, glam::Vec4};

    #[scheduler::item]
    pub(crate) struct Inner {
        pub weight: f32,
        pub tag: u32,
    }

    #[scheduler::item]
    pub(crate) struct Particle {
        pub position: Vec4,
        pub pair: [Inner; 2],
        pub id: u32,
        pub _pad: [u32; 3],
    }

    #[scheduler::item]
    pub(crate) struct Spark {
        pub inner: Inner,
        pub id: i32,
    }

    #[test]
    fn the_derive_writes_the_wgsl_struct_and_its_dependencies() {
        assert_eq!(
            Inner::wgsl_struct(),
            "struct Inner { weight: f32, tag: u32 }"
        );
        assert_eq!(
            ItemType::of::<Particle>().wgsl_source(),
            "struct Inner { weight: f32, tag: u32 }\n\
             struct Particle { position: vec4<f32>, pair: array<Inner, 2>, id: u32, _pad: array<u32, 3> }"
        );
        assert_eq!(
            Particle::rust_fields(),
            [("position", 0), ("pair", 16), ("id", 32), ("_pad", 36)]
        );
        assert_eq!(ItemType::of::<Particle>().size(), 48);
        assert_eq!(
            (Particle::WGSL_ALIGN, Particle::WGSL_SIZE),
            (16, std::mem::size_of::<Particle>())
        );
    }

    #[test]
    fn a_graph_of_derived_items_and_constants_compiles_to_the_expected_text() {
        let mut graph = Graph::new("derived");
        graph
            .constant("GRAVITY", -9.81f32)
            .constant("STEPS", 7u32)
            .constant("OFFSET", -3i32)
            .constant("ENABLED", true);
        let particle = graph.procedure(Procedure::of::<Particle>("Move").initial(true).body(
            "if (valid && ENABLED && item.id < STEPS) {
    var next = item;
    next.position.y += GRAVITY;
    next.id += 1u;
    enqueue_Move(next);
    enqueue_Emit(Spark(item.pair[1], i32(item.id) + OFFSET));
}",
        ));
        let spark = graph.procedure(
            Procedure::of::<Spark>("Emit").body("_ = item.inner.weight * f32(item.id);"),
        );
        graph.connect(&particle, &particle);
        graph.connect(&particle, &spark);
        let wgsl = graph
            .compile(&CompileOptions::default())
            .unwrap()
            .wgsl()
            .to_owned();
        for line in [
            "// Graph constants (`Graph::constant`).\nconst GRAVITY: f32 = -9.81f;",
            "const STEPS: u32 = 7u;",
            "const OFFSET: i32 = -3i;",
            "const ENABLED: bool = true;",
            "struct Spark { inner: Inner, id: i32 }",
        ] {
            assert!(wgsl.contains(line), "missing `{line}` in\n{wgsl}");
        }
        // `Inner` is nested in both item types and declared once.
        assert_eq!(wgsl.matches("struct Inner {").count(), 1, "{wgsl}");
    }
}
