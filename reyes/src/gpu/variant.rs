//! The variant of the megakernel a frame needs: the switches that select
//! large amounts of code, as WGSL constants, so that the scheduler's
//! specialization ([`scheduler::CompileOptions::specialize`]) compiles only
//! the code the frame can run.
//!
//! Each specialized switch multiplies the modules the driver compiles (and
//! caches) separately, so only those whose code is large are switches here
//! (docs/performance.md, "Specialization"):
//! - time and lens sampling: the five 5D rasterizers and the motion and
//!   lens paths, about half of the module, inlined into each of the three
//!   dice procedures;
//! - displacement: the height sources, the displaced normals and the
//!   displaced border chords;
//! - the depth test ([`DepthTest`]): the nearest key as one 64-bit atomic,
//!   the same in two 32-bit words over two passes on devices without
//!   64-bit atomics, or the nearest and second-nearest depths, which only
//!   the midpoint depth filter reads
//!   ([`crate::depth::DepthFilter::Midpoint`]); each is no constant but a
//!   choice of the depth test's file, of the framebuffer's type and of the
//!   resources (`reyes::gpu::graph::reyes_graph_with`);
//! - shadow maps, which only frames with a shadowed light or a user
//!   shader's `ShadowId` look up: no constant either but a choice of
//!   library, the lookup (`shaders/reyes/library_shadow.wgsl`, and the
//!   user shaders' `host_shadow`) or stubs that let all light through.
//!
//! The sampling mode, the dicer and the AOV stay run-time switches in the
//! frame uniform: their code is small, and a frame's mode can change (as in
//! the viewer) without a new module. The WGSL tests the constants
//! (`VARIANT_*`) in plain `if` conditions without `&&` or `||`, which naga
//! lowers into statements of their own, so they would not fold.

use std::fmt;

use scheduler::ConstantValue;

use crate::prepare::PreparedScene;

/// How the megakernel keeps the nearest surface of each sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DepthTest {
    /// One 64-bit key per sample, `depth bits << 32 | colour`, kept by
    /// `atomicMin` (`shaders/reyes/offer.wgsl`). Needs
    /// [`super::graph::WIDE_ATOMICS`].
    #[default]
    Key64,
    /// The same key as two 32-bit words, for devices without 64-bit
    /// atomics (wgpu's GL backend, among others), kept over two runs of the
    /// megakernel (`shaders/reyes/offer_two_pass.wgsl`): the first keeps the
    /// nearest depth, the second the least colour at that depth. The
    /// framebuffer ends as the 64-bit test leaves it, at twice the work;
    /// a frame of the depth output runs the first pass only.
    TwoPass32,
    /// The nearest and the second-nearest depth per sample, in two 32-bit
    /// words and no colour ([`PreparedScene::keeps_second_depth`]): a frame
    /// of the midpoint depth filter, on any device.
    SecondDepth,
}

impl DepthTest {
    /// Whether the framebuffer holds 32-bit words (two per sample) instead
    /// of 64-bit keys.
    pub fn uses_32_bit_words(self) -> bool {
        self != DepthTest::Key64
    }
}

/// The switches of a frame that select code in the megakernel. Two frames
/// with the same variant (and the same user displacement function) run the
/// same module.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct KernelVariant {
    /// Samples carry a time and a lens position
    /// ([`PreparedScene::samples_time_and_lens`]): the 5D rasterizers.
    pub blurred: bool,
    /// Some object is displaced.
    pub displaced: bool,
    /// How each sample keeps its nearest surface.
    pub depth_test: DepthTest,
    /// Some light has shadow maps
    /// ([`crate::shading::PreparedLight::shadow`]), or a user shader's
    /// `ShadowId` parameter names one
    /// ([`crate::surface_shader::ShaderTable::looks_up_shadow_maps`]): the
    /// shadow lookup.
    pub shadowed: bool,
}

impl KernelVariant {
    /// Every variant, in a fixed order: the frame's switches, then the
    /// depth test, then shadow maps.
    pub const ALL: [Self; 24] = {
        const TESTS: [DepthTest; 3] = [
            DepthTest::Key64,
            DepthTest::SecondDepth,
            DepthTest::TwoPass32,
        ];
        let mut all = [Self::new(false, false, DepthTest::Key64, false); 24];
        let mut index = 0;
        while index < 24 {
            let blurred = index & 2 != 0;
            let displaced = index & 1 != 0;
            let depth_test = TESTS[(index / 4) % 3];
            let shadowed = index >= 12;
            all[index] = Self::new(blurred, displaced, depth_test, shadowed);
            index += 1;
        }
        all
    };

