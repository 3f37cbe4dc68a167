//! Animation: keys on the camera (`[[animation.camera]]`) and on objects'
//! placements (`[[objects.keys]]`), and the still scene of one frame
//! ([`Scene::frame`]).
//!
//! Frame `n` shows the scene at time `n / fps` seconds. Its shutter opens
//! then and closes `shutter / fps` seconds later: the frame's scene places
//! every animated object and the camera at both instants, as `transform`
//! and `transform_close` (`[camera]` and `[camera_close]`), and the
//! renderer's motion blur moves them between the two as it does any
//! motion (`crate::motion`). The field of view and the lens are those at
//! shutter open, as a still scene's are fixed during its shutter.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::error::{finite, invalid};
use super::keyframes::{Animatable, Interpolation, Key, evaluate};
use super::{CameraPose, Scale, Scene, SceneError, SceneObject};

/// The largest frame rate (frames per second) a scene may give.
pub const MAX_FPS: f32 = 10_000.0;

/// The scene's animation (`[animation]`): its frame rate, the default
/// interpolation of its keys, and the camera's keys.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Animation {
    /// Frames per second, in (0, [`MAX_FPS`]] (default 24): frame `n`
    /// shows time `n / fps`.
    #[serde(default = "default_fps")]
    pub fps: f32,
    /// The interpolation of keys that do not give theirs (default linear).
    #[serde(default)]
    pub interpolation: Interpolation,
    /// The camera's keys (`[[animation.camera]]`), in time order; they need
    /// a `[camera]` table, whose values stand for those no key gives.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub camera: Vec<CameraKey>,
}

impl Default for Animation {
    fn default() -> Self {
        Animation {
            fps: default_fps(),
            interpolation: Interpolation::default(),
            camera: Vec::new(),
        }
    }
}

fn default_fps() -> f32 {
    24.0
}

/// One key of the camera: when (`frame` or `time`) and any of the camera's
/// animated values. A value no key gives stays the `[camera]`'s (or the
/// `[lens]`'s); each value is interpolated over the keys that give it.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraKey {
    /// The key's frame (may be fractional); give `frame` or `time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<f32>,
    /// The key's time in seconds; give `frame` or `time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f32>,
    /// How the values move to the next key (default: `[animation]`'s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolation: Option<Interpolation>,
    /// Eye position.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub eye: Option<Vec3>,
    /// Point looked at.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<Vec3>,
    /// Up direction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub up: Option<Vec3>,
    /// Vertical field of view in degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fov_y_degrees: Option<f32>,
    /// Lens radius (`lens.aperture`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aperture: Option<f32>,
    /// Distance in focus (`lens.focus_distance`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub focus_distance: Option<f32>,
}

/// One key of an object's placement (`[[objects.keys]]`): when and any of
/// `transform`'s translation, rotation and scale. A value no key gives
/// stays the object's `transform`'s.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformKey {
    /// The key's frame (may be fractional); give `frame` or `time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frame: Option<f32>,
    /// The key's time in seconds; give `frame` or `time`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f32>,
    /// How the values move to the next key (default: `[animation]`'s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interpolation: Option<Interpolation>,
    /// Translation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub translate: Option<Vec3>,
    /// Euler angles in degrees about x, then y, then z; interpolated per
    /// angle, so 0 to 360 is a whole turn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotate_degrees: Option<Vec3>,
    /// Scale, uniform or per axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<Scale>,
}

/// What a key of either kind shares: its time and interpolation.
trait Keyed {
    fn frame(&self) -> Option<f32>;
    fn time(&self) -> Option<f32>;
    fn interpolation(&self) -> Option<Interpolation>;
}

macro_rules! keyed {
    ($type:ty) => {
        impl Keyed for $type {
            fn frame(&self) -> Option<f32> {
                self.frame
            }
            fn time(&self) -> Option<f32> {
                self.time
            }
            fn interpolation(&self) -> Option<Interpolation> {
                self.interpolation
            }
        }
    };
}
keyed!(CameraKey);
keyed!(TransformKey);

impl Scene {
    /// Whether the scene is animated: it has an `[animation]` table or an
    /// object with keys.
    pub fn is_animated(&self) -> bool {
        self.animation.is_some() || self.objects.iter().any(|o| !o.keys.is_empty())
    }

    /// The frame rate (the `[animation]`'s, else 24).
    pub fn fps(&self) -> f32 {
        self.animation.as_ref().map_or_else(default_fps, |a| a.fps)
    }

