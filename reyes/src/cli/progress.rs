//! The command line's progress on stderr: one line, redrawn in place by a
//! ticker thread while the renderer works (the main thread waits inside
//! the driver while it compiles the megakernel), and the notice that the
//! frame runs on a software adapter.
//!
//! The line is drawn only on a terminal and without `--quiet`; it is
//! written as `\r<text>` padded with spaces over the last one and ends with
//! `\r`, so that a log line printed meanwhile starts at the left edge, and
//! it is blanked when the frame ends. It is written again only when its
//! text changes (at least every second while something goes on, as the
//! seconds count). No ANSI escape is used.

use std::io::Write;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use crate::output::console::{ConsoleError, errln};
use crate::progress::{AdapterSummary, Progress, ProgressEvent, compile_label, elapsed_label};

/// How often the ticker redraws the line.
const TICK: Duration = Duration::from_millis(250);

/// The longest line drawn, in characters: it must not wrap on an
/// 80-column terminal, where `\r` would return to its last row only.
const MAX_LINE: usize = 79;

/// The notice for a frame on `adapter`, `None` on a hardware adapter.
pub(crate) fn software_notice(adapter: &AdapterSummary) -> Option<String> {
    adapter.software.then(|| {
        format!(
            "note: no GPU found: rendering on {}, a CPU driver; `--cpu` renders the same picture faster here",
            adapter.short_name()
        )
    })
}

/// Prints [`software_notice`] on stderr, once per process.
pub(crate) fn print_software_notice(adapter: &AdapterSummary) -> Result<(), ConsoleError> {
    static PRINTED: AtomicBool = AtomicBool::new(false);
    match software_notice(adapter) {
        Some(notice) if !PRINTED.swap(true, Ordering::Relaxed) => errln!("{notice}"),
        _ => Ok(()),
    }
}

/// What the line says: the frame's label, or the compile's while the
/// driver compiles, each with the time since it started.
#[derive(Debug, Default)]
struct Status {
    /// The frame's size and where it is (tile, batch), and its start.
    frame: Option<(String, Instant)>,
    /// The tile and batch of a frame that has several.
    place: String,
    /// The compile's label and start.
    compile: Option<(String, Instant)>,
}

impl Status {
    /// Follows `event`, which happened at `now`.
    fn follow(&mut self, event: &ProgressEvent, now: Instant) {
        match event {
            ProgressEvent::FrameStarted { width, height, spp } => {
                self.frame = Some((format!("rendering {width}x{height} at {spp} spp"), now));
                self.place.clear();
            }
            ProgressEvent::CompileStarted { adapter } => {
                self.compile = Some((compile_label(adapter), now));
            }
            ProgressEvent::CompileFinished { .. } => self.compile = None,
            ProgressEvent::TileStarted { tile, tiles } => {
                self.place = format!(", tile {tile}/{tiles}");
            }
            ProgressEvent::BatchFinished { batch, batches } => {
                let tile = self.place.split(", batch").next().unwrap_or_default();
                self.place = format!("{tile}, batch {batch}/{batches} done");
            }
            ProgressEvent::FrameFinished { .. } => *self = Status::default(),
        }
    }

    /// The line at `now`, `None` when nothing is going on.
    fn line(&self, now: Instant) -> Option<String> {
        let (label, place, since) = match (&self.compile, &self.frame) {
            (Some((label, since)), _) => (label, "", since),
            (None, Some((label, since))) => (label, self.place.as_str(), since),
            (None, None) => return None,
        };
        let elapsed = elapsed_label(now.saturating_duration_since(*since));
        let suffix = format!(" … {elapsed}");
        let mut text: String = format!("{label}{place}");
        let room = MAX_LINE.saturating_sub(suffix.chars().count());
        if text.chars().count() > room {
            text = text.chars().take(room.saturating_sub(1)).collect();
            text.push('…');
        }
        text.push_str(&suffix);
        Some(text)
    }
}

/// The line on a writer: what is drawn, and how to draw over it.
#[derive(Debug)]
struct Line<W: Write> {
    out: W,
    status: Status,
    /// The text on screen (empty: none).
    drawn: String,
}

impl<W: Write> Line<W> {
    fn new(out: W) -> Self {
        Self {
            out,
            status: Status::default(),
            drawn: String::new(),
        }
    }

    /// Draws the line at `now` over the last one, or blanks it when nothing
    /// is going on. A failed write is ignored: progress is no output.
    fn draw(&mut self, now: Instant) {
        let text = self.status.line(now).unwrap_or_default();
        if text == self.drawn {
            return;
        }
        let pad = self
            .drawn
            .chars()
            .count()
            .saturating_sub(text.chars().count());
        let _ = write!(self.out, "\r{text}{:pad$}\r", "");
        let _ = self.out.flush();
        self.drawn = text;
    }

    /// Blanks the line.
    fn clear(&mut self) {
        if !self.drawn.is_empty() {
            let width = self.drawn.chars().count();
            let _ = write!(self.out, "\r{:width$}\r", "");
            let _ = self.out.flush();
            self.drawn.clear();
        }
    }
}

