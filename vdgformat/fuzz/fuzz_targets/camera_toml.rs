//! Any text must either give validated camera parameters or a one-line error —
//! never a panic; accepted parameters are finite and in range.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vdgformat::camera::CameraParams;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data)
        && let Ok(p) = CameraParams::from_toml_str(text)
    {
        p.validate().expect("parsed parameters validate");
    }
});
