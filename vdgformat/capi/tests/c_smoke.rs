//! The proof in C: `tests/c/smoke.c` is compiled with the system C compiler
//! against the `libvdg.a` cargo built for this test run, opens a generated
//! map's `.vdg` from a path and from memory, runs the queries, 600 camera
//! frames and a director, and prints every float as its bit pattern. The
//! same script run through the Rust API must give the same text byte for
//! byte. Skips (with a message) where no C compiler is found.
//!
//! `scripts/capi-check.sh` runs the same program under valgrind and times it
//! against the Rust API; `SMOKE_KEEP=DIR` keeps the compiled program, graph
//! and script in DIR for that.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use toolbox::SplitMix64;
use vdgformat::camera::{Camera, CameraParams, Director, DirectorEvent, Pose, Status, Target};
use vdgformat::{Vdg, VdgFile};

const FRAMES: usize = 600;
const DIRECTOR_PARAMS: &str = "distance_mu = 160.0\nangle_mu_yaw_deg = 90.0\n";

fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scratch_dir() -> PathBuf {
    let dir = match std::env::var_os("SMOKE_KEEP") {
        Some(d) => PathBuf::from(d),
        None => Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("capi-smoke-{}", std::process::id())),
    };
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Compiles `testdata/maps/complex.bsp` with the bsp2vdg library.
fn compile_map(dir: &Path) -> PathBuf {
    use bsp2vdg::log::{Log, Verbosity};
    let out = dir.join("complex.vdg");
    let options = bsp2vdg::options::CompileOptions::new(out.clone());
    let map = repo_root().join("testdata/maps/complex.bsp");
    bsp2vdg::pipeline::compile(
        &map,
        &options,
        &Log::new(Verbosity::Quiet, true),
        &bsp2vdg::progress::NoProgress,
    )
    .unwrap_or_else(|e| panic!("compiling {}: {e}", map.display()));
    out
}

fn hex(f: f32) -> String {
    format!("{:08x}", f.to_bits())
}

struct Query {
    a: [f32; 3],
    b: [f32; 3],
    radius: f32,
}

struct Frame {
    target: [f32; 9],
    dt: f32,
}

impl Frame {
    fn target(&self) -> Target {
        let t = &self.target;
        Target::from_angles([t[0], t[1], t[2]], [t[3], t[4], t[5]], [t[6], t[7], t[8]])
    }
}

/// Query pairs between jittered vertex positions (mostly inside the volume),
/// a few far outside, and agent radii from 0 to beyond the widest door.
fn queries(g: &Vdg<'_>, rng: &mut SplitMix64) -> Vec<Query> {
    let vs = g.vertices();
    let max = g.info().max_clearance;
    let pick = |rng: &mut SplitMix64| {
        let v = vs[rng.below(vs.len())];
        let j = |rng: &mut SplitMix64| rng.range(-0.5, 0.5) as f32 * v.clearance;
        [v.pos[0] + j(rng), v.pos[1] + j(rng), v.pos[2] + j(rng)]
    };
    let mut out: Vec<Query> = (0..40)
        .map(|i| Query {
            a: pick(rng),
            b: pick(rng),
            radius: [0.0, 16.0, 0.5 * max, 1.5 * max][i % 4],
        })
        .collect();
    let far = g.info().volume_max.map(|c| c + 1000.0);
    out.push(Query {
        a: far,
        b: pick(rng),
        radius: 0.0,
    });
    out
}

