//! Bounded amplification (issue 42, item 2): a few bytes of input that ask
//! for many patches are refused at the request that passes the patch
//! budget (`--max-patches`), before the patches are made, and within a
//! stated multiple of the budget's bytes. Each run's peak memory (the
//! child's own, from `wait4`) and time are printed.

mod files;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use files::{TempDir, run_cli};

/// The default budget (`reyes::budget::DEFAULT_MAX_PATCHES`), written out.
const DEFAULT_BUDGET: usize = 1 << 20;
/// The bytes of one patch: 16 points of 3 `f32`.
const PATCH_BYTES: u64 = 16 * 3 * 4;
/// The documented multiple (`reyes::budget::MEMORY_MULTIPLE`).
const MEMORY_MULTIPLE: u64 = 3;
/// A tiny CPU frame.
const TINY: [&str; 7] = ["--cpu", "--width", "16", "--height", "12", "--spp", "1"];

fn path_str(path: &Path) -> &str {
    path.to_str().expect("temp paths are UTF-8")
}

/// What a measured run did.
struct Run {
    ok: bool,
    stderr: String,
    /// Peak resident memory of the child, in KiB.
    peak_kib: u64,
    wall: Duration,
}

/// Runs `reyes args`, measuring the child's own peak resident memory
/// (`wait4`'s `ru_maxrss`) and wall time; killed after a minute.
#[cfg(target_os = "linux")]
fn measured(args: &[&str]) -> Run {
    measured_with(args, &[])
}

/// [`measured`] with the environment variables `unset` removed.
#[cfg(target_os = "linux")]
fn measured_with(args: &[&str], unset: &[&str]) -> Run {
    use std::io::Read;
    let start = Instant::now();
    let mut command = Command::new(env!("CARGO_BIN_EXE_reyes"));
    for name in unset {
        command.env_remove(name);
    }
    #[expect(
        clippy::zombie_processes,
        reason = "reaped by wait4 below, which also reads its peak memory"
    )]
    let mut child = command
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the command starts");
    let mut pipe = child.stderr.take().unwrap();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        let _ = pipe.read_to_string(&mut text);
        text
    });
    let pid = libc::pid_t::try_from(child.id()).expect("a pid fits pid_t");
    let (status, usage) = loop {
        let mut status = 0;
        // SAFETY: both pointers are to locals of the right types.
        #[expect(
            unsafe_code,
            reason = "wait4 is the only way to read one child's peak memory"
        )]
        let (done, usage) = unsafe {
            let mut usage: libc::rusage = std::mem::zeroed();
            (
                libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage),
                usage,
            )
        };
        if done == pid {
            break (status, usage);
        }
        assert!(done == 0, "wait4 failed");
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("reyes {args:?} ran for more than a minute");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let wall = start.elapsed();
    Run {
        ok: libc::WIFEXITED(status) && libc::WEXITSTATUS(status) == 0,
        stderr: reader.join().unwrap(),
        peak_kib: u64::try_from(usage.ru_maxrss).unwrap(),
        wall,
    }
}

/// `WorldBegin`, `n` lines of `sphere`, `WorldEnd`, after `options`.
fn spheres(options: &str, n: usize, sphere: &str) -> String {
    let mut text = format!("{options}WorldBegin\n");
    for _ in 0..n {
        text.push_str(sphere);
        text.push('\n');
    }
    text + "WorldEnd\n"
}

const HUGE_SPHERE: &str = "Sphere 1e12 -1e12 1e12 360";

#[cfg(target_os = "linux")]
#[test]
fn four_thousand_huge_spheres_are_refused_within_a_gigabyte_and_ten_seconds() {
    let dir = TempDir::new("budget-spheres");
    let rib = dir.path("spheres.rib");
    // RenderMan's default camera (orthographic, the screen window 2 units
    // high): no 64 x 64 segments bring a 1e12 sphere within 0.1 pixel, so
    // each takes the most, 4096 patches.
    std::fs::write(&rib, spheres("", 4096, HUGE_SPHERE)).unwrap();
    let per_sphere = 64 * 64;
    // The first sphere past the budget, and its line (after WorldBegin).
    let refused = DEFAULT_BUDGET / per_sphere + 1;
    let expected = format!(
        "{}:{}:1: Sphere: 64 x 64 segments: 4096 patches",
        path_str(&rib),
        refused + 1
    );
    let out = dir.path("out.png");
    let toml = dir.path("out.toml");
    for (command, args) in [
        (
            "render --cpu",
            vec!["render", "--cpu", path_str(&rib), "-o", path_str(&out)],
        ),
        (
            "convert",
            vec!["convert", path_str(&rib), "-o", path_str(&toml)],
        ),
    ] {
        let run = measured(&args);
        println!(
            "{command}: exit ok {}, peak {} MiB, {:.2} s: {}",
            run.ok,
            run.peak_kib / 1024,
            run.wall.as_secs_f64(),
            run.stderr.trim()
        );
        assert!(!run.ok, "{command}: {}", run.stderr);
        assert!(
            run.stderr.contains(&expected) && run.stderr.contains("--max-patches"),
            "{command}: expected {expected:?} in {}",
            run.stderr
        );
        assert!(
            run.peak_kib < 1 << 20,
            "{command}: peak {} KiB",
            run.peak_kib
        );
        assert!(
            run.wall < Duration::from_secs(10),
            "{command}: {:?}",
            run.wall
        );
        assert!(!out.exists() && !toml.exists(), "{command} wrote an output");
    }
}

