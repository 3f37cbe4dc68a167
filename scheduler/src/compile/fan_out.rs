//! Fan-out derived from a body: the most calls to `enqueue_<Target>` that one
//! item of a procedure can make, counted on the validated naga module.
//!
//! The count walks the body and every function it calls. Statements in
//! sequence add up; of an `if` or a `switch`, the larger branch counts; a
//! `return` ends its path (the paths that return and those that fall
//! through are counted apart, so `if (c) { enqueue; return; } enqueue;` is
//! 1, not 2). A call inside a loop (directly or through a function that
//! enqueues) has no bound: the fan-out must then be declared.
//!
//! Every thread of an item runs the body, so a call counts once per thread
//! of the item, unless an enclosing `if` of the body admits fewer threads:
//! `thread == C` admits one, `thread < C` admits `C` (`C` a constant), and a
//! `&&` with such a term as many (`if (valid && thread == 0u) { ... }`).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use naga::{BinaryOperator, Block, Expression, Function, Handle, Module, Statement};

use crate::CompileError;
use crate::naming::{body_name, enqueue_name};
use crate::plan::Plan;

/// The position of `thread` among a body's parameters (`item`, `valid`,
/// `thread`, `slot`).
const THREAD_ARGUMENT: u32 = 2;

/// A call to the target inside a loop, in the function named here.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct InLoop {
    /// The function whose loop makes the call: `its body`, or `helper `f``.
    pub via: String,
}

/// What the paths through a statement or block enqueue, by how they end:
/// falling through, returning from the function, or leaving the enclosing
/// loop or switch (`break`, `continue`). `None`: no path ends that way.
#[derive(Clone, Copy, Debug, Default)]
struct Paths {
    fall: Option<u32>,
    exit: Option<u32>,
    leave: Option<u32>,
}

impl Paths {
    fn falling(count: u32) -> Self {
        Self {
            fall: Some(count),
            ..Self::default()
        }
    }

    /// Either of two alternatives.
    fn either(self, other: Self) -> Self {
        Self {
            fall: self.fall.max(other.fall),
            exit: self.exit.max(other.exit),
            leave: self.leave.max(other.leave),
        }
    }

    /// `next` after the paths of `self` that fall through.
    fn then(self, next: Self) -> Self {
        let Some(before) = self.fall else {
            return self;
        };
        let add = |count: Option<u32>| count.map(|c| before.saturating_add(c));
        Self {
            fall: add(next.fall),
            exit: self.exit.max(add(next.exit)),
            leave: self.leave.max(add(next.leave)),
        }
    }

    fn most(self) -> u32 {
        self.fall.max(self.exit).max(self.leave).unwrap_or(0)
    }
}

/// Every procedure's targets with their fan-outs: `declared` where the graph
/// declares one, the bound derived from the body (at least 1) for the pairs
/// of `derived` that it does not. A declared fan-out below a derived bound,
/// and a pair of `derived` without a bound, are errors.
pub(crate) fn targets(
    module: &Module,
    plan: &Plan,
    declared: &[BTreeMap<usize, u32>],
    derived: &BTreeSet<(usize, usize)>,
) -> Result<Vec<BTreeMap<usize, u32>>, CompileError> {
    let function = |name: &str| {
        module
            .functions
            .iter()
            .find(|(_, f)| f.name.as_deref() == Some(name))
            .map(|(handle, _)| handle)
    };
    let mut targets = declared.to_vec();
    let pairs = declared
        .iter()
        .enumerate()
        .flat_map(|(from, to)| to.keys().map(move |&to| (from, to)))
        .chain(derived.iter().copied());
    for (from, to) in pairs {
        let (source, target) = (&plan.queues[from], &plan.queues[to]);
        let (Some(body), Some(enqueue)) = (
            function(&body_name(&source.name)),
            function(&enqueue_name(&target.name)),
        ) else {
            continue;
        };
        let derivation = bound(module, body, enqueue, source.threads_per_item);
        match (declared[from].get(&to), derivation) {
            (Some(&fan_out), Ok(bound)) if fan_out < bound => {
                return Err(CompileError::FanOutBelowBound {
                    procedure: source.name.clone(),
                    target: target.name.clone(),
                    declared: fan_out,
                    bound,
                });
            }
            (Some(_), _) => {}
            (None, Ok(bound)) => {
                targets[from].insert(to, bound.max(1));
            }
            (None, Err(InLoop { via })) => {
                return Err(CompileError::FanOutNotDerivable {
                    procedure: source.name.clone(),
                    target: target.name.clone(),
                    via,
                });
            }
        }
    }
    Ok(targets)
}

