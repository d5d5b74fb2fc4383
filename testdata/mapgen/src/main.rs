//! `mapgen --out DIR [--only NAME]`: writes the standard test maps (and, by name, the extra ones)
//! (`NAME.bsp` + `NAME.json`) into DIR, byte-identically on every run.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use mapgen::{bsp, manifest::Manifest};

const USAGE: &str = "usage: mapgen --out DIR [--only NAME]  (NAME may also be an extra world: open_field, crawl_duct)";

fn main() -> Result<()> {
    let mut out: Option<PathBuf> = None;
    let mut only: Option<String> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--out" | "-o" => out = Some(args.next().context("--out needs a directory")?.into()),
            "--only" => only = Some(args.next().context("--only needs a map name")?),
            "--help" | "-h" => {
                println!("{USAGE}");
                return Ok(());
            }
            other => bail!("unknown argument {other:?}; {USAGE}"),
        }
    }
    let out = out.context(USAGE)?;
    if !out.is_dir() {
        bail!("output directory {} does not exist", out.display());
    }
    // The extra worlds (large, not committed) only when asked for by name.
    let worlds: Vec<_> = match &only {
        None => mapgen::worlds(),
        Some(n) => mapgen::worlds()
            .into_iter()
            .chain(mapgen::worlds::extra_worlds())
            .filter(|w| w.name == *n)
            .collect(),
    };
    if worlds.is_empty() {
        bail!("no standard map is called {:?}", only.unwrap_or_default());
    }
    for w in worlds {
        w.validate().with_context(|| format!("world {}", w.name))?;
        let compiled = bsp::compile(&w);
        let bytes = bsp::write(&w, &compiled);
        let json = Manifest::new(&w, &compiled, bytes.len()).to_json();
        write_atomic(&out.join(format!("{}.bsp", w.name)), &bytes)?;
        write_atomic(&out.join(format!("{}.json", w.name)), json.as_bytes())?;
        let m = &compiled.models[0];
        println!(
            "{:<10} {:>7} bytes  {:>4} faces  {:>4} nodes  {:>4} leaves  clipnodes {} {} {}",
            w.name,
            bytes.len(),
            m.faces.len(),
            m.hull0.nodes.len(),
            m.hull0.leaves.len(),
            m.clip[0].nodes.len(),
            m.clip[1].nodes.len(),
            m.clip[2].nodes.len()
        );
    }
    Ok(())
}

/// Writes via a synced temporary file and a rename, so no half-written map is left.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    toolbox::write_bytes_atomic(path, bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}
