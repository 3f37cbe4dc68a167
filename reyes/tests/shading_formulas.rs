//! Rendered shading against the formulas themselves, computed here from a
//! ray cast per pixel onto an exact sphere (not from the renderer's
//! tessellation or its shading code): Lambert's law for `matte` under one
//! distant light, `defaultsurface` without lights, the peak of `plastic`'s
//! highlight at the half-vector, and a spotlight's cone edge. The CPU
//! reference renders; the `tests` crate holds the GPU against it.

use glam::DVec3;
use reyes::color::{linear_to_srgb8, srgb_to_linear};
use reyes::rib::RibScene;

/// Image side in pixels; the camera's field of view in degrees.
const SIZE: u32 = 64;
const FOV: f64 = 30.0;
/// The sphere: radius 1, centred 5 units in front of the camera.
const CENTRE: DVec3 = DVec3::new(0.0, 0.0, 5.0);

/// The sphere scene with `lights` and `surface`, rendered by the CPU
/// reference at 16 samples per pixel, each pixel the mean of its own
/// (a box filter over one pixel, which the expectations average too). The shading rate is 1/16 (a
/// micropolygon a quarter of a pixel wide): the colours are interpolated
/// across each micropolygon, and across the terminator, where `max(0, N.L)`
/// has its kink, that interpolation is off by up to half a micropolygon's
/// change of `N.L` (about 0.01 at a shading rate of 1/4 here, more than the
/// 2/255 these tests allow). The codes are rounded without dither
/// (`Quantize ... 0`): the tolerances below allow the rounding alone.
fn render(lights: &str, surface: &str) -> image::RgbaImage {
    let text = format!(
        "Format {SIZE} {SIZE} 1\nPixelSamples 4 4\nPixelFilter \"box\" 1 1\nShadingRate 0.0625\n\
         Quantize \"rgba\" 255 0 255 0\n\
         Projection \"perspective\" \"fov\" [{FOV}]\nWorldBegin\n{lights}\n{surface}\n\
         Translate 0 0 5\nSphere 1 -1 1 360\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "sphere.rib").unwrap_or_else(|e| panic!("{e}\n{text}"));
    reyes::reference::render(&rib.prepare().unwrap()).image
}

/// Where the ray through the point `(x, y)` of the image (in pixels, y
/// down) meets the sphere, and the unit normal there; `None` for a miss.
/// RenderMan's camera: x right, y up, looking down +z.
fn hit(x: f64, y: f64) -> Option<(DVec3, DVec3)> {
    let half = (FOV.to_radians() / 2.0).tan();
    let s = f64::from(SIZE);
    let dir = DVec3::new((2.0 * x / s - 1.0) * half, (1.0 - 2.0 * y / s) * half, 1.0).normalize();
    // |t dir - c|^2 = 1.
    let b = dir.dot(CENTRE);
    let disc = b * b - (CENTRE.length_squared() - 1.0);
    if disc < 0.0 {
        return None;
    }
    let p = dir * (b - disc.sqrt());
    Some((p, (p - CENTRE).normalize()))
}

/// Pixels whose whole square (with a margin of half a pixel) lies on the
/// sphere: the shading there is not mixed with the background.
fn interior() -> Vec<(u32, u32)> {
    let mut pixels = Vec::new();
    for py in 0..SIZE {
        for px in 0..SIZE {
            let inside = [-0.5, 0.5, 1.5].iter().all(|&dx| {
                [-0.5, 0.5, 1.5]
                    .iter()
                    .all(|&dy| hit(f64::from(px) + dx, f64::from(py) + dy).is_some())
            });
            if inside {
                pixels.push((px, py));
            }
        }
    }
    pixels
}

/// Every interior pixel against `expected(point, normal)` (linear grey),
/// averaged over the pixel's 16 sample positions as the renderer samples
/// it: the rendered pixel, decoded to linear, within `tolerance / 255` of
/// it plus half the 8-bit sRGB step there (the image's own rounding).
/// Returns the largest difference in 255ths of linear intensity.
fn assert_matches(
    image: &image::RgbaImage,
    tolerance: f64,
    expected: impl Fn(DVec3, DVec3) -> f64,
) -> f64 {
    let pixels = interior();
    assert!(pixels.len() > 300, "{} interior pixels", pixels.len());
    let mut worst = 0f64;
    for &(px, py) in &pixels {
        let mut sum = 0.0;
        for sy in 0..4 {
            for sx in 0..4 {
                let x = f64::from(px) + (f64::from(sx) + 0.5) / 4.0;
                let y = f64::from(py) + (f64::from(sy) + 0.5) / 4.0;
                let (p, n) = hit(x, y).expect("an interior pixel");
                sum += expected(p, n);
            }
        }
        let want = sum / 16.0;
        let got = image.get_pixel(px, py)[0];
        let linear = |v: u8| f64::from(srgb_to_linear(f32::from(v) / 255.0));
        let step = linear(got.saturating_add(1)) - linear(got.saturating_sub(1));
        let diff = (linear(got) - want).abs() * 255.0;
        worst = worst.max(diff);
        assert!(
            diff <= tolerance + step * 255.0 / 4.0,
            "pixel ({px}, {py}): rendered {got} (linear {:.4}), the formula gives {want:.4} (sRGB {})",
            linear(got),
            linear_to_srgb8(want as f32)
        );
    }
    worst
}

/// `matte` (Ka 0, Kd 1) under one distant light: `Cs * Kd * max(0, N.L)`.
#[test]
fn matte_follows_lamberts_law() {
    // The light travels from (1, 1, 0) to (0, 0, 1): L = (1, 1, -1) / sqrt 3.
    let image = render(
        "LightSource \"distantlight\" 1 \"from\" [1 1 0] \"to\" [0 0 1] \"intensity\" [0.9]",
        "Surface \"matte\" \"Ka\" [0] \"Kd\" [1]",
    );
    let l = DVec3::new(1.0, 1.0, -1.0).normalize();
    let worst = assert_matches(&image, 2.0, |_, n| 0.9 * n.dot(l).max(0.0));
    eprintln!("matte: largest difference {worst:.2}/255");
}

/// `defaultsurface` with no lights: `Cs * (Ka + Kd * d^2)`,
/// `d = normalize(I).N`.
#[test]
fn defaultsurface_follows_its_formula_without_lights() {
    let image = render("", "");
    let worst = assert_matches(&image, 2.0, |p, n| {
        let d = p.normalize().dot(n);
        0.2 + 0.8 * d * d
    });
    eprintln!("defaultsurface: largest difference {worst:.2}/255");
}

/// `plastic`'s highlight: the brightest pixel is where `N` is the half
/// vector between the light and the eye, and it falls off as
/// `(N.H)^(1 / roughness)` around it.
#[test]
fn plastics_highlight_peaks_at_the_half_vector() {
    let image = render(
        "LightSource \"distantlight\" 1 \"from\" [1 1 0] \"to\" [0 0 1] \"intensity\" [1]",
        "Surface \"plastic\" \"Ka\" [0] \"Kd\" [0] \"Ks\" [1] \"roughness\" [0.1]",
    );
    let l = DVec3::new(1.0, 1.0, -1.0).normalize();
    let worst = assert_matches(&image, 2.0, |p, n| {
        let v = -p.normalize();
        if n.dot(l) <= 0.0 {
            return 0.0;
        }
        let h = (l + v).normalize();
        n.dot(h).max(0.0).powf(10.0).min(1.0)
    });
    eprintln!("plastic: largest difference {worst:.2}/255");
    // The peak: the interior pixel whose centre's normal is nearest H.
    let (mut best, mut best_value) = ((0, 0), 0u8);
    for (px, py) in interior() {
        let v = image.get_pixel(px, py)[0];
        if v > best_value {
            (best, best_value) = ((px, py), v);
        }
    }
    let peak_normal = |px: u32, py: u32| {
        let (p, n) = hit(f64::from(px) + 0.5, f64::from(py) + 0.5).unwrap();
        n.dot((l - p.normalize()).normalize())
    };
    let nearest = interior()
        .into_iter()
        .max_by(|a, b| peak_normal(a.0, a.1).total_cmp(&peak_normal(b.0, b.1)))
        .unwrap();
    assert!(
        best.0.abs_diff(nearest.0) <= 1 && best.1.abs_diff(nearest.1) <= 1,
        "brightest pixel {best:?}, the half vector's {nearest:?}"
    );
}

/// RenderMan's `spotlight` at the eye along +z, of intensity 16, on
/// `matte` (Ka 0, Kd 1) at point `p` with normal `n`: `cone` and `delta`
/// in degrees, `cos^beam / d^2` falloff, a smoothstep across the delta.
fn spot_on_matte(p: DVec3, n: DVec3, cone: f64, delta: f64, beam: i32) -> f64 {
    let (outside, inside) = (cone.to_radians().cos(), (cone - delta).to_radians().cos());
    let distance = p.length();
    let l = -p / distance;
    let cos_angle = p.z / distance;
    if cos_angle < outside {
        return 0.0;
    }
    let t = ((cos_angle - outside) / (inside - outside)).clamp(0.0, 1.0);
    let fade = t * t * (3.0 - 2.0 * t);
    16.0 * cos_angle.powi(beam) / (distance * distance) * fade * n.dot(l).max(0.0)
}

/// A spotlight from the eye along +z with a 4 degree cone that fades over
/// its last degree: full inside 3 degrees (times cos^2 / d^2), dark beyond
/// 4, as RenderMan's `spotlight` computes it.
#[test]
fn a_spotlights_cone_falls_where_its_angles_put_it() {
    let image = render(
        "LightSource \"spotlight\" 1 \"from\" [0 0 0] \"to\" [0 0 1] \"intensity\" [16] \
         \"coneangle\" [0.06981317] \"conedeltaangle\" [0.01745329]",
        "Surface \"matte\" \"Ka\" [0] \"Kd\" [1]",
    );
    let worst = assert_matches(&image, 2.0, |p, n| spot_on_matte(p, n, 4.0, 1.0, 2));
    eprintln!("spotlight: largest difference {worst:.2}/255");
    // The cone's edge crosses the image: lit pixels and dark ones.
    let lit = interior()
        .iter()
        .filter(|&&(x, y)| image.get_pixel(x, y)[0] > 50)
        .count();
    assert!(lit > 50 && lit < interior().len() - 50, "{lit} lit pixels");
}

/// A spotlight's `beamdistribution` is the exponent of its falloff across
/// the cone: `cos^8` here, against the default `cos^2` (6% dimmer at the
/// sphere's rim, 11.5 degrees off the axis), under a 15-degree cone that
/// lights the whole sphere.
#[test]
fn a_spotlights_beam_distribution_is_its_falloff_exponent() {
    let image = render(
        "LightSource \"spotlight\" 1 \"from\" [0 0 0] \"to\" [0 0 1] \"intensity\" [16] \
         \"coneangle\" [0.2617994] \"conedeltaangle\" [0.01745329] \"beamdistribution\" [8]",
        "Surface \"matte\" \"Ka\" [0] \"Kd\" [1]",
    );
    let worst = assert_matches(&image, 2.0, |p, n| spot_on_matte(p, n, 15.0, 1.0, 8));
    eprintln!("spotlight, beamdistribution 8: largest difference {worst:.2}/255");
}
