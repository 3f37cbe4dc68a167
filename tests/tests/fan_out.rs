//! Fan-outs derived from the bodies' enqueue calls for `Graph::connect`, and
//! the compile errors where none can be derived or a declared one is below
//! the derived bound. Pure tests: no GPU needed.

use scheduler::{CompileError, CompileOptions, Graph, Procedure};
use tests::graphs::Node;

/// The fan-out of `Source` into `Sink` for a `Source` body, connected with
/// `connect`; `threads` threads per item.
fn derived(body: &str, threads: u32) -> Result<u32, CompileError> {
    let mut graph = Graph::new("derived");
    let source = graph.procedure(
        Procedure::of::<Node>("Source")
            .initial(true)
            .threads_per_item(threads)
            .body(body),
    );
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect(&source, &sink);
    let compiled = graph.compile(&CompileOptions::default())?;
    Ok(compiled.queues()[0].targets[0].1)
}

#[test]
fn straight_line_branching_and_helper_bodies_get_their_bound() {
    let straight = "if (valid) {
    enqueue_Sink(item);
    enqueue_Sink(Node(item.depth + 1u, item.id));
    enqueue_Sink(item);
}";
    assert_eq!(derived(straight, 1), Ok(3));
    let branching = "if (!valid) {
    return;
}
if (item.id % 2u == 0u) {
    enqueue_Sink(item);
    enqueue_Sink(item);
} else if (item.id % 3u == 0u) {
    enqueue_Sink(item);
} else {
    switch item.depth {
        case 0u, 1u: { enqueue_Sink(item); enqueue_Sink(item); enqueue_Sink(item); }
        default: {}
    }
}";
    assert_eq!(derived(branching, 1), Ok(3));
    // A loop that does not enqueue bounds nothing; no call at all is 1.
    let looping = "var n = 0u;
for (var i = 0u; i < item.id; i += 1u) { n += i; }
if (valid && n > 3u) { enqueue_Sink(item); }";
    assert_eq!(derived(looping, 1), Ok(1));
    assert_eq!(derived("_ = item;", 1), Ok(1));
    // Every thread of an item counts, unless a condition on `thread` admits
    // fewer.
    assert_eq!(derived("if (valid) { enqueue_Sink(item); }", 8), Ok(8));
    assert_eq!(
        derived("if (valid && thread == 0u) { enqueue_Sink(item); }", 8),
        Ok(1)
    );
    assert_eq!(
        derived("if (valid && thread < 2u) { enqueue_Sink(item); }", 8),
        Ok(2)
    );
}

#[test]
fn calls_in_library_functions_count_where_they_are_called() {
    let mut graph = Graph::new("helpers");
    graph.library(
        "fn emit_pair(n: Node) {
    enqueue_Sink(n);
    if (n.id > 4u) {
        enqueue_Sink(n);
    }
}",
    );
    let source = graph.procedure(
        Procedure::of::<Node>("Source")
            .initial(true)
            .body("if (valid) { emit_pair(item); emit_pair(item); }"),
    );
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect(&source, &sink);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    assert_eq!(compiled.queues()[0].targets, [(1, 4)]);
}

#[test]
fn an_enqueue_inside_a_loop_needs_a_declared_fan_out() {
    let body = "if (valid) {
    for (var k = 0u; k < item.depth; k += 1u) {
        enqueue_Sink(Node(k, item.id));
    }
}";
    assert_eq!(
        derived(body, 1),
        Err(CompileError::FanOutNotDerivable {
            procedure: "Source".into(),
            target: "Sink".into(),
            via: "its body".into(),
        })
    );
    let message = derived(body, 1).unwrap_err().to_string();
    assert!(message.contains("connect_with_fan_out"), "{message}");

    // Declared, it compiles with the declared fan-out.
    let mut graph = Graph::new("declared");
    let source = graph.procedure(Procedure::of::<Node>("Source").initial(true).body(body));
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect_with_fan_out(&source, &sink, 10);
    let compiled = graph.compile(&CompileOptions::default()).unwrap();
    assert_eq!(compiled.queues()[0].targets, [(1, 10)]);
}

#[test]
fn a_declared_fan_out_below_the_derived_bound_is_an_error() {
    let mut graph = Graph::new("below");
    let source = graph.procedure(Procedure::of::<Node>("Source").initial(true).body(
        "if (valid) {
    enqueue_Sink(item);
    enqueue_Sink(item);
}",
    ));
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect_with_fan_out(&source, &sink, 1);
    assert_eq!(
        graph.compile(&CompileOptions::default()).unwrap_err(),
        CompileError::FanOutBelowBound {
            procedure: "Source".into(),
            target: "Sink".into(),
            declared: 1,
            bound: 2,
        }
    );
}

/// A small generator of random numbers (xorshift), seeded per run.
struct Random(u64);

impl Random {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// A random block of enqueues and `if`/`else` branches on the item's data,
/// and the most calls a path through it makes.
fn random_block(random: &mut Random, depth: u32, out: &mut String) -> u32 {
    let mut most = 0;
    for _ in 0..=random.below(3) {
        if depth > 0 && random.below(2) == 0 {
            let divisor = 2 + random.below(5);
            out.push_str(&format!("if (item.id % {divisor}u == 0u) {{\n"));
            let accept = random_block(random, depth - 1, out);
            out.push_str("} else {\n");
            let reject = if random.below(3) == 0 {
                0
            } else {
                random_block(random, depth - 1, out)
            };
            out.push_str("}\n");
            most += accept.max(reject);
        } else {
            out.push_str("enqueue_Sink(item);\n");
            most += 1;
        }
    }
    most
}

#[test]
fn random_branching_bodies_get_their_bound() {
    let seed = tests::seed("random branching bodies");
    // xorshift needs a state other than zero.
    let mut random = Random(seed | 1);
    for _ in 0..20 {
        let mut body = String::new();
        let most = random_block(&mut random, 3, &mut body);
        assert_eq!(derived(&body, 1), Ok(most), "seed {seed}, body:\n{body}");
    }
}

/// The per-item check as checked mode generates it, for review: the
/// enqueue's count, the chunk loop's check of the previous chunk (with the
/// barrier items of several threads need) and the check after the last.
#[test]
fn snapshot_of_the_per_item_check() {
    let mut graph = Graph::new("per-item check");
    let source = graph.procedure(
        Procedure::of::<Node>("Source")
            .initial(true)
            .threads_per_item(4)
            .body("if (valid && thread < 2u) {\n    enqueue_Sink(item);\n}"),
    );
    let sink = graph.procedure(Procedure::of::<Node>("Sink").body("_ = item;"));
    graph.connect(&source, &sink);
    let options = CompileOptions {
        workgroup_size: 64,
        chunks_per_batch: 2,
        ..CompileOptions::default()
    }
    .checked();
    let compiled = graph.compile(&options).unwrap();
    assert_eq!(compiled.queues()[0].targets, [(1, 2)]);
    insta::assert_snapshot!("per_item_check", compiled.wgsl());
    // Without checked mode none of it is generated.
    let unchecked = graph
        .compile(&CompileOptions {
            checked: false,
            ..options
        })
        .unwrap();
    assert!(
        !unchecked.wgsl().contains("fan_out"),
        "{}",
        unchecked.wgsl()
    );
}
