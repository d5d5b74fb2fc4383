//! Any text must either give a flow tiling problem or a one-line error — never
//! a panic, a hang, or an allocation that the text's numbers alone ask for.
#![no_main]

use flowtile_bake::spec::Problem;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = Problem::from_toml(text);
    }
});
