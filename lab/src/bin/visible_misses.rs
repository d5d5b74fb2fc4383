//! Where `Visible` misses sight lines whose ends lie inside the volume: per map,
//! random free segments (as `vdgview check` draws them: SEGMENTS = its samples / 10
//! gives its very lines) whose ends the volume
//! contains, BSP-visible, that `Visible` rejects, split into those that leave
//! Volume(VDG) on the way (a gap of the graph, not of the query) and those that
//! stay inside it (sampled every half unit: the query's own misses).
//!
//! ```text
//! cargo run --release -p lab --bin visible_misses -- MAP.bsp MAP.vdg [SEGMENTS]
//! ```

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use rayon::prelude::*;
use vdgcheck::{CheckOptions, SightSegments};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(
        args.len() >= 2,
        "usage: visible_misses MAP.bsp MAP.vdg [SEGMENTS]"
    );
    let bsp = Bsp::open(&args[0])?;
    let file = vdgformat::VdgFile::open(&args[1])?;
    let vdg = file.graph();
    let n: usize = args.get(2).map_or(Ok(100_000), |s| s.parse())?;
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let f32p = |p: [f64; 3]| p.map(|c| c as f32);
    let segments = SightSegments::new(&bsp, &oracle, n, CheckOptions::default().seed);
    let parts: Vec<[usize; 5]> = (0..segments.chunks())
        .into_par_iter()
        .map(|c| {
            let mut s = [0usize; 5];
            segments.for_each_in_chunk(c, |a, b| {
                if !(oracle.segment_free(a, b) && vdg.contains(f32p(a)) && vdg.contains(f32p(b))) {
                    return;
                }
                s[0] += 1;
                if vdg.visible(f32p(a), f32p(b)) {
                    return;
                }
                s[1] += 1;
                let len = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
                let steps = (len / 0.5).ceil().max(1.0) as usize;
                let outside = (0..=steps).any(|j| {
                    let t = j as f64 / steps as f64;
                    !vdg.contains(f32p([0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]))))
                });
                if outside {
                    s[2] += 1;
                } else {
                    s[3] += 1;
                    if s[3] <= 3 && c == 0 {
                        eprintln!("inside miss: {a:?} -> {b:?} len {len:.1}");
                    }
                }
            });
            s
        })
        .collect();
    let s = parts.iter().fold([0usize; 5], |mut a, p| {
        for i in 0..5 {
            a[i] += p[i];
        }
        a
    });
    println!(
        "segments_inside_ends {}  fn {} ({:.2} %)  leaving_volume {} ({:.2} %)  staying_inside {} ({:.2} %)",
        s[0],
        s[1],
        100.0 * s[1] as f64 / s[0].max(1) as f64,
        s[2],
        100.0 * s[2] as f64 / s[0].max(1) as f64,
        s[3],
        100.0 * s[3] as f64 / s[0].max(1) as f64
    );
    Ok(())
}
