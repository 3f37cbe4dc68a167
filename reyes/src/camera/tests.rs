//! Unit tests of the camera and its conventions, and a camera the other
//! modules' tests share.

use glam::Vec2;

use super::*;

/// A 200 x 100 camera 10 units in front of the origin, z up (shared
/// with other modules' tests).
pub(crate) fn camera() -> Camera {
    Camera::new(
        Vec3::new(0.0, -10.0, 0.0),
        Vec3::ZERO,
        Vec3::Z,
        60f32.to_radians(),
        200,
        100,
        1.0,
        100.0,
    )
}

/// Orthographic: a point's pixel depends on its offset across the view
/// only, by the worked formula `px = W/2 + x * W / width_world`, and
/// not on its depth; depth still runs from 0 (near) to 1 (far).
#[test]
fn an_orthographic_camera_projects_parallel_to_the_view() {
    // Looking down -y from y = -10 at the origin, z up; 200 x 100
    // pixels over a view 4 units high (8 wide).
    let ortho = camera().orthographic(4.0);
    for depth in [-5.0, 0.0, 20.0] {
        let p = Vec3::new(1.0, depth, 0.5);
        let px = ortho.to_pixel(ortho.to_clip(p));
        // x right is +x (the eye looks along +y with z up).
        assert!((px.x - (100.0 + 1.0 * 200.0 / 8.0)).abs() < 1e-3, "{px}");
        assert!((px.y - (50.0 - 0.5 * 100.0 / 4.0)).abs() < 1e-3, "{px}");
    }
    let near = ortho.to_pixel(ortho.to_clip(Vec3::new(0.0, -9.0, 0.0)));
    let far = ortho.to_pixel(ortho.to_clip(Vec3::new(0.0, 90.0, 0.0)));
    assert!(
        near.z.abs() < 1e-5 && (far.z - 1.0).abs() < 1e-5,
        "{near} {far}"
    );
    // The viewer is a direction: towards -y from everywhere.
    assert_eq!(ortho.homogeneous_eye(), Vec4::new(0.0, -1.0, 0.0, 0.0));
    assert_eq!(
        ortho.towards_eye(Vec3::new(3.0, 7.0, -2.0)),
        Vec3::new(0.0, -1.0, 0.0)
    );
    // Perspective: exactly eye - p.
    let p = Vec3::new(0.3, 1.7, -2.9);
    assert_eq!(camera().towards_eye(p), camera().eye - p);
    // A moved orthographic camera stays orthographic.
    let moved = ortho.looking(Vec3::new(0.0, -20.0, 0.0), Vec3::ZERO, Vec3::Z);
    assert_eq!(moved.projection, Projection::Orthographic);
    assert_eq!(moved.proj, ortho.proj);
}

#[test]
fn target_projects_to_image_centre() {
    let cam = camera();
    let p = cam.to_pixel(cam.to_clip(Vec3::ZERO));
    assert!(
        (p.x - 100.0).abs() < 1e-4 && (p.y - 50.0).abs() < 1e-4,
        "{p}"
    );
    assert!(p.z > 0.0 && p.z < 1.0);
}

#[test]
fn clip_pad_bounds_the_clip_motion_of_a_ball() {
    let cam = camera();
    let pad = cam.clip_pad();
    let centre = Vec3::new(0.3, 1.0, -0.2);
    let c = cam.to_clip(centre);
    for k in 0..200 {
        let a = k as f32 * 0.731;
        let b = k as f32 * 0.377;
        let offset = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * 0.5;
        let moved = cam.to_clip(centre + offset);
        let delta = (moved - c).abs();
        assert!(
            delta.cmple(pad * 0.5 * 1.0001 + 1e-6).all(),
            "{delta} {pad}"
        );
    }
}

/// A small deterministic generator for the crop tests (xorshift64*).
struct Random(u64);

impl Random {
    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40;
        lo + (hi - lo) * (bits as f32 / (1u64 << 24) as f32)
    }
}

/// The crops exercised: the whole image, aligned bands and tiles, a
/// partial edge tile, an odd-sized tile, and one reaching past the image.
const CROPS: [(u32, u32, u32, u32); 6] = [
    (0, 0, 200, 100),
    (0, 64, 200, 36),
    (64, 0, 64, 64),
    (128, 64, 72, 36),
    (13, 7, 101, 53),
    (192, 64, 64, 64),
];

