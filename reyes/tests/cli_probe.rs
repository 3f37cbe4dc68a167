//! The repeatable CLI probe of issue 19 ("bounded, honest behaviour on every
//! input"): a table of `reyes` invocations, each run in its own temporary
//! directory with the inputs it needs (device links, FIFOs, crafted files),
//! asserting its exit code, the key words of its message, a wall-time bound
//! (the child is killed past it, so a hang fails the test instead of hanging
//! it) and a peak-memory bound.
//!
//! Peak memory comes from `/usr/bin/time -v` ("Maximum resident set size")
//! where it exists, else from `wait4` (the child's own `getrusage`), else the
//! memory assertion is skipped with a notice. A case whose inputs the OS
//! lacks (no `/dev/zero`, no FIFOs, no `/proc`) is skipped with a notice.
//!
//! The run doubles as the probe report: one line per case with its name,
//! exit, wall time and peak memory (`cargo test -p reyes --test cli_probe --
//! --nocapture`). Every case that renders uses `--cpu` and a tiny image, so
//! nothing compiles a GPU shader.
//!
//! `assert_cmd` is not in the offline registry here, so the binary is driven
//! with `std::process::Command` and `CARGO_BIN_EXE_reyes`.

mod files;

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use files::TempDir;
use reyes::load::bpt;
use reyes::model::Model;

/// Creates a case's inputs in its directory; `Err` is the notice for a
/// skipped case (the OS lacks a device, FIFOs or `/proc`).
type Setup = fn(&Path) -> Result<(), String>;

/// One probe: run `reyes ARGS` in a fresh directory prepared by `setup`.
#[derive(Debug, Clone, Copy)]
struct Case {
    name: &'static str,
    setup: Setup,
    args: &'static [&'static str],
    /// The expected exit code: 0 for success, 1 for a reported error.
    code: i32,
    /// Words that must all appear in stderr or stdout.
    words: &'static [&'static str],
    /// Words that must not appear anywhere in the output.
    absent: &'static [&'static str],
    /// Wall-time bound; the child is killed when it is exceeded.
    max_ms: u64,
    /// Peak resident memory bound of the child.
    max_kb: u64,
    /// Bound on the length of stderr in bytes.
    max_stderr: usize,
    /// Files (relative to the case directory) that must exist afterwards.
    written: &'static [&'static str],
    /// Files that must not exist afterwards.
    not_written: &'static [&'static str],
}

/// The defaults every case starts from (`..BASE`).
const BASE: Case = Case {
    name: "",
    setup: nothing,
    args: &[],
    code: 1,
    words: &[],
    absent: &[],
    max_ms: 20_000,
    max_kb: 128 * 1024,
    max_stderr: 64 * 1024,
    written: &[],
    not_written: &[],
};

/// A tiny CPU frame: nothing compiles a GPU shader.
macro_rules! cpu_tiny {
    ($($arg:expr),* $(,)?) => {
        &[$($arg,)* "--cpu", "--width", "32", "--height", "24"]
    };
}

/// A CPU frame large enough that `fine.toml` (fixed dicing at threshold
/// 0.5) takes minutes even in a release build: it must be stopped.
macro_rules! cpu_slow {
    ($($arg:expr),* $(,)?) => {
        &[$($arg,)* "--cpu", "--width", "640", "--height", "480"]
    };
}

/// Words every message naming a non-regular input carries.
const NOT_REGULAR: &str = "not a regular file";