/// The most items one item of the procedure whose body is `body` enqueues
/// through `enqueue` (the target's generated enqueue function), with
/// `threads` threads per item; or the loop that leaves it unbounded.
pub(crate) fn bound(
    module: &Module,
    body: Handle<Function>,
    enqueue: Handle<Function>,
    threads: u32,
) -> Result<u32, InLoop> {
    let mut walker = Walker {
        module,
        body,
        enqueue,
        memo: HashMap::new(),
    };
    walker.function(body, threads)
}

struct Walker<'a> {
    module: &'a Module,
    body: Handle<Function>,
    enqueue: Handle<Function>,
    /// Per function and weight of a call: its bound.
    memo: HashMap<(Handle<Function>, u32), Result<u32, InLoop>>,
}

impl Walker<'_> {
    /// The bound of one call of `function`, each enqueue counting `weight`.
    fn function(&mut self, function: Handle<Function>, weight: u32) -> Result<u32, InLoop> {
        if let Some(known) = self.memo.get(&(function, weight)) {
            return known.clone();
        }
        let result = self
            .block(function, &self.module.functions[function].body, weight)
            .map(|paths| paths.fall.max(paths.exit).unwrap_or(0));
        self.memo.insert((function, weight), result.clone());
        result
    }

    fn block(
        &mut self,
        function: Handle<Function>,
        block: &Block,
        weight: u32,
    ) -> Result<Paths, InLoop> {
        let mut paths = Paths::falling(0);
        for statement in block.iter() {
            if paths.fall.is_none() {
                break;
            }
            let next = self.statement(function, statement, weight)?;
            paths = paths.then(next);
        }
        Ok(paths)
    }

    fn statement(
        &mut self,
        function: Handle<Function>,
        statement: &Statement,
        weight: u32,
    ) -> Result<Paths, InLoop> {
        Ok(match statement {
            Statement::Call { function: f, .. } if *f == self.enqueue => Paths::falling(weight),
            Statement::Call { function: f, .. } => Paths::falling(self.function(*f, weight)?),
            Statement::Block(inner) => self.block(function, inner, weight)?,
            Statement::If {
                condition,
                accept,
                reject,
            } => {
                let admitted = if function == self.body {
                    threads_admitted(self.module, &self.module.functions[function], *condition)
                } else {
                    None
                };
                let accepted =
                    self.block(function, accept, admitted.map_or(weight, |a| a.min(weight)))?;
                accepted.either(self.block(function, reject, weight)?)
            }
            Statement::Switch { cases, .. } => {
                // From the last case up: a case that falls through continues
                // with the next one's paths.
                let mut result = Paths::default();
                let mut next: Option<Paths> = None;
                for case in cases.iter().rev() {
                    let own = self.block(function, &case.body, weight)?;
                    let paths = match next {
                        Some(following) if case.fall_through => own.then(following),
                        _ => own,
                    };
                    result = result.either(Paths {
                        fall: paths.fall.max(paths.leave),
                        exit: paths.exit,
                        leave: None,
                    });
                    next = Some(paths);
                }
                result
            }
            Statement::Loop {
                body, continuing, ..
            } => {
                let inside = self
                    .block(function, body, weight)?
                    .either(self.block(function, continuing, weight)?);
                if inside.most() > 0 {
                    let via = if function == self.body {
                        "its body".to_owned()
                    } else {
                        format!(
                            "helper `{}`",
                            self.module.functions[function]
                                .name
                                .as_deref()
                                .unwrap_or_default()
                        )
                    };
                    return Err(InLoop { via });
                }
                Paths {
                    fall: Some(0),
                    exit: inside.exit,
                    leave: None,
                }
            }
            Statement::Return { .. } | Statement::Kill => Paths {
                exit: Some(0),
                ..Paths::default()
            },
            Statement::Break | Statement::Continue => Paths {
                leave: Some(0),
                ..Paths::default()
            },
            _ => Paths::falling(0),
        })
    }
}