/// The line and whether the ticker should stop, and the clock both the
/// ticker and the observer read.
struct Shared<W: Write> {
    state: Mutex<(Line<W>, bool)>,
    wake: Condvar,
    clock: Box<dyn Fn() -> Instant + Send + Sync>,
}

impl<W: Write> std::fmt::Debug for Shared<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Shared").finish_non_exhaustive()
    }
}

/// The ticker thread that redraws the line every [`TICK`], and the
/// [`Progress`] observer that feeds it. Dropping it stops the thread and
/// blanks the line.
#[derive(Debug)]
pub(crate) struct Ticker<W: Write + Send + 'static> {
    shared: Arc<Shared<W>>,
    thread: Option<JoinHandle<()>>,
}

impl Ticker<std::io::Stderr> {
    /// A ticker on stderr when stderr is a terminal and `quiet` is false;
    /// `None` otherwise (nothing is drawn then).
    pub(crate) fn on_terminal(quiet: bool) -> Option<Self> {
        use std::io::IsTerminal;
        if quiet || !std::io::stderr().is_terminal() {
            return None;
        }
        // A ticker that cannot start leaves the frame without a line.
        Self::start(std::io::stderr(), TICK, Box::new(Instant::now)).ok()
    }
}

impl<W: Write + Send + 'static> Ticker<W> {
    /// Starts the thread that redraws the line on `out` every `tick`, at
    /// the times `clock` tells.
    fn start(
        out: W,
        tick: Duration,
        clock: Box<dyn Fn() -> Instant + Send + Sync>,
    ) -> std::io::Result<Self> {
        let shared = Arc::new(Shared {
            state: Mutex::new((Line::new(out), false)),
            wake: Condvar::new(),
            clock,
        });
        let thread_shared = shared.clone();
        let thread = std::thread::Builder::new()
            .name("reyes-progress".into())
            .spawn(move || {
                let shared = thread_shared;
                let mut state = shared.state.lock().unwrap_or_else(PoisonError::into_inner);
                while !state.1 {
                    state.0.draw((shared.clock)());
                    state = shared
                        .wake
                        .wait_timeout(state, tick)
                        .unwrap_or_else(PoisonError::into_inner)
                        .0;
                }
                state.0.clear();
            })?;
        Ok(Self {
            shared,
            thread: Some(thread),
        })
    }

    /// The observer that feeds the line; it redraws it at each event.
    pub(crate) fn progress(&self) -> Progress {
        let shared = self.shared.clone();
        Progress::new(move |event| {
            let now = (shared.clock)();
            let mut state = shared.state.lock().unwrap_or_else(PoisonError::into_inner);
            state.0.status.follow(event, now);
            state.0.draw(now);
        })
    }
}

