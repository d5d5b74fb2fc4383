//! Where the reduction loses coverage: random free points with true
//! clearance ≥ 32 (as `vdgview check` draws them) that the unreduced graph covers
//! and the reduced one does not — how far outside the reduced volume they lie,
//! how deep inside the unreduced one, their true clearance, and where (cells of
//! 512 units). Also the coverage the reduced graph would have with the clearances
//! its vertices had before the reduction (an upper bound for raising them back).
//!
//! With `--walkable`, the points are standing player origins (`vdgview check`'s
//! walkable coverage) instead.
//!
//! `cargo run --release -p lab --bin coverage_loss -- MAP.bsp UNREDUCED.vdg REDUCED.vdg [POINTS] [--walkable]`

use anyhow::{Context, bail};
use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use std::collections::HashMap;
use toolbox::SplitMix64;

fn quantiles(v: &mut [f64]) -> String {
    v.sort_by(f64::total_cmp);
    let at = |f: f64| {
        v.get(((v.len() as f64 - 1.0) * f) as usize)
            .copied()
            .unwrap_or(f64::NAN)
    };
    format!(
        "p10 {:7.2} p25 {:7.2} p50 {:7.2} p75 {:7.2} p90 {:7.2} max {:7.2}",
        at(0.1),
        at(0.25),
        at(0.5),
        at(0.75),
        at(0.9),
        at(1.0)
    )
}

fn main() -> anyhow::Result<()> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let walkable = args.iter().any(|a| a == "--walkable");
    args.retain(|a| a != "--walkable");
    let [map, unreduced, reduced] = match args.get(..3) {
        Some([a, b, c]) => [a, b, c],
        _ => bail!("usage: coverage_loss MAP.bsp UNREDUCED.vdg REDUCED.vdg [POINTS]"),
    };
    let n: usize = match args.get(3) {
        Some(a) => a
            .parse()
            .with_context(|| format!("POINTS must be a count, not {a:?}"))?,
        None => 100_000,
    };
    let bsp = Bsp::open(std::path::Path::new(map)).with_context(|| format!("cannot read {map}"))?;
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let walls = Walls::of_map(&bsp, &OracleOptions::default());
    let full_file =
        vdgformat::VdgFile::open(unreduced).with_context(|| format!("cannot read {unreduced}"))?;
    let red_file =
        vdgformat::VdgFile::open(reduced).with_context(|| format!("cannot read {reduced}"))?;
    let (full, red) = (full_file.graph(), red_file.graph());

    // The reduced graph with the vertices' unreduced clearances.
    let mut old: HashMap<[u32; 3], f32> = HashMap::new();
    for v in full.vertices() {
        old.insert(v.pos.map(f32::to_bits), v.clearance);
    }
    let mut b = vdgformat::VdgBuilder::new();
    let mut lowered = Vec::new();
    for v in red.vertices() {
        let o = old
            .get(&v.pos.map(f32::to_bits))
            .copied()
            .unwrap_or(v.clearance);
        if o > v.clearance {
            lowered.push((o - v.clearance) as f64);
        }
        b.add_vertex(v.pos, o);
    }
    for f in red.faces() {
        b.add_face(f);
    }
    let raised_file = vdgformat::VdgFile::from_bytes(&b.to_bytes()?)?;
    let raised = raised_file.graph();
    println!(
        "reduced vertices {}, lowered {} by: {}",
        red.vertices().len(),
        lowered.len(),
        quantiles(&mut lowered)
    );

    let w = bsp.world();
    let (lo, hi) = (w.mins.map(f64::from), w.maxs.map(f64::from));
    let mut rng = SplitMix64::new(0xc0);
    let (mut points, mut in_full, mut in_red, mut in_raised) = (0usize, 0usize, 0usize, 0usize);
    let (mut outside, mut depth, mut truec, mut rdepth) = (vec![], vec![], vec![], vec![]);
    let mut cells: HashMap<[i32; 3], usize> = HashMap::new();
    let mut bands = [0usize; 6];
    let standing: Vec<[f64; 3]> = if walkable {
        vdgcheck::standing_places(&bsp, &oracle, n, 1)
            .iter()
            .map(|s| s.origin)
            .collect()
    } else {
        Vec::new()
    };
    let (mut lost_full, mut lost_full_truec) = (0usize, vec![]);
    while points < n.min(if walkable { standing.len() } else { n }) {
        let p = if walkable {
            standing[points].map(|c| c as f32)
        } else {
            [0, 1, 2].map(|i| rng.range(lo[i], hi[i]) as f32)
        };
        let q = p.map(f64::from);
        if !walkable && (!oracle.is_free(q) || walls.distance_within(q, 32.0).is_some()) {
            continue;
        }
        points += 1;
        if walkable && !full.contains(p) {
            lost_full += 1;
            lost_full_truec.push(walls.distance(q));
        }
        let cf = full.contains(p);
        let cr = red.contains(p);
        in_full += cf as usize;
        in_red += cr as usize;
        in_raised += raised.contains(p) as usize;
        if cr {
            rdepth.push(red.clearance(p) as f64);
        }
        if cf && !cr {
            let out = -red.clearance(p) as f64;
            outside.push(out);
            let band = [1.0, 4.0, 16.0, 64.0, 256.0]
                .iter()
                .position(|&x| out < x)
                .unwrap_or(5);
            bands[band] += 1;
            depth.push(full.clearance(p) as f64);
            truec.push(walls.distance(q));
            *cells
                .entry(p.map(|x| (x / 512.0).floor() as i32))
                .or_default() += 1;
        }
    }
    println!(
        "points {points}: unreduced {:.4}, reduced {:.4}, reduced with unreduced clearances {:.4}",
        in_full as f64 / points as f64,
        in_red as f64 / points as f64,
        in_raised as f64 / points as f64
    );
    println!("lost {} points", outside.len());
    if walkable {
        println!(
            "not in the unreduced volume: {lost_full}, true clearance {}",
            quantiles(&mut lost_full_truec)
        );
    }
    println!(
        "outside the reduced volume by (units) <1 {} <4 {} <16 {} <64 {} <256 {} more {}",
        bands[0], bands[1], bands[2], bands[3], bands[4], bands[5]
    );
    println!("  outside by   {}", quantiles(&mut outside));
    println!("  unreduced depth {}", quantiles(&mut depth));
    println!("  true clearance  {}", quantiles(&mut truec));
    println!("covered points' reduced depth {}", quantiles(&mut rdepth));
    let mut c: Vec<_> = cells.into_iter().collect();
    c.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    println!("cells of 512 units with most lost points:");
    for (k, v) in c.iter().take(12) {
        println!("  {:?} {}", k.map(|x| x * 512), v);
    }
    Ok(())
}
