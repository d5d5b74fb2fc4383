//! Where the standing places outside a graph's volume are: for the places
//! `vdgview check` draws (player origins, clip hull 1 free, floor below), those the
//! volume misses, binned by the true wall distance at the origin and the graph's
//! clearance there (how far outside), with the first few listed. On a graph that
//! misses places its reduction kept (the unreduced one), this tells a sampling or
//! `-md` limit (origins in narrow spots, where the medial sheets' clearance is at
//! most the sample spacing or `-md`) from a gap of the reduction.
//!
//! ```text
//! cargo run --release -p lab --bin walkable_misses -- MAP.bsp MAP.vdg [PLACES]
//! ```

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(
        args.len() >= 2,
        "usage: walkable_misses MAP.bsp MAP.vdg [PLACES]"
    );
    let bsp = Bsp::open(&args[0])?;
    let file = vdgformat::VdgFile::open(&args[1])?;
    let g = file.graph();
    let n: usize = args.get(2).map_or(Ok(30_000), |s| s.parse())?;
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let walls = Walls::of_map(&bsp, &OracleOptions::default());
    let places = vdgcheck::standing_places(&bsp, &oracle, n, 1);
    let bins = [16.0, 18.0, 20.0, 22.0, 24.0, 28.0, 32.0, f64::INFINITY];
    let mut all = [0usize; 8];
    let mut miss = [0usize; 8];
    let mut listed = 0;
    let mut solid = 0;
    for s in &places {
        let d = walls.distance(s.origin);
        let b = bins.iter().position(|&x| d < x).unwrap_or(7);
        all[b] += 1;
        let p = s.origin.map(|c| c as f32);
        if g.contains(p) {
            continue;
        }
        miss[b] += 1;
        solid += usize::from(!oracle.is_free(s.origin));
        if listed < 12 {
            listed += 1;
            // How far down the point-sized world is free: a floor only clip hull 1
            // has (a clip brush) leaves the drop long.
            let o = s.origin;
            let drop = (1..=4096)
                .find(|&k| !oracle.is_free([o[0], o[1], o[2] - k as f64]))
                .map_or(f64::INFINITY, |k| k as f64);
            println!(
                "miss at {:?}: wall distance {d:.1}, graph clearance {:.1}, contents {}, point free for {drop} units down",
                o.map(|c| c.round()),
                g.clearance(p),
                oracle.contents(o)
            );
        }
    }
    println!(
        "{} places, {} outside ({:.2} %)",
        places.len(),
        miss.iter().sum::<usize>(),
        100.0 * miss.iter().sum::<usize>() as f64 / places.len().max(1) as f64
    );
    println!("of those, origin in solid for the point hull (hull 0): {solid}");
    println!("wall distance <16 <18 <20 <22 <24 <28 <32 >=32");
    println!("places        {all:?}");
    println!("outside       {miss:?}");
    Ok(())
}
