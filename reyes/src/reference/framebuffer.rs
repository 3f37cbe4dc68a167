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
    /// Per sample the bits of the second-nearest depth (the least depth
    /// greater than the nearest's; `u32::MAX` while there is none), kept
    /// only for the midpoint depth filter ([`Framebuffer::keep_second`]);
    /// empty otherwise.
    pub second: Vec<u32>,
}

impl Framebuffer {
    /// A cleared framebuffer.
    pub fn new(width: u32, height: u32, spp: u32) -> Framebuffer {
        Framebuffer {
            width,
            height,
            spp,
            keys: vec![CLEAR_KEY; width as usize * height as usize * spp as usize],
            second: Vec::new(),
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
            second: Vec::new(),
        })
    }

    /// Keeps each sample's second-nearest depth too (cleared), or `None` when
    /// the host cannot allocate them.
    pub fn keep_second(mut self) -> Option<Framebuffer> {
        let mut second = Vec::new();
        second.try_reserve_exact(self.keys.len()).ok()?;
        second.resize(self.keys.len(), u32::MAX);
        self.second = second;
        Some(self)
    }

    /// Index of sample `s` of pixel `(x, y)`.
    pub fn index(&self, x: u32, y: u32, s: u32) -> usize {
        (y as usize * self.width as usize + x as usize) * self.spp as usize + s as usize
    }

    /// Offers a key to a sample: the sample keeps the minimum (nearest depth,
    /// then smaller colour), so the order of offers does not matter.
    /// With the second depths kept, the depth that loses to the nearest
    /// (the old one or this one) is offered to the second layer likewise,
    /// unless the two are equal: whatever the order of the offers, it ends
    /// with the least depth greater than the nearest, and offering a key
    /// again changes nothing (`offer` in `library_raster.wgsl` does the
    /// same with 32-bit atomic minima).
    pub fn offer(&mut self, x: u32, y: u32, s: u32, key: u64) {
        let i = self.index(x, y, s);
        let old = self.keys[i];
        self.keys[i] = old.min(key);
        if !self.second.is_empty() {
            let (old_bits, bits) = ((old >> 32) as u32, (key >> 32) as u32);
            if old_bits != bits {
                self.second[i] = self.second[i].min(old_bits.max(bits));
            }
        }
    }

    /// The keys of pixel `(x, y)`'s samples.
    pub fn pixel(&self, x: u32, y: u32) -> &[u64] {
        let start = self.index(x, y, 0);
        &self.keys[start..start + self.spp as usize]
    }
}

#[cfg(test)]
mod tests {
    use rand::Rng;
    use rand::seq::SliceRandom;

    use super::*;
    use crate::color::pack_key;
    use crate::test_random::fresh_rng;

    #[test]
    fn the_second_depth_is_the_least_beyond_the_nearest_in_any_order() {
        let (seed, mut rng) = fresh_rng("the_second_depth_is_the_least_beyond_the_nearest_in_any_order");
        for round in 0..200 {
            // A few depths, some repeated (a surface offered twice: a
            // batch run again, or two micropolygons meeting at a sample).
            let depths: Vec<f32> = (0..rng.random_range(1..6))
                .map(|_| f32::from(rng.random_range(0u8..5)) / 4.0)
                .collect();
            let mut offers: Vec<u64> = depths
                .iter()
                .map(|&d| pack_key(d, rng.random_range(0..1024)))
                .collect();
            let again = offers[rng.random_range(0..offers.len())];
            offers.push(again);
            offers.shuffle(&mut rng);
            let mut framebuffer = Framebuffer::new(1, 1, 1).keep_second().unwrap();
            for &key in &offers {
                framebuffer.offer(0, 0, 0, key);
            }
            let nearest = depths.iter().copied().fold(f32::INFINITY, f32::min);
            let second = depths
                .iter()
                .copied()
                .filter(|&d| d > nearest)
                .fold(f32::INFINITY, f32::min);
            let what = format!("seed {seed}, round {round}: {depths:?}");
            assert_eq!(crate::color::key_depth(framebuffer.keys[0]), nearest, "{what}");
            let expected = if second.is_finite() {
                second.to_bits()
            } else {
                u32::MAX
            };
            assert_eq!(framebuffer.second[0], expected, "{what}");
        }
    }
}
