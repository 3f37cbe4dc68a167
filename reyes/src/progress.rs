//! What the GPU renderer is doing while a caller waits: the events of a
//! frame ([`ProgressEvent`]) and the observer that receives them
//! ([`Progress`], a field of [`GpuOptions`](crate::gpu::GpuOptions)).
//!
//! On a software adapter the driver's compile of the megakernel takes
//! seconds when its shader cache holds the module and minutes when it does
//! not; the events let a front end say so while it happens (the `reyes`
//! command line draws a line on a terminal, the viewer its overlay). Without
//! an observer ([`Progress::none`], the default) nothing is built or sent.
//!
//! ```
//! use reyes::progress::{Progress, ProgressEvent};
//!
//! let progress = Progress::new(|event: &ProgressEvent| eprintln!("{event:?}"));
//! let options = reyes::GpuOptions { progress, ..Default::default() };
//! # let _ = options;
//! ```

use std::sync::Arc;
use std::time::Duration;

/// The adapter a frame runs on, as the events name it.
#[derive(Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub struct AdapterSummary {
    /// The adapter's name (`llvmpipe (LLVM 15.0.6, 256 bits)` on lavapipe).
    pub name: String,
    /// Whether it is a software adapter: a driver that runs shaders on the
    /// CPU (see [`is_software`]).
    pub software: bool,
}

impl AdapterSummary {
    /// The summary of the adapter `info` describes.
    pub fn of(info: &wgpu::AdapterInfo) -> Self {
        Self {
            name: info.name.clone(),
            software: is_software(info),
        }
    }

    /// The name up to its first parenthesis (`llvmpipe` for
    /// `llvmpipe (LLVM 15.0.6, 256 bits)`), for a short line.
    pub fn short_name(&self) -> &str {
        let short = self.name.split(" (").next().unwrap_or_default().trim();
        if short.is_empty() { &self.name } else { short }
    }
}

/// Whether the adapter `info` describes runs shaders on the CPU: wgpu's
/// [`wgpu::DeviceType::Cpu`] (lavapipe, WARP, SwiftShader), or llvmpipe as
/// [`scheduler::Quirks`] recognizes it where the backend reports another
/// type (GL).
pub fn is_software(info: &wgpu::AdapterInfo) -> bool {
    info.device_type == wgpu::DeviceType::Cpu
        || scheduler::Quirks::of(info).cpu_workgroups.is_some()
}

/// What a front end says while the driver compiles the GPU program for
/// `adapter` (the elapsed time follows it): `compiling the GPU program for
/// llvmpipe (cached after the first run)`. The first compile of a
/// configuration takes minutes on a software adapter, later ones seconds
/// (the driver's shader cache holds the module).
pub fn compile_label(adapter: &AdapterSummary) -> String {
    format!(
        "compiling the GPU program for {} (cached after the first run)",
        adapter.short_name()
    )
}

/// An elapsed time as the progress lines show it: whole seconds, `12 s`.
pub fn elapsed_label(elapsed: Duration) -> String {
    format!("{} s", elapsed.as_secs())
}

/// One step of a frame on the GPU, in the order a frame sends them:
/// [`FrameStarted`](Self::FrameStarted); the compile of the megakernel
/// ([`CompileStarted`](Self::CompileStarted) and
/// [`CompileFinished`](Self::CompileFinished)) when the frame needs a
/// pipeline the renderer has not created yet (its first frame, a new
/// displacement function or queue sizing); per screen tile and batch of
/// input patches when the frame has several; and
/// [`FrameFinished`](Self::FrameFinished) when the frame succeeded.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ProgressEvent {
    /// A frame started.
    FrameStarted {
        /// Its width in pixels.
        width: u32,
        /// Its height in pixels.
        height: u32,
        /// Its samples per pixel.
        spp: u32,
    },
    /// The GPU program (the megakernel's pipeline) is being created; the
    /// driver compiles it now.
    CompileStarted {
        /// The adapter whose driver compiles it.
        adapter: AdapterSummary,
    },
    /// The GPU program was created.
    CompileFinished {
        /// The adapter whose driver compiled it.
        adapter: AdapterSummary,
        /// How long the creation took.
        elapsed: Duration,
    },
    /// A screen tile of a frame rendered in several started.
    TileStarted {
        /// Its number, from 1.
        tile: u32,
        /// The frame's tiles.
        tiles: u32,
    },
    /// A batch of input patches of a tile run in several batches is done.
    BatchFinished {
        /// Its number within the tile, from 1.
        batch: u32,
        /// The tile's batches.
        batches: u32,
    },
    /// The frame is rendered.
    FrameFinished {
        /// How long the frame took, compile included.
        elapsed: Duration,
    },
}

