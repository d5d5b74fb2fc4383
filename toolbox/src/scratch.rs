//! A scratch folder that cleans up after itself, for tests, examples and doc tests
//! that compile maps or write graphs: every run of the test suite used to leave its
//! folders (a map copy, graphs, logs; about 10 MB a run) in the system's temporary
//! directory for good. A folder is kept when its owner panics, so a failing test
//! leaves its files to look at, and its path is printed.

use std::ffi::OsStr;
use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// A fresh, empty folder `TMP/TAG-PID-N`, removed with everything in it when dropped
/// (kept, with a note on stderr, when dropped while the thread panics).
///
/// Unique per process and call, so tests running in parallel, and two test runs at
/// once, never share one.
///
/// ```
/// let dir = toolbox::ScratchDir::new("toolbox-doc-scratch").unwrap();
/// std::fs::write(dir.join("a.txt"), "hello").unwrap();
/// let path = dir.to_path_buf();
/// assert!(path.join("a.txt").is_file());
/// drop(dir);
/// assert!(!path.exists());
/// ```
#[derive(Debug)]
pub struct ScratchDir {
    path: PathBuf,
}

impl ScratchDir {
    /// Creates the folder; `tag` names what it is for (it shows in the path).
    pub fn new(tag: &str) -> std::io::Result<ScratchDir> {
        static SERIAL: AtomicU64 = AtomicU64::new(0);
        let serial = SERIAL.fetch_add(1, Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!("{tag}-{}-{serial}", std::process::id()));
        // A folder of this name can only be a leftover of a killed process that had
        // the same id: it is ours to replace.
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path)?;
        Ok(ScratchDir { path })
    }

    /// The folder's path.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept {} to look at", self.path.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

impl Deref for ScratchDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for ScratchDir {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<OsStr> for ScratchDir {
    fn as_ref(&self) -> &OsStr {
        self.path.as_os_str()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_are_distinct_and_removed_with_their_contents() {
        let a = ScratchDir::new("toolbox-scratch").unwrap();
        let b = ScratchDir::new("toolbox-scratch").unwrap();
        assert_ne!(a.path(), b.path());
        std::fs::create_dir_all(a.join("sub")).unwrap();
        std::fs::write(a.join("sub/x.bin"), [1u8, 2, 3]).unwrap();
        let (pa, pb) = (a.to_path_buf(), b.to_path_buf());
        assert!(pa.is_dir() && pb.is_dir());
        drop(a);
        drop(b);
        assert!(!pa.exists() && !pb.exists());
    }

    #[test]
    fn a_panicking_owner_keeps_its_folder() {
        let kept = std::thread::spawn(|| {
            let dir = ScratchDir::new("toolbox-scratch-panic").unwrap();
            let path = dir.to_path_buf();
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(move || {
                let _dir = dir;
                panic!("a failing test");
            }));
            assert!(r.is_err());
            path
        })
        .join()
        .unwrap();
        assert!(kept.is_dir(), "a failing test's files are gone");
        std::fs::remove_dir_all(&kept).unwrap();
    }
}
