//! Scripted input for tests and demos (`reyes view --script`): a list of
//! steps, separated by `;` or new lines, that the event loop feeds to the
//! same [`Controls`](super::controls::Controls) as the window's events.
//!
//! ```text
//! wait                      until the view is refined
//! move X,Y                  the cursor to (X, Y) window pixels
//! press left|right|middle   a button at the cursor
//! release left|right|middle
//! drag BUTTON X0,Y0 X1,Y1   move, press, move, release
//! wheel LINES               turn the wheel (positive zooms in)
//! resize W,H                ask the window system for this inner size
//! key NAME                  frame, save, sampling, spp+, spp-, finer,
//!                           coarser, motion, aperture+, aperture-, aov,
//!                           overlay, quit
//! ```

use super::controls::{Button, Input, Key};
use super::error::ViewError;

/// One step of a script.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// Wait until the current view has been refined and presented.
    Wait,
    /// Feed this input.
    Input(Input),
    /// Ask for this window size (the window system answers with a resize).
    Resize(u32, u32),
}

/// Parses a script.
pub fn parse(text: &str) -> Result<Vec<Step>, ViewError> {
    let mut steps = Vec::new();
    for command in text
        .split([';', '\n'])
        .map(str::trim)
        .filter(|c| !c.is_empty())
    {
        let words: Vec<&str> = command.split_whitespace().collect();
        let bad = || ViewError::Script(format!("cannot read {command:?}"));
        match words.as_slice() {
            ["wait"] => steps.push(Step::Wait),
            ["move", at] => {
                let (x, y) = point(at).ok_or_else(bad)?;
                steps.push(Step::Input(Input::CursorMoved(x, y)));
            }
            ["press", b] => steps.push(Step::Input(Input::Pressed(button(b).ok_or_else(bad)?))),
            ["release", b] => {
                steps.push(Step::Input(Input::Released(button(b).ok_or_else(bad)?)));
            }
            ["drag", b, from, to] => {
                let b = button(b).ok_or_else(bad)?;
                let (x0, y0) = point(from).ok_or_else(bad)?;
                let (x1, y1) = point(to).ok_or_else(bad)?;
                steps.extend(
                    [
                        Input::CursorMoved(x0, y0),
                        Input::Pressed(b),
                        Input::CursorMoved(x1, y1),
                        Input::Released(b),
                    ]
                    .map(Step::Input),
                );
            }
            ["resize", size] => {
                let (w, h) = point(size).ok_or_else(bad)?;
                if !(1.0..=16384.0).contains(&w) || !(1.0..=16384.0).contains(&h) {
                    return Err(bad());
                }
                steps.push(Step::Resize(w as u32, h as u32));
            }
            ["wheel", lines] => {
                let lines: f32 = lines
                    .parse()
                    .ok()
                    .filter(|l: &f32| l.is_finite())
                    .ok_or_else(bad)?;
                steps.push(Step::Input(Input::Wheel(lines)));
            }
            ["key", name] => steps.push(Step::Input(Input::Key(key(name).ok_or_else(bad)?))),
            _ => return Err(bad()),
        }
    }
    Ok(steps)
}

fn point(text: &str) -> Option<(f32, f32)> {
    let (x, y) = text.split_once(',')?;
    let (x, y): (f32, f32) = (x.trim().parse().ok()?, y.trim().parse().ok()?);
    (x.is_finite() && y.is_finite()).then_some((x, y))
}

fn button(text: &str) -> Option<Button> {
    match text {
        "left" => Some(Button::Left),
        "right" => Some(Button::Right),
        "middle" => Some(Button::Middle),
        _ => None,
    }
}

fn key(text: &str) -> Option<Key> {
    Some(match text {
        "frame" => Key::Frame,
        "save" => Key::Save,
        "sampling" => Key::NextSampling,
        "spp+" => Key::MoreSpp,
        "spp-" => Key::FewerSpp,
        "finer" => Key::Finer,
        "coarser" => Key::Coarser,
        "motion" => Key::ToggleMotion,
        "shadows" => Key::ToggleShadows,
        "aperture+" => Key::WiderAperture,
        "aperture-" => Key::NarrowerAperture,
        "aov" => Key::NextAov,
        "overlay" => Key::ToggleOverlay,
        "quit" => Key::Quit,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_script_expands_drags_and_reads_every_step() {
        let steps = parse("wait; drag left 10,20 110,20\nwheel -2 ; key spp+; move 1,2").unwrap();
        assert_eq!(steps.len(), 1 + 4 + 3);
        assert_eq!(steps[0], Step::Wait);
        assert_eq!(steps[3], Step::Input(Input::CursorMoved(110.0, 20.0)));
        assert_eq!(steps[5], Step::Input(Input::Wheel(-2.0)));
        assert_eq!(steps[6], Step::Input(Input::Key(Key::MoreSpp)));
    }

    #[test]
    fn bad_steps_are_named() {
        for bad in ["jump", "drag up 1,1 2,2", "wheel x", "move 1", "key nope"] {
            let error = parse(bad).unwrap_err().to_string();
            assert!(error.contains(bad), "{error}");
        }
    }
}