fn cases() -> Vec<Case> {
    vec![
        // D1: devices as model, scene, .wgsl and height map.
        Case {
            name: "D1 /dev/zero link as model",
            setup: devices,
            args: cpu_tiny!["render", "zero.bpt", "-o", "out.png"],
            words: &["model file zero.bpt", "character device", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D1 /dev/urandom link as model",
            setup: devices,
            args: cpu_tiny!["render", "random.bpt", "-o", "out.png"],
            words: &["model file random.bpt", "character device", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D1 /dev/zero link as scene",
            setup: devices,
            args: cpu_tiny!["render", "zero.toml", "-o", "out.png"],
            words: &["scene file zero.toml", "character device", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            // Without --cpu: a .wgsl function is GPU only, and the file is
            // refused before any device is opened.
            name: "D1 /dev/zero link as .wgsl",
            setup: devices,
            args: &[
                "render",
                "--displace",
                "zero.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &[
                "displacement function zero.wgsl",
                "character device",
                NOT_REGULAR,
            ],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D1 /dev/zero link as height map",
            setup: devices,
            args: cpu_tiny![
                "render",
                "--displace",
                "zero.png",
                "--displace-scale",
                "0.1",
                "-o",
                "out.png"
            ],
            words: &["height map", "zero.png", "character device", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D1 scene displacement source /dev/zero",
            setup: scene_dev_zero,
            args: cpu_tiny!["render", "dz.toml", "-o", "out.png"],
            words: &[
                "object 0",
                "height map /dev/zero",
                "character device",
                NOT_REGULAR,
            ],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D1 directory as model",
            setup: directory,
            args: cpu_tiny!["render", "dir.bpt", "-o", "out.png"],
            words: &["model file dir.bpt", "is a directory", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        // D2: FIFOs and stdin (an open, empty pipe here) never block.
        Case {
            name: "D2 FIFO as model",
            setup: fifos,
            args: cpu_tiny!["render", "fifo.bpt", "-o", "out.png"],
            words: &["model file fifo.bpt", "FIFO", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D2 FIFO as height map",
            setup: fifos,
            args: cpu_tiny![
                "render",
                "--displace",
                "fifo.png",
                "--displace-scale",
                "0.1",
                "-o",
                "out.png"
            ],
            words: &["height map", "fifo.png", "FIFO", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D2 /dev/stdin link as model",
            setup: stdin_link,
            args: cpu_tiny!["render", "stdin.bpt", "-o", "out.png"],
            words: &["model file stdin.bpt", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            // No extension: refused by type before anything is read.
            name: "D2 /dev/stdin as scene",
            setup: has_dev_stdin,
            args: cpu_tiny!["render", "/dev/stdin", "-o", "out.png"],
            words: &["/dev/stdin", "unknown scene type"],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D2 /dev/stdin as height map",
            setup: has_dev_stdin,
            args: cpu_tiny![
                "render",
                "--displace",
                "/dev/stdin",
                "--displace-scale",
                "0.1",
                "-o",
                "out.png"
            ],
            words: &["height map /dev/stdin", NOT_REGULAR],
            not_written: &["out.png"],
            ..BASE
        },
        // D5: the largest --timeout is accepted, not a panic.
        Case {
            name: "D5 --timeout u64::MAX",
            args: cpu_tiny![
                "render",
                "--timeout",
                "18446744073709551615",
                "-o",
                "out.png"
            ],
            code: 0,
            words: &["wrote out.png"],
            written: &["out.png"],
            ..BASE
        },
        // D7: a huge frame is a clean size error, nothing allocated.
        Case {
            name: "D7 --cpu 65536x65536",
            args: &[
                "render", "--cpu", "--width", "65536", "--height", "65536", "-o", "out.png",
            ],
            words: &["65536x65536", "RGBA image", "--width/--height"],
            not_written: &["out.png"],
            ..BASE
        },
        // D8: a frame too fine for the budget stops at the CPU timeout.
        Case {
            name: "D8 dice_threshold 0.5 --timeout 2",
            setup: fine_scene,
            args: cpu_slow!["render", "fine.toml", "--timeout", "2", "-o", "out.png"],
            words: &["timed out", "--timeout"],
            not_written: &["out.png"],
            ..BASE
        },
        // D11: a 20 MB one-line model: the message quotes an excerpt only.
        Case {
            name: "D11 20 MB one-line .bpt",
            setup: one_line_bpt,
            args: cpu_tiny!["render", "long.bpt", "-o", "out.png"],
            words: &["long.bpt", "line 1", "patch count"],
            max_kb: 256 * 1024,
            max_stderr: 4096,
            not_written: &["out.png"],
            ..BASE
        },
        // D13: the statistics JSON may not overwrite the image, and its
        // directory is checked before rendering.
        Case {
            name: "D13 -o x.png --stats-json x.png",
            args: cpu_tiny!["render", "-o", "x.png", "--stats-json", "x.png"],
            words: &["both name", "x.png", "nothing was written"],
            not_written: &["x.png"],
            ..BASE
        },
        Case {
            name: "D13 -o x.png --stats-json ./x.png",
            args: cpu_tiny!["render", "-o", "x.png", "--stats-json", "./x.png"],
            words: &["both name", "x.png", "nothing was written"],
            not_written: &["x.png"],
            ..BASE
        },
        Case {
            name: "D13 --stats-json /proc/x.json",
            setup: has_proc,
            args: cpu_tiny!["render", "-o", "out.png", "--stats-json", "/proc/x.json"],
            words: &["/proc"],
            not_written: &["out.png"],
            ..BASE
        },
        // D14: an eye too far out is named, not a NaN frame.
        Case {
            name: "D14 --eye 3e38,0,0",
            args: cpu_tiny!["render", "--eye", "3e38,0,0", "-o", "out.png"],
            words: &["camera", "eye", "too large"],
            not_written: &["out.png"],
            ..BASE
        },
        // D15: an unsupported image format is refused before rendering.
        Case {
            name: "D15 -o out.jpg",
            args: cpu_tiny!["render", "-o", "out.jpg"],
            words: &["out.jpg", "unknown image format", ".png", ".exr"],
            not_written: &["out.jpg"],
            ..BASE
        },
        // D16: dropped pieces are reported. (At 32x24 every teapot patch
        // dices unsplit, so this case renders 64x48.)
        Case {
            name: "D16 max_split_depth = 0",
            setup: depth0_scene,
            args: &[
                "render",
                "depth0.toml",
                "--cpu",
                "--width",
                "64",
                "--height",
                "48",
                "-o",
                "out.png",
            ],
            code: 0,
            words: &[
                "warning: the depth guard dropped",
                "max_split_depth",
                "wrote out.png",
            ],
            written: &["out.png"],
            ..BASE
        },
        // D18: a PNG header claiming 60000x60000 is refused by its size.
        Case {
            name: "D18 PNG claiming 60000x60000",
            setup: huge_png,
            args: cpu_tiny![
                "render",
                "--displace",
                "huge.png",
                "--displace-scale",
                "0.1",
                "-o",
                "out.png"
            ],
            words: &["huge.png", "60000", "at most 4096x4096"],
            absent: &["Memory limit"],
            not_written: &["out.png"],
            ..BASE
        },
        // D19: a UTF-8 byte-order mark before a model is accepted.
        Case {
            name: "D19 .bpt with a UTF-8 BOM",
            setup: bom_bpt,
            args: cpu_tiny!["render", "bom.bpt", "-o", "out.png"],
            code: 0,
            words: &["wrote out.png"],
            written: &["out.png"],
            ..BASE
        },
        // D3: motion that leaves the view is sampled while in view; the
        // frame used to be blank with 0 samples tested and no warning.
        Case {
            name: "D3 teapot receding past the far plane",
            setup: motion_scenes,
            args: cpu_tiny!["render", "far.toml", "--stats", "-o", "out.png"],
            code: 0,
            absent: &["covered no sample"],
            written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D3 teapot moving through the eye",
            setup: motion_scenes,
            args: cpu_tiny!["render", "behind.toml", "--stats", "-o", "out.png"],
            code: 0,
            absent: &["covered no sample"],
            written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D3 --move 100,0,0",
            args: cpu_tiny!["render", "--move", "100,0,0", "--stats", "-o", "out.png"],
            code: 0,
            absent: &["covered no sample"],
            written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D3 --camera-pan 179",
            args: cpu_tiny!["render", "--camera-pan", "179", "--stats", "-o", "out.png"],
            code: 0,
            absent: &["covered no sample"],
            written: &["out.png"],
            ..BASE
        },
        // D4, D12: user WGSL that reaches the renderer's buffers, a
        // function named only in a comment, a barrier; refused on the
        // function's own source, at its own line, before any device is opened.
        Case {
            name: "D4 user WGSL writing the framebuffer",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "framebuffer.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["framebuffer", "line 3", "never the renderer's buffers"],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D4 user WGSL writing the statistics",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "stats.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["`stats`", "line 2"],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D12 user function named only in a comment",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "comment.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["does not define `fn displacement_user"],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D12 syntax error at the user's line",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "syntax.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["line 4"],
            absent: &["graph library"],
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "D12 barrier in a user function",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "barrier.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["barrier", "line 3"],
            not_written: &["out.png"],
            ..BASE
        },
        // Issue 42, item 5: once reported at a line of the generated
        // library (`enable`) or at "line 0" of the entry point (`discard`).
        Case {
            name: "I42 enable directive in a user function",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "enable.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["`enable` directive", "line 2"],
            not_written: &["out.png"],
            ..BASE
        },
        // Issue 42, item 5: once reported at a line of the generated
        // library (`enable`) or at "line 0" of the entry point (`discard`).
        Case {
            name: "I42 discard in a user function",
            setup: user_wgsl,
            args: &[
                "render",
                "--displace",
                "discard.wgsl",
                "--displace-scale",
                "0.1",
                "--displace-bound",
                "0.1",
                "-o",
                "out.png",
            ],
            words: &["`discard`", "line 3", "fragment"],
            not_written: &["out.png"],
            ..BASE
        },
        // RIB: a syntax error gives file:line:column.
        Case {
            name: "RIB malformed array",
            setup: bad_rib,
            args: cpu_tiny!["render", "bad.rib", "-o", "out.png"],
            words: &["bad.rib:2:14:", "mixes numbers and strings"],
            not_written: &["out.png"],
            ..BASE
        },
        // Issue 42, item 2: 4,096 spheres of 4096 patches each once took
        // 6.8 GB and 178 s; the 257th passes the default patch budget of
        // 2^20 (at line 258, after WorldBegin), before it is made.
        Case {
            name: "I42 4096 x Sphere 1e12, render --cpu",
            setup: huge_spheres,
            args: &["render", "--cpu", "spheres.rib", "-o", "out.png"],
            words: &[
                "spheres.rib:258:1: Sphere: 64 x 64 segments: 4096 patches",
                "--max-patches",
            ],
            max_ms: 10_000,
            max_kb: 1024 * 1024,
            not_written: &["out.png"],
            ..BASE
        },
        Case {
            name: "I42 4096 x Sphere 1e12, convert",
            setup: huge_spheres,
            args: &["convert", "spheres.rib", "-o", "out.toml"],
            words: &[
                "spheres.rib:258:1: Sphere: 64 x 64 segments: 4096 patches",
                "--max-patches",
            ],
            max_ms: 10_000,
            max_kb: 1024 * 1024,
            not_written: &["out.toml", "out-0.bpt"],
            ..BASE
        },
    ]
}

/// 4,096 lines of `Sphere 1e12 -1e12 1e12 360` in a world block (123 KB).
fn huge_spheres(dir: &Path) -> Result<(), String> {
    let spheres = "Sphere 1e12 -1e12 1e12 360\n".repeat(4096);
    write(
        dir,
        "spheres.rib",
        &format!("WorldBegin\n{spheres}WorldEnd\n"),
    )
}

#[test]
fn cli_probe() {
    let failures = run_cases(&cases());
    assert!(
        failures.is_empty(),
        "{} case(s) failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The harness itself: a child past its bound is killed (under `time`, its
/// whole process group, or the output pipes would stay open), and it is
/// reported as a failure, not waited for.
#[test]
fn the_time_bound_kills_a_slow_child() {
    let case = Case {
        name: "harness: a slow frame past a 1 s bound",
        setup: fine_scene,
        args: cpu_slow!["render", "fine.toml", "--timeout", "120", "-o", "out.png"],
        max_ms: 1000,
        ..BASE
    };
    let dir = TempDir::new("probe-kill");
    let root = dir.path("");
    (case.setup)(&root).unwrap();
    let start = Instant::now();
    let outcome = run_case(&root, &case, Meter::detect());
    assert!(outcome.timed_out, "{outcome:?}");
    assert!(
        start.elapsed() < Duration::from_secs(10),
        "{:?}",
        start.elapsed()
    );
    let problems = check(&case, &root, &outcome);
    assert!(problems[0].contains("was killed"), "{problems:?}");
}

/// The `wait4` fallback measures the child's peak memory.
#[cfg(unix)]
#[test]
fn wait4_measures_the_peak_memory() {
    let case = Case {
        name: "harness: wait4",
        setup: one_line_bpt,
        args: cpu_tiny!["render", "long.bpt", "-o", "out.png"],
        ..BASE
    };
    let dir = TempDir::new("probe-wait4");
    let root = dir.path("");
    (case.setup)(&root).unwrap();
    let outcome = run_case(&root, &case, Meter::Wait4);
    assert_eq!(outcome.code, Some(1), "{outcome:?}");
    // The 20 MB file is read whole.
    let kb = outcome.peak_kb.expect("wait4 reports the peak");
    assert!((20_000..256 * 1024).contains(&kb), "{kb} KB");
}

/// Runs every case in turn (one at a time, so the time and memory bounds
/// are not muddied by the other cases), prints the probe line of each and
/// returns the failures.
fn run_cases(cases: &[Case]) -> Vec<String> {
    let meter = Meter::detect();
    println!("probe: peak memory from {}", meter.describe());
    let mut failures = Vec::new();
    for (index, case) in cases.iter().enumerate() {
        let dir = TempDir::new(&format!("probe-{index}"));
        let root = dir.path("");
        if let Err(notice) = (case.setup)(&root) {
            println!("NOTICE: {}: skipped: {notice}", case.name);
            continue;
        }
        let outcome = run_case(&root, case, meter);
        println!(
            "probe {:<40} exit {:<7} {:>6} ms {:>9} KB",
            case.name,
            outcome
                .code
                .map_or_else(|| "signal".to_string(), |c| c.to_string()),
            outcome.wall.as_millis(),
            outcome
                .peak_kb
                .map_or_else(|| "?".to_string(), |kb| kb.to_string()),
        );
        let problems = check(case, &root, &outcome);
        if !problems.is_empty() {
            let mut stderr = outcome.stderr.clone();
            if stderr.len() > 2000 {
                let mut end = 2000;
                while !stderr.is_char_boundary(end) {
                    end -= 1;
                }
                stderr.truncate(end);
                stderr.push_str("...");
            }
            failures.push(format!(
                "{}: {}\n  stderr: {stderr}\n  stdout: {}",
                case.name,
                problems.join("; "),
                outcome.stdout.trim_end()
            ));
        }
    }
    failures
}

/// What is wrong with `outcome` for `case`.
fn check(case: &Case, dir: &Path, outcome: &Outcome) -> Vec<String> {
    let mut problems = Vec::new();
    if outcome.timed_out {
        problems.push(format!(
            "ran past its {} ms bound and was killed",
            case.max_ms
        ));
        return problems;
    }
    if outcome.code != Some(case.code) {
        problems.push(format!("exit {:?}, expected {}", outcome.code, case.code));
    }
    let text = format!("{}\n{}", outcome.stderr, outcome.stdout);
    for word in case.words {
        if !text.contains(word) {
            problems.push(format!("message lacks {word:?}"));
        }
    }
    for word in case.absent.iter().chain(&["panicked", "RUST_BACKTRACE"]) {
        if text.contains(word) {
            problems.push(format!("message contains {word:?}"));
        }
    }
    if outcome.stderr.len() > case.max_stderr {
        problems.push(format!(
            "stderr is {} bytes, bound {}",
            outcome.stderr.len(),
            case.max_stderr
        ));
    }
    if outcome.wall > Duration::from_millis(case.max_ms) {
        problems.push(format!(
            "took {} ms, bound {} ms",
            outcome.wall.as_millis(),
            case.max_ms
        ));
    }
    if let Some(kb) = outcome.peak_kb
        && kb > case.max_kb
    {
        problems.push(format!("peak memory {kb} KB, bound {} KB", case.max_kb));
    }
    for name in case.written {
        if !dir.join(name).is_file() {
            problems.push(format!("{name} was not written"));
        }
    }
    for name in case.not_written {
        if dir.join(name).exists() {
            problems.push(format!("{name} was written"));
        }
    }
    problems
}

/// How the peak memory of a child is measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Meter {
    /// `/usr/bin/time -v -o FILE`: "Maximum resident set size (kbytes)".
    TimeV,
    /// `wait4`: the reaped child's own resource usage.
    #[cfg_attr(not(unix), allow(dead_code, reason = "unix only"))]
    Wait4,
    /// Not measured: the memory bound is skipped.
    None,
}

const TIME: &str = "/usr/bin/time";

impl Meter {
    fn detect() -> Meter {
        let report = std::env::temp_dir().join(format!("reyes-probe-{}.time", std::process::id()));
        let works = Command::new(TIME)
            .arg("-v")
            .arg("-o")
            .arg(&report)
            .arg(env!("CARGO_BIN_EXE_reyes"))
            .arg("--version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
            && std::fs::read_to_string(&report).is_ok_and(|t| max_rss_kb(&t).is_some());
        let _ = std::fs::remove_file(&report);
        if works {
            Meter::TimeV
        } else if cfg!(unix) {
            Meter::Wait4
        } else {
            println!("NOTICE: no /usr/bin/time -v and no wait4: the memory bounds are skipped");
            Meter::None
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Meter::TimeV => "/usr/bin/time -v",
            Meter::Wait4 => "wait4 (the child's rusage)",
            Meter::None => "nothing (memory bounds skipped)",
        }
    }
}

/// "Maximum resident set size (kbytes): N" in a `time -v` report.
fn max_rss_kb(report: &str) -> Option<u64> {
    report
        .lines()
        .find_map(|l| l.trim().strip_prefix("Maximum resident set size (kbytes):"))
        .and_then(|n| n.trim().parse().ok())
}

#[derive(Debug)]
struct Outcome {
    /// The exit code; `None` when the child died of a signal.
    code: Option<i32>,
    stdout: String,
    stderr: String,
    wall: Duration,
    peak_kb: Option<u64>,
    timed_out: bool,
}

/// Runs `reyes` with the case's arguments in `dir`, stdin an open empty
/// pipe, killed past the case's time bound.
fn run_case(dir: &Path, case: &Case, meter: Meter) -> Outcome {
    let report = dir.join(".probe-time.txt");
    let mut command = if meter == Meter::TimeV {
        let mut command = Command::new(TIME);
        command
            .arg("-v")
            .arg("-o")
            .arg(&report)
            .arg(env!("CARGO_BIN_EXE_reyes"));
        command
    } else {
        Command::new(env!("CARGO_BIN_EXE_reyes"))
    };
    command
        .args(case.args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // Its own process group, so a kill reaches reyes under `time` too.
    #[cfg(unix)]
    std::os::unix::process::CommandExt::process_group(&mut command, 0);
    let start = Instant::now();
    let mut child = command.spawn().expect("the reyes binary starts");
    // Held open (and empty) until the child is gone: a read of stdin blocks.
    let stdin = child.stdin.take();
    let stdout = drain(child.stdout.take());
    let stderr = drain(child.stderr.take());
    let limit = Duration::from_millis(case.max_ms);
    let (mut code, mut peak_kb, timed_out) = loop {
        if let Some((code, peak)) = poll(&mut child, meter) {
            break (code, peak, false);
        }
        if start.elapsed() > limit {
            kill(&mut child, meter);
            break (None, None, true);
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let wall = start.elapsed();
    drop(stdin);
    if meter == Meter::TimeV && !timed_out {
        let text = std::fs::read_to_string(&report).unwrap_or_default();
        peak_kb = max_rss_kb(&text);
        if text.contains("Command terminated by signal") {
            code = None;
        }
    }
    Outcome {
        code,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
        wall,
        peak_kb,
        timed_out,
    }
}

/// Reads a pipe to its end on its own thread, so a chatty child cannot
/// fill it and stall.
fn drain(pipe: Option<impl Read + Send + 'static>) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut bytes = Vec::new();
        if let Some(mut pipe) = pipe {
            let _ = pipe.read_to_end(&mut bytes);
        }
        String::from_utf8_lossy(&bytes).into_owned()
    })
}

/// The exit code and peak memory once the child has exited.
fn poll(child: &mut Child, meter: Meter) -> Option<(Option<i32>, Option<u64>)> {
    #[cfg(unix)]
    if meter == Meter::Wait4 {
        return wait4_nohang(child.id()).map(|(code, kb)| (code, Some(kb)));
    }
    let _ = meter;
    child
        .try_wait()
        .unwrap()
        .map(|status| (status.code(), None))
}

/// Kills the child (and, on unix, its process group: reyes under `time`),
/// then reaps it.
fn kill(child: &mut Child, meter: Meter) {
    #[cfg(unix)]
    let _ = Command::new("kill")
        .args(["-KILL", "--", &format!("-{}", child.id())])
        .stderr(Stdio::null())
        .status();
    let _ = child.kill();
    let reaped = Instant::now();
    while poll(child, meter).is_none() && reaped.elapsed() < Duration::from_secs(10) {
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// `wait4(pid, WNOHANG)`: `Some((exit code or None for a signal, peak KB))`
/// once the child has exited. Safe std has no per-child rusage.
#[cfg(unix)]
#[expect(unsafe_code, reason = "libc::wait4 for the child's own peak memory")]
fn wait4_nohang(pid: u32) -> Option<(Option<i32>, u64)> {
    let mut status = 0;
    // SAFETY: rusage is plain old data; all zeros is a valid value.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = libc::pid_t::try_from(pid).unwrap();
    // SAFETY: valid pointers to a local status and rusage.
    let reaped = unsafe { libc::wait4(pid, &mut status, libc::WNOHANG, &mut usage) };
    if reaped != pid {
        return None;
    }
    let code = libc::WIFEXITED(status).then(|| libc::WEXITSTATUS(status));
    let max_rss = u64::try_from(usage.ru_maxrss).unwrap_or(0);
    // Bytes on macOS, kilobytes elsewhere.
    let kb = if cfg!(target_os = "macos") {
        max_rss / 1024
    } else {
        max_rss
    };
    Some((code, kb))
}

// ----- setups -----

fn nothing(_: &Path) -> Result<(), String> {
    Ok(())
}

fn link(target: &str, link: PathBuf) -> Result<(), String> {
    if !Path::new(target).exists() {
        return Err(format!("{target} does not exist on this system"));
    }
    if !files::symlink(Path::new(target), &link) {
        return Err("no symbolic links on this system".into());
    }
    Ok(())
}

/// `zero.{bpt,toml,wgsl,png}` -> /dev/zero, `random.bpt` -> /dev/urandom.
fn devices(dir: &Path) -> Result<(), String> {
    for name in ["zero.bpt", "zero.toml", "zero.wgsl", "zero.png"] {
        link("/dev/zero", dir.join(name))?;
    }
    link("/dev/urandom", dir.join("random.bpt"))
}

fn scene_dev_zero(dir: &Path) -> Result<(), String> {
    if !Path::new("/dev/zero").exists() {
        return Err("/dev/zero does not exist on this system".into());
    }
    write(
        dir,
        "dz.toml",
        "[[objects]]\nmodel = \"teapot\"\n[objects.displacement]\nsource = \"/dev/zero\"\nscale = 0.1\n",
    )
}

fn directory(dir: &Path) -> Result<(), String> {
    std::fs::create_dir(dir.join("dir.bpt")).map_err(|e| e.to_string())
}

fn fifos(dir: &Path) -> Result<(), String> {
    for name in ["fifo.bpt", "fifo.png"] {
        if !files::mkfifo(&dir.join(name)) {
            return Err("no FIFOs (mkfifo failed)".into());
        }
    }
    Ok(())
}

fn has_dev_stdin(_: &Path) -> Result<(), String> {
    if Path::new("/dev/stdin").exists() {
        Ok(())
    } else {
        Err("no /dev/stdin on this system".into())
    }
}

fn stdin_link(dir: &Path) -> Result<(), String> {
    link("/dev/stdin", dir.join("stdin.bpt"))
}

fn has_proc(_: &Path) -> Result<(), String> {
    if Path::new("/proc").is_dir() {
        Ok(())
    } else {
        Err("no /proc on this system".into())
    }
}

fn fine_scene(dir: &Path) -> Result<(), String> {
    write(
        dir,
        "fine.toml",
        "dicing = \"fixed\"\ndice_threshold = 0.5\n[[objects]]\nmodel = \"teapot\"\n",
    )
}

/// The teapot seen from `[0, -20, 1.5]`, moving along the view past the
/// far plane (`far.toml`) or through the eye (`behind.toml`).
fn motion_scenes(dir: &Path) -> Result<(), String> {
    let scene = |translate: &str| {
        format!(
            "spp = 16\nsampling = \"interval\"\n[camera]\neye = [0.0, -20.0, 1.5]\ntarget = [0.0, 0.0, 1.5]\nnear = 0.1\nfar = 1000.0\n[[objects]]\nmodel = \"teapot\"\n[objects.transform_close]\ntranslate = {translate}\n"
        )
    };
    write(dir, "far.toml", &scene("[0.0, 2000.0, 0.0]"))?;
    write(dir, "behind.toml", &scene("[0.0, -40.0, 0.0]"))
}

fn depth0_scene(dir: &Path) -> Result<(), String> {
    write(
        dir,
        "depth0.toml",
        "max_split_depth = 0\n\n[[objects]]\nmodel = \"teapot\"\n",
    )
}

/// 20 MB on one line: `1 1 1 ...`.
fn one_line_bpt(dir: &Path) -> Result<(), String> {
    write(dir, "long.bpt", &"1 ".repeat(10_000_000))
}

fn bom_bpt(dir: &Path) -> Result<(), String> {
    write(
        dir,
        "bom.bpt",
        &format!("\u{feff}{}", bpt::write(&Model::teapot())),
    )
}

fn user_wgsl(dir: &Path) -> Result<(), String> {
    let head = "fn displacement_user(u: f32, v: f32) -> f32 {\n";
    write(
        dir,
        "framebuffer.wgsl",
        &format!(
            "{head}    let i = u32(u * 100.0);\n    atomicMin(&framebuffer[i], 0u);\n    return u;\n}}\n"
        ),
    )?;
    write(
        dir,
        "stats.wgsl",
        &format!("{head}    atomicStore(&stats[4], 7777u);\n    return u;\n}}\n"),
    )?;
    write(
        dir,
        "comment.wgsl",
        "// fn displacement_user(u: f32, v: f32) -> f32\nfn height(u: f32, v: f32) -> f32 { return u; }\n",
    )?;
    write(
        dir,
        "syntax.wgsl",
        &format!(
            "// A helper.\nfn twice(x: f32) -> f32 {{ return 2.0 * x; }}\n{head}    return twice(u) + ;\n}}\n"
        ),
    )?;
    write(
        dir,
        "barrier.wgsl",
        &format!(
            "{head}    if (u > 0.5) {{\n        workgroupBarrier();\n    }}\n    return u;\n}}\n"
        ),
    )?;
    write(
        dir,
        "enable.wgsl",
        &format!("// Half floats.\nenable f16;\n{head}    return u;\n}}\n"),
    )?;
    write(
        dir,
        "discard.wgsl",
        &format!("{head}    if (u > 0.5) {{\n        discard;\n    }}\n    return u;\n}}\n"),
    )
}

fn bad_rib(dir: &Path) -> Result<(), String> {
    write(dir, "bad.rib", "WorldBegin\n  Color [1 0 \"x\"]\n")
}

/// A 1x1 grey PNG whose IHDR claims 60000x60000 (CRC recomputed, so the
/// decoder trusts the header).
fn huge_png(dir: &Path) -> Result<(), String> {
    let mut bytes = Vec::new();
    image::GrayImage::new(1, 1)
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .map_err(|e| e.to_string())?;
    assert_eq!(&bytes[12..16], b"IHDR");
    bytes[16..20].copy_from_slice(&60000u32.to_be_bytes());
    bytes[20..24].copy_from_slice(&60000u32.to_be_bytes());
    let crc = files::crc32(&bytes[12..29]);
    bytes[29..33].copy_from_slice(&crc.to_be_bytes());
    std::fs::write(dir.join("huge.png"), bytes).map_err(|e| e.to_string())
}

fn write(dir: &Path, name: &str, text: &str) -> Result<(), String> {
    std::fs::write(dir.join(name), text).map_err(|e| e.to_string())
}
