//! The sample framebuffer: one 64-bit key per sample (see [`crate::color`]).

use crate::color::CLEAR_KEY;

/// `width * height * spp` sample keys, sample `s` of pixel `(x, y)` at index
/// `(y * width + x) * spp + s`, cleared to [`CLEAR_KEY`].
#[derive(Debug, Clone, PartialEq)]
pub struct Framebuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// The keys.
    pub keys: Vec<u64>,
}

impl Framebuffer {
    /// A cleared framebuffer.
    pub fn new(width: u32, height: u32, spp: u32) -> Framebuffer {
        Framebuffer {
            width,
            height,
            spp,
            keys: vec![CLEAR_KEY; width as usize * height as usize * spp as usize],
        }
    }

    /// A cleared framebuffer, or `None` when the host cannot allocate its
    /// keys (instead of aborting the process).
    pub fn try_new(width: u32, height: u32, spp: u32) -> Option<Framebuffer> {
        let len = (width as usize)
            .checked_mul(height as usize)?
            .checked_mul(spp as usize)?;
        let mut keys = Vec::new();
        keys.try_reserve_exact(len).ok()?;
        keys.resize(len, CLEAR_KEY);
        Some(Framebuffer {
            width,
            height,
            spp,
            keys,
        })
    }

    /// Index of sample `s` of pixel `(x, y)`.
    pub fn index(&self, x: u32, y: u32, s: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * self.spp as usize + s as usize
    }

    /// Offers a key to a sample: the sample keeps the minimum (nearest depth,
    /// then smaller colour), so the order of offers does not matter.
    pub fn offer(&mut self, x: u32, y: u32, s: u32, key: u64) {
        let i = self.index(x, y, s);
        self.keys[i] = self.keys[i].min(key);
    }

    /// The keys of pixel `(x, y)`'s samples.
    pub fn pixel(&self, x: u32, y: u32) -> &[u64] {
        let start = self.index(x, y, 0);
        &self.keys[start..start + self.spp as usize]
    }
}
