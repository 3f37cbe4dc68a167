//! Scene descriptions in TOML.
//!
//! A scene names the models to render, where they are, how they are lit and
//! seen, and how finely the pipeline samples them. Every field except an
//! object's `model` has a default, so the smallest scene is
//!
//! ```toml
//! [[objects]]
//! model = "teapot"
//! ```
//!
//! (with no `[camera]` table the camera is framed automatically around the
//! objects when the scene is prepared; see [`crate::prepare::PreparedScene`]).
//!
//! A full example with every field (the values shown for optional fields are
//! the defaults, except where a comment says otherwise):
//!
//! ```toml
//! spp = 4                            # samples per pixel: k * k for k = 1 to 16 (1, 4, 9, ..., 256)
//! sampling = "bbox"                  # "bbox", "simple", "interleave", "interval", "adaptive" or "nearest"
//! interleave_tile = 2                # Interleave UVT's tile side in pixels: 2, 3 or 4
//! interleave_permutations = 64       # permutations of a tile's pixels Interleave UVT picks from: 1 to 256
//! jitter = false                     # jitter samples within their strata
//! pixel_filter = { filter = "gaussian", xwidth = 2.0, ywidth = 2.0 }  # box, triangle, gaussian, catmull-rom or sinc
//! exposure = { gain = 1.0, gamma = 1.0 }  # the 8-bit image's (c * gain)^(1/gamma); not the EXR's
//! quantize = { one = 255.0, min = 0.0, max = 255.0, dither = 0.5 }  # the 8-bit codes; not the EXR's
//! shutter = 1.0                      # fraction of the open-to-close motion the shutter sees
//! background = [0.05, 0.05, 0.07]    # linear RGB
//! ambient = 0.1                      # an ambient light of this intensity (white)
//! dicing = "rate"                   # "rate" (to the shading rate) or "fixed" (16 x 16 points)
//! aov = "shaded"                     # what the image shows: "shaded", "grids", "depth", "normal", or "z" (depth data, .exr only)
//! depth_filter = "min"               # the "z" output's depth per pixel from its samples' (RenderMan's depthfilter)
//! shading_rate = 1.0                 # target micropolygon area in pixels (rate dicing)
//! shading_interpolation = "smooth"   # "smooth" (blend corner colours) or "constant" (one per micropolygon)
//! dice_threshold = 16.0              # fixed dicing: dice when the projected patch fits in this many pixels
//! max_split_depth = 24               # drop patches that still need a split at this depth
//!
//! [resolution]
//! width = 800
//! height = 600
//!
//! [camera]                           # optional: framed automatically when absent
//! eye = [4.0, -12.0, 7.0]            # required in a [camera] table
//! target = [0.2, 0.0, 1.5]           # required in a [camera] table
//! up = [0.0, 0.0, 1.0]
//! fov_y_degrees = 40.0
//! near = 0.1
//! far = 1000.0
//!
//! [camera_close]                     # optional: the camera at shutter close (camera motion)
//! eye = [4.5, -12.0, 7.0]            # required in a [camera_close] table
//! target = [0.7, 0.0, 1.5]           # required in a [camera_close] table
//! up = [0.0, 0.0, 1.0]               # default: the [camera]'s up
//!
//! [lens]                             # depth of field (default: a pinhole)
//! aperture = 0.0                     # lens radius in world units
//! focus_distance = 12.5              # default: the distance from eye to target
//!
//! [specular]                         # the highlight of objects without a [objects.surface]
//! strength = 0.25                    # their plastic's Ks
//! shininess = 32.0                   # 1 / their plastic's roughness
//!
//! [[objects]]
//! model = "teapot"                   # the embedded teapot, or a .bpt/.bez path
//! color = [0.8, 0.8, 0.8]            # linear RGB colour, RenderMan's Cs
//! sides = 2                          # 1: only the front (dP/du x dP/dv towards the eye) is drawn
//! reverse_orientation = false        # the front is the other side
//! [objects.transform]
//! translate = [0.0, 0.0, 0.0]
//! rotate_degrees = [0.0, 0.0, 0.0]   # about x, then y, then z
//! scale = 1.0                        # uniform, or per axis: [1.0, 1.0, 2.0]
//! [objects.displacement]             # optional: no displacement when absent
//! source = "bumps"                   # "bumps", "sines", "wgsl" or a grey PNG path
//! scale = 0.05                       # required: world units per unit of height
//! bound = 0.05                       # default: |scale| * the source's max height
//! tiling = 1.0                       # repetitions of the source per patch
//! [objects.transform_close]          # optional: the placement at shutter close (motion blur)
//! rotate_degrees = [0.0, 0.0, 30.0]  # (not the default: the default is `transform`)
//! [objects.surface]                  # optional: plastic with Ka 1, Kd 1 and [specular]'s Ks and roughness
//! shader = "plastic"                 # "constant", "matte", "metal", "plastic", "defaultsurface" or "null"
//! Ka = 1.0                           # RenderMan's parameters and defaults (docs/reyes.md, "Surfaces")
//! Kd = 0.5
//! Ks = 0.5
//! roughness = 0.1
//! specularcolor = [1.0, 1.0, 1.0]
//!
//! [[objects]]
//! model = "models/killeroo.bpt"      # relative to the scene file's directory
//! color = [0.3, 0.5, 0.8]            # (not the default)
//! transform = { translate = [6.0, 0.0, 0.0], scale = 0.5 }
//!
//! [[lights]]                         # without any [[lights]]: one default light like this
//! direction = [0.4, 0.8, -1.0]       # the direction the light travels
//! color = [1.0, 1.0, 1.0]
//! intensity = 1.0
//!
//! [[lights]]                         # a point light: `position` instead of `direction`
//! position = [0.0, 3.0, 4.0]         # falls off as intensity / distance^2
//! intensity = 20.0
//!
//! [[lights]]                         # a spotlight (RenderMan's spotlight)
//! kind = "spot"                      # "distant", "point", "spot" or "ambient"
//! position = [0.0, -6.0, 6.0]
//! direction = [0.0, 1.0, -1.0]       # the axis of its cone
//! cone_angle_degrees = 30.0          # no light beyond this angle from the axis
//! cone_delta_degrees = 5.0           # fading out over this angle inside the edge
//! beam_distribution = 2.0            # falls off as cos^beam_distribution from the axis
//! intensity = 40.0                   # and as intensity / distance^2
//!
//! [[lights]]                         # an ambient light, added to `ambient`
//! kind = "ambient"
//! color = [0.2, 0.2, 0.3]
//! intensity = 0.5
//! ```
//!
//! Parse with [`Scene::from_toml_str`] or [`Scene::load`]; both validate the
//! values (see [`Scene::validate`]) and report [`SceneError`].
//!
//! The module is cut along its responsibilities: the types as written
//! (`description`, `camera_desc`, `object`, `light`, with their defaults in
//! `defaults`), `error`, `validation`, automatic camera `framing`, and TOML
//! `parse`-ing. Every public item is re-exported here.

