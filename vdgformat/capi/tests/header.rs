//! `include/vdg.h` is what C programs compile against: it must say exactly
//! what `src/lib.rs` exports. This test runs cbindgen in memory and fails
//! when the committed header is stale; with `VDG_BLESS=1` it rewrites it.

use std::path::Path;

#[test]
fn committed_header_matches_the_exported_functions() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_config(config)
        .with_src(dir.join("src/lib.rs"))
        .generate()
        .expect("cbindgen cannot parse src/lib.rs");
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let path = dir.join("include/vdg.h");
    if std::env::var_os("VDG_BLESS").is_some_and(|v| v == "1") {
        toolbox::write_bytes_atomic(&path, &fresh).expect("cannot write include/vdg.h");
        return;
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "vdgformat/capi/include/vdg.h is stale (it differs from what cbindgen makes of src/lib.rs); \
         regenerate it with: VDG_BLESS=1 cargo test -p vdgformat-capi --test header"
    );
}
