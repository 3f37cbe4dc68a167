//! The viewer's errors: each names what failed and, where there is one, what
//! to do about it.

use thiserror::Error;

/// Why the viewer could not start or had to stop.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ViewError {
    /// No window system to open a window on.
    #[error(
        "cannot open a window: {0} (run it in a desktop session, or headless under `xvfb-run -a reyes view ...`)"
    )]
    NoDisplay(String),
    /// The window system refused the window.
    #[error("cannot create the viewer window: {0}")]
    Window(String),
    /// The graphics API has no surface for the window.
    #[error("cannot create a surface for the window: {0}")]
    CreateSurface(String),
    /// No adapter with the renderer's features can present to the window.
    #[error(
        "no adapter can present to this window with the features the renderer needs (is a Vulkan driver such as Mesa's lavapipe installed?)"
    )]
    SurfaceUnsupported,
    /// The device could not be created.
    #[error("cannot create the GPU device: {0}")]
    Device(String),
    /// The surface went away and could not be configured again.
    #[error("the window's surface was lost")]
    SurfaceLost,
    /// Any other failure to get a surface texture.
    #[error("the window's surface failed: {0}")]
    Surface(String),
    /// The renderer failed (the message includes its causes).
    #[error("rendering failed: {0}")]
    Render(String),
    /// The render worker thread could not be started.
    #[error("cannot start the render thread: {0}")]
    Thread(#[source] std::io::Error),
    /// Reading the presented image back failed.
    #[error("cannot read the presented image back: {0}")]
    Screenshot(String),
    /// Writing the PNG or the scene failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// A message could not be written to standard output or error.
    #[error(transparent)]
    Console(#[from] crate::output::console::ConsoleError),
    /// Writing the scene file for `P` failed.
    #[error("cannot write {path}: {source}")]
    Write {
        /// The file.
        path: String,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The `--script` text is malformed.
    #[error("--script: {0}")]
    Script(String),
    /// The window closed before `--frames` frames were presented.
    #[error("the window closed after {presented} of {wanted} frames")]
    Closed {
        /// Frames presented.
        presented: u64,
        /// Frames asked for.
        wanted: u64,
    },
}
