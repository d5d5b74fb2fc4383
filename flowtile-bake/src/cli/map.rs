//! `flowtile-bake map`: a baked tiling placed onto world triangles, its
//! streamlines drawn in world space, optionally a sampler grid of world
//! velocities.

use std::path::PathBuf;

use anyhow::{Context, Result};

use flowtile_bake::bake::{BakedTiling, write_atomic};
use flowtile_bake::world::{Flow, PictureOptions, WorldField, streamlines};

// The options of `flowtile-bake map`; its help text is the doc comment of
// `Command::Map` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Baked tiling file.
    pub input: PathBuf,
    /// Mesh: OBJ with `v` world positions (x, y used), `vt` flow coordinates.
    #[arg(long)]
    pub mesh: PathBuf,
    /// Picture (PNG) to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Sampler file (JSON) of world velocities on a regular grid.
    #[arg(long)]
    pub sampler: Option<PathBuf>,
    /// Sampler grid spacing in world units.
    #[arg(long, default_value_t = 16.0)]
    pub cell: f64,
    /// Plot width in pixels.
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Name of the world length unit for the axes.
    #[arg(long, default_value = "units")]
    pub units: String,
    /// Seed for streamline seeds.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs `flowtile-bake map`.
pub fn run(a: Args) -> Result<()> {
    let (input, output) = (&a.input, &a.output);
    let baked = BakedTiling::read(input).with_context(|| format!("{}", input.display()))?;
    let mesh = super::read_mesh(&a.mesh)?;
    let field = WorldField::new(&mesh, Flow::Steady(baked))?;
    if let Some(path) = &a.sampler {
        let s = field.sample(a.cell, 0.0)?;
        write_atomic(path, s.to_json().as_bytes())
            .with_context(|| format!("{}", path.display()))?;
        outln!(
            "wrote {} ({}x{} samples, {} world units apart)",
            path.display(),
            s.cols,
            s.rows,
            a.cell
        )?;
    }
    let opt = PictureOptions {
        width: a.width,
        particles: 0,
        seed: a.seed,
        title: format!("{} on {} triangles", input.display(), mesh.triangles.len()),
        units: a.units.to_string(),
    };
    let canvas = streamlines(&field, &opt, 0.0, None)?;
    write_atomic(output, &canvas.to_png()?).with_context(|| format!("{}", output.display()))?;
    outln!("wrote {}", output.display())?;
    Ok(())
}
