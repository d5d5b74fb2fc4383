//! Baking on Dask.distributed (scripts/bake.py): a scheduler and two worker processes on
//! 127.0.0.1, a worker killed mid-batch, every map still baked and byte-identical to a
//! direct compile. Skips with a message when Python or its dask.distributed package is
//! missing (the compiler itself needs neither).

use std::path::Path;
use std::process::Command;

#[test]
fn bake_on_a_loopback_cluster_survives_a_killed_worker() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let script = root.join("scripts/bake_loopback_test.py");
    let have_dask = Command::new("python3")
        .args(["-c", "import distributed"])
        .output()
        .is_ok_and(|o| o.status.success());
    let have_cli = Command::new("dask")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !(have_dask && have_cli) {
        eprintln!("skipped: python3 with dask.distributed (pip install distributed) is missing");
        return;
    }
    let mut maps: Vec<_> = std::fs::read_dir(root.join("testdata/maps"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        // The largest generated map takes longest; five small ones keep this test short.
        .filter(|p| !p.ends_with("complex.bsp"))
        .collect();
    maps.sort();
    let o = Command::new("python3")
        .arg(&script)
        .arg("--bsp2vdg")
        .arg(env!("CARGO_BIN_EXE_bsp2vdg"))
        .args(&maps)
        .args(["--", "-rl", "1.0"])
        .current_dir(&root)
        .output()
        .expect("python3 runs");
    let out = String::from_utf8_lossy(&o.stdout);
    if o.status.code() == Some(77) {
        eprintln!("{out}");
        return;
    }
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("killed worker"), "{out}");
    assert!(out.contains("was redone: built"), "{out}");
}

/// scripts/bake_test.py: bake.py's per-map timeout, its log per map, its progress on a
/// terminal and in a pipe, and its refusal of two maps with one name, with no cluster (an
/// in-process stand-in for the Dask client). Needs only python3.
#[test]
fn bake_script_keeps_logs_progress_and_timeouts() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    if Command::new("python3").arg("--version").output().is_err() {
        eprintln!("skipped: no python3 to run scripts/bake_test.py");
        return;
    }
    let o = Command::new("python3")
        .arg(root.join("scripts/bake_test.py"))
        .arg("--bsp2vdg")
        .arg(env!("CARGO_BIN_EXE_bsp2vdg"))
        .current_dir(&root)
        .output()
        .expect("python3 runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && !out.contains("FAILED"),
        "scripts/bake_test.py failed:\n{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
