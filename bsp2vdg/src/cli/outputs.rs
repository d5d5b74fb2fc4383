//! Where the maps are and where their outputs go, settled before any compile starts:
//! a map name without `.bsp` (J.A.C.K.'s `$path\$file`) finds `MAP.bsp`, `-o DIR` puts
//! `DIR/MAP.vdg` as batch mode does, and every output place is checked up front, so a
//! run that cannot finish fails in a second with a [`UsageError`] (exit 2), never after
//! the compile and never by overwriting a map: an output that is an input (the same
//! file, also through a link), an output with a map's extension, and two maps whose
//! outputs would land on one file are refused, naming the paths.

use super::args::{UsageError, usage};
use anyhow::Result;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Extensions of map files (compiled and editor sources): an output never gets one.
const MAP_EXTENSIONS: &[&str] = &["bsp", "map", "rmf", "jmf", "vmf", "nav"];

/// The maps as the user meant them: a name with no such file but a `NAME.bsp` beside
/// it is that file. Folders and missing files are refused.
pub fn resolve_maps(maps: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::with_capacity(maps.len());
    for map in maps {
        if map.is_dir() {
            usage!(
                "{} is a folder, not a map file (give the maps inside it, e.g. {}/*.bsp)",
                map.display(),
                map.display()
            );
        }
        if map.is_file() {
            out.push(map.clone());
            continue;
        }
        let mut with_bsp = map.clone().into_os_string();
        with_bsp.push(".bsp");
        let with_bsp = PathBuf::from(with_bsp);
        if !has_extension(map, "bsp") && with_bsp.is_file() {
            out.push(with_bsp);
        } else {
            usage!("{}: no such map file", map.display());
        }
    }
    Ok(out)
}

fn has_extension(p: &Path, ext: &str) -> bool {
    p.extension()
        .is_some_and(|e| e.to_string_lossy().eq_ignore_ascii_case(ext))
}

/// Whether `-o PATH` names a folder: an existing one, or a path ending in a separator.
pub fn names_folder(o: &Path) -> bool {
    let s = o.as_os_str().to_string_lossy();
    o.is_dir() || s.ends_with('/') || s.ends_with(std::path::MAIN_SEPARATOR)
}

/// The `.vdg` of `map`: `-o FILE`, `DIR/MAP.vdg` for `-o DIR`, else `MAP.vdg` beside
/// the map.
pub fn output_for(map: &Path, output: Option<&Path>) -> PathBuf {
    let default_output = map.with_extension("vdg");
    match output {
        Some(o) if names_folder(o) => o.join(default_output.file_name().unwrap_or_default()),
        Some(o) => o.to_path_buf(),
        None => default_output,
    }
}

/// The files one map's compile writes, for the checks.
pub struct Planned<'a> {
    pub map: &'a Path,
    pub output: PathBuf,
    /// The other files beside it (log, `.err`, samples).
    pub companions: Vec<PathBuf>,
}

