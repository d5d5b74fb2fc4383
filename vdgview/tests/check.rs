//! `check` on the generated maps: the compiler's graphs must not leak or see through
//! walls, and a graph that does must be caught.

use bsp::Bsp;
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::pipeline::{self, CompileOptions};
use bsp2vdg::progress::NoProgress;
use std::path::{Path, PathBuf};
use vdgview::check::{CheckOptions, check};

fn generated_maps() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/maps");
    let mut maps: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        .collect();
    maps.sort();
    maps
}

fn compile(map: &Path, out: &Path) {
    let options = CompileOptions {
        reduction_limit: 1.0,
        ..CompileOptions::new(out.to_path_buf())
    };
    pipeline::compile(
        map,
        &options,
        &Log::new(Verbosity::Quiet, true),
        &NoProgress,
    )
    .unwrap();
}

fn tempdir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("vdgview-check-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn compiled_graphs_do_not_leak_or_see_through_walls() {
    let dir = tempdir();
    for map in generated_maps() {
        let out = dir.join(map.file_name().unwrap()).with_extension("vdg");
        compile(&map, &out);
        let bsp = Bsp::open(&map).unwrap();
        let file = vdgformat::VdgFile::open(&out).unwrap();
        let options = CheckOptions {
            samples: 20_000,
            ..Default::default()
        };
        let r = check(&bsp, &file.graph(), 0, &options);
        eprintln!("{}: {}", map.display(), r.to_json());
        assert_eq!(r.leaked, 0, "{}: leak", map.display());
        assert_eq!(
            r.false_positives,
            0,
            "{}: visible through a wall",
            map.display()
        );
        assert!(
            r.coverage() > 0.95,
            "{}: coverage {}",
            map.display(),
            r.coverage()
        );
        assert!(r.free_segments > 0 && r.visible > 0);
        // Same figures for the same seed.
        let mut again = check(&bsp, &file.graph(), 0, &options);
        (again.seconds, again.seconds_parts) = (r.seconds, r.seconds_parts);
        assert_eq!(again, r);
    }
}

#[test]
fn an_inflated_graph_is_caught_leaking() {
    let dir = tempdir();
    let map = generated_maps()
        .into_iter()
        .find(|m| m.ends_with("two_rooms.bsp"))
        .unwrap();
    let out = dir.join("two_rooms_honest.vdg");
    compile(&map, &out);
    let file = vdgformat::VdgFile::open(&out).unwrap();
    let g = file.graph();
    // Triple every clearance: the volume now reaches through the walls.
    let mut b = vdgformat::VdgBuilder::new();
    for v in g.vertices() {
        b.add_vertex(v.pos, v.clearance * 3.0);
    }
    for f in g.faces() {
        b.add_face(*f);
    }
    let bytes = b.to_bytes().unwrap();
    let inflated = vdgformat::VdgFile::from_bytes(&bytes).unwrap();
    let bsp = Bsp::open(&map).unwrap();
    let r = check(
        &bsp,
        &inflated.graph(),
        bytes.len(),
        &CheckOptions {
            samples: 20_000,
            ..Default::default()
        },
    );
    assert!(r.leaked > 0 && !r.passed(), "{}", r.to_json());
}

/// World brushes with `{` alpha textures are solid in the BSP: the graph must treat
/// them as walls (a name-only skip let the volume pass through the fence).
#[test]
fn alpha_textured_world_brushes_are_walls() {
    let map = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/testmaps/goldsrc/allocblock-in-bsp-texture-test.bsp");
    if !map.exists() {
        eprintln!("skipped: {} is absent", map.display());
        return;
    }
    let out = tempdir().join("fence.vdg");
    compile(&map, &out);
    let bsp = Bsp::open(&map).unwrap();
    let file = vdgformat::VdgFile::open(&out).unwrap();
    let r = check(
        &bsp,
        &file.graph(),
        0,
        &CheckOptions {
            samples: 20_000,
            ..Default::default()
        },
    );
    assert!(r.leaked == 0 && r.false_positives == 0, "{}", r.to_json());
}
