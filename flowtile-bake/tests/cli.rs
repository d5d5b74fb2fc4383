//! End-to-end checks of the `flowtile-bake` binary.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_flowtile-bake"))
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().expect("binary runs")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flowtile-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn spec(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/flowtiles")
        .join(name)
        .display()
        .to_string()
}

/// A failure must be one clear line on stderr, a non-zero exit, no panic.
fn assert_clean_failure(o: &Output, needle: &str) {
    assert!(!o.status.success(), "unexpected success");
    let err = stderr(o);
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains(needle), "expected {needle:?} in {err:?}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err:?}");
}

#[test]
fn count_prints_the_paper_numbers() {
    for (mx, my, c, want) in [
        ("3", "3", "1", "19"),
        ("5", "5", "1", "85"),
        ("3", "3", "5", "11875"),
    ] {
        let o = run(&["count", "--mx", mx, "--my", my, "--corners", c]);
        assert!(o.status.success());
        assert_eq!(stdout(&o).trim(), want);
    }
    let o = run(&[
        "count",
        "--mx",
        "3",
        "--my",
        "3",
        "--corners",
        "1",
        "--classes",
    ]);
    assert!(stdout(&o).contains("rotation classes: 6"));
    assert_clean_failure(&run(&["count", "--mx", "0", "--my", "3"]), "at least 1");
}

