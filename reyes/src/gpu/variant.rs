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
//! - the second-nearest depth per sample, which only the midpoint depth
//!   filter reads ([`crate::depth::DepthFilter::Midpoint`]): small, but a
//!   second atomic per sample that every other frame must not pay for; it
//!   is no constant but a choice of the depth test's file and of the
//!   framebuffer's type (`reyes::gpu::graph::reyes_graph_with`);
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
    /// Every sample keeps its second-nearest key too
    /// ([`PreparedScene::keeps_second_depth`]).
    pub second_depth: bool,
    /// Some light has shadow maps
    /// ([`crate::shading::PreparedLight::shadow`]), or a user shader's
    /// `ShadowId` parameter names one
    /// ([`crate::surface_shader::ShaderTable::looks_up_shadow_maps`]): the
    /// shadow lookup.
    pub shadowed: bool,
}

impl KernelVariant {
    /// Every variant, in a fixed order.
    pub const ALL: [Self; 16] = [
        Self::new(false, false, false, false),
        Self::new(false, true, false, false),
        Self::new(true, false, false, false),
        Self::new(true, true, false, false),
        Self::new(false, false, true, false),
        Self::new(false, true, true, false),
        Self::new(true, false, true, false),
        Self::new(true, true, true, false),
        Self::new(false, false, false, true),
        Self::new(false, true, false, true),
        Self::new(true, false, false, true),
        Self::new(true, true, false, true),
        Self::new(false, false, true, true),
        Self::new(false, true, true, true),
        Self::new(true, false, true, true),
        Self::new(true, true, true, true),
    ];

    const fn new(blurred: bool, displaced: bool, second_depth: bool, shadowed: bool) -> Self {
        Self {
            blurred,
            displaced,
            second_depth,
            shadowed,
        }
    }

    /// The variant `scene` needs.
    pub fn of(scene: &PreparedScene) -> Self {
        Self {
            blurred: scene.samples_time_and_lens(),
            displaced: scene.objects.iter().any(|o| o.displacement.is_some()),
            second_depth: scene.keeps_second_depth(),
            shadowed: scene.lights.iter().any(|l| {
                l.shadow
                    .is_some_and(|s| !s.maps(&scene.shadow_maps).is_empty())
            }) || scene.shaders.looks_up_shadow_maps(&scene.shadow_maps),
        }
    }

    /// The WGSL constants that state this variant, declared as graph
    /// constants.
    /// (`second_depth` and `shadowed` are no constants: they choose
    /// files of the module and the framebuffer's type,
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
    /// second-nearest keys, then `-shadowed` where it looks up shadow maps.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.blurred { "blurred" } else { "still" })?;
        if self.displaced {
            f.write_str("-displaced")?;
        }
        if self.second_depth {
            f.write_str("-second-depth")?;
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
                "still-shadowed",
                "still-displaced-shadowed",
                "blurred-shadowed",
                "blurred-displaced-shadowed",
                "still-second-depth-shadowed",
                "still-displaced-second-depth-shadowed",
                "blurred-second-depth-shadowed",
                "blurred-displaced-second-depth-shadowed"
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
