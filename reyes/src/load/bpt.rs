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

use std::io::Write;

use super::LoadError;
use super::lines::{Lines, capacity_hint, exactly, parse_point, take_declared};
use crate::budget::PatchBudget;
use crate::input::excerpt;
use crate::model::{Model, Patch};

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
    lines.expect_end()?;
    Ok(Model { patches })
}

/// Writes a model as `.bpt` text. Coordinates are written with Rust's
/// shortest round-trip formatting, so [`parse`] gives back the same values.
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
    Ok(())
}
