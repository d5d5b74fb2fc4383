//! `flowtile-bake render`: a baked tiling drawn to PNG.

use anyhow::{Context, Result};
use clap::ValueEnum;

use flowtile_bake::bake::BakedTiling;
use flowtile_bake::render::{RenderOptions, Style, render_to_file};
use std::path::PathBuf;

// The options of `flowtile-bake render`; its help text is the doc comment of
// `Command::Render` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Baked tiling file.
    pub input: PathBuf,
    /// PNG to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// What to draw.
    #[arg(long, value_enum, default_value_t = StyleArg::Streamlines)]
    pub style: StyleArg,
    /// Pixels per tile.
    #[arg(long, default_value_t = 48)]
    pub px: u32,
    /// Do not draw tile seams.
    #[arg(long)]
    pub no_seams: bool,
    /// Particles to advect (particle style).
    #[arg(long, default_value_t = 600)]
    pub particles: usize,
    /// Advection steps per particle.
    #[arg(long, default_value_t = 400)]
    pub steps: usize,
    /// Seed for streamline seeds and particles.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Map units per tile side: the scale bar and the speed are in map units
    /// (by default in tiles).
    #[arg(long, value_name = "UNITS")]
    pub tile_units: Option<f64>,
    /// Draw no legend strip (speed colours, blocked slots, scale bar, flow direction).
    #[arg(long)]
    pub no_legend: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum StyleArg {
    Arrows,
    Streamlines,
    Particles,
}

/// Runs `flowtile-bake render`.
pub fn run(a: Args) -> Result<()> {
    let input = &a.input;
    let baked = BakedTiling::read(input).with_context(|| format!("{}", input.display()))?;
    let opt = RenderOptions {
        px_per_tile: a.px,
        style: match a.style {
            StyleArg::Arrows => Style::Arrows,
            StyleArg::Streamlines => Style::Streamlines,
            StyleArg::Particles => Style::Particles,
        },
        seams: !a.no_seams,
        particles: a.particles,
        steps: a.steps,
        seed: a.seed,
        legend: !a.no_legend,
        tile_units: a.tile_units,
    };
    if let Some(u) = a.tile_units
        && !(u.is_finite() && u > 0.0)
    {
        anyhow::bail!("--tile-units must be a positive number of map units, got {u}");
    }
    render_to_file(&baked, &opt, &a.output).with_context(|| format!("{}", a.output.display()))?;
    outln!("wrote {}", a.output.display())?;
    Ok(())
}
