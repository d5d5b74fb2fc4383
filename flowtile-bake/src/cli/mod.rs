//! Command-line interface (binary only; errors are `anyhow`): the clap
//! definitions and the dispatch; each subcommand in its own module, its
//! options in its `Args`.

mod animate;
mod count;
mod edit;
mod info;
mod map;
mod region;
mod render;
mod tile;

use std::path::Path;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use flowtile_bake::world::Mesh;

#[derive(Parser, Debug)]
#[command(
    name = "flowtile-bake",
    version,
    about = "Flow tiles: divergence-free flow fields from tiles"
)]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the number of tiles in an (M_x, M_y, c) set.
    Count(count::Args),
    /// Tile a grid (from a spec file, or --grid/--set) and bake it.
    Tile(tile::Args),
    /// Render a baked tiling to PNG.
    Render(render::Args),
    /// Place a baked tiling onto world triangles (OBJ with flow coordinates as
    /// vt) and draw its streamlines in world space; optionally write a sampler
    /// grid of world velocities.
    Map(map::Args),
    /// Build a time-varying flow from key tilings (a spec tiled with a random
    /// key sequence, or baked keys) blended over a period, and write an
    /// animated GIF of advected particles, in world space with --mesh.
    Animate(animate::Args),
    /// Derive a tiling spec from a map: the walkable floor at one level (where a
    /// standing player fits, from the map's player clip hull), walls as blocked
    /// slots, spawns/named entities as sources and sinks of a designed flow.
    Region(region::Args),
    /// The interactive editor: paint the region, fix edge fluxes and corner
    /// velocities, place tiles from the palette of a slot (only tiles that
    /// keep the tiling completable; the others greyed with the reason), fill
    /// the rest, undo/redo, save the spec, bake the file. With --script the
    /// commands of a file are applied first and the editor runs headless
    /// (add --window to open it afterwards); --screenshot writes a PNG.
    Edit(edit::Args),
    /// Describe a baked tiling and check it.
    Info(info::Args),
}

/// Runs the command line.
pub fn run() -> Result<()> {
    match Args::parse().command {
        Command::Count(a) => count::run(a),
        Command::Tile(a) => tile::run(a),
        Command::Render(a) => render::run(a),
        Command::Map(a) => map::run(a),
        Command::Animate(a) => animate::run(a),
        Command::Region(a) => region::run(a),
        Command::Edit(a) => edit::run(a),
        Command::Info(a) => info::run(a),
    }
}

/// Reads a mesh (OBJ) of `map` and `animate --mesh`.
fn read_mesh(path: &Path) -> Result<Mesh> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    Mesh::from_obj(&text).with_context(|| format!("{}", path.display()))
}

/// A size `WxH` (`x` or `X`, spaces around the numbers allowed) of the
/// `--grid` and `--size` options; the callers say what else they need.
fn wxh(text: &str) -> Option<(u32, u32)> {
    text.split_once(['x', 'X'])
        .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
}
