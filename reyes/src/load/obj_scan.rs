//! A line-by-line pass over an OBJ text before `tobj` reads it: what
//! `tobj` cannot say with a line number (bad numbers, bad indices,
//! elements that are not faces) is refused here, naming the line and the
//! face; and the face count, each face's line, its vertices in the file's
//! numbering and whether every face vertex has a `vt` are recorded.
//!
//! OBJ numbers its vertices, texture coordinates and normals from 1 in
//! file order; a negative index counts back from the last one defined
//! before the face (`-1` is the latest). Indices are checked against the
//! file's counts once it is read.

use std::path::Path;

use super::LoadError;
use crate::input::{excerpt, strip_bom};

/// The statements that only name or group what follows (`o`, `g`),
/// pick materials (`usemtl`, `mtllib`) or set smoothing groups (`s`):
/// the whole file is one mesh, so they change nothing.
const GROUPING: [&str; 5] = ["o", "g", "usemtl", "mtllib", "s"];

/// What the pass found.
#[derive(Debug, Default)]
pub(super) struct Scan {
    /// The 1-based line of each face, in file order.
    pub(super) face_lines: Vec<usize>,
    /// The size of each face.
    pub(super) face_sizes: Vec<u32>,
    /// The 0-based file vertex of every face vertex, face after face.
    pub(super) face_vertices: Vec<u32>,
    /// Whether every face vertex names a texture coordinate.
    pub(super) all_st: bool,
    /// Whether any face vertex names one.
    pub(super) some_st: bool,
    /// Whether the text has grouping statements ([`GROUPING`]).
    pub(super) has_grouping: bool,
}

/// The patches the bilinear scheme makes of `text`'s faces (a quad 1, an
/// `n`-gon `n`), counted without storing anything: what a file asks for
/// before it is read.
pub(super) fn bilinear_patch_estimate(text: &str) -> u64 {
    strip_bom(text)
        .lines()
        .filter_map(|line| {
            let mut words = line.split_whitespace();
            (words.next() == Some("f")).then(|| match words.count() {
                4 => 1,
                n => n as u64,
            })
        })
        .fold(0u64, u64::saturating_add)
}

/// One kind of index (vertex, texture coordinate, normal): how many are
/// defined so far, and the largest positive index seen with its face.
#[derive(Debug, Default)]
struct Counter {
    defined: usize,
    /// `(index as written, face, line)` of the largest positive index.
    largest: Option<(i64, usize, usize)>,
}

impl Counter {
    /// The 0-based index `written` stands for in face `face` at `line`,
    /// or why it stands for none. Positive indices are checked at the end
    /// ([`Counter::check_largest`]): OBJ readers accept forward references.
    fn resolve(
        &mut self,
        written: i64,
        face: usize,
        line: usize,
        what: &str,
    ) -> Result<u32, String> {
        let resolved = if written < 0 {
            i64::try_from(self.defined)
                .unwrap_or(i64::MAX)
                .saturating_add(written)
        } else {
            if self.largest.is_none_or(|(w, _, _)| written > w) {
                self.largest = Some((written, face, line));
            }
            written - 1
        };
        if written == 0 || resolved < 0 || resolved > i64::from(u32::MAX) {
            return Err(format!(
                "face {} uses {what} {written}, but the face comes after {} {} (indices count from 1, or back from -1)",
                face + 1,
                self.defined,
                plural(what, self.defined)
            ));
        }
        Ok(resolved as u32)
    }

    /// The largest positive index, against the file's count.
    fn check_largest(&self, what: &str) -> Result<(), (usize, String)> {
        match self.largest {
            Some((written, face, line)) if written as u64 > self.defined as u64 => Err((
                line,
                format!(
                    "face {} uses {what} {written}, but the file has {} {}",
                    face + 1,
                    self.defined,
                    plural(what, self.defined)
                ),
            )),
            _ => Ok(()),
        }
    }
}

/// `what` (a vertex, texture coordinate or normal) for `n` of them.
fn plural(what: &str, n: usize) -> String {
    match (what, n) {
        (_, 1) => what.to_owned(),
        ("vertex", _) => "vertices".to_owned(),
        _ => format!("{what}s"),
    }
}

