//! Every `CompileError` variant, from graphs built to trigger it (those of
//! constants and nested item structs are in `typed_api.rs`). Pure tests: no
//! GPU needed.

use scheduler::{
    CompileError, CompileOptions, Graph, Procedure, ProcedureId, Resource, SourceOrigin, item_type,
};
use tests::graphs::{Node, binary_tree, node_type};

fn compile(graph: &Graph) -> Result<scheduler::CompiledGraph, CompileError> {
    graph.compile(&CompileOptions::default())
}

fn leaf(name: &str) -> Procedure<Node> {
    Procedure::of::<Node>(name).initial(true).body("_ = item;")
}

#[test]
fn a_valid_graph_compiles() {
    assert!(compile(&binary_tree(4)).is_ok());
}

#[test]
fn duplicate_procedure_names() {
    let mut g = Graph::new("dup");
    g.procedure(leaf("A"));
    g.procedure(leaf("A"));
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::DuplicateProcedure("A".into())
    );
}

#[test]
fn procedure_names_must_be_identifiers() {
    let mut g = Graph::new("names");
    g.procedure(leaf("not valid"));
    assert!(
        matches!(compile(&g).unwrap_err(), CompileError::InvalidProcedureName(n) if n == "not valid")
    );
}

#[test]
fn no_initial_procedure() {
    let mut g = Graph::new("none");
    g.procedure(Procedure::of::<Node>("A").body("_ = item;"));
    assert_eq!(compile(&g).unwrap_err(), CompileError::NoInitialProcedure);
}

#[test]
fn connection_to_unknown_procedure() {
    let mut g = Graph::new("unknown");
    let a = g.procedure(leaf("A"));
    // A handle can only name a procedure of another graph, or none, untyped.
    g.connect(&a, &ProcedureId::named("Missing"));
    assert!(matches!(
        compile(&g).unwrap_err(),
        CompileError::UnknownProcedure { unknown, .. } if unknown == "Missing"
    ));
}

#[test]
fn zero_fan_out() {
    let mut g = Graph::new("fan-out");
    let a = g.procedure(leaf("A"));
    g.connect_with_fan_out(&a, &a, 0);
    assert!(matches!(
        compile(&g).unwrap_err(),
        CompileError::ZeroFanOut { .. }
    ));
}

#[test]
fn invalid_thread_counts() {
    for threads in [0, 3, 12, 512] {
        let mut g = Graph::new("threads");
        g.procedure(leaf("A").threads_per_item(threads));
        assert!(
            matches!(compile(&g).unwrap_err(), CompileError::InvalidThreadCount { threads: t, .. } if t == threads),
            "{threads} threads per item must be rejected"
        );
    }
}

#[test]
fn invalid_workgroup_size() {
    let options = CompileOptions {
        workgroup_size: 96,
        ..CompileOptions::default()
    };
    assert!(matches!(
        binary_tree(2).compile(&options).unwrap_err(),
        CompileError::InvalidWorkgroupSize { size: 96, .. }
    ));
    let options = CompileOptions {
        workgroup_size: 1024,
        ..CompileOptions::default()
    };
    assert!(matches!(
        binary_tree(2).compile(&options).unwrap_err(),
        CompileError::InvalidWorkgroupSize { .. }
    ));
}

#[test]
fn chunks_per_batch_out_of_range() {
    for chunks in [0, scheduler::MAX_CHUNKS_PER_BATCH + 1] {
        let options = CompileOptions {
            chunks_per_batch: chunks,
            ..CompileOptions::default()
        };
        let error = binary_tree(2).compile(&options).unwrap_err();
        assert!(
            matches!(error, CompileError::InvalidChunksPerBatch { chunks: c, max } if c == chunks && max == scheduler::MAX_CHUNKS_PER_BATCH),
            "{error:?}"
        );
        assert!(error.to_string().contains("chunks per batch"), "{error}");
    }
    // The bounds themselves are accepted, and a batch then stages the
    // children of all its chunks.
    for chunks in [1, scheduler::MAX_CHUNKS_PER_BATCH] {
        let options = CompileOptions {
            chunks_per_batch: chunks,
            ..CompileOptions::default()
        };
        let compiled = binary_tree(2).compile(&options).unwrap();
        let grow = &compiled.queues()[0];
        assert_eq!(grow.items_per_batch, 256 * chunks);
        assert_eq!(grow.stage_capacity, 2 * 256 * chunks);
    }
}

