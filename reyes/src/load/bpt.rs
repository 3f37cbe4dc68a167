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

use std::fmt::Write as _;

use super::LoadError;
use super::lines::{Lines, capacity_hint, exactly, parse_point};
use crate::input::excerpt;
use crate::model::{Model, Patch};

/// Parses a `.bpt` text.
pub fn parse(text: &str) -> Result<Model, LoadError> {
    let mut lines = Lines::new(text);
    let (_, count) = lines.expect_count("patch count")?;
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
    let mut out = String::with_capacity(model.patches.len() * 16 * 32 + 16);
    // Writing to a String cannot fail.
    let _ = writeln!(out, "{}", model.patches.len());
    for patch in &model.patches {
        out.push_str("3 3\n");
        for p in &patch.points {
            let _ = writeln!(out, "{} {} {}", p.x, p.y, p.z);
        }
    }
    out
}
