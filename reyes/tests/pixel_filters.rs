//! Pixel filters against their definitions: a vertical edge between a
//! white `constant` half-plane and the black background, rendered by the CPU
//! reference with each of RenderMan's filters, has the profile of the
//! filter's integral across the edge: each pixel is the filter-weighted
//! share of its window's samples that lie left of the edge. The weights and
//! the sample positions are computed here from the RenderMan Interface's
//! formulas, not with the renderer's code.

use reyes::color::srgb_to_linear;
use reyes::rib::RibScene;

/// Where the edge crosses the image, in pixels from the left: between two
/// sample columns (an 8 x 8 grid of samples per pixel puts them at
/// 16 + 1.5 / 8 and 16 + 2.5 / 8).
const EDGE: f64 = 16.25;
const WIDTH: u32 = 32;
const HEIGHT: u32 = 8;
/// Samples per pixel side.
const K: u32 = 8;

/// The filters' weights as the RenderMan Interface 3.2 defines them, for a
/// sample `(x, y)` pixels from the pixel's centre inside the window.
fn weight(filter: &str, x: f64, y: f64, xwidth: f64, ywidth: f64) -> f64 {
    if x.abs() > xwidth / 2.0 || y.abs() > ywidth / 2.0 {
        return 0.0;
    }
    match filter {
        "box" => 1.0,
        "triangle" => (1.0 - x.abs() / (xwidth / 2.0)) * (1.0 - y.abs() / (ywidth / 2.0)),
        "gaussian" => {
            let (u, v) = (2.0 * x / xwidth, 2.0 * y / ywidth);
            (-2.0 * (u * u + v * v)).exp()
        }
        "catmull-rom" => {
            let r = (x * x + y * y).sqrt();
            if r < 1.0 {
                3.0 * r.powi(3) - 5.0 * r * r + 2.0
            } else if r < 2.0 {
                -r.powi(3) + 5.0 * r * r - 8.0 * r + 4.0
            } else {
                0.0
            }
        }
        "sinc" => {
            let axis = |t: f64, w: f64| {
                if t == 0.0 {
                    1.0
                } else {
                    let pt = std::f64::consts::PI * t;
                    (0.5 * pt / w).cos() * pt.sin() / pt
                }
            };
            axis(x, xwidth) * axis(y, ywidth)
        }
        other => panic!("no filter {other}"),
    }
}

/// The expected linear value of pixel `(px, py)`: the weighted share of
/// the samples of the pixels around it (inside the image) left of the edge.
fn expected(filter: &str, xwidth: f64, ywidth: f64, px: u32, py: u32) -> f64 {
    let (mut lit, mut total) = (0.0, 0.0);
    for qy in 0..HEIGHT {
        for qx in 0..WIDTH {
            for s in 0..K * K {
                let sx = f64::from(qx) + (f64::from(s % K) + 0.5) / f64::from(K);
                let sy = f64::from(qy) + (f64::from(s / K) + 0.5) / f64::from(K);
                let w = weight(
                    filter,
                    sx - (f64::from(px) + 0.5),
                    sy - (f64::from(py) + 0.5),
                    xwidth,
                    ywidth,
                );
                total += w;
                if sx < EDGE {
                    lit += w;
                }
            }
        }
    }
    (lit / total).clamp(0.0, 1.0)
}

/// The edge scene with `PixelFilter filter xwidth ywidth`: an orthographic
/// view whose screen window maps x in [-16, 16] onto the 32 columns.
fn render(filter: &str, xwidth: f64, ywidth: f64) -> image::RgbaImage {
    let left = EDGE - 16.0;
    let text = format!(
        "Format {WIDTH} {HEIGHT} 1\nPixelSamples {K} {K}\nPixelFilter \"{filter}\" {xwidth} {ywidth}\n\
         Projection \"orthographic\"\nScreenWindow -16 16 -4 4\nWorldBegin\nSurface \"constant\"\n\
         Color [1 1 1]\nTranslate 0 0 5\n\
         Polygon \"P\" [-30 -10 0  -30 10 0  {left} 10 0  {left} -10 0]\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "edge.rib").unwrap_or_else(|e| panic!("{e}\n{text}"));
    assert!(rib.warnings.is_empty(), "{:?}", rib.warnings);
    reyes::reference::render(&rib.prepare().unwrap()).image
}

#[test]
fn an_edge_has_the_profile_of_each_filters_integral() {
    for (filter, xwidth, ywidth) in [
        ("box", 1.0, 1.0),
        ("box", 2.0, 2.0),
        ("triangle", 2.0, 2.0),
        ("gaussian", 2.0, 2.0),
        ("gaussian", 4.0, 2.0),
        ("catmull-rom", 3.0, 3.0),
        ("sinc", 4.0, 4.0),
    ] {
        let image = render(filter, xwidth, ywidth);
        let mut profile = Vec::new();
        let mut worst = 0f64;
        for py in [0, HEIGHT / 2] {
            for px in 10..22 {
                let want = expected(filter, xwidth, ywidth, px, py);
                let got = f64::from(srgb_to_linear(
                    f32::from(image.get_pixel(px, py)[0]) / 255.0,
                ));
                // 2/255 plus the 8-bit sRGB rounding at this value.
                let step = 1.0 / 255.0 * (1.0 + 2.0 * got.sqrt());
                let diff = (got - want).abs();
                worst = worst.max(diff * 255.0);
                assert!(
                    diff <= 2.0 / 255.0 + step,
                    "{filter} {xwidth}x{ywidth}, pixel ({px}, {py}): rendered {got:.4}, the filter gives {want:.4}"
                );
                if py == HEIGHT / 2 {
                    profile.push(format!("{got:.3}"));
                }
            }
        }
        eprintln!(
            "{filter} {xwidth}x{ywidth}: largest difference {worst:.2}/255; columns 10..22: {}",
            profile.join(" ")
        );
    }
}

/// The filters differ: a wider window spreads the edge over more pixels.
#[test]
fn wider_filters_spread_the_edge_further() {
    let spread = |filter: &str, width: f64| {
        let image = render(filter, width, width);
        (0..WIDTH)
            .filter(|&x| {
                let v = image.get_pixel(x, HEIGHT / 2)[0];
                v > 2 && v < 253
            })
            .count()
    };
    assert_eq!(spread("box", 1.0), 1);
    assert!(spread("gaussian", 4.0) > spread("gaussian", 2.0));
    assert!(spread("gaussian", 2.0) > spread("box", 1.0));
}
