//! Which frames a command draws (`--frame`, `--frames`), and the output
//! paths of each (`-o out.####.png`).

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use crate::rib::RibFrames;

/// The most frames one selection may name: a typo such as `1-2400000`
/// must not start a run of millions of frames (or plan them in memory).
pub(crate) const MAX_SELECTED_FRAMES: u64 = 100_000;

/// The frames `--frame` (`--frames`) selects: numbers and inclusive
/// ranges with an optional step, `2`, `1-240`, `1-240x2`, `1..3`,
/// `1,4-6`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct FrameSelection {
    /// Each part: its inclusive range and its step (1 for every frame).
    ranges: Vec<(RangeInclusive<u32>, u32)>,
    /// As given, for messages.
    text: String,
}

/// Parses `--frame`/`--frames`: comma-separated frame numbers or inclusive
/// ranges `A-B` (or `A..B`), each range with an optional step `xS`
/// (`1-240x2`: 1, 3, ..., 239). An empty range (`5-1`), a range without
/// its end (`1-`), a step of 0 or on a single frame (`0x0`), and a
/// selection of more than [`MAX_SELECTED_FRAMES`] frames are refused.
pub(crate) fn parse_frames(text: &str) -> Result<FrameSelection, String> {
    const FORMS: &str = "give N, A-B, A-BxS (every S-th frame) or a list such as 1,5-9,20-40x2";
    let number = |part: &str, what: &str| {
        let part = part.trim();
        if part.is_empty() {
            return Err(format!("{text:?}: {what} is missing; {FORMS}"));
        }
        part.parse::<u32>().map_err(|_| {
            format!("{text:?}: {part:?} is not a frame number (a whole number >= 0); {FORMS}")
        })
    };
    let mut ranges = Vec::new();
    let mut count: u64 = 0;
    for part in text.split(',') {
        let (span, step) = match part.split_once('x') {
            Some((span, step)) => (span, Some(step)),
            None => (part, None),
        };
        let bounds = span.split_once("..").or_else(|| span.split_once('-'));
        let range = match bounds {
            Some((first, last)) => {
                let first = number(first, "the range's first frame")?;
                let last = number(last, "the range's last frame")?;
                if first > last {
                    return Err(format!(
                        "{text:?}: the range {first}-{last} is empty (its first frame is after its last); write {last}-{first}"
                    ));
                }
                first..=last
            }
            None => {
                if step.is_some() {
                    return Err(format!(
                        "{text:?}: a step (x) needs a range, as in 1-240x2; {FORMS}"
                    ));
                }
                let n = number(span, "a frame number")?;
                n..=n
            }
        };
        let step = match step {
            Some(step) => number(step, "the step after x")?,
            None => 1,
        };
        if step == 0 {
            return Err(format!("{text:?}: the step must be at least 1"));
        }
        count += u64::from((range.end() - range.start()) / step) + 1;
        if count > MAX_SELECTED_FRAMES {
            return Err(format!(
                "{text:?}: selects more than {MAX_SELECTED_FRAMES} frames; render a long sequence in parts (reyes farm splits one into chunks)"
            ));
        }
        ranges.push((range, step));
    }
    Ok(FrameSelection {
        ranges,
        text: text.to_owned(),
    })
}

impl std::fmt::Display for FrameSelection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

impl FrameSelection {
    fn contains(&self, n: u32) -> bool {
        self.ranges
            .iter()
            .any(|(r, step)| r.contains(&n) && (n - r.start()).is_multiple_of(*step))
    }

    /// The frame numbers selected, in the order given, each once.
    pub(crate) fn numbers(&self) -> Vec<u32> {
        let mut seen = std::collections::HashSet::new();
        self.ranges
            .iter()
            .flat_map(|(r, step)| r.clone().step_by(*step as usize))
            .filter(|n| seen.insert(*n))
            .collect()
    }

