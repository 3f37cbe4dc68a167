//! A typed description of the generated megakernel module, printed with
//! `Display`. Each section of the module is one field, so the order and the
//! layout of the output are decided in one place (`render`).

use std::fmt;

use crate::{SourceOrigin, naming};

/// One `const NAME: TYPE = VALUE;` declaration.
#[derive(Clone, Debug)]
pub(crate) struct Constant {
    pub name: String,
    pub ty: String,
    pub value: String,
    pub doc: String,
}

impl Constant {
    /// A `u32` constant.
    pub(crate) fn u32(name: &str, value: u32, doc: impl Into<String>) -> Self {
        Self {
            name: name.to_owned(),
            ty: "u32".to_owned(),
            value: format!("{value}u"),
            doc: doc.into(),
        }
    }
}

/// One module-scope variable declaration, e.g. a binding or a workgroup
/// array: `ATTRIBUTES var<SPACE> NAME: TYPE;`.
#[derive(Clone, Debug)]
pub(crate) struct Global {
    pub attributes: String,
    pub space: String,
    pub name: String,
    pub ty: String,
    pub doc: String,
}

/// A function. `body` lines are written with one level of indentation; a
/// function with `origin` set carries user text whose line numbers are tracked.
#[derive(Clone, Debug)]
pub(crate) struct Function {
    pub doc: Vec<String>,
    pub attributes: Vec<String>,
    pub name: String,
    pub params: Vec<(String, String)>,
    pub ret: Option<String>,
    /// Generated lines written before `body` (not part of its user region).
    pub prelude: Vec<String>,
    pub body: Vec<String>,
    pub origin: SourceOrigin,
}

impl Function {
    pub(crate) fn new(name: impl Into<String>) -> Self {
        Self {
            doc: Vec::new(),
            attributes: Vec::new(),
            name: name.into(),
            params: Vec::new(),
            ret: None,
            prelude: Vec::new(),
            body: Vec::new(),
            origin: SourceOrigin::Generated,
        }
    }

    pub(crate) fn doc(mut self, line: impl Into<String>) -> Self {
        self.doc.push(line.into());
        self
    }

    pub(crate) fn param(mut self, name: &str, ty: &str) -> Self {
        self.params.push((name.to_owned(), ty.to_owned()));
        self
    }

    pub(crate) fn returns(mut self, ty: &str) -> Self {
        self.ret = Some(ty.to_owned());
        self
    }

    pub(crate) fn line(&mut self, line: impl Into<String>) {
        self.body.push(line.into());
    }
}

/// A block of verbatim WGSL with its origin (item declarations, the library,
/// the runtime template).
#[derive(Clone, Debug)]
pub(crate) struct Verbatim {
    pub title: String,
    pub text: String,
    pub origin: SourceOrigin,
}

/// The whole module.
#[derive(Clone, Debug, Default)]
pub(crate) struct KernelModule {
    pub header: Vec<String>,
    pub constants: Vec<Constant>,
    pub items: Vec<Verbatim>,
    pub globals: Vec<Global>,
    pub library: Option<Verbatim>,
    pub runtime: Option<Verbatim>,
    /// The item-wide helpers, when the graph uses them.
    pub helpers: Option<Verbatim>,
    pub functions: Vec<Function>,
}

/// A range of lines of the rendered module and where they came from.
#[derive(Clone, Debug)]
pub(crate) struct Region {
    /// First line (1-based) of the region in the module.
    pub first_line: u32,
    /// Last line (inclusive).
    pub last_line: u32,
    /// Columns the generator added in front of each line.
    pub indent: u32,
    pub origin: SourceOrigin,
}

/// Text plus the map from module lines back to user sources.
#[derive(Clone, Debug)]
pub(crate) struct Rendered {
    pub text: String,
    pub regions: Vec<Region>,
}

impl Rendered {
    /// Maps a 1-based module line/column to (origin, line in that source, column).
    pub(crate) fn locate(&self, line: u32, column: u32) -> (SourceOrigin, u32, u32) {
        for region in &self.regions {
            if (region.first_line..=region.last_line).contains(&line) {
                return (
                    region.origin.clone(),
                    line - region.first_line + 1,
                    column.saturating_sub(region.indent).max(1),
                );
            }
        }
        (SourceOrigin::Generated, line, column)
    }
}

/// Writes text while counting lines, recording user regions.
struct Writer {
    text: String,
    line: u32,
    regions: Vec<Region>,
}

