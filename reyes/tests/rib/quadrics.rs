//! The quadrics against the RenderMan Interface 3.2 definitions, their
//! orientation, a sphere's silhouette, and `Display` as the output path.

use std::f64::consts::FRAC_PI_2;

use glam::{DMat4, DVec2, DVec3};
use rand::Rng;
use reyes::rib::RibScene;
use reyes::rib::quadrics::{arc, arc_error};

use super::{fresh_rng, temp_dir};

/// The exact surface of quadric `name` with arguments `n` at `(u, v)`,
/// object space, as the specification defines it (typed here again).
fn exact(name: &str, n: &[f64], u: f64, v: f64) -> DVec3 {
    let (s, c) = (u * n[n.len() - 1].to_radians()).sin_cos();
    let rz = |r: f64, z: f64| DVec3::new(r * c, r * s, z);
    match name {
        "Sphere" => {
            let r = n[0];
            let lo = if n[1] > -r {
                (n[1] / r).asin()
            } else {
                -FRAC_PI_2
            };
            let hi = if n[2] < r {
                (n[2] / r).asin()
            } else {
                FRAC_PI_2
            };
            let phi = lo + v * (hi - lo);
            rz(r * phi.cos(), r * phi.sin())
        }
        "Cylinder" => rz(n[0], n[1] + v * (n[2] - n[1])),
        "Cone" => rz(n[1] * (1.0 - v), v * n[0]),
        "Disk" => rz(n[1] * (1.0 - v), n[0]),
        "Torus" => {
            let phi = (n[2] + v * (n[3] - n[2])).to_radians();
            rz(n[0] + n[1] * phi.cos(), n[1] * phi.sin())
        }
        "Paraboloid" => {
            let z = n[1] + v * (n[2] - n[1]);
            rz(n[0] * (z / n[2]).sqrt(), z)
        }
        "Hyperboloid" => {
            let p = DVec3::new(n[0], n[1], n[2]).lerp(DVec3::new(n[3], n[4], n[5]), v);
            DVec3::new(p.x * c - p.y * s, p.x * s + p.y * c, p.z)
        }
        _ => unreachable!(),
    }
}

fn bezier(points: &[glam::Vec3; 16], u: f64, v: f64) -> DVec3 {
    let b = |t: f64| {
        let s = 1.0 - t;
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
    };
    let (bu, bv) = (b(u), b(v));
    (0..16)
        .map(|k| points[k].as_dvec3() * bu[k % 4] * bv[k / 4])
        .sum()
}

/// The `(u, v)` in [0, 1]^2 minimizing `f`: the best of a grid and of
/// `seeds`, then a pattern search.
fn minimize(f: impl Fn(f64, f64) -> f64, seeds: &[(f64, f64)]) -> (f64, f64) {
    const N: usize = 40;
    let mut best = (0.0, 0.0, f64::INFINITY);
    let grid =
        (0..=N).flat_map(|i| (0..=N).map(move |j| (i as f64 / N as f64, j as f64 / N as f64)));
    // Seeds first: at a degenerate apex (a disk's centre) every u ties at
    // the same v, and only a seed's u points the descent the right way.
    for (u, v) in seeds.iter().copied().chain(grid) {
        let d = f(u, v);
        if d < best.2 {
            best = (u, v, d);
        }
    }
    let mut h = 1.0 / N as f64;
    while h > 1e-13 {
        let mut moved = false;
        for (du, dv) in [(h, 0.0), (-h, 0.0), (0.0, h), (0.0, -h)] {
            let (u, v) = ((best.0 + du).clamp(0.0, 1.0), (best.1 + dv).clamp(0.0, 1.0));
            let d = f(u, v);
            if d < best.2 {
                best = (u, v, d);
                moved = true;
            }
        }
        if !moved {
            h /= 2.0;
        }
    }
    (best.0, best.1)
}

const QUADRICS: [(&str, &str); 7] = [
    ("Sphere", "1.5 -1 1.2 300"),
    ("Cylinder", "1 -1 1.5 270"),
    ("Cone", "2 1.2 330"),
    ("Disk", "0.5 1.5 360"),
    ("Torus", "1.2 0.5 -30 250 300"),
    ("Paraboloid", "1.5 0.2 2 360"),
    ("Hyperboloid", "1 0 -1  0.3 1.2 1  200"),
];

#[test]
fn arc_error_is_the_measured_radial_error() {
    for degrees in [90.0f64, 45.0, 20.0, 5.0] {
        let c = arc(0.3, 0.3 + degrees.to_radians());
        let measured = (0..=20000)
            .map(|i| {
                let t = f64::from(i) / 20000.0;
                let s = 1.0 - t;
                let p: DVec2 = c[0] * s * s * s
                    + c[1] * 3.0 * t * s * s
                    + c[2] * 3.0 * t * t * s
                    + c[3] * t * t * t;
                (p.length() - 1.0).abs()
            })
            .fold(0.0, f64::max);
        let bound = arc_error(degrees.to_radians());
        eprintln!("{degrees} degrees: measured {measured:e}, closed form {bound:e}");
        assert!(measured <= bound * (1.0 + 1e-6) + 1e-15 && measured >= bound * 0.999);
    }
}

