//! The statistics buffer read back: its words as [`RenderStats`].

use super::abi::stat;
use crate::nonfinite::Source;
use crate::stats::RenderStats;

/// Statistics read back from the GPU, before the frame time is added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GpuCounters {
    /// The words of the statistics buffer.
    pub words: [u32; stat::WORDS as usize],
}

impl GpuCounters {
    /// Parses the read-back bytes.
    pub fn from_bytes(bytes: &[u8]) -> Self {
        let mut words = [0u32; stat::WORDS as usize];
        for (word, chunk) in words.iter_mut().zip(bytes.chunks_exact(4)) {
            *word = u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
        }
        Self { words }
    }

    fn wide(&self, index: u32) -> u64 {
        let i = index as usize;
        u64::from(self.words[i]) | (u64::from(self.words[i + 1]) << 32)
    }

    /// Rasterization loops the driver cut short (a correct run has none).
    pub fn loops_cut(&self) -> u32 {
        self.words[stat::LOOPS_CUT as usize]
    }

    /// The counters as [`RenderStats`] (without a frame time).
    pub fn to_stats(&self) -> RenderStats {
        let w = |i: u32| u64::from(self.words[i as usize]);
        RenderStats {
            input_patches: w(stat::INPUT_PATCHES),
            splits: w(stat::SPLITS),
            culled_patches: w(stat::CULLED),
            depth_guard_drops: w(stat::DEPTH_GUARD_DROPS),
            grids_diced: w(stat::GRIDS_DICED),
            micropolygons: self.wide(stat::MICROPOLYGONS),
            samples_tested: self.wide(stat::SAMPLES_TESTED),
            samples_hit: self.wide(stat::SAMPLES_HIT),
            samples_skipped: self.wide(stat::SAMPLES_SKIPPED),
            largest_micropolygon_px: f32::from_bits(
                self.words[stat::LARGEST_MICROPOLYGON as usize],
            ),
            displacement_bound_exceeded: w(stat::DISPLACEMENT_BOUND_EXCEEDED),
            non_finite_displacement: w(stat::NON_FINITE + Source::Displacement as u32),
            non_finite_transform: w(stat::NON_FINITE + Source::Transform as u32),
            non_finite_camera: w(stat::NON_FINITE + Source::Camera as u32),
            interleave_grids: w(stat::INTERLEAVE_GRIDS),
            grids_by_class: std::array::from_fn(|c| w(stat::GRIDS_BY_CLASS + c as u32)),
            dice_threads: self.wide(stat::DICE_THREADS),
            frame_time_ms: None,
            passes: Vec::new(),
        }
    }
}
