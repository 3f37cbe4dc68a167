//! `shadow()` in a user's WGSL surface shader, the RenderMan way: a RIB file
//! renders a depth frame from a spotlight, `MakeShadow` makes its map, and a
//! beauty frame's `Surface "lit" "string key" ["spot1.shad"]` looks the
//! map up (`lit.wgsl` beside the RIB). Rendered by the binary on the GPU,
//! the frame matches the same frame shaded by the standard `matte` under a
//! `shadowspot` that reads the same map: `lit` is matte with its one light
//! scaled by `1 - shadow(key, P)`, which is what the shadowed light does.
//! The unshadowed frame differs, so the shadows are there.

mod files;

use std::path::Path;
use std::process::Command;

use files::TempDir;
use gpu_test::gpu_test;
use image::RgbImage;

/// matte (`Ka = Kd = 1`) with the light that `diffuse` gathers scaled by
/// the map's shadow.
const LIT_WGSL: &str = "struct Parameters { key: ShadowId }

fn surface(ctx: ShadingContext, params: Parameters) -> SurfaceOutput {
    let lit = ambient() + (1.0 - shadow(params.key, ctx.P)) * diffuse(ctx, ctx.N);
    return SurfaceOutput(ctx.Cs * lit, ctx.Os);
}
";

/// The golden scene's world (tests/data/rib_shadows/geometry.rib) with
/// `surface` for its `Surface "matte"`.
fn geometry(surface: &str) -> String {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/rib_shadows");
    std::fs::read_to_string(data.join("geometry.rib"))
        .unwrap()
        .replace("Surface \"matte\"", surface)
}

/// The depth frame from the golden scene's first spotlight, its map, and a
/// beauty frame written to `picture` lit by an ambient light and `spot`
/// (a `LightSource`'s name, handle and parameters, placed as that
/// spotlight), its world shaded by `surface`.
fn scene(spot: &str, surface: &str, picture: &str) -> String {
    format!(
        "Clipping 0.1 100
FrameBegin 1
  Format 256 256 1
  PixelSamples 1 1
  Projection \"perspective\" \"fov\" [60]
  Display \"spot1.z\" \"zfile\" \"z\"
  Hider \"hidden\" \"depthfilter\" \"midpoint\"
  Transform [0.70710678 -0.57735027 -0.40824829 0  0.70710678 0.57735027 0.40824829 0
             0 0.57735027 -0.81649658 0  0 0 7.3484692 1]
  WorldBegin
{world}
  WorldEnd
FrameEnd
MakeShadow \"spot1.z\" \"spot1.shad\"
FrameBegin 2
  Format 120 90 1
  PixelSamples 2 2
  Projection \"perspective\" \"fov\" [40]
  Display \"{picture}\" \"file\" \"rgba\"
  Transform [0.8660254 -0.35355339 -0.35355339 0  0.5 0.61237244 0.61237244 0
             0 0.70710678 -0.70710678 0  0 0 11.313708 1]
  WorldBegin
    LightSource \"ambientlight\" 1 \"intensity\" [0.1]
    LightSource {spot} \"intensity\" [40] \"from\" [3 -3 6] \"to\" [0 0 0]
      \"coneangle\" [0.43633231] \"conedeltaangle\" [0.08726646]
{world_shaded}
  WorldEnd
FrameEnd
",
        world = geometry("Surface \"matte\""),
        world_shaded = geometry(surface),
    )
}

fn render(dir: &TempDir, rib: &str, text: &str) -> RgbImage {
    std::fs::write(dir.path(rib), text).unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir.path(""))
        .args(["render", "--quiet", rib])
        .output()
        .expect("reyes runs");
    assert!(
        output.status.success(),
        "{rib}: {}\n{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let picture = dir.path(&rib.replace(".rib", ".png"));
    image::open(&picture)
        .unwrap_or_else(|e| panic!("{}: {e}", picture.display()))
        .to_rgb8()
}

/// Pixels whose channels differ by more than `tolerance`.
fn differing(a: &RgbImage, b: &RgbImage, tolerance: i32) -> usize {
    a.pixels()
        .zip(b.pixels())
        .filter(|(p, q)| (0..3).any(|c| (i32::from(p[c]) - i32::from(q[c])).abs() > tolerance))
        .count()
}

#[gpu_test]
fn a_shader_reading_a_made_map_shades_as_a_shadowspot() {
    let dir = TempDir::new("rib-shader-shadow");
    std::fs::write(dir.path("lit.wgsl"), LIT_WGSL).unwrap();
    let shadowspot = render(
        &dir,
        "shadowspot.rib",
        &scene(
            "\"shadowspot\" 2 \"string shadowname\" [\"spot1.shad\"]",
            "Surface \"matte\"",
            "shadowspot.png",
        ),
    );
    let shader = render(
        &dir,
        "shader.rib",
        &scene(
            "\"spotlight\" 2",
            "Surface \"lit\" \"string key\" [\"spot1.shad\"]",
            "shader.png",
        ),
    );
    let unshadowed = render(
        &dir,
        "unshadowed.rib",
        &scene("\"spotlight\" 2", "Surface \"matte\"", "unshadowed.png"),
    );
    let pixels = shader.pixels().len();
    let apart = differing(&shader, &shadowspot, 2);
    let shadowed = differing(&unshadowed, &shadowspot, 8);
    eprintln!(
        "{apart} of {pixels} pixels differ by more than 2/255 between the shader and the shadowspot; \
         the shadows change {shadowed}"
    );
    assert!(
        shadowed > 100,
        "the map shadows the frame: {shadowed} pixels"
    );
    assert!(apart * 200 <= pixels, "{apart} of {pixels} pixels differ");
}
