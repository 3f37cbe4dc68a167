//! RIB projections: `Projection "orthographic"` (RenderMan's default) and
//! `"perspective"`, sized by `ScreenWindow`, with `FrameAspectRatio`.

use reyes::rib::RibScene;
use reyes::scene::Projection;

fn scene(options: &str, world: &str) -> RibScene {
    let text = format!(
        "{options}WorldBegin\nLightSource \"ambientlight\" 1 \"intensity\" [1]\n{world}WorldEnd\n"
    );
    RibScene::from_text(&text, "p.rib").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn warnings(rib: &RibScene) -> String {
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    all.join("\n")
}

/// A unit square facing the camera, centred on the view axis at depth `z`,
/// shifted by `x` across it.
fn square(x: f64, z: f64) -> String {
    let (a, b) = (x - 0.5, x + 0.5);
    format!("Polygon \"P\" [{a} -0.5 {z} {b} -0.5 {z} {b} 0.5 {z} {a} 0.5 {z}]\n")
}

/// Covered pixels of the CPU render, left half and right half.
fn coverage(rib: &RibScene) -> (usize, usize) {
    let rendered = reyes::reference::render(&rib.prepare().unwrap());
    let width = rib.scene.resolution.width as usize;
    let (mut left, mut right) = (0, 0);
    for (i, &covered) in rendered.coverage.iter().enumerate() {
        if covered {
            if i % width < width / 2 {
                left += 1
            } else {
                right += 1
            }
        }
    }
    (left, right)
}

#[test]
fn orthographic_is_the_default_and_keeps_sizes_at_every_depth() {
    // 64 x 32 pixels, default window [-2, 2] x [-1, 1]: 16 pixels per unit.
    let world = format!("{}{}", square(-1.0, 3.0), square(1.0, 30.0));
    let rib = scene("Format 64 32 1\n", &world);
    let camera = rib.scene.camera.unwrap();
    assert_eq!(camera.projection, Projection::Orthographic);
    assert_eq!(camera.ortho_height, Some(2.0));
    assert_eq!(warnings(&rib), "");
    // Both squares are 16 x 16 pixels, however far.
    assert_eq!(coverage(&rib), (256, 256));

    // The same squares in perspective: the far one is ten times smaller
    // across, so about a hundredth of the area (a few pixels here).
    let rib = scene(
        "Format 64 32 1\nProjection \"perspective\" \"fov\" 90\n",
        &world,
    );
    let (near, far) = coverage(&rib);
    assert!(near > 10 * far.max(1), "{near} {far}");
}

#[test]
fn screen_window_sets_the_view_size() {
    // Orthographic over [-1, 1] x [-0.5, 0.5]: 32 pixels per unit.
    let rib = scene(
        "Format 64 32 1\nProjection \"orthographic\"\nScreenWindow -1 1 -0.5 0.5\n",
        &square(0.0, 5.0),
    );
    assert_eq!(rib.scene.camera.unwrap().ortho_height, Some(1.0));
    assert_eq!(coverage(&rib).0 + coverage(&rib).1, 32 * 32);
    assert_eq!(warnings(&rib), "");

    // Perspective: a window half the default size halves tan(fov / 2).
    let rib = scene(
        "Format 32 32 1\nProjection \"perspective\" \"fov\" 90\nScreenWindow -0.5 0.5 -0.5 0.5\n",
        &square(0.0, 5.0),
    );
    let fov = rib.scene.camera.unwrap().fov_y_degrees;
    let expected = 2.0 * 0.5f32.atan().to_degrees();
    assert!((fov - expected).abs() < 1e-3, "{fov} vs {expected}");
}

#[test]
fn windows_and_aspects_the_camera_cannot_show_warn() {
    let rib = scene(
        "Format 64 32 1\nScreenWindow 0 2 -1 1\nFrameAspectRatio 1\nDepthOfField 2 0.1 5\n",
        &square(0.0, 5.0),
    );
    let all = warnings(&rib);
    assert!(
        all.contains("p.rib:2: ScreenWindow 0 2 -1 1 is off-centre"),
        "{all}"
    );
    assert!(
        all.contains("ScreenWindow 0 2 -1 1 has the aspect 1"),
        "{all}"
    );
    assert!(
        all.contains("FrameAspectRatio 1 differs from the image's 2"),
        "{all}"
    );
    assert!(
        all.contains("DepthOfField needs a perspective camera"),
        "{all}"
    );
    assert_eq!(rib.scene.lens.aperture, 0.0);
    // A matching FrameAspectRatio is silent.
    let rib = scene("Format 64 32 1\nFrameAspectRatio 2\n", &square(0.0, 5.0));
    assert_eq!(warnings(&rib), "");
    // Malformed windows are errors with the line.
    let text = "Format 8 8 1\nScreenWindow 1 -1 -1 1\nWorldBegin\nWorldEnd\n";
    let error = RibScene::from_text(text, "e.rib").unwrap_err().to_string();
    assert!(error.contains("e.rib:2"), "{error}");
}
