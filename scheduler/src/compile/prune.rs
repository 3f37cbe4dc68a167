//! Specialization of the generated module to what a run needs.
//!
//! Graph constants ([`crate::Graph::constant`]) turn a caller's switches
//! into WGSL `const`s. This pass then, on the validated module:
//!
//! 1. **folds** every `if` whose condition is a constant expression: the
//!    branch that cannot run is deleted and the other one stays as a plain
//!    `{ ... }` block;
//! 2. **drops** every function that no entry point reaches any more, with
//!    the comment lines directly above it.
//!
//! Both edit the module's *text*, located through naga's spans, so the
//! output keeps the sources' comments and layout, and the driver never sees
//! the code a run cannot execute. The result is parsed and validated again
//! by the caller.

use std::collections::BTreeSet;
use std::ops::Range;

use super::checks::collect_calls;
use text::{IfShape, Otherwise, delete_ranges, whole_lines, with_leading_comments};

use naga::{BinaryOperator, Block, Expression, Handle, Literal, Module, Statement, UnaryOperator};

/// What the pass removed, for the compiled graph's summary.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(crate) struct Pruned {
    /// The specialized module text.
    pub text: String,
    /// `if` statements folded to one branch.
    pub folded_branches: usize,
    /// Names of the functions dropped, in module order.
    pub dropped_functions: Vec<String>,
}

/// Folds constant `if`s in `source` (whose parse is `module`), then drops
/// unreachable functions.
pub(crate) fn prune(
    source: &str,
    module: &Module,
) -> Result<Pruned, naga::front::wgsl::ParseError> {
    let mut folds = Folds::default();
    for (_, function) in module.functions.iter() {
        folds.block(source, module, &function.expressions, &function.body);
    }
    for entry in &module.entry_points {
        let function = &entry.function;
        folds.block(source, module, &function.expressions, &function.body);
    }
    let folded_branches = folds.count;
    let folded = delete_ranges(source, folds.deletions);
    let folded_module = naga::front::wgsl::parse_str(&folded)?;
    let (text, dropped_functions) = drop_unreachable_functions(&folded, &folded_module);
    Ok(Pruned {
        text,
        folded_branches,
        dropped_functions,
    })
}

/// The deletions that fold constant `if`s.
#[derive(Default)]
struct Folds {
    deletions: Vec<Range<usize>>,
    count: usize,
}

impl Folds {
    fn block(
        &mut self,
        source: &str,
        module: &Module,
        expressions: &naga::Arena<Expression>,
        block: &Block,
    ) {
        for (statement, span) in block.span_iter() {
            match statement {
                Statement::If {
                    condition,
                    accept,
                    reject,
                } => {
                    let Some(range) = span.to_range() else {
                        continue;
                    };
                    // An `else if` is nested in the reject block with a span
                    // that starts at `else`; the outer `if` handles it.
                    if !source[range.clone()].starts_with("if") {
                        self.block(source, module, expressions, accept);
                        self.block(source, module, expressions, reject);
                        continue;
                    }
                    self.fold_if(
                        source,
                        module,
                        expressions,
                        range,
                        *condition,
                        accept,
                        reject,
                    );
                }
                Statement::Block(inner) => self.block(source, module, expressions, inner),
                Statement::Loop {
                    body, continuing, ..
                } => {
                    self.block(source, module, expressions, body);
                    self.block(source, module, expressions, continuing);
                }
                Statement::Switch { cases, .. } => {
                    for case in cases {
                        self.block(source, module, expressions, &case.body);
                    }
                }
                _ => {}
            }
        }
    }

    /// `if` statement text at `range` (`if c { a } [else { b } | else if ...]`).
    #[expect(
        clippy::too_many_arguments,
        reason = "the statement's parts, as naga splits them"
    )]
    fn fold_if(
        &mut self,
        source: &str,
        module: &Module,
        expressions: &naga::Arena<Expression>,
        range: Range<usize>,
        condition: Handle<Expression>,
        accept: &Block,
        reject: &Block,
    ) {
        let Some(shape) = IfShape::scan(source, range.clone()) else {
            // Text this pass does not recognise: leave the statement whole.
            self.block(source, module, expressions, accept);
            self.block(source, module, expressions, reject);
            return;
        };
        match evaluate(module, expressions, condition) {
            None => {
                self.block(source, module, expressions, accept);
                self.else_branch(source, module, expressions, &shape, reject);
            }
            Some(Value::Bool(true)) => {
                self.count += 1;
                self.deletions.push(range.start..shape.accept.start);
                self.deletions.push(shape.accept.end..range.end);
                self.block(source, module, expressions, accept);
            }
            Some(Value::Bool(false)) => {
                self.count += 1;
                match shape.otherwise {
                    Otherwise::Nothing => self.deletions.push(whole_lines(source, range)),
                    Otherwise::Block(block) => {
                        self.deletions.push(range.start..block.start);
                        self.block(source, module, expressions, reject);
                    }
                    Otherwise::ElseIf(at) => {
                        self.deletions.push(range.start..at);
                        self.nested_if(source, module, expressions, at..range.end, reject);
                    }
                }
            }
            Some(_) => {}
        }
    }

    fn else_branch(
        &mut self,
        source: &str,
        module: &Module,
        expressions: &naga::Arena<Expression>,
        shape: &IfShape,
        reject: &Block,
    ) {
        match shape.otherwise {
            Otherwise::ElseIf(at) => {
                self.nested_if(source, module, expressions, at..shape.end, reject);
            }
            _ => self.block(source, module, expressions, reject),
        }
    }

    /// The `if` of an `else if` chain, at `range`: naga nests it in the
    /// reject block, with a span that starts at `else` and ends where the
    /// whole chain does (a `&&` or `||` in its condition puts statements of
    /// its own before it).
    fn nested_if(
        &mut self,
        source: &str,
        module: &Module,
        expressions: &naga::Arena<Expression>,
        range: Range<usize>,
        reject: &Block,
    ) {
        let nested = reject
            .span_iter()
            .find_map(|(statement, span)| match statement {
                Statement::If {
                    condition,
                    accept,
                    reject,
                } if span.to_range().is_some_and(|r| r.end == range.end) => {
                    Some((*condition, accept, reject))
                }
                _ => None,
            });
        match nested {
            Some((condition, accept, inner_reject)) => {
                self.fold_if(
                    source,
                    module,
                    expressions,
                    range,
                    condition,
                    accept,
                    inner_reject,
                );
            }
            None => self.block(source, module, expressions, reject),
        }
    }
}

