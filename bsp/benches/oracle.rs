//! Oracle throughput on real maps: point-contents queries and segment tests per second
//! on one core, median of 7 runs. Target: ≥ 5 million point queries per
//! second per core.
//!
//! `cargo bench -p bsp --bench oracle [-- MAP.bsp ...]` — without maps it uses the
//! GoldSrc maps in ../shared/testmaps and the repository's generated demo map.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;
use toolbox::SplitMix64;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn default_maps() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut maps = Vec::new();
    for dir in [
        "../shared/testmaps/goldsrc/nonfree",
        "../shared/testmaps/quake1",
    ] {
        if let Ok(rd) = std::fs::read_dir(root.join(dir)) {
            let mut found: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
                .collect();
            found.sort();
            maps.extend(found.into_iter().filter(|p| {
                let n = p.to_string_lossy();
                n.contains("de_dust2") || n.contains("c1a0.bsp") || n.contains("lq_e0m2")
            }));
        }
    }
    let demo = root.join("testdata/maps/complex.bsp");
    if demo.exists() {
        maps.push(demo);
    }
    maps
}

fn main() {
    let args: Vec<PathBuf> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .collect();
    let maps = if args.is_empty() {
        default_maps()
    } else {
        args
    };
    if maps.is_empty() {
        println!("oracle bench skipped: no maps (../shared/testmaps is absent)");
        return;
    }
    println!(
        "{:<34} {:>10} {:>16} {:>16}",
        "map", "nodes", "points/s (1 core)", "segments/s"
    );
    for path in maps {
        let bsp = match Bsp::open(&path) {
            Ok(b) => b,
            Err(e) => {
                println!("{}: {e}", path.display());
                continue;
            }
        };
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let w = bsp.world();
        let mut rng = SplitMix64::new(42);
        let points: Vec<[f64; 3]> = (0..1_000_000)
            .map(|_| [0, 1, 2].map(|i| rng.range(w.mins[i] as f64, w.maxs[i] as f64)))
            .collect();
        let point_rates: Vec<f64> = (0..7)
            .map(|_| {
                let t = Instant::now();
                let mut free = 0usize;
                for &p in &points {
                    free += oracle.is_free(black_box(p)) as usize;
                }
                black_box(free);
                points.len() as f64 / t.elapsed().as_secs_f64()
            })
            .collect();
        // Segments of up to 512 units from random points, as Voronoi extraction asks.
        let segments: Vec<([f64; 3], [f64; 3])> = points[..100_000]
            .iter()
            .map(|&a| (a, [0, 1, 2].map(|i| a[i] + rng.range(-256.0, 256.0))))
            .collect();
        let seg_rates: Vec<f64> = (0..7)
            .map(|_| {
                let t = Instant::now();
                let mut clear = 0usize;
                for &(a, b) in &segments {
                    clear += oracle.segment_free(black_box(a), black_box(b)) as usize;
                }
                black_box(clear);
                segments.len() as f64 / t.elapsed().as_secs_f64()
            })
            .collect();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        println!(
            "{:<34} {:>10} {:>14.2} M {:>14.2} M",
            name,
            bsp.nodes.len(),
            median(point_rates) / 1e6,
            median(seg_rates) / 1e6
        );
    }
}
