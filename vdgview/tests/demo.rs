//! GoldSrc demos as replay routes, end to end: `vdgview demo` prints the header, `replay
//! --routes demo:FILE.dem` follows the recorded player and `--save-routes` writes it as
//! JSONL; a demo, nav mesh or graph made for another map is refused unless `--force`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use vdgformat::VdgBuilder;

fn map(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/maps")
        .join(format!("{name}.bsp"))
}

fn vdgview(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vdgview"))
        .args(args)
        .output()
        .expect("run vdgview")
}

macro_rules! args {
    ($($a:expr),* $(,)?) => { &[$(std::ffi::OsStr::new(&$a)),*] };
}

fn shared_demos() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/testmaps/demos");
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipped: {} absent", p.display());
        None
    }
}

/// A protocol 5 demo on `map_name`: one playback segment of `n` client frames at 100 Hz
/// of a player at `origin(i)` looking along +x, crouched in the frames `crouch(i)`.
fn write_demo(
    path: &Path,
    map_name: &str,
    n: usize,
    origin: impl Fn(usize) -> [f32; 3],
    crouch: impl Fn(usize) -> bool,
) {
    let mut b = Vec::new();
    b.extend_from_slice(b"HLDEMO\0\0");
    b.extend_from_slice(&5i32.to_le_bytes());
    b.extend_from_slice(&48i32.to_le_bytes());
    let mut name = vec![0u8; 260];
    name[..map_name.len()].copy_from_slice(map_name.as_bytes());
    b.extend_from_slice(&name);
    let mut game = vec![0u8; 260];
    game[..5].copy_from_slice(b"valve");
    b.extend_from_slice(&game);
    b.extend_from_slice(&0u32.to_le_bytes());
    let dir_slot = b.len();
    b.extend_from_slice(&0i32.to_le_bytes());
    let start = b.len();
    for i in 0..n {
        let t = i as f32 * 0.01;
        b.push(1);
        b.extend_from_slice(&t.to_le_bytes());
        b.extend_from_slice(&(i as i32).to_le_bytes());
        let mut body = vec![0u8; 468];
        let o = origin(i);
        let put = |body: &mut Vec<u8>, off: usize, v: f32| {
            body[off..off + 4].copy_from_slice(&v.to_le_bytes())
        };
        for (k, &v) in o.iter().enumerate() {
            put(&mut body, 104 + 4 * k, v);
        }
        put(&mut body, 124, if crouch(i) { 12.0 } else { 28.0 });
        b.extend_from_slice(&body);
    }
    b.push(5);
    b.extend_from_slice(&[0u8; 8]);
    let dir = b.len();
    b[dir_slot..dir_slot + 4].copy_from_slice(&(dir as i32).to_le_bytes());
    b.extend_from_slice(&1i32.to_le_bytes());
    b.extend_from_slice(&1i32.to_le_bytes());
    let mut desc = vec![0u8; 64];
    desc[..8].copy_from_slice(b"Playback");
    b.extend_from_slice(&desc);
    b.extend_from_slice(&0i32.to_le_bytes());
    b.extend_from_slice(&(-1i32).to_le_bytes());
    b.extend_from_slice(&(n as f32 * 0.01).to_le_bytes());
    b.extend_from_slice(&(n as i32).to_le_bytes());
    b.extend_from_slice(&(start as i32).to_le_bytes());
    b.extend_from_slice(&((dir - start) as i32).to_le_bytes());
    std::fs::write(path, b).unwrap();
}

/// A graph filling box_room's interior at the player's height (clearance falling off
/// towards the walls), recording no source map.
fn box_room_graph(dir: &Path, z: f32) -> PathBuf {
    let bsp = bsp::Bsp::open(map("box_room")).unwrap();
    let (lo, hi) = (bsp.world().mins, bsp.world().maxs);
    let inset = 40.0;
    let (x0, x1, y0, y1) = (lo[0] + inset, hi[0] - inset, lo[1] + inset, hi[1] - inset);
    let n = 8;
    let mut b = VdgBuilder::new();
    let mut ids = vec![];
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let edge = u.min(1.0 - u).min(v.min(1.0 - v));
            ids.push(b.add_vertex(
                [x0 + (x1 - x0) * u, y0 + (y1 - y0) * v, z],
                8.0 + 100.0 * edge,
            ));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            b.add_face([ids[a], ids[a + 1], ids[a + n + 1]]);
            b.add_face([ids[a + 1], ids[a + n + 2], ids[a + n + 1]]);
        }
    }
    let path = dir.join("box_room.vdg");
    std::fs::write(&path, b.to_bytes().unwrap()).unwrap();
    path
}

