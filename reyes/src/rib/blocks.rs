//! The block structure of a RIB stream: every `...Begin` request opens a
//! block that its `...End` must close, innermost first.
//!
//! The structure is checked for every request, including those the
//! interpreter skips (inside `ObjectBegin`, after the first `WorldEnd`), so
//! a truncated file or a missing end is found wherever it is. A problem is
//! an error with the line, or under [`Interp::lenient`] a warning: an end
//! without its begin is then ignored, the blocks left open inside the one
//! an end closes are closed first, and the blocks still open at the end of
//! the scene are closed there, so what was read renders.

use std::path::{Path, PathBuf};

use super::RibError;
use super::interp::Interp;
use super::parser::Call;

/// What a block is, by the request that opens it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum BlockKind {
    Frame,
    World,
    Attribute,
    Transform,
    Motion,
    Solid,
    Object,
}

impl BlockKind {
    const ALL: [BlockKind; 7] = [
        BlockKind::Frame,
        BlockKind::World,
        BlockKind::Attribute,
        BlockKind::Transform,
        BlockKind::Motion,
        BlockKind::Solid,
        BlockKind::Object,
    ];

    /// The request that opens the block.
    pub(super) fn begin(self) -> &'static str {
        match self {
            BlockKind::Frame => "FrameBegin",
            BlockKind::World => "WorldBegin",
            BlockKind::Attribute => "AttributeBegin",
            BlockKind::Transform => "TransformBegin",
            BlockKind::Motion => "MotionBegin",
            BlockKind::Solid => "SolidBegin",
            BlockKind::Object => "ObjectBegin",
        }
    }

    /// The request that closes the block.
    pub(super) fn end(self) -> &'static str {
        match self {
            BlockKind::Frame => "FrameEnd",
            BlockKind::World => "WorldEnd",
            BlockKind::Attribute => "AttributeEnd",
            BlockKind::Transform => "TransformEnd",
            BlockKind::Motion => "MotionEnd",
            BlockKind::Solid => "SolidEnd",
            BlockKind::Object => "ObjectEnd",
        }
    }
}

/// An open block: what it is and where its begin request is.
#[derive(Debug, Clone)]
pub(super) struct Block {
    pub(super) kind: BlockKind,
    pub(super) file: PathBuf,
    pub(super) line: usize,
    pub(super) col: usize,
}

impl Block {
    /// `the AttributeBegin of line 7` (with the file when it is not `file`).
    pub(super) fn describe(&self, file: &Path) -> String {
        if self.file == file {
            format!("the {} of line {}", self.kind.begin(), self.line)
        } else {
            format!(
                "the {} of {}:{}",
                self.kind.begin(),
                self.file.display(),
                self.line
            )
        }
    }
}

/// Most enclosing blocks an error at the end of the scene names.
const MAX_NAMED: usize = 3;

/// The advice every structure error ends with.
const LENIENT: &str = "--lenient (RibOptions::lenient) renders what was read";

impl Interp {
    /// Checks `call` against the open blocks and records it. Returns
    /// whether the interpreter should run it: `false` for an end without
    /// its begin under [`Interp::lenient`] (warned and ignored).
    pub(super) fn structure(&mut self, call: &Call, file: &Path) -> Result<bool, String> {
        let name = call.name.as_str();
        if let Some(kind) = BlockKind::ALL.into_iter().find(|k| k.begin() == name) {
            self.blocks.push(Block {
                kind,
                file: file.to_path_buf(),
                line: call.line,
                col: call.col,
            });
            return Ok(true);
        }
        let Some(kind) = BlockKind::ALL.into_iter().find(|k| k.end() == name) else {
            return Ok(true);
        };
        let Some(index) = self.blocks.iter().rposition(|b| b.kind == kind) else {
            let problem = format!("without its {}", kind.begin());
            self.structure_problem(file, call.line, name, &problem, "ignored")?;
            return Ok(false);
        };
        if index + 1 < self.blocks.len() {
            let inner = self.blocks.last().expect("an inner block").clone();
            let problem = format!(
                "{} is still open inside {} ({} missing before this {name})",
                inner.describe(file),
                self.blocks[index].describe(file),
                inner.kind.end()
            );
            let then = "the blocks inside are closed here";
            self.structure_problem(file, call.line, name, &problem, then)?;
            // Closes the inner blocks as if their ends came here, innermost
            // first, so their state (attributes, motion) is restored too.
            while self.blocks.len() > index + 1 {
                let inner = self.blocks.last().expect("an inner block").clone();
                self.close_block(&inner, file, call.line, call.col)?;
            }
        }
        self.blocks.pop();
        Ok(true)
    }

    /// The blocks still open at the end of the scene: an error naming the
    /// innermost (its file and line) and the others, or under
    /// [`Interp::lenient`] one warning per block, each closed there.
    pub(super) fn finish(&mut self) -> Result<(), RibError> {
        let Some(innermost) = self.blocks.last().cloned() else {
            return Ok(());
        };
        if !self.lenient {
            // The nearest enclosing blocks; a long list (a file of begins)
            // is counted, to keep the message short.
            let outer = &self.blocks[..self.blocks.len() - 1];
            let mut named: Vec<String> = outer
                .iter()
                .rev()
                .take(MAX_NAMED)
                .map(|b| b.describe(&innermost.file))
                .collect();
            if outer.len() > MAX_NAMED {
                named.push(format!("{} more", outer.len() - MAX_NAMED));
            }
            let also = if named.is_empty() {
                String::new()
            } else {
                format!(" (also open: {})", named.join(", "))
            };
            return Err(RibError::Syntax {
                file: innermost.file.clone(),
                line: innermost.line,
                col: innermost.col,
                message: format!(
                    "{} is never closed: the scene ends before its {}{also}; a truncated file? {LENIENT}",
                    innermost.kind.begin(),
                    innermost.kind.end()
                ),
            });
        }
        while let Some(block) = self.blocks.last().cloned() {
            self.warn(
                &block.file,
                block.line,
                format!(
                    "{} is never closed: the scene ends before its {}; closed at the end (--lenient)",
                    block.kind.begin(),
                    block.kind.end()
                ),
            );
            self.close_block(&block, &block.file, block.line, block.col)
                .map_err(|message| RibError::Syntax {
                    file: block.file.clone(),
                    line: block.line,
                    col: block.col,
                    message,
                })?;
        }
        Ok(())
    }

    /// Runs `block`'s end request as if it were at `line`, `col` of `file`.
    fn close_block(
        &mut self,
        block: &Block,
        file: &Path,
        line: usize,
        col: usize,
    ) -> Result<(), String> {
        let call = Call {
            name: block.kind.end().to_owned(),
            values: Vec::new(),
            line,
            col,
        };
        self.request(&call, file)
            .map_err(|e| format!("{}: {e}", block.kind.end()))
    }

    /// A structure problem of request `name`: an error, or under
    /// [`Interp::lenient`] a warning saying what is done instead (`then`).
    fn structure_problem(
        &mut self,
        file: &Path,
        line: usize,
        name: &str,
        problem: &str,
        then: &str,
    ) -> Result<(), String> {
        if !self.lenient {
            return Err(format!("{problem}; {LENIENT}"));
        }
        self.warn(file, line, format!("{name}: {problem}; {then} (--lenient)"));
        Ok(())
    }
}