/// The most threads of an item for which `condition` can hold, if it says:
/// `thread == C` admits 1, `thread < C` admits `C`, `thread <= C` admits
/// `C + 1` (either way round, `C` a constant); a `&&` admits the fewer of
/// its sides, a `||` the sum.
fn threads_admitted(
    module: &Module,
    function: &Function,
    condition: Handle<Expression>,
) -> Option<u32> {
    let expressions = &function.expressions;
    let is_thread = |e: Handle<Expression>| {
        matches!(
            expressions[e],
            Expression::FunctionArgument(THREAD_ARGUMENT)
        )
    };
    let constant = |e: Handle<Expression>| {
        let literal = match expressions[e] {
            Expression::Literal(literal) => literal,
            Expression::Constant(c) => match module.global_expressions[module.constants[c].init] {
                Expression::Literal(literal) => literal,
                _ => return None,
            },
            _ => return None,
        };
        match literal {
            naga::Literal::U32(value) => Some(value),
            naga::Literal::I32(value) => u32::try_from(value).ok(),
            naga::Literal::AbstractInt(value) => u32::try_from(value).ok(),
            _ => None,
        }
    };
    let Expression::Binary { op, left, right } = expressions[condition] else {
        // naga lowers a `&&` or `||` evaluated at run time to an unnamed
        // variable set by an `if` (see `short_circuit`).
        let Expression::Load { pointer } = expressions[condition] else {
            return None;
        };
        let Expression::LocalVariable(variable) = expressions[pointer] else {
            return None;
        };
        if function.local_variables[variable].name.is_some() {
            return None;
        }
        let (op, left, right) = short_circuit(function, &function.body, variable)?;
        let (left, right) = (
            threads_admitted(module, function, left),
            threads_admitted(module, function, right),
        );
        return match op {
            BinaryOperator::LogicalAnd => left.min(right).or(left).or(right),
            _ => left.zip(right).map(|(l, r)| l.saturating_add(r)),
        };
    };
    // `thread OP C`, with `C OP thread` turned round.
    let (op, value) = if is_thread(left) {
        (op, constant(right))
    } else if is_thread(right) {
        let turned = match op {
            BinaryOperator::Less => BinaryOperator::Greater,
            BinaryOperator::LessEqual => BinaryOperator::GreaterEqual,
            BinaryOperator::Greater => BinaryOperator::Less,
            BinaryOperator::GreaterEqual => BinaryOperator::LessEqual,
            other => other,
        };
        (turned, constant(left))
    } else {
        let (left, right) = (
            threads_admitted(module, function, left),
            threads_admitted(module, function, right),
        );
        return match op {
            BinaryOperator::LogicalAnd => left.min(right).or(left).or(right),
            BinaryOperator::LogicalOr => left.zip(right).map(|(l, r)| l.saturating_add(r)),
            _ => None,
        };
    };
    match op {
        BinaryOperator::Equal => Some(1),
        BinaryOperator::Less => value,
        BinaryOperator::LessEqual => value.map(|v| v.saturating_add(1)),
        _ => None,
    }
}

/// The operator and operands of the lowered `left && right` or `left ||
/// right` that sets `variable`: naga writes `if (left) { v = right; } else {
/// v = false; }` and `if (!left) { v = right; } else { v = true; }`.
fn short_circuit(
    function: &Function,
    block: &Block,
    variable: Handle<naga::LocalVariable>,
) -> Option<(BinaryOperator, Handle<Expression>, Handle<Expression>)> {
    let expressions = &function.expressions;
    let stores = |block: &Block| match block.last() {
        Some(&Statement::Store { pointer, value }) => {
            matches!(expressions[pointer], Expression::LocalVariable(v) if v == variable)
                .then_some(value)
        }
        _ => None,
    };
    block.iter().find_map(|statement| match statement {
        Statement::If {
            condition,
            accept,
            reject,
        } => {
            let lowered = stores(accept)
                .zip(stores(reject))
                .and_then(|(right, otherwise)| {
                    match (&expressions[*condition], &expressions[otherwise]) {
                        (_, Expression::Literal(naga::Literal::Bool(false))) => {
                            Some((BinaryOperator::LogicalAnd, *condition, right))
                        }
                        (
                            &Expression::Unary {
                                op: naga::UnaryOperator::LogicalNot,
                                expr,
                            },
                            Expression::Literal(naga::Literal::Bool(true)),
                        ) => Some((BinaryOperator::LogicalOr, expr, right)),
                        _ => None,
                    }
                });
            match lowered {
                Some(found) => Some(found),
                None => short_circuit(function, accept, variable)
                    .or_else(|| short_circuit(function, reject, variable)),
            }
        }
        Statement::Block(inner) => short_circuit(function, inner, variable),
        Statement::Loop {
            body, continuing, ..
        } => short_circuit(function, body, variable)
            .or_else(|| short_circuit(function, continuing, variable)),
        Statement::Switch { cases, .. } => cases
            .iter()
            .find_map(|case| short_circuit(function, &case.body, variable)),
        _ => None,
    })
}

#[cfg(test)]
mod tests;