/// A player running through the level at 265 u/s: along the graph's path
/// between two far-apart vertices and back, looking where it goes, with
/// irregular frame times (a 0 and long frames) and a teleport at frame 450.
fn frames(g: &Vdg<'_>) -> Vec<Frame> {
    let vs = g.vertices();
    let by_x = |i: &u32| vs[*i as usize].pos[0] + vs[*i as usize].pos[1];
    let all: Vec<u32> = (0..vs.len() as u32).collect();
    let lo = *all
        .iter()
        .min_by(|a, b| by_x(a).total_cmp(&by_x(b)))
        .unwrap();
    let hi = *all
        .iter()
        .max_by(|a, b| by_x(a).total_cmp(&by_x(b)))
        .unwrap();
    let path = g
        .vertex_path(lo, hi)
        .expect("the test map's graph is connected");
    let mut poly: Vec<[f64; 3]> = path
        .vertices
        .iter()
        .map(|&v| vs[v as usize].pos.map(f64::from))
        .collect();
    let back: Vec<_> = poly.iter().rev().skip(1).copied().collect();
    poly.extend(back);
    let seg = |i: usize| {
        let (a, b) = (poly[i], poly[i + 1]);
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        (a, d, (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
    };
    let (mut i, mut along) = (0, 0.0);
    (0..FRAMES)
        .map(|f| {
            let dt: f32 = match f % 97 {
                13 => 0.0,
                50 => 0.1,
                _ => 1.0 / 60.0,
            };
            let mut step = 265.0 * f64::from(dt);
            if f == 450 {
                (i, along) = (0, 0.0); // teleport back to the start
                step = 0.0;
            }
            along += step;
            while i + 2 < poly.len() && along > seg(i).2 {
                along -= seg(i).2;
                i += 1;
            }
            let (a, d, len) = seg(i);
            let u = if len > 0.0 {
                (along / len).min(1.0)
            } else {
                0.0
            };
            let pos = [a[0] + u * d[0], a[1] + u * d[1], a[2] + u * d[2] - 36.0];
            let horiz = (d[0] * d[0] + d[1] * d[1]).sqrt();
            let (pitch, yaw) = (
                -d[2].atan2(horiz).to_degrees(),
                d[1].atan2(d[0]).to_degrees(),
            );
            let v = if len > 0.0 { 265.0 / len } else { 0.0 };
            Frame {
                target: [
                    pos[0] as f32,
                    pos[1] as f32,
                    pos[2] as f32,
                    pitch as f32,
                    yaw as f32,
                    0.0,
                    (d[0] * v) as f32,
                    (d[1] * v) as f32,
                    (d[2] * v) as f32,
                ],
                dt,
            }
        })
        .collect()
}

fn script(queries: &[Query], frames: &[Frame]) -> String {
    let mut s = String::new();
    for q in queries {
        let v = [q.a[0], q.a[1], q.a[2], q.b[0], q.b[1], q.b[2], q.radius];
        writeln!(s, "Q {}", v.map(hex).join(" ")).unwrap();
    }
    for f in frames {
        let v: Vec<String> = f.target.iter().chain([&f.dt]).map(|&x| hex(x)).collect();
        writeln!(s, "T {}", v.join(" ")).unwrap();
    }
    s
}

fn pose_text(p: &Pose) -> String {
    let status = match p.status {
        Status::Following | Status::Held => 0,
        Status::TargetOutside => 1,
        Status::NoGraph => 2,
    };
    let a = p.angles();
    format!(
        "{} {} {} {} {} {} {} {} {} {} {} {} {}",
        hex(p.eye[0]),
        hex(p.eye[1]),
        hex(p.eye[2]),
        hex(a[0]),
        hex(a[1]),
        hex(a[2]),
        i32::from(p.cut),
        i32::from(p.target_visible),
        hex(p.look_at[0]),
        hex(p.look_at[1]),
        hex(p.look_at[2]),
        status,
        p.face.map_or(-1, |f| f as i64)
    )
}

/// What `smoke.c` must print, computed with the Rust API.
fn expected(
    g: &Vdg<'_>,
    other: &Vdg<'_>,
    queries: &[Query],
    frames: &[Frame],
    corrupt: &Path,
) -> String {
    let mut s = String::new();
    for label in ["P", "M"] {
        let info = g.info();
        writeln!(
            s,
            "{label} info {} {} {:016x} {}",
            info.vertex_count,
            info.face_count,
            g.source_hash(),
            hex(info.max_clearance)
        )
        .unwrap();
        for q in queries {
            let path = g.path_with_clearance(q.a, q.b, q.radius);
            let n = path.as_ref().map_or(0, |p| p.vertices.len() + 2);
            write!(
                s,
                "{label} Q {} {} {} {n} {}",
                hex(g.clearance(q.a)),
                i32::from(g.visible(q.a, q.b)),
                hex(g.vdistance(q.a, q.b).unwrap_or(f32::INFINITY)),
                path.as_ref().map_or("00000000".into(), |p| hex(p.length)),
            )
            .unwrap();
            if let Some(p) = &path {
                let inner = p.vertices.iter().map(|&v| g.vertices()[v as usize].pos);
                for pt in std::iter::once(q.a).chain(inner).chain([q.b]) {
                    write!(s, " {} {} {}", hex(pt[0]), hex(pt[1]), hex(pt[2])).unwrap();
                }
            }
            s.push('\n');
        }
    }

    let mut cam = Camera::new(CameraParams::default()).unwrap();
    for (i, f) in frames.iter().enumerate() {
        let pose = if i == 0 {
            cam.reset(g, &f.target())
        } else {
            cam.update(g, &f.target(), f.dt)
        };
        writeln!(s, "C {i} {}", pose_text(&pose)).unwrap();
    }
    let last = frames.last().unwrap();
    let pose = cam.update(other, &last.target(), last.dt);
    assert!(pose.cut, "a camera moved to another graph must cut");
    writeln!(s, "C other {}", pose_text(&pose)).unwrap();

    let mut d = Director::new();
    let a = d.add_camera(CameraParams::default()).unwrap();
    let b = d
        .add_camera(CameraParams::from_toml_str(DIRECTOR_PARAMS).unwrap())
        .unwrap();
    writeln!(
        s,
        "D cameras {} {} active {}",
        a.0,
        b.0,
        d.active().unwrap().0
    )
    .unwrap();
    for (i, f) in frames.iter().enumerate() {
        d.set_target(a, f.target());
        d.set_target(b, f.target());
        if i == frames.len() / 2 {
            d.activate(b);
        }
        let pose = d.update(g, f.dt).expect("the active camera has a target");
        write!(
            s,
            "D {i} 1 {} events {}",
            pose_text(&pose),
            d.events().len()
        )
        .unwrap();
        for e in d.events().iter().take(8) {
            let (k, c, from) = match *e {
                DirectorEvent::Switched { from, to } => {
                    (1, to.0 as i64, from.map_or(-1, |f| f.0 as i64))
                }
                DirectorEvent::Cut { camera } => (2, camera.0 as i64, -1),
                DirectorEvent::GraphChanged => (3, -1, -1),
            };
            write!(s, " {k}:{c}:{from}").unwrap();
        }
        s.push('\n');
    }

    let open_err = VdgFile::open(corrupt).unwrap_err();
    writeln!(s, "E corrupt-open NULL {}: {open_err}", corrupt.display()).unwrap();
    let mem_err = VdgFile::from_bytes(&std::fs::read(corrupt).unwrap()).unwrap_err();
    writeln!(s, "E corrupt-memory NULL memory image: {mem_err}").unwrap();
    s.push_str("E clearance-null-graph NaN vdg_clearance: graph is NULL\n");
    s.push_str("E clearance-nan NaN vdg_clearance: p is not finite (NaN, 0, 0)\n");
    s.push_str("E visible-null-point -1 vdg_visible: b is NULL\n");
    s.push_str("E path-negative-radius -1 vdg_path: radius must be finite and >= 0 (got -1)\n");
    s.push_str("E path-null-buffer -1 vdg_path: points is NULL but capacity is 4\n");
    let o = [0.0; 3];
    let n = g
        .path_with_clearance(o, o, 0.0)
        .map_or(0, |p| p.vertices.len() + 2);
    writeln!(s, "E path-size-only {n}").unwrap();
    let params_err = CameraParams::from_toml_str("distance_mu = \"far\"").unwrap_err();
    writeln!(s, "E camera-bad-params NULL vdg_camera_new: {params_err}").unwrap();
    s.push_str("E camera-nan-dt -1 vdg_camera_update: dt must be finite and >= 0 (got NaN)\n");
    s.push_str("E camera-null-out -1 vdg_camera_update: out is NULL\n");
    s
}

/// The C compiler: `$CC`, else `cc`; `None` when it does not run.
fn c_compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let ok = Command::new(&cc)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    ok.then_some(cc)
}

/// The static library cargo built for this test run: beside the test
/// binary (`target/PROFILE/deps/`) or one level up.
fn static_lib() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let deps = exe.parent().unwrap();
    let name = if cfg!(windows) { "vdg.lib" } else { "libvdg.a" };
    [deps.join(name), deps.join("..").join(name)]
        .into_iter()
        .find(|p| p.exists())
        .unwrap_or_else(|| panic!("no {name} near {}", deps.display()))
}

