//! Files written beside their target and renamed over it only once complete.
//!
//! A write that fails part way (a full disk, a quota, a size limit) then
//! leaves the target as it was, old file or none, never a truncated one,
//! and the temporary file is removed. [`StagedFiles`] does this for several
//! files at once: none is renamed before all are complete.
//!
//! A write past the process's file-size limit (`ulimit -f`) would kill the
//! process with `SIGXFSZ` before the temporary file could be removed;
//! [`ignore_file_size_signal`] turns it into an ordinary write error.

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use super::OutputError;

/// A complete temporary file waiting to replace its target; dropped
/// without [`Staged::commit`], it is removed.
#[derive(Debug)]
pub(super) struct Staged {
    /// The temporary file, in the target's directory (so the rename stays
    /// on one file system and is atomic).
    temp: PathBuf,
    /// The file it replaces.
    target: PathBuf,
    /// Set once renamed: nothing is left to remove.
    committed: bool,
}

impl Staged {
    /// Writes a temporary file beside `target` with `write`, flushed and
    /// synced to disk (some file systems report a full disk only then).
    /// On any error the temporary file is removed and `target` untouched.
    pub(super) fn write(
        target: &Path,
        write: impl FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
    ) -> Result<Staged, OutputError> {
        let (file, temp) = create_temp(target).map_err(|source| OutputError::Write {
            path: target.to_path_buf(),
            source,
        })?;
        // From here on, dropping `staged` removes the temporary file.
        let staged = Staged {
            temp,
            target: target.to_path_buf(),
            committed: false,
        };
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        let io_error = |source| OutputError::Write {
            path: target.to_path_buf(),
            source,
        };
        let file = writer.into_inner().map_err(|e| io_error(e.into_error()))?;
        file.sync_all().map_err(io_error)?;
        keep_permissions(target, &staged.temp);
        Ok(staged)
    }

    /// Renames the temporary file over the target.
    pub(super) fn commit(mut self) -> Result<(), OutputError> {
        fs::rename(&self.temp, &self.target).map_err(|source| OutputError::Rename {
            path: self.target.clone(),
            source,
        })?;
        self.committed = true;
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the error being reported matters more.
            let _ = fs::remove_file(&self.temp);
        }
    }
}

/// Creates a new temporary file named after `target` in its directory,
/// hidden (a leading dot) and unique to this process.
fn create_temp(target: &Path) -> io::Result<(File, PathBuf)> {
    let dir = target.parent().unwrap_or(Path::new("."));
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    for attempt in 0..16u32 {
        let temp = dir.join(format!(
            ".{name}.reyes-tmp-{}-{attempt}",
            std::process::id()
        ));
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((file, temp)),
            // Left by a process that was killed: try another name.
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::new(
        io::ErrorKind::AlreadyExists,
        "every temporary file name is taken",
    ))
}

/// Gives the temporary file the permissions of the file it replaces, so a
/// rename does not silently change them (a new file keeps the defaults).
fn keep_permissions(target: &Path, temp: &Path) {
    if let Ok(meta) = fs::metadata(target) {
        // Best effort: the file is still right with default permissions.
        let _ = fs::set_permissions(temp, meta.permissions());
    }
}

/// Writes `bytes` to `target` through a temporary file, replacing it only
/// when the whole content is on disk.
pub(super) fn write_bytes(target: &Path, bytes: &[u8]) -> Result<Staged, OutputError> {
    Staged::write(target, |writer| {
        writer
            .write_all(bytes)
            .map_err(|source| OutputError::Write {
                path: target.to_path_buf(),
                source,
            })
    })
}

/// Files written to temporaries beside their targets, renamed into place
/// together by [`StagedFiles::commit`] only once every one is complete.
/// Dropped without a commit, every temporary file is removed and every
/// target is left as it was.
#[derive(Debug, Default)]
pub struct StagedFiles {
    staged: Vec<Staged>,
}

impl StagedFiles {
    /// No file yet.
    pub fn new() -> StagedFiles {
        StagedFiles::default()
    }

    /// Writes `bytes` to a temporary file beside `target` (a path an
    /// [`super::OutputGuard`] returned), synced to disk. On an error the
    /// files staged so far stay staged; dropping the set removes them.
    pub fn write(&mut self, target: &Path, bytes: &[u8]) -> Result<(), OutputError> {
        self.staged.push(write_bytes(target, bytes)?);
        Ok(())
    }

