//! bsp2vdg in a build chain: a closed or full stdout never stops the compile, an
//! output never destroys a map, two maps never share an output, every command-line
//! mistake exits 2 before compiling, the log is written as the compile goes, and the
//! compile tools' shared flags and map names without `.bsp` are accepted.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use toolbox::ScratchDir;

const EXE: &str = env!("CARGO_BIN_EXE_bsp2vdg");

fn bsp2vdg(args: &[&str]) -> Output {
    Command::new(EXE).args(args).output().expect("bsp2vdg runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A fresh folder with a copy of the smallest generated map as `box.bsp`.
fn folder_with_map(tag: &str) -> Option<(ScratchDir, PathBuf)> {
    let source = common::generated_maps().into_iter().next()?;
    let dir = ScratchDir::new(&format!("bsp2vdg-chain-{tag}")).unwrap();
    let map = dir.path().join("box.bsp");
    std::fs::copy(source, &map).unwrap();
    Some((dir, map))
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `bsp2vdg MAP | head -1` through a real shell: bsp2vdg's own exit status, the files.
#[test]
fn a_closed_pipe_never_stops_the_compile() {
    let Some((dir, map)) = folder_with_map("pipe") else {
        return;
    };
    let out = dir.path().join("out.vdg");
    let script = format!(
        "'{EXE}' -rl 1.0 -verbose '{}' -o '{}' | head -1 >/dev/null; exit ${{PIPESTATUS[0]}}",
        s(&map),
        s(&out)
    );
    let o = Command::new("bash")
        .arg("-c")
        .arg(&script)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{}", stderr(&o));
    assert!(out.is_file(), "no .vdg after a closed pipe");
    let log = std::fs::read_to_string(out.with_extension("log")).unwrap();
    assert!(log.contains("Loading model"), "{log}");

    // Batch mode: the worker threads print too.
    let copy = dir.path().join("copy.bsp");
    std::fs::copy(&map, &copy).unwrap();
    let outdir = dir.path().join("batch");
    std::fs::create_dir(&outdir).unwrap();
    let script = format!(
        "'{EXE}' -rl 1.0 '{}' '{}' -o '{}' | true; exit ${{PIPESTATUS[0]}}",
        s(&map),
        s(&copy),
        s(&outdir)
    );
    let o = Command::new("bash")
        .arg("-c")
        .arg(&script)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(outdir.join("box.vdg").is_file() && outdir.join("copy.vdg").is_file());
}

/// `> /dev/full`: the log on stdout is lost, the compile is not.
#[test]
fn a_full_stdout_never_stops_the_compile() {
    let Some((dir, map)) = folder_with_map("full") else {
        return;
    };
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        eprintln!("skipped: no /dev/full");
        return;
    };
    let out = dir.path().join("out.vdg");
    let o = Command::new(EXE)
        .args(["-rl", "1.0", s(&map), "-o", s(&out)])
        .stdout(Stdio::from(full))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(out.is_file());
}

#[test]
fn an_output_that_is_the_map_is_refused() {
    let Some((dir, map)) = folder_with_map("same") else {
        return;
    };
    let before = std::fs::read(&map).unwrap();
    let o = bsp2vdg(&[s(&map), "-o", s(&map)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(&map).unwrap(),
        before,
        "the map was overwritten"
    );
    // Through a hard link with a .vdg name.
    let link = dir.path().join("link.vdg");
    std::fs::hard_link(&map, &link).unwrap();
    let o = bsp2vdg(&[s(&map), "-o", s(&link)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("is the map"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&map).unwrap(), before);
    // Any output with a map's extension.
    let other = dir.path().join("other.bsp");
    let o = bsp2vdg(&[s(&map), "-o", s(&other)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!other.exists());
}

#[test]
fn maps_with_the_same_name_are_refused_naming_both() {
    let Some((dir, map)) = folder_with_map("dup") else {
        return;
    };
    for d in ["a", "b", "out"] {
        std::fs::create_dir(dir.path().join(d)).unwrap();
    }
    let (a, b) = (dir.path().join("a/x.bsp"), dir.path().join("b/x.bsp"));
    std::fs::copy(&map, &a).unwrap();
    std::fs::copy(&map, &b).unwrap();
    let out = dir.path().join("out");
    let o = bsp2vdg(&[s(&a), s(&b), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains(s(&a)) && err.contains(s(&b)), "{err}");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 0);
    // The same map twice.
    let o = bsp2vdg(&[s(&a), s(&a), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("given twice"), "{}", stderr(&o));
}

#[test]
fn output_folders_are_settled_before_compiling() {
    let Some((dir, map)) = folder_with_map("dir") else {
        return;
    };
    let outdir = dir.path().join("out");
    std::fs::create_dir(&outdir).unwrap();
    let cwd = ScratchDir::new("bsp2vdg-chain-cwd").unwrap();
    let o = Command::new(EXE)
        .args(["-rl", "1.0", s(&map), "-o", s(&outdir)])
        .current_dir(cwd.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(outdir.join("box.vdg").is_file() && outdir.join("box.log").is_file());
    assert_eq!(std::fs::read_dir(cwd.path()).unwrap().count(), 0);
    // A missing folder: exit 2 before compiling, nothing written anywhere.
    let missing = dir.path().join("missing/");
    let o = Command::new(EXE)
        .args([s(&map), "-o", s(&missing)])
        .current_dir(cwd.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    assert!(!String::from_utf8_lossy(&o.stdout).contains("Loading"));
    assert_eq!(std::fs::read_dir(cwd.path()).unwrap().count(), 0);
}

#[test]
fn command_line_mistakes_exit_2_without_compiling() {
    let Some((dir, map)) = folder_with_map("usage") else {
        return;
    };
    for args in [
        vec!["-sd", "0"],
        vec!["-rl", "2"],
        vec!["-ms", "0"],
        vec!["-threads", "100000"],
        vec!["-nosuchoption"],
    ] {
        let mut a = args.clone();
        a.push(s(&map));
        let o = bsp2vdg(&a);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
        assert!(!map.with_extension("err").exists(), "{args:?} wrote .err");
    }
    let o = bsp2vdg(&[s(&dir.path().join("missing.bsp"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no such map file"));
    // A map that fails is 1.
    let o = bsp2vdg(&["-md", "100000", s(&map)]);
    assert_eq!(o.status.code(), Some(1));
}

#[test]
fn compile_tool_flags_and_names_without_bsp() {
    let Some((_dir, map)) = folder_with_map("flags") else {
        return;
    };
    let without = map.with_extension("");
    let o = bsp2vdg(&[
        "-texdata",
        "8192",
        "-lightdata",
        "8192",
        "-noinfo",
        "-console",
        "0",
        "-wadautodetect",
        "-chop",
        "64",
        "-nocolor",
        "-estimate",
        "-rl",
        "1.0",
        s(&without),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let warnings: Vec<&str> = out.lines().filter(|l| l.contains("ignoring")).collect();
    assert_eq!(warnings.len(), 1, "{out}");
    assert!(warnings[0].contains("-texdata 8192") && warnings[0].contains("-nocolor"));
    assert!(map.with_extension("vdg").is_file());
}

/// The log is appended as the compile goes: killed after its first stage line, the
/// compile leaves a log holding that line.
#[test]
fn the_log_is_written_as_the_compile_goes() {
    let Some((dir, map)) = folder_with_map("log") else {
        return;
    };
    let out = dir.path().join("out.vdg");
    // Fine sampling keeps the compile busy for a while after its first line.
    let mut child = Command::new(EXE)
        .args(["-sd", "1", "-ms", "100000000", s(&map), "-o", s(&out)])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = std::io::BufRead::lines(std::io::BufReader::new(child.stdout.take().unwrap()));
    let seen = lines.any(|l| l.is_ok_and(|l| l.contains("Loading model")));
    child.kill().unwrap();
    let _ = child.wait();
    assert!(seen);
    let log = std::fs::read_to_string(out.with_extension("log")).expect("a log after a kill");
    assert!(log.contains("Loading model"), "{log}");
}

/// The build identity is recorded in the .vdg and shown by --version.
#[test]
fn the_build_identity_is_recorded() {
    let Some((_dir, map)) = folder_with_map("build") else {
        return;
    };
    let o = bsp2vdg(&["--version"]);
    let version = String::from_utf8_lossy(&o.stdout).into_owned();
    let build = version
        .split("(build ")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .expect("--version names the build")
        .to_string();
    assert_eq!(build.len(), 16, "{version}");
    let o = bsp2vdg(&["-rl", "1.0", s(&map)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let file = vdgformat::VdgFile::open(map.with_extension("vdg")).unwrap();
    assert_eq!(
        file.graph().metadata_value("tool.build"),
        Some(build.as_str())
    );
}
