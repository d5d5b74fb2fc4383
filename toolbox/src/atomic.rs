//! Replacing a file so that a reader (or a build system) never sees half of it: the
//! bytes go to a temporary sibling `.NAME.tmpPID-N`, which is synced and renamed over
//! the target, and then the directory is synced so the rename itself survives a power
//! cut. A run killed before the rename leaves its temporary file behind; the next run
//! removes it with [`clean_stale_temps`].

use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The temporary sibling `path`'s next atomic write in this process uses:
/// `DIR/.NAME.tmpPID-N`, unique per process and call so concurrent writers never share
/// one, and hidden so file managers and globs such as `*.vdg` skip it.
pub fn temp_path(path: &Path) -> std::io::Result<PathBuf> {
    static SERIAL: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} is not a file path", path.display()),
        )
    })?;
    let serial = SERIAL.fetch_add(1, Ordering::Relaxed);
    Ok(parent(path).join(format!(
        ".{}.tmp{}-{serial}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

fn parent(path: &Path) -> &Path {
    path.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Writes `path` atomically with what `body` writes into a buffered temporary file.
/// On any error the temporary file is removed and `path` is left as it was.
///
/// ```
/// use std::io::Write;
/// let dir = std::env::temp_dir().join(format!("toolbox-doc-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let path = dir.join("hello.txt");
/// toolbox::write_atomic(&path, |w| writeln!(w, "hello")).unwrap();
/// assert_eq!(std::fs::read_to_string(&path).unwrap(), "hello\n");
/// std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let tmp = temp_path(path)?;
    let result = (|| {
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        let mut w = BufWriter::new(file);
        body(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&tmp, path).map_err(|e| rename_error(e, &tmp))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
        return result;
    }
    // Persist the rename itself; not every platform can open a directory.
    if let Ok(d) = std::fs::File::open(parent(path)) {
        let _ = d.sync_all();
    }
    Ok(())
}

/// The final rename's error, naming the step and its usual cause: on Windows a file
/// cannot be replaced while a program (a running game, a viewer) has it open or
/// memory-mapped.
fn rename_error(e: std::io::Error, tmp: &Path) -> std::io::Error {
    let hint = if cfg!(windows) {
        "; on Windows a file cannot be replaced while a program (a running game, a viewer) \
         has it open or memory-mapped: close it, or load it from memory (vdg_open_memory)"
    } else {
        ""
    };
    std::io::Error::new(
        e.kind(),
        format!(
            "the final rename of the finished temporary file {} failed: {e}{hint}",
            tmp.display()
        ),
    )
}

/// [`write_atomic`] for bytes already in memory.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic(path, |w| w.write_all(bytes))
}

/// Removes the temporary siblings of `path` that runs which no longer exist left
/// behind (a kill between write and rename), and returns them. Files of a live process
/// (another tool writing the same output right now) are left alone. Where it cannot
/// tell whether a process lives (no `/proc`), only files older than an hour go.
pub fn clean_stale_temps(path: &Path) -> Vec<PathBuf> {
    let Some(name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return Vec::new();
    };
    let Ok(entries) = std::fs::read_dir(parent(path)) else {
        return Vec::new();
    };
    let prefixes = [format!(".{name}.tmp"), format!("{name}.tmp")];
    let mut removed = Vec::new();
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().into_owned();
        let Some(rest) = prefixes
            .iter()
            .find_map(|p| file_name.strip_prefix(p.as_str()))
        else {
            continue;
        };
        let pid_text: String = rest.chars().take_while(char::is_ascii_digit).collect();
        let Ok(pid) = pid_text.parse::<u32>() else {
            continue;
        };
        if pid == std::process::id() || process_alive(pid, &entry.path()) {
            continue;
        }
        if std::fs::remove_file(entry.path()).is_ok() {
            removed.push(entry.path());
        }
    }
    removed.sort();
    removed
}

fn process_alive(pid: u32, file: &Path) -> bool {
    let proc = Path::new("/proc");
    if proc.join("self").exists() {
        return proc.join(pid.to_string()).exists();
    }
    // No way to ask: keep anything written in the last hour.
    std::fs::metadata(file)
        .and_then(|m| m.modified())
        .ok()
        .and_then(|t| t.elapsed().ok())
        .is_none_or(|age| age.as_secs() < 3600)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("toolbox-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn replaces_and_leaves_no_temporary() {
        let d = scratch("replace");
        let p = d.join("a.bin");
        write_bytes_atomic(&p, b"one").unwrap();
        write_bytes_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn failed_body_keeps_the_old_file() {
        let d = scratch("fail");
        let p = d.join("a.bin");
        write_bytes_atomic(&p, b"old").unwrap();
        let err = write_atomic(&p, |_| Err(std::io::Error::other("boom"))).unwrap_err();
        assert_eq!(err.to_string(), "boom");
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn unwritable_directory_is_an_error() {
        let p = Path::new("/nonexistent-dir-for-toolbox/a.bin");
        assert!(write_bytes_atomic(p, b"x").is_err());
    }

    #[test]
    fn failed_rename_names_the_step_and_leaves_no_temporary() {
        let dir = scratch("rename");
        // A non-empty directory cannot be replaced by a file.
        let target = dir.join("busy");
        std::fs::create_dir_all(target.join("inside")).unwrap();
        let e = write_bytes_atomic(&target, b"new").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("the final rename of the finished temporary file"),
            "{e}"
        );
        assert!(target.join("inside").is_dir());
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "temporary left behind"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn stale_temporaries_of_dead_processes_go() {
        let d = scratch("stale");
        let p = d.join("map.vdg");
        // A pid that cannot be running (beyond Linux's pid_max limit of 2^22).
        let dead = d.join(".map.vdg.tmp4194304999-0");
        let old_style = d.join("map.vdg.tmp4194304998");
        let mine = temp_path(&p).unwrap();
        let other = d.join("other.vdg.tmp4194304999");
        for f in [&dead, &old_style, &mine, &other] {
            std::fs::write(f, b"x").unwrap();
        }
        let removed = clean_stale_temps(&p);
        if Path::new("/proc/self").exists() {
            assert_eq!(removed, vec![dead.clone(), old_style.clone()]);
            assert!(!dead.exists() && !old_style.exists());
        }
        assert!(mine.exists(), "the running process's own file stays");
        assert!(other.exists(), "another output's file stays");
        std::fs::remove_dir_all(&d).unwrap();
    }
}
