//! The event loop: window events and scripted steps go to the
//! [`Controls`]; a changed view becomes a request to the render worker; a
//! finished frame comes back as a user event and is presented.
//!
//! Progressive refinement: while the camera moves, previews (1 spp, a
//! reduced resolution) are requested; once input has been still for
//! [`ViewConfig::settle`] (and no button is held), the full frame is.

use std::sync::Arc;
use std::time::{Duration, Instant};

use image::{Rgba32FImage, RgbaImage};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoopProxy};
use winit::window::{Window, WindowId};

use super::controls::{Controls, Input, Orbit};
use super::error::ViewError;
use super::log::{FrameRecord, ViewLog};
use super::overlay::{FrameInfo, Overlay, OverlayInfo};
use super::present::{COMPOSITE_FORMAT, Presenter};
use super::script::Step;
use super::worker::{Compiling, Frame, FrameSpec, Quality, RenderWorker, WorkerEvent, settings_of};
use super::{ViewConfig, events, open_gpu, save};
use crate::output::console::{errln, outln};
use crate::prepare::PreparedScene;

/// The viewer while its window is open.
#[derive(Debug)]
struct Running {
    presenter: Presenter,
    overlay: Overlay,
    worker: RenderWorker,
    adapter: String,
    controls: Controls,
    /// The scene's camera, whose near and far planes every view keeps.
    base: crate::camera::Camera,
    /// Bumped by every change of the view.
    generation: u64,
    /// The last request sent: generation and quality.
    requested: (u64, Quality),
    /// When the view last changed.
    changed_at: Instant,
    /// The frame on screen.
    shown: Option<FrameSpec>,
    info: Option<FrameInfo>,
    /// Whether `shown` has been presented.
    presented: bool,
    /// The last refined frame, for `P`.
    refined: Option<(FrameSpec, RgbaImage, Rgba32FImage)>,
    /// `P` was pressed before the view was refined.
    save_pending: bool,
    /// The driver's compile of the megakernel, while it lasts, and when
    /// the overlay next counts a second of it.
    compiling: Option<(Compiling, Instant)>,
}

/// The application handed to winit.
#[derive(Debug)]
pub(super) struct App {
    config: ViewConfig,
    scene: Arc<PreparedScene>,
    proxy: EventLoopProxy<WorkerEvent>,
    running: Option<Running>,
    script: std::collections::VecDeque<Step>,
    /// Frames presented.
    pub presented: u64,
    /// A scripted resize not yet seen: the view is not refined before it.
    awaiting_size: Option<(u32, u32)>,
    /// `--frames` has ended the viewer (the loop may still deliver events).
    pub done: bool,
    /// The first error, which ends the viewer.
    pub error: Option<ViewError>,
    /// What happened, for `--log-json`.
    pub log: ViewLog,
}

