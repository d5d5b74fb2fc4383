//! The `info`, `query` and `render` subcommands end to end: on a generated map
//! with a graph built inside it, and on bad input.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use vdgformat::VdgBuilder;

const BACKGROUND: [u8; 3] = [28, 30, 36];

fn map(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/maps")
        .join(name)
}

fn tmpdir(tag: &str) -> toolbox::ScratchDir {
    toolbox::ScratchDir::new(&format!("vdgview-cli-{tag}")).unwrap()
}

fn vdgview(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vdgview"))
        .args(args)
        .output()
        .expect("run vdgview")
}

/// A graph filling box_room's interior: a grid of triangles at mid height whose
/// clearance falls off towards the walls (like a real medial-axis sheet).
fn box_room_graph(dir: &Path) -> PathBuf {
    let bsp = bsp::Bsp::open(map("box_room.bsp")).unwrap();
    let (lo, hi) = (bsp.world().mins, bsp.world().maxs);
    let inset = 40.0;
    let (x0, x1, y0, y1) = (lo[0] + inset, hi[0] - inset, lo[1] + inset, hi[1] - inset);
    let z = (lo[2] + hi[2]) * 0.5;
    let n = 12;
    let mut b = VdgBuilder::new();
    let mut ids = vec![];
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            let edge = u.min(1.0 - u).min(v.min(1.0 - v));
            ids.push(b.add_vertex(
                [x0 + (x1 - x0) * u, y0 + (y1 - y0) * v, z],
                8.0 + 200.0 * edge,
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
    b.set_metadata("source.name", "box_room.bsp");
    let path = dir.join("box_room.vdg");
    std::fs::write(&path, b.to_bytes().unwrap()).unwrap();
    path
}

/// Decoded RGB pixels of a PNG.
fn decode(bytes: &[u8]) -> (u32, u32, Vec<[u8; 3]>) {
    let mut r = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    let px = buf[..info.buffer_size()]
        .chunks(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    (info.width, info.height, px)
}

/// Saturated: the graph's clearance colours, not grey walls, tinted sky or the
/// background.
fn is_coloured(p: [u8; 3]) -> bool {
    p.iter().max().unwrap() - p.iter().min().unwrap() > 80
}

fn render(args: &[&str]) -> Vec<u8> {
    let out = vdgview(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let png = args[args.iter().position(|&a| a == "-o").unwrap() + 1];
    std::fs::read(png).unwrap()
}

#[test]
fn renders_are_non_empty_coloured_and_deterministic() {
    let dir = tmpdir("render");
    let g = box_room_graph(&dir);
    let samples = dir.join("s.txt");
    std::fs::write(&samples, "0 0 0\n64 64 64\n").unwrap();
    let m = map("box_room.bsp");
    let (m, g, s) = (
        m.to_str().unwrap(),
        g.to_str().unwrap(),
        samples.to_str().unwrap(),
    );
    let a = dir.join("a.png");
    let b = dir.join("b.png");
    for extra in [
        &["--mode", "3"][..],
        &["--mode", "1", "--top"],
        &["--mode", "0", "--samples", s],
    ] {
        let mut args = vec!["render", m, g, "--size", "160x120"];
        args.extend_from_slice(extra);
        let first = render(&[&args[..], &["-o", a.to_str().unwrap()]].concat());
        let second = render(&[&args[..], &["-o", b.to_str().unwrap()]].concat());
        assert_eq!(first, second, "render {extra:?} is not deterministic");
        let (w, h, px) = decode(&first);
        assert_eq!((w, h), (160, 120));
        let drawn = px.iter().filter(|&&p| p != BACKGROUND).count();
        assert!(
            drawn > px.len() / 10,
            "{extra:?}: only {drawn} pixels drawn"
        );
        let coloured = px.iter().filter(|&&p| is_coloured(p)).count();
        if extra[1] == "0" {
            assert_eq!(coloured, 0, "mode 0 draws the graph");
        } else {
            assert!(
                coloured > 200,
                "{extra:?}: the graph is missing ({coloured} coloured pixels)"
            );
        }
    }
}

#[test]
fn a_camera_inside_the_room_sees_walls_around_it() {
    let dir = tmpdir("camera");
    let g = box_room_graph(&dir);
    let bsp = bsp::Bsp::open(map("box_room.bsp")).unwrap();
    let (lo, hi) = (bsp.world().mins, bsp.world().maxs);
    let c: Vec<f32> = (0..3).map(|i| (lo[i] + hi[i]) * 0.5).collect();
    let cam = format!(
        "{},{},{}:{},{},{}:90",
        c[0],
        c[1],
        c[2] + 20.0,
        hi[0],
        c[1],
        c[2]
    );
    let out = dir.join("in.png");
    let bytes = render(&[
        "render",
        map("box_room.bsp").to_str().unwrap(),
        g.to_str().unwrap(),
        "--camera",
        &cam,
        "--size",
        "64x48",
        "--supersample",
        "1",
        "-o",
        out.to_str().unwrap(),
    ]);
    let (_, _, px) = decode(&bytes);
    let missing = px.iter().filter(|&&p| p == BACKGROUND).count();
    // Enclosed: every pixel shows a wall or the graph.
    assert_eq!(missing, 0, "{cam}");
}

#[test]
fn info_and_queries_print_their_answers() {
    let dir = tmpdir("query");
    let g = box_room_graph(&dir);
    let g = g.to_str().unwrap();
    let info = vdgview(&["info", g]);
    assert!(info.status.success());
    let text = String::from_utf8(info.stdout).unwrap();
    assert!(text.contains("vertices       169"), "{text}");
    let version = vdgformat::layout::FORMAT_VERSION;
    assert!(
        text.contains(&format!(
            "file format    version {version}, faces and vertex lists in 16 bits"
        )),
        "{text}"
    );
    assert!(text.contains("source.name = box_room.bsp"), "{text}");
    // Given the map, info names its game and format.
    let info = vdgview(&["info", map("box_room.bsp").to_str().unwrap()]);
    assert!(info.status.success());
    let text = String::from_utf8(info.stdout).unwrap();
    assert!(text.contains("game           GoldSrc"), "{text}");
    assert!(text.contains("format         BSP30 (GoldSrc)"), "{text}");

    let bsp = bsp::Bsp::open(map("box_room.bsp")).unwrap();
    let (lo, hi) = (bsp.world().mins, bsp.world().maxs);
    let c: Vec<String> = (0..3)
        .map(|i| ((lo[i] + hi[i]) * 0.5).to_string())
        .collect();
    let q = vdgview(&["query", g, "clearance", &c[0], &c[1], &c[2]]);
    let text = String::from_utf8(q.stdout).unwrap();
    let clearance: f32 = text.lines().next().unwrap()["clearance ".len()..]
        .parse()
        .unwrap();
    assert!(clearance > 50.0, "{text}");
    let far = (lo[0] + 60.0).to_string();
    let p = vdgview(&["query", g, "path", &far, &c[1], &c[2], &c[0], &c[1], &c[2]]);
    let text = String::from_utf8(p.stdout).unwrap();
    assert!(text.starts_with("vdistance "), "{text}");
    let v = vdgview(&[
        "query", g, "visible", &far, &c[1], &c[2], &c[0], &c[1], &c[2],
    ]);
    assert_eq!(String::from_utf8(v.stdout).unwrap(), "visible true\n");
}

#[test]
fn bad_input_gives_one_line_errors_and_no_output() {
    let dir = tmpdir("bad");
    let g = box_room_graph(&dir);
    let garbage = dir.join("garbage.vdg");
    std::fs::write(&garbage, b"not a graph").unwrap();
    let m = map("box_room.bsp");
    let (m, g, bad) = (
        m.to_str().unwrap(),
        g.to_str().unwrap(),
        garbage.to_str().unwrap(),
    );
    let out = dir.join("never.png");
    let o = out.to_str().unwrap();
    let cases: Vec<Vec<&str>> = vec![
        vec!["info", bad],
        vec!["query", g, "clearance", "1", "2"],
        vec!["query", g, "warp", "1", "2", "3"],
        vec!["render", m, bad, "-o", o],
        vec!["render", bad, g, "-o", o],
        vec!["render", m, g, "--mode", "2", "-o", o],
        vec!["render", m, g, "--mode", "7", "-o", o],
        vec!["render", m, g, "--camera", "1,2:3,4,5", "-o", o],
        vec!["render", m, g, "--size", "0x10", "-o", o],
        vec!["render", m, g, "-o", "/nonexistent-dir/x.png"],
    ];
    for args in cases {
        let r = vdgview(&args);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.starts_with("vdgview: error: ") && err.lines().count() == 1,
            "{args:?}: {err}"
        );
        assert!(!out.exists());
    }
}

/// A graph built from another map: `check` refuses it in one line (exit 1), `render`
/// warns and still draws. The .vdg records the XXH64 of its source map's bytes.
#[test]
fn a_graph_of_another_map_is_named() {
    let dir = tmpdir("othermap");
    let mut b = VdgBuilder::new();
    let ids: Vec<u32> = [
        [100.0, 100.0, 100.0],
        [200.0, 100.0, 100.0],
        [100.0, 200.0, 100.0],
    ]
    .iter()
    .map(|&p| b.add_vertex(p, 30.0))
    .collect();
    b.add_face([ids[0], ids[1], ids[2]]);
    let pillars = std::fs::read(map("pillars.bsp")).unwrap();
    b.set_source("pillars.bsp", vdgformat::xxh64(&pillars, 0));
    let graph = dir.join("from-pillars.vdg");
    std::fs::write(&graph, b.to_bytes().unwrap()).unwrap();
    let other = map("box_room.bsp");
    let o = vdgview(&[
        "check",
        other.to_str().unwrap(),
        graph.to_str().unwrap(),
        "--samples",
        "100",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("was built from another map"), "{err}");
    // The right map passes this test (its figures are another matter).
    let o = vdgview(&[
        "check",
        map("pillars.bsp").to_str().unwrap(),
        graph.to_str().unwrap(),
        "--samples",
        "100",
    ]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("another map"));
    let png = dir.join("other.png");
    let o = vdgview(&[
        "render",
        other.to_str().unwrap(),
        graph.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--size",
        "64x48",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("warning:"));
    assert!(png.is_file());
}
