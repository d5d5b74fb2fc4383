//! Where the sight lines that `Visible` misses leave the volume: for random free
//! segments with both ends inside Volume(VDG) (drawn as `vdgview check` and the
//! `visible_misses` example draw them) that `Visible` rejects and that leave the
//! volume between their ends, the outside stretches (sampled every half unit): their
//! length, the true wall distance at the deepest outside point, how far outside the
//! reduced volume it is, whether the unreduced graph (optional third file) holds it, and
//! what the nearest wall looks like there (a plane, a convex edge or corner).
//!
//! ```text
//! cargo run --release -p lab --bin miss_shape -- MAP.bsp REDUCED.vdg [UNREDUCED.vdg] [SEGMENTS]
//! ```

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use rayon::prelude::*;
use toolbox::SplitMix64;
use vdgcheck::{CheckOptions, SightSegments};

/// Upper bounds of the histogram bins (units).
const BINS: [f64; 8] = [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, f64::INFINITY];

fn bin(x: f64) -> usize {
    BINS.iter().position(|&b| x < b).unwrap_or(BINS.len() - 1)
}

#[derive(Default, Clone)]
struct Stats {
    inside_ends: usize,
    leaving: usize,
    /// Histograms over the leaving misses' deepest outside point.
    wall: [usize; 8],
    depth: [usize; 8],
    stretch: [usize; 8],
    /// Deepest point's clearance in the unreduced graph.
    unreduced: [usize; 8],
    unreduced_outside: usize,
    /// The wall distance at the deepest point relative to the segment's own wall distance
    /// minimum (is it where the line grazes a wall?).
    near_min: usize,
    stretches: usize,
    /// The deepest point's reduced clearance relative to its true wall distance: ratio bins.
    frac: [usize; 5],
    /// What the nearest wall looks like from the deepest point (see [`wall_shape`]):
    /// a plane, a convex edge, a convex corner, or where two walls are equally near.
    shape: [usize; 4],
}

