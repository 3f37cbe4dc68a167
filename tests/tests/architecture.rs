//! The workspace's structure, checked from its source text: the layers
//! inside each crate point one way, no source file grows past
//! [`MAX_SOURCE_LINES`], and nothing re-derives the dicing rule.
//!
//! `cargo test --release -p tests --test architecture -- --nocapture`
//! prints each crate's module graph in Graphviz form as well
//! (`docs/architecture.md` shows the layers it enforces).

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The longest a source file may be (tests and generated snapshots aside).
const MAX_SOURCE_LINES: usize = 600;

/// A crate's top-level modules and the modules each one names.
type ModuleGraph = BTreeMap<String, BTreeSet<String>>;

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("the tests crate sits in the workspace")
        .to_path_buf()
}

/// Every file under `dir` whose name ends in one of `extensions`, sorted.
fn files_under(dir: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        let Ok(entries) = fs::read_dir(&dir) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| extensions.contains(&e))
            {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The source without comments (line, doc and block comments) and without
/// string literals, so that prose and messages naming a module do not count
/// as a dependency on it.
fn code_only(source: &str) -> String {
    let bytes = source.as_bytes();
    let mut code = String::with_capacity(source.len());
    let mut i = 0;
    while i < bytes.len() {
        match (bytes[i], bytes.get(i + 1)) {
            (b'/', Some(b'/')) => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            (b'/', Some(b'*')) => {
                let mut depth = 0;
                while i < bytes.len() {
                    if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
                        depth += 1;
                        i += 2;
                    } else if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        i += 1;
                    }
                }
            }
            // A quote character literal is no string.
            (b'\'', Some(b'"')) if bytes.get(i + 2) == Some(&b'\'') => {
                code.push_str("'\"'");
                i += 3;
            }
            (b'"', _) => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
                code.push_str("\"\"");
            }
            (byte, _) => {
                code.push(char::from(byte));
                i += 1;
            }
        }
    }
    code
}

fn is_ident_byte(byte: u8) -> bool {
    byte.is_ascii_alphanumeric() || byte == b'_'
}

/// The identifier at the start of `text`.
fn leading_ident(text: &str) -> &str {
    let end = text
        .bytes()
        .position(|b| !is_ident_byte(b))
        .unwrap_or(text.len());
    &text[..end]
}

/// The first path segment of every item named in a `{...}` group that
/// starts at `text[0] == '{'`, with the group's length.
fn group_heads(text: &str) -> (Vec<&str>, usize) {
    let mut heads = Vec::new();
    let mut depth = 0;
    let mut expect_head = true;
    for (i, byte) in text.bytes().enumerate() {
        match byte {
            b'{' => {
                depth += 1;
                expect_head = depth == 1;
            }
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return (heads, i + 1);
                }
            }
            b',' if depth == 1 => expect_head = true,
            _ if expect_head && depth == 1 && is_ident_byte(byte) => {
                heads.push(leading_ident(&text[i..]));
                expect_head = false;
            }
            _ => {}
        }
    }
    (heads, text.len())
}

/// The names that `code` reaches through `crate::`: the first segment of
/// each path, and each item of a `crate::{...}` group.
fn crate_paths(code: &str) -> Vec<&str> {
    let mut names = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("crate::") {
        let preceded_by_ident = at > 0 && is_ident_byte(rest.as_bytes()[at - 1]);
        rest = &rest[at + "crate::".len()..];
        if preceded_by_ident {
            continue;
        }
        if rest.starts_with('{') {
            let (heads, _) = group_heads(rest);
            names.extend(heads);
        } else {
            names.push(leading_ident(rest));
        }
    }
    names
}