    const fn new(blurred: bool, displaced: bool, depth_test: DepthTest, shadowed: bool) -> Self {
        Self {
            blurred,
            displaced,
            depth_test,
            shadowed,
        }
    }

    /// The variant `scene` needs.
    pub fn of(scene: &PreparedScene) -> Self {
        Self {
            blurred: scene.samples_time_and_lens(),
            displaced: scene.objects.iter().any(|o| o.displacement.is_some()),
            depth_test: if scene.keeps_second_depth() {
                DepthTest::SecondDepth
            } else {
                DepthTest::Key64
            },
            shadowed: scene.lights.iter().any(|l| {
                l.shadow
                    .is_some_and(|s| !s.maps(&scene.shadow_maps).is_empty())
            }) || scene.shaders.looks_up_shadow_maps(&scene.shadow_maps),
        }
    }

    /// This variant on a device without 64-bit atomics (or where the
    /// renderer is asked for the 32-bit test,
    /// [`super::GpuOptions::two_pass_depth_test`]): the 64-bit key becomes
    /// [`DepthTest::TwoPass32`]; the other tests need no 64-bit atomics.
    pub fn with_32_bit_atomics(self) -> Self {
        Self {
            depth_test: match self.depth_test {
                DepthTest::Key64 => DepthTest::TwoPass32,
                other => other,
            },
            ..self
        }
    }

    /// The device features the variant's module needs:
    /// [`super::graph::WIDE_ATOMICS`] where its framebuffer holds 64-bit
    /// keys ([`DepthTest::Key64`]), none otherwise.
    pub fn features(self) -> wgpu::Features {
        if self.depth_test.uses_32_bit_words() {
            wgpu::Features::empty()
        } else {
            super::graph::WIDE_ATOMICS
        }
    }

    /// The WGSL constants that state this variant, declared as graph
    /// constants.
    /// (`depth_test` and `shadowed` are no constants: they choose
    /// files of the module, its resources and the framebuffer's type,
    /// `reyes::gpu::graph::reyes_graph_with`.)
    pub fn constants(self) -> [(&'static str, ConstantValue); 2] {
        [
            ("VARIANT_BLURRED", self.blurred.into()),
            ("VARIANT_DISPLACED", self.displaced.into()),
        ]
    }

    /// A stable 64-bit hash of the variant (FNV-1a of its name), the same
    /// on every machine and build.
    pub fn stable_hash(self) -> u64 {
        scheduler::pipeline_cache::fnv1a_64(self.to_string().as_bytes())
    }
}

impl fmt::Display for KernelVariant {
    /// A short name: `still`, `blurred`, `still-displaced` or
    /// `blurred-displaced`, followed by `-second-depth` where it keeps the
    /// second-nearest depths or `-two-pass` where it keeps the nearest key in
    /// two 32-bit words, then `-shadowed` where it looks up shadow maps.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.blurred { "blurred" } else { "still" })?;
        if self.displaced {
            f.write_str("-displaced")?;
        }
        match self.depth_test {
            DepthTest::Key64 => {}
            DepthTest::SecondDepth => f.write_str("-second-depth")?,
            DepthTest::TwoPass32 => f.write_str("-two-pass")?,
        }
        if self.shadowed {
            f.write_str("-shadowed")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_hashes_are_stable() {
        let names: Vec<String> = KernelVariant::ALL.iter().map(|v| v.to_string()).collect();
        assert_eq!(
            names,
            [
                "still",
                "still-displaced",
                "blurred",
                "blurred-displaced",
                "still-second-depth",
                "still-displaced-second-depth",
                "blurred-second-depth",
                "blurred-displaced-second-depth",
                "still-two-pass",
                "still-displaced-two-pass",
                "blurred-two-pass",
                "blurred-displaced-two-pass",
                "still-shadowed",
                "still-displaced-shadowed",
                "blurred-shadowed",
                "blurred-displaced-shadowed",
                "still-second-depth-shadowed",
                "still-displaced-second-depth-shadowed",
                "blurred-second-depth-shadowed",
                "blurred-displaced-second-depth-shadowed",
                "still-two-pass-shadowed",
                "still-displaced-two-pass-shadowed",
                "blurred-two-pass-shadowed",
                "blurred-displaced-two-pass-shadowed"
            ]
        );
        // FNV-1a of "still", computed independently, fixed here so that a
        // change of the name or of the hash shows up.
        assert_eq!(
            KernelVariant::default().stable_hash(),
            0x3327_dbad_6c7e_a411
        );
    }
}
