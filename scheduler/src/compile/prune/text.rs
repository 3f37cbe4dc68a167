//! Text positions in WGSL source: the parts of an `if` statement, braces
//! and comments, and deletions of ranges, for the specialization pass.

use std::ops::Range;

/// Where the parts of an `if` statement lie in the text.
pub(super) struct IfShape {
    /// The accept block, braces included.
    pub(super) accept: Range<usize>,
    pub(super) otherwise: Otherwise,
    /// The end of the whole statement.
    pub(super) end: usize,
}

pub(super) enum Otherwise {
    Nothing,
    /// `else { ... }`, braces included.
    Block(Range<usize>),
    /// `else if`: the offset of that `if`.
    ElseIf(usize),
}

impl IfShape {
    pub(super) fn scan(source: &str, range: Range<usize>) -> Option<Self> {
        let bytes = source.as_bytes();
        // WGSL expressions hold no braces: the first one opens the block.
        let open = next_token(bytes, range.start + 2, range.end, b'{')?;
        let close = matching_brace(bytes, open, range.end)?;
        let accept = open..close + 1;
        let after = skip_trivia(bytes, close + 1, range.end);
        let otherwise = if source[after..range.end].starts_with("else") {
            let next = skip_trivia(bytes, after + 4, range.end);
            if bytes.get(next) == Some(&b'{') {
                let block_close = matching_brace(bytes, next, range.end)?;
                Otherwise::Block(next..block_close + 1)
            } else if source[next..range.end].starts_with("if") {
                Otherwise::ElseIf(next)
            } else {
                return None;
            }
        } else {
            Otherwise::Nothing
        };
        Some(Self {
            accept,
            otherwise,
            end: range.end,
        })
    }
}

/// The offset of the first `token` byte outside comments in `from..to`.
fn next_token(bytes: &[u8], from: usize, to: usize, token: u8) -> Option<usize> {
    let mut at = from;
    while at < to {
        at = skip_trivia(bytes, at, to);
        if at >= to {
            return None;
        }
        if bytes[at] == token {
            return Some(at);
        }
        at += 1;
    }
    None
}

/// The offset of the `}` closing the `{` at `open`, skipping comments.
fn matching_brace(bytes: &[u8], open: usize, to: usize) -> Option<usize> {
    let mut depth = 0usize;
    let mut at = open;
    while at < to {
        at = skip_trivia(bytes, at, to);
        match bytes.get(at)? {
            b'{' => depth += 1,
            b'}' => {
                depth -= 1;
                if depth == 0 {
                    return Some(at);
                }
            }
            _ => {}
        }
        at += 1;
    }
    None
}

/// The first offset at or after `at` that is not whitespace or a comment
/// (line comments and nested block comments).
fn skip_trivia(bytes: &[u8], mut at: usize, to: usize) -> usize {
    while at < to {
        match (bytes[at], bytes.get(at + 1)) {
            (b' ' | b'\t' | b'\r' | b'\n', _) => at += 1,
            (b'/', Some(b'/')) => {
                while at < to && bytes[at] != b'\n' {
                    at += 1;
                }
            }
            (b'/', Some(b'*')) => {
                let mut depth = 0usize;
                while at < to {
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
            }
            _ => break,
        }
    }
    at
}

/// `range` grown to whole lines when only whitespace shares its first and
/// last lines, so that deleting it leaves no blank line behind.
pub(super) fn whole_lines(source: &str, range: Range<usize>) -> Range<usize> {
    let line_start = source[..range.start].rfind('\n').map_or(0, |i| i + 1);
    let line_end = source[range.end..]
        .find('\n')
        .map_or(source.len(), |i| range.end + i + 1);
    let before_blank = source[line_start..range.start].trim().is_empty();
    let after_blank = source[range.end..line_end].trim().is_empty();
    if before_blank && after_blank {
        line_start..line_end
    } else {
        range
    }
}

/// `source` without the union of `deletions`.
pub(super) fn delete_ranges(source: &str, mut deletions: Vec<Range<usize>>) -> String {
    deletions.sort_by_key(|r| (r.start, r.end));
    let mut out = String::with_capacity(source.len());
    let mut kept_from = 0;
    for range in deletions {
        if range.start > kept_from {
            out.push_str(&source[kept_from..range.start]);
        }
        kept_from = kept_from.max(range.end);
    }
    out.push_str(&source[kept_from..]);
    out
}

/// `range` (whole lines) grown upwards over the `//` comment lines directly
/// above it, and over one blank line that would otherwise double up.
pub(super) fn with_leading_comments(source: &str, range: Range<usize>) -> Range<usize> {
    let mut start = range.start;
    while start > 0 {
        let previous_start = source[..start - 1].rfind('\n').map_or(0, |i| i + 1);
        if source[previous_start..start].trim_start().starts_with("//") {
            start = previous_start;
        } else {
            break;
        }
    }
    let mut end = range.end;
    let blank_before = start >= 2 && &source[start - 2..start] == "\n\n";
    if blank_before && source[end..].starts_with('\n') {
        end += 1;
    }
    start..end
}
