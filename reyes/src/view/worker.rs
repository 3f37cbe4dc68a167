//! The render worker: a thread that owns the [`GpuRenderer`] and renders
//! the latest requested view, so the event loop never waits on a frame.
//!
//! Requests queue in a channel; the worker drains it and renders only the
//! newest one (older views are already stale). Every finished frame, and
//! any error, goes back through a callback that wakes the event loop; so
//! do the start and end of the driver's compile of the megakernel (through
//! the renderer's [`Progress`] observer), which the overlay shows while it
//! lasts.

use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;
use std::time::Instant;

use image::{Rgba32FImage, RgbaImage};

use crate::camera::Camera;
use crate::dicing::DicingRule;
use crate::gpu::{GpuOptions, GpuRenderer};
use crate::motion::PreparedLens;
use crate::prepare::PreparedScene;
use crate::progress::{Progress, ProgressEvent, compile_label};
use crate::stats::RenderStats;

use super::controls::Settings;
use super::shadow_cache::{ShadowCache, ShadowTime};

/// How finely a frame is rendered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quality {
    /// While the camera moves: 1 spp at a reduced resolution.
    Preview,
    /// When it stops: the settings' spp at the window's resolution.
    Full,
}

/// One frame to render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameSpec {
    /// Increases with every change of the view; a frame answers the
    /// request with the same number.
    pub generation: u64,
    /// Preview or full.
    pub quality: Quality,
    /// The camera, at the resolution to render.
    pub camera: Camera,
    /// The render settings.
    pub settings: Settings,
}

/// A rendered frame.
#[derive(Debug)]
pub struct Frame {
    /// The request it answers.
    pub spec: FrameSpec,
    /// The image (8-bit sRGB RGBA, straight from the renderer).
    pub image: RgbaImage,
    /// The resolve's linear floats, which `P` saves as EXR.
    pub linear: Rgba32FImage,
    /// The renderer's counters.
    pub stats: RenderStats,
    /// Megakernel time measured on the GPU, when the adapter has timestamps.
    pub gpu_ms: Option<f64>,
    /// Wall-clock time of the whole frame in the worker (its shadow
    /// maps' depth passes included when they were rendered for it).
    pub wall_ms: f64,
    /// The time of the frame's shadow maps, for a frame with automatic
    /// shadows.
    pub shadows: Option<ShadowTime>,
}

/// The driver's compile of the megakernel, while it lasts.
#[derive(Debug, Clone, PartialEq)]
pub struct Compiling {
    /// What is compiled for which adapter
    /// ([`compile_label`]).
    pub label: String,
    /// When it started.
    pub since: Instant,
}

/// What the worker reports.
#[derive(Debug)]
pub enum WorkerEvent {
    /// A frame is ready.
    Frame(Box<Frame>),
    /// The driver started compiling the megakernel (`Some`) or finished
    /// (`None`).
    Compile(Option<Compiling>),
    /// The renderer could not be created or a frame failed; the message is
    /// the error's, with its causes.
    Failed(String),
}

/// The worker thread and its request channel.
#[derive(Debug)]
pub struct RenderWorker {
    requests: Option<Sender<FrameSpec>>,
    thread: Option<JoinHandle<()>>,
}

impl RenderWorker {
    /// Starts the worker on `gpu` for `scene`; `report` is called on the
    /// worker thread for every frame or error.
    pub fn start(
        gpu: scheduler::Gpu,
        options: GpuOptions,
        scene: Arc<PreparedScene>,
        report: impl Fn(WorkerEvent) + Send + Sync + 'static,
    ) -> std::io::Result<RenderWorker> {
        let (requests, receiver) = channel();
        let report = Arc::new(report);
        let options = GpuOptions {
            progress: compile_reports(options.progress.clone(), report.clone()),
            ..options
        };
        let thread = std::thread::Builder::new()
            .name("reyes-view-render".into())
            .spawn(move || run(&gpu, options, &scene, &receiver, &*report))?;
        Ok(RenderWorker {
            requests: Some(requests),
            thread: Some(thread),
        })
    }

    /// Asks for a frame; false when the worker has stopped.
    pub fn request(&self, spec: FrameSpec) -> bool {
        self.requests.as_ref().is_some_and(|r| r.send(spec).is_ok())
    }

    /// Whether the worker thread has ended (after an error).
    pub fn finished(&self) -> bool {
        self.thread.as_ref().is_none_or(JoinHandle::is_finished)
    }
}

impl Drop for RenderWorker {
    fn drop(&mut self) {
        // Closing the channel ends the worker after its current frame. It is
        // not joined: a frame on a CPU adapter can take seconds, and closing
        // the window must not wait for it (the process exit ends it).
        self.requests = None;
        if let Some(thread) = self.thread.take()
            && thread.is_finished()
        {
            let _ = thread.join();
        }
    }
}

/// An observer that passes every event to `caller` (the options' own) and
/// reports the start and end of the driver's compile through `report`.
fn compile_reports(
    caller: Progress,
    report: Arc<impl Fn(WorkerEvent) + Send + Sync + 'static>,
) -> Progress {
    Progress::new(move |event| {
        caller.send(|| event.clone());
        if let ProgressEvent::CompileStarted { adapter } = event {
            report(WorkerEvent::Compile(Some(Compiling {
                label: compile_label(adapter),
                since: Instant::now(),
            })));
        } else if let ProgressEvent::CompileFinished { .. } = event {
            report(WorkerEvent::Compile(None));
        }
    })
}

