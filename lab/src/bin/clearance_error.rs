//! Clearance of compiled graphs against exact answers on the generated maps: at random
//! free points inside Volume(VDG), the graph's clearance (how deep the point lies in the
//! volume) against the exact distance to the walls from the map's manifest. The error
//! `exact − graph` must never be negative (that would be volume outside free space).
//!
//! `cargo run --release -p lab --bin clearance_error -- [POINTS] [bsp2vdg options...]`

use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::CompileOptions;
use bsp2vdg::pipeline;
use bsp2vdg::progress::NoProgress;
use mapgen::world::World;
use std::path::Path;
use toolbox::SplitMix64;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = args.first().and_then(|a| a.parse().ok()).unwrap_or(100_000);
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/maps");
    let mut maps: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        .collect();
    maps.sort();
    let tmp = std::env::temp_dir().join(format!("clearance-error-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).unwrap();
    println!(
        "{:<12} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>9}",
        "map", "inside", "free", "p50", "p90", "p99", "max", "min", "negative"
    );
    for map in maps {
        let world = World::from_manifest_json(
            &std::fs::read_to_string(map.with_extension("json")).unwrap(),
        )
        .unwrap();
        let out = tmp.join(map.file_name().unwrap()).with_extension("vdg");
        let options = CompileOptions {
            reduction_limit: 1.0,
            ..CompileOptions::new(out.clone())
        };
        pipeline::compile(
            &map,
            &options,
            &Log::new(Verbosity::Quiet, true),
            &NoProgress,
        )
        .unwrap();
        let file = vdgformat::VdgFile::open(&out).unwrap();
        let g = file.graph();
        let b = world.free_bounds();
        let mut rng = SplitMix64::new(3);
        let (mut free, mut errors) = (0usize, Vec::new());
        while free < n {
            let p = [0, 1, 2].map(|i| rng.range(b.min[i], b.max[i]) as f32);
            let q = p.map(f64::from);
            if !world.is_free(q) {
                continue;
            }
            free += 1;
            if g.contains(p) {
                errors.push(world.clearance(q) - g.clearance(p) as f64);
            }
        }
        errors.sort_by(f64::total_cmp);
        let at = |f: f64| {
            errors
                .get(((errors.len() as f64 - 1.0) * f) as usize)
                .copied()
                .unwrap_or(f64::NAN)
        };
        let negative = errors.iter().filter(|&&e| e < -1e-3).count();
        println!(
            "{:<12} {:>8} {:>8} {:>8.2} {:>8.2} {:>8.2} {:>8.2} {:>8.3} {:>9}",
            map.file_stem().unwrap().to_string_lossy(),
            errors.len(),
            free,
            at(0.5),
            at(0.9),
            at(0.99),
            at(1.0),
            at(0.0),
            negative
        );
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