impl App {
    /// The viewer of `scene`.
    pub(super) fn new(
        scene: PreparedScene,
        config: ViewConfig,
        proxy: EventLoopProxy<WorkerEvent>,
    ) -> App {
        let script = config.script.iter().copied().collect();
        App {
            config,
            scene: Arc::new(scene),
            proxy,
            running: None,
            script,
            presented: 0,
            done: false,
            awaiting_size: None,
            error: None,
            log: ViewLog::default(),
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: ViewError) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    fn start(&mut self, event_loop: &ActiveEventLoop) -> Result<Running, ViewError> {
        let camera = self.scene.camera;
        let attributes = Window::default_attributes()
            .with_title(self.config.title.clone())
            .with_inner_size(winit::dpi::PhysicalSize::new(camera.width, camera.height));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| ViewError::Window(e.to_string()))?,
        );
        let devices = open_gpu(event_loop, &window)?;
        let gpu = devices.render;
        let (device, queue) = devices.present;
        let presenter = Presenter::new(
            window.clone(),
            devices.surface,
            &gpu.adapter,
            &device,
            &queue,
        )?;
        let overlay = Overlay::new(&window, &device, &queue, COMPOSITE_FORMAT);
        let info = gpu.adapter.get_info();
        let adapter = format!("{} ({:?}, {:?})", info.name, info.device_type, info.backend);
        let gpu_description = gpu.describe();
        let proxy = self.proxy.clone();
        let worker = RenderWorker::start(
            gpu,
            self.config.gpu_options.clone(),
            self.scene.clone(),
            move |event| {
                // The loop is gone only when the viewer is closing.
                let _ = proxy.send_event(event);
            },
        )
        .map_err(ViewError::Thread)?;
        let lo_hi = bounds(&self.scene);
        let mut controls =
            Controls::new(Orbit::from_camera(&camera), settings_of(&self.scene), lo_hi);
        controls.overlay = self.config.overlay;
        let mut running = Running {
            presenter,
            overlay,
            worker,
            adapter,
            controls,
            base: camera,
            generation: 0,
            requested: (0, Quality::Full),
            changed_at: Instant::now(),
            shown: None,
            info: None,
            presented: true,
            refined: None,
            save_pending: false,
            compiling: None,
        };
        self.log.adapter = gpu_description;
        request(&mut running, Quality::Full, &self.config);
        Ok(running)
    }

    /// Applies one input; `size` is the window's.
    fn input(&mut self, event_loop: &ActiveEventLoop, input: Input) {
        let Some(running) = &mut self.running else {
            return;
        };
        let size = running.presenter.size();
        let before = running.controls.overlay;
        let outcome = running.controls.handle(input, size);
        if running.controls.overlay != before {
            running.presenter.window.request_redraw();
        }
        if outcome.camera_moved || outcome.settings_changed {
            running.generation += 1;
            running.changed_at = Instant::now();
            let quality = if outcome.camera_moved {
                Quality::Preview
            } else {
                Quality::Full
            };
            request(running, quality, &self.config);
        }
        if outcome.save {
            running.save_pending = true;
            if let Err(error) = self.try_save() {
                return self.fail(event_loop, error);
            }
        }
        if outcome.quit {
            event_loop.exit();
        }
    }

    /// Saves the refined frame when `P` is pending and it is there. A save
    /// that fails is reported and the viewer goes on; only a message that
    /// cannot be written ends it.
    fn try_save(&mut self) -> Result<(), ViewError> {
        let Some(running) = &mut self.running else {
            return Ok(());
        };
        let Some((spec, image, linear)) = &running.refined else {
            return Ok(());
        };
        if !running.save_pending || spec.generation != running.generation {
            return Ok(());
        }
        running.save_pending = false;
        let path = &self.config.save_path;
        match crate::output::write_rendered_image(image, linear, path) {
            Ok(()) => {
                let (line, note) =
                    save::render_command(&self.config.command, &spec.camera, &spec.settings, path);
                outln!(
                    "saved {}; the same frame from the command line:\n{line}",
                    path.display()
                )?;
                if let Some(note) = note {
                    outln!("note: {note}")?;
                }
            }
            Err(error) => errln!("error: cannot save {}: {error}", path.display())?,
        }
        Ok(())
    }

    fn frame(&mut self, event_loop: &ActiveEventLoop, frame: Frame) {
        let Some(running) = &mut self.running else {
            return;
        };
        running.presenter.upload(&frame.image);
        let info = FrameInfo::of(&frame);
        self.log
            .frames
            .push(FrameRecord::of(&frame, running.generation));
        if frame.spec.quality == Quality::Full {
            running.refined = Some((frame.spec, frame.image, frame.linear));
        }
        running.shown = Some(frame.spec);
        running.info = Some(info);
        running.presented = false;
        running.presenter.window.request_redraw();
        if let Err(error) = self.try_save() {
            self.fail(event_loop, error);
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(running) = &mut self.running else {
            return;
        };
        let status = status(running);
        let Running {
            presenter,
            overlay,
            controls,
            info,
            adapter,
            compiling,
            ..
        } = running;
        let size = presenter.size();
        let window = presenter.window.clone();
        let show_overlay = controls.overlay;
        let overlay_info = OverlayInfo {
            adapter,
            frame: info.as_ref(),
            settings: &controls.settings,
            status: &status,
            compiling: compiling.as_ref().map(|(c, _)| c),
        };
        let start = Instant::now();
        let mut again = false;
        let result = presenter.present(|encoder, target| {
            if show_overlay {
                again = overlay.draw(&window, encoder, target, size, &overlay_info);
            }
        });
        if again {
            window.request_redraw();
        }
        // The event loop must never wait for a render; a slow present
        // would show here.
        log::debug!("present took {:.1} ms", start.elapsed().as_secs_f64() * 1e3);
        match result {
            Ok(true) => {
                if !running.presented && running.shown.is_some() {
                    running.presented = true;
                    self.presented += 1;
                }
                self.check_done(event_loop);
            }
            Ok(false) => running.presenter.window.request_redraw(),
            Err(error) => self.fail(event_loop, error),
        }
    }

    /// Whether the view on screen is the refined frame of the current view.
    fn refined(&self) -> bool {
        self.running.as_ref().is_some_and(|r| {
            self.awaiting_size
                .is_none_or(|size| size == r.presenter.size())
                && r.presented
                && r.shown
                    .is_some_and(|s| s.generation == r.generation && s.quality == Quality::Full)
        })
    }

    /// `--frames N`: after N presented frames, once the view is refined and
    /// the script is done, save the screenshot and close. A refined view
    /// with the script done is also the end: without input no further
    /// frame comes, so fewer than N frames stop there, saying so (waiting
    /// would never end).
    fn check_done(&mut self, event_loop: &ActiveEventLoop) {
        let Some(wanted) = self.config.frames else {
            return;
        };
        if self.done || !self.refined() || !self.script.is_empty() {
            return;
        }
        if self.presented < wanted
            && let Err(error) = outln!(
                "note: --frames {wanted}: the view is refined after {} presented frames and no further frame comes without input; stopping there",
                self.presented
            )
        {
            return self.fail(event_loop, error.into());
        }
        if let (Some(path), Some(running)) = (&self.config.screenshot, &self.running) {
            let saved = running
                .presenter
                .read_composite()
                .and_then(|image| Ok(crate::output::write_image(&image, path)?));
            if let Err(error) = saved {
                return self.fail(event_loop, error);
            }
            if let Err(error) = outln!("wrote {}", path.display()) {
                return self.fail(event_loop, error.into());
            }
        }
        if let Some(running) = &self.running {
            self.log.final_camera = Some(super::log::CameraRecord::of(
                &running.controls.orbit.camera(&self.scene.camera, 1, 1),
            ));
        }
        self.done = true;
        event_loop.exit();
    }

    /// Runs script steps up to the next `wait` that is not yet satisfied.
    fn run_script(&mut self, event_loop: &ActiveEventLoop) {
        while let Some(&step) = self.script.front() {
            match step {
                Step::Wait if !self.refined() => return,
                Step::Wait => {}
                Step::Input(input) => self.input(event_loop, input),
                Step::Resize(width, height) => {
                    self.awaiting_size = Some((width, height));
                    if let Some(running) = &self.running {
                        let size = winit::dpi::PhysicalSize::new(width, height);
                        // Applied now or announced by a Resized event.
                        if let Some(now) = running.presenter.window.request_inner_size(size) {
                            self.window_event(
                                event_loop,
                                running.presenter.window.id(),
                                WindowEvent::Resized(now),
                            );
                        }
                    }
                }
            }
            self.script.pop_front();
        }
        // The last step may have been the one `--frames` waited for.
        if self.refined() {
            self.check_done(event_loop);
        }
    }
}

