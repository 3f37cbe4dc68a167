//! Bicubic Bezier patch models.

use std::path::Path;

use glam::Vec3;

use crate::input::{self, InputKind};
use crate::load::{self, LoadError};

/// The embedded Utah teapot (32 patches, z up) in `.bpt` format.
const TEAPOT_BPT: &str = include_str!("../assets/teapot.bpt");

/// One bicubic Bezier patch: 16 control points, row by row.
///
/// `points[v * 4 + u]` is the control point in column `u` (along the patch
/// parameter `u`, or `s` inside a diced grid) and row `v` (parameter `v`/`t`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Patch {
    /// The control points, `points[v * 4 + u]`.
    pub points: [Vec3; 16],
}

impl Patch {
    /// The control point in column `u` and row `v` (both in `0..4`).
    pub fn point(&self, u: usize, v: usize) -> Vec3 {
        self.points[v * 4 + u]
    }
}

/// A model: a list of bicubic Bezier patches in the model's own space.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Model {
    /// The patches.
    pub patches: Vec<Patch>,
}

impl Model {
    /// The axis-aligned bounding box `(min, max)` of all control points (which
    /// contains the surface, by the convex-hull property of Bezier patches).
    /// An empty model gives `(Vec3::ZERO, Vec3::ZERO)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut points = self.patches.iter().flat_map(|p| p.points.iter().copied());
        let Some(first) = points.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)))
    }

    /// The embedded Utah teapot (32 patches, z up, about 6.4 units wide).
    pub fn teapot() -> Model {
        // The embedded file is checked by the tests; failing here is a build defect.
        load::bpt::parse(TEAPOT_BPT).expect("the embedded teapot.bpt is valid")
    }

    /// Loads a model file, choosing the parser by extension: `.bpt` or `.bez`
    /// (case-insensitive). Any other extension is [`LoadError::UnknownExtension`].
    ///
    /// The file is read through [`crate::input`]: it must be a regular file
    /// of at most the model cap ([`InputKind::Model`]`.limit()`, 1 GiB by
    /// default), else [`LoadError::Input`].
    pub fn load(path: impl AsRef<Path>) -> Result<Model, LoadError> {
        Model::load_with_limit(path, InputKind::Model.limit())
    }

    /// [`Model::load`] with an explicit size cap in bytes instead of the
    /// process-wide one.
    pub fn load_with_limit(path: impl AsRef<Path>, limit: u64) -> Result<Model, LoadError> {
        let path = path.as_ref();
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let parse: fn(&str) -> Result<Model, LoadError> = match extension.as_deref() {
            Some("bpt") => load::bpt::parse,
            Some("bez") => load::bez::parse,
            _ => {
                return Err(LoadError::UnknownExtension {
                    path: path.to_path_buf(),
                });
            }
        };
        // The parsers need the whole text; the cap bounds it (and the error
        // messages quote at most an excerpt of it).
        let text = input::read_text(path, InputKind::Model, limit)?;
        parse(&text)
    }
}
