//! Median cost of the exact queries on the `complex` world, so tests that
//! call them 10^5–10^6 times can budget for it.
//!
//!     cargo run -p mapgen --example query_speed [--release]

use std::hint::black_box;
use std::time::Instant;

fn main() {
    let w = mapgen::worlds::complex();
    let b = w.free_bounds();
    let mut seed = 0x1234_5678_u64;
    let mut unit = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 20_000;
    let points: Vec<[f64; 3]> = (0..2 * n)
        .map(|_| [0, 1, 2].map(|i| b.min[i] + (b.max[i] - b.min[i]) * unit()))
        .collect();
    w.wall_polygons(); // build the cache outside the timings
    let time = |name: &str, f: &dyn Fn(usize) -> f64| {
        let mut runs: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                let mut acc = 0.0;
                for i in 0..n {
                    acc += f(i);
                }
                black_box(acc);
                t.elapsed().as_secs_f64() * 1e9 / n as f64
            })
            .collect();
        runs.sort_by(f64::total_cmp);
        println!("{name:<28} {:>9.0} ns/query (median of 5 x {n})", runs[2]);
    };
    let p = &points;
    time("contents", &|i| w.contents(p[i]).bsp_value() as f64);
    time("distance_to_boundary", &|i| w.distance_to_boundary(p[i]));
    time("hull_contents(1)", &|i| {
        w.hull_contents(1, p[i]).bsp_value() as f64
    });
    time("hull_distance_to_boundary(1)", &|i| {
        w.hull_distance_to_boundary(1, p[i])
    });
    time("clearance", &|i| w.clearance(p[i]));
    time("segment_free", &|i| {
        f64::from(u8::from(w.segment_free(p[i], p[n + i])))
    });
    time("segment_margin", &|i| w.segment_margin(p[i], p[n + i]));
    println!("wall polygons: {}", w.wall_polygons().len());
}
