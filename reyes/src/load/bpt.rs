//! The `.bpt` format: bicubic Bezier patches as plain text.
//!
//! ```text
//! <number of patches>
//! 3 3          <- degree in u and v, repeated before every patch
//! x y z        <- 16 control points, row by row (4 rows of 4)
//! ...
//! ```
//!
//! Point `k` of a patch (0-based, in file order) is `points[k]`, i.e. row
//! `v = k / 4`, column `u = k % 4`.
//!
//! The patches may be followed by an optional section of texture
//! coordinates ([`Model::st`]), one line per patch, in patch order: the
//! `s t` of its corners `(u, v) = (0,0), (1,0), (0,1), (1,1)`.
//!
//! ```text
//! st <number of patches>
//! s00 t00 s10 t10 s01 t01 s11 t11
//! ...
//! ```
//!
//! Without the section every patch has `s, t = u, v`. A reader that does
//! not know the section refuses the file (trailing text) rather than
//! dropping the coordinates.

use std::io::Write;

use super::LoadError;
use glam::Vec2;

use super::lines::{Lines, capacity_hint, exactly, parse_point, take_declared};
use crate::budget::PatchBudget;
use crate::input::excerpt;
use crate::model::{Model, Patch};

/// The first word of the texture coordinate section's header line.
const ST_HEADER: &str = "st";

/// Parses a `.bpt` text, within a scene's patch budget of its own
/// ([`PatchBudget::from_setting`]).
pub fn parse(text: &str) -> Result<Model, LoadError> {
    parse_within(text, &mut PatchBudget::from_setting())
}

/// Parses a `.bpt` text, taking its declared patch count from `budget`
/// before reading any patch.
pub fn parse_within(text: &str, budget: &mut PatchBudget) -> Result<Model, LoadError> {
    let mut lines = Lines::new(text);
    let (line, count) = lines.expect_count("patch count")?;
    take_declared(budget, line, count)?;
    let mut patches = Vec::with_capacity(capacity_hint(count, text.len() / 16));
    for patch_index in 0..count {
        let (line, degree) = lines
            .expect_line(|| format!("the degree line \"3 3\" of patch {}", patch_index + 1))?;
        if exactly::<2>(degree.split_whitespace()) != Ok(["3", "3"]) {
            return Err(LoadError::UnsupportedDegree {
                line,
                found: excerpt(degree),
            });
        }
        let mut patch = Patch::default();
        for (point_index, point) in patch.points.iter_mut().enumerate() {
            let (line, text) = lines.expect_line(|| {
                format!(
                    "control point {} of 16 of patch {} of {count}",
                    point_index + 1,
                    patch_index + 1
                )
            })?;
            *point = parse_point(line, text.split_whitespace())?;
        }
        patches.push(patch);
    }
    let st = parse_st(&mut lines, patches.len())?;
    lines.expect_end()?;
    Ok(Model { patches, st })
}

/// The optional texture coordinate section after `patches` patches.
fn parse_st(lines: &mut Lines<'_>, patches: usize) -> Result<Option<Vec<[Vec2; 4]>>, LoadError> {
    let Some((line, header)) = lines.peek_line() else {
        return Ok(None);
    };
    let mut words = header.split_whitespace();
    if words.next() != Some(ST_HEADER) {
        // Not the section: the caller reports the trailing text.
        return Ok(None);
    }
    lines.next_line();
    let count = match exactly::<1>(words) {
        Ok([n]) => n.parse::<usize>().ok(),
        Err(_) => None,
    };
    if count != Some(patches) {
        return Err(LoadError::StCount {
            line,
            patches,
            found: excerpt(header),
        });
    }
    let mut st = Vec::with_capacity(patches);
    for patch_index in 0..patches {
        let (line, text) = lines.expect_line(|| {
            format!(
                "the texture coordinates (8 numbers) of patch {} of {patches}",
                patch_index + 1
            )
        })?;
        let tokens: [&str; 8] = exactly(text.split_whitespace())
            .map_err(|found| LoadError::WrongStCount { line, found })?;
        let mut values = [0.0f32; 8];
        for (slot, token) in values.iter_mut().zip(tokens) {
            let value = token.parse::<f32>().map_err(|_| LoadError::InvalidNumber {
                line,
                token: excerpt(token),
            })?;
            if !value.is_finite() {
                return Err(LoadError::NonFiniteCoordinate {
                    line,
                    token: excerpt(token),
                });
            }
            *slot = value;
        }
        st.push(std::array::from_fn(|c| {
            Vec2::new(values[2 * c], values[2 * c + 1])
        }));
    }
    Ok(Some(st))
}

/// Writes a model as `.bpt` text, with the texture coordinate section when
/// the model has texture coordinates. Coordinates are written with Rust's
/// shortest round-trip formatting, so [`parse`] gives back the same values.
/// Texture coordinates that do not fit the patches
/// ([`Model::st_problem`]) are written as they are, and refused on reading.
pub fn write(model: &Model) -> String {
    let mut out = Vec::with_capacity(model.patches.len() * 16 * 32 + 16);
    // Writing to a Vec cannot fail.
    let _ = write_to(model, &mut out);
    String::from_utf8(out).expect("numbers and spaces are UTF-8")
}

/// [`write`] to `out`, a patch at a time (a model's text is several times
/// the size of its patches: `reyes convert` streams it to the file).
pub fn write_to(model: &Model, out: &mut dyn Write) -> std::io::Result<()> {
    writeln!(out, "{}", model.patches.len())?;
    for patch in &model.patches {
        out.write_all(b"3 3\n")?;
        for p in &patch.points {
            writeln!(out, "{} {} {}", p.x, p.y, p.z)?;
        }
    }
    if let Some(st) = &model.st {
        writeln!(out, "{ST_HEADER} {}", st.len())?;
        for corners in st {
            let [a, b, c, d] = corners;
            writeln!(
                out,
                "{} {} {} {} {} {} {} {}",
                a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y
            )?;
        }
    }
    Ok(())
}
