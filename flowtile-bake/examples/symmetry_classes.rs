//! Draws one tile of each rotational symmetry class of a tile set, like the
//! paper's Fig. 4 for the (3,3,1) set with zero corner velocity.
//!
//! `cargo run --release -p flowtile-bake --example symmetry_classes -- out.png [MX MY C N]`

use flowtile_bake::bake::{BLOCKED, BakedTiling};
use flowtile_bake::fill::fill_tile;
use flowtile_bake::render::{RenderOptions, Style, render_to_file};
use flowtile_bake::tileset::TileSet;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = args.first().map(String::as_str).unwrap_or("classes.png");
    let num = |i: usize, d: u32| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let set = TileSet::paper(num(1, 3), num(2, 3), num(3, 1) as usize, num(4, 7) as usize)?;
    let classes = set.rotation_classes()?;
    println!(
        "{} tiles in {} rotation classes",
        set.count(),
        classes.len()
    );
    // Representatives side by side, a blocked slot between neighbours.
    let tiles: Vec<_> = classes
        .iter()
        .map(|c| fill_tile(&set, &set.key_at(c[0]).expect("class member")))
        .collect();
    for t in &tiles {
        println!(
            "  {} (class of {})",
            t.key,
            classes
                .iter()
                .find(|c| set.key_at(c[0]) == Some(t.key))
                .map_or(0, |c| c.len())
        );
    }
    let width = (2 * tiles.len() - 1) as u32;
    let grid = (0..width)
        .map(|x| if x % 2 == 0 { x / 2 } else { BLOCKED })
        .collect();
    let baked = BakedTiling {
        set,
        width,
        height: 1,
        periodic_x: false,
        periodic_y: false,
        tiles,
        grid,
    };
    let opt = RenderOptions {
        px_per_tile: 96,
        style: Style::Arrows,
        seams: true,
        ..Default::default()
    };
    render_to_file(&baked, &opt, std::path::Path::new(out))?;
    println!("wrote {out}");
    Ok(())
}
