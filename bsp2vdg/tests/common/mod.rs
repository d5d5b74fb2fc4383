//! Shared helpers of the integration tests: where maps are, and skipping politely.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The real maps of ../shared/testmaps in the given subfolders, or `None` (with a
/// message) when that folder is absent, e.g. on a fresh clone.
pub fn shared_maps(subdirs: &[&str]) -> Option<Vec<PathBuf>> {
    let root = repo_root().join("../shared/testmaps");
    if !root.is_dir() {
        eprintln!("skipped: {} is absent", root.display());
        return None;
    }
    let mut maps = Vec::new();
    for d in subdirs {
        if let Ok(rd) = std::fs::read_dir(root.join(d)) {
            maps.extend(
                rd.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.extension().is_some_and(|e| e == "bsp")),
            );
        }
    }
    maps.sort();
    Some(maps)
}

/// The maps the repository generates itself (testdata/maps).
pub fn generated_maps() -> Vec<PathBuf> {
    let mut maps: Vec<PathBuf> = std::fs::read_dir(repo_root().join("testdata/maps"))
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
                .collect()
        })
        .unwrap_or_default();
    maps.sort();
    maps
}
