//! Where models come from: files by path (the extension dispatch behind
//! [`Model::load`]) and the embedded teapot.
//!
//! These are inherent methods of [`Model`] defined here, beside the parsers
//! they call, so that [`crate::model`] needs nothing from [`crate::load`].

use std::path::Path;

use crate::budget::PatchBudget;
use crate::input::{self, InputKind};
use crate::model::Model;
use crate::subdiv::Scheme;

use super::{LoadError, bez, bpt, obj};

/// The embedded Utah teapot (32 patches, z up) in `.bpt` format.
const TEAPOT_BPT: &str = include_str!("../../assets/teapot.bpt");

impl Model {
    /// The embedded Utah teapot (32 patches, z up, about 6.4 units wide).
    pub fn teapot() -> Model {
        // The embedded file is checked by the tests; failing here is a build defect.
        bpt::parse(TEAPOT_BPT).expect("the embedded teapot.bpt is valid")
    }

    /// Loads a model file, choosing the parser by extension: `.bpt`, `.bez`
    /// or `.obj` (case-insensitive; an OBJ mesh is subdivided with the
    /// default scheme, Catmull-Clark). Any other extension is
    /// [`LoadError::UnknownExtension`].
    ///
    /// The file is read through `crate::input`: it must be a regular file
    /// of at most the model cap ([`InputKind::Model`]`.limit()`, 1 GiB by
    /// default), else [`LoadError::Input`].
    pub fn load(path: impl AsRef<Path>) -> Result<Model, LoadError> {
        Model::load_with_limit(path, InputKind::Model.limit())
    }

    /// [`Model::load`] with an explicit size cap in bytes instead of the
    /// process-wide one.
    pub fn load_with_limit(path: impl AsRef<Path>, limit: u64) -> Result<Model, LoadError> {
        Model::load_within(path, limit, &mut PatchBudget::from_setting())
    }

    /// [`Model::load_with_limit`], taking the patches the file declares
    /// from `budget` (a scene's, shared by all its models) before reading
    /// them: [`LoadError::PatchBudget`] when they would pass it.
    pub fn load_within(
        path: impl AsRef<Path>,
        limit: u64,
        budget: &mut PatchBudget,
    ) -> Result<Model, LoadError> {
        Model::load_subdivided_within(path, limit, budget, Scheme::default())
    }

    /// [`Model::load_within`], subdividing an `.obj` mesh with `scheme`
    /// (the scene's `subdivision`); other formats ignore it.
    pub fn load_subdivided_within(
        path: impl AsRef<Path>,
        limit: u64,
        budget: &mut PatchBudget,
        scheme: Scheme,
    ) -> Result<Model, LoadError> {
        let path = path.as_ref();
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let parse: fn(&str, &mut PatchBudget) -> Result<Model, LoadError> =
            match extension.as_deref() {
                Some("bpt") => bpt::parse_within,
                Some("bez") => bez::parse_within,
                Some("obj") => {
                    let text = input::read_text(path, InputKind::Model, limit)?;
                    return obj::parse_within(&text, path, scheme, budget);
                }
                _ => {
                    return Err(LoadError::UnknownExtension {
                        path: path.to_path_buf(),
                    });
                }
            };
        // The parsers need the whole text; the cap bounds it (and the error
        // messages quote at most an excerpt of it).
        let text = input::read_text(path, InputKind::Model, limit)?;
        parse(&text, budget)
    }
}