    /// The selection of `numbers` written compactly (`1-9,12,20-40x2`):
    /// runs of consecutive numbers and of three or more evenly spaced
    /// ones become ranges.
    pub(crate) fn of_numbers(numbers: &[u32]) -> FrameSelection {
        let mut parts = Vec::new();
        let mut ranges = Vec::new();
        let mut i = 0;
        while i < numbers.len() {
            let first = numbers[i];
            let mut j = i;
            let step = numbers.get(i + 1).and_then(|n| n.checked_sub(first));
            if let Some(step) = step.filter(|&s| s > 0) {
                while j + 1 < numbers.len() && numbers[j + 1].checked_sub(numbers[j]) == Some(step)
                {
                    j += 1;
                }
                // Two neighbours read best as a range too (`3-4`); two
                // frames further apart as a list (`3,5`).
                if j - i >= 2 || (j > i && step == 1) {
                    let last = numbers[j];
                    parts.push(if step == 1 {
                        format!("{first}-{last}")
                    } else {
                        format!("{first}-{last}x{step}")
                    });
                    ranges.push((first..=last, step));
                    i = j + 1;
                    continue;
                }
            }
            parts.push(first.to_string());
            ranges.push((first..=first, 1));
            i += 1;
        }
        FrameSelection {
            ranges,
            text: parts.join(","),
        }
    }
}

/// The indices into `frames.frames` that `selection` names (all without
/// one), in file order. A number or range that names no frame of the file
/// is an error listing the file's frames; so is a selection on a file
/// without frames.
pub(crate) fn select(
    file: &Path,
    frames: &RibFrames,
    selection: Option<&FrameSelection>,
) -> Result<Vec<usize>, String> {
    let Some(selection) = selection else {
        return Ok((0..frames.frames.len()).collect());
    };
    if !frames.numbered() {
        return Err(format!(
            "--frame {}: {} has no FrameBegin (it is one frame); leave --frame out",
            selection.text,
            file.display()
        ));
    }
    let numbers: Vec<u32> = frames.frames.iter().filter_map(|f| f.number).collect();
    let missing: Vec<String> = selection
        .ranges
        .iter()
        .filter(|(r, step)| {
            !numbers
                .iter()
                .any(|n| r.contains(n) && (n - r.start()).is_multiple_of(*step))
        })
        .map(|(r, step)| {
            if r.start() == r.end() {
                r.start().to_string()
            } else if *step == 1 {
                format!("{}..{}", r.start(), r.end())
            } else {
                format!("{}..{}x{step}", r.start(), r.end())
            }
        })
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "--frame {}: {} has no frame {}; its frames are {}",
            selection.text,
            file.display(),
            missing.join(", "),
            frames.list()
        ));
    }
    Ok(frames
        .frames
        .iter()
        .enumerate()
        .filter(|(_, f)| f.number.is_some_and(|n| selection.contains(n)))
        .map(|(i, _)| i)
        .collect())
}

/// The path of frame `number` for an output named `path` with `flag`
/// (`-o`, `--stats-json`): a file name with a run of `#`s gets the number
/// there, zero-padded to as many digits as there are `#`s (`out.####.png`:
/// `out.0007.png`). A name without `#`s serves one frame only: with
/// `several` frames it is an error that suggests the pattern or `--frame`.
pub(crate) fn frame_path(
    path: &Path,
    flag: &str,
    number: Option<u32>,
    several: bool,
) -> Result<PathBuf, String> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let runs = hash_runs(&name);
    let Some(&(start, width)) = runs.first() else {
        if several {
            return Err(format!(
                "{flag} {}: several frames are selected, and one file cannot hold them all: name the files with the frame number, e.g. {flag} {}, or select one frame with --frame N",
                path.display(),
                example(path)
            ));
        }
        return Ok(path.to_path_buf());
    };
    if runs.len() > 1 {
        return Err(format!(
            "{flag} {}: the file name has {} runs of '#'; the frame number goes in one (e.g. out.####.png)",
            path.display(),
            runs.len()
        ));
    }
    let Some(number) = number else {
        return Err(format!(
            "{flag} {}: the scene has no FrameBegin, so no frame number to put in place of the '#'s; name the file without them",
            path.display()
        ));
    };
    let expanded = format!(
        "{}{number:0width$}{}",
        &name[..start],
        &name[start + width..]
    );
    Ok(path.with_file_name(expanded))
}

/// The `(start, length)` in bytes of each run of `#` in `name`.
fn hash_runs(name: &str) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (i, b) in name.bytes().enumerate() {
        if b != b'#' {
            continue;
        }
        match runs.last_mut() {
            Some((start, len)) if *start + *len == i => *len += 1,
            _ => runs.push((i, 1)),
        }
    }
    runs
}

