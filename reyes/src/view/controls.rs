//! The viewer's input handling as a pure state machine: input events in,
//! camera and render settings out. Nothing here touches a window or the
//! GPU, so the mapping from a drag or a key to the camera is unit-tested
//! directly, and a scripted event goes through exactly the same code as one
//! from the window.

use glam::{Quat, Vec3};

use crate::aov::Aov;
use crate::camera::Camera;
use crate::scene::{Dicing, Sampling};

/// Radians of orbit per pixel of drag.
pub const ORBIT_RADIANS_PER_PIXEL: f32 = 0.01;
/// Distance factor per wheel line towards the target (`< 1`: zoom in).
pub const ZOOM_PER_LINE: f32 = 0.9;
/// The orbit keeps this far (radians) from the up axis, where the view's
/// up vector would become parallel to the view direction.
const POLE_MARGIN: f32 = 0.01;
/// The sample counts the renderer accepts (perfect squares up to 256).
pub const SPP_STEPS: [u32; 16] = crate::params::VALID_SPP;
/// The sampling modes, in the order the `M` key cycles through them.
pub const SAMPLING_MODES: [Sampling; 6] = Sampling::ALL;
/// The AOVs, in the order the `V` key cycles through them.
pub const AOVS: [Aov; 4] = [Aov::Shaded, Aov::Grids, Aov::Depth, Aov::Normal];

/// An orbit camera: an eye and a target, turning about a fixed world up
/// axis. The eye is stored, not derived, so an orbit that has not moved
/// reproduces its camera exactly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The eye position.
    pub eye: Vec3,
    /// The point looked at and orbited about.
    pub target: Vec3,
    /// World up (as the camera gives it); the orbit's yaw axis.
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y_radians: f32,
}

impl Orbit {
    /// The orbit that reproduces `camera`'s pose.
    pub fn from_camera(camera: &Camera) -> Orbit {
        Orbit {
            eye: camera.eye,
            target: camera.target,
            up: camera.up,
            fov_y_radians: camera.fov_y_radians,
        }
    }

    /// Eye-to-target distance.
    pub fn distance(&self) -> f32 {
        self.eye.distance(self.target)
    }

    /// Unit direction from the target to the eye.
    pub fn direction(&self) -> Vec3 {
        (self.eye - self.target).normalize_or(Vec3::Z)
    }

    fn axis(&self) -> Vec3 {
        self.up.normalize_or(Vec3::Z)
    }

    /// The camera's right axis on screen (world space, unit length).
    fn right(&self) -> Vec3 {
        (-self.direction()).cross(self.axis()).normalize_or(Vec3::X)
    }

    /// The camera's up axis on screen (world space, unit length).
    fn screen_up(&self) -> Vec3 {
        self.right()
            .cross(-self.direction())
            .normalize_or(self.axis())
    }

    /// Orbits by `dx, dy` pixels of drag: a drag to the right turns the
    /// eye to the left about the up axis (the scene follows the mouse),
    /// a drag down raises the eye. The elevation stays short of the poles.
    pub fn orbit(&mut self, dx: f32, dy: f32) {
        let axis = self.axis();
        let distance = self.distance();
        let yaw = Quat::from_axis_angle(axis, -dx * ORBIT_RADIANS_PER_PIXEL);
        let mut direction = yaw * self.direction();
        // Elevation measured from the up axis, clamped away from the poles.
        let polar = direction.dot(axis).clamp(-1.0, 1.0).acos();
        let wanted = (polar - dy * ORBIT_RADIANS_PER_PIXEL)
            .clamp(POLE_MARGIN, std::f32::consts::PI - POLE_MARGIN);
        let right = (-direction).cross(axis).normalize_or(Vec3::X);
        direction =
            (Quat::from_axis_angle(right, wanted - polar) * direction).normalize_or(direction);
        self.eye = self.target + direction * distance;
    }

    /// Pans by `dx, dy` pixels in an image `height` pixels tall: the point
    /// on the target's plane under the cursor stays under it.
    pub fn pan(&mut self, dx: f32, dy: f32, height: u32) {
        let world_per_pixel =
            2.0 * self.distance() * (self.fov_y_radians * 0.5).tan() / height.max(1) as f32;
        let by = (-dx * self.right() + dy * self.screen_up()) * world_per_pixel;
        self.target += by;
        self.eye += by;
    }