#[test]
fn a_sphere_around_the_camera_takes_the_same_segments_at_any_radius() {
    // The camera at the centre, perspective: the surface is at distance r
    // in every direction, so the pixel there grows with r as the error
    // does. (The bounding sphere of the whole sphere holds the eye: its
    // nearest depth was the near plane, and a radius of 1e12 took 64 x 64
    // segments.)
    let counts: Vec<usize> = ["1", "1000", "1e12"]
        .iter()
        .map(|r| {
            let text = spheres(
                "Projection \"perspective\" \"fov\" 45\nFormat 640 480 1\n",
                1,
                &format!("Sphere {r} -{r} {r} 360"),
            );
            let scene = reyes::rib::RibScene::from_text(&text, "t.rib").unwrap();
            assert!(scene.warnings.is_empty(), "{r}: {:?}", scene.warnings);
            scene.models[0].patches.len()
        })
        .collect();
    println!("patches for radius 1, 1000, 1e12: {counts:?}");
    assert!(counts.iter().all(|&c| c == counts[0]), "{counts:?}");
    assert!(counts[0] <= 64, "{counts:?}");
}

#[test]
fn each_kind_of_rib_request_is_counted_before_it_is_made() {
    let dir = TempDir::new("budget-requests");
    let out = dir.path("out.png");
    // (request, the patches it makes): counted independently of the
    // converter (a polygon of n vertices is a fan of (n - 1) / 2 patches).
    let cases = [
        (
            "Polygon \"P\" [0 0 0 1 0 0 1 1 0 0.5 1.5 0 0 1 0]",
            2,
            "its fan: 2 patches",
        ),
        (
            "PointsPolygons [3 4 5] [0 1 2 0 1 2 3 0 1 2 3 4] \"P\" [0 0 0 1 0 0 1 1 0 0.5 1.5 0 0 1 0]",
            1 + 1 + 2,
            "their fans: 4 patches",
        ),
        (
            "PatchMesh \"bilinear\" 3 \"nonperiodic\" 3 \"nonperiodic\" \"P\" [0 0 0 1 0 0 2 0 0 0 1 0 1 1 0 2 1 0 0 2 0 1 2 0 2 2 0]",
            4,
            "2 x 2 patches: 4 patches",
        ),
        ("Sphere 1 -1 1 360", 8, "segments: "),
    ];
    for (request, patches, what) in cases {
        let scene = dir.path("one.rib");
        let text = format!("Format 16 12 1\nWorldBegin\nTranslate 0 0 5\n{request}\nWorldEnd\n");
        std::fs::write(&scene, &text).unwrap();
        // One patch short: refused at the request, naming it and its line.
        let short = (patches - 1).to_string();
        let mut args = vec!["render", path_str(&scene)];
        args.extend(TINY);
        args.extend(["-o", path_str(&out), "--max-patches", &short]);
        let (ok, stderr) = run_cli(&args);
        let name = request.split(' ').next().unwrap();
        let at = format!("{}:4:1: {name}: ", path_str(&scene));
        assert!(
            !ok && stderr.contains(&at) && stderr.contains(what),
            "{request}: {stderr}"
        );
        // Enough: rendered.
        let enough = (patches + 8).to_string();
        let mut args = vec!["render", path_str(&scene)];
        args.extend(TINY);
        args.extend(["-o", path_str(&out), "--max-patches", &enough]);
        let (ok, stderr) = run_cli(&args);
        assert!(ok, "{request}: {stderr}");
    }
}

#[test]
fn modest_requests_add_up_to_the_budget() {
    // 100 unit squares, each one patch: the 11th passes a budget of 10.
    let dir = TempDir::new("budget-total");
    let scene = dir.path("many.rib");
    let mut text = String::from("WorldBegin\nTranslate 0 0 5\n");
    for _ in 0..100 {
        text.push_str("Patch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n");
    }
    text.push_str("WorldEnd\n");
    std::fs::write(&scene, text).unwrap();
    let toml = dir.path("many.toml");
    let (ok, stderr) = run_cli(&[
        "convert",
        path_str(&scene),
        "-o",
        path_str(&toml),
        "--max-patches",
        "10",
    ]);
    assert!(!ok && !toml.exists(), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "{}:13:1: Patch: 1 patches (0.0 MiB) would bring the scene to 11 patches, over the budget of 10",
            path_str(&scene)
        )),
        "{stderr}"
    );
}