/// The observer of a renderer's [`ProgressEvent`]s: a function called on
/// the rendering thread, in order, for each event. It should return
/// quickly (the frame waits for it). Cloning shares the function.
#[derive(Clone, Default)]
pub struct Progress(Option<Arc<Observe>>);

/// The function behind a [`Progress`].
type Observe = dyn Fn(&ProgressEvent) + Send + Sync;

impl Progress {
    /// An observer that calls `observe` for each event.
    pub fn new(observe: impl Fn(&ProgressEvent) + Send + Sync + 'static) -> Self {
        Self(Some(Arc::new(observe)))
    }

    /// No observer: events are neither built nor sent (the default).
    pub fn none() -> Self {
        Self(None)
    }

    /// Whether an observer is set.
    pub fn is_observed(&self) -> bool {
        self.0.is_some()
    }

    /// Sends the event `event` builds, which is built only when an observer
    /// is set.
    pub fn send(&self, event: impl FnOnce() -> ProgressEvent) {
        if let Some(observe) = &self.0 {
            observe(&event());
        }
    }
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.is_observed() {
            "Progress(observed)"
        } else {
            "Progress(none)"
        })
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use super::*;

    fn info(name: &str, driver: &str, device_type: wgpu::DeviceType) -> wgpu::AdapterInfo {
        wgpu::AdapterInfo {
            name: name.into(),
            driver: driver.into(),
            ..wgpu::AdapterInfo::new(device_type, wgpu::Backend::Vulkan)
        }
    }

    #[test]
    fn software_adapters_are_cpu_devices_or_llvmpipe() {
        let lavapipe = info(
            "llvmpipe (LLVM 15.0.6, 256 bits)",
            "llvmpipe",
            wgpu::DeviceType::Cpu,
        );
        assert!(is_software(&lavapipe));
        assert_eq!(AdapterSummary::of(&lavapipe).short_name(), "llvmpipe");
        let gl = info("llvmpipe (LLVM 15)", "", wgpu::DeviceType::Other);
        assert!(is_software(&gl));
        let warp = info("Microsoft Basic Render Driver", "", wgpu::DeviceType::Cpu);
        assert!(is_software(&warp));
        let gpu = info("NVIDIA H200", "NVIDIA", wgpu::DeviceType::DiscreteGpu);
        assert!(!is_software(&gpu));
        assert_eq!(AdapterSummary::of(&gpu).short_name(), "NVIDIA H200");
        assert_eq!(
            compile_label(&AdapterSummary::of(&lavapipe)),
            "compiling the GPU program for llvmpipe (cached after the first run)"
        );
        assert_eq!(elapsed_label(Duration::from_millis(12_999)), "12 s");
    }

    #[test]
    fn no_observer_builds_no_event() {
        let built = Mutex::new(0);
        let none = Progress::default();
        none.send(|| {
            *built.lock().unwrap() += 1;
            ProgressEvent::FrameFinished {
                elapsed: Duration::ZERO,
            }
        });
        assert_eq!(*built.lock().unwrap(), 0);
        assert_eq!(format!("{none:?}"), "Progress(none)");
        let seen = Arc::new(Mutex::new(Vec::new()));
        let sink = seen.clone();
        let observed = Progress::new(move |e| sink.lock().unwrap().push(e.clone()));
        let event = ProgressEvent::TileStarted { tile: 1, tiles: 2 };
        observed.clone().send(|| event.clone());
        assert_eq!(*seen.lock().unwrap(), [event]);
        assert_eq!(format!("{observed:?}"), "Progress(observed)");
    }
}
