//! The bounds of one reference render: frame size, work and time.
//!
//! The reference is single-threaded and holds the whole sample framebuffer
//! in host memory, so, like the GPU path, it refuses frames and scenes it
//! cannot finish: an RGBA image over [`MAX_IMAGE_BYTES`] (the GPU path's
//! limit too), a sample framebuffer over
//! [`ReferenceOptions::max_framebuffer_bytes`], more work items or
//! micropolygons than [`ReferenceOptions::max_items`] and
//! [`ReferenceOptions::max_micropolygons`], and a frame that takes longer
//! than [`ReferenceOptions::timeout`]. Each refusal is a
//! [`super::ReferenceError`] that names the bound and how to raise it.

use std::time::{Duration, Instant};

use super::ReferenceError;
use crate::params::DEFAULT_RENDER_TIMEOUT;
pub use crate::prepare::MAX_IMAGE_BYTES;
use crate::stats::RenderStats;

/// Default [`ReferenceOptions::max_framebuffer_bytes`]: 2 GiB, 2^28 samples
/// of 8 bytes (e.g. 4096 x 4096 at 16 spp, 1920 x 1080 at 64 spp, or 1024 x
/// 1024 at 256 spp).
pub const DEFAULT_MAX_FRAMEBUFFER_BYTES: u64 = 2 << 30;

/// Default [`ReferenceOptions::max_items`]: 2^26 (about 67 million) work
/// items, input patches and split pieces together. The default teapot at
/// 800 x 600 takes about 3,000; the 11,532-patch Killeroo about 11,600.
/// Splitting without end (a surface through the eye with
/// `max_split_depth = 64`) ran at about 120,000 items a second in a debug
/// build (2-core VM), about 9 minutes to this bound; the default timeout
/// (600 s) bounds the time either way.
pub const DEFAULT_MAX_ITEMS: u64 = 1 << 26;

/// Default [`ReferenceOptions::max_micropolygons`]: 2^30 (about a billion)
/// micropolygons diced. The default teapot at 800 x 600 dices about 234,000,
/// the Killeroo with fixed dicing about 2.6 million.
pub const DEFAULT_MAX_MICROPOLYGONS: u64 = 1 << 30;

/// How often (in work items) the render reads the clock.
const CLOCK_EVERY_ITEMS: u64 = 64;

/// How often (in sample tests) the rasterization of one grid reads the clock.
const CLOCK_EVERY_SAMPLES: u64 = 1 << 20;

/// The bounds of a reference render ([`super::try_render_with`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReferenceOptions {
    /// Longest the frame may take (`None`: no limit). Default
    /// [`DEFAULT_RENDER_TIMEOUT`], the GPU path's. A timeout too large
    /// to add to the clock (e.g. `u64::MAX` seconds) means no limit.
    pub timeout: Option<Duration>,
    /// Largest RGBA image, in bytes (default [`MAX_IMAGE_BYTES`]).
    pub max_image_bytes: u64,
    /// Largest sample framebuffer (8 bytes per sample), in bytes (default
    /// `DEFAULT_MAX_FRAMEBUFFER_BYTES`).
    pub max_framebuffer_bytes: u64,
    /// Most work items (input patches and split pieces) processed (default
    /// `DEFAULT_MAX_ITEMS`).
    pub max_items: u64,
    /// Most micropolygons diced (default `DEFAULT_MAX_MICROPOLYGONS`).
    pub max_micropolygons: u64,
    /// Rasterize a still frame's bbox-sampled micropolygons as two
    /// triangles with a box each, over whole pixels
    /// (`super::raster::raster_triangle`), as the renderer did before
    /// its quad boxes (default `false`): the same image, with more sample
    /// tests. For measuring what the quad boxes save (`reyes-bench ste`).
    pub triangle_boxes: bool,
}

impl Default for ReferenceOptions {
    fn default() -> Self {
        ReferenceOptions {
            timeout: Some(DEFAULT_RENDER_TIMEOUT),
            max_image_bytes: MAX_IMAGE_BYTES,
            max_framebuffer_bytes: DEFAULT_MAX_FRAMEBUFFER_BYTES,
            max_items: DEFAULT_MAX_ITEMS,
            max_micropolygons: DEFAULT_MAX_MICROPOLYGONS,
            triangle_boxes: false,
        }
    }
}

impl ReferenceOptions {
    /// No bound on work or time; the image and framebuffer limits stay
    /// (what [`super::render`] uses).
    pub fn unbounded_work() -> ReferenceOptions {
        ReferenceOptions {
            timeout: None,
            max_items: u64::MAX,
            max_micropolygons: u64::MAX,
            ..ReferenceOptions::default()
        }
    }

