//! The command line as users and CI scripts see it: exit codes, one-line errors, the
//! `--json` keys, output files, determinism across thread counts, batch mode.

mod common;

use std::path::PathBuf;
use std::process::{Command, Output};

fn bsp2vdg(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bsp2vdg"))
        .args(args)
        .output()
        .expect("bsp2vdg runs")
}

/// A copy of a small map in a fresh folder (the compile log goes beside the map, and
/// tests must not write into the source tree): a generated map, else a free real one,
/// else none (skip).
fn some_map() -> Option<PathBuf> {
    let source = match common::generated_maps().into_iter().next() {
        Some(m) => m,
        None => common::shared_maps(&["goldsrc"])?
            .into_iter()
            .find(|p| p.to_string_lossy().contains("allocblock-vis-test-simple"))?,
    };
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COPIES: AtomicUsize = AtomicUsize::new(0);
    let dir = tempdir(&format!("map{}", COPIES.fetch_add(1, Ordering::Relaxed)));
    let copy = dir.join(source.file_name().unwrap());
    std::fs::copy(&source, &copy).unwrap();
    Some(copy)
}

fn tempdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bsp2vdg-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn json_report_has_the_documented_keys() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("json");
    let out = dir.join("m.vdg");
    let o = bsp2vdg(&[
        "--stop-after",
        "samples",
        "--json",
        "-savesamples",
        "--samples-format",
        "qhull",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value =
        serde_json::from_slice(&o.stdout).expect("stdout is one JSON object");
    for key in [
        "faces",
        "sampled_faces",
        "samples",
        "sample_spacing",
        "seconds",
    ] {
        assert!(v.get(key).is_some(), "missing {key} in {v}");
    }
    for stage in ["load", "sample", "total"] {
        assert!(
            v["seconds"][stage].as_f64().is_some(),
            "missing seconds.{stage}"
        );
    }
    let samples = v["samples"].as_u64().unwrap();
    assert!(samples > 0 && v["sample_spacing"].as_f64() == Some(24.0));
    // qhull format: dimension, count, then one point per line.
    let text = std::fs::read_to_string(dir.join("m.samples.txt")).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "3");
    assert_eq!(lines[1].parse::<u64>().unwrap(), samples);
    assert_eq!(lines.len() as u64, samples + 2);
}

#[test]
fn unbuilt_stages_fail_clearly() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("unbuilt");
    let out = dir.join("m.vdg");
    let o = bsp2vdg(&["-quiet", "-o", out.to_str().unwrap(), map.to_str().unwrap()]);
    if o.status.success() {
        // Later stages exist: then the output must be there.
        assert!(out.exists());
        return;
    }
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("not built yet"), "{err}");
}

#[test]
fn corrupt_maps_and_bad_options_give_one_line_errors() {
    let dir = tempdir("bad");
    let bad = dir.join("bad.bsp");
    let mut bytes = vec![0u8; 300];
    bytes[..4].copy_from_slice(&30i32.to_le_bytes());
    bytes[4..8].copy_from_slice(&1000i32.to_le_bytes()); // entities lump past the end
    bytes[8..12].copy_from_slice(&50i32.to_le_bytes());
    std::fs::write(&bad, &bytes).unwrap();
    let o = bsp2vdg(&["--stop-after", "samples", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("lump entities") && err.contains("truncated or corrupt"),
        "{err}"
    );
    assert!(!dir.join("bad.vdg").exists());

    let missing = dir.join("missing.bsp");
    let o = bsp2vdg(&[missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no such map file"));

    let Some(map) = some_map() else { return };
    for (opt, val, what) in [
        ("-sd", "0", "-sd"),
        ("-sd", "-4", "-sd"),
        ("-rl", "2", "-rl"),
        ("-ms", "1", "-ms"),
    ] {
        let o = bsp2vdg(&[opt, val, map.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{opt} {val}");
        let err = stderr(&o);
        assert!(
            err.starts_with("bsp2vdg: error: ") && err.contains(what),
            "{err}"
        );
    }
}

#[test]
fn unwritable_output_leaves_nothing_behind() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("unwritable");
    let out = dir.join("no/such/dir/m.vdg");
    let o = bsp2vdg(&[
        "--stop-after",
        "samples",
        "-savesamples",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("cannot write"), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
}

#[test]
fn samples_are_identical_for_any_thread_count() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("threads");
    let mut files = Vec::new();
    for t in ["1", "2", "3"] {
        let out = dir.join(format!("t{t}.vdg"));
        let o = bsp2vdg(&[
            "--stop-after",
            "samples",
            "-savesamples",
            "-threads",
            t,
            "-quiet",
            "-o",
            out.to_str().unwrap(),
            map.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        files.push(std::fs::read(dir.join(format!("t{t}.samples.txt"))).unwrap());
    }
    assert!(files.windows(2).all(|w| w[0] == w[1]));
}

#[test]
fn batch_mode_compiles_several_maps_with_a_summary() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("batch");
    let bad = dir.join("broken.bsp");
    std::fs::write(&bad, b"not a map at all, clearly").unwrap();
    let o = bsp2vdg(&[
        "--stop-after",
        "samples",
        "-o",
        dir.to_str().unwrap(),
        map.to_str().unwrap(),
        bad.to_str().unwrap(),
    ]);
    // One map failed: the batch fails, but the good map was compiled and summarised.
    assert_eq!(o.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("status"), "{stdout}");
    assert!(
        stdout
            .lines()
            .any(|l| l.contains("broken.bsp") && l.contains("FAILED")),
        "{stdout}"
    );
    assert!(stdout.lines().any(|l| l.ends_with(" ok")), "{stdout}");
}

#[test]
fn unreduced_graph_is_written_identically_for_any_thread_count() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("vdg");
    let mut files = Vec::new();
    for t in ["1", "2"] {
        let out = dir.join(format!("t{t}.vdg"));
        let o = bsp2vdg(&[
            "-rl",
            "1.0",
            "--json",
            "-threads",
            t,
            "-o",
            out.to_str().unwrap(),
            map.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        for key in [
            "tetrahedra",
            "inner_vertices",
            "inner_faces",
            "vertices",
            "bytes",
        ] {
            assert!(v[key].as_u64().is_some_and(|n| n > 0), "{key} in {v}");
        }
        let file = vdgformat::VdgFile::open(&out).expect("the written .vdg opens");
        let g = file.graph();
        assert_eq!(g.vertices().len() as u64, v["vertices"].as_u64().unwrap());
        files.push(std::fs::read(&out).unwrap());
    }
    assert!(
        files[0] == files[1],
        "the .vdg differs between 1 and 2 threads"
    );
    // No temporary files are left beside the output.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.contains("tmp")), "{names:?}");
}

/// The log goes beside the output: MAP.log for the default output, and with `-o`
/// elsewhere the map's folder is left untouched.
#[test]
fn the_log_goes_beside_the_output() {
    let Some(map) = some_map() else { return };
    let o = bsp2vdg(&["-quiet", "--stop-after", "samples", map.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        map.with_extension("log").is_file(),
        "no MAP.log beside the map"
    );
    std::fs::remove_file(map.with_extension("log")).unwrap();

    let out = tempdir("logout").join("elsewhere.vdg");
    let o = bsp2vdg(&[
        "-quiet",
        "--stop-after",
        "samples",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        out.with_extension("log").is_file(),
        "no log beside the output"
    );
    assert!(
        !map.with_extension("log").exists(),
        "the map's folder got a log"
    );
}
