//! Gives the shared library its SONAME, `libvdg.so.N`, N being `VDG_ABI_VERSION`
//! of `src/lib.rs` (read from there, so the number is written once): a program
//! linked against one ABI never loads a library of another.

fn main() {
    println!("cargo:rerun-if-changed=src/lib.rs");
    let source = std::fs::read_to_string("src/lib.rs").unwrap_or_default();
    let abi = source
        .lines()
        .find_map(|l| l.trim().strip_prefix("pub const VDG_ABI_VERSION: c_int = "))
        .and_then(|rest| rest.trim_end_matches(';').trim().parse::<u32>().ok())
        .expect("src/lib.rs defines pub const VDG_ABI_VERSION: c_int = N;");
    println!("cargo:rustc-env=VDG_ABI_VERSION={abi}");
    let os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if os == "linux" || os.ends_with("bsd") {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libvdg.so.{abi}");
    }
}
