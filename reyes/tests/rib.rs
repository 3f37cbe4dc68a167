//! RenderMan RIB input: tokenizer and parser errors, ReadArchive, the
//! change of basis of every PatchMesh basis, handedness, the convert round
//! trip, unsupported requests and a mutation test.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use glam::{DVec3, Vec3};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use reyes::prepare::PreparedScene;
use reyes::rib::{RibError, RibScene};
use reyes::scene::Scene;

#[path = "rib/quadrics.rs"]
mod quadrics;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/rib")
        .join(name)
}

/// A random generator drawn afresh, its seed printed; `TEST_SEED=<seed>`
/// replays a run.
fn fresh_rng(test: &str) -> StdRng {
    let seed: u64 = std::env::var("TEST_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(rand::random);
    eprintln!("{test} seed = {seed} (replay with TEST_SEED={seed})");
    StdRng::seed_from_u64(seed)
}

/// A fresh, empty directory under the system's temporary directory.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reyes-rib-test-{}-{test}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn parse_error(text: &str) -> RibError {
    RibScene::from_text(text, "bad.rib").expect_err("the RIB is invalid")
}

#[test]
fn syntax_errors_give_file_line_and_column() {
    let cases: [(&str, (usize, usize), &str); 9] = [
        (
            "WorldBegin\n  Color [1 0 \"x\"]\n",
            (2, 14),
            "mixes numbers and strings",
        ),
        (
            "WorldBegin\n Display \"unterminated\n",
            (2, 10),
            "unterminated string",
        ),
        ("Format 64 4x8 1\n", (1, 11), "invalid number"),
        ("WorldBegin ]\n", (1, 12), "without a matching"),
        ("Color [1 0\nWorldBegin\n", (2, 1), "inside an array"),
        ("1 2 3\n", (1, 1), "before the first request"),
        ("Format 64 48\n", (1, 1), "expected 3 numbers"),
        (
            "WorldBegin\n\n   Surface \"matte\" \"Kd\"\n",
            (3, 4),
            "odd count",
        ),
        (
            "# comment \"[\n  Surface \"matte\" \"bogus float Kd\" 1\n",
            (2, 3),
            "unknown storage class",
        ),
    ];
    for (text, (line, col), message) in cases {
        let error = parse_error(text);
        let shown = error.to_string();
        assert_eq!(error.position(), Some((line, col)), "{text:?}: {shown}");
        assert!(shown.contains(message), "{text:?}: {shown}");
        assert!(
            shown.starts_with(&format!("bad.rib:{line}:{col}:")),
            "{shown}"
        );
    }
}

#[test]
fn binary_rib_is_refused_as_not_supported() {
    let mut bytes = b"Format 64 48 1\nWorldBegin\n  ".to_vec();
    bytes.extend_from_slice(&[0o200, 0x41, 0xff]);
    let error = RibScene::from_bytes(&bytes, "binary.rib").expect_err("binary RIB");
    assert_eq!(error.position(), Some((3, 3)));
    assert!(
        error.to_string().contains("binary RIB is not supported"),
        "{error}"
    );
}

#[test]
fn read_archive_resolves_against_the_including_file() {
    let rib = RibScene::load(data("archive/main.rib")).unwrap();
    assert_eq!(rib.scene.lights.len(), 1);
    // square.rib (before the colour) and the polygon after it.
    assert_eq!(rib.scene.objects.len(), 2, "{:?}", rib.scene.objects);
    assert_eq!(rib.scene.objects[0].color, Vec3::ONE);
    assert_eq!(rib.scene.objects[1].color, Vec3::new(0.25, 0.5, 0.75));
    let missing = RibScene::from_text("WorldBegin\nReadArchive \"nope.rib\"\n", data("x.rib"))
        .expect_err("missing archive");
    assert_eq!(missing.position(), Some((2, 1)), "{missing}");
}

#[test]
fn read_archive_cycles_are_detected() {
    let error = RibScene::load(data("cycle_a.rib")).expect_err("cycle");
    let shown = error.to_string();
    assert!(shown.contains("cycle"), "{shown}");
    assert!(shown.contains("cycle_b.rib:2:1"), "{shown}");
}

/// `[u^3 u^2 u 1] B`, with the bases of the RenderMan specification typed
/// here again (not taken from the crate).
fn weights(m: &[[f64; 4]; 4], u: f64) -> [f64; 4] {
    let pu = [u * u * u, u * u, u, 1.0];
    std::array::from_fn(|k| (0..4).map(|r| pu[r] * m[r][k]).sum())
}

fn spec_bases() -> Vec<(&'static str, [[f64; 4]; 4], usize)> {
    let s = 1.0 / 6.0;
    vec![
        (
            "bezier",
            [
                [-1., 3., -3., 1.],
                [3., -6., 3., 0.],
                [-3., 3., 0., 0.],
                [1., 0., 0., 0.],
            ],
            3,
        ),
        (
            "b-spline",
            [
                [-s, 3. * s, -3. * s, s],
                [3. * s, -6. * s, 3. * s, 0.],
                [-3. * s, 0., 3. * s, 0.],
                [s, 4. * s, s, 0.],
            ],
            1,
        ),
        (
            "catmull-rom",
            [
                [-0.5, 1.5, -1.5, 0.5],
                [1., -2.5, 2., -0.5],
                [-0.5, 0., 0.5, 0.],
                [0., 1., 0., 0.],
            ],
            1,
        ),
        (
            "hermite",
            [
                [2., 1., -2., 1.],
                [-3., -2., 3., -1.],
                [0., 1., 0., 0.],
                [1., 0., 0., 0.],
            ],
            2,
        ),
        (
            "power",
            [
                [1., 0., 0., 0.],
                [0., 1., 0., 0.],
                [0., 0., 1., 0.],
                [0., 0., 0., 1.],
            ],
            4,
        ),
    ]
}

