use super::*;

fn run(source: &str) -> Pruned {
    let module = naga::front::wgsl::parse_str(source).expect("test source parses");
    let pruned = prune(source, &module).expect("pruned text parses");
    let reparsed = naga::front::wgsl::parse_str(&pruned.text).expect("pruned text parses");
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&reparsed)
    .expect("pruned text validates");
    pruned
}

const ENTRY: &str = "@compute @workgroup_size(1)\nfn main() {\n    out[0] = pick(1u);\n}\n";

fn module(constants: &str, pick_body: &str, extra: &str) -> String {
    format!(
        "{constants}\n@group(0) @binding(0) var<storage, read_write> out: array<u32>;\n\n// pick's doc\nfn pick(x: u32) -> u32 {{\n{pick_body}\n}}\n\n{extra}{ENTRY}"
    )
}

#[test]
fn a_true_condition_keeps_the_accept_block_only() {
    let source = module(
        "const ON: bool = true;",
        "    var r = 0u;\n    if (ON) {\n        r = 1u;\n    } else {\n        r = 2u;\n    }\n    return r;",
        "",
    );
    let pruned = run(&source);
    assert_eq!(pruned.folded_branches, 1);
    assert!(
        pruned
            .text
            .contains("    {\n        r = 1u;\n    }\n    return r;")
    );
    assert!(!pruned.text.contains("r = 2u"), "{}", pruned.text);
}

#[test]
fn a_false_condition_keeps_the_else_block_or_nothing() {
    let source = module(
        "const ON: bool = false;",
        "    var r = 0u;\n    if (ON) {\n        r = 1u;\n    }\n    if (!ON) {\n        r = 3u;\n    }\n    if ON { r = 4u; } else { r = 5u; }\n    return r;",
        "",
    );
    let pruned = run(&source);
    assert_eq!(pruned.folded_branches, 3);
    assert!(!pruned.text.contains("r = 1u"));
    assert!(!pruned.text.contains("r = 4u"));
    assert!(pruned.text.contains("    {\n        r = 3u;\n    }\n"));
    assert!(pruned.text.contains("    { r = 5u; }\n"));
    // The deleted statement takes its whole lines with it.
    assert!(
        pruned.text.contains("    var r = 0u;\n    {\n"),
        "{}",
        pruned.text
    );
}

#[test]
fn else_if_chains_fold_to_the_branch_the_constants_choose() {
    for (mode, kept) in [
        (0u32, "r = 10u"),
        (1, "r = 11u"),
        (2, "r = 12u"),
        (7, "r = 13u"),
    ] {
        let source = module(
            &format!("const MODE: u32 = {mode}u;\nconst ONE: u32 = 1u;"),
            "    var r = 0u;\n    if (MODE == 0u) {\n        r = 10u;\n    } else if (MODE == ONE) {\n        r = 11u;\n    } else if (MODE == 2u) {\n        r = 12u;\n    } else {\n        r = 13u;\n    }\n    return r;",
            "",
        );
        let pruned = run(&source);
        for other in ["r = 10u", "r = 11u", "r = 12u", "r = 13u"] {
            assert_eq!(
                pruned.text.contains(other),
                other == kept,
                "mode {mode}: {other}\n{}",
                pruned.text
            );
        }
    }
}

#[test]
fn dynamic_conditions_stay_and_their_branches_still_fold() {
    // naga lowers `&&` and `||` at run time into statements of their own:
    // such conditions stay as they are, even with a constant operand.
    let source = module(
        "const ON: bool = false;",
        "    var r = 0u;\n    if (x > 3u) {\n        if (ON) {\n            r = 1u;\n        }\n        if (ON && x > 4u) {\n            r = 5u;\n        }\n    } else if (ON || x == 2u) {\n        r = 2u;\n    } else if (ON) {\n        r = 3u;\n    } else {\n        r = 4u;\n    }\n    return r;",
        "",
    );
    let pruned = run(&source);
    assert_eq!(pruned.folded_branches, 2, "{}", pruned.text);
    assert!(pruned.text.contains("if (x > 3u) {"));
    assert!(pruned.text.contains("if (ON && x > 4u) {"));
    assert!(
        pruned.text.contains(
            "} else if (ON || x == 2u) {\n        r = 2u;\n    } else {\n        r = 4u;\n    }"
        ),
        "{}",
        pruned.text
    );
    assert!(!pruned.text.contains("r = 1u"));
    assert!(!pruned.text.contains("r = 3u"));
}

#[test]
fn braces_in_comments_do_not_confuse_the_scan() {
    let source = module(
        "const ON: bool = true;",
        "    var r = 0u;\n    if (ON) { // a } here\n        /* and { /* nested } */ here */\n        r = 1u;\n    } /* } */ else { r = 2u; }\n    return r;",
        "",
    );
    let pruned = run(&source);
    assert!(pruned.text.contains("r = 1u"));
    assert!(!pruned.text.contains("r = 2u"), "{}", pruned.text);
}

#[test]
fn functions_only_dead_branches_called_are_dropped_with_their_comments() {
    let extra = "// helper's doc\n// second line\nfn helper() -> u32 {\n    return 9u;\n}\n\n// deep's doc\nfn deep() -> u32 {\n    return helper();\n}\n\n// kept's doc\nfn kept() -> u32 {\n    return 1u;\n}\n\n";
    let source = module(
        "const ON: bool = false;",
        "    var r = kept();\n    if (ON) {\n        r = deep();\n    }\n    return r;",
        extra,
    );
    let pruned = run(&source);
    assert_eq!(pruned.dropped_functions, ["helper", "deep"]);
    assert!(!pruned.text.contains("helper"), "{}", pruned.text);
    assert!(!pruned.text.contains("deep"));
    assert!(pruned.text.contains("// kept's doc\nfn kept()"));
    assert!(pruned.text.contains("// pick's doc\nfn pick("));
    assert!(!pruned.text.contains("\n\n\n"), "{}", pruned.text);
}

#[test]
fn a_module_without_constant_conditions_is_unchanged() {
    let source = module(
        "",
        "    var r = 0u;\n    if (x > 1u) {\n        r = 1u;\n    }\n    return r;",
        "",
    );
    let pruned = run(&source);
    assert_eq!(pruned.text, source);
    assert_eq!(pruned.folded_branches, 0);
    assert!(pruned.dropped_functions.is_empty());
}