#[test]
fn quadrics_stay_within_a_tenth_of_a_pixel_of_the_exact_surface() {
    let mut rng = fresh_rng("quadrics_stay_within_a_tenth_of_a_pixel_of_the_exact_surface");
    // A far small image and a near large one: more patches for the latter.
    for (w, h, depth) in [(320u32, 240u32, 7.0), (1600, 1200, 3.5)] {
        let fov = 45.0f64;
        let scale = f64::from(w.min(h)) / 2.0 / (fov.to_radians() / 2.0).tan();
        let to_world = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0))
            * DMat4::from_translation(DVec3::new(0.3, -0.2, depth))
            * DMat4::from_axis_angle(DVec3::new(1.0, 0.5, 0.0).normalize(), 35f64.to_radians());
        let pixel = |p: DVec3| DVec2::new(p.x / p.z, p.y / p.z) * scale;
        for (name, args) in QUADRICS {
            let text = format!(
                "Format {w} {h} 1\nProjection \"perspective\" \"fov\" {fov}\nWorldBegin\n\
                 Translate 0.3 -0.2 {depth}\nRotate 35 1 0.5 0\n{name} {args}\nWorldEnd\n"
            );
            let rib = RibScene::from_text(&text, "q.rib").unwrap();
            assert!(
                rib.warnings.iter().all(|w| !w.message.contains(name)),
                "{:?}",
                rib.warnings
            );
            let n: Vec<f64> = args
                .split_whitespace()
                .map(|x| x.parse().unwrap())
                .collect();
            let patches = &rib.models[0].patches;
            let (mut world, mut px) = (0.0f64, 0.0f64);
            for _ in 0..150 {
                let patch = &patches[rng.random_range(0..patches.len())];
                let p = bezier(&patch.points, rng.random(), rng.random());
                let surface = |u: f64, v: f64| to_world.transform_point3(exact(name, &n, u, v));
                // The point's angle about z, less the profile's own angle
                // at v (0 but for the hyperboloid), gives u: seeds that
                // keep the search off the degenerate apex.
                let object = to_world.inverse().transform_point3(p);
                let seeds: Vec<(f64, f64)> = (0..=400)
                    .map(|j| {
                        let v = f64::from(j) / 400.0;
                        let q = exact(name, &n, 0.0, v);
                        let turn = (object.y.atan2(object.x) - q.y.atan2(q.x))
                            .rem_euclid(std::f64::consts::TAU);
                        let u = turn / n[n.len() - 1].to_radians();
                        (u.min(1.0), v)
                    })
                    .collect();
                let (u, v) = minimize(|u, v| surface(u, v).distance_squared(p), &seeds);
                let q = surface(u, v);
                world = world.max(p.distance(q));
                px = px.max(pixel(p).distance(pixel(q)));
            }
            eprintln!(
                "{w}x{h} at {depth}: {name}: {} patches, max error {world:.2e} world, {px:.4} px",
                patches.len()
            );
            assert!(px < 0.1, "{name}: {px} pixels");
            assert!(world < 0.1 * 2.0 * depth * (fov.to_radians() / 2.0).tan() / f64::from(h));
        }
    }
}

fn render(text: &str) -> image::RgbaImage {
    let rib = RibScene::from_text(text, "s.rib").unwrap();
    reyes::reference::render(&rib.prepare().unwrap()).image
}

/// The covered area in pixels: the sum of the linear coverage of a white
/// `constant` object.
fn coverage(image: &image::RgbaImage) -> f64 {
    image
        .pixels()
        .map(|p| f64::from(reyes::color::srgb_to_linear(f32::from(p[0]) / 255.0)))
        .sum()
}

const LIT: &str = "PixelSamples 4 4\nProjection \"perspective\" \"fov\" 90\nWorldBegin\n\
    Surface \"constant\"\n";

#[test]
fn sphere_silhouette_covers_pi_r_squared() {
    // Radius 1 at distance 3, fov 90 on 64 x 64: the silhouette cone's
    // half angle is asin(1/3), a circle of 32 tan(asin(1/3)) = 32 / sqrt(8)
    // = 11.31 pixels: 402.1 pixels of area.
    let image = render(&format!(
        "Format 64 64 1\n{LIT}Sides 1\nTranslate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\n"
    ));
    let r = 32.0 / 8f64.sqrt();
    let expected = std::f64::consts::PI * r * r;
    let area = coverage(&image);
    eprintln!("sphere: {area:.1} pixels, expected {expected:.1}");
    assert!(
        (area - expected).abs() < 0.03 * expected,
        "{area} vs {expected}"
    );
}

