//! Checks on user WGSL (a scene's displacement function, and the parts
//! every user shader shares: parsing, module-scope names, function memory,
//! barriers, validation), made on naga's IR of the user's source alone, before it joins the megakernel: errors carry the
//! line in the user's own text, the function is found by name in the IR (not
//! by a substring, which a comment would satisfy), and the function cannot
//! reach anything of the renderer's. A user function sees its arguments, its
//! own helpers and constants and WGSL's built-ins; the megakernel's buffers
//! (`framebuffer`, `stats`, ...) and the scheduler's `sched_*` state are not
//! in scope in its source, so naming one is an error that names it.

use naga::{Block, Statement};

use crate::input::excerpt;

/// The name a user displacement function must have.
pub const USER_FUNCTION_NAME: &str = "displacement_user";

/// Why a user displacement function is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum UserWgslError {
    /// naga cannot parse or validate the source.
    #[error("line {line}, column {column} of the function's source: {message}")]
    Invalid {
        /// 1-based line in the user's source.
        line: u32,
        /// 1-based column.
        column: u32,
        /// naga's message.
        message: String,
    },
    /// The source names something it does not define: most likely one of
    /// the renderer's globals or functions, which a user function may not
    /// touch.
    #[error(
        "line {line}, column {column} of the function's source: `{name}` is not defined there; a user function may use only its arguments, its own helpers and constants, and WGSL's built-ins, never the renderer's buffers or functions"
    )]
    OutsideName {
        /// The name.
        name: String,
        /// 1-based line in the user's source.
        line: u32,
        /// 1-based column.
        column: u32,
    },
    /// No function of the expected name and signature.
    #[error("the source does not define `fn {USER_FUNCTION_NAME}(u: f32, v: f32) -> f32`{found}")]
    Missing {
        /// What was found under the name instead, if anything.
        found: String,
    },
    /// The source declares a module-scope variable: its binding or state
    /// would be shared with the renderer's.
    #[error(
        "line {line} of the function's source: `var {name}` at module scope is not allowed in a user function (use a `let` or `var` inside the function, or a `const`)"
    )]
    Global {
        /// The variable.
        name: String,
        /// 1-based line.
        line: u32,
    },
    /// A function of the user's text declares more function memory than
    /// [`MAX_FUNCTION_MEMORY`] (boxed: the error stays small).
    #[error(transparent)]
    Memory(Box<FunctionMemory>),
    /// A barrier: the renderer calls the function from divergent control
    /// flow, where barriers are undefined behaviour on real GPUs.
    #[error(
        "line {line} of the function's source: `{function}` calls a barrier; the renderer calls user functions from divergent control flow, where barriers are undefined"
    )]
    Barrier {
        /// The function with the barrier.
        function: String,
        /// 1-based line.
        line: u32,
    },
    /// `discard`, a fragment shader's statement: the renderer runs user
    /// functions in compute shaders, where it does not exist.
    #[error(
        "line {line} of the function's source: `{function}` uses `discard`, which only fragment shaders have; the renderer runs user functions in a compute shader (a surface shader that draws nothing is RenderMan's `null`)"
    )]
    Discard {
        /// The function with the `discard`.
        function: String,
        /// 1-based line.
        line: u32,
    },
    /// A statement (or declaration) of more than [`MAX_STATEMENT_TOKENS`]
    /// tokens: its expression could nest deeper than the WGSL front end and
    /// the drivers' compilers can recurse.
    #[error(
        "line {line} of the function's source: a statement of more than {limit} tokens; split it into several `let`s"
    )]
    StatementTooLong {
        /// 1-based line where the statement starts.
        line: u32,
        /// The limit ([`MAX_STATEMENT_TOKENS`]).
        limit: usize,
    },
    /// A global directive (`enable`, `requires`, `diagnostic`): the user's
    /// source is placed inside the renderer's module, whose own first lines
    /// say what it enables.
    #[error(
        "line {line} of the function's source: the `{directive}` directive is not allowed in a user function, which is compiled inside the renderer's module (that module says what it enables); remove it"
    )]
    Directive {
        /// `enable`, `requires` or `diagnostic`.
        directive: String,
        /// 1-based line.
        line: u32,
    },
}