/// Reads `text` (the file at `path`, for messages).
pub(super) fn scan(text: &str, path: &Path) -> Result<Scan, LoadError> {
    let error = |line: usize, message: String| LoadError::ObjSyntax {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut out = Scan {
        all_st: true,
        ..Scan::default()
    };
    let (mut v, mut vt, mut vn) = (Counter::default(), Counter::default(), Counter::default());
    for (index, text) in strip_bom(text).lines().enumerate() {
        let line = index + 1;
        let mut words = text.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "v" => {
                numbers(words, 3, "a vertex (v x y z)").map_err(|m| error(line, m))?;
                v.defined += 1;
            }
            "vt" => {
                numbers(words, 2, "a texture coordinate (vt u v)").map_err(|m| error(line, m))?;
                vt.defined += 1;
            }
            "vn" => {
                numbers(words, 3, "a normal (vn x y z)").map_err(|m| error(line, m))?;
                vn.defined += 1;
            }
            "f" => {
                let face = out.face_lines.len();
                let mut size = 0u32;
                for word in words {
                    let mut parts = word.split('/');
                    let (Some(pv), pt, pn, None) =
                        (parts.next(), parts.next(), parts.next(), parts.next())
                    else {
                        return Err(error(
                            line,
                            format!(
                                "face {}: {:?} is not v, v/vt, v//vn or v/vt/vn",
                                face + 1,
                                excerpt(word)
                            ),
                        ));
                    };
                    let index = |part: &str| -> Result<i64, LoadError> {
                        part.parse::<i64>().map_err(|_| {
                            error(
                                line,
                                format!(
                                    "face {}: {:?} is not an index in {:?}",
                                    face + 1,
                                    excerpt(part),
                                    excerpt(word)
                                ),
                            )
                        })
                    };
                    let vertex = v
                        .resolve(index(pv)?, face, line, "vertex")
                        .map_err(|m| error(line, m))?;
                    out.face_vertices.push(vertex);
                    match pt.filter(|p| !p.is_empty()) {
                        Some(p) => {
                            vt.resolve(index(p)?, face, line, "texture coordinate")
                                .map_err(|m| error(line, m))?;
                            out.some_st = true;
                        }
                        None => out.all_st = false,
                    }
                    if let Some(p) = pn.filter(|p| !p.is_empty()) {
                        vn.resolve(index(p)?, face, line, "normal")
                            .map_err(|m| error(line, m))?;
                    }
                    size = size.saturating_add(1);
                }
                out.face_lines.push(line);
                out.face_sizes.push(size);
            }
            "l" | "p" => {
                return Err(error(
                    line,
                    format!(
                        "{} statements ({}) are not surfaces; remove them (only faces, f, are read)",
                        keyword,
                        if keyword == "l" {
                            "polylines"
                        } else {
                            "points"
                        }
                    ),
                ));
            }
            word if GROUPING.contains(&word) => out.has_grouping = true,
            // Normals, free-form curves and surfaces and the rest: no surface.
            _ => {}
        }
    }
    for (counter, what) in [(&v, "vertex"), (&vt, "texture coordinate"), (&vn, "normal")] {
        counter
            .check_largest(what)
            .map_err(|(line, message)| error(line, message))?;
    }
    if out.face_lines.is_empty() {
        out.all_st = false;
    }
    Ok(out)
}

/// Checks that `words` start with `n` finite numbers (`what` names the
/// statement for the message); `v` may have more (a weight or a colour).
fn numbers<'a>(words: impl Iterator<Item = &'a str>, n: usize, what: &str) -> Result<(), String> {
    let mut found = 0;
    for word in words.take(n) {
        match word.parse::<f32>() {
            Ok(x) if x.is_finite() => found += 1,
            Ok(_) => return Err(format!("{what}: {:?} is not finite", excerpt(word))),
            Err(_) => return Err(format!("{what}: {:?} is not a number", excerpt(word))),
        }
    }
    if found < n {
        return Err(format!("{what} needs {n} numbers, found {found}"));
    }
    Ok(())
}

/// `text` with its grouping statements blanked (the line count kept), so
/// that `tobj` reads the file as one model and keeps the vertices that
/// groups share shared.
pub(super) fn without_grouping(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for line in strip_bom(text).lines() {
        let keyword = line.split_whitespace().next().unwrap_or("");
        if !GROUPING.contains(&keyword) {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}
