//! The typed API without a GPU: derived items against the naga check,
//! handles looked up by name and item type, and graph constants.

use scheduler::{CompileError, CompileOptions, Graph, Procedure, item_type};
use tests::graphs::{Node, binary_tree};

fn compile(graph: &Graph) -> Result<scheduler::CompiledGraph, CompileError> {
    graph.compile(&CompileOptions::default())
}

fn leaf(name: &str) -> Procedure<Node> {
    Procedure::of::<Node>(name).initial(true).body("_ = item;")
}

#[test]
fn constants_with_bad_names_or_values_are_typed_errors() {
    let with_constant = |name: &str, value: scheduler::ConstantValue| {
        let mut g = Graph::new("constants");
        g.constant(name, value);
        g.procedure(leaf("A"));
        compile(&g)
    };
    for name in ["2x", "a b", "__x", "loop"] {
        assert_eq!(
            with_constant(name, 1u32.into()).unwrap_err(),
            CompileError::InvalidConstantName(name.into()),
            "{name}"
        );
    }
    for name in ["SCHED_LIMIT", "sched_x", "enqueue_A"] {
        assert_eq!(
            with_constant(name, 1u32.into()).unwrap_err(),
            CompileError::ReservedName { name: name.into() },
            "{name}"
        );
    }
    for value in [f32::NAN, f32::INFINITY] {
        let error = with_constant("X", value.into()).unwrap_err();
        assert!(
            matches!(&error, CompileError::NonFiniteConstant { name, .. } if name == "X"),
            "{error:?}"
        );
        assert!(error.to_string().contains("finite"), "{error}");
    }

    let mut g = Graph::new("twice");
    g.constant("N", 1u32).constant("N", 2i32);
    g.procedure(leaf("A"));
    assert_eq!(
        compile(&g).unwrap_err(),
        CompileError::DuplicateConstant("N".into())
    );
}

#[test]
fn a_constant_the_library_declares_too_is_a_wgsl_error() {
    let mut g = Graph::new("clash");
    g.constant("LIMIT", 4u32);
    g.library("const LIMIT: u32 = 5u;");
    g.procedure(leaf("A"));
    assert!(matches!(
        compile(&g).unwrap_err(),
        CompileError::Wgsl { .. }
    ));
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable, scheduler::Item)]
struct Leaf {
    value: u32,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable, scheduler::Item)]
struct Branch {
    leaf: Leaf,
    depth: u32,
}

#[test]
fn two_item_types_declaring_one_struct_differently_are_an_error() {
    // A hand-written `Leaf`, laid out like the derived one but written
    // differently: the module could only keep one of the two.
    let other = item_type!(Leaf, "struct Leaf {\n    value: u32,\n}", [value]);
    let mut g = Graph::new("clash");
    let a = g.procedure(Procedure::of::<Branch>("A").initial(true).body("_ = item;"));
    let b = g.procedure(Procedure::new("B", other).body("_ = item;"));
    g.connect(&a, &b);
    let error = compile(&g).unwrap_err();
    assert!(
        matches!(&error, CompileError::ItemLayoutMismatch { detail, .. } if detail.contains("`Leaf`")),
        "{error:?}"
    );
}

#[test]
fn typed_handles_are_found_by_name_and_item_type() {
    let tree = binary_tree(2);
    assert_eq!(tree.procedure_id::<Node>("Grow"), Some(tree.ids.clone()));
    assert_eq!(tree.procedure_id::<Leaf>("Grow"), None);
    assert_eq!(tree.procedure_id::<Node>("Nope"), None);
    let compiled = compile(&tree).unwrap();
    assert_eq!(
        compiled.procedure_id::<Node>("Grow"),
        Some(tree.ids.clone())
    );
    assert_eq!(compiled.procedure_id::<Leaf>("Grow"), None);
}
