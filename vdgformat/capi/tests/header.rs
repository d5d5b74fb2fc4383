//! `include/vdg.h` is what C programs compile against: it must say exactly
//! what `src/lib.rs` exports. This test runs cbindgen in memory and fails
//! when the committed header is stale; with `VDG_BLESS=1` it rewrites it.
//! The header is C89 (`-std=c89 -pedantic`, proven by tests/c_smoke.rs):
//! cbindgen writes the documentation as `/* */` comments, and [`c89`] turns
//! the `//` labels it puts after its `#endif`s into `/* */` ones.

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
    let mut raw = Vec::new();
    bindings.write(&mut raw);
    let fresh = c89(&String::from_utf8(raw).expect("cbindgen writes UTF-8")).into_bytes();
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

/// cbindgen's `#endif // __cplusplus` lines as C89 allows them.
fn c89(header: &str) -> String {
    header
        .lines()
        .map(|l| match l.split_once("//") {
            Some((code, label)) if l.trim_start().starts_with("#endif") || code.trim() == "}" => {
                format!("{}/* {} */", code, label.trim())
            }
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

#[test]
fn the_header_has_no_line_comments() {
    let header =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/vdg.h"))
            .unwrap();
    let line_comments: Vec<&str> = header
        .lines()
        .filter(|l| l.contains("//") && !l.contains("://"))
        .collect();
    assert!(
        line_comments.is_empty(),
        "C89 has no // comments: {line_comments:?}"
    );
}