#[test]
fn tile_grid_json_has_the_stats() {
    let o = run(&[
        "tile", "--grid", "12x9", "--set", "5,5,1", "--seed", "1", "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["slots"], 108);
    assert!(v["tiles_used"].as_u64().unwrap() <= 85);
    // (5,5,1) is closed under all eight symmetries of the square: fewer
    // classes than tiles, and the file that stores classes is smaller.
    assert!(
        v["symmetry_classes_used"].as_u64() < v["tiles_used"].as_u64(),
        "{v}"
    );
    assert!(
        v["bytes_rotated"].as_u64() < v["bytes_plain"].as_u64(),
        "{v}"
    );
    assert_eq!(v["bytes"], v["bytes_rotated"]);
    assert!(v["seconds"].as_f64().unwrap() >= 0.0);
    // Processor time of the tiling (POSIX systems): never negative.
    if cfg!(unix) {
        assert!(v["cpu_seconds"].as_f64().unwrap() >= 0.0, "{v}");
    }
    assert!(v["max_divergence"].as_f64().unwrap() <= 1e-12);
    assert!(v["max_seam_mismatch"].as_f64().unwrap() <= 1e-12);
    assert_clean_failure(&run(&["tile", "--grid", "12by9"]), "WxH");
    assert_clean_failure(&run(&["tile", "--grid", "4x4", "--set", "5,5"]), "MX,MY,C");
    assert_clean_failure(&run(&["tile"]), "spec file");
}

#[test]
fn spec_tile_info_render_round_trip_is_deterministic() {
    let dir = scratch("roundtrip");
    let (a, b) = (dir.join("a.ftbk"), dir.join("b.ftbk"));
    for out in [&a, &b] {
        let o = run(&["tile", &spec("river.toml"), "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let o = run(&["info", a.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(stdout(&o).trim()).unwrap();
    assert_eq!(v["width"], 28);
    // The river's set mirrors top to bottom only; still fewer tiles stored.
    assert_eq!(v["version"], 2);
    assert!(v["tiles_stored"].as_u64() < v["tiles_used"].as_u64(), "{v}");
    let png = dir.join("r.png");
    let o = run(&[
        "render",
        a.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--px",
        "8",
        "--style",
        "particles",
        "--particles",
        "20",
        "--steps",
        "20",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_inputs_fail_cleanly() {
    let dir = scratch("bad");
    let good = dir.join("good.ftbk");
    assert!(
        run(&[
            "tile",
            "--grid",
            "5x4",
            "--set",
            "3,3,1",
            "-o",
            good.to_str().unwrap()
        ])
        .status
        .success()
    );
    let bytes = std::fs::read(&good).unwrap();
    let cut = dir.join("cut.ftbk");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    assert_clean_failure(&run(&["info", cut.to_str().unwrap()]), "truncated");
    let junk = dir.join("junk.ftbk");
    std::fs::write(&junk, b"hello world, not a tiling").unwrap();
    assert_clean_failure(&run(&["info", junk.to_str().unwrap()]), "magic");
    assert_clean_failure(
        &run(&["render", junk.to_str().unwrap(), "-o", "x.png"]),
        "magic",
    );
    assert_clean_failure(
        &run(&["info", dir.join("missing").to_str().unwrap()]),
        "missing",
    );
    // Unwritable output: error, and nothing left behind.
    let nowhere = dir.join("no/such/dir/out.ftbk");
    assert_clean_failure(
        &run(&["tile", "--grid", "3x3", "-o", nowhere.to_str().unwrap()]),
        "out.ftbk",
    );
    assert!(!nowhere.exists());
    // Bad and infeasible specs.
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 2\nheight = 1\nborder_x = \"zero\"\nborder_y = \"zero\"\n[[flux]]\nedge = \"v\"\nx = 1\ny = 0\nm = 1\n").unwrap();
    assert_clean_failure(&run(&["tile", bad.to_str().unwrap()]), "no complete tiling");
    std::fs::write(&bad, "[tileset]\nmx = 3\n").unwrap();
    assert_clean_failure(&run(&["tile", bad.to_str().unwrap()]), "bad.toml");
    let o = run(&[
        "render",
        good.to_str().unwrap(),
        "-o",
        dir.join("big.png").to_str().unwrap(),
        "--px",
        "100000",
    ]);
    assert_clean_failure(&o, "pixels");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn map_and_animate_write_world_pictures() {
    let dir = scratch("world");
    let ftb = dir.join("river.ftb");
    let o = run(&["tile", &spec("river.toml"), "-o", ftb.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = dir.join("bend.png");
    let json = dir.join("bend.json");
    let o = run(&[
        "map",
        ftb.to_str().unwrap(),
        "--mesh",
        &spec("river-bend.obj"),
        "-o",
        png.to_str().unwrap(),
        "--sampler",
        json.to_str().unwrap(),
        "--cell",
        "64",
        "--width",
        "200",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let s: serde_json::Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
    let (cols, rows) = (s["cols"].as_u64().unwrap(), s["rows"].as_u64().unwrap());
    assert_eq!(s["vx"].as_array().unwrap().len() as u64, cols * rows);
    let gif = dir.join("bend.gif");
    let o = run(&[
        "animate",
        &spec("river.toml"),
        "--keys",
        "2",
        "--frames",
        "2",
        "--particles",
        "20",
        "--width",
        "120",
        "--mesh",
        &spec("river-bend.obj"),
        "-o",
        gif.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&gif).unwrap().starts_with(b"GIF89a"));
    // Bad input: a clear one-line error, nothing written.
    let bad = dir.join("bad.obj");
    std::fs::write(&bad, "v 0 0 0\nf 1/1 1/1 1/1\n").unwrap();
    let out = dir.join("no.png");
    let o = run(&[
        "map",
        ftb.to_str().unwrap(),
        "--mesh",
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "OBJ line 2");
    assert!(!out.exists());
    let o = run(&[
        "animate",
        &spec("river.toml"),
        "--period",
        "0",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "period");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Regions from the shared maps (skipped without them): every GoldSrc,
/// Quake and Quake 2 map gives a spec that `tile` completes, and a picture. Slow
/// (every map), so ignored by default; `scripts/flowtile-regions.sh` measures the
/// same with timings. The quick test below runs two maps.
#[test]
#[ignore]
fn region_from_every_shared_map() {
    region_from_shared_maps(|_| true);
}

#[test]
fn region_from_two_shared_maps() {
    region_from_shared_maps(|p| {
        let n = p.file_name().unwrap().to_string_lossy();
        n.contains("de_dust2") || n.contains("qbsp-example-bsp29") || n == "lq_e0m1-quake2.bsp"
    });
}

fn region_from_shared_maps(pick: impl Fn(&Path) -> bool) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/testmaps");
    if !root.is_dir() {
        eprintln!("skip: {} not found", root.display());
        return;
    }
    let dir = scratch("region");
    let mut maps: Vec<PathBuf> = [
        "goldsrc",
        "goldsrc/nonfree",
        "quake1",
        "quake1/nonfree",
        "quake2",
    ]
    .iter()
    .flat_map(|g| std::fs::read_dir(root.join(g)).into_iter().flatten())
    .flatten()
    .map(|e| e.path())
    .filter(|p| p.extension().is_some_and(|e| e == "bsp") && pick(p))
    .collect();
    maps.sort();
    assert!(!maps.is_empty());
    for map in &maps {
        let spec = dir.join("r.toml");
        let png = dir.join("r.png");
        let o = run(&[
            "region",
            map.to_str().unwrap(),
            "--tile",
            "96",
            "-o",
            spec.to_str().unwrap(),
            "--picture",
            png.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}: {}", map.display(), stderr(&o));
        assert!(std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
        // The map's top view for the editor's background, named in the spec.
        assert!(
            std::fs::read(dir.join("r.top.png"))
                .unwrap()
                .starts_with(b"\x89PNG")
        );
        let o = run(&["tile", spec.to_str().unwrap()]);
        assert!(o.status.success(), "{}: {}", map.display(), stderr(&o));
        let shot = dir.join("edit.png");
        let script = dir.join("s.txt");
        std::fs::write(&script, "fill\n").unwrap();
        let o = run(&[
            "edit",
            spec.to_str().unwrap(),
            "--script",
            script.to_str().unwrap(),
            "--screenshot",
            shot.to_str().unwrap(),
            "--size",
            "800x500",
        ]);
        assert!(o.status.success(), "{}: {}", map.display(), stderr(&o));
        assert!(std::fs::read(&shot).unwrap().starts_with(b"\x89PNG"));
    }
    let o = run(&[
        "region",
        maps[0].to_str().unwrap(),
        "--tile",
        "2",
        "-o",
        "/tmp/x.toml",
    ]);
    assert_clean_failure(&o, "--tile 2");
    let o = run(&["region", "/no/such.bsp", "-o", "/tmp/x.toml"]);
    assert!(!o.status.success());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `edit --script --screenshot` runs headless: the script's saves and bakes
/// land, the screenshot is the same bytes twice; a refused command, a bad
/// line or an impossible spec is one clear error line.
#[test]
fn edit_runs_scripts_headless() {
    let dir = scratch("edit");
    let script = dir.join("s.txt");
    let (toml, ftb) = (dir.join("e.toml"), dir.join("e.ftb"));
    std::fs::write(
        &script,
        format!(
            "place 11 3 2 -1 0 1\nfill\nsave {}\nbake {}\nselect 3 3\ntime 1\n",
            toml.display(),
            ftb.display()
        ),
    )
    .unwrap();
    let shots: Vec<Vec<u8>> = (0..2)
        .map(|k| {
            let shot = dir.join(format!("shot{k}.png"));
            let o = run(&[
                "edit",
                &spec("river.toml"),
                "--script",
                script.to_str().unwrap(),
                "--screenshot",
                shot.to_str().unwrap(),
                "--size",
                "900x500",
            ]);
            assert!(o.status.success(), "{}", stderr(&o));
            assert!(
                stdout(&o).contains("2: fill -> filled 219 slots"),
                "{}",
                stdout(&o)
            );
            std::fs::read(&shot).unwrap()
        })
        .collect();
    assert_eq!(shots[0], shots[1]);
    // The saved spec tiles to the editor's bytes.
    let again = dir.join("again.ftb");
    let o = run(&[
        "tile",
        toml.to_str().unwrap(),
        "-o",
        again.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&ftb).unwrap());
    // A baked file opens too.
    let o = run(&[
        "edit",
        ftb.to_str().unwrap(),
        "--screenshot",
        dir.join("b.png").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(&script, "flux v 28 3 1\n").unwrap();
    let o = run(&[
        "edit",
        &spec("river.toml"),
        "--script",
        script.to_str().unwrap(),
    ]);
    assert_clean_failure(
        &o,
        "line 1: `flux v 28 3 1` refused: the spec admits no tiling",
    );
    std::fs::write(&script, "fill\nwiggle 3\n").unwrap();
    let o = run(&[
        "edit",
        &spec("river.toml"),
        "--script",
        script.to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "line 2: unknown command");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "[tileset]\nmx = 3\nmy = 3\n[grid]\nwidth = 2\nheight = 1\nborder_x = \"zero\"\nborder_y = \"zero\"\n[[flux]]\nedge = \"v\"\nx = 0\ny = 0\nm = 1\n",
    )
    .unwrap();
    let o = run(&[
        "edit",
        bad.to_str().unwrap(),
        "--screenshot",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "admits no tiling");
    let o = run(&[
        "edit",
        "--grid",
        "0x3",
        "--screenshot",
        dir.join("x.png").to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "--grid");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `region --nav`: floors from the bot navigation mesh of de_dust2 (skipped
/// without the shared maps); a corrupt mesh is a one-line error, no output.
#[test]
fn region_from_a_nav_mesh() {
    let map = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/testmaps/goldsrc/nonfree/bspview-cstrike-de_dust2.bsp");
    let nav = map.with_extension("nav");
    if !nav.is_file() {
        eprintln!("skip: {} not found", nav.display());
        return;
    }
    let dir = scratch("region-nav");
    let spec = dir.join("r.toml");
    let o = run(&[
        "region",
        map.to_str().unwrap(),
        "--nav",
        nav.to_str().unwrap(),
        "-o",
        spec.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let stats: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(stats["open_slots"].as_u64().unwrap() > 300, "{stats}");
    assert!(
        stats["floors_from"]
            .as_str()
            .unwrap()
            .contains("navigation mesh")
    );
    let o = run(&["tile", spec.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bad = dir.join("bad.nav");
    std::fs::write(&bad, &std::fs::read(&nav).unwrap()[..1000]).unwrap();
    let out = dir.join("bad.toml");
    let o = run(&[
        "region",
        map.to_str().unwrap(),
        "--nav",
        bad.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_clean_failure(&o, "bad.nav: area count 718");
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A reader that closes the pipe early (`flowtile-bake info F | head -1`)
/// ends the program quietly: exit 0, no panic message. The read end is
/// closed before the child can write, for a command with one short line
/// (`count`) and one with several (`info` on a baked file).
#[test]
fn closed_stdout_pipe_ends_quietly() {
    use std::process::Stdio;
    let dir = scratch("pipe");
    let ftb = dir.join("g.ftb");
    let o = run(&["tile", "--grid", "6x4", "-o", ftb.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let commands: [&[&str]; 3] = [
        &["count", "--mx", "5", "--my", "5", "--corners", "1"],
        &["info", ftb.to_str().unwrap()],
        &["tile", "--grid", "8x8", "--json"],
    ];
    for args in commands {
        let mut child = bin()
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("binary runs");
        drop(child.stdout.take()); // the reader goes away at once
        let o = child.wait_with_output().expect("binary ends");
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(o.status.success(), "{args:?}: {:?} {err}", o.status);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