    /// The still scene of frame `number`: every animated value at shutter
    /// open (time `number / fps`) in `[camera]`, `[lens]` and each object's
    /// `transform`, the poses at shutter close (`shutter / fps` later) in
    /// `[camera_close]` and `transform_close`, `shutter` 1 (the motion
    /// given is the motion seen), no keys left, and the sampling seeded
    /// with the frame number ([`Scene::sampling_seed`]). A scene without
    /// animation stays as it is, but for the seed. The frame's scene is
    /// validated: a camera that the keys make unusable at this frame is an
    /// error.
    pub fn frame(&self, number: u32) -> Result<Scene, SceneError> {
        let mut frame = self.clone();
        frame.sampling_seed = number;
        if !self.is_animated() {
            return Ok(frame);
        }
        let fps = self.fps();
        let default = self
            .animation
            .as_ref()
            .map(|a| a.interpolation)
            .unwrap_or_default();
        let open = number as f32 / fps;
        let close = open + self.shutter / fps;
        let moves = self.shutter > 0.0;
        if let Some(animation) = frame.animation.take()
            && !animation.camera.is_empty()
        {
            let keys = &animation.camera;
            let points = |value: fn(&CameraKey) -> Option<Vec3>| track(keys, fps, default, value);
            let (eye, target, up) = (points(|k| k.eye), points(|k| k.target), points(|k| k.up));
            let scalar = |value: fn(&CameraKey) -> Option<f32>| track(keys, fps, default, value);
            let (fov, aperture, focus) = (
                scalar(|k| k.fov_y_degrees),
                scalar(|k| k.aperture),
                scalar(|k| k.focus_distance),
            );
            let camera = frame
                .camera
                .as_mut()
                .ok_or_else(|| invalid("animation.camera", NEEDS_CAMERA))?;
            let at = |track: &Option<Vec<Key<Vec3>>>, time, still| {
                track.as_ref().map_or(still, |t| evaluate(t, time))
            };
            let still = *camera;
            camera.eye = at(&eye, open, still.eye);
            camera.target = at(&target, open, still.target);
            camera.up = at(&up, open, still.up);
            if let Some(fov) = &fov {
                camera.fov_y_degrees = evaluate(fov, open);
            }
            if let Some(aperture) = &aperture {
                frame.lens.aperture = evaluate(aperture, open);
            }
            if let Some(focus) = &focus {
                frame.lens.focus_distance = Some(evaluate(focus, open));
            }
            if moves {
                frame.camera_close = Some(CameraPose {
                    eye: at(&eye, close, still.eye),
                    target: at(&target, close, still.target),
                    up: Some(at(&up, close, still.up)),
                });
            }
        }
        for object in &mut frame.objects {
            let keys = std::mem::take(&mut object.keys);
            if keys.is_empty() {
                continue;
            }
            let translate = track(&keys, fps, default, |k| k.translate);
            let rotate = track(&keys, fps, default, |k| k.rotate_degrees);
            let scale = track(&keys, fps, default, |k| k.scale.map(Scale::to_vec3));
            let still = object.transform;
            let placed = |time| {
                let mut transform = still;
                if let Some(track) = &translate {
                    transform.translate = evaluate(track, time);
                }
                if let Some(track) = &rotate {
                    transform.rotate_degrees = evaluate(track, time);
                }
                if let Some(track) = &scale {
                    transform.scale = Scale::PerAxis(evaluate(track, time));
                }
                transform
            };
            object.transform = placed(open);
            object.transform_close = moves.then(|| placed(close));
        }
        if frame.camera_close.is_some() || frame.objects.iter().any(|o| o.transform_close.is_some())
        {
            frame.shutter = 1.0;
        }
        frame.validate()?;
        Ok(frame)
    }