/// A constant's value, as far as conditions need.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Value {
    Bool(bool),
    Int(i128),
}

/// The value of `expression` when it is constant: literals, named
/// constants, `!`, comparisons of integers and booleans, and `&&`/`||`
/// (which short-circuit: `false && x` is false whatever `x` is).
fn evaluate(
    module: &Module,
    expressions: &naga::Arena<Expression>,
    expression: Handle<Expression>,
) -> Option<Value> {
    let recurse = |h| evaluate(module, expressions, h);
    match &expressions[expression] {
        Expression::Literal(literal) => literal_value(*literal),
        Expression::Constant(constant) => {
            let init = module.constants[*constant].init;
            evaluate(module, &module.global_expressions, init)
        }
        Expression::Unary {
            op: UnaryOperator::LogicalNot,
            expr,
        } => match recurse(*expr)? {
            Value::Bool(b) => Some(Value::Bool(!b)),
            Value::Int(_) => None,
        },
        Expression::Binary { op, left, right } => {
            // `false && x` and `true || x` are decided by one side, and so
            // are `x && false` and `x || true`: WGSL expressions in
            // conditions have no side effects once naga has lowered calls
            // into statements of their own.
            let decides = |value: Option<Value>| match (op, value) {
                (BinaryOperator::LogicalAnd, Some(Value::Bool(false)))
                | (BinaryOperator::LogicalOr, Some(Value::Bool(true))) => value,
                _ => None,
            };
            let left_value = recurse(*left);
            if let Some(decided) = decides(left_value) {
                return Some(decided);
            }
            let right_value = recurse(*right);
            if let Some(decided) = decides(right_value) {
                return Some(decided);
            }
            binary(*op, left_value?, right_value?)
        }
        _ => None,
    }
}

fn literal_value(literal: Literal) -> Option<Value> {
    Some(match literal {
        Literal::Bool(b) => Value::Bool(b),
        Literal::U32(v) => Value::Int(v.into()),
        Literal::I32(v) => Value::Int(v.into()),
        Literal::U64(v) => Value::Int(v.into()),
        Literal::I64(v) => Value::Int(v.into()),
        Literal::AbstractInt(v) => Value::Int(v.into()),
        _ => return None,
    })
}

fn binary(op: BinaryOperator, left: Value, right: Value) -> Option<Value> {
    use BinaryOperator as B;
    Some(Value::Bool(match (left, right) {
        (Value::Bool(a), Value::Bool(b)) => match op {
            B::Equal => a == b,
            B::NotEqual => a != b,
            B::LogicalAnd => a && b,
            B::LogicalOr => a || b,
            _ => return None,
        },
        (Value::Int(a), Value::Int(b)) => match op {
            B::Equal => a == b,
            B::NotEqual => a != b,
            B::Less => a < b,
            B::LessEqual => a <= b,
            B::Greater => a > b,
            B::GreaterEqual => a >= b,
            _ => return None,
        },
        _ => return None,
    }))
}

/// `source` without the functions no entry point calls (directly or not),
/// and their names.
fn drop_unreachable_functions(source: &str, module: &Module) -> (String, Vec<String>) {
    let mut reached = BTreeSet::new();
    let mut stack: Vec<Handle<naga::Function>> = Vec::new();
    for entry in &module.entry_points {
        collect_calls(&entry.function.body, &mut stack);
    }
    while let Some(function) = stack.pop() {
        if reached.insert(function) {
            collect_calls(&module.functions[function].body, &mut stack);
        }
    }
    let mut deletions = Vec::new();
    let mut dropped = Vec::new();
    for (handle, function) in module.functions.iter() {
        if reached.contains(&handle) {
            continue;
        }
        let Some(range) = module.functions.get_span(handle).to_range() else {
            continue;
        };
        if !source[range.clone()].starts_with("fn") {
            continue;
        }
        deletions.push(with_leading_comments(source, whole_lines(source, range)));
        dropped.push(function.name.clone().unwrap_or_default());
    }
    (delete_ranges(source, deletions), dropped)
}

mod text;

#[cfg(test)]
mod tests;
