//! Any byte string must either parse into a map on which every query is safe, or give
//! a clean error — never a panic, a hang or an unbounded allocation.
#![no_main]

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp2vdg::sample::{self, SampleOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(bsp) = Bsp::parse(data) else { return };
    // A parsed map is promised to be safe to walk: exercise everything that indexes.
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let w = bsp.world();
    let mid = [0, 1, 2].map(|i| (w.mins[i] as f64 + w.maxs[i] as f64) * 0.5);
    let _ = oracle.is_free(mid);
    let _ = oracle.segment_free(mid, [mid[0] + 100.0, mid[1] - 50.0, mid[2] + 10.0]);
    for h in 1..=3 {
        let _ = oracle.clip_contents(h, mid);
    }
    // Sample with a spacing and cap that keep each run cheap.
    let options = SampleOptions { spacing: 64.0, max_samples: 2000, ..Default::default() };
    let _ = sample::sample(&bsp, &options);
    for e in &bsp.entities {
        let _ = (e.origin(), e.model_index());
    }
});
