//! Any byte string must either parse into a map on which every query is safe, or give
//! a clean error — never a panic, a hang or an unbounded allocation. (The compiler's
//! own target, `bsp2vdg/fuzz`, goes on to sample the parsed map.)
#![no_main]

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(bsp) = Bsp::parse(data) else { return };
    // A parsed map is promised to be safe to walk: exercise everything that indexes.
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let (lo, hi) = bsp.bounds();
    let mid = [0, 1, 2].map(|i| (lo[i] as f64 + hi[i] as f64) * 0.5);
    let _ = oracle.is_free(mid);
    let _ = oracle.segment_free(mid, [mid[0] + 100.0, mid[1] - 50.0, mid[2] + 10.0]);
    for h in 1..=3 {
        let _ = oracle.clip_contents(h, mid);
    }
    for m in 0..bsp.models.len() {
        for f in bsp::faces::polygons(&bsp, m) {
            let _ = f.class;
        }
    }
    let walls = bsp::walls::Walls::of_map(&bsp, &OracleOptions::default());
    let _ = walls.distance_within(mid, 256.0);
    let _ = bsp.spawns();
});