#[test]
fn a_demo_is_replayed_and_saved_as_routes() {
    let dir = toolbox::ScratchDir::new("vdgview-demo-replay").unwrap();
    let bsp = bsp::Bsp::open(map("box_room")).unwrap();
    let spawn = bsp.spawns()[0];
    let vdg = box_room_graph(dir.path(), spawn[2] + 28.0);
    let dem = dir.path().join("walk.dem");
    // 1.5 s walking along +x at 60 units/s, crouched for the last half second.
    write_demo(
        &dem,
        "box_room",
        150,
        |i| {
            let c = i >= 100;
            let z = spawn[2] - if c { 18.0 } else { 0.0 };
            [spawn[0] + 0.6 * i as f32, spawn[1], z]
        },
        |i| i >= 100,
    );
    let o = vdgview(args!["demo", dem]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    for want in [
        "map       box_room",
        "game      valve",
        "demo 5, network 48",
        "1.50 s",
        "150 client frames",
    ] {
        assert!(text.contains(want), "{want:?} missing in:\n{text}");
    }
    let jsonl = dir.path().join("routes.jsonl");
    let o = vdgview(args![
        "replay",
        map("box_room"),
        vdg,
        "--routes",
        format!("demo:{}", dem.display()),
        "--camera",
        "chase,vdg",
        "--dt",
        "1/30",
        "--json",
        "--save-routes",
        jsonl,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["routes"]["count"], 1);
    // 1.49 s of frames at 1/30 s.
    assert_eq!(v["routes"]["frames"], 45);
    assert_eq!(v["cameras"]["chase"]["frames"], 45);
    let saved = std::fs::read_to_string(&jsonl).unwrap();
    assert_eq!(saved.lines().count(), 150, "one line per player frame");
    assert!(saved.lines().last().unwrap().contains("\"crouch\":true"));
    assert!(saved.lines().next().unwrap().contains("\"crouch\":false"));
    // The saved routes replay the same motion.
    let o = vdgview(args![
        "replay",
        map("box_room"),
        vdg,
        "--routes",
        jsonl,
        "--camera",
        "chase",
        "--dt",
        "1/30",
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let w: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(w["cameras"]["chase"]["frames"], 45);
}

#[test]
fn another_maps_demo_nav_mesh_or_graph_is_refused_unless_forced() {
    let dir = toolbox::ScratchDir::new("vdgview-demo-othermap").unwrap();
    let bsp = bsp::Bsp::open(map("box_room")).unwrap();
    let spawn = bsp.spawns()[0];
    let vdg = box_room_graph(dir.path(), spawn[2] + 28.0);
    let dem = dir.path().join("elsewhere.dem");
    write_demo(&dem, "c1a0", 20, |_| spawn, |_| false);
    let o = vdgview(args![
        "replay",
        map("box_room"),
        vdg,
        "--routes",
        format!("demo:{}", dem.display()),
        "--camera",
        "chase",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    let last = err.lines().last().unwrap_or("");
    assert!(
        last.contains("\"c1a0\"") && last.contains("box_room.bsp"),
        "{err}"
    );
    let o = vdgview(args![
        "replay",
        map("box_room"),
        vdg,
        "--routes",
        format!("demo:{}", dem.display()),
        "--camera",
        "chase",
        "--force",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning:"));

    // A nav mesh recording another BSP's size (version 5, no places, no areas).
    let nav = dir.path().join("other.nav");
    let mut b = Vec::new();
    for v in [0xFEED_FACEu32, 5, 123_456] {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend_from_slice(&0u16.to_le_bytes());
    b.extend_from_slice(&0u32.to_le_bytes());
    std::fs::write(&nav, b).unwrap();
    let o = vdgview(args![
        "replay",
        map("box_room"),
        vdg,
        "--routes",
        format!("nav:{}", nav.display()),
        "--camera",
        "chase",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("another map") && err.contains("123456-byte"),
        "{err}"
    );

    // A graph recording another map's hash.
    let mut g = VdgBuilder::new();
    let ids: Vec<u32> = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 100.0, 0.0]]
        .iter()
        .map(|&p| g.add_vertex(p, 30.0))
        .collect();
    g.add_face([ids[0], ids[1], ids[2]]);
    let pillars = std::fs::read(map("pillars")).unwrap();
    g.set_source("pillars.bsp", vdgformat::xxh64(&pillars, 0));
    let other = dir.path().join("from-pillars.vdg");
    std::fs::write(&other, g.to_bytes().unwrap()).unwrap();
    let o = vdgview(args!["replay", map("box_room"), other, "--camera", "chase"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("was built from another map") && err.contains("--force"),
        "{err}"
    );
    let o = vdgview(args![
        "replay",
        map("box_room"),
        other,
        "--camera",
        "chase",
        "--force",
        "--max-routes",
        "1"
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning:") && err.contains("built from another map"),
        "{err}"
    );
}

#[test]
fn the_shared_demos_print_their_header_or_a_one_line_error() {
    let Some(dir) = shared_demos() else { return };
    let o = vdgview(args!["demo", dir.join("hldemo-rs-basic.dem")]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("map       c1a0") && text.contains("289 client frames"),
        "{text}"
    );
    let o = vdgview(args![
        "demo",
        dir.join("sourceless-HL1005-boot_camp.dem"),
        "--json"
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(
        (v["map"].as_str(), v["demo_protocol"].as_i64()),
        (Some("boot_camp"), Some(4))
    );
    for bad in [
        "hldemo-rs-invalid-demo-protocol.dem",
        "hldemo-rs-invalid-directory-entry-count.dem",
        "hldemo-rs-invalid-frame-type.dem",
        "hldemo-rs-invalid-magic.dem",
        "hldemo-rs-invalid-netmsg-length.dem",
    ] {
        let o = vdgview(args!["demo", dir.join(bad)]);
        assert_eq!(o.status.code(), Some(1), "{bad}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.lines().count(), 1, "{bad}: {err}");
        assert!(err.contains(bad), "{bad}: {err}");
        assert!(o.stdout.is_empty());
    }
}