/// Sends a request for the current view.
fn request(running: &mut Running, quality: Quality, config: &ViewConfig) {
    let (width, height) = running.presenter.size();
    let (width, height) = match quality {
        Quality::Full => (width, height),
        Quality::Preview => (
            ((width as f32 * config.preview_scale) as u32).max(1),
            ((height as f32 * config.preview_scale) as u32).max(1),
        ),
    };
    let spec = FrameSpec {
        generation: running.generation,
        quality,
        camera: running.controls.orbit.camera(&running.base, width, height),
        settings: running.controls.settings,
    };
    running.requested = (running.generation, quality);
    running.worker.request(spec);
}

fn status(running: &Running) -> String {
    let (generation, quality) = running.requested;
    let done = running
        .shown
        .is_some_and(|s| s.generation == generation && s.quality == quality);
    match (done, quality) {
        (true, Quality::Full) => "refined".to_owned(),
        (true, Quality::Preview) => "preview (refines when the camera stops)".to_owned(),
        (false, Quality::Preview) => "rendering preview...".to_owned(),
        (false, Quality::Full) => "refining...".to_owned(),
    }
}

/// The world-space bounds of the scene's patches.
fn bounds(scene: &PreparedScene) -> (glam::Vec3, glam::Vec3) {
    let mut lo = glam::Vec3::splat(f32::INFINITY);
    let mut hi = glam::Vec3::splat(f32::NEG_INFINITY);
    for patch in &scene.patches {
        for p in patch.points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    if lo.x > hi.x {
        (glam::Vec3::splat(-1.0), glam::Vec3::splat(1.0))
    } else {
        (lo, hi)
    }
}

impl ApplicationHandler<WorkerEvent> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        match self.start(event_loop) {
            Ok(running) => {
                self.log.initial_camera = Some(super::log::CameraRecord::of(&self.scene.camera));
                self.running = Some(running);
            }
            Err(error) => self.fail(event_loop, error),
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, event: WorkerEvent) {
        match event {
            WorkerEvent::Frame(frame) => self.frame(event_loop, *frame),
            WorkerEvent::Failed(message) => self.fail(event_loop, ViewError::Render(message)),
            WorkerEvent::Compile(compiling) => {
                if let Some(running) = &mut self.running {
                    running.compiling = compiling.map(|c| {
                        let tick = c.since + Duration::from_secs(1);
                        (c, tick)
                    });
                    running.presenter.window.request_redraw();
                }
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(running) = &mut self.running else {
            return;
        };
        let window = running.presenter.window.clone();
        // A redraw is no input for egui (passing it on would ask for the
        // next redraw, for ever).
        let for_overlay =
            running.controls.overlay && !matches!(event, WindowEvent::RedrawRequested);
        let (consumed, repaint) = if for_overlay {
            running.overlay.on_window_event(&window, &event)
        } else {
            (false, false)
        };
        if repaint {
            window.request_redraw();
        }
        let input = match event {
            WindowEvent::CloseRequested => return event_loop.exit(),
            WindowEvent::RedrawRequested => return self.redraw(event_loop),
            WindowEvent::Resized(size) => {
                if running.presenter.resize(size.width, size.height) {
                    running.generation += 1;
                    running.changed_at = Instant::now();
                    request(running, Quality::Preview, &self.config);
                }
                window.request_redraw();
                return;
            }
            event => events::input_of(&event, consumed),
        };
        if let Some(input) = input {
            self.input(event_loop, input);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        self.run_script(event_loop);
        let Some(running) = &mut self.running else {
            return;
        };
        if running.worker.finished() && self.error.is_none() {
            // The worker reports its error before it ends; without one it
            // ended unexpectedly.
            return self.fail(
                event_loop,
                ViewError::Render("the render thread stopped".into()),
            );
        }
        let (generation, quality) = running.requested;
        if generation == running.generation && quality == Quality::Preview {
            let due = running.changed_at + self.config.settle;
            if Instant::now() >= due && !running.controls.dragging() {
                request(running, Quality::Full, &self.config);
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(due.max(Instant::now())));
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
        // While the driver compiles, the overlay counts the seconds.
        if let Some((compiling, tick)) = &mut running.compiling {
            let now = Instant::now();
            if now >= *tick {
                running.presenter.window.request_redraw();
                let seconds = now.saturating_duration_since(compiling.since).as_secs();
                *tick = compiling.since + Duration::from_secs(seconds + 1);
            }
            let wake = match event_loop.control_flow() {
                ControlFlow::WaitUntil(due) => due.min(*tick),
                _ => *tick,
            };
            event_loop.set_control_flow(ControlFlow::WaitUntil(wake));
        }
    }
}
