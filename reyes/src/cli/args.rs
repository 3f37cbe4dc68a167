//! The arguments of `reyes render` (and of `reyes view`, which flattens
//! them in): the scene, the frame's overrides, the outputs and the limits.

use std::path::PathBuf;

use glam::Vec3;

use super::frames::{FrameSelection, parse_frames};
use super::parse::{parse_bytes, parse_pan, parse_vec3};
use crate::aov::Aov;
use crate::depth::DepthFilter;
use crate::modes::{Dicing, Sampling, ShadingInterpolation};

/// The arguments of `reyes render`, which `reyes view` shares.
#[derive(Debug, clap::Args)]
pub(crate) struct RenderArgs {
    /// A scene file (.toml) or a bare model (.bpt/.bez patches, or an .obj
    /// mesh subdivided as Catmull-Clark; framed automatically with a default
    /// light). Default: the embedded teapot.
    pub(crate) scene: Option<PathBuf>,
    /// Output image; the extension chooses the format: `.png` (8-bit sRGB,
    /// with the scene's exposure and quantization) or `.exr` (OpenEXR, the
    /// resolve's float linear RGBA as it is), case-insensitive. Missing
    /// directories are created. Checked before rendering, written through a
    /// temporary file renamed over it, so a failure leaves no partial file.
    /// Default: a RIB scene's `Display` file (relative to the current
    /// directory; each frame's own), else `reyes.png`. For several frames
    /// of a RIB file, a run of `#`s in the file name takes the frame
    /// number, zero-padded to as many digits (`out.####.png`: out.0001.png,
    /// out.0002.png...); a name without `#`s holds one frame only.
    #[arg(short, long)]
    pub(crate) output: Option<PathBuf>,
    /// The frames of a RIB file to render (its `FrameBegin n` blocks, in
    /// the file's order): a number, an inclusive range `N..M` or a list
    /// `1,3..5`. Default: every frame. A number the file lacks is an
    /// error that lists the file's frames.
    #[arg(long, value_name = "N|N..M|LIST", value_parser = parse_frames)]
    pub(crate) frame: Option<FrameSelection>,
    /// Render the later frames of a RIB file after a frame or a request
    /// between frames (`MakeShadow`) fails (by default a failure stops the
    /// file). The exit status is non-zero when anything failed, and the
    /// last message lists it.
    #[arg(long)]
    pub(crate) keep_going: bool,
    /// Image width in pixels (default: the scene's, 800).
    #[arg(long)]
    pub(crate) width: Option<u32>,
    /// Image height in pixels (default: the scene's, 600).
    #[arg(long)]
    pub(crate) height: Option<u32>,
    /// Samples per pixel: a perfect square k * k, k = 1 to 16 (1, 4, 9, ...,
    /// 225, 256; default: the scene's, 4).
    #[arg(long)]
    pub(crate) spp: Option<u32>,
    /// Sampling mode (default: the scene's, bbox).
    #[arg(long, value_enum)]
    pub(crate) sampling: Option<Sampling>,
    /// Side, in pixels, of Interleave UVT's tiles: 2, 3 or 4 (default: the
    /// scene's, 2). Interleave UVT and Adaptive use it.
    #[arg(long, value_name = "K", value_parser = clap::value_parser!(u32).range(2..=4))]
    pub(crate) interleave_tile: Option<u32>,
    /// Number of permutations of a tile's pixels Interleave UVT chooses
    /// from, 1 to 256 (default: the scene's, 64). Tile (tx, ty) takes
    /// permutation (ty * W + tx + tx + ty) mod P, W tiles a row
    /// (Sattlecker and Steinberger); 1 repeats one pattern in every tile.
    #[arg(
        long,
        value_name = "P",
        value_parser = clap::value_parser!(u32)
            .range(1..=i64::from(crate::uvt::MAX_INTERLEAVE_PERMUTATIONS))
    )]
    pub(crate) interleave_permutations: Option<u32>,
    /// How pieces are diced (default: the scene's, rate).
    #[arg(long, value_enum)]
    pub(crate) dicing: Option<Dicing>,
    /// Target micropolygon area in pixels for rate dicing (default: the
    /// scene's, 1).
    #[arg(long, value_name = "R")]
    pub(crate) shading_rate: Option<f32>,
    /// How colour varies over a micropolygon (default: the scene's, smooth).
    #[arg(long, value_enum)]
    pub(crate) shading_interpolation: Option<ShadingInterpolation>,
    /// One colour per micropolygon, the mean of its corners' (the same as
    /// `--shading-interpolation constant`).
    #[arg(long, conflicts_with = "shading_interpolation")]
    pub(crate) flat_shading: bool,
    /// What the image shows: the shaded surface, each micropolygon coloured
    /// by its grid's size (checkered), the view depth or the shading normal;
    /// or `z`, the camera-space depth per pixel as floats (+inf where no
    /// surface is), written only as a single-channel EXR (`-o depth.exr`).
    #[arg(long, value_enum)]
    pub(crate) aov: Option<Aov>,
    /// How `--aov z` makes a pixel's depth from its samples' (RenderMan's
    /// `Hider "hidden" "depthfilter"`; default: the scene's, min).
    #[arg(long, value_enum)]
    pub(crate) depth_filter: Option<DepthFilter>,
    /// 1: draw only the front of every object (RenderMan's `Sides 1`;
    /// default: the scene's, 2).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub(crate) sides: Option<u8>,
    /// The front of every object is the other side (RenderMan's
    /// `ReverseOrientation`).
    #[arg(long)]
    pub(crate) reverse_orientation: bool,
    /// Print the statistics table (one per frame, each headed by its frame).
    #[arg(long)]
    pub(crate) stats: bool,
    /// Draw no progress line and print no notice about the adapter (the
    /// line is drawn only when stderr is a terminal); errors, warnings and
    /// the `wrote` line stay.
    #[arg(short, long)]
    pub(crate) quiet: bool,
    /// Write the statistics as JSON to FILE (any name but the image's;
    /// missing directories are created, as for `-o`). The image and FILE
    /// are replaced together, or neither is. For several frames, a run of
    /// `#`s in the name takes the frame number, as for `-o` (one file per
    /// frame).
    #[arg(long, value_name = "FILE")]
    pub(crate) stats_json: Option<PathBuf>,
    /// Trace the GPU megakernel and write the Chrome trace (Trace Event
    /// Format, for Perfetto or chrome://tracing) of the frame's last run to
    /// FILE (docs/scheduler.md, "Seeing a run"); for several frames, a run
    /// of `#`s in the name takes the frame number, as for `-o`.
    #[arg(long, value_name = "FILE")]
    pub(crate) trace: Option<PathBuf>,
    /// Camera position, e.g. `4,-12,7`. A camera framed automatically (a
    /// bare model, the teapot, a scene without `[camera]`) gets near and
    /// far planes around the scene as seen from here.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) eye: Option<Vec3>,
    /// Point the camera looks at.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) target: Option<Vec3>,
    /// Camera up direction.
    #[arg(long, value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[arg(long)]
    pub(crate) fov: Option<f32>,
    /// Near clipping plane: the distance from the eye (along the view
    /// direction) of the nearest surface drawn, in (0, far). Replaces the
    /// scene's and the automatic framing's.
    #[arg(long)]
    pub(crate) near: Option<f32>,
    /// Far clipping plane: the distance from the eye of the farthest
    /// surface drawn, beyond near. Replaces the scene's and the automatic
    /// framing's.
    #[arg(long)]
    pub(crate) far: Option<f32>,
    /// Render with the CPU reference instead of the GPU. It refuses frames
    /// whose RGBA image exceeds 128 MiB (as the GPU does) or whose sample
    /// framebuffer exceeds 2 GiB, and stops after 2^26 work items, 2^30
    /// micropolygons or the --timeout.
    #[arg(long)]
    pub(crate) cpu: bool,
    /// Displace every object: `bumps` (the embedded height map), `sines`
    /// (built-in procedural bumps), a grey PNG height map, or a `.wgsl` file
    /// defining `fn displacement_user(u: f32, v: f32) -> f32` (GPU only;
    /// needs --displace-bound). Replaces any displacement of the scene.
    #[arg(long, value_name = "SOURCE", requires = "displace_scale")]
    pub(crate) displace: Option<std::ffi::OsString>,
    /// World units of displacement per unit of height (negative: inwards).
    #[arg(
        long,
        value_name = "S",
        requires = "displace",
        allow_hyphen_values = true
    )]
    pub(crate) displace_scale: Option<f32>,
    /// Displacement bound in world units (default: |scale| * max height).
    #[arg(
        long,
        value_name = "B",
        requires = "displace",
        allow_hyphen_values = true
    )]
    pub(crate) displace_bound: Option<f32>,
    /// Repetitions of the displacement source per patch (default 1).
    #[arg(long, value_name = "T", requires = "displace")]
    pub(crate) displace_tiling: Option<f32>,
    /// Longest a frame may take, in seconds (default 600), on the GPU or
    /// with --cpu. On the GPU it includes the driver's first compile of the
    /// megakernel, which takes longer than a minute on lavapipe when its
    /// shader cache is cold (e.g. for a new `--displace FILE.wgsl` function).
    #[arg(long, value_name = "SECONDS", value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) timeout: Option<u64>,
    /// Chunks per batch of the megakernel, 1 to 64: how many workgroup-fulls
    /// of items one batch claims (default 4 on CPU adapters, else 1). The
    /// image is the same for any value. On lavapipe at most 4: its compile
    /// of the megakernel grows with the count (96 s at 2 chunks on a cold
    /// shader cache, 324 s at 8). GPU only: refused with `--cpu`.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(scheduler::MAX_CHUNKS_PER_BATCH)))]
    pub(crate) chunks: Option<u32>,
    /// Motion blur: spin every object by DEG degrees about its vertical
    /// (model z) axis between shutter open and close.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub(crate) spin: Option<f32>,
    /// Motion blur: move every object by this world-space vector between
    /// shutter open and close, e.g. `0.5,0,0`.
    #[arg(long = "move", value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) move_by: Option<Vec3>,
    /// Motion blur from camera motion: move the eye and the target by this
    /// world-space vector between shutter open and close, e.g. `0.2,0,0`.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, allow_hyphen_values = true)]
    pub(crate) camera_move: Option<Vec3>,
    /// Motion blur from camera motion: pan the camera by DEG degrees about
    /// its up axis through the eye between shutter open and close (positive
    /// turns left, so the scene sweeps right), in (-180, 180); combines with
    /// `--camera-move`.
    #[arg(long, value_name = "DEG", value_parser = parse_pan, allow_hyphen_values = true)]
    pub(crate) camera_pan: Option<f32>,
    /// Fraction of the open-to-close motion the shutter sees, in [0, 1]
    /// (default: the scene's, 1).
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub(crate) shutter: Option<f32>,
    /// Depth of field: lens radius in world units (default: the scene's, 0).
    #[arg(long, value_name = "R", allow_hyphen_values = true)]
    pub(crate) aperture: Option<f32>,
    /// Depth of field: distance in focus (default: the scene's, or the
    /// distance from the eye to the camera target).
    #[arg(long, value_name = "D", allow_hyphen_values = true)]
    pub(crate) focus: Option<f32>,
    /// Largest input file read, in bytes, for every kind of input: models,
    /// scenes, .wgsl functions and height-map PNGs (suffixes K, M, G, T:
    /// KiB, MiB, GiB, TiB). Default: 1G for models, 16M for scenes and
    /// .wgsl files, 64M for height maps. Only regular files are read.
    #[arg(long, value_name = "BYTES", value_parser = parse_bytes)]
    pub(crate) max_input_bytes: Option<u64>,
    /// Most bicubic patches the scene may make, in all (default 1048576 =
    /// 2^20, 192 MiB of control points; see docs/reyes.md, "Patch
    /// budget"). RIB quadrics, polygons and patch meshes and model files
    /// are counted before their patches are made; a scene past it is
    /// refused, naming the RIB request and line or the object and model.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub(crate) max_patches: Option<u64>,
    /// Read a RIB scene whose block structure is unbalanced or truncated (a
    /// missing `WorldEnd`, an unclosed `AttributeBegin`, an `AttributeEnd`
    /// without its begin) with warnings instead of an error, and render
    /// what was read. A shader's missing texture file is a warning too:
    /// the object keeps its colour with the default surface, or is not
    /// displaced; so is a light's missing shadow map: the light lights
    /// unshadowed.
    #[arg(long)]
    pub(crate) lenient: bool,
    /// Neither read nor write compiled pipelines in the cache directory
    /// (`$REYES_CACHE_DIR`, else the platform's, e.g.
    /// `~/.cache/reyes/pipelines`; see `reyes cache info`).
    #[arg(long)]
    pub(crate) no_pipeline_cache: bool,
}

impl RenderArgs {
    /// Refuses the options the chosen renderer would ignore: the command
    /// line must not look as if it changed what it did not.
    pub(crate) fn check_backend(&self) -> Result<(), String> {
        if self.cpu && self.chunks.is_some() {
            return Err(
                "--chunks applies to the GPU renderer; --cpu ignores it (leave one out)".into(),
            );
        }
        Ok(())
    }
}

/// Sets the process's patch budget from `--max-patches`, if given.
pub(crate) fn set_patch_budget(max_patches: Option<u64>) {
    if let Some(patches) = max_patches {
        crate::budget::set_max_patches(patches);
    }
}
