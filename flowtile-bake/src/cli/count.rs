//! `flowtile-bake count`: the number of tiles of a set, and of its rotation
//! classes.

use anyhow::{Result, bail};

use flowtile_bake::tileset::TileSet;

// The options of `flowtile-bake count`; its help text is the doc comment of
// `Command::Count` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Flux options on vertical edges.
    #[arg(long)]
    pub mx: u32,
    /// Flux options on horizontal edges.
    #[arg(long)]
    pub my: u32,
    /// Corner velocity options.
    #[arg(long, default_value_t = 1)]
    pub corners: usize,
    /// Also print the number of rotational symmetry classes.
    #[arg(long)]
    pub classes: bool,
}

/// Runs `flowtile-bake count`.
pub fn run(a: Args) -> Result<()> {
    if a.mx == 0 || a.my == 0 || a.corners == 0 {
        bail!("--mx, --my and --corners must be at least 1");
    }
    let set = TileSet::paper(a.mx, a.my, a.corners, 3)?;
    outln!("{}", set.count())?;
    if a.classes {
        let c = set.rotation_classes()?;
        outln!("rotation classes: {}", c.len())?;
    }
    Ok(())
}
