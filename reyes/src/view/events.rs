//! Window events to the viewer's [`Input`]s: the only place that knows
//! winit's event types, so [`super::controls`] stays free of them.

use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{Key as WinitKey, NamedKey};

use super::controls::{Button, Input, Key};

/// The input `event` means, if any; `consumed`: the overlay used it (a
/// release still ends a drag).
pub fn input_of(event: &WindowEvent, consumed: bool) -> Option<Input> {
    match *event {
        WindowEvent::CursorMoved { position, .. } => {
            Some(Input::CursorMoved(position.x as f32, position.y as f32))
        }
        WindowEvent::MouseInput { state, button, .. }
            if !consumed || state == ElementState::Released =>
        {
            let button = match button {
                MouseButton::Left => Some(Button::Left),
                MouseButton::Right => Some(Button::Right),
                MouseButton::Middle => Some(Button::Middle),
                _ => None,
            };
            button.map(|b| match state {
                ElementState::Pressed => Input::Pressed(b),
                ElementState::Released => Input::Released(b),
            })
        }
        WindowEvent::MouseWheel { delta, .. } if !consumed => Some(Input::Wheel(match delta {
            MouseScrollDelta::LineDelta(_, y) => y,
            // About 40 pixels to a line, as browsers scroll.
            MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
        })),
        WindowEvent::KeyboardInput { ref event, .. }
            if !consumed && event.state == ElementState::Pressed && !event.repeat =>
        {
            key_of(&event.logical_key).map(Input::Key)
        }
        _ => None,
    }
}

/// The viewer's key for a winit key.
pub fn key_of(key: &WinitKey) -> Option<Key> {
    match key {
        WinitKey::Named(NamedKey::Escape) => Some(Key::Quit),
        WinitKey::Character(text) => Some(match text.to_lowercase().as_str() {
            "f" => Key::Frame,
            "p" => Key::Save,
            "m" => Key::NextSampling,
            "+" | "=" => Key::MoreSpp,
            "-" | "_" => Key::FewerSpp,
            "[" => Key::Finer,
            "]" => Key::Coarser,
            "b" => Key::ToggleMotion,
            "s" => Key::ToggleShadows,
            "a" => Key::WiderAperture,
            "z" => Key::NarrowerAperture,
            "v" => Key::NextAov,
            "h" => Key::ToggleOverlay,
            "q" => Key::Quit,
            _ => return None,
        }),
        _ => None,
    }
}