/// The crate root's re-exports: each re-exported name and the top-level
/// module it comes from (`pub use runtime::seeds::Seeds` maps `Seeds` to
/// `runtime`), so a `crate::Seeds` counts as a use of `runtime`.
fn root_reexports(lib: &str, modules: &BTreeSet<String>) -> BTreeMap<String, String> {
    let mut names = BTreeMap::new();
    for statement in code_only(lib).split(';') {
        let Some(at) = statement.find("pub use ") else {
            continue;
        };
        let path = statement[at + "pub use ".len()..].trim();
        let module = leading_ident(path);
        if !modules.contains(module) {
            continue;
        }
        let last = match path.rfind('{') {
            Some(open) => path[open + 1..].trim_end_matches('}').to_string(),
            None => path.rsplit("::").next().unwrap_or(path).to_string(),
        };
        for item in last.split(',') {
            let name = item.split(" as ").last().unwrap_or(item).trim();
            if !name.is_empty() {
                names.insert(name.to_string(), module.to_string());
            }
        }
    }
    names
}

/// The graph of `src`'s top-level modules (each file under `src/x/` or
/// `src/x.rs` belongs to module `x`).
fn module_graph(src: &Path) -> ModuleGraph {
    let files = files_under(src, &["rs"]);
    let module_of = |file: &Path| -> Option<String> {
        let relative = file.strip_prefix(src).ok()?;
        let first = relative.components().next()?.as_os_str().to_str()?;
        let name = first.trim_end_matches(".rs");
        (!matches!(name, "lib" | "main")).then(|| name.to_string())
    };
    let modules: BTreeSet<String> = files.iter().filter_map(|f| module_of(f)).collect();
    let lib = fs::read_to_string(src.join("lib.rs")).unwrap_or_default();
    let reexports = root_reexports(&lib, &modules);
    let mut graph: ModuleGraph = modules
        .iter()
        .map(|m| (m.clone(), BTreeSet::new()))
        .collect();
    for file in &files {
        let Some(from) = module_of(file) else {
            continue;
        };
        let source = fs::read_to_string(file).expect("source files are readable");
        for name in crate_paths(&code_only(&source)) {
            let to = if modules.contains(name) {
                Some(name.to_string())
            } else {
                reexports.get(name).cloned()
            };
            if let Some(to) = to.filter(|to| *to != from) {
                graph.entry(from.clone()).or_default().insert(to);
            }
        }
    }
    graph
}

/// The cycles of `graph`: its strongly connected components of more than
/// one module (Tarjan's algorithm).
fn cycles(graph: &ModuleGraph) -> Vec<Vec<String>> {
    struct Search<'g> {
        graph: &'g ModuleGraph,
        index: BTreeMap<&'g str, usize>,
        low: BTreeMap<&'g str, usize>,
        stack: Vec<&'g str>,
        on_stack: BTreeSet<&'g str>,
        found: Vec<Vec<String>>,
    }
    impl<'g> Search<'g> {
        fn visit(&mut self, module: &'g str) {
            let index = self.index.len();
            self.index.insert(module, index);
            self.low.insert(module, index);
            self.stack.push(module);
            self.on_stack.insert(module);
            for next in self.graph.get(module).into_iter().flatten() {
                let next = next.as_str();
                if !self.index.contains_key(next) {
                    self.visit(next);
                    let low = self.low[module].min(self.low[next]);
                    self.low.insert(module, low);
                } else if self.on_stack.contains(next) {
                    let low = self.low[module].min(self.index[next]);
                    self.low.insert(module, low);
                }
            }
            if self.low[module] == self.index[module] {
                let mut component = Vec::new();
                while let Some(top) = self.stack.pop() {
                    self.on_stack.remove(top);
                    component.push(top.to_string());
                    if top == module {
                        break;
                    }
                }
                if component.len() > 1 {
                    component.sort();
                    self.found.push(component);
                }
            }
        }
    }
    let mut search = Search {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        found: Vec::new(),
    };
    for module in graph.keys() {
        if !search.index.contains_key(module.as_str()) {
            search.visit(module);
        }
    }
    search.found
}

fn print_dot(name: &str, graph: &ModuleGraph) {
    eprintln!("digraph {name} {{");
    for (from, targets) in graph {
        for to in targets {
            eprintln!("    {from} -> {to};");
        }
    }
    eprintln!("}}");
}