    /// Zooms by `lines` wheel lines (positive: towards the target).
    pub fn zoom(&mut self, lines: f32) {
        let distance = self.distance();
        let wanted = (distance * ZOOM_PER_LINE.powf(lines)).max(1e-4);
        self.eye = self.target + self.direction() * wanted;
    }

    /// Frames the bounding box `lo..hi` from the current direction: the
    /// target is its centre and its bounding sphere fills the smaller of the
    /// field's two extents.
    pub fn frame(&mut self, lo: Vec3, hi: Vec3, aspect: f32) {
        let radius = (0.5 * (hi - lo).length()).max(1e-4);
        let half_y = self.fov_y_radians * 0.5;
        let half_x = (half_y.tan() * aspect.max(1e-3)).atan();
        let half = half_y.min(half_x);
        let direction = self.direction();
        self.target = 0.5 * (lo + hi);
        self.eye = self.target + direction * (radius / half.sin());
    }

    /// The camera for an image of `width x height` pixels, keeping the
    /// near and far planes of `base`.
    pub fn camera(&self, base: &Camera, width: u32, height: u32) -> Camera {
        Camera::new(
            self.eye,
            self.target,
            self.up,
            self.fov_y_radians,
            width.max(1),
            height.max(1),
            base.near,
            base.far,
        )
    }
}

/// The render settings the viewer can change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Samples per pixel of a refined frame (one of [`SPP_STEPS`]).
    pub spp: u32,
    /// Sampling mode.
    pub sampling: Sampling,
    /// How pieces are diced (fixed for a session: it picks which of the
    /// two next settings applies).
    pub dicing: Dicing,
    /// Target micropolygon area in pixels (rate dicing).
    pub shading_rate: f32,
    /// Dice threshold in pixels (fixed dicing).
    pub dice_threshold: f32,
    /// Whether moving objects blur.
    pub motion_blur: bool,
    /// Lens radius in world units.
    pub aperture: f32,
    /// What the image shows.
    pub aov: Aov,
    /// Whether the lights cast their shadows (automatic or from files).
    pub shadows: bool,
}

/// A mouse button the viewer reacts to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Button {
    /// Orbits.
    Left,
    /// Pans.
    Right,
    /// Pans.
    Middle,
}

/// A key the viewer reacts to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// Frame the scene again.
    Frame,
    /// Save the full-quality frame (PNG, plus the equivalent command line).
    Save,
    /// Next sampling mode.
    NextSampling,
    /// More samples per pixel.
    MoreSpp,
    /// Fewer samples per pixel.
    FewerSpp,
    /// Finer dicing (halve the shading rate or dice threshold).
    Finer,
    /// Coarser dicing (double the shading rate or dice threshold).
    Coarser,
    /// Motion blur on or off.
    ToggleMotion,
    /// Shadows on or off.
    ToggleShadows,
    /// Larger lens.
    WiderAperture,
    /// Smaller lens (down to a pinhole).
    NarrowerAperture,
    /// Next AOV.
    NextAov,
    /// Show or hide the overlay.
    ToggleOverlay,
    /// Close the viewer.
    Quit,
}

/// One input event, in window pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    /// The cursor moved to `(x, y)`.
    CursorMoved(f32, f32),
    /// A button went down at the cursor.
    Pressed(Button),
    /// A button was released.
    Released(Button),
    /// The wheel turned by this many lines (positive: away from the user,
    /// which zooms in).
    Wheel(f32),
    /// A key was pressed.
    Key(Key),
}

/// What an event asks of the viewer besides the state change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Outcome {
    /// The camera moved: render a quick frame now, refine later.
    pub camera_moved: bool,
    /// A render setting changed: the frame must be rendered again.
    pub settings_changed: bool,
    /// Save the frame.
    pub save: bool,
    /// Close the viewer.
    pub quit: bool,
}

/// The viewer's interaction state.
#[derive(Debug, Clone)]
pub struct Controls {
    /// The current camera pose.
    pub orbit: Orbit,
    /// The current render settings.
    pub settings: Settings,
    /// Whether the overlay is drawn.
    pub overlay: bool,
    /// The scene's bounds, for [`Key::Frame`].
    bounds: (Vec3, Vec3),
    cursor: Option<(f32, f32)>,
    dragging: Option<Button>,
    /// Lens radius step for the aperture keys (a fraction of the scene).
    aperture_step: f32,
}

