//! Files written whole or not at all: every file solscope writes (the command
//! line's `--output`, `--out`, `--write-plan` and `--write-actuals`, the app's
//! save and exports) goes into a new file beside its target, is flushed to disk,
//! and is then renamed over the target. A kill, a full disk or an error on the
//! way leaves the target as it was (or absent), never cut short.
//!
//! A target that exists and is not a regular file (`/dev/null`, `/dev/stdout`,
//! a named pipe) cannot be replaced: it is written in place, as a shell
//! redirection would.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// Distinguishes the temporary files of one process.
static NEXT: AtomicU64 = AtomicU64::new(0);

/// Writes `bytes` to `target` whole or not at all (see the module).
pub fn write_whole(target: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut file = WholeFile::create(target)?;
    match file.write_all(bytes) {
        Ok(()) => file.commit(),
        Err(e) => Err(file.abandon(e)),
    }
}

/// The directory a file is in (`.` for a bare file name).
pub fn parent(target: &Path) -> PathBuf {
    match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Whether `target` can be written by [`write_whole`] as far as can be told
/// before the output is made: its directory exists and it is not a directory.
/// Commands that run long check this first, so that their work does not end
/// in nothing.
pub fn check_target(target: &Path) -> io::Result<()> {
    if target.is_dir() {
        return Err(io::Error::other("it is a directory"));
    }
    let dir = parent(target);
    if dir.is_dir() {
        Ok(())
    } else {
        Err(io::Error::other(format!(
            "the directory {} does not exist",
            dir.display()
        )))
    }
}

/// A file being written whole: [`WholeFile::commit`] puts it in place; dropped
/// uncommitted, it leaves the target as it was.
#[derive(Debug)]
pub struct WholeFile {
    /// The open file (the temporary one, or a non-regular target itself).
    file: File,
    /// The temporary file and the target it replaces; `None` when the target
    /// is written in place.
    rename: Option<(PathBuf, PathBuf)>,
}

impl WholeFile {
    /// Starts writing `target`: a new temporary file beside it (beside the file
    /// a symbolic link points to: the link stays), with the target's
    /// permissions when it exists.
    pub fn create(target: &Path) -> io::Result<WholeFile> {
        // The file a link names is the one replaced.
        let target = match fs::symlink_metadata(target) {
            Ok(m) if m.file_type().is_symlink() => fs::canonicalize(target)?,
            _ => target.to_path_buf(),
        };
        let existing = match fs::metadata(&target) {
            Ok(m) => Some(m),
            Err(e) if e.kind() == io::ErrorKind::NotFound => None,
            Err(e) => return Err(e),
        };
        if let Some(m) = &existing {
            if m.is_dir() {
                return Err(io::Error::other("it is a directory"));
            }
            if !m.is_file() {
                let file = OpenOptions::new().write(true).open(&target)?;
                return Ok(WholeFile { file, rename: None });
            }
        }
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .ok_or_else(|| io::Error::other("not a file name"))?;
        let temp = parent(&target).join(format!(
            ".{name}.{}-{}.tmp",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        ));
        let file = OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temp)?;
        let whole = WholeFile {
            file,
            rename: Some((temp, target)),
        };
        if let Some(m) = existing {
            if let Err(e) = whole.file.set_permissions(m.permissions()) {
                return Err(whole.abandon(e));
            }
        }
        Ok(whole)
    }

    /// Flushes the file to disk and renames it over the target.
    pub fn commit(mut self) -> io::Result<()> {
        let done = self.file.flush().and_then(|()| match &self.rename {
            Some((temp, target)) => self.file.sync_all().and_then(|()| fs::rename(temp, target)),
            None => Ok(()),
        });
        match done {
            Ok(()) => {
                self.rename = None;
                Ok(())
            }
            Err(e) => Err(self.abandon(e)),
        }
    }

    /// Removes the temporary file after `e`, and gives `e` back (saying so if
    /// the temporary file could not be removed either).
    pub fn abandon(mut self, e: io::Error) -> io::Error {
        match self.remove_temp() {
            Ok(()) => e,
            Err((temp, r)) => io::Error::new(
                e.kind(),
                format!("{e} (and {} could not be removed: {r})", temp.display()),
            ),
        }
    }

    /// Removes the temporary file, if there is one still.
    fn remove_temp(&mut self) -> Result<(), (PathBuf, io::Error)> {
        match self.rename.take() {
            Some((temp, _)) => fs::remove_file(&temp).map_err(|e| (temp, e)),
            None => Ok(()),
        }
    }
}

impl Write for WholeFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.file.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl Drop for WholeFile {
    /// Dropped uncommitted (an error or a panic on the way): the temporary file
    /// goes; the target stays as it was. Nothing is left to report a failed
    /// removal to here: [`WholeFile::abandon`] is the path that reports it.
    fn drop(&mut self) {
        if self.remove_temp().is_err() {
            // Unreportable (see above).
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("solscope-write-{name}-{}", std::process::id()));
        fs::create_dir_all(&d).unwrap();
        d
    }

    fn entries(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_file_is_replaced_whole_and_nothing_is_left_beside_it() {
        let d = dir("replace");
        let target = d.join("out.json");
        fs::write(&target, "old").unwrap();
        write_whole(&target, b"new text").unwrap();
        assert_eq!(fs::read_to_string(&target).unwrap(), "new text");
        assert_eq!(entries(&d), ["out.json"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn an_abandoned_file_leaves_the_old_one() {
        let d = dir("abandon");
        let target = d.join("out.json");
        fs::write(&target, "old").unwrap();
        let mut w = WholeFile::create(&target).unwrap();
        w.write_all(b"half").unwrap();
        drop(w);
        assert_eq!(fs::read_to_string(&target).unwrap(), "old");
        assert_eq!(entries(&d), ["out.json"]);
        let w = WholeFile::create(&target).unwrap();
        let e = w.abandon(io::Error::other("no space"));
        assert_eq!(e.to_string(), "no space");
        assert_eq!(entries(&d), ["out.json"]);
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn directories_and_missing_directories_are_refused() {
        let d = dir("refuse");
        assert!(write_whole(&d, b"x").is_err());
        assert!(check_target(&d).is_err());
        assert!(write_whole(&d.join("no/such.json"), b"x").is_err());
        assert!(check_target(&d.join("no/such.json")).is_err());
        assert!(check_target(&d.join("fine.json")).is_ok());
        assert!(entries(&d).is_empty());
        fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_device_is_written_in_place_and_a_full_one_fails() {
        write_whole(Path::new("/dev/null"), b"x").unwrap();
        let e = write_whole(Path::new("/dev/full"), &[0; 1 << 16]).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        assert!(Path::new("/dev/full").exists());
    }

    #[cfg(unix)]
    #[test]
    fn a_link_keeps_pointing_at_the_replaced_file_with_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = dir("link");
        let real = d.join("real.json");
        fs::write(&real, "old").unwrap();
        fs::set_permissions(&real, fs::Permissions::from_mode(0o600)).unwrap();
        std::os::unix::fs::symlink(&real, d.join("link.json")).unwrap();
        write_whole(&d.join("link.json"), b"new").unwrap();
        assert!(
            fs::symlink_metadata(d.join("link.json"))
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(fs::read_to_string(&real).unwrap(), "new");
        assert_eq!(
            fs::metadata(&real).unwrap().permissions().mode() & 0o777,
            0o600
        );
        fs::remove_dir_all(&d).unwrap();
    }
}
