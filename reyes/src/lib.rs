//! A Reyes renderer for bicubic Bezier patch models.
//!
//! This crate holds the renderer's CPU side:
//!
//! * [`model`] and [`load`]: patch models and the `.bpt`/`.bez` loaders;
//! * [`input`]: the one way input files are read (regular files only, with a
//!   size cap);
//! * [`scene`]: the TOML scene description; [`modes`]: its sampling,
//!   dicing and shading-interpolation modes;
//! * [`displacement`]: displacement sources (height maps, procedural and
//!   user WGSL heights) and their preparation;
//! * [`prepare`]: host preparation (world-space patches, camera, lights);
//! * [`dicing`]: grid sizes from the shading rate and the canonical edge
//!   vertices that keep neighbouring grids watertight;
//! * [`camera`], [`color`], [`sampling`], [`bezier`], [`params`]: the
//!   conventions and building blocks that every implementation of the
//!   pipeline shares;
//! * [`reference`](mod@reference): the CPU reference renderer;
//! * [`stats`]: render statistics; [`output`]: PNG output;
//! * `view` (feature `viewer`, on by default): the interactive viewer;
//! * `cli` (feature `cli`, on by default): the `reyes` command line.
//!
//! The pipeline and its conventions are described in `docs/reyes.md`, the
//! scene format in `docs/reyes-scene.md`.

pub mod aov;
pub mod bezier;
pub mod camera;
#[cfg(feature = "cli")]
pub mod cli;
pub mod color;
pub mod dicing;
pub mod displacement;
pub mod input;
pub mod load;
pub mod model;
pub mod modes;
pub mod motion;
pub mod nonfinite;
pub mod output;
pub mod params;
pub mod prepare;
pub mod reference;
pub mod rib;
pub mod sampling;
pub mod scene;
pub mod stats;
pub mod uvt;
#[cfg(feature = "viewer")]
pub mod view;

#[cfg(test)]
mod test_random;

pub mod gpu;