#[test]
fn scratch_over_the_limit_names_the_largest_procedure() {
    // 64 bytes x 256 items = 16 KiB, plus the scheduler's own words: too much.
    let mut g = Graph::new("scratch");
    let small = g.procedure(leaf("Small").scratch_bytes(4));
    let big = g.procedure(
        Procedure::of::<Node>("Big")
            .scratch_bytes(64)
            .body("_ = item;"),
    );
    g.connect(&small, &big);
    match compile(&g).unwrap_err() {
        CompileError::ScratchTooLarge {
            procedure,
            needed,
            limit,
            ..
        } => {
            assert_eq!(procedure, "Big");
            assert!(needed > limit);
        }
        other => panic!("unexpected {other}"),
    }
    // The same need fits once the limit is raised: the region is shared, not summed.
    let mut options = CompileOptions::default();
    options.limits.max_compute_workgroup_storage_size = 32768;
    assert!(g.compile(&options).is_ok());
}

#[test]
fn library_workgroup_variables_count_towards_the_limit() {
    let graph = |library: &str| {
        let mut g = Graph::new("workgroup library");
        g.library(library);
        g.procedure(leaf("A").body("touch_tile(thread);"));
        g
    };
    let without = graph("fn touch_tile(i: u32) { _ = i; }");
    let with =
        graph("var<workgroup> tile: array<u32, 1000>;\nfn touch_tile(i: u32) { tile[i] = i; }");
    // The scheduler's own variables, each rounded up to 16 bytes: the pick
    // (16), the flush (8), one staged counter (4) and one word of scratch.
    let base = compile(&without).unwrap().workgroup_memory_bytes();
    assert_eq!(base, 4 * 16);
    assert_eq!(
        compile(&with).unwrap().workgroup_memory_bytes(),
        base + 4000
    );

    // A limit that the scheduler's variables fit but the tile does not.
    let mut options = CompileOptions::default();
    options.limits.max_compute_workgroup_storage_size = base + 3999;
    assert!(without.compile(&options).is_ok());
    match with.compile(&options).unwrap_err() {
        CompileError::ScratchTooLarge {
            needed,
            internal,
            limit,
            ..
        } => {
            assert_eq!(needed, base + 4000);
            assert!(internal >= 4000, "{internal}");
            assert_eq!(limit, base + 3999);
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn scratch_is_sized_by_the_largest_procedure_not_the_sum() {
    // Each needs 12 KiB on its own; their sum (24 KiB) would not fit.
    let mut g = Graph::new("shared scratch");
    let a = g.procedure(leaf("A").scratch_bytes(48));
    let b = g.procedure(
        Procedure::of::<Node>("B")
            .scratch_bytes(48)
            .body("_ = item;"),
    );
    g.connect(&a, &b);
    assert!(compile(&g).is_ok());
}

#[test]
fn undeclared_enqueue_in_a_body() {
    let mut g = Graph::new("undeclared");
    let a = g.procedure(leaf("A").body("if (valid) { enqueue_B(item); }"));
    let b = g.procedure(Procedure::of::<Node>("B").body("_ = item;"));
    g.connect(&b, &b);
    g.connect(&a, &a);
    // B is unreachable from A through declared connections, but reachability is
    // checked first; make B reachable through a second initial procedure.
    let c = g.procedure(leaf("C"));
    g.connect(&c, &b);
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UndeclaredEnqueue {
            procedure: "A".into(),
            target: "B".into(),
            via: "its body".into()
        }
    );
}

#[test]
fn undeclared_enqueue_through_a_helper() {
    let mut g = Graph::new("helper");
    g.library("fn spawn_more(n: Node) { enqueue_B(n); }\nfn indirect(n: Node) { spawn_more(n); }");
    g.procedure(leaf("A").body("if (valid) { indirect(item); }"));
    g.procedure(leaf("B"));
    match compile(&g).unwrap_err() {
        CompileError::UndeclaredEnqueue {
            procedure,
            target,
            via,
        } => {
            assert_eq!((procedure.as_str(), target.as_str()), ("A", "B"));
            assert!(via.contains("spawn_more"), "{via}");
        }
        other => panic!("unexpected {other}"),
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Padded {
    a: u32,
    b: [f32; 3],
}

#[test]
fn item_size_mismatch_with_naga_stride() {
    // vec3<f32> aligns to 16 bytes in WGSL: the struct is 32 bytes there, 16 in Rust.
    let item = item_type!(Padded, "struct Padded { a: u32, b: vec3<f32> }", [a, b]);
    let mut g = Graph::new("size");
    g.procedure(Procedure::new("A", item).initial(true).body("_ = item;"));
    match compile(&g).unwrap_err() {
        CompileError::ItemLayoutMismatch { detail, .. } => {
            assert!(detail.contains("stride"), "{detail}")
        }
        other => panic!("unexpected {other}"),
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Swapped {
    a: u32,
    b: u32,
}

#[test]
fn item_field_offset_mismatch() {
    let item = item_type!(Swapped, "struct Swapped { b: u32, a: u32 }", [a, b]);
    let mut g = Graph::new("offsets");
    g.procedure(Procedure::new("A", item).initial(true).body("_ = item;"));
    match compile(&g).unwrap_err() {
        CompileError::ItemLayoutMismatch { detail, .. } => {
            assert!(detail.contains("field"), "{detail}")
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn item_field_missing_on_one_side() {
    let item = item_type!(Swapped, "struct Swapped { a: u32, b: u32 }", [a]);
    let mut g = Graph::new("missing");
    g.procedure(Procedure::new("A", item).initial(true).body("_ = item;"));
    assert!(matches!(
        compile(&g).unwrap_err(),
        CompileError::ItemLayoutMismatch { .. }
    ));
}

#[test]
fn unsupported_item_field() {
    let item = item_type!(Swapped, "struct Swapped { a: atomic<u32>, b: u32 }", [a, b]);
    let mut g = Graph::new("atomic field");
    g.procedure(Procedure::new("A", item).initial(true).body("_ = item;"));
    assert!(
        matches!(compile(&g).unwrap_err(), CompileError::UnsupportedItemField { field, .. } if field == "a")
    );
}

#[test]
fn unreachable_procedure_is_an_error() {
    let mut g = Graph::new("unreachable");
    g.procedure(leaf("A"));
    g.procedure(Procedure::of::<Node>("Orphan").body("_ = item;"));
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UnreachableProcedure("Orphan".into())
    );
}

#[test]
fn reserved_names_in_the_library() {
    for name in ["sched_helper", "enqueue_Extra", "SCHED_LIMIT"] {
        let mut g = Graph::new("reserved");
        let decl = if name.starts_with("SCHED") {
            format!("const {name}: u32 = 1u;")
        } else {
            format!("fn {name}() {{}}")
        };
        g.library(&decl);
        g.procedure(leaf("A"));
        assert_eq!(
            compile(&g).unwrap_err(),
            CompileError::ReservedName { name: name.into() },
            "{name}"
        );
    }
}

#[test]
fn resource_problems() {
    let mut g = Graph::new("resources");
    g.resource(Resource::storage::<[u32]>("out"))
        .resource(Resource::storage_read::<[u32]>("out"));
    g.procedure(leaf("A"));
    assert!(
        matches!(compile(&g).unwrap_err(), CompileError::Resource(m) if m.contains("duplicate"))
    );

    let mut g = Graph::new("too many");
    for i in 0..6 {
        g.resource(Resource::storage::<[u32]>(format!("buffer{i}")));
    }
    g.procedure(leaf("A"));
    assert!(matches!(compile(&g).unwrap_err(), CompileError::Resource(m) if m.contains("exceed")));
}

#[test]
fn wgsl_error_in_a_body_names_the_procedure_and_its_own_line() {
    let mut g = Graph::new("typo");
    let fine = g.procedure(leaf("Fine"));
    let broken = g.procedure(
        Procedure::of::<Node>("Broken")
            .body("let a = 1u;\nlet b = a + 2u;\nlet c = b + undefined_name;"),
    );
    g.connect(&fine, &broken);
    match compile(&g).unwrap_err() {
        CompileError::Wgsl {
            origin,
            line,
            message,
            ..
        } => {
            assert_eq!(origin, SourceOrigin::Body("Broken".into()));
            assert_eq!(line, 3, "{message}");
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn wgsl_type_error_in_a_body_is_located_too() {
    let mut g = Graph::new("types");
    g.procedure(leaf("A").body("var x: u32 = 0u;\nx = 1.5;"));
    match compile(&g).unwrap_err() {
        CompileError::Wgsl { origin, line, .. } => {
            assert_eq!(origin, SourceOrigin::Body("A".into()));
            assert_eq!(line, 2);
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn wgsl_error_in_the_library_is_located_in_the_library() {
    let mut g = Graph::new("library");
    g.library("fn ok() -> u32 { return 1u; }\n\nfn bad() -> u32 { return 1.0 +; }");
    g.procedure(leaf("A"));
    match compile(&g).unwrap_err() {
        CompileError::Wgsl { origin, line, .. } => {
            assert_eq!(origin, SourceOrigin::Library);
            assert_eq!(line, 3);
        }
        other => panic!("unexpected {other}"),
    }
}

#[test]
fn item_type_helper_reports_size() {
    assert_eq!(node_type().size(), std::mem::size_of::<Node>());
}

/// A hand-written `WgslType` that states `vec3<f32>` for a 12-byte Rust
/// type: WGSL's array stride is 16, so host and shader would disagree on
/// every element after the first. naga's layout of the module catches it.
#[test]
fn a_typed_resource_whose_wgsl_stride_differs_from_rust_is_refused() {
    #[repr(C)]
    #[derive(Clone, Copy, scheduler::bytemuck::Pod, scheduler::bytemuck::Zeroable)]
    struct Point([f32; 3]);
    impl scheduler::WgslType for Point {
        const WGSL_ALIGN: usize = 4;
        const WGSL_SIZE: usize = 12;
        fn wgsl_type() -> String {
            "vec3<f32>".to_owned()
        }
    }
    let mut g = Graph::new("stride");
    g.resource(Resource::storage::<[Point]>("points"));
    g.procedure(leaf("A"));
    match compile(&g).unwrap_err() {
        CompileError::Resource(message) => assert!(
            message.contains("points") && message.contains("16") && message.contains("12"),
            "{message}"
        ),
        other => panic!("expected a resource error, got {other}"),
    }
}

/// A body or library function that names the scheduler's own state (here
/// its control words) is refused at the line in the user's source, naming
/// the global; the generated helpers that use that state are not.
#[test]
fn user_code_may_not_name_the_schedulers_state() {
    let mut g = Graph::new("meddling body");
    g.procedure(
        Procedure::of::<Node>("A")
            .initial(true)
            .body("let x = item.id;\natomicStore(&sched_control[0], x);"),
    );
    match compile(&g).unwrap_err() {
        CompileError::Wgsl {
            origin: SourceOrigin::Body(procedure),
            line,
            message,
            ..
        } => {
            assert_eq!((procedure.as_str(), line), ("A", 2));
            assert!(message.contains("sched_control"), "{message}");
        }
        other => panic!("expected a located error, got {other}"),
    }
    let mut g = Graph::new("meddling library");
    g.library("fn reset() {\n    atomicStore(&sched_control[1], 0u);\n}");
    g.procedure(Procedure::of::<Node>("A").initial(true).body("reset();"));
    match compile(&g).unwrap_err() {
        CompileError::Wgsl {
            origin: SourceOrigin::Library,
            line,
            message,
            ..
        } => {
            assert_eq!(line, 2);
            assert!(message.contains("sched_control"), "{message}");
        }
        other => panic!("expected a located error, got {other}"),
    }
}

#[test]
fn join_with_unknown_procedure() {
    let mut g = Graph::new("join");
    let a = g.procedure(leaf("A"));
    g.join(&a, &ProcedureId::named("Missing"));
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UnknownJoinProcedure {
            parent: "A".into(),
            continuation: "Missing".into(),
            unknown: "Missing".into(),
        }
    );
}

#[test]
fn opening_an_undeclared_join() {
    let mut g = Graph::new("join");
    let a = g.procedure(leaf("A"));
    // `B` opens joins of `C` without `g.join(&b, &c)`; `A`'s are declared.
    let b = g.procedure(
        Procedure::of::<Node>("B")
            .initial(true)
            .body("if (valid) { _ = join_open_C(item); }"),
    );
    let c = g.procedure(Procedure::of::<Node>("C").body("_ = item;"));
    g.join(&a, &c);
    let _ = b;
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UndeclaredJoin {
            procedure: "B".into(),
            continuation: "C".into(),
            via: "its body".into(),
        }
    );
}

#[test]
fn a_continuation_is_reachable_through_its_join() {
    let mut g = Graph::new("join");
    let a = g.procedure(
        Procedure::of::<Node>("A")
            .initial(true)
            .body("if (valid) { _ = join_open_C(item); }"),
    );
    let c = g.procedure(Procedure::of::<Node>("C").body("_ = item;"));
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UnreachableProcedure("C".into()),
        "without the join, `C` is unreachable"
    );
    g.join(&a, &c);
    let compiled = compile(&g).unwrap();
    assert!(
        compiled
            .wgsl()
            .contains("fn join_open_C(record: Node) -> bool")
    );
}

#[test]
fn enqueueing_into_a_continuation_needs_a_connection() {
    let mut g = Graph::new("join");
    let a = g.procedure(
        Procedure::of::<Node>("A")
            .initial(true)
            .body("if (valid && join_open_C(item)) { enqueue_C(item); }"),
    );
    let c = g.procedure(Procedure::of::<Node>("C").body("_ = item;"));
    g.join(&a, &c);
    // The join lets `A` fire continuations, not enqueue into `C` itself.
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::UndeclaredEnqueue {
            procedure: "A".into(),
            target: "C".into(),
            via: "its body".into(),
        }
    );
    g.connect(&a, &c);
    assert!(compile(&g).is_ok());
}