impl<W: Write + Send + 'static> Drop for Ticker<W> {
    fn drop(&mut self) {
        self.shared
            .state
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .1 = true;
        self.shared.wake.notify_all();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer the test reads back.
    #[derive(Clone, Debug, Default)]
    struct Sink(Arc<Mutex<Vec<u8>>>);

    impl Write for Sink {
        fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(bytes);
            Ok(bytes.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Sink {
        fn text(&self) -> String {
            String::from_utf8(self.0.lock().unwrap().clone()).unwrap()
        }
    }

    fn llvmpipe() -> AdapterSummary {
        let mut info = wgpu::AdapterInfo::new(wgpu::DeviceType::Cpu, wgpu::Backend::Vulkan);
        info.name = "llvmpipe (LLVM 15.0.6, 256 bits)".into();
        info.driver = "llvmpipe".into();
        AdapterSummary::of(&info)
    }

    #[test]
    fn the_line_follows_the_frame_and_the_compile() {
        let t0 = Instant::now();
        let at = |ms| t0 + Duration::from_millis(ms);
        let mut status = Status::default();
        assert_eq!(status.line(t0), None);
        let frame = ProgressEvent::FrameStarted {
            width: 800,
            height: 600,
            spp: 4,
        };
        status.follow(&frame, t0);
        assert_eq!(
            status.line(at(1_500)).unwrap(),
            "rendering 800x600 at 4 spp … 1 s"
        );
        status.follow(
            &ProgressEvent::CompileStarted {
                adapter: llvmpipe(),
            },
            at(2_000),
        );
        let compiling = status.line(at(14_000)).unwrap();
        assert_eq!(
            compiling,
            "compiling the GPU program for llvmpipe (cached after the first run) … 12 s"
        );
        assert!(compiling.chars().count() <= MAX_LINE);
        status.follow(
            &ProgressEvent::CompileFinished {
                adapter: llvmpipe(),
                elapsed: Duration::from_secs(12),
            },
            at(14_000),
        );
        status.follow(
            &ProgressEvent::TileStarted { tile: 2, tiles: 4 },
            at(15_000),
        );
        status.follow(
            &ProgressEvent::BatchFinished {
                batch: 1,
                batches: 3,
            },
            at(15_500),
        );
        status.follow(
            &ProgressEvent::BatchFinished {
                batch: 2,
                batches: 3,
            },
            at(15_700),
        );
        assert_eq!(
            status.line(at(16_000)).unwrap(),
            "rendering 800x600 at 4 spp, tile 2/4, batch 2/3 done … 16 s"
        );
        status.follow(
            &ProgressEvent::FrameFinished {
                elapsed: Duration::from_secs(16),
            },
            at(16_000),
        );
        assert_eq!(status.line(at(16_000)), None);
    }

    #[test]
    fn a_long_label_is_cut_to_one_terminal_row() {
        let mut status = Status::default();
        let t0 = Instant::now();
        let mut adapter = llvmpipe();
        adapter.name = "A graphics adapter with a name far longer than any terminal row".into();
        status.follow(&ProgressEvent::CompileStarted { adapter }, t0);
        let line = status.line(t0 + Duration::from_secs(100)).unwrap();
        assert_eq!(line.chars().count(), MAX_LINE, "{line}");
        assert!(line.ends_with("… … 100 s"), "{line}");
    }

    #[test]
    fn lines_are_drawn_over_each_other_and_blanked() {
        let sink = Sink::default();
        let mut line = Line::new(sink.clone());
        let t0 = Instant::now();
        line.draw(t0);
        assert_eq!(sink.text(), "", "nothing going on draws nothing");
        let frame = ProgressEvent::FrameStarted {
            width: 8,
            height: 6,
            spp: 1,
        };
        line.status.follow(&frame, t0);
        line.draw(t0);
        line.draw(t0 + Duration::from_millis(900));
        line.status
            .follow(&ProgressEvent::TileStarted { tile: 1, tiles: 2 }, t0);
        line.draw(t0 + Duration::from_secs(3));
        line.status = Status::default();
        line.status.follow(&frame, t0);
        line.draw(t0 + Duration::from_secs(4));
        line.clear();
        line.clear();
        // The same text (0 s at 900 ms) is not written again.
        let first = "rendering 8x6 at 1 spp … 0 s";
        let second = "rendering 8x6 at 1 spp, tile 1/2 … 3 s";
        let third = "rendering 8x6 at 1 spp … 4 s";
        let pad = " ".repeat(second.chars().count() - third.chars().count());
        let blank = " ".repeat(third.chars().count());
        assert_eq!(
            sink.text(),
            format!("\r{first}\r\r{second}\r\r{third}{pad}\r\r{blank}\r")
        );
    }

    #[test]
    fn the_ticker_redraws_and_leaves_no_partial_line() {
        use std::sync::atomic::{AtomicU64, Ordering};

        // A clock that moves a second at every reading: the text changes at
        // every tick, a millisecond apart.
        let start = Instant::now();
        let seconds = AtomicU64::new(0);
        let clock = move || start + Duration::from_secs(seconds.fetch_add(1, Ordering::Relaxed));
        let sink = Sink::default();
        let ticker =
            Ticker::start(sink.clone(), Duration::from_millis(1), Box::new(clock)).unwrap();
        ticker.progress().send(|| ProgressEvent::FrameStarted {
            width: 8,
            height: 6,
            spp: 1,
        });
        let lines = |text: &str| -> Vec<String> {
            text.split('\r')
                .filter(|s| !s.is_empty())
                .map(str::to_owned)
                .collect()
        };
        // The thread redraws without events.
        let deadline = Instant::now() + Duration::from_secs(5);
        while lines(&sink.text()).len() < 3 && Instant::now() < deadline {
            std::thread::sleep(Duration::from_millis(1));
        }
        drop(ticker);
        let text = sink.text();
        let lines = lines(&text);
        assert!(lines.len() >= 4, "{text:?}");
        assert!(
            lines[0].starts_with("rendering 8x6 at 1 spp … "),
            "{text:?}"
        );
        // The last line blanks the one before it, and ends at its start.
        let (last, blank) = (&lines[lines.len() - 2], &lines[lines.len() - 1]);
        assert!(last.trim_end().ends_with(" s"), "{text:?}");
        assert!(blank.trim().is_empty(), "{text:?}");
        assert_eq!(blank.len(), last.trim_end().chars().count(), "{text:?}");
        assert!(text.ends_with('\r'));
        // Nothing ticks after the ticker is dropped.
        std::thread::sleep(Duration::from_millis(5));
        assert_eq!(sink.text(), text);
    }

    #[test]
    fn the_notice_names_software_adapters_only() {
        let notice = software_notice(&llvmpipe()).unwrap();
        assert!(
            notice.starts_with("note: no GPU found: rendering on llvmpipe, a CPU driver"),
            "{notice}"
        );
        assert!(notice.contains("`--cpu`"));
        let gpu = AdapterSummary::of(&wgpu::AdapterInfo::new(
            wgpu::DeviceType::DiscreteGpu,
            wgpu::Backend::Vulkan,
        ));
        assert_eq!(software_notice(&gpu), None);
    }
}
