//! Parsers (and writers) for the bicubic Bezier patch file formats.
//!
//! * `bpt`: the `.bpt` text format: a patch count, then per patch a degree
//!   line `3 3` and 16 lines `x y z`.
//! * `bez`: Newell's `.bez` format: a patch count, one line of 16
//!   comma-separated 1-based vertex indices per patch, a vertex count, and one
//!   `x,y,z` line per vertex.
//! * [`obj`]: Wavefront `.obj` polygon meshes (read with `tobj`), subdivided
//!   into patches ([`crate::subdiv`]).
//!
//! The patch parsers work on `&str`, skip a leading UTF-8 byte-order mark and
//! blank lines, tolerate extra whitespace, and report errors as [`LoadError`]
//! with the 1-based line number; text they quote is cut to
//! `crate::input::EXCERPT_CHARS` characters. Use
//! [`crate::model::Model::load`] to read a file by path (through
//! `crate::input`: regular files only, at most 1 GiB by default); it is
//! defined here, in `sources`, so that [`crate::model`] imports nothing from
//! this module.

internal_modules! {
    bez;
    bpt;
}
mod error;
mod lines;
pub mod obj;
mod obj_scan;
mod sources;

pub use error::LoadError;
