//! The error type of the model loaders.

use std::path::PathBuf;

use crate::input::InputError;

/// Why a model file could not be loaded. Parse errors carry the 1-based line
/// number where the problem was found and say what was expected there; text
/// they quote from the file is cut to `crate::input::EXCERPT_CHARS` characters.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LoadError {
    /// The file could not be opened or read (missing, no permission, ...).
    #[error("cannot read model file {}: {source}", path.display())]
    Io {
        /// The file that was being read.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file was refused before parsing: not a regular file, larger than
    /// the model cap, or not UTF-8 (never [`InputError::Io`], which becomes
    /// [`LoadError::Io`]).
    #[error(transparent)]
    Input(InputError),
    /// The file name does not end in a supported extension (`.bpt`, `.bez`,
    /// `.obj`).
    #[error("unsupported model file extension for {} (expected .bpt, .bez or .obj)", path.display())]
    UnknownExtension {
        /// The offending path.
        path: PathBuf,
    },
    /// The file ended before a count (`what`: "patch count" or "vertex count").
    #[error("line {line}: expected the {what}, found end of file")]
    MissingCount {
        /// Line where the count was expected.
        line: usize,
        /// Which count was expected.
        what: &'static str,
    },
    /// A count line is not a single non-negative integer.
    #[error("line {line}: expected the {what} (one non-negative integer), found {found:?}")]
    InvalidCount {
        /// Line of the bad count.
        line: usize,
        /// Which count was expected.
        what: &'static str,
        /// The text found instead.
        found: String,
    },
    /// A `.bpt` degree line is not `3 3` (only bicubic patches are supported).
    #[error("line {line}: unsupported patch degree {found:?} (expected \"3 3\": bicubic)")]
    UnsupportedDegree {
        /// Line of the degree.
        line: usize,
        /// The text found instead.
        found: String,
    },
    /// A control-point or vertex line does not have exactly 3 coordinates.
    #[error("line {line}: expected 3 coordinates (x y z), found {found}")]
    WrongCoordinateCount {
        /// Line of the point.
        line: usize,
        /// Number of coordinates found.
        found: usize,
    },
    /// A token that should be a number (coordinate or vertex index) does not parse.
    #[error("line {line}: expected a number, found {token:?}")]
    InvalidNumber {
        /// Line of the token.
        line: usize,
        /// The token.
        token: String,
    },
    /// A `.bpt` texture coordinate header is not `st <number of patches>`.
    #[error(
        "line {line}: expected \"st {patches}\" (one texture coordinate line per patch), found {found:?}"
    )]
    StCount {
        /// Line of the header.
        line: usize,
        /// The model's patch count.
        patches: usize,
        /// The header found.
        found: String,
    },
    /// A `.bpt` texture coordinate line does not have 8 numbers.
    #[error("line {line}: expected 8 texture coordinates (s t of 4 corners), found {found}")]
    WrongStCount {
        /// Line of the coordinates.
        line: usize,
        /// Number of values found.
        found: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("line {line}: coordinate {token:?} is not finite")]
    NonFiniteCoordinate {
        /// Line of the coordinate.
        line: usize,
        /// The token as written in the file.
        token: String,
    },
    /// The file ended before everything its counts declared.
    #[error("line {line}: file ended early: expected {expected}")]
    Truncated {
        /// The line after the last line of the file.
        line: usize,
        /// What was still expected.
        expected: String,
    },
    /// Non-blank text after the last declared patch or vertex.
    #[error("line {line}: unexpected text after the end of the data: {text:?}")]
    TrailingGarbage {
        /// Line of the extra text.
        line: usize,
        /// The extra text (trimmed).
        text: String,
    },
    /// A `.bez` vertex index is 0 or larger than the vertex count (indices are 1-based).
    #[error("line {line}: vertex index {index} out of range 1..={vertex_count}")]
    VertexIndexOutOfRange {
        /// Line of the patch that uses the index.
        line: usize,
        /// The index as written.
        index: u64,
        /// Number of vertices in the file.
        vertex_count: usize,
    },
    /// The declared patch count is more than the scene's patch budget has
    /// left ([`crate::budget`]); no patch was read.
    #[error("line {line}: the declared patch count: {source}")]
    PatchBudget {
        /// Line of the count.
        line: usize,
        /// The count and the budget.
        #[source]
        source: crate::budget::BudgetExceeded,
    },
    /// A `.bez` patch line does not have exactly 16 vertex indices.
    #[error("line {line}: expected 16 comma-separated vertex indices, found {found}")]
    WrongIndexCount {
        /// Line of the patch.
        line: usize,
        /// Number of indices found.
        found: usize,
    },
    /// An OBJ statement that cannot be read (a bad number, an index out of
    /// range, a polyline): the file, the line and what is wrong (naming
    /// the face, numbered from 1, when it is a face's).
    #[error("{}:{line}: {message}", path.display())]
    ObjSyntax {
        /// The OBJ file.
        path: std::path::PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// `tobj` refused an OBJ file (its errors name no line).
    #[error("{}: {message}", path.display())]
    ObjRead {
        /// The OBJ file.
        path: std::path::PathBuf,
        /// tobj's message.
        message: String,
    },
    /// An OBJ file's mesh has no surface ([`crate::subdiv::Mesh::validate`])
    /// or cannot be subdivided. Unlike [`crate::subdiv::MeshError`]'s own
    /// convention, its faces and vertices are numbered from 1 in file
    /// order, as OBJ indices are.
    #[error("{}{}: {source}{}", path.display(), line.map_or_else(String::new, |l| format!(":{l}")), numbering_note(source))]
    Mesh {
        /// The OBJ file.
        path: std::path::PathBuf,
        /// 1-based line of the face at fault, when one is.
        line: Option<usize>,
        /// What is wrong, in the file's numbering.
        #[source]
        source: crate::subdiv::MeshError,
    },
    /// The patches an OBJ file's faces make are more than the scene's
    /// patch budget has left ([`crate::budget`]).
    #[error("{}: its faces' patches: {source}", path.display())]
    PatchBudgetOf {
        /// The OBJ file.
        path: std::path::PathBuf,
        /// The count and the budget.
        #[source]
        source: crate::budget::BudgetExceeded,
    },
}

