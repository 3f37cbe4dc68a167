//! The codes the megakernel and the host agree on: the statistics buffer's
//! words, the non-finite stage bits, the displacement, dicing and sampling
//! modes as the frame uniform and the object table encode them, the Bound
//! decisions and the point flags. Data layouts ([`super::buffers`],
//! [`super::objects`]) and the graph ([`super::graph`]) read them from here;
//! `shared_constants` declares them to the WGSL.

/// Indices into the statistics buffer (`array<atomic<u32>>`). 64-bit
/// counters take two words (low, high).
pub mod stat {
    /// Input patches (Bound items).
    pub const INPUT_PATCHES: u32 = 0;
    /// Split decisions.
    pub const SPLITS: u32 = 1;
    /// Culled pieces.
    pub const CULLED: u32 = 2;
    /// Pieces dropped by the split-depth guard.
    pub const DEPTH_GUARD_DROPS: u32 = 3;
    /// Grids diced.
    pub const GRIDS_DICED: u32 = 4;
    /// Micropolygons (64-bit: words 5, 6).
    pub const MICROPOLYGONS: u32 = 5;
    /// Samples tested (64-bit: words 7, 8).
    pub const SAMPLES_TESTED: u32 = 7;
    /// Samples hit (64-bit: words 9, 10).
    pub const SAMPLES_HIT: u32 = 9;
    /// Bits of the largest micropolygon side in pixels (an f32 >= 0).
    pub const LARGEST_MICROPOLYGON: u32 = 11;
    /// Rasterization loops the driver ended early (must stay 0).
    pub const LOOPS_CUT: u32 = 12;
    /// Displaced grid points that left their object's displacement bound.
    pub const DISPLACEMENT_BOUND_EXCEEDED: u32 = 13;
    /// Grids sampled with Interleave UVT.
    pub const INTERLEAVE_GRIDS: u32 = 14;
    /// Grids diced per class (words 15, 16, 17: small, medium, large).
    pub const GRIDS_BY_CLASS: u32 = 15;
    /// Threads of the dice items (64-bit: words 18, 19).
    pub const DICE_THREADS: u32 = 18;
    /// Grid points whose position turned infinite or NaN, by the stage that
    /// turned it (words 20, 21, 22: [`super::non_finite`]'s displacement,
    /// transform, camera).
    pub const NON_FINITE: u32 = 20;
    /// Samples a box's loop reached and skipped untested (64-bit: words
    /// 23, 24).
    pub const SAMPLES_SKIPPED: u32 = 23;
    /// Words in the buffer.
    pub const WORDS: u32 = 25;
}

/// The stages that can turn a grid point's position non-finite, as bits of
/// the per-point mask of `dice_shade_sample.wgsl`; bit `b` is counted in
/// stats word [`stat::NON_FINITE`] + `b`, as [`crate::nonfinite::Source`]
/// orders them.
pub mod non_finite {
    /// The displacement (height times scale, or the displaced point).
    pub const DISPLACEMENT: u32 = 1 << crate::nonfinite::Source::Displacement as u32;
    /// The object's transform (the patch evaluated at a finite
    /// transform's points near the `f32` limit, or the shutter-close motion).
    pub const TRANSFORM: u32 = 1 << crate::nonfinite::Source::Transform as u32;
    /// The camera (clip or pixel position of a finite world position).
    pub const CAMERA: u32 = 1 << crate::nonfinite::Source::Camera as u32;
}

/// Displacement sources, as [`super::objects::ObjectData::displace_kind`]
/// encodes them.
pub mod displace {
    /// No displacement.
    pub const NONE: u32 = 0;
    /// A height map in the `height_texels` buffer.
    pub const IMAGE: u32 = 1;
    /// The built-in sines.
    pub const SINES: u32 = 2;
    /// A displacement shader (`user_displacement`), also a user's WGSL
    /// height function ([`crate::displacement::height_shader`]).
    pub const SHADER: u32 = 3;
}

/// Surface shaders, as [`super::objects::ObjectData::surface`] encodes
/// them ([`crate::shading::PreparedSurface`]).
pub mod surface {
    use crate::shading::PreparedSurface;