impl Controls {
    /// Controls starting at `orbit` and `settings`, for a scene within
    /// `bounds`.
    pub fn new(orbit: Orbit, settings: Settings, bounds: (Vec3, Vec3)) -> Controls {
        let size = (bounds.1 - bounds.0).length();
        Controls {
            orbit,
            settings,
            overlay: true,
            bounds,
            cursor: None,
            dragging: None,
            aperture_step: if size.is_finite() && size > 0.0 {
                size * 0.005
            } else {
                0.01
            },
        }
    }

    /// Whether a drag is in progress (the camera is moving).
    pub fn dragging(&self) -> bool {
        self.dragging.is_some()
    }

    /// Applies one event; `size` is the window's size in pixels.
    pub fn handle(&mut self, input: Input, size: (u32, u32)) -> Outcome {
        let mut outcome = Outcome::default();
        match input {
            Input::CursorMoved(x, y) => {
                if let (Some(button), Some((px, py))) = (self.dragging, self.cursor) {
                    let (dx, dy) = (x - px, y - py);
                    if dx != 0.0 || dy != 0.0 {
                        match button {
                            Button::Left => self.orbit.orbit(dx, dy),
                            Button::Right | Button::Middle => self.orbit.pan(dx, dy, size.1),
                        }
                        outcome.camera_moved = true;
                    }
                }
                self.cursor = Some((x, y));
            }
            Input::Pressed(button) => self.dragging = Some(button),
            Input::Released(button) => {
                if self.dragging == Some(button) {
                    self.dragging = None;
                }
            }
            Input::Wheel(lines) => {
                if lines != 0.0 && lines.is_finite() {
                    self.orbit.zoom(lines);
                    outcome.camera_moved = true;
                }
            }
            Input::Key(key) => self.key(key, size, &mut outcome),
        }
        outcome
    }

    fn key(&mut self, key: Key, size: (u32, u32), outcome: &mut Outcome) {
        let before = self.settings;
        let s = &mut self.settings;
        match key {
            Key::Frame => {
                let aspect = size.0 as f32 / size.1.max(1) as f32;
                self.orbit.frame(self.bounds.0, self.bounds.1, aspect);
                outcome.camera_moved = true;
            }
            Key::Save => outcome.save = true,
            Key::Quit => outcome.quit = true,
            Key::ToggleOverlay => self.overlay = !self.overlay,
            Key::NextSampling => s.sampling = next(&SAMPLING_MODES, s.sampling),
            Key::NextAov => s.aov = next(&AOVS, s.aov),
            Key::MoreSpp => s.spp = step_spp(s.spp, true),
            Key::FewerSpp => s.spp = step_spp(s.spp, false),
            Key::Finer | Key::Coarser => {
                let factor = if key == Key::Finer { 0.5 } else { 2.0 };
                match s.dicing {
                    Dicing::Rate => s.shading_rate = (s.shading_rate * factor).clamp(0.0625, 64.0),
                    Dicing::Fixed => {
                        s.dice_threshold = (s.dice_threshold * factor).clamp(1.0, 4096.0);
                    }
                }
            }
            Key::ToggleMotion => s.motion_blur = !s.motion_blur,
            Key::ToggleShadows => s.shadows = !s.shadows,
            Key::WiderAperture => s.aperture += self.aperture_step,
            Key::NarrowerAperture => s.aperture = (s.aperture - self.aperture_step).max(0.0),
        }
        outcome.settings_changed = self.settings != before;
    }
}

/// The element after `current` in `all`, wrapping (the first when absent).
fn next<T: Copy + PartialEq>(all: &[T], current: T) -> T {
    let at = all.iter().position(|&x| x == current);
    at.map_or(all[0], |i| all[(i + 1) % all.len()])
}

/// The next larger or smaller sample count of [`SPP_STEPS`].
fn step_spp(spp: u32, up: bool) -> u32 {
    if up {
        SPP_STEPS
            .iter()
            .copied()
            .find(|&s| s > spp)
            .unwrap_or(SPP_STEPS[SPP_STEPS.len() - 1])
    } else {
        SPP_STEPS
            .iter()
            .rev()
            .copied()
            .find(|&s| s < spp)
            .unwrap_or(1)
    }
}

#[cfg(test)]
mod tests;
