//! Every subcommand's printing survives a reader that closes the pipe early
//! (`vdgview info G | head -1`, `| true`): no panic, no exit 101; a report lost on a
//! full disk (`> /dev/full`) is an error naming it.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

const EXE: &str = env!("CARGO_BIN_EXE_vdgview");

fn map(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/maps")
        .join(format!("{name}.bsp"))
}

fn compiled(dir: &Path) -> PathBuf {
    let vdg = dir.join("two_rooms.vdg");
    bsp2vdg::pipeline::compile(
        &map("two_rooms"),
        &bsp2vdg::options::CompileOptions::new(vdg.clone()),
        &bsp2vdg::log::Log::new(bsp2vdg::log::Verbosity::Quiet, true),
        &bsp2vdg::progress::NoProgress,
    )
    .unwrap();
    vdg
}

#[test]
fn a_closed_pipe_ends_the_printing_not_the_program() {
    let dir = toolbox::ScratchDir::new("vdgview-pipes").unwrap();
    let vdg = compiled(dir.path());
    let (m, g) = (map("two_rooms"), vdg.clone());
    let (m, g) = (m.to_str().unwrap(), g.to_str().unwrap());
    let runs: Vec<Vec<&str>> = vec![
        vec!["info", g],
        vec!["info", m],
        vec!["query", g, "clearance", "0", "0", "0"],
        vec!["check", m, g, "--samples", "500"],
        vec!["replay", m, g, "--max-routes", "1"],
    ];
    for args in runs {
        let quoted: Vec<String> = args.iter().map(|a| format!("'{a}'")).collect();
        for reader in ["head -1 >/dev/null", "true"] {
            let script = format!(
                "'{EXE}' {} | {reader}; exit ${{PIPESTATUS[0]}}",
                quoted.join(" ")
            );
            let o = Command::new("bash")
                .arg("-c")
                .arg(&script)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&o.stderr);
            assert!(!err.contains("panicked"), "{args:?} | {reader}: {err}");
            assert_ne!(o.status.code(), Some(101), "{args:?} | {reader}: {err}");
            // `check` keeps its verdict's meaning; the others succeed.
            if args[0] != "check" {
                assert_eq!(o.status.code(), Some(0), "{args:?} | {reader}: {err}");
            }
        }
    }
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        return;
    };
    let o = Command::new(EXE)
        .args(["info", g])
        .stdout(Stdio::from(full))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("cannot write to standard output"), "{err}");
}

/// `view` without a display: the error names xvfb-run, and `--screenshot` writes the
/// view with no window at all.
#[test]
fn view_without_a_display() {
    let dir = toolbox::ScratchDir::new("vdgview-headless").unwrap();
    let m = map("two_rooms");
    let o = Command::new(EXE)
        .arg("view")
        .arg(&m)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("xvfb-run") && err.contains("--screenshot"),
        "{err}"
    );
    let shot = dir.path().join("shot.png");
    let o = Command::new(EXE)
        .arg("view")
        .arg(&m)
        .args(["--size", "320x200", "--exec", "setang 0 10", "--screenshot"])
        .arg(&shot)
        .env_remove("DISPLAY")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png = std::fs::read(&shot).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    assert_eq!(
        u32::from_be_bytes([png[16], png[17], png[18], png[19]]),
        320
    );
}