/// A function of the user's text declares more function memory (its local
/// variables, array and struct values, the constants it uses) than
/// [`MAX_FUNCTION_MEMORY`]: drivers unroll such memory into registers or
/// scratch at compile time, and an array of a million floats drove one
/// driver's compile to 23 GB.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "line {line} of the function's source: `{name}` in `{function}` takes {bytes} bytes of function memory ({total} bytes in all in `{function}`), more than the {limit} bytes a user function may use per invocation; use a smaller array"
)]
pub struct FunctionMemory {
    /// The function.
    pub function: String,
    /// The variable, value or constant that goes over the limit (the
    /// largest of the function's).
    pub name: String,
    /// 1-based line of its declaration.
    pub line: u32,
    /// Its size in bytes.
    pub bytes: u64,
    /// The function's total.
    pub total: u64,
    /// The limit ([`MAX_FUNCTION_MEMORY`]).
    pub limit: u64,
}

/// The most function memory (local variables, array and struct values,
/// constants used) one function of user code may declare, in bytes, per
/// invocation: far more than a displacement or shading function needs (a
/// 4x4 matrix is 64 bytes), far less than what stalls a driver's compile.
pub const MAX_FUNCTION_MEMORY: u64 = 16 * 1024;

/// Checks `wgsl`, the source of a user displacement function and its
/// helpers, on its own.
pub fn check(wgsl: &str) -> Result<(), UserWgslError> {
    check_statement_sizes(wgsl)?;
    check_directives(wgsl)?;
    let module = parse(wgsl)?;
    check_globals(&module, wgsl, wgsl.len())?;
    check_memory(&module, wgsl, wgsl.len())?;
    let user = module
        .functions
        .iter()
        .find(|(_, f)| f.name.as_deref() == Some(USER_FUNCTION_NAME));
    let Some((_, function)) = user else {
        return Err(UserWgslError::Missing {
            found: String::new(),
        });
    };
    let f32_type = |ty: naga::Handle<naga::Type>| {
        matches!(
            module.types[ty].inner,
            naga::TypeInner::Scalar(naga::Scalar::F32)
        )
    };
    let signature_ok = function.arguments.len() == 2
        && function.arguments.iter().all(|a| f32_type(a.ty))
        && function.result.as_ref().is_some_and(|r| f32_type(r.ty));
    if !signature_ok {
        return Err(UserWgslError::Missing {
            found: " with that signature (it takes two f32 and returns an f32)".to_owned(),
        });
    }
    check_barriers(&module, wgsl)?;
    validate(&module, wgsl)
}

/// Parses `wgsl` (a user's source, possibly followed by declarations it
/// may use), naming an undefined identifier as [`UserWgslError::OutsideName`].
pub(crate) fn parse(wgsl: &str) -> Result<naga::Module, UserWgslError> {
    naga::front::wgsl::parse_str(wgsl).map_err(|error| {
        let (line, column) = error
            .location(wgsl)
            .map_or((0, 0), |l| (l.line_number, l.line_position));
        let undefined = error
            .message()
            .starts_with("no definition in scope for identifier");
        let name = error
            .labels()
            .next()
            .and_then(|(span, _)| wgsl.get(span.to_range()?))
            .filter(|name| undefined && !name.is_empty());
        match name {
            Some(name) => UserWgslError::OutsideName {
                name: excerpt(name),
                line,
                column,
            },
            // naga quotes the offending token whole, however long.
            None => UserWgslError::Invalid {
                line,
                column,
                message: excerpt(error.message()),
            },
        }
    })
}

/// Refuses a module-scope variable declared in the user's text (the first
/// `user_end` bytes of `wgsl`): its binding or state would be shared with
/// the renderer's.
pub(crate) fn check_globals(
    module: &naga::Module,
    wgsl: &str,
    user_end: usize,
) -> Result<(), UserWgslError> {
    let in_user_text = |handle| {
        module
            .global_variables
            .get_span(handle)
            .to_range()
            .is_some_and(|r| r.start < user_end)
    };
    match module
        .global_variables
        .iter()
        .find(|(handle, _)| in_user_text(*handle))
    {
        Some((handle, global)) => Err(UserWgslError::Global {
            name: global.name.clone().unwrap_or_default(),
            line: module
                .global_variables
                .get_span(handle)
                .location(wgsl)
                .line_number,
        }),
        None => Ok(()),
    }
}

