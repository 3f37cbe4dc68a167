//! Newell's `.bez` format: patches as indices into a shared vertex list.
//!
//! ```text
//! <number of patches>
//! i1,i2,...,i16      <- one line per patch: 16 1-based vertex indices, row by row
//! <number of vertices>
//! x,y,z              <- one line per vertex
//! ```
//!
//! Coordinates may be separated by commas and/or whitespace.

use std::collections::HashMap;
use std::fmt::Write as _;

use glam::Vec3;

use super::LoadError;
use super::lines::{Lines, capacity_hint, exactly, parse_point, take_declared};
use crate::budget::PatchBudget;
use crate::input::excerpt;
use crate::model::{Model, Patch};

/// Parses a `.bez` text, within a scene's patch budget of its own
/// ([`PatchBudget::from_setting`]).
pub fn parse(text: &str) -> Result<Model, LoadError> {
    parse_within(text, &mut PatchBudget::from_setting())
}

/// Parses a `.bez` text, taking its declared patch count from `budget`
/// before reading any patch (a patch line of 16 indices makes 16 points:
/// 32 bytes of text become 192 of patch).
pub fn parse_within(text: &str, budget: &mut PatchBudget) -> Result<Model, LoadError> {
    let mut lines = Lines::new(text);
    let (line, patch_count) = lines.expect_count("patch count")?;
    take_declared(budget, line, patch_count)?;

    // Indices are checked against the vertex count once it is known, so keep
    // each patch's line number for the error message.
    let mut index_lines: Vec<(usize, [u64; 16])> =
        Vec::with_capacity(capacity_hint(patch_count, text.len() / 32));
    for patch_index in 0..patch_count {
        let (line, text) = lines.expect_line(|| {
            format!(
                "the vertex-index line of patch {} of {patch_count}",
                patch_index + 1
            )
        })?;
        let tokens: [&str; 16] = exactly(text.split(',').map(str::trim))
            .map_err(|found| LoadError::WrongIndexCount { line, found })?;
        let mut indices = [0u64; 16];
        for (slot, token) in indices.iter_mut().zip(tokens) {
            *slot = token.parse::<u64>().map_err(|_| LoadError::InvalidNumber {
                line,
                token: excerpt(token),
            })?;
        }
        index_lines.push((line, indices));
    }

    let (_, vertex_count) = lines.expect_count("vertex count")?;
    let mut vertices = Vec::with_capacity(capacity_hint(vertex_count, text.len() / 8));
    for vertex_index in 0..vertex_count {
        let (line, text) =
            lines.expect_line(|| format!("vertex {} of {vertex_count}", vertex_index + 1))?;
        let tokens = text
            .split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty());
        vertices.push(parse_point(line, tokens)?);
    }
    lines.expect_end()?;

    let mut patches = Vec::with_capacity(index_lines.len());
    for (line, indices) in index_lines {
        let mut patch = Patch::default();
        for (point, &index) in patch.points.iter_mut().zip(&indices) {
            if index == 0 || index > vertices.len() as u64 {
                return Err(LoadError::VertexIndexOutOfRange {
                    line,
                    index,
                    vertex_count: vertices.len(),
                });
            }
            *point = vertices[(index - 1) as usize];
        }
        patches.push(patch);
    }
    Ok(Model::new(patches))
}

/// Writes a model as `.bez` text, sharing vertices whose coordinates are
/// bit-identical. [`parse`] gives back the same control points.
pub fn write(model: &Model) -> String {
    let mut vertices: Vec<Vec3> = Vec::new();
    let mut lookup: HashMap<[u32; 3], usize> = HashMap::new();
    let mut out = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(out, "{}", model.patches.len());
    for patch in &model.patches {
        let indices: Vec<String> = patch
            .points
            .iter()
            .map(|p| {
                let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
                let index = *lookup.entry(key).or_insert_with(|| {
                    vertices.push(*p);
                    vertices.len()
                });
                index.to_string()
            })
            .collect();
        let _ = writeln!(out, "{}", indices.join(","));
    }
    let _ = writeln!(out, "{}", vertices.len());
    for v in &vertices {
        let _ = writeln!(out, "{},{},{}", v.x, v.y, v.z);
    }
    out
}
