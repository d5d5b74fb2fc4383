//! The editor's palette: the time from a click on a slot to its palette
//! (every flux tuple and corner option of the tile set, allowed or greyed
//! with the reason) on a 64×64 grid. Budget: one frame,
//! 16 ms. Prints the median and the worst of many slots per situation.
//! Run with `cargo bench -p flowtile-bake --bench editor_palette`.

use std::time::Instant;

use flowtile_bake::editor::model::Editor;
use flowtile_bake::rng::Rng;
use flowtile_bake::spec::Problem;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Palettes of `slots` random open slots (empty or not).
fn run(label: &str, ed: &Editor, slots: usize, seed: u64) {
    let (w, h) = ed.size();
    let mut rng = Rng::new(seed);
    let mut times = Vec::with_capacity(slots);
    let mut allowed = 0u64;
    while times.len() < slots {
        let (x, y) = (rng.below(w as u64) as u32, rng.below(h as u64) as u32);
        if ed.tiling().is_blocked(x, y) {
            continue;
        }
        let t0 = Instant::now();
        let p = ed.palette(x, y).expect("open slot");
        times.push(t0.elapsed().as_secs_f64());
        allowed += p.allowed_count();
    }
    let max = times.iter().copied().fold(0.0, f64::max);
    println!(
        "{label:<44} median {:>8.3} ms  max {:>8.3} ms  ({slots} slots, {:.0} tiles allowed on average)",
        median(times) * 1e3,
        max * 1e3,
        allowed as f64 / slots as f64
    );
}

fn spec(border: &str, corners: u32) -> Problem {
    Problem::from_toml(&format!(
        "seed = 5\n[tileset]\nmx = 5\nmy = 5\ncorners = {corners}\n[grid]\nwidth = 64\nheight = 64\nborder_x = \"{border}\"\nborder_y = \"{border}\"\n"
    ))
    .unwrap()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let n = if quick { 20 } else { 200 };
    for (border, corners) in [("free", 5), ("zero", 5), ("periodic", 1)] {
        let name = format!("64x64 (5,5,{corners}) {border}");
        let empty = Editor::new(spec(border, corners)).unwrap();
        run(&format!("{name}, empty grid"), &empty, n, 1);
        // Half the slots placed by the designer (random allowed tiles, in
        // random order, so slots with 3 and 4 free edges occur).
        let mut half = empty.clone();
        let mut rng = Rng::new(2);
        let mut placed = 0;
        while placed < 64 * 64 / 2 {
            let (x, y) = (rng.below(64) as u32, rng.below(64) as u32);
            if half.slot(x, y).is_some() {
                continue;
            }
            let p = half.palette(x, y).unwrap();
            let k = p.selection.key(rng.below(p.allowed_count()));
            half.place(x, y, k).unwrap();
            placed += 1;
        }
        run(&format!("{name}, half placed at random"), &half, n, 3);
        let mut full = empty.clone();
        full.fill(None).unwrap();
        run(
            &format!("{name}, filled (palette to replace a tile)"),
            &full,
            n,
            4,
        );
    }
}