/// `path` with `.####` before its extension, for advice.
fn example(path: &Path) -> String {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let name = match path.extension() {
        Some(ext) => format!("{stem}.####.{}", ext.to_string_lossy()),
        None => format!("{stem}.####"),
    };
    path.with_file_name(name).display().to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selections_parse_numbers_ranges_and_lists() {
        let s = parse_frames("1,4..6").unwrap();
        assert!(s.contains(1) && s.contains(4) && s.contains(6));
        assert!(!s.contains(2) && !s.contains(7));
        assert!(parse_frames("3..2").unwrap_err().contains("empty"));
        assert!(parse_frames("5-1").unwrap_err().contains("empty"));
        assert!(parse_frames("x").unwrap_err().contains("needs a range"));
        assert!(
            parse_frames("y")
                .unwrap_err()
                .contains("not a frame number")
        );
        assert!(parse_frames("-1").is_err());
        assert!(parse_frames("1,").is_err());
    }

    #[test]
    fn dashed_ranges_take_steps() {
        assert_eq!(parse_frames("1-5").unwrap().numbers(), [1, 2, 3, 4, 5]);
        assert_eq!(parse_frames("1-9x4").unwrap().numbers(), [1, 5, 9]);
        assert_eq!(parse_frames("1-10x4").unwrap().numbers(), [1, 5, 9]);
        assert_eq!(parse_frames("0..2x2").unwrap().numbers(), [0, 2]);
        // In the order given, each once.
        assert_eq!(parse_frames("7,1-3,2").unwrap().numbers(), [7, 1, 2, 3]);
        let s = parse_frames("10-20x5").unwrap();
        assert!(s.contains(15) && !s.contains(16) && !s.contains(25));
    }

    #[test]
    fn malformed_selections_say_what_is_wrong() {
        let error = |text| parse_frames(text).unwrap_err();
        assert!(
            error("1-").contains("last frame is missing"),
            "{}",
            error("1-")
        );
        assert!(error("-3").contains("first frame is missing"));
        assert!(error("0x0").contains("needs a range"), "{}", error("0x0"));
        assert!(error("1-5x0").contains("at least 1"));
        assert!(error("1-5x").contains("step after x is missing"));
        assert!(error("1-4000000000").contains("more than 100000 frames"));
        // The bound counts every part.
        assert!(error("1-60000,100000-160000").contains("more than"));
        assert!(parse_frames("1-100000").is_ok());
        assert!(error("1-100001").contains("more than"));
    }

    #[test]
    fn numbers_write_back_compactly() {
        let text = |n: &[u32]| FrameSelection::of_numbers(n).to_string();
        assert_eq!(text(&[1, 2, 3, 4]), "1-4");
        assert_eq!(text(&[1, 2, 7, 9, 11, 13, 20]), "1-2,7-13x2,20");
        assert_eq!(text(&[3, 5]), "3,5");
        assert_eq!(text(&[5]), "5");
        assert_eq!(text(&[]), "");
        for numbers in [vec![3, 4, 5, 9, 10], vec![1, 3, 5, 6, 7, 8], vec![2, 1, 0]] {
            let again = parse_frames(&text(&numbers)).unwrap().numbers();
            assert_eq!(again, numbers);
        }
    }

    #[test]
    fn patterns_put_the_padded_number_in_the_hashes() {
        let p = |s: &str, n| frame_path(Path::new(s), "-o", n, true);
        assert_eq!(
            p("dir/out.####.png", Some(7)).unwrap(),
            Path::new("dir/out.0007.png")
        );
        assert_eq!(p("out.#.png", Some(123)).unwrap(), Path::new("out.123.png"));
        // A '#' in a directory is no pattern.
        assert_eq!(
            p("a#b/f_##.exr", Some(3)).unwrap(),
            Path::new("a#b/f_03.exr")
        );
        assert!(p("out#.#.png", Some(1)).unwrap_err().contains("2 runs"));
        assert!(p("out.png", Some(1)).unwrap_err().contains("out.####.png"));
        assert!(p("out.##.png", None).unwrap_err().contains("no FrameBegin"));
        assert_eq!(
            frame_path(Path::new("out.png"), "-o", Some(2), false).unwrap(),
            Path::new("out.png")
        );
    }
}