    /// The animation's own checks ([`Scene::validate`] runs them): `fps`
    /// finite in (0, [`MAX_FPS`]]; each key with exactly one of `frame` and
    /// `time`, finite and in strictly increasing order; every keyed value
    /// finite; camera keys only with a `[camera]`; no `[camera_close]` and
    /// no `transform_close` in an animated scene (the keys make the motion
    /// during the shutter).
    pub(super) fn check_animation(&self) -> Result<(), SceneError> {
        if !self.is_animated() {
            return Ok(());
        }
        // A frame's shutter sees the motion its keys make: a motion of its
        // own on top would need a shutter of its own.
        if self.camera_close.is_some() {
            return Err(invalid("camera_close", NO_CLOSE));
        }
        if let Some(index) = self
            .objects
            .iter()
            .position(|o| o.transform_close.is_some())
        {
            return Err(invalid(
                &format!("objects[{index}].transform_close"),
                NO_CLOSE,
            ));
        }
        let fps = self.fps();
        if let Some(animation) = &self.animation {
            finite("animation.fps", [animation.fps])?;
            if !(animation.fps > 0.0 && animation.fps <= MAX_FPS) {
                return Err(invalid(
                    "animation.fps",
                    &format!("{} frames per second: give (0, {MAX_FPS}]", animation.fps),
                ));
            }
            let keys = &animation.camera;
            if !keys.is_empty() && self.camera.is_none() {
                return Err(invalid("animation.camera", NEEDS_CAMERA));
            }
            check_times("animation.camera", keys, fps)?;
            for (i, key) in keys.iter().enumerate() {
                let field = |name: &str| format!("animation.camera[{i}].{name}");
                for (name, value) in [("eye", key.eye), ("target", key.target), ("up", key.up)] {
                    if let Some(value) = value {
                        finite(&field(name), value.to_array())?;
                    }
                }
                for (name, value) in [
                    ("fov_y_degrees", key.fov_y_degrees),
                    ("aperture", key.aperture),
                    ("focus_distance", key.focus_distance),
                ] {
                    if let Some(value) = value {
                        finite(&field(name), [value])?;
                    }
                }
            }
        }
        for (index, object) in self.objects.iter().enumerate() {
            check_object_keys(index, object, fps)?;
        }
        Ok(())
    }
}

const NO_CLOSE: &str = "an animated scene moves during each frame's shutter by its keys: animate the camera with [[animation.camera]] keys and objects with [[objects.keys]] instead of a pose at shutter close";

const NEEDS_CAMERA: &str = "camera keys need a [camera] table (it gives the values no key animates, and the clipping planes)";

/// Object `index`'s keys: their times and values.
fn check_object_keys(index: usize, object: &SceneObject, fps: f32) -> Result<(), SceneError> {
    let keys = &object.keys;
    if keys.is_empty() {
        return Ok(());
    }
    check_times(&format!("objects[{index}].keys"), keys, fps)?;
    for (i, key) in keys.iter().enumerate() {
        let field = |name: &str| format!("objects[{index}].keys[{i}].{name}");
        if let Some(value) = key.translate {
            finite(&field("translate"), value.to_array())?;
        }
        if let Some(value) = key.rotate_degrees {
            finite(&field("rotate_degrees"), value.to_array())?;
        }
        if let Some(value) = key.scale {
            finite(&field("scale"), value.to_vec3().to_array())?;
        }
    }
    Ok(())
}

/// The keys of `list` (named `list` in messages, e.g. `objects[0].keys`):
/// each with one finite `frame` or `time`, in strictly increasing order.
fn check_times<K: Keyed>(list: &str, keys: &[K], fps: f32) -> Result<(), SceneError> {
    let mut previous: Option<f32> = None;
    for (i, key) in keys.iter().enumerate() {
        let field = format!("{list}[{i}]");
        let time = match (key.frame(), key.time()) {
            (Some(frame), None) => {
                finite(&format!("{field}.frame"), [frame])?;
                frame / fps
            }
            (None, Some(time)) => {
                finite(&format!("{field}.time"), [time])?;
                time
            }
            (Some(_), Some(_)) => {
                return Err(invalid(&field, "give frame or time, not both"));
            }
            (None, None) => {
                return Err(invalid(
                    &field,
                    "a key needs its frame (frame = 12) or its time in seconds (time = 0.5)",
                ));
            }
        };
        if let Some(previous) = previous
            && time <= previous
        {
            return Err(invalid(
                &field,
                &format!(
                    "keys out of order: this key is at {} s ({} frames), not after the key before it at {previous} s; list the keys in time order, one per instant",
                    time,
                    time * fps
                ),
            ));
        }
        previous = Some(time);
    }
    Ok(())
}

/// The track of the value `value` picks from `keys` (those keys that give
/// it), `None` when no key gives it. Validation has checked the times.
fn track<K: Keyed, T: Animatable>(
    keys: &[K],
    fps: f32,
    default: Interpolation,
    value: impl Fn(&K) -> Option<T>,
) -> Option<Vec<Key<T>>> {
    let track: Vec<Key<T>> = keys
        .iter()
        .filter_map(|key| {
            let value = value(key)?;
            let time = key
                .time()
                .unwrap_or_else(|| key.frame().unwrap_or(0.0) / fps);
            Some(Key {
                time,
                value,
                interpolation: key.interpolation().unwrap_or(default),
            })
        })
        .collect();
    (!track.is_empty()).then_some(track)
}