#[test]
fn crop_shifts_pixels_by_the_origin() {
    let cam = camera();
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    for &(x0, y0, w, h) in &CROPS {
        let crop = cam.crop(x0, y0, w, h);
        assert_eq!((crop.width, crop.height), (w, h));
        assert_eq!(
            (crop.eye, crop.target, crop.up, crop.view),
            (cam.eye, cam.target, cam.up, cam.view)
        );
        for _ in 0..500 {
            // Points in front of the camera, inside and well outside its frustum.
            let p = Vec3::new(
                random.range(-12.0, 12.0),
                random.range(-8.0, 60.0),
                random.range(-8.0, 8.0),
            );
            let (full, tile) = (cam.to_clip(p), crop.to_clip(p));
            assert!(full.w > 0.5, "{p} is not in front of the camera");
            assert_eq!(tile.w, full.w, "crop changed w at {p}");
            let (a, b) = (cam.to_pixel(full), crop.to_pixel(tile));
            let expected = Vec3::new(a.x - x0 as f32, a.y - y0 as f32, a.z);
            // Float rounding, relative to the pixel magnitudes involved.
            let tolerance = 1e-5 * (1.0 + a.x.abs().max(a.y.abs()) + 200.0);
            assert!(
                (b - expected).abs().cmple(Vec3::splat(tolerance)).all(),
                "crop {:?}: {p} at {b}, expected {expected}",
                (x0, y0, w, h)
            );
            assert_eq!(b.z, a.z, "crop changed the depth of {p}");
        }
    }
}

/// A crop's window (what a screen tile culls against) maps a point's
/// full-image clip position to the tile's own frustum: the point's pixel in
/// the tile, from the windowed clip position, is its full-image pixel less
/// the tile's origin; and a ball's windowed clip motion stays within the
/// pad grown as `shaders/reyes/library.wgsl`'s `window_outcode` grows it.
#[test]
fn a_crops_window_is_the_tiles_frustum() {
    let cam = camera();
    assert_eq!(cam.window(), Vec4::new(1.0, 1.0, 0.0, 0.0));
    let mut random = Random(0x2545_f491_4f6c_dd1d);
    for &(x0, y0, w, h) in &CROPS {
        let crop = cam.crop(x0, y0, w, h);
        let s = crop.window();
        let pad = cam.clip_pad();
        let grown = Vec4::new(
            s.x.abs() * pad.x + s.z.abs() * pad.w,
            s.y.abs() * pad.y + s.w.abs() * pad.w,
            pad.z,
            pad.w,
        );
        for _ in 0..50 {
            let centre = Vec3::new(
                random.range(-3.0, 3.0),
                random.range(-3.0, 10.0),
                random.range(-3.0, 3.0),
            );
            let full = cam.to_clip(centre);
            let windowed = crop.window_clip(full);
            assert_eq!((windowed.z, windowed.w), (full.z, full.w));
            let ndc = windowed / windowed.w;
            let in_tile = Vec2::new(
                (ndc.x * 0.5 + 0.5) * w.max(1) as f32,
                (0.5 - ndc.y * 0.5) * h.max(1) as f32,
            );
            let expected = cam.to_pixel(full).truncate() - Vec2::new(x0 as f32, y0 as f32);
            let tolerance = 1e-4 * (1.0 + expected.abs().max_element());
            assert!(
                (in_tile - expected).abs().max_element() <= tolerance,
                "crop {:?}: {centre} at {in_tile} in the window, expected {expected}",
                (x0, y0, w, h)
            );
            let radius = random.range(0.01, 2.0);
            for k in 0..100 {
                let a = k as f32 * 0.731;
                let b = k as f32 * 0.377;
                let offset = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * radius;
                let delta = (crop.window_clip(cam.to_clip(centre + offset)) - windowed).abs();
                let bound =
                    grown * radius * 1.0001 + Vec4::splat(1e-4 * (1.0 + windowed.abs().max_element()));
                assert!(
                    delta.cmple(bound).all(),
                    "crop {:?}: {delta} {grown}",
                    (x0, y0, w, h)
                );
            }
        }
    }
}

#[test]
fn axes_and_depth_conventions() {
    let cam = camera();
    // +x is to the right when looking along +y with z up; +z is up (smaller py).
    let right = cam.to_pixel(cam.to_clip(Vec3::new(1.0, 0.0, 0.0)));
    let up = cam.to_pixel(cam.to_clip(Vec3::new(0.0, 0.0, 1.0)));
    assert!(right.x > 100.0);
    assert!(up.y < 50.0);
    let near = cam.to_pixel(cam.to_clip(Vec3::new(0.0, -9.0, 0.0)));
    let far = cam.to_pixel(cam.to_clip(Vec3::new(0.0, 90.0, 0.0)));
    assert!(near.z.abs() < 1e-6, "{}", near.z);
    assert!((far.z - 1.0).abs() < 1e-5, "{}", far.z);
}