/// The shape of the walls nearest to `p` at wall distance `d`, from the Laplacian of
/// the distance field (finite differences at half a unit): 0 near a plane (`d` is
/// linear there), about `1/d` near a convex edge (the distance is a cylinder's) and
/// `2/d` near a convex corner (a sphere's); negative where two walls are equally near
/// (the distance is the smaller of two and has a crease). Returns 0 plane, 1 convex
/// edge, 2 convex corner, 3 crease.
fn wall_shape(walls: &Walls, p: [f64; 3], d: f64) -> usize {
    let h = 0.5f64.min(d / 4.0).max(1e-3);
    let mut lap = 0.0;
    for i in 0..3 {
        let mut a = p;
        let mut b = p;
        a[i] += h;
        b[i] -= h;
        lap += (walls.distance(a) + walls.distance(b) - 2.0 * d) / (h * h);
    }
    let k = lap * d;
    if k < -0.3 {
        3
    } else if k < 0.5 {
        0
    } else if k < 1.5 {
        1
    } else {
        2
    }
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(
        args.len() >= 2,
        "usage: miss_shape MAP.bsp REDUCED.vdg [UNREDUCED.vdg] [SEGMENTS]"
    );
    let bsp = Bsp::open(&args[0])?;
    let file = vdgformat::VdgFile::open(&args[1])?;
    let vdg = file.graph();
    let (ufile, n): (_, usize) = match args.get(2) {
        Some(a) if a.ends_with(".vdg") => (
            Some(vdgformat::VdgFile::open(a)?),
            args.get(3).map_or(Ok(100_000), |s| s.parse())?,
        ),
        Some(a) => (None, a.parse()?),
        None => (None, 100_000),
    };
    let uvdg = ufile.as_ref().map(|f| f.graph());
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let walls = Walls::of_map(&bsp, &OracleOptions::default());
    let w = bsp.world();
    let (lo, hi) = (w.mins.map(f64::from), w.maxs.map(f64::from));
    let f32p = |p: [f64; 3]| p.map(|c| c as f32);
    let segments = SightSegments::new(&bsp, &oracle, n, CheckOptions::default().seed);
    let parts: Vec<Stats> = (0..segments.chunks())
        .into_par_iter()
        .map(|c| {
            let mut s = Stats::default();
            segments.for_each_in_chunk(c, |a, b| {
                if !(oracle.segment_free(a, b) && vdg.contains(f32p(a)) && vdg.contains(f32p(b))) {
                    return;
                }
                s.inside_ends += 1;
                if vdg.visible(f32p(a), f32p(b)) {
                    return;
                }
                let len = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
                let steps = (len / 0.5).ceil().max(1.0) as usize;
                let at = |j: usize| {
                    let t = j as f64 / steps as f64;
                    [0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]))
                };
                let mut deepest: Option<([f64; 3], f64)> = None;
                let mut run = 0usize;
                let mut longest = 0usize;
                let mut runs = 0usize;
                for j in 0..=steps {
                    let p = at(j);
                    if vdg.contains(f32p(p)) {
                        run = 0;
                        continue;
                    }
                    if run == 0 {
                        runs += 1;
                    }
                    run += 1;
                    longest = longest.max(run);
                    let c = vdg.clearance(f32p(p)) as f64;
                    if deepest.is_none_or(|(_, d)| c < d) {
                        deepest = Some((p, c));
                    }
                }
                let Some((p, c)) = deepest else { return };
                s.leaving += 1;
                s.stretches += runs;
                let wd = walls.distance(p);
                s.wall[bin(wd)] += 1;
                s.shape[wall_shape(&walls, p, wd)] += 1;
                s.depth[bin(-c)] += 1;
                s.stretch[bin(longest as f64 * 0.5)] += 1;
                let minwall = (0..=steps)
                    .step_by(4)
                    .map(|j| walls.distance(at(j)))
                    .fold(f64::INFINITY, f64::min);
                if wd <= minwall + 4.0 {
                    s.near_min += 1;
                }
                // How much of the true ball the reduced graph lost: -c / wd.
                let f = -c / wd.max(1e-9);
                s.frac[if f < 0.1 {
                    0
                } else if f < 0.25 {
                    1
                } else if f < 0.5 {
                    2
                } else if f < 1.0 {
                    3
                } else {
                    4
                }] += 1;
                if let Some(u) = uvdg {
                    let cu = u.clearance(f32p(p)) as f64;
                    if cu <= 0.0 {
                        s.unreduced_outside += 1;
                    } else {
                        s.unreduced[bin(cu)] += 1;
                    }
                }
            });
            s
        })
        .collect();
    let mut t = Stats::default();
    for p in parts {
        t.inside_ends += p.inside_ends;
        t.leaving += p.leaving;
        t.unreduced_outside += p.unreduced_outside;
        t.near_min += p.near_min;
        t.stretches += p.stretches;
        for i in 0..8 {
            t.wall[i] += p.wall[i];
            t.depth[i] += p.depth[i];
            t.stretch[i] += p.stretch[i];
            t.unreduced[i] += p.unreduced[i];
        }
        for i in 0..5 {
            t.frac[i] += p.frac[i];
        }
        for i in 0..4 {
            t.shape[i] += p.shape[i];
        }
    }
    // Coverage of free points by true wall distance, reduced and unreduced.
    let cov: Vec<[usize; 24]> = (0..n.div_ceil(4096))
        .into_par_iter()
        .map(|c| {
            let mut rng = SplitMix64::new(0x99 ^ c as u64);
            let mut h = [0usize; 24];
            for _ in 0..4096 {
                let p = [0, 1, 2].map(|i| rng.range(lo[i], hi[i]));
                let p = f32p(p).map(f64::from);
                if !oracle.is_free(p) {
                    continue;
                }
                let b = bin(walls.distance(p));
                h[b] += 1;
                h[8 + b] += vdg.contains(f32p(p)) as usize;
                h[16 + b] += uvdg.is_some_and(|u| u.contains(f32p(p))) as usize;
            }
            h
        })
        .collect();
    let mut h = [0usize; 24];
    for x in cov {
        for i in 0..24 {
            h[i] += x[i];
        }
    }
    let v: Vec<String> = (0..8)
        .map(|i| {
            format!(
                "{:.3}/{:.3}",
                h[8 + i] as f64 / h[i].max(1) as f64,
                h[16 + i] as f64 / h[i].max(1) as f64
            )
        })
        .collect();
    println!(
        "free points by wall distance: share {:?}",
        (0..8).map(|i| h[i]).collect::<Vec<_>>()
    );
    println!("inside reduced/unreduced      {}", v.join(" "));
    let pc = |x: usize| 100.0 * x as f64 / t.leaving.max(1) as f64;
    println!(
        "segments with ends inside {}; leaving misses {} ({:.2} %), {:.2} outside stretches each",
        t.inside_ends,
        t.leaving,
        100.0 * t.leaving as f64 / t.inside_ends.max(1) as f64,
        t.stretches as f64 / t.leaving.max(1) as f64
    );
    let head: Vec<String> = BINS.iter().map(|b| format!("<{b}")).collect();
    println!("bins (units)            {}", head.join("  "));
    let row = |name: &str, h: &[usize; 8]| {
        let v: Vec<String> = h.iter().map(|&x| format!("{:5.1}", pc(x))).collect();
        println!("{name:<24}{}", v.join(" "));
    };
    row("wall dist @deepest %", &t.wall);
    row("depth outside %", &t.depth);
    row("longest stretch %", &t.stretch);
    if uvdg.is_some() {
        row("unreduced clearance %", &t.unreduced);
        println!(
            "deepest outside the unreduced volume too: {:.1} %",
            pc(t.unreduced_outside)
        );
    }
    println!(
        "deepest point within 4 units of the segment's closest approach to a wall: {:.1} %",
        pc(t.near_min)
    );
    println!(
        "nearest wall at the deepest point: plane {:.1} %, convex edge {:.1} %, convex corner {:.1} %, two walls equally near {:.1} %",
        pc(t.shape[0]),
        pc(t.shape[1]),
        pc(t.shape[2]),
        pc(t.shape[3])
    );
    let f: Vec<String> = t.frac.iter().map(|&x| format!("{:.1}", pc(x))).collect();
    println!(
        "depth / wall distance  <0.1 <0.25 <0.5 <1 >=1: {}",
        f.join(" ")
    );
    Ok(())
}