impl LoadError {
    /// The 1-based line number of a `.bpt` or `.bez` parse error (`None`
    /// for I/O, input and extension errors, and for the OBJ errors, whose
    /// messages name their file and line themselves).
    pub fn line(&self) -> Option<usize> {
        match self {
            LoadError::Io { .. }
            | LoadError::Input(_)
            | LoadError::UnknownExtension { .. }
            | LoadError::ObjSyntax { .. }
            | LoadError::ObjRead { .. }
            | LoadError::Mesh { .. }
            | LoadError::PatchBudgetOf { .. } => None,
            LoadError::MissingCount { line, .. }
            | LoadError::InvalidCount { line, .. }
            | LoadError::UnsupportedDegree { line, .. }
            | LoadError::WrongCoordinateCount { line, .. }
            | LoadError::InvalidNumber { line, .. }
            | LoadError::NonFiniteCoordinate { line, .. }
            | LoadError::Truncated { line, .. }
            | LoadError::TrailingGarbage { line, .. }
            | LoadError::VertexIndexOutOfRange { line, .. }
            | LoadError::WrongIndexCount { line, .. }
            | LoadError::PatchBudget { line, .. }
            | LoadError::StCount { line, .. }
            | LoadError::WrongStCount { line, .. } => Some(*line),
        }
    }
}

/// The note after a mesh error that numbers faces or vertices: they are
/// the file's numbers, not [`crate::subdiv::MeshError`]'s 0-based ones.
fn numbering_note(error: &crate::subdiv::MeshError) -> &'static str {
    use crate::subdiv::MeshError as E;
    match error {
        E::FaceTooSmall { .. }
        | E::VertexOutOfRange { .. }
        | E::RepeatedVertex { .. }
        | E::DuplicateFace { .. }
        | E::InconsistentWinding { .. }
        | E::NonManifoldEdge { .. }
        | E::NonFinitePosition { .. } => " (faces and vertices numbered from 1, as in the file)",
        _ => "",
    }
}

impl From<InputError> for LoadError {
    /// Plain I/O failures keep their long-standing [`LoadError::Io`] variant;
    /// refusals become [`LoadError::Input`].
    fn from(error: InputError) -> LoadError {
        match error {
            InputError::Io { path, source, .. } => LoadError::Io { path, source },
            other => LoadError::Input(other),
        }
    }
}
