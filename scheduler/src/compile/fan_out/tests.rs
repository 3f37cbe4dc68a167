use super::*;

/// The bound of `fn body(item: u32, valid: bool, thread: u32, slot: u32)`
/// into `enqueue_T`, with `library` declaring helpers.
fn bound_of(body: &str, library: &str, threads: u32) -> Result<u32, InLoop> {
    let text = format!(
        "fn enqueue_T(x: u32) {{}}\n{library}\nfn body(item: u32, valid: bool, thread: u32, slot: u32) {{\n{body}\n}}\n"
    );
    let module = naga::front::wgsl::parse_str(&text).expect("test WGSL parses");
    let find = |name: &str| {
        module
            .functions
            .iter()
            .find(|(_, f)| f.name.as_deref() == Some(name))
            .map(|(h, _)| h)
            .expect("function exists")
    };
    bound(&module, find("body"), find("enqueue_T"), threads)
}

#[test]
fn straight_line_calls_add_up() {
    assert_eq!(bound_of("", "", 1), Ok(0));
    assert_eq!(bound_of("enqueue_T(1u);", "", 1), Ok(1));
    assert_eq!(
        bound_of(
            "enqueue_T(1u);\nlet a = item + 1u;\nenqueue_T(a);\nenqueue_T(2u);",
            "",
            1
        ),
        Ok(3)
    );
}

#[test]
fn branches_count_their_larger_side() {
    let body = "if (valid && item > 3u) {\n    enqueue_T(1u);\n    enqueue_T(2u);\n} else {\n    enqueue_T(3u);\n}\nenqueue_T(4u);";
    assert_eq!(bound_of(body, "", 1), Ok(3));
    let switch = "switch item {\n    case 0u: { enqueue_T(1u); }\n    case 1u, 2u: { enqueue_T(1u); enqueue_T(2u); }\n    default: {}\n}";
    assert_eq!(bound_of(switch, "", 1), Ok(2));
}

#[test]
fn a_return_ends_its_path() {
    let body = "if (item == 0u) {\n    enqueue_T(1u);\n    return;\n}\nenqueue_T(2u);";
    assert_eq!(bound_of(body, "", 1), Ok(1));
    let body =
        "if (item == 0u) {\n    enqueue_T(1u);\n    enqueue_T(1u);\n    return;\n}\nenqueue_T(2u);";
    assert_eq!(bound_of(body, "", 1), Ok(2));
}

#[test]
fn helpers_count_where_they_are_called() {
    let library = "fn twice(x: u32) {\n    enqueue_T(x);\n    if (x > 1u) { enqueue_T(x); }\n}";
    assert_eq!(bound_of("twice(item);\ntwice(1u);", library, 1), Ok(4));
}

#[test]
fn every_thread_of_an_item_counts_unless_one_thread_is_chosen() {
    assert_eq!(bound_of("enqueue_T(1u);", "", 4), Ok(4));
    assert_eq!(
        bound_of("if (valid && thread == 0u) {\n    enqueue_T(1u);\n}", "", 4),
        Ok(1)
    );
    assert_eq!(
        bound_of(
            "if (0u == thread && item > 2u) {\n    enqueue_T(1u);\n}",
            "",
            4
        ),
        Ok(1)
    );
    // `thread < C` admits C threads, `C >= thread` C + 1.
    assert_eq!(
        bound_of(
            "if (valid) {\n    if (thread < 4u) {\n        enqueue_T(1u);\n    }\n}",
            "",
            16
        ),
        Ok(4)
    );
    assert_eq!(
        bound_of(
            "if (valid && 2u >= thread) {\n    enqueue_T(1u);\n}",
            "",
            16
        ),
        Ok(3)
    );
    // `||` admits every thread.
    assert_eq!(
        bound_of("if (thread == 0u || valid) {\n    enqueue_T(1u);\n}", "", 4),
        Ok(4)
    );
    assert_eq!(
        bound_of(
            "if (thread == 1u) {\n    enqueue_T(1u);\n    enqueue_T(2u);\n}\nif (valid) {\n    enqueue_T(3u);\n}",
            "",
            8
        ),
        Ok(10)
    );
}

#[test]
fn a_call_in_a_loop_has_no_bound() {
    let body = "for (var i = 0u; i < item; i += 1u) {\n    enqueue_T(i);\n}";
    assert_eq!(
        bound_of(body, "", 1),
        Err(InLoop {
            via: "its body".into()
        })
    );
    let library = "fn many(n: u32) {\n    for (var i = 0u; i < n; i += 1u) {\n        if (i > 2u) { enqueue_T(i); }\n    }\n}";
    assert_eq!(
        bound_of("many(item);", library, 1),
        Err(InLoop {
            via: "helper `many`".into()
        })
    );
    // A helper that enqueues, called in a loop of the body.
    let library = "fn once(x: u32) { enqueue_T(x); }";
    let body = "var i = 0u;\nloop {\n    if (i >= item) { break; }\n    once(i);\n    i += 1u;\n}";
    assert!(bound_of(body, library, 1).is_err());
    // A loop without enqueues costs nothing, and its early return ends a path.
    let body =
        "for (var i = 0u; i < item; i += 1u) {\n    if (i == 7u) { return; }\n}\nenqueue_T(1u);";
    assert_eq!(bound_of(body, "", 1), Ok(1));
}
