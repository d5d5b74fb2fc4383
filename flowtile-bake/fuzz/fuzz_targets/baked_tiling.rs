//! Any byte string must either parse into a baked flow tiling that answers the
//! runtime's queries, or give an error — never a panic, a hang or an
//! allocation larger than the file could describe. An accepted tiling must
//! also write back to the same bytes' meaning (read, write, read is stable).
#![no_main]

use flowtile_bake::bake::BakedTiling;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(tiling) = BakedTiling::from_bytes(data) else { return };
    let (w, h) = (tiling.width as f64, tiling.height as f64);
    for (u, v) in [(0.5, 0.5), (w * 0.5, h * 0.25), (w - 0.01, h - 0.01), (-1.0, h + 1.0)] {
        let _ = tiling.is_blocked_at(u, v);
        let _ = tiling.slot_of(u, v);
        let _ = tiling.velocity(u, v);
    }
    let _ = tiling.box_flux([0.0, 0.0], [w.min(2.0), h.min(2.0)]);
    let _ = tiling.max_cell_divergence();
    let again = BakedTiling::from_bytes(&tiling.to_bytes()).expect("a written tiling reads back");
    assert_eq!(again.grid, tiling.grid);
});
