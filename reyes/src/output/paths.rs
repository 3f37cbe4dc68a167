//! Where an output path really points, and whether its directory takes files.
//!
//! Two output paths clash when they lead to the same file, however they are
//! spelled (relative or absolute, through `..`, or through a symbolic link),
//! so every path is first resolved to the file it names.

use std::ffi::OsString;
use std::fs::{self, OpenOptions};
use std::io;
use std::path::{Component, Path, PathBuf};

/// Most symbolic links followed for one path (Linux's own limit is 40).
const MAX_LINKS: usize = 40;

/// The file `path` names: an absolute path whose existing part has every
/// symbolic link resolved, the missing directories appended as spelled (a
/// directory that does not exist yet cannot be a link), and a final link
/// followed to its target, existing or not.
///
/// The file itself is never opened, so a FIFO or a device is safe to name.
/// `None` when the path names no file (empty, `/`, or ending in `..`).
pub(super) fn resolve(path: &Path) -> io::Result<Option<PathBuf>> {
    if path.as_os_str().is_empty() {
        return Ok(None);
    }
    let mut current = std::path::absolute(path)?;
    for _ in 0..MAX_LINKS {
        let Some(name) = file_name(&current) else {
            return Ok(None);
        };
        let Some(parent) = current.parent() else {
            return Ok(None);
        };
        let file = resolve_dir(parent).join(name);
        match fs::symlink_metadata(&file) {
            Ok(meta) if meta.file_type().is_symlink() => {
                // A relative target is relative to the link's directory;
                // `join` keeps an absolute one as it is.
                let target = fs::read_link(&file)?;
                current = file.parent().unwrap_or(Path::new("/")).join(target);
            }
            _ => return Ok(Some(file)),
        }
    }
    Err(io::Error::other(format!(
        "more than {MAX_LINKS} levels of symbolic links"
    )))
}

/// The last component of `path` when it is a plain name (not `..` or `/`).
fn file_name(path: &Path) -> Option<OsString> {
    match path.components().next_back()? {
        Component::Normal(name) => Some(name.to_os_string()),
        _ => None,
    }
}

/// `dir` (absolute) with its longest existing prefix canonicalized and
/// the rest appended lexically: `.` dropped, `..` removing the previous
/// component, which is right because a missing directory holds no links.
fn resolve_dir(dir: &Path) -> PathBuf {
    let components: Vec<Component<'_>> = dir.components().collect();
    for split in (1..=components.len()).rev() {
        let prefix: PathBuf = components[..split].iter().collect();
        if let Ok(mut resolved) = fs::canonicalize(&prefix) {
            for component in &components[split..] {
                match component {
                    Component::ParentDir => {
                        resolved.pop();
                    }
                    Component::Normal(name) => resolved.push(name),
                    _ => {}
                }
            }
            return resolved;
        }
    }
    // Not even the root could be canonicalized: keep the spelling.
    dir.to_path_buf()
}

/// Checks that files can be created in `dir` by creating (and removing)
/// an empty one, so that a render never starts towards a directory that
/// would refuse its result (`/proc`, read-only media, no permission).
pub(super) fn probe_writable(dir: &Path, name: &str) -> io::Result<()> {
    for attempt in 0..16u32 {
        let probe = dir.join(format!(
            ".{name}.reyes-probe-{}-{attempt}",
            std::process::id()
        ));
        match OpenOptions::new().write(true).create_new(true).open(&probe) {
            Ok(file) => {
                drop(file);
                return fs::remove_file(&probe);
            }
            // Left by a process that was killed: try another name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        "every probe file name is taken",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory under the system temp directory.
    fn scratch(name: &str) -> PathBuf {
        fs::canonicalize(crate::output::scratch_dir("paths", name)).unwrap()
    }

    #[test]
    fn spellings_of_one_file_resolve_alike() {
        let dir = scratch("spellings");
        let plain = resolve(&dir.join("a.png")).unwrap().unwrap();
        assert_eq!(plain, dir.join("a.png"));
        let dotted = resolve(&dir.join("missing/../x/./../a.png")).unwrap();
        assert_eq!(dotted.as_ref(), Some(&plain));
        assert_eq!(
            resolve(&dir.join("new/b.png")).unwrap(),
            Some(dir.join("new/b.png"))
        );
        assert_eq!(resolve(Path::new("")).unwrap(), None);
        assert_eq!(resolve(Path::new("/")).unwrap(), None);
        assert_eq!(resolve(&dir.join("..")).unwrap(), None);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn links_are_followed_even_when_dangling() {
        let dir = scratch("links");
        std::os::unix::fs::symlink("a.png", dir.join("link.png")).unwrap();
        std::os::unix::fs::symlink(&dir, dir.join("here")).unwrap();
        let target = Some(dir.join("a.png"));
        assert_eq!(resolve(&dir.join("link.png")).unwrap(), target);
        assert_eq!(resolve(&dir.join("here/link.png")).unwrap(), target);
        std::os::unix::fs::symlink("loop", dir.join("loop")).unwrap();
        assert!(resolve(&dir.join("loop")).is_err());
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn probing_leaves_nothing_behind() {
        let dir = scratch("probe");
        probe_writable(&dir, "x.png").unwrap();
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
        assert!(probe_writable(&dir.join("missing"), "x.png").is_err());
        fs::remove_dir_all(&dir).unwrap();
    }
}
