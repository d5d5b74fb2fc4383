//! libFuzzer target over the `.vdg` reader: any input must be rejected with
//! an error or, if accepted, answer every query without panicking. Each
//! input is tried as is and re-sealed with a valid checksum, so mutations
//! reach the validation behind the checksum.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vdgformat::VdgFile;
use vdgformat::__private::{exercise_queries, seal};

fn check(data: &[u8]) {
    if let Ok(file) = VdgFile::from_bytes(data) {
        exercise_queries(file.graph());
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    if data.len() >= 16 {
        let mut sealed = data.to_vec();
        seal(&mut sealed);
        check(&sealed);
    }
});