/// Refuses a run whose outputs would destroy an input, carry a map's extension, land
/// two maps on one file, or go to a folder that is missing or not writable.
pub fn check(planned: &[Planned<'_>]) -> Result<()> {
    check_distinct_maps(planned)?;
    let maps: Vec<&Path> = planned.iter().map(|p| p.map).collect();
    let mut owner: HashMap<PathBuf, &Path> = HashMap::new();
    for p in planned {
        if let Some(ext) = p
            .output
            .extension()
            .map(|e| e.to_string_lossy().to_lowercase())
            && MAP_EXTENSIONS.contains(&ext.as_str())
        {
            usage!(
                "refusing to write the graph of {} to {}: .{ext} is a map's extension (give -o a .vdg path)",
                p.map.display(),
                p.output.display()
            );
        }
        for out in std::iter::once(&p.output).chain(&p.companions) {
            if let Some(map) = maps.iter().find(|m| same_file(m, out)) {
                usage!(
                    "refusing to write {}: it is the map {} itself",
                    out.display(),
                    map.display()
                );
            }
        }
        let key = normal_form(&p.output)?;
        if let Some(first) = owner.insert(key, p.map) {
            usage!(
                "{} and {} would both be written to {} (give the maps different names, or compile them in separate runs with their own -o)",
                first.display(),
                p.map.display(),
                p.output.display()
            );
        }
    }
    let mut folders: Vec<PathBuf> = planned.iter().map(|p| folder_of(&p.output)).collect();
    folders.sort();
    folders.dedup();
    for f in folders {
        check_writable_folder(&f)?;
    }
    Ok(())
}

/// The same map given twice (under any spelling) would be compiled twice at once.
fn check_distinct_maps(planned: &[Planned<'_>]) -> Result<()> {
    for (i, a) in planned.iter().enumerate() {
        if let Some(b) = planned[..i].iter().find(|b| same_file(a.map, b.map)) {
            if a.map == b.map {
                usage!("{} is given twice", a.map.display());
            }
            usage!(
                "{} and {} are the same map file, given twice",
                b.map.display(),
                a.map.display()
            );
        }
    }
    Ok(())
}

/// Whether both paths name one existing file (the same device and inode on Unix, so
/// hard and symbolic links count; the same canonical path elsewhere).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
        false
    }
    #[cfg(not(unix))]
    {
        match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

fn folder_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// The output's folder made canonical, with its file name: two spellings of one place
/// (`out/x.vdg`, `./out/../out/x.vdg`) compare equal.
fn normal_form(p: &Path) -> Result<PathBuf> {
    let folder = folder_of(p);
    let Ok(canonical) = folder.canonicalize() else {
        usage!(
            "cannot write {}: the folder {} does not exist",
            p.display(),
            folder.display()
        );
    };
    Ok(canonical.join(p.file_name().unwrap_or_default()))
}

/// Creates and removes a temporary file in `folder`, so an unwritable place fails now.
fn check_writable_folder(folder: &Path) -> Result<()> {
    if !folder.is_dir() {
        usage!("cannot write to {}: it is not a folder", folder.display());
    }
    let probe = folder.join(format!(".bsp2vdg-probe-{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(anyhow::Error::new(UsageError(format!(
            "cannot write to {}: {e}",
            folder.display()
        )))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planned<'a>(map: &'a Path, output: &Path) -> Planned<'a> {
        Planned {
            map,
            output: output.to_path_buf(),
            companions: vec![output.with_extension("log"), output.with_extension("err")],
        }
    }

    fn write(p: &Path) {
        std::fs::write(p, b"x").unwrap();
    }

    #[test]
    fn an_output_that_is_the_map_is_refused() {
        let dir = toolbox::ScratchDir::new("outputs-same").unwrap();
        let map = dir.path().join("box.bsp");
        write(&map);
        let e = check(&[planned(&map, &map)]).unwrap_err().to_string();
        assert!(e.contains("extension"), "{e}");
        // Through a link with a harmless name.
        #[cfg(unix)]
        {
            let link = dir.path().join("box.vdg");
            std::os::unix::fs::symlink(&map, &link).unwrap();
            let e = check(&[planned(&map, &link)]).unwrap_err().to_string();
            assert!(e.contains("is the map"), "{e}");
            let hard = dir.path().join("hard.vdg");
            std::fs::hard_link(&map, &hard).unwrap();
            let e = check(&[planned(&map, &hard)]).unwrap_err().to_string();
            assert!(e.contains("is the map"), "{e}");
        }
    }

    #[test]
    fn two_maps_on_one_output_are_refused_with_both_paths() {
        let dir = toolbox::ScratchDir::new("outputs-dup").unwrap();
        for d in ["a", "b", "out"] {
            std::fs::create_dir(dir.path().join(d)).unwrap();
        }
        let a = dir.path().join("a/x.bsp");
        let b = dir.path().join("b/x.bsp");
        write(&a);
        write(&b);
        let out = dir.path().join("out");
        let e = check(&[
            planned(&a, &output_for(&a, Some(&out))),
            planned(&b, &output_for(&b, Some(&out))),
        ])
        .unwrap_err();
        let text = e.to_string();
        assert!(e.downcast_ref::<UsageError>().is_some());
        assert!(
            text.contains(&a.display().to_string()) && text.contains(&b.display().to_string()),
            "{text}"
        );
        // The same map twice, spelt differently.
        let again = dir.path().join("a/../a/x.bsp");
        let e = check(&[
            planned(&a, &a.with_extension("vdg")),
            planned(&again, &again.with_extension("vdg")),
        ])
        .unwrap_err()
        .to_string();
        assert!(e.contains("same map file"), "{e}");
    }

    #[test]
    fn output_folders_and_names_without_bsp() {
        let dir = toolbox::ScratchDir::new("outputs-dir").unwrap();
        let map = dir.path().join("c1a0.d.bsp");
        write(&map);
        let given = dir.path().join("c1a0.d");
        assert_eq!(resolve_maps(&[given]).unwrap(), std::slice::from_ref(&map));
        assert!(resolve_maps(&[dir.path().join("nothere")]).is_err());
        assert_eq!(
            output_for(&map, Some(dir.path())),
            dir.path().join("c1a0.d.vdg")
        );
        let missing = dir.path().join("missing/x.vdg");
        let e = check(&[planned(&map, &missing)]).unwrap_err().to_string();
        assert!(e.contains("does not exist"), "{e}");
    }
}
