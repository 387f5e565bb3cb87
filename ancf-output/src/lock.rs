//! An output folder belongs to one run at a time: `ancf run`, `--resume`
//! and `ancf sweep` hold an advisory lock on `DIR/.ancf.lock` (the
//! operating system's file lock, `File::try_lock`) while they write. A
//! second writer is refused with the holder's process id; a lock left by a
//! killed process is released by the operating system with it, so the next
//! run takes the folder over. A run that ends (completed, failed or
//! interrupted) removes the file; only a killed one leaves it, with its id.

use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::{Path, PathBuf};

/// The lock file's name inside an output folder.
pub const LOCK_FILE: &str = ".ancf.lock";

/// A held lock on an output folder; released when dropped.
#[derive(Debug)]
pub struct OutputLock {
    _file: File,
    path: PathBuf,
}

impl OutputLock {
    /// Lock `dir` (created if missing) for this process, or say who holds it.
    /// A lock taken on a file that its holder removed as it ended (the
    /// path now names another file, or none) is taken again on the path's.
    pub fn acquire(dir: &Path) -> Result<Self, String> {
        for _ in 0..16 {
            let lock = Self::acquire_once(dir)?;
            if lock.still_at_path() {
                return Ok(lock);
            }
            // Its drop leaves the path alone: it names another file.
            drop(lock);
        }
        Err(format!(
            "{}: the lock file keeps changing hands; another program is creating and removing it",
            dir.join(LOCK_FILE).display()
        ))
    }

    /// Whether the locked file is still the one the path names.
    fn still_at_path(&self) -> bool {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt as _;
            match (self._file.metadata(), std::fs::symlink_metadata(&self.path)) {
                (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
                _ => false,
            }
        }
        #[cfg(not(unix))]
        {
            self.path.exists()
        }
    }

    fn acquire_once(dir: &Path) -> Result<Self, String> {
        if std::fs::symlink_metadata(dir).is_ok_and(|m| m.file_type().is_symlink())
            && std::fs::metadata(dir).is_err()
        {
            let target =
                std::fs::read_link(dir).map_or(String::from("?"), |t| t.display().to_string());
            return Err(format!(
                "{}: a symbolic link to {target}, which does not exist; create that folder or \
                 choose another --out",
                dir.display()
            ));
        }
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let path = dir.join(LOCK_FILE);
        // A symbolic link planted there is removed, never written through
        // (the PID would land in its target).
        if std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            std::fs::remove_file(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        let mut file = OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(&path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                let holder = holder.trim();
                let who = if holder.is_empty() {
                    "another process".to_string()
                } else {
                    format!("process {holder}")
                };
                return Err(format!(
                    "{}: {who} is writing into this folder (it holds {}); wait for it to end, \
                     stop it, or choose another --out",
                    dir.display(),
                    path.display()
                ));
            }
            Err(TryLockError::Error(e)) => return Err(format!("{}: {e}", path.display())),
        }
        let stamp = |f: &mut File| -> std::io::Result<()> {
            f.set_len(0)?;
            f.rewind()?;
            writeln!(f, "{}", std::process::id())?;
            f.flush()
        };
        stamp(&mut file).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(OutputLock { _file: file, path })
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for OutputLock {
    /// Removes the lock file while still holding its lock (a writer that
    /// opened it meanwhile finds it gone and takes the path's new one).
    fn drop(&mut self) {
        if self.still_at_path() {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symbolic link planted as the lock file is removed, not followed:
    /// its target keeps its contents.
    #[cfg(unix)]
    #[test]
    fn a_planted_lock_link_is_not_followed() {
        let dir = std::env::temp_dir().join(format!("ancf-lock-link-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("victim");
        std::fs::write(&target, "keep").unwrap();
        std::os::unix::fs::symlink(&target, dir.join(LOCK_FILE)).unwrap();
        let lock = OutputLock::acquire(&dir).unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
        drop(lock);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A second lock on the same folder is refused, naming this process;
    /// once the first is dropped, the folder can be locked again.
    #[test]
    fn one_writer_at_a_time() {
        let dir = std::env::temp_dir().join(format!("ancf-lock-{}", std::process::id()));
        let first = OutputLock::acquire(&dir).unwrap();
        let second = OutputLock::acquire(&dir).unwrap_err();
        assert!(
            second.contains(&format!("process {}", std::process::id())),
            "{second}"
        );
        drop(first);
        let again = OutputLock::acquire(&dir).unwrap();
        assert!(again.path().ends_with(LOCK_FILE));
        drop(again);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