    /// [`StagedFiles::write`] with the content streamed by `write` instead
    /// of held in memory (a model's text can be several times its patches).
    pub fn write_with(
        &mut self,
        target: &Path,
        write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
    ) -> Result<(), OutputError> {
        self.staged.push(Staged::write(target, |writer| {
            write(writer).map_err(|source| OutputError::Write {
                path: target.to_path_buf(),
                source,
            })
        })?);
        Ok(())
    }

    /// Renames every temporary file over its target, in the order written
    /// (so a file that names the others, such as a scene naming its models,
    /// goes last). Renames within one directory do not fail for lack of
    /// space; if one fails all the same, the files before it are replaced
    /// and the rest are left as they were.
    pub fn commit(self) -> Result<(), OutputError> {
        self.staged.into_iter().try_for_each(Staged::commit)
    }
}

/// Ignores `SIGXFSZ` for the process (on Unix; elsewhere there is no such
/// signal), so that a write past the file-size limit fails with `EFBIG`,
/// which is reported with its path and leaves no temporary file, instead
/// of killing the process. Call it once at start-up, before any thread is
/// spawned (the command line does).
#[cfg(unix)]
#[expect(
    unsafe_code,
    reason = "libc::signal; ignoring a signal installs no handler and touches no memory"
)]
pub fn ignore_file_size_signal() {
    // SAFETY: `SIG_IGN` is no function to call: no handler runs, so nothing
    // about async-signal safety or memory applies. The previous disposition
    // (returned) is not needed.
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

/// Ignores `SIGXFSZ`: nothing to do where the signal does not exist.
#[cfg(not(unix))]
pub fn ignore_file_size_signal() {}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory under the system temp directory.
    fn scratch(name: &str) -> PathBuf {
        crate::output::scratch_dir("staged", name)
    }

    #[test]
    fn a_failed_write_keeps_the_old_file_and_no_temp() {
        let dir = scratch("fail");
        let target = dir.join("out.png");
        fs::write(&target, b"old").unwrap();
        let failure = Staged::write(&target, |writer| {
            // Half a file, then the disk fills.
            writer.write_all(&[7; 10_000]).unwrap();
            Err(OutputError::Write {
                path: target.clone(),
                source: io::Error::other("no space left on device (simulated)"),
            })
        });
        assert!(matches!(failure, Err(OutputError::Write { .. })));
        assert_eq!(fs::read(&target).unwrap(), b"old");
        assert_eq!(
            fs::read_dir(&dir).unwrap().count(),
            1,
            "a temp file is left"
        );
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn only_a_commit_replaces_the_target() {
        let dir = scratch("commit");
        let target = dir.join("stats.json");
        fs::write(&target, b"old").unwrap();
        let staged = write_bytes(&target, b"new").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"old");
        staged.commit().unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"new");
        // Abandoned: the target stays, the temp goes.
        drop(write_bytes(&target, b"newer").unwrap());
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_set_is_replaced_all_or_nothing() {
        let dir = scratch("set");
        let first = dir.join("scene-0.bpt");
        fs::write(&first, b"old model").unwrap();
        let mut set = StagedFiles::new();
        set.write(&first, b"new model").unwrap();
        // The second target's directory is missing: its write fails.
        let failure = set.write(&dir.join("missing/scene.toml"), b"new scene");
        assert!(
            matches!(&failure, Err(OutputError::Write { path, .. }) if path.ends_with("missing/scene.toml")),
            "{failure:?}"
        );
        drop(set);
        assert_eq!(fs::read(&first).unwrap(), b"old model");
        assert_eq!(
            fs::read_dir(&dir).unwrap().count(),
            1,
            "a temp file is left"
        );
        // Complete: both are replaced.
        let second = dir.join("scene.toml");
        let mut set = StagedFiles::new();
        set.write(&first, b"new model").unwrap();
        set.write(&second, b"new scene").unwrap();
        assert_eq!(fs::read(&first).unwrap(), b"old model");
        set.commit().unwrap();
        assert_eq!(fs::read(&first).unwrap(), b"new model");
        assert_eq!(fs::read(&second).unwrap(), b"new scene");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 2);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch("mode");
        let target = dir.join("out.png");
        fs::write(&target, b"old").unwrap();
        fs::set_permissions(&target, fs::Permissions::from_mode(0o640)).unwrap();
        write_bytes(&target, b"new").unwrap().commit().unwrap();
        let mode = fs::metadata(&target).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o640);
        fs::remove_dir_all(&dir).unwrap();
    }
}