/// What a program linking the Rust static library also needs (the output
/// of `rustc --print native-static-libs` on these targets).
fn native_libs() -> &'static [&'static str] {
    if cfg!(target_os = "linux") {
        &[
            "-lgcc_s",
            "-lutil",
            "-lrt",
            "-lpthread",
            "-lm",
            "-ldl",
            "-lc",
        ]
    } else if cfg!(target_os = "macos") {
        &["-lSystem", "-lc", "-lm"]
    } else {
        &["-lpthread", "-lm"]
    }
}

#[test]
fn the_c_program_gets_bit_identical_answers() {
    let Some(cc) = c_compiler() else {
        eprintln!("skipped: no C compiler (set CC or install cc) to build tests/c/smoke.c");
        return;
    };
    let dir = scratch_dir();
    let vdg = compile_map(&dir);
    let file = VdgFile::open(&vdg).unwrap();
    let bytes = std::fs::read(&vdg).unwrap();
    let other_file = VdgFile::from_bytes(&bytes).unwrap();
    let (g, other) = (file.graph(), other_file.graph());

    let mut rng = SplitMix64::new(15);
    let queries = queries(&g, &mut rng);
    let frames = frames(&g);
    let script_path = dir.join("script.txt");
    std::fs::write(&script_path, script(&queries, &frames)).unwrap();
    let mut corrupt = bytes.clone();
    let mid = corrupt.len() / 2;
    corrupt[mid] ^= 0x40;
    let corrupt_path = dir.join("corrupt.vdg");
    std::fs::write(&corrupt_path, &corrupt).unwrap();

    let capi = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = dir.join(if cfg!(windows) { "smoke.exe" } else { "smoke" });
    let out = Command::new(&cc)
        .args([
            "-std=c99",
            "-O2",
            "-g",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
        ])
        .arg("-I")
        .arg(capi.join("include"))
        .arg(capi.join("tests/c/smoke.c"))
        .arg(static_lib())
        .args(native_libs())
        .arg("-o")
        .arg(&exe)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{cc} failed on smoke.c:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let run = Command::new(&exe)
        .arg(&vdg)
        .arg(&script_path)
        .arg(&corrupt_path)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "smoke failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let got = String::from_utf8(run.stdout).unwrap();
    let want = expected(&g, &other, &queries, &frames, &corrupt_path);
    let (got_lines, want_lines): (Vec<_>, Vec<_>) = (got.lines().collect(), want.lines().collect());
    for (i, (a, b)) in got_lines.iter().zip(&want_lines).enumerate() {
        assert_eq!(a, b, "line {} differs (C, then Rust)", i + 1);
    }
    assert_eq!(got_lines.len(), want_lines.len(), "line counts differ");

    // The script exercises what it claims to.
    let camera_lines: Vec<&str> = got_lines
        .iter()
        .copied()
        .filter(|l| l.starts_with("C "))
        .collect();
    assert_eq!(camera_lines.len(), FRAMES + 1);
    let cuts = camera_lines
        .iter()
        .filter(|l| l.split(' ').nth(8) == Some("1"))
        .count();
    assert!(
        cuts >= 3,
        "reset, teleport and graph change each cut ({cuts} cuts)"
    );
    let paths = got_lines
        .iter()
        .filter(|l| {
            l.starts_with("P Q")
                && l.split(' ')
                    .nth(5)
                    .is_some_and(|n| n.parse::<i64>().unwrap() > 8)
        })
        .count();
    assert!(paths > 0, "no path took the 'needed size' route");
    assert!(
        got.contains("events 1 1:1:0"),
        "the director's switch is reported"
    );
    if std::env::var_os("SMOKE_KEEP").is_none() {
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// The header compiles as C89 under `-pedantic -Wall -Wextra -Werror`, and a
/// pointer from `vdg_last_error()` stays readable across later failing calls.
#[test]
fn the_header_is_c89_and_the_error_string_outlives_later_failures() {
    let Some(cc) = c_compiler() else {
        eprintln!("skipped: no C compiler (set CC or install cc) to build tests/c/c89.c");
        return;
    };
    let dir = scratch_dir();
    let capi = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = dir.join(if cfg!(windows) { "c89.exe" } else { "c89" });
    let out = Command::new(&cc)
        .args([
            "-std=c89",
            "-pedantic",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-O1",
        ])
        .arg("-I")
        .arg(capi.join("include"))
        .arg(capi.join("tests/c/c89.c"))
        .arg(static_lib())
        .args(native_libs())
        .arg("-o")
        .arg(&exe)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{cc} -std=c89 -pedantic failed on c89.c:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let run = Command::new(&exe).output().unwrap();
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(run.status.success() && text.ends_with("ok\n"), "{text}");
}