fn run(
    gpu: &scheduler::Gpu,
    options: GpuOptions,
    scene: &PreparedScene,
    requests: &Receiver<FrameSpec>,
    report: &dyn Fn(WorkerEvent),
) {
    let mut renderer = match GpuRenderer::new(gpu, options) {
        Ok(renderer) => renderer,
        Err(error) => return report(WorkerEvent::Failed(describe(&error))),
    };
    let mut shadow_maps = ShadowCache::default();
    while let Ok(mut spec) = requests.recv() {
        // Only the newest view matters.
        while let Ok(newer) = requests.try_recv() {
            spec = newer;
        }
        let mut frame_scene = scene_for(scene, &spec);
        let start = std::time::Instant::now();
        let depth_pass = |pass: &PreparedScene| {
            let rendered = renderer.render(pass)?;
            Ok::<_, crate::gpu::RenderError>(crate::depth::depths(&rendered.linear))
        };
        let shadows = match shadow_maps.apply(&mut frame_scene, &spec.settings, depth_pass) {
            Ok(shadows) => shadows,
            Err(error) => {
                report(WorkerEvent::Failed(describe(&error)));
                return;
            }
        };
        match renderer.render(&frame_scene) {
            Ok(rendered) => report(WorkerEvent::Frame(Box::new(Frame {
                shadows,
                spec,
                image: rendered.image,
                linear: rendered.linear,
                stats: rendered.stats,
                gpu_ms: rendered.timings.megakernel_gpu_ms,
                wall_ms: start.elapsed().as_secs_f64() * 1e3,
            }))),
            Err(error) => {
                report(WorkerEvent::Failed(describe(&error)));
                return;
            }
        }
    }
}

/// An error's message followed by the causes it does not already include.
pub fn describe(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let cause_text = cause.to_string();
        if !text.contains(&cause_text) {
            text.push_str(": ");
            text.push_str(&cause_text);
        }
        source = cause.source();
    }
    text
}

/// `base` with the view's camera and settings: the frame the worker
/// renders for `spec`. A preview uses 1 spp; everything else is the same,
/// so a preview differs from the refined frame only in sampling.
pub fn scene_for(base: &PreparedScene, spec: &FrameSpec) -> PreparedScene {
    let s = &spec.settings;
    let mut scene = base.clone();
    scene.camera = spec.camera;
    // The lens scale follows the resolution; the focus follows the orbit
    // (the scene's own focus distance when the orbit has not moved it).
    let focus = if base.camera.eye == spec.camera.eye && base.camera.target == spec.camera.target {
        base.lens.focus
    } else {
        spec.camera.eye.distance(spec.camera.target)
    };
    scene.lens = PreparedLens::new(&spec.camera, s.aperture, Some(focus));
    scene.spp = match spec.quality {
        Quality::Preview => 1,
        Quality::Full => s.spp,
    };
    scene.sampling = s.sampling;
    scene.aov = s.aov;
    // The same rule as the scene's preparation, from the view's settings.
    scene.dicing = DicingRule::new(s.dicing, s.shading_rate, s.dice_threshold);
    if !s.motion_blur {
        for object in &mut scene.objects {
            object.motion = None;
        }
    }
    if !s.shadows {
        scene = scene.without_shadows();
    }
    scene
}

/// The settings `scene` was prepared with.
pub fn settings_of(scene: &PreparedScene) -> Settings {
    Settings {
        spp: scene.spp,
        sampling: scene.sampling,
        dicing: scene.dicing.mode(),
        shading_rate: scene.dicing.shading_rate(),
        dice_threshold: scene.dicing.fixed_threshold(),
        motion_blur: true,
        aperture: scene.lens.aperture,
        aov: scene.aov,
        shadows: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn the_compile_is_reported_and_every_event_passed_on() {
        use std::sync::Mutex;

        use crate::progress::AdapterSummary;

        let passed = Arc::new(Mutex::new(Vec::new()));
        let sink = passed.clone();
        let caller = Progress::new(move |e| sink.lock().unwrap().push(e.clone()));
        let reported = Arc::new(Mutex::new(Vec::new()));
        let sink = reported.clone();
        let progress = compile_reports(
            caller,
            Arc::new(move |e: WorkerEvent| match e {
                WorkerEvent::Compile(c) => sink.lock().unwrap().push(c.map(|c| c.label)),
                other => panic!("unexpected {other:?}"),
            }),
        );
        let adapter = AdapterSummary::of(&wgpu::AdapterInfo {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            ..wgpu::AdapterInfo::new(
                wgpu::DeviceType::Cpu,
                wgpu::Backend::Vulkan,
            )
        });
        let events = [
            ProgressEvent::FrameStarted {
                width: 8,
                height: 6,
                spp: 1,
            },
            ProgressEvent::CompileStarted {
                adapter: adapter.clone(),
            },
            ProgressEvent::CompileFinished {
                adapter,
                elapsed: std::time::Duration::from_secs(3),
            },
        ];
        for event in &events {
            progress.send(|| event.clone());
        }
        assert_eq!(*passed.lock().unwrap(), events);
        assert_eq!(
            *reported.lock().unwrap(),
            [
                Some("compiling the GPU program for llvmpipe (cached after the first run)".into()),
                None
            ]
        );
    }

    #[test]
    fn the_scene_settings_round_trip_through_a_full_frame() {
        let base = PreparedScene::load(&Scene::default_teapot()).unwrap();
        let spec = FrameSpec {
            generation: 0,
            quality: Quality::Full,
            camera: base.camera,
            settings: settings_of(&base),
        };
        let scene = scene_for(&base, &spec);
        assert_eq!(scene.camera, base.camera);
        assert_eq!(scene.lens, base.lens);
        assert_eq!(scene.spp, base.spp);
        assert_eq!(scene.dicing, base.dicing);
        let preview = scene_for(
            &base,
            &FrameSpec {
                quality: Quality::Preview,
                ..spec
            },
        );
        assert_eq!(preview.spp, 1);
    }
}