mod animation;
mod camera_desc;
mod defaults;
mod description;
mod error;
mod framing;
mod keyframes;
mod light;
mod lines;
mod object;
mod parse;
mod surface;
mod validation;

#[cfg(test)]
mod animation_tests;
#[cfg(test)]
mod tests;

pub use crate::camera::Projection;
pub use crate::modes::{Dicing, Sampling, ShadingInterpolation};
pub use animation::{Animation, CameraKey, MAX_FPS, TransformKey};
pub use camera_desc::{CameraDesc, CameraPose, Lens};
pub use description::{Resolution, Scene, TEAPOT_MODEL};
pub use error::{SceneError, format_point};
pub(crate) use framing::framed_bounds;
pub use framing::{FramingError, MIN_FRAMED_DEPTH};
pub use keyframes::{Animatable, Interpolation, Key, evaluate};
pub use light::{
    DEFAULT_BEAM_DISTRIBUTION, DEFAULT_CONE_ANGLE_DEGREES, DEFAULT_CONE_DELTA_DEGREES,
    DEFAULT_SHADOW_MAP_SIZE, Light, LightKind, LightShadow, MAX_SHADOW_MAP_SIZE, ShadowMaps,
    Specular,
};
pub use lines::SourceLines;
pub use object::{ModelSource, Scale, SceneObject, Subdivision, Transform, is_obj_model};
pub use surface::{ShaderValue, Surface};

/// The warning for a scene without objects, which renders as its
/// background: `reyes render`, `view` and `convert` print it, and
/// [`crate::rib::RibScene`] carries it among its warnings.
pub const NO_OBJECTS_WARNING: &str = "the scene has no objects: the image is the background";
