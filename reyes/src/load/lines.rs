//! Line-oriented helpers shared by the two text formats: a cursor over the
//! non-blank lines with their 1-based numbers, and number parsing that reports
//! errors with those numbers.
//!
//! Nothing here collects a line's tokens into a vector: a single line can be
//! hundreds of megabytes long, and its tokens would take many times that.

use glam::Vec3;

use super::LoadError;
use crate::budget::PatchBudget;
use crate::input::{excerpt, strip_bom};

/// A cursor over the non-blank, trimmed lines of a text, remembering line numbers.
pub(crate) struct Lines<'a> {
    inner: std::iter::Enumerate<std::str::Lines<'a>>,
    /// Number of the last line seen (0 before the first), used to report the
    /// position of a truncation: the line after the last one.
    last_line: usize,
}

impl<'a> Lines<'a> {
    /// A cursor over `text`; a leading byte-order mark is skipped.
    pub(crate) fn new(text: &'a str) -> Self {
        Lines {
            inner: strip_bom(text).lines().enumerate(),
            last_line: 0,
        }
    }

    /// The next non-blank line as `(line_number, trimmed_text)`.
    pub(crate) fn next_line(&mut self) -> Option<(usize, &'a str)> {
        for (index, line) in self.inner.by_ref() {
            self.last_line = index + 1;
            let trimmed = line.trim();
            if !trimmed.is_empty() {
                return Some((index + 1, trimmed));
            }
        }
        None
    }

    /// The next non-blank line, without consuming it.
    pub(crate) fn peek_line(&self) -> Option<(usize, &'a str)> {
        let mut ahead = Lines {
            inner: self.inner.clone(),
            last_line: self.last_line,
        };
        ahead.next_line()
    }

    /// The next non-blank line, or [`LoadError::Truncated`] saying what was expected.
    pub(crate) fn expect_line(
        &mut self,
        expected: impl FnOnce() -> String,
    ) -> Result<(usize, &'a str), LoadError> {
        match self.next_line() {
            Some(found) => Ok(found),
            None => Err(LoadError::Truncated {
                line: self.last_line + 1,
                expected: expected(),
            }),
        }
    }

    /// Reads a count line (a single non-negative integer).
    pub(crate) fn expect_count(&mut self, what: &'static str) -> Result<(usize, usize), LoadError> {
        let Some((line, text)) = self.next_line() else {
            return Err(LoadError::MissingCount {
                line: self.last_line + 1,
                what,
            });
        };
        let count = text.parse::<usize>().map_err(|_| LoadError::InvalidCount {
            line,
            what,
            found: excerpt(text),
        })?;
        Ok((line, count))
    }

    /// Fails with [`LoadError::TrailingGarbage`] if any non-blank line is left.
    pub(crate) fn expect_end(&mut self) -> Result<(), LoadError> {
        match self.next_line() {
            Some((line, text)) => Err(LoadError::TrailingGarbage {
                line,
                text: excerpt(text),
            }),
            None => Ok(()),
        }
    }
}

/// Takes exactly `N` tokens, or reports how many there were (counting the
/// rest without storing them) as `Err(count)`.
pub(crate) fn exactly<'a, const N: usize>(
    mut tokens: impl Iterator<Item = &'a str>,
) -> Result<[&'a str; N], usize> {
    let mut taken = [""; N];
    for (index, slot) in taken.iter_mut().enumerate() {
        *slot = tokens.next().ok_or(index)?;
    }
    match tokens.count() {
        0 => Ok(taken),
        extra => Err(N + extra),
    }
}

/// Parses the three coordinates of a point given as tokens.
pub(crate) fn parse_point<'a>(
    line: usize,
    tokens: impl Iterator<Item = &'a str>,
) -> Result<Vec3, LoadError> {
    let tokens: [&str; 3] =
        exactly(tokens).map_err(|found| LoadError::WrongCoordinateCount { line, found })?;
    let mut xyz = [0.0f32; 3];
    for (slot, token) in xyz.iter_mut().zip(tokens) {
        let value = token.parse::<f32>().map_err(|_| LoadError::InvalidNumber {
            line,
            token: excerpt(token),
        })?;
        // Rust's float parser accepts "nan" and "inf"; a NaN or infinite control
        // point would poison every bound and grid derived from it, so reject it here.
        if !value.is_finite() {
            return Err(LoadError::NonFiniteCoordinate {
                line,
                token: excerpt(token),
            });
        }
        *slot = value;
    }
    Ok(Vec3::from_array(xyz))
}

/// Caps a declared count for pre-allocation, so that a bogus huge count in a
/// small file cannot make us allocate gigabytes before failing as truncated.
pub(crate) fn capacity_hint(declared: usize, text_len: usize) -> usize {
    declared.min(text_len / 8 + 1)
}

/// Takes the `count` patches a file declares on `line` from `budget`,
/// before any is read: the count, not the file's size, says what loading
/// it will hold.
pub(crate) fn take_declared(
    budget: &mut PatchBudget,
    line: usize,
    count: usize,
) -> Result<(), LoadError> {
    budget
        .take(count as u64)
        .map_err(|source| LoadError::PatchBudget { line, source })
}
