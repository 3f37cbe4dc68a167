//! RIB `Exposure` and `Quantize`: honoured (on the scene, through
//! `reyes convert` and in the rendered image), out-of-range values are
//! errors that name the line, `Quantize "z"` is accepted with a warning.

use std::path::PathBuf;

use reyes::quantize::{Exposure, Quantize};
use reyes::rib::RibScene;
use reyes::scene::Scene;

/// A flat grey frame (the background only, one sample, a box filter)
/// after `options` (RIB requests before `WorldBegin`).
fn flat(options: &str) -> String {
    format!(
        "Format 8 8 1\nPixelSamples 1 1\nPixelFilter \"box\" 1 1\n{options}\nWorldBegin\nWorldEnd\n"
    )
}

/// The sRGB transfer function in f64 (IEC 61966-2-1).
fn srgb(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

#[test]
fn exposure_and_quantize_are_honoured() {
    let rib = RibScene::from_text(
        &flat("Exposure 2 1\nQuantize \"rgba\" 255 0 255 0"),
        "e.rib",
    )
    .expect("the RIB reads");
    assert_eq!(
        rib.scene.exposure,
        Exposure {
            gain: 2.0,
            gamma: 1.0
        }
    );
    assert_eq!(rib.scene.quantize, Quantize::NO_DITHER);
    // A RIB scene's background is black: give it a grey to expose.
    let mut scene = rib.scene.clone();
    scene.background = glam::Vec3::splat(0.2);
    let prepared = reyes::PreparedScene::new(&scene, &rib.models).unwrap();
    let image = reyes::reference::render(&prepared).image;
    // Gain 2: the linear 0.2 is encoded as 0.4; no dither.
    let want = (255.0 * srgb(0.4)).round() as u8;
    assert!(
        image.pixels().all(|p| p.0 == [want, want, want, 255]),
        "want {want}"
    );
    // Absent, both are RenderMan's defaults.
    let plain = RibScene::from_text(&flat(""), "p.rib").unwrap();
    assert_eq!(plain.scene.exposure, Exposure::default());
    assert_eq!(plain.scene.quantize, Quantize::default());
}

#[test]
fn bad_values_are_errors_with_the_line() {
    let cases = [
        ("Exposure -1 1", "gain -1 is outside [0, inf)"),
        ("Exposure 1 0", "gamma 0 is outside (0, inf)"),
        ("Exposure 1", "expected 2 numbers"),
        ("Quantize \"rgba\" 255 10 5 0.5", "min 10 is above max 5"),
        (
            "Quantize \"rgba\" 255 0 256 0.5",
            "max 256 is not a whole number in [0, 255]",
        ),
        (
            "Quantize \"rgba\" 0 0 255 0.5",
            "one 0 is outside (0, 65535]",
        ),
        (
            "Quantize \"rgba\" 255 0 255 -0.5",
            "dither -0.5 is outside [0, 255]",
        ),
        ("Quantize \"rgba\" 255 0 255", "expected 4 numbers"),
        (
            "Quantize \"rgb\" 255 0 255 0.5",
            "unknown quantization type \"rgb\"",
        ),
    ];
    for (request, want) in cases {
        let text = flat(request);
        let error = RibScene::from_text(&text, "bad.rib").expect_err(request);
        let shown = error.to_string();
        // The request is on line 4 of `flat`.
        assert!(shown.contains("bad.rib:4"), "{request}: {shown}");
        assert!(shown.contains(want), "{request}: {shown}");
    }
}

#[test]
fn quantize_z_and_requests_in_the_world_warn() {
    let text = "Format 8 8 1\nQuantize \"z\" 0 0 0 0\nWorldBegin\nExposure 2 1\nQuantize \"rgba\" 1 0 1 0\nWorldEnd\n";
    let rib = RibScene::from_text(text, "w.rib").unwrap();
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let all = all.join("\n");
    assert!(all.contains("w.rib:2: Quantize \"z\""), "{all}");
    assert!(
        all.contains("w.rib:4: Exposure inside the world block is ignored"),
        "{all}"
    );
    assert!(
        all.contains("w.rib:5: Quantize inside the world block is ignored"),
        "{all}"
    );
    assert_eq!(rib.scene.exposure, Exposure::default());
    assert_eq!(rib.scene.quantize, Quantize::default());
}

#[test]
fn convert_carries_both() {
    let dir = std::env::temp_dir().join(format!("reyes-rib-output-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = "Format 16 16 1\nExposure 1.5 2.2\nQuantize \"rgba\" 200 5 250 0.25\nProjection \"perspective\"\n\
        WorldBegin\nPolygon \"P\" [0 0 5 0 1 5 1 1 5]\nWorldEnd\n";
    let rib = RibScene::from_text(text, "c.rib").unwrap();
    let toml: PathBuf = dir.join("c.toml");
    rib.write(&toml).unwrap();
    let written = std::fs::read_to_string(&toml).unwrap();
    assert!(
        written.contains("[exposure]") || written.contains("exposure ="),
        "{written}"
    );
    let scene = Scene::load(&toml).unwrap();
    assert_eq!(
        scene.exposure,
        Exposure {
            gain: 1.5,
            gamma: 2.2
        }
    );
    assert_eq!(
        scene.quantize,
        Quantize {
            one: 200.0,
            min: 5.0,
            max: 250.0,
            dither_amplitude: 0.25
        }
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
