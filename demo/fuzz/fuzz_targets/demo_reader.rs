//! Any byte string must either parse into a demo whose player frames are all finite and
//! in time order, or give a clean one-line error — never a panic, a hang or an
//! allocation larger than the input.
#![no_main]

use demo::Demo;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    match Demo::parse(data) {
        Ok(d) => {
            let _ = (d.duration(), d.frame_count(), d.client_frames());
            let frames = d.player();
            for w in frames.windows(2) {
                assert!(w[0].segment != w[1].segment || w[0].t < w[1].t);
            }
            for f in &frames {
                assert!(f.origin.iter().chain(&f.angles).all(|v| v.is_finite()));
                let _ = f.crouched();
            }
        }
        Err(e) => assert!(!e.to_string().contains('\n')),
    }
});
