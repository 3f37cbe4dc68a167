//! Checked mode ([`CompileOptions::checked`](crate::CompileOptions::checked)):
//! every index into a runtime-sized array resource, in the bodies and the
//! library, goes through a guard that compares it with the bound buffer's
//! real length (`arrayLength`). A violation is counted per procedure and
//! resource, with the first offending index and the bound, in control words
//! the host reads back; the run then fails with `RunError::OutOfBounds`.
//!
//! The rewrite is textual: `name[index]` becomes
//! `name[sched_checked_name(u32(index))]` wherever `name` is a guarded
//! resource and the bracket follows it directly (not a member `.name[`),
//! outside comments. Accesses through a pointer (`let p = &name; p[i]`) are
//! not seen. Line breaks are kept, so diagnostics keep their line numbers.

use crate::codegen::module::{Constant, Function, Global};
use crate::naming::guard_name;
use crate::plan::checked::{BOUND, COUNT, FIRST_INDEX, WORDS_PER_CHECK};
use crate::plan::{Plan, control};

/// The private variable holding the queue of the batch being run.
pub(crate) const RUNNING: &str = "sched_running";

/// `text` with every index into one of `names` guarded (see the module
/// documentation).
pub(crate) fn rewrite(text: &str, names: &[&str]) -> String {
    let chars: Vec<char> = text.chars().collect();
    rewrite_range(&chars, 0, chars.len(), names)
}

fn rewrite_range(chars: &[char], start: usize, end: usize, names: &[&str]) -> String {
    let mut out = String::with_capacity(end - start);
    let mut i = start;
    while i < end {
        let c = chars[i];
        // Comments are copied as they are.
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < end && chars[i] != '\n' {
                out.push(chars[i]);
                i += 1;
            }
            continue;
        }
        if c == '/' && chars.get(i + 1) == Some(&'*') {
            let close = (i + 2..end.saturating_sub(1))
                .find(|&j| chars[j] == '*' && chars[j + 1] == '/')
                .map_or(end, |j| j + 2);
            out.extend(&chars[i..close]);
            i = close;
            continue;
        }
        if !(c.is_ascii_alphabetic() || c == '_') {
            out.push(c);
            i += 1;
            continue;
        }
        let word_start = i;
        while i < end && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
            i += 1;
        }
        let word: String = chars[word_start..i].iter().collect();
        out.push_str(&word);
        let member = chars[..word_start]
            .iter()
            .rev()
            .find(|c| !c.is_whitespace())
            .is_some_and(|&c| c == '.');
        if member || !names.contains(&word.as_str()) {
            continue;
        }
        let mut open = i;
        while open < end && chars[open].is_whitespace() {
            open += 1;
        }
        if open >= end || chars[open] != '[' {
            continue;
        }
        let Some(close) = matching_bracket(chars, open, end) else {
            continue;
        };
        let index = rewrite_range(chars, open + 1, close, names);
        out.extend(&chars[i..open]);
        out.push_str(&format!("[{}(u32({index}))]", guard_name(&word)));
        i = close + 1;
    }
    out
}

/// The `]` that closes the `[` at `open`, if any before `end`.
fn matching_bracket(chars: &[char], open: usize, end: usize) -> Option<usize> {
    let mut depth = 0i32;
    for (j, &c) in chars.iter().enumerate().take(end).skip(open) {
        match c {
            '[' | '(' => depth += 1,
            ']' | ')' => {
                depth -= 1;
                if depth == 0 {
                    return (c == ']').then_some(j);
                }
            }
            _ => {}
        }
    }
    None
}

/// The constants the recorder uses: where the checks' words start and how
/// many resources are guarded.
pub(crate) fn constants(plan: &Plan) -> Vec<Constant> {
    let constant = Constant::u32;
    vec![
        constant(
            "SCHED_CTRL_CHECKS",
            control::words(plan.queues.len()),
            "Checked mode: first control word of the violation counts (after the queue blocks).",
        ),
        constant(
            "SCHED_CHECKED_RESOURCES",
            plan.guarded_resources().len() as u32,
            "Checked mode: guarded resources; each procedure has 3 words (count, first index, bound) per one.",
        ),
    ]
}

/// The private variable the guards read the running procedure from.
pub(crate) fn globals() -> Vec<Global> {
    vec![Global {
        attributes: String::new(),
        space: "private".into(),
        name: RUNNING.into(),
        ty: "u32".into(),
        doc: "Checked mode: the queue whose batch this invocation runs, for the guards.".into(),
    }]
}

/// The violation recorder and one guard per guarded resource.
pub(crate) fn functions(plan: &Plan) -> Vec<Function> {
    let guarded = plan.guarded_resources();
    let mut record = Function::new("sched_record_violation")
        .doc("Checked mode: counts an out-of-bounds index into guarded resource `r` for")
        .doc("the running procedure; the first one also records the index and the bound.")
        .param("r", "u32")
        .param("index", "u32")
        .param("bound", "u32");
    record.line(format!(
        "let word = SCHED_CTRL_CHECKS + {WORDS_PER_CHECK}u * ({RUNNING} * SCHED_CHECKED_RESOURCES + r);"
    ));
    record.line(format!(
        "if (atomicAdd(&sched_control[word + {COUNT}u], 1u) == 0u) {{"
    ));
    record.line(format!(
        "    atomicStore(&sched_control[word + {FIRST_INDEX}u], index);"
    ));
    record.line(format!(
        "    atomicStore(&sched_control[word + {BOUND}u], bound);"
    ));
    record.line("}");
    let mut functions = vec![record];
    for (r, name) in guarded.iter().enumerate() {
        let mut f = Function::new(guard_name(name))
            .doc(format!(
                "Checked mode: `index` if it lies within the buffer bound to `{name}`; otherwise"
            ))
            .doc("the violation is recorded and the last element (if any) is used instead, so")
            .doc("that nothing beyond the buffer is touched while the run goes on to fail.")
            .param("index", "u32")
            .returns("u32");
        f.line(format!("let bound = arrayLength(&{name});"));
        f.line("if (index < bound) {");
        f.line("    return index;");
        f.line("}");
        f.line(format!("sched_record_violation({r}u, index, bound);"));
        f.line("return select(0u, bound - 1u, bound > 0u);");
        functions.push(f);
    }
    functions
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_into_guarded_resources_are_rewritten_and_nothing_else() {
        let names = ["counts", "sink"];
        assert_eq!(
            rewrite("counts[i + 1u] = 2u;", &names),
            "counts[sched_checked_counts(u32(i + 1u))] = 2u;"
        );
        // Nested, with a call and a pointer.
        assert_eq!(
            rewrite("atomicAdd(&sink[counts[f(a, b[0])]], 1u);", &names),
            "atomicAdd(&sink[sched_checked_sink(u32(counts[sched_checked_counts(u32(f(a, b[0])))]))], 1u);"
        );
        // Members, other names, comments and a name without an index stay.
        let kept =
            "x.counts[0] = mycounts[1]; // counts[2]\n/* sink[3] */ let n = arrayLength(&counts);";
        assert_eq!(rewrite(kept, &names), kept);
        // Line breaks inside an index are kept.
        assert_eq!(
            rewrite("counts[\n  i\n] = 0u;", &names),
            "counts[sched_checked_counts(u32(\n  i\n))] = 0u;"
        );
    }
}