fn checked_graph(crate_dir: &str) -> ModuleGraph {
    let graph = module_graph(&workspace_root().join(crate_dir).join("src"));
    print_dot(crate_dir, &graph);
    let cycles = cycles(&graph);
    assert!(
        cycles.is_empty(),
        "{crate_dir}: the top-level modules import each other in cycles: {cycles:?}"
    );
    graph
}

#[test]
fn scheduler_layers_point_one_way() {
    let graph = checked_graph("scheduler");
    for layer in ["plan", "codegen", "compile"] {
        assert!(graph.contains_key(layer), "scheduler has a `{layer}` layer");
    }
    let imports = |from: &str, to: &str| graph[from].contains(to);
    assert!(!imports("plan", "codegen") && !imports("plan", "compile"));
    assert!(!imports("codegen", "compile"));
}

#[test]
fn reyes_modules_point_one_way() {
    let graph = checked_graph("reyes");
    for (from, to) in [("reference", "gpu"), ("gpu", "reference")] {
        assert!(
            !graph[from].contains(to),
            "reyes::{from} must not import reyes::{to}"
        );
    }
}

#[test]
fn the_module_graph_sees_cycles_and_group_imports() {
    // The checker itself: a group import and a re-exported name both count,
    // and a two-module cycle is found.
    let code = code_only(
        "use crate::{alpha::A, beta}; // crate::gamma in a comment\n\
         fn f() { crate::Delta::new(); let _ = ('\"', \"crate::gamma\"); }",
    );
    assert_eq!(crate_paths(&code), ["alpha", "beta", "Delta"]);
    let graph: ModuleGraph = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec!["a"]),
    ]
    .into_iter()
    .map(|(from, to)| (from.into(), to.into_iter().map(String::from).collect()))
    .collect();
    assert_eq!(cycles(&graph), [vec!["a", "b", "c"]]);
}

#[test]
fn no_source_file_is_longer_than_the_limit() {
    let root = workspace_root();
    let mut too_long = Vec::new();
    for dir in fs::read_dir(&root)
        .expect("the workspace is readable")
        .flatten()
    {
        let dir = dir.path();
        let name = dir.file_name().and_then(|n| n.to_str()).unwrap_or("");
        // The `tests` crate and dot-folders (git, CI) are tests and tooling;
        // `target` is build output.
        if !dir.is_dir() || name.starts_with('.') || matches!(name, "tests" | "target" | "docs") {
            continue;
        }
        for file in files_under(&dir, &["rs", "wgsl"]) {
            let relative = file.strip_prefix(&root).unwrap_or(&file);
            if relative.components().any(|c| c.as_os_str() == "tests") {
                continue;
            }
            let lines = fs::read_to_string(&file).map_or(0, |text| text.lines().count());
            if lines > MAX_SOURCE_LINES {
                too_long.push(format!("{} ({lines} lines)", relative.display()));
            }
        }
    }
    assert!(
        too_long.is_empty(),
        "source files over {MAX_SOURCE_LINES} lines: {too_long:?}"
    );
}

#[test]
fn nothing_squares_the_micropolygon_side_back_into_a_rate() {
    // The dicing rule is computed once (`reyes::prepare`); a consumer that
    // multiplies the side by itself is re-deriving the shading rate.
    let src = workspace_root().join("reyes/src");
    let mut offenders = Vec::new();
    for file in files_under(&src, &["rs"]) {
        let code = code_only(&fs::read_to_string(&file).expect("readable"));
        for line in code.lines() {
            let squared = line.matches("micropolygon_side").count() >= 2 && line.contains('*')
                || line.contains("micropolygon_side.powi(2)");
            if squared {
                offenders.push(format!("{}: {}", file.display(), line.trim()));
            }
        }
    }
    assert!(offenders.is_empty(), "{offenders:?}");
}