/// Refuses a function of the user's text (the first `user_end` bytes of
/// `wgsl`) whose function memory exceeds [`MAX_FUNCTION_MEMORY`]: its local
/// variables, the array and struct values it builds (`let a = array<f32,
/// N>(...)`, besides a variable's initializer, which the variable counts)
/// and the constants it names, each once, sized by naga. The
/// error names the largest of them.
pub(crate) fn check_memory(
    module: &naga::Module,
    wgsl: &str,
    user_end: usize,
) -> Result<(), UserWgslError> {
    // A type whose size overflows naga's u32 is too large here.
    let size = |ty: naga::Handle<naga::Type>| -> u64 {
        module.types[ty]
            .inner
            .try_size(module.to_ctx())
            .map_or(u64::MAX, u64::from)
    };
    for (handle, function) in module.functions.iter() {
        let in_user_text = module
            .functions
            .get_span(handle)
            .to_range()
            .is_some_and(|r| r.start < user_end);
        if !in_user_text {
            continue;
        }
        // (name, bytes, span) of everything that takes function memory.
        let mut items: Vec<(String, u64, naga::Span)> = Vec::new();
        let mut initializers = std::collections::HashSet::new();
        for (local, variable) in function.local_variables.iter() {
            initializers.extend(variable.init);
            items.push((
                variable.name.clone().unwrap_or_default(),
                size(variable.ty),
                function.local_variables.get_span(local),
            ));
        }
        let mut constants = std::collections::HashSet::new();
        for (expression, value) in function.expressions.iter() {
            let (name, ty) = match *value {
                naga::Expression::Compose { ty, .. } | naga::Expression::ZeroValue(ty)
                    if !initializers.contains(&expression)
                        && matches!(
                            module.types[ty].inner,
                            naga::TypeInner::Array { .. } | naga::TypeInner::Struct { .. }
                        ) =>
                {
                    let name = module.types[ty]
                        .name
                        .clone()
                        .unwrap_or_else(|| "an array value".to_owned());
                    (name, ty)
                }
                naga::Expression::Constant(constant) if constants.insert(constant) => {
                    let constant = &module.constants[constant];
                    (constant.name.clone().unwrap_or_default(), constant.ty)
                }
                _ => continue,
            };
            items.push((name, size(ty), function.expressions.get_span(expression)));
        }
        let total = items
            .iter()
            .fold(0u64, |sum, (_, bytes, _)| sum.saturating_add(*bytes));
        if total > MAX_FUNCTION_MEMORY {
            let (name, bytes, span) = items
                .into_iter()
                .max_by_key(|(_, bytes, _)| *bytes)
                .expect("a total above zero has items");
            return Err(UserWgslError::Memory(Box::new(FunctionMemory {
                function: function.name.clone().unwrap_or_default(),
                name: excerpt(&name),
                line: span.location(wgsl).line_number,
                bytes,
                total,
                limit: MAX_FUNCTION_MEMORY,
            })));
        }
    }
    Ok(())
}

/// The most tokens one statement or declaration of user code may have
/// (between `;`, `{` and `}`). A chain of 20,000 additions or indexings
/// overflows an 8 MiB stack in naga's WGSL front end, which recurses once
/// per level of the expression tree; at this limit an expression nests at
/// most about a thousand deep, a few hundred KiB of stack. Real shaders'
/// statements have tens of tokens.
pub const MAX_STATEMENT_TOKENS: usize = 2048;

/// Refuses a statement of more than [`MAX_STATEMENT_TOKENS`] tokens in
/// `wgsl`, before naga parses it (comments are not counted).
pub(crate) fn check_statement_sizes(wgsl: &str) -> Result<(), UserWgslError> {
    let bytes = wgsl.as_bytes();
    let (mut at, mut line) = (0usize, 1u32);
    let (mut tokens, mut start_line) = (0usize, 1u32);
    let word = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'.' || b >= 0x80;
    while at < bytes.len() {
        let b = bytes[at];
        if b == b'\n' {
            line += 1;
            at += 1;
        } else if b.is_ascii_whitespace() {
            at += 1;
        } else if let Some(end) = comment_end(bytes, at) {
            line += bytes[at..end].iter().filter(|&&c| c == b'\n').count() as u32;
            at = end;
        } else {
            if tokens == 0 {
                start_line = line;
            }
            if matches!(b, b';' | b'{' | b'}') {
                tokens = 0;
                at += 1;
                continue;
            }
            tokens += 1;
            if tokens > MAX_STATEMENT_TOKENS {
                return Err(UserWgslError::StatementTooLong {
                    line: start_line,
                    limit: MAX_STATEMENT_TOKENS,
                });
            }
            if word(b) {
                while at < bytes.len() && word(bytes[at]) {
                    at += 1;
                }
            } else {
                at += 1;
            }
        }
    }
    Ok(())
}

