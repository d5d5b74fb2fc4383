//! `flowtile-bake info`: a baked tiling described and checked.

use std::path::PathBuf;

use anyhow::{Context, Result};
use serde_json::json;

use flowtile_bake::bake::BakedTiling;

// The options of `flowtile-bake info`; its help text is the doc comment of
// `Command::Info` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Baked tiling file.
    pub input: PathBuf,
    /// Print as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `flowtile-bake info`.
pub fn run(a: Args) -> Result<()> {
    let (path, json) = (a.input.as_path(), a.json);
    let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
    let b = BakedTiling::from_bytes(&bytes).with_context(|| format!("{}", path.display()))?;
    let slots = b
        .grid
        .iter()
        .filter(|&&g| g != flowtile_bake::bake::BLOCKED)
        .count();
    let nodes = (b.set.n + 1) * (b.set.n + 1);
    // What storing every slot's stream function would take.
    let unshared = slots * nodes * 8;
    let s = &b.set;
    // Version 2 stores one tile per symmetry class; `tiles_used` counts the
    // distinct tiles of the grid either way.
    let version = u32::from_le_bytes(bytes[4..8].try_into().expect("read checked the header"));
    let stored = if version == flowtile_bake::bake::VERSION_ROTATED {
        b.symmetry_classes_used()
    } else {
        b.tiles.len()
    };
    let stats = json!({
        "file": path.display().to_string(),
        "bytes": bytes.len(),
        "version": version,
        "tiles_stored": stored,
        "width": b.width,
        "height": b.height,
        "periodic_x": b.periodic_x,
        "periodic_y": b.periodic_y,
        "n": s.n,
        "mx": [s.mx.min, s.mx.max],
        "my": [s.my.min, s.my.max],
        "corners": s.corners,
        "f_base": s.f_base,
        "tile_set_size": s.count(),
        "slots": slots,
        "tiles_used": b.tiles.len(),
        "stream_bytes_vs_unshared": (stored * nodes * 8) as f64 / unshared.max(1) as f64,
        "max_divergence": b.max_cell_divergence(),
        "max_flux_error": b.max_flux_error(),
        "max_seam_mismatch": b.max_seam_mismatch(),
    });
    if json {
        outln!("{stats}")?;
    } else {
        outln!(
            "{}: {} bytes, format version {version}",
            path.display(),
            bytes.len(),
        )?;
        outln!(
            "grid {}x{} ({} slots, {} blocked){}{}",
            b.width,
            b.height,
            slots,
            b.grid.len() - slots,
            if b.periodic_x { ", periodic in x" } else { "" },
            if b.periodic_y { ", periodic in y" } else { "" }
        )?;
        outln!(
            "tile set: m_x {}..{}, m_y {}..{}, {} corner velocities, f_base {}, {} cells per tile; {} tiles",
            s.mx.min,
            s.mx.max,
            s.my.min,
            s.my.max,
            s.corners.len(),
            s.f_base,
            s.n,
            s.count()
        )?;
        outln!(
            "tiles: {} distinct, {stored} stored ({:.1}% of the stream data of storing every slot)",
            b.tiles.len(),
            100.0 * (stored * nodes * 8) as f64 / unshared.max(1) as f64
        )?;
        outln!(
            "max |divergence| {:.1e}, max flux error {:.1e}, max seam mismatch {:.1e}",
            b.max_cell_divergence(),
            b.max_flux_error(),
            b.max_seam_mismatch()
        )?;
    }
    Ok(())
}