    /// Checks the frame size: the RGBA image and the sample framebuffer.
    pub fn check_frame(&self, width: u32, height: u32, spp: u32) -> Result<(), ReferenceError> {
        let pixels = u64::from(width) * u64::from(height);
        let image = pixels.saturating_mul(4);
        if image > self.max_image_bytes {
            return Err(ReferenceError::ImageTooLarge {
                width,
                height,
                needed: image,
                limit: self.max_image_bytes,
            });
        }
        let framebuffer = pixels.saturating_mul(u64::from(spp)).saturating_mul(8);
        if framebuffer > self.max_framebuffer_bytes {
            return Err(ReferenceError::FramebufferTooLarge {
                width,
                height,
                spp,
                needed: framebuffer,
                limit: self.max_framebuffer_bytes,
            });
        }
        Ok(())
    }
}

/// The running account of one render against its options.
#[derive(Debug)]
pub(crate) struct Budget {
    start: Instant,
    timeout: Option<Duration>,
    deadline: Option<Instant>,
    max_items: u64,
    max_micropolygons: u64,
    items: u64,
    next_clock_samples: u64,
}

impl Budget {
    /// Starts the clock now.
    pub(crate) fn new(options: &ReferenceOptions) -> Budget {
        let start = Instant::now();
        Budget {
            start,
            timeout: options.timeout,
            // Checked: a timeout past the clock's range is no limit.
            deadline: options.timeout.and_then(|t| start.checked_add(t)),
            max_items: options.max_items,
            max_micropolygons: options.max_micropolygons,
            items: 0,
            next_clock_samples: CLOCK_EVERY_SAMPLES,
        }
    }

    /// Accounts one work item (popped from the stack), reading the clock
    /// every [`CLOCK_EVERY_ITEMS`].
    pub(crate) fn item(&mut self) -> Result<(), ReferenceError> {
        self.items += 1;
        if self.items > self.max_items {
            return Err(ReferenceError::WorkLimit {
                what: "work items (input patches and split pieces)",
                limit: self.max_items,
                field: "max_items",
            });
        }
        if self.items.is_multiple_of(CLOCK_EVERY_ITEMS) {
            self.clock()?;
        }
        Ok(())
    }

    /// Accounts a grid of `quads` micropolygons about to be diced.
    pub(crate) fn grid(&self, stats: &RenderStats, quads: u32) -> Result<(), ReferenceError> {
        if stats.micropolygons.saturating_add(u64::from(quads)) > self.max_micropolygons {
            return Err(ReferenceError::WorkLimit {
                what: "micropolygons",
                limit: self.max_micropolygons,
                field: "max_micropolygons",
            });
        }
        Ok(())
    }

    /// Reads the clock when rasterization has tested another
    /// [`CLOCK_EVERY_SAMPLES`] samples (one grid may test many).
    pub(crate) fn samples(&mut self, stats: &RenderStats) -> Result<(), ReferenceError> {
        if stats.samples_tested >= self.next_clock_samples {
            self.next_clock_samples = stats.samples_tested.saturating_add(CLOCK_EVERY_SAMPLES);
            self.clock()?;
        }
        Ok(())
    }

    /// Fails past the deadline.
    pub(crate) fn clock(&self) -> Result<(), ReferenceError> {
        match (self.deadline, self.timeout) {
            (Some(deadline), Some(timeout)) if Instant::now() >= deadline => {
                Err(ReferenceError::Timeout {
                    timeout,
                    items: self.items,
                    elapsed: self.start.elapsed(),
                })
            }
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_timeout_beyond_the_clock_is_no_limit() {
        let budget = Budget::new(&ReferenceOptions {
            timeout: Some(Duration::from_secs(u64::MAX)),
            ..ReferenceOptions::default()
        });
        assert_eq!(budget.deadline, None);
        budget.clock().unwrap();
    }

    #[test]
    fn a_zero_timeout_expires() {
        let budget = Budget::new(&ReferenceOptions {
            timeout: Some(Duration::ZERO),
            ..ReferenceOptions::default()
        });
        assert!(matches!(
            budget.clock(),
            Err(ReferenceError::Timeout { .. })
        ));
    }

    #[test]
    fn frame_checks_do_not_overflow() {
        let options = ReferenceOptions::default();
        assert!(matches!(
            options.check_frame(u32::MAX, u32::MAX, 64),
            Err(ReferenceError::ImageTooLarge { .. })
        ));
        let huge = ReferenceOptions {
            max_image_bytes: u64::MAX,
            ..ReferenceOptions::default()
        };
        assert!(matches!(
            huge.check_frame(u32::MAX, u32::MAX, 64),
            Err(ReferenceError::FramebufferTooLarge { .. })
        ));
        options.check_frame(800, 600, 64).unwrap();
    }
}