impl Writer {
    fn push_line(&mut self, line: &str) {
        self.text.push_str(line);
        self.text.push('\n');
        self.line += 1;
    }

    fn blank(&mut self) {
        self.push_line("");
    }

    fn section(&mut self, title: &str) {
        self.blank();
        self.push_line(&format!("// ---- {title} ----"));
    }

    /// Writes verbatim text, recording it as a region unless it is generated.
    fn verbatim(&mut self, text: &str, indent: &str, origin: &SourceOrigin) {
        let first = self.line + 1;
        for line in text.trim_end_matches('\n').lines() {
            if line.trim().is_empty() {
                self.push_line("");
            } else {
                self.push_line(&format!("{indent}{line}"));
            }
        }
        if *origin != SourceOrigin::Generated && self.line >= first {
            self.regions.push(Region {
                first_line: first,
                last_line: self.line,
                indent: indent.len() as u32,
                origin: origin.clone(),
            });
        }
    }

    fn function(&mut self, function: &Function) {
        self.blank();
        for doc in &function.doc {
            self.push_line(&format!("// {doc}"));
        }
        for attribute in &function.attributes {
            self.push_line(attribute);
        }
        let params: Vec<String> = function
            .params
            .iter()
            .map(|(name, ty)| format!("{name}: {ty}"))
            .collect();
        let ret = function
            .ret
            .as_ref()
            .map(|ty| format!(" -> {ty}"))
            .unwrap_or_default();
        self.push_line(&format!(
            "fn {}({}){} {{",
            function.name,
            params.join(", "),
            ret
        ));
        for line in &function.prelude {
            self.push_line(&format!("    {line}"));
        }
        let body = function.body.join("\n");
        self.verbatim(&body, "    ", &function.origin);
        self.push_line("}");
    }
}

impl KernelModule {
    /// Renders the module and the map of user regions.
    pub(crate) fn render(&self) -> Rendered {
        let mut w = Writer {
            text: String::new(),
            line: 0,
            regions: Vec::new(),
        };
        for line in &self.header {
            w.push_line(format!("// {line}").trim_end());
        }
        w.section("constants");
        for c in &self.constants {
            if !c.doc.is_empty() {
                w.push_line(&format!("// {}", c.doc));
            }
            w.push_line(&format!("const {}: {} = {};", c.name, c.ty, c.value));
        }
        for item in &self.items {
            w.section(&item.title);
            w.verbatim(&item.text, "", &item.origin);
        }
        w.section("bindings and workgroup state");
        for g in &self.globals {
            if !g.doc.is_empty() {
                w.push_line(&format!("// {}", g.doc));
            }
            let attributes = if g.attributes.is_empty() {
                String::new()
            } else {
                format!("{} ", g.attributes)
            };
            w.push_line(&format!(
                "{attributes}var<{}> {}: {};",
                g.space, g.name, g.ty
            ));
        }
        if let Some(library) = &self.library {
            w.section(&library.title);
            w.verbatim(&library.text, "", &library.origin);
        }
        if let Some(runtime) = &self.runtime {
            w.blank();
            w.verbatim(&runtime.text, "", &runtime.origin);
        }
        if let Some(helpers) = &self.helpers {
            w.blank();
            w.verbatim(&helpers.text, "", &helpers.origin);
        }
        let mut last_section = String::new();
        for function in &self.functions {
            let section = section_of(&function.name);
            if section != last_section {
                w.section(section);
                last_section = section.to_owned();
            }
            w.function(function);
        }
        Rendered {
            text: w.text,
            regions: w.regions,
        }
    }
}

/// Groups generated functions under a heading by their name prefix.
fn section_of(name: &str) -> &'static str {
    if name.starts_with(naming::DECODE_PREFIX) || name.starts_with(naming::ENCODE_PREFIX) {
        "item codecs"
    } else if name.starts_with(naming::ENQUEUE_PREFIX) {
        "enqueue functions"
    } else if name.starts_with(naming::BODY_PREFIX) {
        "procedure bodies"
    } else if name.starts_with(naming::RUNNER_PREFIX) {
        "procedure runners"
    } else if name.starts_with("sched_item_") {
        "item-wide helpers"
    } else if name == "sched_policy_start" {
        "queue policy"
    } else if name.starts_with("sched_payload_") {
        "queue payload access"
    } else if name.starts_with("sched_copy_") {
        "item copies"
    } else if name.starts_with("sched_trace_") {
        "tracing"
    } else {
        "entry point"
    }
}

impl fmt::Display for KernelModule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.render().text)
    }
}
