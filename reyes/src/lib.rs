//! A Reyes renderer for bicubic Bezier patch models, built on the
//! `scheduler` megakernel.
//!
//! A frame goes from a [`Scene`] (a TOML scene, a RenderMan RIB file or a
//! bare `.bpt`/`.bez` model) through [`PreparedScene`] (world-space patches,
//! the camera, the lights and the [`DicingRule`], all computed once) to an
//! image, on the GPU with a [`GpuRenderer`] or on the CPU with the reference
//! renderer ([`reference::render`]). Both return the image and the same
//! [`RenderStats`].
//!
//! ```no_run
//! use reyes::{GpuOptions, GpuRenderer, PreparedScene, Scene};
//!
//! let scene = Scene::load("scene.toml")?;        // or Scene::default_teapot()
//! let prepared = PreparedScene::load(&scene)?;   // models, camera, lights, the dicing rule
//! let gpu = reyes::gpu::create_gpu()?;
//! let rendered = GpuRenderer::new(&gpu, GpuOptions::default())?.render(&prepared)?;
//! reyes::output::write_png(&rendered.image, "scene.png")?;
//! let cpu = reyes::reference::render(&prepared);  // the CPU reference, same picture
//! println!("{} micropolygons on the GPU, {} on the CPU", rendered.stats.micropolygons, cpu.stats.micropolygons);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! (The README shows the same lines; this copy is compiled as a doctest.)
//!
//! The modules:
//!
//! * [`scene`]: the scene description, its TOML format and its validation;
//!   [`modes`]: the sampling, dicing and shading-interpolation modes;
//!   [`aov`]: what the image shows;
//!   [`depth`]: the depth output (camera-space depth per pixel);
//! * [`model`] and [`load`]: patch models and their loaders; [`rib`]:
//!   RenderMan RIB input; [`displacement`]: displacement sources;
//! * [`noise`]: RenderMan's `noise` on the CPU, and its WGSL twin;
//! * [`prepare`]: host preparation of a frame;
//! * [`gpu`]: the GPU renderer; [`reference`](mod@reference): the CPU
//!   reference renderer;
//! * [`texture`]: image textures, their mip chains and their filtering;
//!   [`shadow`]: shadow maps and their percentage-closer lookups;
//!   [`surface_shader`]: user WGSL surface shaders;
//! * [`stats`]: render statistics; [`output`]: PNG and EXR output;
//!   [`quantize`]: the 8-bit encoding (RenderMan's `Exposure` and
//!   `Quantize`); [`progress`]: what the GPU renderer is doing while a
//!   caller waits;
//! * `view` (feature `viewer`, on by default): the interactive viewer;
//! * `cli` (feature `cli`, on by default): the `reyes` command line.
//!
//! The renderer's building blocks (the Bezier and dicing arithmetic, the
//! camera, sample positions and tables, the GPU data layouts, the
//! reference's stages) are internal. The `internals` feature makes them
//! public, undocumented and unstable, for the workspace's own tests and
//! benchmarks, which check them one by one.
//!
//! The pipeline and its conventions are described in `docs/reyes.md`, the
//! scene format in `docs/reyes-scene.md`, the layers of the crate in
//! `docs/architecture.md`.

// Without `internals`, the items that only the workspace's tests and
// benchmarks reach are unused (and so are their re-exports), `pub` items
// in internal modules are unreachable, and clippy judges their names as
// private API: none of it is a defect of that build.
#![cfg_attr(
    not(feature = "internals"),
    expect(
        dead_code,
        unused_imports,
        unreachable_pub,
        clippy::wrong_self_convention,
        reason = "the internal modules are public only with the `internals` feature"
    )
)]

/// Declares internal modules: public, but hidden from the documentation,
/// with the `internals` feature (the workspace's tests and benchmarks
/// enable it); visible to this crate alone without it.
macro_rules! internal_modules {
    ($($name:ident;)*) => {$(
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        pub(crate) mod $name;
    )*};
}

pub mod aov;
pub mod budget;
#[cfg(feature = "cli")]
pub mod cli;
pub mod depth;
pub mod displacement;
pub mod filter;
pub mod gpu;
pub mod load;
pub mod model;
pub mod modes;
pub mod noise;
pub mod output;
pub mod prepare;
pub mod progress;
pub mod quantize;
pub mod reference;
pub mod rib;
pub mod scene;
pub mod shading;
pub mod shadow;
pub mod stats;
pub mod subdiv;
pub mod surface_shader;
pub mod texture;
#[cfg(feature = "viewer")]
pub mod view;

internal_modules! {
    bezier;
    camera;
    color;
    dicing;
    input;
    motion;
    nonfinite;
    params;
    sampling;
    user_wgsl;
    uvt;
}

#[cfg(test)]
mod test_random;

pub use aov::Aov;
pub use dicing::DicingRule;
pub use displacement::{DisplacementDesc, DisplacementError};
pub use gpu::{GpuOptions, GpuRendered, GpuRenderer, RenderError};
pub use input::{InputError, InputKind};
pub use load::LoadError;
pub use model::{Model, Patch};
pub use modes::{Dicing, Sampling, ShadingInterpolation};
pub use output::OutputError;
pub use prepare::PreparedScene;
pub use reference::{ReferenceError, ReferenceOptions, Rendered};
pub use rib::RibError;
pub use scene::{FramingError, Scene, SceneError};
pub use stats::RenderStats;