#[test]
fn model_files_are_counted_per_object_and_for_the_scene() {
    let dir = TempDir::new("budget-models");
    let teapot = dir.path("teapot.bpt");
    // 32 patches.
    std::fs::write(
        &teapot,
        reyes::load::bpt::write(&reyes::model::Model::teapot()),
    )
    .unwrap();
    let out = dir.path("out.png");
    // A bare model past the budget: its file and the count's line.
    let mut args = vec!["render", path_str(&teapot)];
    args.extend(TINY);
    args.extend(["-o", path_str(&out), "--max-patches", "31"]);
    let (ok, stderr) = run_cli(&args);
    assert!(
        !ok && stderr.contains(&format!(
            "{}: line 1: the declared patch count: 32 patches",
            path_str(&teapot)
        )),
        "{stderr}"
    );
    // Four objects of 32 patches: the fourth passes 100, named with its model.
    let scene = dir.path("four.toml");
    std::fs::write(&scene, "[[objects]]\nmodel = \"teapot.bpt\"\n".repeat(4)).unwrap();
    let mut args = vec!["render", path_str(&scene)];
    args.extend(TINY);
    args.extend(["-o", path_str(&out), "--max-patches", "100"]);
    let (ok, stderr) = run_cli(&args);
    assert!(
        !ok && stderr.contains(
            "object 3 (model \"teapot.bpt\"): line 1: the declared patch count: 32 patches (0.0 MiB) would bring the scene to 128 patches, over the budget of 100"
        ),
        "{stderr}"
    );
    args.pop();
    args.push("128");
    let (ok, stderr) = run_cli(&args);
    assert!(ok, "{stderr}");
}

#[cfg(target_os = "linux")]
#[test]
fn memory_stays_within_the_stated_multiple_of_the_budget() {
    // 64 spheres of 4096 patches, exactly the budget given: the scene is
    // read, converted and prepared whole.
    let dir = TempDir::new("budget-memory");
    let budget: u64 = 64 * 4096;
    let rib = dir.path("full.rib");
    std::fs::write(&rib, spheres("Format 16 12 1\n", 64, HUGE_SPHERE)).unwrap();
    let small = dir.path("small.rib");
    std::fs::write(&small, spheres("Format 16 12 1\n", 1, "Sphere 1 -1 1 360")).unwrap();
    let out = dir.path("out.png");
    let toml = dir.path("out.toml");
    let limit = budget.to_string();
    let estimate_kib = budget * PATCH_BYTES / 1024;
    for (command, base_args, args) in [
        (
            "render --cpu",
            vec!["render", "--cpu", path_str(&small), "-o", path_str(&out)],
            vec![
                "render",
                "--cpu",
                path_str(&rib),
                "-o",
                path_str(&out),
                "--max-patches",
                &limit,
            ],
        ),
        (
            "convert",
            vec!["convert", path_str(&small), "-o", path_str(&toml)],
            vec![
                "convert",
                path_str(&rib),
                "-o",
                path_str(&toml),
                "--max-patches",
                &limit,
            ],
        ),
    ] {
        let base = measured(&base_args);
        assert!(base.ok, "{command}: {}", base.stderr);
        let run = measured(&args);
        assert!(run.ok, "{command}: {}", run.stderr);
        let over = run.peak_kib.saturating_sub(base.peak_kib);
        println!(
            "{command}: {budget} patches ({} MiB): peak {} MiB, {} MiB over a one-sphere scene's {} MiB ({:.2} x the estimate), {:.2} s",
            estimate_kib / 1024,
            run.peak_kib / 1024,
            over / 1024,
            base.peak_kib / 1024,
            over as f64 / estimate_kib as f64,
            run.wall.as_secs_f64()
        );
        assert!(
            over <= MEMORY_MULTIPLE * estimate_kib,
            "{command}: {over} KiB over the base, more than {MEMORY_MULTIPLE} x {estimate_kib} KiB"
        );
    }
}

/// A RIB file of `frames` frames, each of `polygons` squares (a patch each).
fn frames_of_squares(frames: u32, polygons: u32) -> String {
    let mut rib = String::new();
    for frame in 1..=frames {
        rib += &format!("FrameBegin {frame}\nFormat 32 24 1\nWorldBegin\nTranslate 0 0 5\n");
        for _ in 0..polygons {
            rib += "Polygon \"P\" [-1 -1 0  1 -1 0  1 1 0  -1 1 0]\n";
        }
        rib += "WorldEnd\nFrameEnd\n";
    }
    rib
}

