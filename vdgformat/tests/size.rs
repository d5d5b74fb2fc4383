//! The file size bound (≤ 100 bytes per face on every map) on a
//! generated open map, where the BBox tree's leaf lists swell most: big faces
//! with clearances of hundreds of units reach into many tree cells.
//!
//! `testdata/graphs/open_field.vdg` is the graph `bsp2vdg` compiled from the
//! generated map `open_field` (mapgen's extra world: 3072² units under a sky,
//! six buildings) at the default options, stored with a one-leaf tree
//! (`-bb 65536`) to keep the fixture small; `testdata/README.md` says how to
//! make it again. Compiling the map takes a minute in the test profile, so the
//! default suite rebuilds only the file from the compiled graph: the writer is
//! what the bound is about. The end-to-end check (fresh compile) is
//! `cargo test --release -p bsp2vdg --test reduce -- --ignored open_field`.

mod common;

use std::path::Path;

use common::Rng;
use vdgformat::{DEFAULT_LEAF_SIZE, VdgBuilder, VdgFile};

/// The bound, for the whole file: header, section table, metadata and
/// padding count too.
const MAX_BYTES_PER_FACE: f64 = 100.0;

/// The compiled open_field graph (see the module comment).
fn open_field() -> VdgFile {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/graphs/open_field.vdg");
    VdgFile::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn open_map_file_stays_within_100_bytes_per_face() {
    let fixture = open_field();
    let g = fixture.graph();
    assert!(
        g.face_count() > 3000,
        "the fixture is the reduced open_field graph"
    );
    let mut b = VdgBuilder::new();
    for v in g.vertices() {
        b.add_vertex(v.pos, v.clearance);
    }
    assert!(
        g.has_face_radii(),
        "the fixture carries the faces' own corner radii, as bsp2vdg writes them"
    );
    for (i, f) in g.faces().iter().enumerate() {
        b.add_face_with_radii(f, g.face_radii(i as u32));
    }
    for (k, v) in g.metadata() {
        b.set_metadata(k, v);
    }
    b.set_metadata("option.bb", "256");
    b.set_leaf_size(DEFAULT_LEAF_SIZE);
    let bytes = b.to_bytes().expect("valid graph");
    let per_face = bytes.len() as f64 / g.face_count() as f64;
    println!(
        "open_field: {} faces, {} bytes, {per_face:.1} bytes per face",
        g.face_count(),
        bytes.len()
    );
    assert!(
        per_face <= MAX_BYTES_PER_FACE,
        "{per_face:.1} bytes per face on the open map (bound {MAX_BYTES_PER_FACE})"
    );
    // The compact file answers like the fixture (one tree leaf: every face tried).
    let file = VdgFile::from_bytes(&bytes).expect("valid file");
    let compact = file.graph();
    let (lo, hi) = (g.info().volume_min, g.info().volume_max);
    let mut rng = Rng::new(14);
    for _ in 0..500 {
        let p = rng.point(lo.map(f64::from), hi.map(f64::from));
        assert_eq!(
            compact.faces_containing(p),
            g.faces_containing(p),
            "at {p:?}"
        );
    }
}

/// The same bound on the smallest graphs a compile gives (a small map
/// reduces to a few dozen faces), where the fixed part of the file —
/// header, section table, info record and the metadata `bsp2vdg` writes —
/// weighs most: 20 faces with their own corner radii and the fixture's
/// metadata.
#[test]
fn a_tiny_graph_stays_within_100_bytes_per_face() {
    let fixture = open_field();
    let grid = common::grid(5, 2, 40.0, |x, _| x * 0.1, |_, _| 20.0, |_, _| true);
    let plain = VdgFile::from_bytes(&grid.to_bytes().unwrap()).unwrap();
    let faces = plain.graph().faces().to_vec();
    assert_eq!(faces.len(), 20);
    let mut tiny = VdgBuilder::new();
    for v in plain.graph().vertices() {
        tiny.add_vertex(v.pos, v.clearance);
    }
    for f in &faces {
        tiny.add_face_with_radii(*f, [21.0, 22.0, 23.0]);
    }
    for (k, v) in fixture.graph().metadata() {
        tiny.set_metadata(k, v);
    }
    let bytes = tiny.to_bytes().expect("valid graph");
    let per_face = bytes.len() as f64 / faces.len() as f64;
    println!(
        "tiny: {} faces, {} bytes, {per_face:.1} bytes per face",
        faces.len(),
        bytes.len()
    );
    assert!(
        per_face <= MAX_BYTES_PER_FACE,
        "{per_face:.1} bytes per face on a 20-face graph (bound {MAX_BYTES_PER_FACE})"
    );
    let file = VdgFile::from_bytes(&bytes).expect("valid file");
    assert_eq!(file.graph().faces().to_vec(), faces);
    assert_eq!(file.graph().face_radii(7), [21.0, 22.0, 23.0]);
}