fn fmt_nums(v: impl IntoIterator<Item = f64>) -> String {
    v.into_iter()
        .map(|x| format!("{x:?}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A mesh of random points and the RIB for it; checks the Bezier patches
/// made from it against direct evaluation of the spline.
fn check_mesh(
    rng: &mut StdRng,
    basis_rib: &str,
    (um, ustep): (&[[f64; 4]; 4], usize),
    (vm, vstep): (&[[f64; 4]; 4], usize),
    bicubic: bool,
    uperiodic: bool,
    vperiodic: bool,
) {
    let order = if bicubic { 4 } else { 2 };
    let (ustep, vstep) = if bicubic { (ustep, vstep) } else { (1, 1) };
    let count = |rng: &mut StdRng, periodic: bool, step: usize| {
        let k = rng.random_range(1..=3usize);
        if periodic {
            step * k.max(if step == 1 { 2 } else { 1 })
        } else {
            order + step * (k - 1)
        }
    };
    let nu = count(rng, uperiodic, ustep);
    let nv = count(rng, vperiodic, vstep);
    let p: Vec<DVec3> = (0..nu * nv)
        .map(|_| {
            DVec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(3.0..6.0),
            )
        })
        .collect();
    let wrap = |w| if w { "periodic" } else { "nonperiodic" };
    let text = format!(
        "Projection \"perspective\"\nWorldBegin\n{basis_rib}\nPatchMesh \"{}\" {nu} \"{}\" {nv} \"{}\" \"P\" [{}]\nWorldEnd\n",
        if bicubic { "bicubic" } else { "bilinear" },
        wrap(uperiodic),
        wrap(vperiodic),
        fmt_nums(p.iter().flat_map(|q| q.to_array())),
    );
    let rib = RibScene::from_text(&text, "mesh.rib").unwrap_or_else(|e| panic!("{e}\n{text}"));
    let nup = if uperiodic {
        nu / ustep
    } else if bicubic {
        (nu - 4) / ustep + 1
    } else {
        nu - 1
    };
    let nvp = if vperiodic {
        nv / vstep
    } else if bicubic {
        (nv - 4) / vstep + 1
    } else {
        nv - 1
    };
    let patches: Vec<_> = rib.models.iter().flat_map(|m| m.patches.iter()).collect();
    assert_eq!(patches.len(), nup * nvp, "{text}");
    for _ in 0..20 {
        let (pu, pv) = (rng.random_range(0..nup), rng.random_range(0..nvp));
        let (u, v): (f64, f64) = (rng.random_range(0.0..=1.0), rng.random_range(0.0..=1.0));
        let (wu, wv) = if bicubic {
            (weights(um, u).to_vec(), weights(vm, v).to_vec())
        } else {
            (vec![1.0 - u, u], vec![1.0 - v, v])
        };
        let mut expected = DVec3::ZERO;
        for (j, wj) in wv.iter().enumerate() {
            for (i, wi) in wu.iter().enumerate() {
                let index = ((pv * vstep + j) % nv) * nu + (pu * ustep + i) % nu;
                expected += p[index] * wi * wj;
            }
        }
        // The renderer's world is camera space with x mirrored.
        let expected = (expected * DVec3::new(-1.0, 1.0, 1.0)).as_vec3();
        let got = reyes::bezier::position(&patches[pv * nup + pu].points, u as f32, v as f32);
        let scale = 1.0 + p.iter().map(|q| q.abs().max_element()).fold(0.0, f64::max) as f32 * 20.0;
        assert!(
            (got - expected).abs().max_element() < 2e-5 * scale,
            "{basis_rib} patch ({pu}, {pv}) at ({u}, {v}): {got} != {expected}\n{text}"
        );
    }
}

#[test]
fn patch_mesh_bases_match_direct_evaluation() {
    let mut rng = fresh_rng("patch_mesh_bases_match_direct_evaluation");
    let bases = spec_bases();
    for (name, m, step) in &bases {
        for (up, vp) in [(false, false), (true, false), (false, true), (true, true)] {
            // The same basis both ways, and paired with another one.
            let (other, om, ostep) = &bases[rng.random_range(0..bases.len())];
            let rib = format!("Basis \"{name}\" {step} \"{other}\" {ostep}");
            check_mesh(&mut rng, &rib, (m, *step), (om, *ostep), true, up, vp);
            check_mesh(&mut rng, &rib, (m, *step), (om, *ostep), false, up, vp);
        }
    }
    // Explicit matrices with their own steps.
    for _ in 0..8 {
        let mut matrix = || -> [[f64; 4]; 4] {
            std::array::from_fn(|_| std::array::from_fn(|_| rng.random_range(-2.0..2.0)))
        };
        let (mu, mv) = (matrix(), matrix());
        let (us, vs) = (rng.random_range(1..=4usize), rng.random_range(1..=4usize));
        let flat = |m: &[[f64; 4]; 4]| fmt_nums(m.iter().flatten().copied());
        let rib = format!("Basis [{}] {us} [{}] {vs}", flat(&mu), flat(&mv));
        let (up, vp) = (rng.random_bool(0.5), rng.random_bool(0.5));
        check_mesh(&mut rng, &rib, (&mu, us), (&mv, vs), true, up, vp);
    }
}

#[test]
fn bicubic_patch_uses_the_current_basis_and_bilinear_is_exact() {
    // Power basis: the control points are the coefficients of u^i v^j;
    // only the constant one (the last) is non-zero.
    let mut coefficients = vec![0.0; 45];
    coefficients.extend([1.0, 2.0, 5.0]);
    let text = format!(
        "Projection \"perspective\"\nWorldBegin\nBasis \"power\" 4 \"power\" 4\n\
         Patch \"bicubic\" \"P\" [{}]\n\
         Patch \"bilinear\" \"P\" [0 0 1  1 0 2  0 1 3  1 1 4]\nWorldEnd\n",
        fmt_nums(coefficients)
    );
    let rib = RibScene::from_text(&text, "p.rib").unwrap();
    let patches = &rib.models[0].patches;
    assert_eq!(patches.len(), 2);
    let c = reyes::bezier::position(&patches[0].points, 0.3, 0.7);
    assert!((c - Vec3::new(-1.0, 2.0, 5.0)).length() < 1e-5, "{c}");
    let b = reyes::bezier::position(&patches[1].points, 0.25, 0.5);
    let (u, v) = (0.25f32, 0.5f32);
    let z = (1.0 - u) * (1.0 - v) + 2.0 * u * (1.0 - v) + 3.0 * (1.0 - u) * v + 4.0 * u * v;
    assert!((b - Vec3::new(-u, v, z)).length() < 1e-6, "{b}");
}

/// Lit pixels per quadrant: upper-left, upper-right, lower-left, lower-right.
fn quadrants(rib: &RibScene) -> [usize; 4] {
    let image = reyes::reference::render(&rib.prepare().unwrap()).image;
    let (w, h) = image.dimensions();
    let mut q = [0; 4];
    for (x, y, p) in image.enumerate_pixels() {
        if p[0] > 60 {
            q[usize::from(y >= h / 2) * 2 + usize::from(x >= w / 2)] += 1;
        }
    }
    q
}

#[test]
fn camera_space_is_left_handed_x_right_y_up() {
    // The patch spans x, y in [1, 2] at z = 5; fov 60 on the 48-pixel
    // height: tan 30 = 0.577, so y / z in [0.2, 0.4] is rows 7.4 to 15.7
    // and x / z (over tan 30 * 4/3) columns 40.3 to 48.6: upper right.
    let text = std::fs::read_to_string(data("quadrant.rib")).unwrap();
    let rib = RibScene::from_text(&text, "quadrant.rib").unwrap();
    assert_eq!(rib.display.as_deref(), Some("quadrant.png"));
    let image = reyes::reference::render(&rib.prepare().unwrap()).image;
    for (x, y, p) in image.enumerate_pixels() {
        let inside = (41..48).contains(&x) && (8..15).contains(&y);
        let outside = !(40..=48).contains(&x) || !(7..=15).contains(&y);
        if inside {
            assert!(p[0] > 200, "pixel ({x}, {y}) should be lit");
        } else if outside {
            assert!(p[0] < 10, "pixel ({x}, {y}) should be background");
        }
    }
    // A camera rotated 90 degrees about z maps world (x, y) to (-y, x):
    // upper left. A mirrored camera (Scale -1 1 1) also puts it upper left.
    for camera in ["Rotate 90 0 0 1", "Scale -1 1 1"] {
        let moved = text.replace("WorldBegin", &format!("{camera}\nWorldBegin"));
        let q = quadrants(&RibScene::from_text(&moved, "q.rib").unwrap());
        assert!(q[0] > 40 && q[1] + q[2] + q[3] == 0, "{camera}: {q:?}");
    }
    // Translate 0 -3 0 before WorldBegin moves the world down: lower right.
    let moved = text.replace("WorldBegin", "Translate 0 -3 0\nWorldBegin");
    let q = quadrants(&RibScene::from_text(&moved, "q.rib").unwrap());
    assert!(q[3] > 40 && q[0] + q[1] + q[2] == 0, "{q:?}");
}

#[test]
fn sides_one_shows_the_front_clockwise_on_screen() {
    let text = std::fs::read_to_string(data("quadrant.rib")).unwrap();
    let one = text.replace("Color [1 1 1]", "Sides 1");
    let lit = |t: &str| quadrants(&RibScene::from_text(t, "s.rib").unwrap())[1];
    // The vertices go up, right, down on screen: clockwise, the front.
    assert!(lit(&one) > 40);
    let reversed = one.replace("1 1 5  1 2 5  2 2 5  2 1 5", "2 1 5  2 2 5  1 2 5  1 1 5");
    assert_eq!(lit(&reversed), 0);
    assert!(lit(&reversed.replace("Sides 1", "Sides 1 ReverseOrientation")) > 40);
    assert!(lit(&reversed.replace("Sides 1", "Sides 1 Orientation \"rh\"")) > 40);
    // A mirroring transform does not change which side is the front.
    let mirrored = one.replace("Sides 1", "Sides 1 Scale 1 1 -1 Translate 0 0 -10");
    assert!(lit(&mirrored) > 40);
}

/// `PixelSamples` maps to a `k x k` grid up to 16 x 16 (256 samples).
#[test]
fn pixel_samples_go_to_16_by_16() {
    let spp = |x: u32, y: u32| {
        let text = format!(
            "Format 8 8 1\nPixelSamples {x} {y}\nWorldBegin\nPolygon \"P\" [0 0 5 0 1 5 1 1 5]\nWorldEnd\n"
        );
        RibScene::from_text(&text, "o.rib").unwrap().scene.spp
    };
    assert_eq!(spp(10, 10), 100);
    assert_eq!(spp(16, 16), 256);
    assert_eq!(spp(20, 20), 256, "clamped to the largest grid");
}

#[test]
fn options_are_mapped() {
    let text = "Format 30 60 1\nPixelSamples 3 2\nShadingRate 4\nProjection \"perspective\" \"fov\" 40\n\
        Clipping 0.5 50\nShadingInterpolation \"constant\"\nShutter 0 0.5\nDepthOfField 2 0.1 5\nPixelFilter \"catmull-rom\" 3 4\n\
        Hider \"raytrace\"\nHider \"hidden\"\nWorldBegin\nMotionBegin [0 1]\nTranslate 0 0 0\nTranslate 1 0 0\nMotionEnd\n\
        Polygon \"P\" [0 0 5 0 1 5 1 1 5]\nWorldEnd\n";
    let rib = RibScene::from_text(text, "o.rib").unwrap();
    let s = &rib.scene;
    assert_eq!((s.resolution.width, s.resolution.height), (30, 60));
    assert_eq!(s.spp, 4);
    assert_eq!(s.shading_rate, 4.0);
    assert_eq!(
        s.shading_interpolation,
        reyes::scene::ShadingInterpolation::Constant
    );
    let camera = s.camera.unwrap();
    let expected = 2.0 * (20f32.to_radians().tan() * 2.0).atan().to_degrees();
    assert!(
        (camera.fov_y_degrees - expected).abs() < 1e-3,
        "{}",
        camera.fov_y_degrees
    );
    assert_eq!((camera.near, camera.far), (0.5, 50.0));
    assert_eq!(s.shutter, 0.5);
    assert!((s.lens.aperture - 0.025).abs() < 1e-7);
    assert_eq!(s.lens.focus_distance, Some(5.0));
    let close = s.objects[0].transform_close.expect("moving");
    assert!(
        (close.translate - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6,
        "{close:?}"
    );
    let warnings: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let all = warnings.join("\n");
    assert!(all.contains("PixelSamples 3 2"), "{all}");
    assert_eq!(
        s.pixel_filter,
        reyes::filter::PixelFilter {
            filter: reyes::filter::FilterKind::CatmullRom,
            xwidth: 3.0,
            ywidth: 4.0
        }
    );
    assert!(!all.contains("PixelFilter"), "{all}");
    // The hidden hider is the renderer's; another one warns.
    assert_eq!(all.matches("Hider").count(), 1, "{all}");
    assert!(
        all.contains("o.rib:10: Hider \"raytrace\": the renderer has the \"hidden\" hider only"),
        "{all}"
    );
}

#[test]
fn unsupported_geometry_warns_and_the_rest_renders() {
    let text = std::fs::read_to_string(data("quadrant.rib"))
        .unwrap()
        .replace("Color [1 1 1]", "Color [1 1 1]\n  Blobby 0 [] [] []\n  NuPatch 4 4 [0 0 0 0 1 1 1 1] 0 1 4 4 [0 0 0 0 1 1 1 1] 0 1 \"Pw\" [0 0 0 1]\n  Patch \"bilinear\" \"Pw\" [0 0 0 1 1 0 0 1 0 1 0 1 1 1 0 1]");
    let rib = RibScene::from_text(&text, "u.rib").unwrap();
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let all = all.join("\n");
    assert!(all.contains("u.rib:13: Blobby is not supported"), "{all}");
    assert!(all.contains("u.rib:14: NuPatch is not supported"), "{all}");
    assert!(all.contains("u.rib:15: Patch with \"Pw\""), "{all}");
    assert_eq!(quadrants(&rib), [0, 81, 0, 0]);
}

#[test]
fn convert_round_trip_renders_the_same_image() {
    let dir = temp_dir("convert");
    let rib = RibScene::load(data("scene.rib")).unwrap();
    assert!(rib.scene.objects.len() >= 2);
    let toml = dir.join("scene.toml");
    let written = rib.write(&toml).unwrap();
    assert!(
        written
            .iter()
            .any(|p| p.extension().is_some_and(|e| e == "bpt"))
    );
    let scene = Scene::load(&toml).unwrap();
    let from_toml = reyes::reference::render(&PreparedScene::load(&scene).unwrap()).image;
    let from_rib = reyes::reference::render(&rib.prepare().unwrap()).image;
    assert_eq!(from_toml.dimensions(), (48, 36));
    assert!(
        from_rib.pixels().filter(|p| p[0] > 30).count() > 100,
        "the scene is visible"
    );
    assert!(
        from_toml == from_rib,
        "the converted scene renders differently"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn cli_renders_and_converts_rib() {
    let dir = temp_dir("cli");
    let exe = env!("CARGO_BIN_EXE_reyes");
    let png = dir.join("out.png");
    let child = std::process::Command::new(exe)
        .args(["render", "--cpu", "-o"])
        .arg(&png)
        .arg(data("scene.rib"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // `render` keeps the RIB's models in memory: it writes only the image.
    let out = child.wait_with_output().unwrap();
    let written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(written, ["out.png"], "render wrote only the image");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        String::from_utf8_lossy(&out.stderr)
            .contains("Hider parameter \"jitter\" is not supported")
    );
    let toml = dir.join("conv.toml");
    let out = std::process::Command::new(exe)
        .args(["convert"])
        .arg(data("scene.rib"))
        .arg("-o")
        .arg(&toml)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(dir.join("conv-0.bpt").exists() && toml.exists());
    let png2 = dir.join("conv.png");
    let out = std::process::Command::new(exe)
        .args(["render", "--cpu", "-o"])
        .arg(&png2)
        .arg(&toml)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        image::open(&png).unwrap().to_rgba8(),
        image::open(&png2).unwrap().to_rgba8()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mutated_rib_never_panics() {
    let mut rng = fresh_rng("mutated_rib_never_panics");
    let base = std::fs::read(data("scene.rib")).unwrap();
    let interesting = b"[]\"#-+.eE0123456789 \n\\PWorldBeginEndAttribute";
    let deadline = Instant::now() + Duration::from_secs(3);
    let (mut runs, mut parsed) = (0, 0);
    while Instant::now() < deadline {
        let mut bytes = base.clone();
        for _ in 0..rng.random_range(1..8) {
            let at = rng.random_range(0..bytes.len().max(1));
            match rng.random_range(0..5) {
                0 => bytes[at] = rng.random(),
                1 => bytes[at] = interesting[rng.random_range(0..interesting.len())],
                2 => bytes.insert(at, interesting[rng.random_range(0..interesting.len())]),
                3 => {
                    let end = (at + rng.random_range(1..40)).min(bytes.len());
                    bytes.drain(at..end);
                }
                _ => {
                    let end = (at + rng.random_range(1..60)).min(bytes.len());
                    let chunk = bytes[at..end].to_vec();
                    let to = rng.random_range(0..bytes.len());
                    bytes.splice(to..to, chunk);
                }
            }
            if bytes.is_empty() {
                bytes.push(b' ');
            }
        }
        runs += 1;
        if let Ok(rib) = RibScene::from_bytes(&bytes, Path::new("fuzz.rib")) {
            parsed += 1;
            let r = rib.scene.resolution;
            if let Ok(prepared) = rib.prepare()
                && u64::from(r.width) * u64::from(r.height) <= 64 * 64
                && rib.scene.spp <= 16
            {
                let _ = reyes::reference::try_render(&prepared);
            }
        }
    }
    eprintln!("{runs} mutations, {parsed} parsed");
    assert!(runs > 10);
}

#[test]
fn transforms_stack_and_motion_maps_to_transform_close() {
    let text = "Projection \"perspective\"\nTranslate 0 0 10\nWorldBegin\n\
        TransformBegin\nTranslate 1 0 0\nAttributeBegin\nScale 2 2 2\nColor [1 0 0]\n\
        Polygon \"P\" [0 0 0 0 1 0 1 1 0]\nAttributeEnd\n\
        Polygon \"P\" [0 0 0 0 1 0 1 1 0]\nTransformEnd\n\
        Identity\nConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 3 0 1]\n\
        Polygon \"P\" [0 0 0 0 1 0 1 1 0]\n\
        MotionBegin [0 1]\nRotate 0 0 0 1\nRotate 30 0 0 1\nMotionEnd\n\
        Polygon \"P\" [0 0 0 0 1 0 1 1 0]\nWorldEnd\n";
    let rib = RibScene::from_text(text, "t.rib").unwrap();
    // Consecutive primitives that look the same share one object.
    let corner = |object: usize, patch: usize| rib.models[object].patches[patch].points[15];
    // Object 0: scaled by 2 and moved by 1, red; then one only moved, and
    // one moved up by 3 from the world origin (Identity is world space),
    // all 10 in front of the camera, x mirrored.
    assert_eq!(rib.scene.objects[0].color, Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(rib.models.len(), 3);
    assert!(
        (corner(0, 0) - Vec3::new(-3.0, 2.0, 10.0)).length() < 1e-6,
        "{}",
        corner(0, 0)
    );
    assert!(
        (corner(1, 0) - Vec3::new(-2.0, 1.0, 10.0)).length() < 1e-6,
        "{}",
        corner(1, 0)
    );
    assert!(
        (corner(1, 1) - Vec3::new(-1.0, 4.0, 10.0)).length() < 1e-6,
        "{}",
        corner(1, 1)
    );
    // A 30 degree turn about camera z is -30 degrees in the mirrored world.
    let close = rib.scene.objects[2].transform_close.expect("moving");
    assert!(
        (close.rotate_degrees - Vec3::new(0.0, 0.0, -30.0)).length() < 1e-3,
        "{close:?}"
    );
    let mismatched = "WorldBegin\nAttributeBegin\nTransformEnd\n";
    assert_eq!(parse_error(mismatched).position(), Some((3, 1)));
    assert_eq!(
        parse_error("WorldBegin\nAttributeEnd\n").position(),
        Some((2, 1))
    );
}

#[test]
fn warnings_are_capped() {
    let text = format!(
        "WorldBegin\n{}WorldEnd\n",
        "Points \"P\" [0 0 1]\n".repeat(500)
    );
    let rib = RibScene::from_text(&text, "w.rib").unwrap();
    let shown: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let points = shown.iter().filter(|w| w.contains("Points")).count();
    assert_eq!(points, reyes::rib::interp::MAX_WARNINGS);
    assert!(
        shown
            .iter()
            .any(|w| w.contains("400 more warnings not shown")),
        "{shown:?}"
    );
}

#[test]
fn non_convex_polygons_warn() {
    // Each text ends its world block: a missing WorldEnd is an error.
    let base = "Projection \"perspective\"\nWorldBegin\n";
    let convex = format!("{base}Polygon \"P\" [0 0 5  0 1 5  1 1 5  1.5 0.5 5  1 0 5]\nWorldEnd\n");
    assert!(
        RibScene::from_text(&convex, "c.rib")
            .unwrap()
            .warnings
            .iter()
            .all(|w| !w.message.contains("convex"))
    );
    let dart = format!("{base}Polygon \"P\" [0 0 5  0 1 5  0.3 0.5 5  1 0 5]\nWorldEnd\n");
    let rib = RibScene::from_text(&dart, "d.rib").unwrap();
    assert!(
        rib.warnings
            .iter()
            .any(|w| w.to_string().contains("d.rib:3: Polygon is not convex")),
        "{:?}",
        rib.warnings
    );
}

#[test]
fn camera_motion_maps_to_camera_close() {
    let scene = |motion: &str| {
        let text = format!(
            "Projection \"perspective\"\nShutter 0 1\nMotionBegin [0 1]\n{motion}\nMotionEnd\nWorldBegin\n\
             Polygon \"P\" [0 0 5 0 1 5 1 1 5]\nWorldEnd\n"
        );
        RibScene::from_text(&text, "m.rib").unwrap()
    };
    // The world moves +x (right) in camera space: the camera moves to the
    // image's left, which is +x in the mirrored world.
    let rib = scene("Translate 0 0 0\nTranslate 1 0 0");
    let close = rib.scene.camera_close.expect("the camera moves");
    assert!((close.eye - Vec3::X).length() < 1e-6, "{close:?}");
    assert!(
        (close.target - Vec3::new(1.0, 0.0, 1.0)).length() < 1e-6,
        "{close:?}"
    );
    assert!((close.up.unwrap() - Vec3::Y).length() < 1e-6, "{close:?}");
    assert_eq!(rib.scene.shutter, 1.0);
    let rib = scene("Scale 1 1 1\nScale 2 2 2");
    assert!(rib.scene.camera_close.is_none());
    assert!(
        rib.warnings.iter().any(|w| w
            .to_string()
            .contains("m.rib:7: the camera's motion is not rigid")),
        "{:?}",
        rib.warnings
    );
}

/// The gallery scene of docs/rib.md reads with no warning but the ones
/// that its matte and plastic surfaces share one specular and one ambient
/// term.
#[test]
fn the_gallery_scene_reads_with_only_the_scene_wide_shading_warnings() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../docs/scenes/gallery.rib");
    let rib = reyes::rib::RibScene::load(&path).unwrap();
    assert!(
        rib.warnings
            .iter()
            .all(|w| w.message.contains("one specular term")
                || w.message.contains("one ambient term")),
        "{:?}",
        rib.warnings
    );
    // One object per attribute block: the cone and its disk share one.
    assert_eq!(rib.scene.objects.len(), 8);
    assert_eq!(rib.display.as_deref(), Some("rib-gallery.png"));
}

/// The patches of the only object of `text`, read as `name`.
fn patches_of(text: &str, name: &str) -> Vec<[Vec3; 16]> {
    let rib = RibScene::from_text(text, name).unwrap();
    rib.models
        .iter()
        .flat_map(|m| m.patches.iter().map(|p| p.points))
        .collect()
}

fn assert_same_patches(a: &[[Vec3; 16]], b: &[[Vec3; 16]], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (pa, pb) in a.iter().zip(b) {
        for (x, y) in pa.iter().zip(pb) {
            assert!((*x - *y).length() < 1e-5, "{what}: {x} != {y}");
        }
    }
}

#[test]
fn points_polygons_cube_lies_on_the_cube() {
    let corners: Vec<DVec3> = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { -1.0 } else { 1.0 },
                if i & 2 == 0 { -1.0 } else { 1.0 },
                if i & 4 == 0 { -1.0 } else { 1.0 },
            )
        })
        .collect();
    let faces: [[usize; 4]; 6] = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let ids = fmt_nums(faces.iter().flatten().map(|&i| i as f64));
    let points = fmt_nums(corners.iter().flat_map(|c| [c.x, c.y, c.z]));
    let text = format!(
        "Projection \"perspective\"\nWorldBegin\nTranslate 0 0 10\n\
         PointsPolygons [4 4 4 4 4 4] [{ids}] \"P\" [{points}]\nWorldEnd\n"
    );
    let patches = patches_of(&text, "cube.rib");
    assert_eq!(patches.len(), 6);
    // The renderer's world is camera space with x mirrored.
    let world = |p: DVec3| Vec3::new(-p.x as f32, p.y as f32, p.z as f32 + 10.0);
    let mut rng = fresh_rng("points_polygons_cube_lies_on_the_cube");
    for (face, patch) in faces.iter().zip(&patches) {
        let [a, b, c, d] = face.map(|i| corners[i]);
        // The fan's quad (a, b, c, d): u from a to b, v from a to d.
        let exact = |u: f64, v: f64| {
            world(a * (1.0 - u) * (1.0 - v) + b * u * (1.0 - v) + d * (1.0 - u) * v + c * u * v)
        };
        let mut uvs = vec![(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
        uvs.extend((0..50).map(|_| (rng.random::<f64>(), rng.random::<f64>())));
        // The face's constant axis.
        let axis = (0..3)
            .find(|&k| a[k] == b[k] && b[k] == c[k] && c[k] == d[k])
            .unwrap();
        for (u, v) in uvs {
            let got = reyes::bezier::position(patch, u as f32, v as f32);
            let want = exact(u, v);
            assert!(
                (got - want).length() < 1e-5,
                "{face:?} ({u}, {v}): {got} != {want}"
            );
            let local = DVec3::new(f64::from(-got.x), f64::from(got.y), f64::from(got.z) - 10.0);
            assert!((local[axis].abs() - 1.0).abs() < 1e-5, "{local}");
            assert!(local.abs().max_element() < 1.0 + 1e-5, "{local}");
        }
    }
}

#[test]
fn points_polygons_and_general_polygon_counts_are_checked() {
    // Each text ends its world block: a missing WorldEnd is an error.
    let base = "Projection \"perspective\"\nWorldBegin\n";
    let p4 = "\"P\" [0 0 5 0 1 5 1 1 5 1 0 5]";
    let cases = [
        (format!("PointsPolygons [4] [0 1 2 4] {p4}"), "out of range"),
        (
            format!("PointsPolygons [4] [0 1 -2 3] {p4}"),
            "not a non-negative integer",
        ),
        (
            format!("PointsPolygons [4 3] [0 1 2 3] {p4}"),
            "add up to 7",
        ),
        (format!("PointsPolygons [2] [0 1] {p4}"), "at least 3"),
        (format!("GeneralPolygon [3] {p4}"), "\"P\" has 4 points"),
        (format!("GeneralPolygon [] {p4}"), "no loops"),
    ];
    for (request, message) in cases {
        let error = parse_error(&format!("{base}\n{request}\nWorldEnd\n"));
        let shown = error.to_string();
        assert_eq!(error.position(), Some((4, 1)), "{shown}");
        assert!(shown.contains(message), "{request}: {shown}");
    }
    // One loop is a Polygon; so is each polygon of PointsPolygons.
    let polygon = patches_of(&format!("{base}Polygon {p4}\nWorldEnd\n"), "p.rib");
    let general = patches_of(
        &format!("{base}GeneralPolygon [4] {p4}\nWorldEnd\n"),
        "g.rib",
    );
    assert_same_patches(&polygon, &general, "GeneralPolygon");
    let indexed = patches_of(
        &format!("{base}PointsPolygons [3] [3 2 1] {p4}\nWorldEnd\n"),
        "i.rib",
    );
    let triangle = patches_of(
        &format!("{base}Polygon \"P\" [1 0 5 1 1 5 0 1 5]\nWorldEnd\n"),
        "t.rib",
    );
    assert_same_patches(&indexed, &triangle, "PointsPolygons");
}

#[test]
fn general_polygon_with_holes_warns_and_the_rest_renders() {
    let text = std::fs::read_to_string(data("quadrant.rib")).unwrap().replace(
        "Color [1 1 1]",
        "Color [1 1 1]\n  GeneralPolygon [4 3] \"P\" [-2 -2 5 -2 -1 5 -1 -1 5 -1 -2 5  -1.8 -1.8 5 -1.5 -1.2 5 -1.2 -1.8 5]",
    );
    let rib = RibScene::from_text(&text, "h.rib").unwrap();
    let all: Vec<String> = rib.warnings.iter().map(ToString::to_string).collect();
    let all = all.join("\n");
    assert!(
        all.contains("h.rib:13: GeneralPolygon with more than one loop: holes are not supported"),
        "{all}"
    );
    assert_eq!(quadrants(&rib), [0, 81, 0, 0]);
}

#[test]
fn skew_matches_the_hand_derived_matrix() {
    let scene = |transform: &str| {
        format!(
            "Projection \"perspective\"\nWorldBegin\nTranslate 0 0 10\n{transform}\n\
             Patch \"bilinear\" \"P\" [0 0 0  1 0 0  0 1 0  1 1 1]\nWorldEnd\n"
        )
    };
    // Skew 45 with d1 = y, d2 = x: y turns 45 degrees towards x, so x' =
    // x + y (RenderMan's row-vector matrix has row 1 = (1 1 0 0)).
    let skewed = patches_of(&scene("Skew 45 0 1 0 1 0 0"), "s.rib");
    let matrix = patches_of(
        &scene("ConcatTransform [1 0 0 0  1 1 0 0  0 0 1 0  0 0 0 1]"),
        "m.rib",
    );
    assert_same_patches(&skewed, &matrix, "Skew 45");
    // (0 1 0) -> (1 1 0), x mirrored in the world.
    assert!((skewed[0][12] - Vec3::new(-1.0, 1.0, 10.0)).length() < 1e-6);
    // 30 degrees: y goes to (tan 30, 1, 0), 30 degrees from y.
    let thirty = patches_of(&scene("Skew 30 0 2 0 3 0 0"), "t.rib");
    let y = thirty[0][12] - Vec3::new(0.0, 0.0, 10.0);
    assert!(
        (-y.x - 30f32.to_radians().tan()).abs() < 1e-6 && (y.y - 1.0).abs() < 1e-6,
        "{y}"
    );
    // The angle must be less than the angle between the axes (90 here).
    for bad in [
        "Skew 90 0 1 0 1 0 0",
        "Skew -90 0 1 0 1 0 0",
        "Skew 10 1 0 0 2 0 0",
    ] {
        let error = parse_error(&scene(bad));
        assert_eq!(error.position(), Some((4, 1)), "{bad}: {error}");
    }
}

#[test]
fn coordinate_systems_are_saved_and_restored() {
    let scene = |body: &str| {
        format!(
            "Projection \"perspective\"\nTranslate 0 0 10\nWorldBegin\n{body}\n\
             Patch \"bilinear\" \"P\" [0 0 0  1 0 0  0 1 0  1 1 1]\nWorldEnd\n"
        )
    };
    let placed = patches_of(
        &scene(
            "TransformBegin\nTranslate 2 0 0\nRotate 90 0 0 1\nCoordinateSystem \"mine\"\nTransformEnd\n\
             Translate 5 5 5\nCoordSysTransform \"mine\"",
        ),
        "c.rib",
    );
    let direct = patches_of(&scene("Translate 2 0 0\nRotate 90 0 0 1"), "d.rib");
    assert_same_patches(&placed, &direct, "CoordSysTransform");
    // The corner (1 0 0) turns to (0 1 0), moves to (2 1 0), then 10 away
    // from the camera, x mirrored.
    assert!(
        (placed[0][3] - Vec3::new(-2.0, 1.0, 10.0)).length() < 1e-6,
        "{}",
        placed[0][3]
    );
    // "world" is the space at WorldBegin; "camera" the camera's.
    let world = patches_of(
        &scene("Translate 3 0 0\nCoordSysTransform \"world\""),
        "w.rib",
    );
    assert_same_patches(&world, &patches_of(&scene(""), "e.rib"), "world");
    let camera = patches_of(
        &scene("Translate 3 0 0\nCoordSysTransform \"camera\""),
        "k.rib",
    );
    assert!(
        (camera[0][3] - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6,
        "{}",
        camera[0][3]
    );
    let error = parse_error(&scene("CoordSysTransform \"nowhere\""));
    assert_eq!(error.position(), Some((4, 1)), "{error}");
    assert!(
        error
            .to_string()
            .contains("unknown coordinate system \"nowhere\""),
        "{error}"
    );
}

#[test]
fn points_general_polygons_skip_only_the_polygons_with_holes() {
    // Each text ends its world block: a missing WorldEnd is an error.
    let base = "Projection \"perspective\"\nWorldBegin\n";
    let p = "\"P\" [0 0 5 0 1 5 1 1 5 1 0 5  2 0 5 2 1 5 3 1 5]";
    let text = format!(
        "{base}PointsGeneralPolygons [1 2] [4 4 3] [0 1 2 3  0 1 2 3  4 5 6] {p}\nWorldEnd\n"
    );
    let rib = RibScene::from_text(&text, "pg.rib").unwrap();
    assert!(
        rib.warnings.iter().any(|w| w
            .to_string()
            .contains("pg.rib:3: PointsGeneralPolygons: 1 polygon(s) with more than one loop")),
        "{:?}",
        rib.warnings
    );
    let got = patches_of(&text, "pg.rib");
    let quad = patches_of(
        &format!("{base}Polygon \"P\" [0 0 5 0 1 5 1 1 5 1 0 5]\nWorldEnd\n"),
        "q.rib",
    );
    assert_same_patches(&got, &quad, "PointsGeneralPolygons");
    for (request, message) in [
        ("[1] [4] [0 1 2 7]", "out of range"),
        ("[2] [4] [0 1 2 3]", "nloops do not add up"),
        ("[1] [4] [0 1 2]", "nverts do not add up"),
        ("[0 1] [4] [0 1 2 3]", "no loops"),
    ] {
        let error = parse_error(&format!(
            "{base}PointsGeneralPolygons {request} {p}\nWorldEnd\n"
        ));
        assert_eq!(error.position(), Some((3, 1)), "{error}");
        assert!(error.to_string().contains(message), "{request}: {error}");
    }
}
