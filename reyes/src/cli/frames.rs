//! Which frames of a RIB file a command draws (`--frame`), and the output
//! paths of each (`-o out.####.png`).

use std::ops::RangeInclusive;
use std::path::{Path, PathBuf};

use crate::rib::RibFrames;

/// The frames `--frame` selects: numbers and inclusive ranges, `2`,
/// `1..3`, `1,4..6`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct FrameSelection {
    ranges: Vec<RangeInclusive<u32>>,
    /// As given, for messages.
    text: String,
}

/// Parses `--frame`: comma-separated frame numbers or inclusive ranges `N..M`.
pub(crate) fn parse_frames(text: &str) -> Result<FrameSelection, String> {
    let number = |part: &str| {
        part.trim().parse::<u32>().map_err(|_| {
            format!("{text:?}: {part:?} is not a frame number (a whole number >= 0); give N, N..M or a list N,M..K")
        })
    };
    let mut ranges = Vec::new();
    for part in text.split(',') {
        let range = match part.split_once("..") {
            Some((first, last)) => {
                let (first, last) = (number(first)?, number(last)?);
                if first > last {
                    return Err(format!("{text:?}: the range {first}..{last} is empty"));
                }
                first..=last
            }
            None => {
                let n = number(part)?;
                n..=n
            }
        };
        ranges.push(range);
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
        self.ranges.iter().any(|r| r.contains(&n))
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
        .filter(|r| !numbers.iter().any(|n| r.contains(n)))
        .map(|r| {
            if r.start() == r.end() {
                r.start().to_string()
            } else {
                format!("{}..{}", r.start(), r.end())
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
        assert!(
            parse_frames("x")
                .unwrap_err()
                .contains("not a frame number")
        );
        assert!(parse_frames("-1").is_err());
        assert!(parse_frames("1,").is_err());
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
