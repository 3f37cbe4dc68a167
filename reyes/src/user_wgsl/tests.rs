//! The checks on user WGSL, each against the source it refuses.

use super::*;

#[test]
fn a_self_contained_function_with_helpers_passes() {
    let wgsl = "const K: f32 = 3.0;
fn wave(x: f32) -> f32 { return sin(K * x); }
fn displacement_user(u: f32, v: f32) -> f32 {
    var h = 0.0;
    for (var i = 0; i < 4; i += 1) { h += wave(u + f32(i)) * v; }
    return h;
}";
    assert_eq!(check(wgsl), Ok(()));
}

#[test]
fn the_renderers_buffers_are_out_of_reach_and_named() {
    for (wgsl, name, line) in [
        (
            "fn displacement_user(u: f32, v: f32) -> f32 {\n    atomicMin(&framebuffer[0], 0u);\n    return u;\n}",
            "framebuffer",
            2,
        ),
        (
            "fn displacement_user(u: f32, v: f32) -> f32 {\n    let s = 1.0;\n    atomicStore(&stats[4], 7777u);\n    return u;\n}",
            "stats",
            3,
        ),
        (
            "fn displacement_user(u: f32, v: f32) -> f32 {\n    atomicStore(&sched_control[0], 0u);\n    return u;\n}",
            "sched_control",
            2,
        ),
    ] {
        match check(wgsl) {
            Err(UserWgslError::OutsideName {
                name: found,
                line: at,
                ..
            }) => assert_eq!((found.as_str(), at), (name, line), "{wgsl}"),
            other => panic!("expected {name} to be refused, got {other:?}"),
        }
    }
}