#[test]
fn quadric_normals_point_outward() {
    let seen = |geometry: &str| {
        coverage(&render(&format!(
            "Format 32 32 1\n{LIT}Sides 1\n{geometry}\nWorldEnd\n"
        )))
    };
    // From inside a sphere (the camera at its centre) its outside faces
    // away: nothing shows unless the orientation is reversed.
    assert_eq!(seen("Sphere 5 -5 5 360"), 0.0);
    assert!(seen("ReverseOrientation Sphere 5 -5 5 360") > 1000.0);
    // Inside a cylinder (its axis turned to y).
    assert_eq!(seen("Rotate 90 1 0 0 Cylinder 2 -5 5 360"), 0.0);
    assert!(seen("Orientation \"inside\" Rotate 90 1 0 0 Cylinder 2 -5 5 360") > 400.0);
    // A disk's outside is +z: seen from behind (the camera looks down +z)
    // unless turned over.
    assert_eq!(seen("Translate 0 0 3 Disk 0 10 360"), 0.0);
    assert!(seen("Translate 0 0 3 Rotate 180 1 0 0 Disk 0 10 360") > 1000.0);
    // As in RenderMan, a mirroring transform turns it inside out (the
    // orientation no longer matches the handedness) until "outside" is
    // declared again.
    assert!(seen("Scale 1 1 -1 Sphere 5 -5 5 360") > 1000.0);
    assert_eq!(
        seen("Scale 1 1 -1 Orientation \"outside\" Sphere 5 -5 5 360"),
        0.0
    );
    // From outside: a cap facing the camera (z from 0.5: a rim of radius
    // 0.866 at distance 2.5, 5.54 pixels, 96 pixels of area, nearer than
    // the sphere's silhouette at z = 1/3) shows its outside, not its inside.
    let dome = "Translate 0 0 3 Rotate 180 1 0 0 Sphere 1 0.5 1 360";
    assert!(seen(dome) > 85.0, "{}", seen(dome));
    assert_eq!(seen(&format!("ReverseOrientation {dome}")), 0.0);
}

#[test]
fn quadrics_warn_when_empty_or_clamped() {
    let rib = RibScene::from_text(
        "Clipping 0.0001 100\nProjection \"perspective\"\nFormat 4000 4000 1\nWorldBegin\n\
         Sphere 1 -1 1 0\nDisk 0 0 360\nTranslate 0 0 100000001\nSphere 1e8 -1e8 1e8 360\n\
         Paraboloid 1 -1 1 360\nWorldEnd\n",
        "e.rib",
    )
    .unwrap();
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let all = all.join("\n");
    assert!(all.contains("e.rib:5: Sphere: thetamax is 0"), "{all}");
    assert!(all.contains("e.rib:6: Disk: the surface is empty"), "{all}");
    assert!(
        all.contains("e.rib:8: Sphere: 64 x 64 segments (the most)"),
        "{all}"
    );
    assert!(
        all.contains("e.rib:9: Paraboloid: zmin -1 and zmax 1"),
        "{all}"
    );
    assert_eq!(rib.models[0].patches.len(), 64 * 64);
}

fn cli(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_reyes"))
        .current_dir(dir)
        .args(["render", "--cpu"])
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn display_names_the_output_unless_o_is_given() {
    let dir = temp_dir("display");
    std::fs::create_dir_all(dir.join("ribs")).unwrap();
    let scene = |display: &str| {
        format!(
            "Format 16 12 1\nDisplay \"{display}\" \"file\" \"rgba\"\n{LIT}Translate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\n"
        )
    };
    // Relative to the current directory, not the RIB's.
    std::fs::write(dir.join("ribs/a.rib"), scene("out/a.png")).unwrap();
    let out = cli(&dir, &["ribs/a.rib"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(image::open(dir.join("out/a.png")).unwrap().width(), 16);
    assert!(!dir.join("ribs/out").exists());
    // -o wins over Display.
    let out = cli(&dir, &["ribs/a.rib", "-o", "b.png"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("b.png").exists());
    // "framebuffer" names the file too; the output checks see the Display
    // path: a format the renderer cannot write fails before rendering.
    std::fs::write(
        dir.join("c.rib"),
        scene("c.exr").replace("\"file\"", "\"framebuffer\""),
    )
    .unwrap();
    assert!(cli(&dir, &["c.rib"]).status.success());
    assert!(dir.join("c.exr").exists());
    std::fs::write(dir.join("d.rib"), scene("d.tif")).unwrap();
    let out = cli(&dir, &["d.rib"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("d.tif"));
    // A Display that is the scene itself is refused by the same checks.
    std::fs::write(dir.join("e.rib"), scene("e.rib")).unwrap();
    let out = cli(&dir, &["e.rib"]);
    assert!(!out.status.success());
    assert_eq!(
        std::fs::read_to_string(dir.join("e.rib")).unwrap(),
        scene("e.rib")
    );
    // Without Display (or with +name only): reyes.png.
    std::fs::write(dir.join("f.rib"), scene("+f.png")).unwrap();
    assert!(cli(&dir, &["f.rib"]).status.success());
    assert!(dir.join("reyes.png").exists() && !dir.join("+f.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