#[cfg(all(target_os = "linux", feature = "viewer"))]
#[test]
fn the_viewer_holds_one_frame_of_a_long_file_in_memory() {
    let dir = TempDir::new("budget-view-frames");
    let (long, one) = (dir.path("long.rib"), dir.path("one.rib"));
    // 40 frames of 5,000 patches (a million bytes of control points each)
    // against one such frame: the viewer needs no more memory for frame 2
    // of the long file than for the short file's one frame.
    std::fs::write(&long, frames_of_squares(40, 5_000)).unwrap();
    std::fs::write(&one, frames_of_squares(1, 5_000)).unwrap();
    let view = |rib: &Path, frame: &str| {
        // Without a display the viewer stops at its window, after reading
        // and preparing the frame.
        let run = measured_with(
            &["view", "--frames", "1", "--frame", frame, path_str(rib)],
            &["DISPLAY", "WAYLAND_DISPLAY"],
        );
        assert!(
            run.stderr.contains("cannot open a window"),
            "{}",
            run.stderr
        );
        run.peak_kib
    };
    let (long_kib, one_kib) = (view(&long, "2"), view(&one, "1"));
    println!("peak resident: frame 2 of 40: {long_kib} KiB; the only frame: {one_kib} KiB");
    // The 39 other frames' control points alone are 37 MiB; the file's
    // text (10 MB) is read whole while the frames are planned.
    assert!(
        long_kib < one_kib + 24 * 1024,
        "frame 2 of 40 took {long_kib} KiB against {one_kib} KiB for one frame"
    );
}

/// A Catmull-Clark mesh of 7,200 triangles (a 60 x 60 grid, each square
/// cut in two) as a RIB `SubdivisionMesh` and as an OBJ model: refinement
/// stops at the first level past what the budget has left, so a budget of
/// 30,000 patches refuses it before the patches are made (it used to make
/// about 3 million patches in 35 s and 2.6 GB, and then refuse them).
#[cfg(target_os = "linux")]
#[test]
fn a_subdivision_mesh_past_the_budget_is_refused_before_it_is_made() {
    let dir = TempDir::new("budget-subdivision");
    let n = 60;
    let vertex = |i: usize, j: usize| j * (n + 1) + i;
    let mut points = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32 - 0.5, j as f32 / n as f32 - 0.5);
            points.push([x, y, 0.1 * (7.0 * x).sin() * (5.0 * y).cos()]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (
                vertex(i, j),
                vertex(i + 1, j),
                vertex(i + 1, j + 1),
                vertex(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    let nverts = vec!["3"; triangles.len()].join(" ");
    let ids: Vec<String> = triangles
        .iter()
        .flatten()
        .map(ToString::to_string)
        .collect();
    let p: Vec<String> = points.iter().flatten().map(ToString::to_string).collect();
    let rib = dir.path("mesh.rib");
    std::fs::write(
        &rib,
        format!(
            "Projection \"perspective\" \"fov\" 40\nWorldBegin\nTranslate 0 0 3\n\
             SubdivisionMesh \"catmull-clark\" [{nverts}] [{}] [] [] [] [] \"P\" [{}]\nWorldEnd\n",
            ids.join(" "),
            p.join(" ")
        ),
    )
    .unwrap();
    let obj = dir.path("mesh.obj");
    let mut text = String::new();
    for q in &points {
        text += &format!("v {} {} {}\n", q[0], q[1], q[2]);
    }
    for t in &triangles {
        text += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    std::fs::write(&obj, text).unwrap();
    let out = dir.path("out.png");
    for (scene, expected) in [
        (
            &rib,
            format!(
                "{}:4:1: SubdivisionMesh: over 30000 patches once subdivided",
                path_str(&rib)
            ),
        ),
        (&obj, path_str(&obj).to_owned()),
    ] {
        let mut args = vec!["render", path_str(scene), "--max-patches", "30000"];
        args.extend(TINY);
        args.extend(["-o", path_str(&out)]);
        let run = measured(&args);
        println!(
            "{}: exit ok {}, peak {} MiB, {:.2} s: {}",
            scene.display(),
            run.ok,
            run.peak_kib / 1024,
            run.wall.as_secs_f64(),
            run.stderr.trim()
        );
        assert!(!run.ok, "{}", run.stderr);
        assert!(
            run.stderr.contains(&expected) && run.stderr.contains("--max-patches"),
            "expected {expected:?} in {}",
            run.stderr
        );
        // 30,000 patches are 5.5 MiB of control points.
        assert!(run.peak_kib < 256 << 10, "peak {} KiB", run.peak_kib);
        assert!(!out.exists(), "wrote an output");
    }
}
