//! Shared helpers of the integration tests: where maps are, and skipping politely.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Compiles `map` into `out` with the bsp2vdg of this build, `-quiet` and `args`,
/// failing the test with the compiler's message if it fails, and returns the graph.
pub fn compile(map: &Path, out: &Path, args: &[&str]) -> vdgformat::VdgFile {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_bsp2vdg"))
        .args(args)
        .args(["-quiet", "-o"])
        .arg(out)
        .arg(map)
        .output()
        .expect("bsp2vdg runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    vdgformat::VdgFile::from_bytes(&std::fs::read(out).unwrap()).unwrap()
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

/// A uniform random point of a convex polygon (area-weighted fan triangle, then
/// uniform barycentric coordinates).
pub fn point_in_polygon(v: &[[f64; 3]], rng: &mut toolbox::SplitMix64) -> [f64; 3] {
    use toolbox::vec3::{cross, dot, sub};
    let tri_area = |i: usize| {
        let c = cross(sub(v[i], v[0]), sub(v[i + 1], v[0]));
        dot(c, c).sqrt()
    };
    let total: f64 = (1..v.len() - 1).map(tri_area).sum();
    let mut x = rng.next_f64() * total;
    let mut k = 1;
    while k < v.len() - 2 && x > tri_area(k) {
        x -= tri_area(k);
        k += 1;
    }
    let (mut u, mut w) = (rng.next_f64(), rng.next_f64());
    if u + w > 1.0 {
        (u, w) = (1.0 - u, 1.0 - w);
    }
    [0, 1, 2].map(|i| v[0][i] + u * (v[k][i] - v[0][i]) + w * (v[k + 1][i] - v[0][i]))
}
