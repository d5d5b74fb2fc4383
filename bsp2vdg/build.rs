//! Records the build identity, `BSP2VDG_BUILD`: a hash of the source code that shapes
//! a graph (this crate, the map reader, the runtime format, the shared helpers and the
//! locked dependency versions). The package version is shared by every commit, so the
//! up-to-date skip and the bake cache key on this instead: after `git pull && cargo
//! build` a changed compiler rebuilds the graphs, while a change of docs or of another
//! tool does not. Content, not the git commit, so a source tarball or a build farm's
//! sandbox without `.git` gets the same identity as the checkout.

use std::path::{Path, PathBuf};

/// The parts of the workspace, relative to this crate, whose source shapes a graph.
const SOURCES: &[&str] = &[
    "src",
    "Cargo.toml",
    "../bsp/src",
    "../bsp/Cargo.toml",
    "../vdgformat/src",
    "../vdgformat/Cargo.toml",
    "../toolbox/src",
    "../toolbox/Cargo.toml",
    "../Cargo.lock",
];

fn main() {
    let here = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default());
    let mut files = Vec::new();
    for s in SOURCES {
        let p = here.join(s);
        println!("cargo:rerun-if-changed={}", p.display());
        collect(&p, &mut files);
    }
    files.sort();
    // FNV-1a, 64 bits: no dependency, stable across Rust versions (std's hasher is not).
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut feed = |bytes: &[u8]| {
        for &b in bytes {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    for f in &files {
        let rel = f.strip_prefix(&here).unwrap_or(f);
        feed(rel.to_string_lossy().replace('\\', "/").as_bytes());
        feed(&[0]);
        // Line ends normalised: a Windows checkout builds the same graphs.
        let text = std::fs::read(f).unwrap_or_default();
        let text: Vec<u8> = text.into_iter().filter(|&b| b != b'\r').collect();
        feed(&text);
        feed(&[0]);
    }
    println!("cargo:rustc-env=BSP2VDG_BUILD={h:016x}");
}

fn collect(p: &Path, out: &mut Vec<PathBuf>) {
    if p.is_file() {
        out.push(p.to_path_buf());
    } else if let Ok(entries) = std::fs::read_dir(p) {
        for e in entries.flatten() {
            collect(&e.path(), out);
        }
    }
}
