//! The command line as users and CI scripts see it: exit codes, one-line errors, the
//! `--json` keys, output files, determinism across thread counts, batch mode.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use toolbox::ScratchDir;

fn bsp2vdg(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_bsp2vdg"))
        .args(args)
        .output()
        .expect("bsp2vdg runs")
}

/// A copy of a small map in a fresh folder (the compile log goes beside the map, and
/// tests must not write into the source tree): a generated map, else a free real one,
/// else none (skip). The folder goes when the copy does.
fn some_map() -> Option<MapCopy> {
    let source = match common::generated_maps().into_iter().next() {
        Some(m) => m,
        None => common::shared_maps(&["goldsrc"])?
            .into_iter()
            .find(|p| p.to_string_lossy().contains("allocblock-vis-test-simple"))?,
    };
    let dir = tempdir("map");
    let path = dir.join(source.file_name().unwrap());
    std::fs::copy(&source, &path).unwrap();
    Some(MapCopy { path, _dir: dir })
}

/// A map copied into its own scratch folder; reads as the copy's path.
struct MapCopy {
    path: PathBuf,
    _dir: ScratchDir,
}

impl std::ops::Deref for MapCopy {
    type Target = PathBuf;
    fn deref(&self) -> &PathBuf {
        &self.path
    }
}

