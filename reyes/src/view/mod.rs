//! `reyes view`: an interactive viewer of a scene.
//!
//! * `controls` maps input events to camera and settings (a pure state
//!   machine);
//! * `events` turns window events into those inputs;
//! * `worker` is the render thread, which owns the renderer;
//! * `shadow_cache` keeps the shadow maps of automatic shadows between
//!   frames while only the camera moves;
//! * `present` holds the surface, the composite texture and the screenshot;
//! * `overlay` draws the statistics with egui;
//! * `save` is `P`: the PNG and the equivalent `reyes render` command;
//! * `script` reads scripted input (`--script`) for tests;
//! * `log` is what `--log-json` writes;
//! * [`error`] has [`ViewError`].
//!
//! The event loop (`app`) never waits on a render: the worker renders the
//! newest requested view and sends the frame back as a user event.

mod app;
internal_modules! {
    controls;
    events;
    log;
    overlay;
    present;
    save;
    script;
    shadow_cache;
    worker;
}
pub mod error;

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

pub use self::log::ViewLog;
pub use error::ViewError;

use crate::gpu::GpuOptions;
use crate::prepare::PreparedScene;
use worker::WorkerEvent;

/// How the viewer runs.
#[derive(Debug, Clone)]
pub struct ViewConfig {
    /// The window's title.
    pub title: String,
    /// Close after this many presented frames, once the view is refined
    /// (and the script done); `None`: when the window is closed.
    pub frames: Option<u64>,
    /// Where to save the last presented image when `frames` ends the viewer
    /// (the extension chooses the format, see [`crate::output::write_image`]).
    pub screenshot: Option<PathBuf>,
    /// Scripted input, run through the event loop.
    pub script: Vec<script::Step>,
    /// Whether the overlay starts visible.
    pub overlay: bool,
    /// Where `P` saves the refined frame (the extension chooses the format).
    pub save_path: PathBuf,
    /// The command line `P` prints, before the view's own options.
    pub command: save::CommandBase,
    /// Renderer options (timeout, chunks per batch).
    pub gpu_options: GpuOptions,
    /// Resolution of a preview relative to the window, in (0, 1].
    pub preview_scale: f32,
    /// How long input must be still before the frame is refined.
    pub settle: Duration,
}

impl Default for ViewConfig {
    fn default() -> Self {
        ViewConfig {
            title: "reyes view".into(),
            frames: None,
            screenshot: None,
            script: Vec::new(),
            overlay: true,
            save_path: PathBuf::from("reyes-view.png"),
            command: save::CommandBase::default(),
            gpu_options: GpuOptions::default(),
            preview_scale: 0.5,
            settle: Duration::from_millis(250),
        }
    }
}

/// Opens the viewer on `scene` and runs it until the window closes (or
/// `config.frames` ends it). Returns what was rendered.
pub fn run(scene: PreparedScene, config: ViewConfig) -> Result<ViewLog, ViewError> {
    let event_loop = winit::event_loop::EventLoop::<WorkerEvent>::with_user_event()
        .build()
        .map_err(|e| ViewError::NoDisplay(e.to_string()))?;
    let wanted = config.frames;
    let mut app = app::App::new(scene, config, event_loop.create_proxy());
    let result = event_loop.run_app(&mut app);
    if let Some(error) = app.error.take() {
        return Err(error);
    }
    result.map_err(|e| ViewError::Window(e.to_string()))?;
    // Ended by `--frames` (at N frames, or at the refined view when fewer
    // come) is success; a window closed before that is not.
    if let Some(wanted) = wanted
        && app.presented < wanted
        && !app.done
    {
        return Err(ViewError::Closed {
            presented: app.presented,
            wanted,
        });
    }
    Ok(std::mem::take(&mut app.log))
}

/// The devices for `window`, on an adapter that can present to its surface.
struct Devices {
    /// The renderer's device, with the renderer's features (as
    /// [`crate::gpu::create_gpu`] asks for them, plus timestamps where
    /// available).
    render: scheduler::Gpu,
    /// A second device on the same adapter for the window. wgpu holds a
    /// device-wide lock while a thread waits for that device's work (the
    /// render worker waits for every frame), and presenting needs that lock
    /// exclusively: on one shared device, a present would wait for the
    /// frame being rendered. Frames come back as images in host memory
    /// anyway, so nothing needs to be shared between the two.
    present: (wgpu::Device, wgpu::Queue),
    surface: wgpu::Surface<'static>,
}

fn open_gpu(
    event_loop: &winit::event_loop::ActiveEventLoop,
    window: &Arc<winit::window::Window>,
) -> Result<Devices, ViewError> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
        Box::new(event_loop.owned_display_handle()),
    ));
    let surface = instance
        .create_surface(window.clone())
        .map_err(|e| ViewError::CreateSurface(e.to_string()))?;
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference:
            wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance),
        compatible_surface: Some(&surface),
        ..Default::default()
    }))
    .map_err(|_| ViewError::SurfaceUnsupported)?;
    let available = adapter.features();
    // 64-bit atomics where the adapter has them: the depth test then takes
    // one pass instead of two (crate::gpu::DepthTest).
    let optional = wgpu::Features::TIMESTAMP_QUERY
        | wgpu::Features::MEMORY_DECORATION_COHERENT
        | crate::gpu::graph::WIDE_ATOMICS;
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("reyes view device"),
        required_features: optional & available,
        required_limits: adapter.limits(),
        ..Default::default()
    }))
    .map_err(|e| ViewError::Device(e.to_string()))?;
    let present = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("reyes view window"),
        ..Default::default()
    }))
    .map_err(|e| ViewError::Device(e.to_string()))?;
    // The window's device reports through the log (its errors end in a
    // lost surface, which the viewer reports); the renderer's through the
    // frame's error.
    let _ = scheduler::UncapturedErrors::install(&present.0);
    let uncaptured = scheduler::UncapturedErrors::install(&device);
    Ok(Devices {
        render: scheduler::Gpu {
            adapter,
            device,
            queue,
            uncaptured,
        },
        present,
        surface,
    })
}