/// Where the comment that starts at byte `at` of `bytes` ends (the index
/// past it: a line comment's newline, or past a block comment's closing
/// `*/`, or the end of an unclosed one); `None` when none starts there.
/// Block comments nest in WGSL.
fn comment_end(bytes: &[u8], mut at: usize) -> Option<usize> {
    if bytes[at..].starts_with(b"//") {
        while at < bytes.len() && bytes[at] != b'\n' {
            at += 1;
        }
        return Some(at);
    }
    if !bytes[at..].starts_with(b"/*") {
        return None;
    }
    let mut depth = 0usize;
    while at < bytes.len() {
        if bytes[at..].starts_with(b"/*") {
            depth += 1;
            at += 2;
        } else if bytes[at..].starts_with(b"*/") {
            depth -= 1;
            at += 2;
            if depth == 0 {
                break;
            }
        } else {
            at += 1;
        }
    }
    Some(at)
}

/// The global directives WGSL has: they may only open a module.
const DIRECTIVES: [&str; 3] = ["enable", "requires", "diagnostic"];

/// Refuses a global directive in `wgsl`, a user's source. WGSL allows them
/// only before every declaration, so only the first word after comments
/// and blank space can be one (one anywhere else is naga's parse error, at
/// its line).
pub(crate) fn check_directives(wgsl: &str) -> Result<(), UserWgslError> {
    let bytes = wgsl.as_bytes();
    let mut at = 0;
    loop {
        while at < bytes.len() && bytes[at].is_ascii_whitespace() {
            at += 1;
        }
        match comment_end(bytes, at) {
            Some(end) => at = end,
            None => break,
        }
    }
    let word: String = wgsl[at..]
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    if DIRECTIVES.contains(&word.as_str()) {
        return Err(UserWgslError::Directive {
            directive: word,
            line: wgsl[..at].matches('\n').count() as u32 + 1,
        });
    }
    Ok(())
}

/// Refuses a barrier or a `discard` in any function of `module` (parsed
/// from `wgsl`).
pub(crate) fn check_barriers(module: &naga::Module, wgsl: &str) -> Result<(), UserWgslError> {
    for (_, function) in module.functions.iter() {
        let name = || function.name.clone().unwrap_or_default();
        match first_forbidden(&function.body) {
            Some((Forbidden::Barrier, span)) => {
                return Err(UserWgslError::Barrier {
                    function: name(),
                    line: span.location(wgsl).line_number,
                });
            }
            Some((Forbidden::Discard, span)) => {
                return Err(UserWgslError::Discard {
                    function: name(),
                    line: span.location(wgsl).line_number,
                });
            }
            None => {}
        }
    }
    Ok(())
}

/// Validates `module` (parsed from `wgsl`), locating an error at its
/// innermost labelled span.
pub(crate) fn validate(module: &naga::Module, wgsl: &str) -> Result<(), UserWgslError> {
    let capabilities = naga::valid::Capabilities::all();
    naga::valid::Validator::new(naga::valid::ValidationFlags::all(), capabilities)
        .validate(module)
        .map_err(|error| {
            // The innermost labelled span (naga also labels the enclosing
            // function), else the error's own location.
            let location = error
                .spans()
                .map(|(span, _)| *span)
                .max_by_key(|span| span.to_range().map_or(0, |r| r.start))
                .map(|span| span.location(wgsl))
                .or_else(|| error.location(wgsl));
            let (line, column) = location.map_or((0, 0), |l| (l.line_number, l.line_position));
            UserWgslError::Invalid {
                line,
                column,
                message: excerpt(&error.as_inner().to_string()),
            }
        })?;
    Ok(())
}

/// A statement a user function may not contain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Forbidden {
    /// A barrier, or a workgroup-uniform load (which is one).
    Barrier,
    /// `discard`.
    Discard,
}

/// The first statement in `block` a user function may not contain, and
/// its span, nested blocks included.
fn first_forbidden(block: &Block) -> Option<(Forbidden, naga::Span)> {
    for (statement, span) in block.span_iter() {
        let nested: Vec<&Block> = match statement {
            Statement::ControlBarrier(_)
            | Statement::MemoryBarrier(_)
            | Statement::WorkGroupUniformLoad { .. } => return Some((Forbidden::Barrier, *span)),
            Statement::Kill => return Some((Forbidden::Discard, *span)),
            Statement::Block(inner) => vec![inner],
            Statement::If { accept, reject, .. } => vec![accept, reject],
            Statement::Switch { cases, .. } => cases.iter().map(|c| &c.body).collect(),
            Statement::Loop {
                body, continuing, ..
            } => vec![body, continuing],
            _ => Vec::new(),
        };
        if let Some(found) = nested.into_iter().find_map(first_forbidden) {
            return Some(found);
        }
    }
    None
}

#[cfg(test)]
mod tests;