impl AsRef<Path> for MapCopy {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

fn tempdir(name: &str) -> ScratchDir {
    ScratchDir::new(&format!("bsp2vdg-cli-{name}")).unwrap()
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
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no such map file"));

    let Some(map) = some_map() else { return };
    for (opt, val, what) in [
        ("-sd", "0", "-sd"),
        ("-sd", "-4", "-sd"),
        ("-rl", "2", "-rl"),
        ("-ms", "1", "-ms"),
    ] {
        let o = bsp2vdg(&[opt, val, map.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{opt} {val}");
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
    assert_eq!(o.status.code(), Some(2));
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

    let elsewhere = tempdir("logout");
    let out = elsewhere.join("elsewhere.vdg");
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

/// Compile-tool habits: single-dash options of ericw-tools and VHLT are
/// accepted, unknown ones are named with the nearest known one (exit 2).
#[test]
fn compile_tool_options_and_unknown_options() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("habits");
    let log = dir.join("build.log");
    let o = bsp2vdg(&[
        "-lowpriority",
        "-estimate",
        "-chart",
        "-dev",
        "1",
        "-logfile",
        log.to_str().unwrap(),
        "-rl",
        "1.0",
        "-o",
        dir.join("m.vdg").to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("Stage chart"), "{out}");
    assert!(log.is_file() && !dir.join("m.log").exists());
    assert!(
        std::fs::read_to_string(&log)
            .unwrap()
            .contains("Stage chart")
    );

    let o = bsp2vdg(&["-nolog", "-rl", "1.0", "-low", map.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!map.with_extension("log").exists(), "-nolog wrote a log");

    for (args, want) in [
        (
            vec!["-savesample"],
            "unknown option -savesample (did you mean -savesamples?)",
        ),
        (vec!["-lo"], "unknown option -lo (did you mean -low?)"),
        (vec!["--jsn"], "unknown option --jsn (did you mean --json?)"),
        (vec!["-low", "-high"], "cannot be used with"),
    ] {
        let mut a = args.clone();
        a.push(map.to_str().unwrap());
        let o = bsp2vdg(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = stderr(&o);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
}

/// Each way a compile hurt a new user is one clear line and the right exit code.
#[test]
fn hurting_cases_give_one_line_and_the_right_exit_code() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("hurt");

    // A folder as input.
    let o = bsp2vdg(&[dir.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("is a folder, not a map file"),
        "{}",
        stderr(&o)
    );

    // An unwritable output is reported before compiling (no log of a compile).
    let o = bsp2vdg(&["-o", "/nonexistent-dir/x.vdg", map.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot write /nonexistent-dir/x.vdg"));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("Sampling"));

    // A corrupt Quake 2 map gets the reader's error (the lump and the problem), not
    // "a format bsp2vdg does not read"; a format it does not read is named as such.
    let q2 = dir.join("q2.bsp");
    let mut bytes = b"IBSP".to_vec();
    bytes.extend_from_slice(&38i32.to_le_bytes());
    bytes.extend_from_slice(&100_000i32.to_le_bytes()); // entities past the end
    bytes.extend_from_slice(&50i32.to_le_bytes());
    bytes.resize(200, 0);
    std::fs::write(&q2, &bytes).unwrap();
    let o = bsp2vdg(&[q2.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("lump") && !err.contains("does not read"),
        "{err}"
    );
    let vbsp = dir.join("source.bsp");
    let mut bytes = b"VBSP".to_vec();
    bytes.extend_from_slice(&20i32.to_le_bytes());
    bytes.resize(2000, 0);
    std::fs::write(&vbsp, &bytes).unwrap();
    let o = bsp2vdg(&[vbsp.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("Source"), "{}", stderr(&o));

    // An empty graph is a failure, with nothing written.
    let out = dir.join("empty.vdg");
    let o = bsp2vdg(&[
        "-md",
        "100000",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("the graph is empty"), "{}", stderr(&o));
    assert!(!out.exists());

    // -quiet in batch mode: the failing map's error is still shown, the good map built.
    let outdir = dir.join("batch");
    std::fs::create_dir(&outdir).unwrap();
    let o = bsp2vdg(&[
        "-quiet",
        "-rl",
        "1.0",
        "-o",
        outdir.to_str().unwrap(),
        map.to_str().unwrap(),
        q2.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("q2.bsp") && err.contains("lump"), "{err}");
    // -quiet keeps the summary table only.
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("2 maps: 1 compiled, 0 up to date, 1 failed"),
        "{out}"
    );
    assert!(!out.contains("Loading"), "{out}");
    let stem = map.file_stem().unwrap().to_str().unwrap();
    assert!(outdir.join(format!("{stem}.vdg")).is_file());
}

/// VHLT's convention: `MAP.err` beside the output on failure, removed on success.
#[test]
fn err_file_on_failure_removed_on_success() {
    let Some(map) = some_map() else { return };
    let err_file = map.with_extension("err");
    let o = bsp2vdg(&["-md", "100000", map.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let text = std::fs::read_to_string(&err_file).expect("MAP.err written");
    assert!(text.contains("the graph is empty"), "{text}");
    let o = bsp2vdg(&["-rl", "1.0", map.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!err_file.exists(), "MAP.err left after a success");
}

/// Batch mode skips maps whose output is current for the same map bytes, options and
/// tool version; a change of an option, a changed map or -force rebuilds.
#[test]
fn batch_skips_up_to_date_outputs() {
    let (Some(a), Some(b)) = (some_map(), some_map()) else {
        return;
    };
    let b2 = b.with_file_name("second.bsp");
    std::fs::rename(&b, &b2).unwrap();
    let out = tempdir("uptodate");
    let run = |extra: &[&str]| {
        let mut args = vec!["-rl", "1.0", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.extend([a.to_str().unwrap(), b2.to_str().unwrap()]);
        let o = bsp2vdg(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    assert!(run(&[]).contains("2 compiled, 0 up to date"));
    let second = run(&[]);
    assert!(second.contains("0 compiled, 2 up to date"), "{second}");
    assert!(second.contains("up to date (skipped; -force rebuilds)"));
    assert!(run(&["-sd", "30"]).contains("2 compiled, 0 up to date"));
    assert!(run(&["-sd", "30", "-force"]).contains("2 compiled, 0 up to date"));
    // A changed map is rebuilt, the other skipped.
    let mut bytes = std::fs::read(&b2).unwrap();
    bytes.extend_from_slice(b"\0\0\0\0");
    std::fs::write(&b2, &bytes).unwrap();
    let third = run(&["-sd", "30"]);
    assert!(third.contains("1 compiled, 1 up to date"), "{third}");
}

/// Renaming or moving the map does not change the output's bytes (build farms run
/// steps in sandboxes with other paths); --source-name records the name when asked.
#[test]
fn output_does_not_depend_on_the_map_name() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("hermetic");
    let renamed = dir.join("other-name.bsp");
    std::fs::copy(&map, &renamed).unwrap();
    let build = |m: &std::path::Path, out: &str, extra: &[&str]| {
        let out = dir.join(out);
        let mut args = vec!["-quiet", "-rl", "1.0", "-o", out.to_str().unwrap()];
        args.extend_from_slice(extra);
        args.push(m.to_str().unwrap());
        let o = bsp2vdg(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(out).unwrap()
    };
    let a = build(&map, "a.vdg", &[]);
    let b = build(&renamed, "b.vdg", &[]);
    assert!(a == b, "renaming the map changed the output");
    let c = build(&renamed, "c.vdg", &["--source-name"]);
    let d = build(&map, "d.vdg", &["--source-name=other-name.bsp"]);
    assert!(a != c, "--source-name recorded nothing");
    assert!(
        c == d,
        "--source-name=NAME differs from the file's own name"
    );
}

/// A run killed before its final rename leaves `.X.vdg.tmpPID-N`; the next run removes
/// it (and the older `X.vdg.tmpPID` spelling).
#[test]
fn stale_temporaries_of_killed_runs_are_removed() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("stale");
    let out = dir.join("m.vdg");
    // Pids beyond Linux's limit (2^22) belong to no running process.
    let stale = [
        dir.join(".m.vdg.tmp4194304999-0"),
        dir.join("m.vdg.tmp4194304998"),
    ];
    for s in &stale {
        std::fs::write(s, b"half").unwrap();
    }
    let o = bsp2vdg(&[
        "-rl",
        "1.0",
        "-o",
        out.to_str().unwrap(),
        map.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    if std::path::Path::new("/proc/self").exists() {
        for s in &stale {
            assert!(!s.exists(), "{} left", s.display());
        }
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("left behind by a run that was killed")
        );
    }
}

/// CI regression mode: an identical rebuild passes, a change of -sd is caught (exit 1),
/// and --json gives the same verdicts.
#[test]
fn baseline_catches_a_change_of_sd_and_passes_a_rebuild() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("baseline");
    let base = dir.join("base");
    let m = map.to_str().unwrap();
    let b = base.to_str().unwrap();
    let common = ["-rl", "1.0", "--check-samples", "2000"];
    let run = |extra: &[&str]| {
        let mut args: Vec<&str> = common.to_vec();
        args.extend_from_slice(extra);
        args.push(m);
        bsp2vdg(&args)
    };
    let o = run(&["--update-baseline", b]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stem = map.file_stem().unwrap().to_str().unwrap();
    assert!(base.join(format!("{stem}.vdg")).is_file());
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(base.join(format!("{stem}.json"))).unwrap())
            .unwrap();
    assert!(stats["check"]["coverage"].is_number(), "{stats}");
    assert!(stats["vertices"].as_u64().unwrap() > 0);

    let o = run(&["--baseline", b]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("identical") && out.contains("0 regressions"),
        "{out}"
    );

    let o = run(&["--baseline", b, "-sd", "40"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("REGRESSION"), "{out}");
    // The table says the options differ, not only the JSON.
    assert!(
        out.contains("options differ from the baseline's: sd: 24 -> 40"),
        "{out}"
    );

    let o = run(&["--baseline", b, "-sd", "40", "--json"]);
    assert_eq!(o.status.code(), Some(1));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["regressed"], true);
    let figs = v["maps"][0]["figures"].as_array().unwrap();
    assert!(
        figs.iter()
            .any(|f| f["name"] == "vertices" && f["ok"] == false),
        "{v}"
    );

    // Looser tolerances from a TOML file let the same change pass the counts.
    let tol = dir.join("tol.toml");
    std::fs::write(
        &tol,
        "counts = 10.0\nbytes = 10.0\nquality = 1.0\n[figures]\nleak = 1.0\nvisible_fp = 1.0\n",
    )
    .unwrap();
    let o = run(&[
        "--baseline",
        b,
        "-sd",
        "40",
        "--tolerances",
        tol.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stdout));

    // No baseline folder, or a typo in the tolerances: configuration errors, exit 2.
    let o = run(&["--baseline", dir.join("none").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    std::fs::write(&tol, "cuonts = 10.0\n").unwrap();
    let o = run(&["--baseline", b, "--tolerances", tol.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("cuonts"), "{}", stderr(&o));
    // A folder without this map's baseline: exit 1 with the reason.
    let empty = dir.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let o = run(&["--baseline", empty.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stdout).contains("run --update-baseline first"));
}

/// `-md` is what the help and README say: the minimum clearance of the unreduced
/// graph. Without reduction no written vertex is below it, and the value matters
/// (a lower `-md` keeps vertices the higher one dropped). After the reduction it is no
/// floor (condition A lowers clearances); `vdgview info` says so, see its tests.
#[test]
fn md_is_the_minimum_clearance_of_the_unreduced_graph() {
    let Some(map) = some_map() else { return };
    let dir = tempdir("md");
    let min_clearance = |md: &str| {
        let out = dir.join(format!("md{md}.vdg"));
        let o = bsp2vdg(&[
            "-quiet",
            "-rl",
            "1.0",
            "-md",
            md,
            "-o",
            out.to_str().unwrap(),
            map.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let file = vdgformat::VdgFile::open(&out).unwrap();
        let g = file.graph();
        assert_eq!(g.metadata_value("md"), Some(md));
        g.vertices()
            .iter()
            .map(|v| v.clearance)
            .fold(f32::INFINITY, f32::min)
    };
    let (low, high) = (min_clearance("8"), min_clearance("40"));
    assert!(low >= 8.0, "a vertex at {low} under -md 8");
    assert!(high >= 40.0, "a vertex at {high} under -md 40");
    assert!(
        low < 40.0,
        "-md 8 kept nothing below 40 ({low}): the test shows nothing"
    );
}
