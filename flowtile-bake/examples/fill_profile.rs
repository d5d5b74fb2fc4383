//! Profiling target: one random scan-line fill of a 256×256 grid.
//! `cargo run --release -p flowtile-bake --example fill_profile -- [free|zero|periodic] [SET]`
use flowtile_bake::rng::Rng;
use flowtile_bake::tileset::TileSet;
use flowtile_bake::tiling::{Border, Conditions, Tiling};

fn main() {
    let border = match std::env::args().nth(1).as_deref() {
        Some("zero") => Border::Zero,
        Some("periodic") => Border::Periodic,
        _ => Border::Free,
    };
    let set = match std::env::args().nth(2).as_deref() {
        Some("335") => TileSet::paper(3, 3, 5, 8).unwrap(),
        _ => TileSet::paper(5, 5, 1, 8).unwrap(),
    };
    let mut t = Tiling::new(set, 256, 256, &Conditions::borders(border, border)).unwrap();
    t.random_fill(&mut Rng::new(1)).unwrap();
    assert!(t.is_complete());
}
