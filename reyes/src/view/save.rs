//! `P`: the refined frame as a PNG, and the `reyes render` command line that
//! renders the same frame (camera and settings included).

use std::path::Path;

use super::controls::Settings;
use crate::camera::Camera;
use crate::scene::Dicing;

/// The part of the command line the viewer does not change: `reyes render`,
/// the scene and the options other than those it sets itself.
#[derive(Debug, Clone, Default)]
pub struct CommandBase {
    /// E.g. `["reyes", "render", "scene.toml", "--chunks", "2"]`.
    pub prefix: Vec<String>,
    /// `--shutter` as given (written again while motion blur is on).
    pub shutter: Option<f32>,
    /// The scene's dice threshold (the command line has no flag for it).
    pub dice_threshold: f32,
}

/// The command that renders what the viewer shows with `camera` and
/// `settings` to `output`, and a note when part of the view has no
/// command-line flag.
pub fn render_command(
    base: &CommandBase,
    camera: &Camera,
    settings: &Settings,
    output: &Path,
) -> (String, Option<String>) {
    let vec3 = |v: glam::Vec3| format!("{},{},{}", v.x, v.y, v.z);
    let mut args = base.prefix.clone();
    let mut push = |flag: &str, value: String| {
        args.push(flag.to_owned());
        args.push(value);
    };
    push("--width", camera.width.to_string());
    push("--height", camera.height.to_string());
    push("--eye", vec3(camera.eye));
    push("--target", vec3(camera.target));
    push("--up", vec3(camera.up));
    push("--fov", camera.fov_y_radians.to_degrees().to_string());
    push("--spp", settings.spp.to_string());
    push("--sampling", settings.sampling.name().to_owned());
    push("--aov", settings.aov.name().to_owned());
    let mut note = None;
    match settings.dicing {
        Dicing::Rate => push("--shading-rate", settings.shading_rate.to_string()),
        Dicing::Fixed => {
            if settings.dice_threshold != base.dice_threshold {
                note = Some(format!(
                    "the command line has no dice threshold flag: set `dice_threshold = {}` in the scene",
                    settings.dice_threshold
                ));
            }
        }
    }
    if settings.aperture > 0.0 {
        push("--aperture", settings.aperture.to_string());
        push("--focus", camera.eye.distance(camera.target).to_string());
    }
    if !settings.motion_blur {
        push("--shutter", "0".to_owned());
    } else if let Some(shutter) = base.shutter {
        push("--shutter", shutter.to_string());
    }
    if !settings.shadows {
        let shadows = "shadows are off in the view, and the command line has no flag for that: \
                       the command renders the lights' shadows, if the scene has any";
        note = Some(match note {
            Some(note) => format!("{note}; {shadows}"),
            None => shadows.to_owned(),
        });
    }
    push("-o", output.to_string_lossy().into_owned());
    let line = args
        .iter()
        .map(|a| shell_quote(a))
        .collect::<Vec<_>>()
        .join(" ");
    (line, note)
}

/// `text` quoted for a POSIX shell when it needs it.
fn shell_quote(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.,/=+:@%".contains(c));
    if plain {
        text.to_owned()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aov::Aov;
    use crate::scene::Sampling;
    use glam::Vec3;

    #[test]
    fn the_command_names_the_camera_and_settings() {
        let camera = Camera::new(
            Vec3::new(1.5, -2.0, 3.0),
            Vec3::ZERO,
            Vec3::Z,
            0.5,
            640,
            480,
            0.1,
            50.0,
        );
        let settings = Settings {
            spp: 16,
            sampling: Sampling::Interleave,
            dicing: Dicing::Rate,
            shading_rate: 0.5,
            dice_threshold: 16.0,
            motion_blur: false,
            aperture: 0.0,
            aov: Aov::Depth,
            shadows: true,
        };
        let base = CommandBase {
            prefix: vec!["reyes".into(), "render".into(), "my scene.toml".into()],
            shutter: Some(0.5),
            dice_threshold: 16.0,
        };
        let (line, note) = render_command(&base, &camera, &settings, Path::new("out.png"));
        assert!(note.is_none());
        assert_eq!(
            line,
            format!(
                "reyes render 'my scene.toml' --width 640 --height 480 --eye 1.5,-2,3 --target 0,0,0 \
                 --up 0,0,1 --fov {} --spp 16 --sampling interleave --aov depth --shading-rate 0.5 \
                 --shutter 0 -o out.png",
                0.5f32.to_degrees()
            )
        );
    }
}