    /// `constant`.
    pub const CONSTANT: u32 = 0;
    /// `matte`.
    pub const MATTE: u32 = 1;
    /// `metal`.
    pub const METAL: u32 = 2;
    /// `plastic`.
    pub const PLASTIC: u32 = 3;
    /// `defaultsurface`.
    pub const DEFAULT_SURFACE: u32 = 4;
    /// A user's WGSL shader.
    pub const USER: u32 = 5;

    /// The code of `surface`.
    pub fn code(surface: &PreparedSurface) -> u32 {
        match surface {
            PreparedSurface::Constant => CONSTANT,
            PreparedSurface::Matte { .. } => MATTE,
            PreparedSurface::Metal { .. } => METAL,
            PreparedSurface::Plastic { .. } => PLASTIC,
            PreparedSurface::DefaultSurface { .. } => DEFAULT_SURFACE,
            PreparedSurface::User { .. } => USER,
        }
    }
}

/// Light kinds, as [`super::buffers::LightData::kind`] encodes them
/// ([`crate::shading::PreparedLightKind`]).
pub mod light {
    use crate::shading::PreparedLightKind;

    /// A distant light.
    pub const DISTANT: u32 = 0;
    /// A point light.
    pub const POINT: u32 = 1;
    /// A spotlight.
    pub const SPOT: u32 = 2;

    /// The code of `kind`.
    pub fn code(kind: PreparedLightKind) -> u32 {
        match kind {
            PreparedLightKind::Distant => DISTANT,
            PreparedLightKind::Point => POINT,
            PreparedLightKind::Spot => SPOT,
        }
    }
}

/// Dicing modes, as the frame uniform encodes them.
pub mod dicing {
    /// [`crate::scene::Dicing::Fixed`].
    pub const FIXED: u32 = 0;
    /// [`crate::scene::Dicing::Rate`].
    pub const RATE: u32 = 1;

    /// The code of `dicing`.
    pub fn code(dicing: crate::scene::Dicing) -> u32 {
        match dicing {
            crate::scene::Dicing::Fixed => FIXED,
            crate::scene::Dicing::Rate => RATE,
        }
    }
}

/// Bound decisions, as the WGSL `decide` returns them.
pub(super) mod decide {
    pub(crate) const CULL: u32 = 0;
    pub(crate) const DICE: u32 = 1;
    pub(crate) const SPLIT_U: u32 = 2;
    pub(crate) const SPLIT_V: u32 = 3;
    pub(crate) const DROP: u32 = 4;
}

/// Sampling modes, as the frame uniform encodes them.
pub mod sampling {
    /// Bounding-box sampling of the two triangles.
    pub const BBOX: u32 = 0;
    /// The sample nearest the micropolygon's centroid.
    pub const NEAREST: u32 = 1;
    /// Simple UVT.
    pub const SIMPLE: u32 = 2;
    /// Interleave UVT.
    pub const INTERLEAVE: u32 = 3;
    /// INTERVAL.
    pub const INTERVAL: u32 = 4;
    /// Adaptive (INTERVAL or Interleave UVT per grid).
    pub const ADAPTIVE: u32 = 5;

    /// The code of `mode`.
    pub fn code(mode: crate::scene::Sampling) -> u32 {
        use crate::scene::Sampling;
        match mode {
            Sampling::Bbox => BBOX,
            Sampling::Nearest => NEAREST,
            Sampling::Simple => SIMPLE,
            Sampling::Interleave => INTERLEAVE,
            Sampling::Interval => INTERVAL,
            Sampling::Adaptive => ADAPTIVE,
        }
    }
}

/// Scratch words per grid point of the dice procedures (see
/// `dice_shade_sample.wgsl`): open px, py, depth, clip w, packed colour,
/// close px, py, depth, clip w. Their items hold `POINT_WORDS *
/// class.max_points()` words: 16 small items take 3,888 words.
pub(super) const POINT_WORDS: u32 = 9;

/// Bits of a point's clip-plane flags (WGSL only: they never leave the GPU).
pub(super) const PLANE_BITS: u32 = 0x3f;
/// The flag of a point behind the near plane.
pub(super) const UNPROJECTABLE: u32 = 0x100;
