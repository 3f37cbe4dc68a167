//! Unit tests of `reyes farm`: the chunks, their commands, the Slurm batch
//! script (a snapshot, checked by reading it) and the status report.

use std::path::PathBuf;

use super::slurm::{ScriptOptions, batch_script};
use super::status::{Status, find, report};
use super::{Format, Sequence, frames_text};
use crate::cli::frames::parse_frames;

/// Frames `frames` of `/farm/shot.toml` in chunks of `chunk`.
fn sequence(frames: &str, chunk: u32) -> Sequence {
    Sequence {
        reyes: PathBuf::from("/opt/reyes/bin/reyes"),
        scene: PathBuf::from("/farm/shot.toml"),
        output: PathBuf::from("/farm/out/shot.####.png"),
        numbers: parse_frames(frames).unwrap().numbers(),
        chunk,
        render_options: Vec::new(),
    }
}

#[test]
fn chunks_hold_consecutive_frames_and_the_last_the_rest() {
    let chunks = sequence("1-25", 10).chunks().unwrap();
    let frames: Vec<&str> = chunks.iter().map(|c| c.frames.as_str()).collect();
    assert_eq!(frames, ["1-10", "11-20", "21-25"]);
    assert_eq!(chunks[2].numbers, [21, 22, 23, 24, 25]);
    assert_eq!(
        chunks.iter().map(|c| c.index).collect::<Vec<_>>(),
        [0, 1, 2]
    );
    // A stepped range and a list chunk by their frames, not their span.
    let chunks = sequence("1-240x2", 40).chunks().unwrap();
    assert_eq!(chunks.len(), 3);
    assert_eq!(chunks[0].frames, "1-79x2");
    assert_eq!(chunks[2].frames, "161-239x2");
    let chunks = sequence("1,2,3,10,20,21", 4).chunks().unwrap();
    let frames: Vec<&str> = chunks.iter().map(|c| c.frames.as_str()).collect();
    assert_eq!(frames, ["1-3,10", "20-21"]);
    // Every frame once, in order.
    let all: Vec<u32> = sequence("1-240", 7)
        .chunks()
        .unwrap()
        .iter()
        .flat_map(|c| c.numbers.clone())
        .collect();
    assert_eq!(all, (1..=240).collect::<Vec<_>>());
}

#[test]
fn each_chunk_has_its_exact_render_command() {
    let mut sequence = sequence("1-4", 2);
    sequence.output = PathBuf::from("/farm/my shots/shot.####.png");
    sequence.render_options = vec!["--spp".into(), "16".into()];
    let chunks = sequence.chunks().unwrap();
    assert_eq!(
        chunks[1].command,
        "/opt/reyes/bin/reyes render /farm/shot.toml --frames 3-4 -o '/farm/my shots/shot.####.png' --skip-existing --keep-going --spp 16"
    );
    assert_eq!(chunks[1].argv[6], "/farm/my shots/shot.####.png");
    let json: serde_json::Value =
        serde_json::from_str(&frames_text(&sequence, Format::Json).unwrap()).unwrap();
    assert_eq!(json["frames"], serde_json::json!([1, 2, 3, 4]));
    assert_eq!(json["chunks"][1]["frames"], "3-4");
    assert_eq!(json["chunks"][1]["command"], chunks[1].command.as_str());
    assert_eq!(json["chunks"][0]["argv"][4], "1-2");
    let text = frames_text(&sequence, Format::Text).unwrap();
    assert!(
        text.starts_with("0\t1-2\t/opt/reyes/bin/reyes render "),
        "{text}"
    );
    assert_eq!(text.lines().count(), 2);
}

#[test]
fn the_slurm_script_runs_one_chunk_per_array_task() {
    let options = ScriptOptions {
        job_name: "reyes-shot".into(),
        logs: PathBuf::from("/farm/out/logs"),
        gpus_per_task: Some(1),
        partition: Some("gpu".into()),
        time: Some("2:00:00".into()),
    };
    let script = batch_script(&sequence("1-240", 10), &options).unwrap();
    // Read by hand: 24 chunks, array 0-23; chunk i is frames 10i+1..10i+10.
    assert!(script.contains("#SBATCH --array=0-23\n"));
    assert!(script.contains("#SBATCH --output=/farm/out/logs/reyes-shot-%A_%a.log\n"));
    assert!(script.contains("  231-240\n)\n"));
    insta::assert_snapshot!(script);
    // Without the options, no directive for them.
    let plain = ScriptOptions {
        gpus_per_task: None,
        partition: None,
        time: None,
        ..options
    };
    let script = batch_script(&sequence("1-12", 3), &plain).unwrap();
    assert!(script.contains("#SBATCH --array=0-3\n"), "{script}");
    assert!(!script.contains("--gpus-per-task") && !script.contains("--partition"));
    // White space in the log directory cannot be quoted in a directive.
    let spaced = ScriptOptions {
        logs: PathBuf::from("/farm/my logs"),
        ..plain
    };
    let error = batch_script(&sequence("1-12", 3), &spaced).unwrap_err();
    assert!(error.to_string().contains("white space"), "{error}");
}

#[test]
fn status_lists_the_missing_frames_and_how_to_render_them() {
    let dir = crate::output::scratch_dir("farm", "status");
    let mut sequence = sequence("1-6", 2);
    sequence.output = dir.join("f.##.png");
    for frame in [1, 2, 4, 6] {
        std::fs::write(dir.join(format!("f.{frame:02}.png")), "").unwrap();
    }
    let status = find(&sequence).unwrap();
    assert_eq!(
        status,
        Status {
            done: vec![1, 2, 4, 6],
            missing: vec![3, 5],
        }
    );
    let text = report(&sequence, &status).unwrap();
    assert!(
        text.starts_with("6 frames: 4 done, 2 missing: 3,5\n"),
        "{text}"
    );
    let render = format!(
        "  /opt/reyes/bin/reyes render /farm/shot.toml --frames '3,5' -o '{}' --skip-existing --keep-going\n",
        dir.join("f.##.png").display()
    );
    assert!(text.contains(&render), "{text}");
    assert!(
        text.contains("farm slurm /farm/shot.toml --frames '3,5' --chunk 2 -o "),
        "{text}"
    );
    for frame in [3, 5] {
        std::fs::write(dir.join(format!("f.{frame:02}.png")), "").unwrap();
    }
    let status = find(&sequence).unwrap();
    assert!(status.missing.is_empty());
    assert_eq!(
        report(&sequence, &status).unwrap(),
        "6 frames: all 6 done\n"
    );
}