#[test]
fn errors_are_at_the_users_own_lines() {
    let wgsl = "// a comment\nfn displacement_user(u: f32, v: f32) -> f32 {\n    return u + ;\n}";
    match check(wgsl) {
        Err(UserWgslError::Invalid { line, .. }) => assert_eq!(line, 3),
        other => panic!("{other:?}"),
    }
    let wrong_type = "fn displacement_user(u: f32, v: f32) -> f32 {\n    return 1u;\n}";
    match check(wrong_type) {
        Err(UserWgslError::Invalid { line, .. }) => assert_eq!(line, 2),
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_function_is_found_by_name_and_signature_not_by_substring() {
    let in_a_comment = "// fn displacement_user(u: f32, v: f32) -> f32\nfn height(u: f32, v: f32) -> f32 { return u; }";
    assert!(matches!(
        check(in_a_comment),
        Err(UserWgslError::Missing { .. })
    ));
    let wrong_signature = "fn displacement_user(u: u32, v: f32) -> f32 { return v; }";
    match check(wrong_signature) {
        Err(UserWgslError::Missing { found }) => assert!(found.contains("signature")),
        other => panic!("{other:?}"),
    }
}

#[test]
fn module_variables_and_barriers_are_refused() {
    let global =
        "var<private> seed: u32;\nfn displacement_user(u: f32, v: f32) -> f32 { return u; }";
    assert!(matches!(
        check(global),
        Err(UserWgslError::Global { line: 1, .. })
    ));
    let barrier = "fn displacement_user(u: f32, v: f32) -> f32 {\n    if (u > 0.5) {\n        workgroupBarrier();\n    }\n    return u;\n}";
    match check(barrier) {
        Err(UserWgslError::Barrier { function, line }) => {
            assert_eq!((function.as_str(), line), ("displacement_user", 3));
        }
        other => panic!("{other:?}"),
    }
    let discard = "fn displacement_user(u: f32, v: f32) -> f32 {\n    if (u > 0.5) {\n        discard;\n    }\n    return u;\n}";
    match check(discard) {
        Err(UserWgslError::Discard { function, line }) => {
            assert_eq!((function.as_str(), line), ("displacement_user", 3));
        }
        other => panic!("{other:?}"),
    }
    let function = "fn displacement_user(u: f32, v: f32) -> f32 { return u; }";
    for (source, directive, line) in [
        (format!("enable f16;\n{function}"), "enable", 1),
        (
            format!("// Half floats.\n/* a /* nested */ comment */\n  enable f16;\n{function}"),
            "enable",
            3,
        ),
        (
            format!("requires readonly_and_readwrite_storage_textures;\n{function}"),
            "requires",
            1,
        ),
        (
            format!("diagnostic(off, derivative_uniformity);\n{function}"),
            "diagnostic",
            1,
        ),
    ] {
        match check(&source) {
            Err(UserWgslError::Directive {
                directive: found,
                line: at,
            }) => {
                assert_eq!((found.as_str(), at), (directive, line), "{source}");
            }
            other => panic!("{source}: {other:?}"),
        }
    }
    // Statements past the token limit, which could nest deeper than
    // the front end recurses (20,000 additions overflowed its stack).
    let sum = format!("u{}", " + u".repeat(MAX_STATEMENT_TOKENS / 2));
    let long = format!(
        "fn displacement_user(u: f32, v: f32) -> f32 {{\n    let a = u;\n    return {sum};\n}}"
    );
    assert_eq!(
        check(&long),
        Err(UserWgslError::StatementTooLong {
            line: 3,
            limit: MAX_STATEMENT_TOKENS
        })
    );
    let index = format!(
        "fn displacement_user(u: f32, v: f32) -> f32 {{ return vec2<f32>(u, v){}; }}",
        "[0]".repeat(20_000)
    );
    assert!(matches!(
        check(&index),
        Err(UserWgslError::StatementTooLong { line: 1, .. })
    ));
    let fits = format!("u{}", " + u".repeat(MAX_STATEMENT_TOKENS / 2 - 10));
    assert_eq!(
        check(&format!(
            "fn displacement_user(u: f32, v: f32) -> f32 {{ return {fits}; }}"
        )),
        Ok(())
    );
    // A name that only begins like a directive is not one.
    assert_eq!(check(&format!("const enabled = 1.0;\n{function}")), Ok(()));
}

/// D28: an array of a million floats drove a driver's compile to 23 GB;
/// function memory past the limit is refused, naming the variable and
/// its line, whether a `var`, a `let` of an array value or a constant.
#[test]
fn function_memory_past_the_limit_is_refused_with_its_name_and_line() {
    let var = "fn displacement_user(u: f32, v: f32) -> f32 {\n    var a: array<f32, 1000000>;\n    a[0] = u;\n    return a[0];\n}";
    match check(var) {
        Err(UserWgslError::Memory(m)) => {
            assert_eq!(
                (
                    m.function.as_str(),
                    m.name.as_str(),
                    m.line,
                    m.bytes,
                    m.limit
                ),
                ("displacement_user", "a", 2, 4_000_000, MAX_FUNCTION_MEMORY)
            );
        }
        other => panic!("{other:?}"),
    }
    // In a helper, as a `let` of an array value.
    let helper = "fn big(i: u32) -> f32 {\n    let t = array<f32, 8192>();\n    return t[i];\n}\nfn displacement_user(u: f32, v: f32) -> f32 { return big(0u) + u; }";
    let error = check(helper).unwrap_err();
    assert!(
        matches!(&error, UserWgslError::Memory(m) if m.function == "big" && m.line == 2 && m.bytes == 32768),
        "{error:?}"
    );
    assert!(
        error.to_string().contains("more than the 16384 bytes"),
        "{error}"
    );
    // A large constant used by the function.
    let constant = "const T = array<f32, 5000>();\nfn displacement_user(u: f32, v: f32) -> f32 {\n    var i = 0u;\n    return T[i] + u;\n}";
    let error = check(constant).unwrap_err();
    assert!(
        matches!(&error, UserWgslError::Memory(m) if m.name == "T" && m.bytes == 20000),
        "{error:?}"
    );
    // Several locals that together go over the limit.
    let several = "fn displacement_user(u: f32, v: f32) -> f32 {\n    var a: array<vec4<f32>, 600>;\n    var b: array<vec4<f32>, 600>;\n    return a[0].x + b[0].x + u;\n}";
    assert!(matches!(
        check(several),
        Err(UserWgslError::Memory(m)) if m.total == 19200
    ));
    // Within the limit: passes.
    let small = "fn displacement_user(u: f32, v: f32) -> f32 {\n    var a: array<f32, 1024>;\n    a[1] = v;\n    return a[1] + u;\n}";
    check(small).unwrap();
}
