//! Maps the game loads must compile. Counter-Strike servers ship
//! maps whose brush models have a clip hull root equal to the clip node count, maps
//! "protected" against decompilers with garbage in records nothing uses, and entity
//! text only the engine's lenient parser reads. Each case is built here by mutating a
//! copy of a shipped map in memory; the mutated map must read, and where the mutation
//! touches nothing the engine uses, compile to the very same graph, free of leaks.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::CompileOptions;
use bsp2vdg::pipeline;
use bsp2vdg::progress::NoProgress;
use std::path::{Path, PathBuf};

const CLIPNODES: usize = 9;
const NODES: usize = 5;
const FACES: usize = 7;
const EDGES: usize = 12;
const SURFEDGES: usize = 13;
const MODELS: usize = 14;
const ENTITIES: usize = 0;

fn testdata(name: &str) -> Vec<u8> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/maps")
        .join(name);
    std::fs::read(p).unwrap()
}

fn lump(bytes: &[u8], i: usize) -> (usize, usize) {
    let at = 4 + 8 * i;
    let r = |k: usize| i32::from_le_bytes(bytes[k..k + 4].try_into().unwrap()) as usize;
    (r(at), r(at + 4))
}

/// The map with lump `i` replaced by `data`, placed at the end of the file.
fn with_lump(bytes: &[u8], i: usize, data: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    while !out.len().is_multiple_of(4) {
        out.push(0);
    }
    let offset = out.len() as i32;
    out.extend_from_slice(data);
    let at = 4 + 8 * i;
    out[at..at + 4].copy_from_slice(&offset.to_le_bytes());
    out[at + 4..at + 8].copy_from_slice(&(data.len() as i32).to_le_bytes());
    out
}

/// The map with one more record at the end of lump `i`.
fn append_record(bytes: &[u8], i: usize, record: &[u8]) -> Vec<u8> {
    let (o, l) = lump(bytes, i);
    let mut data = bytes[o..o + l].to_vec();
    data.extend_from_slice(record);
    with_lump(bytes, i, &data)
}

fn le(values: &[i32]) -> Vec<u8> {
    values.iter().flat_map(|v| v.to_le_bytes()).collect()
}

fn tempdir() -> toolbox::ScratchDir {
    toolbox::ScratchDir::new("bsp2vdg-engine-accepts").unwrap()
}

/// Compiles the map bytes; returns the .vdg bytes.
fn compile(bytes: &[u8], name: &str) -> Vec<u8> {
    let dir = tempdir();
    let map = dir.join(format!("{name}.bsp"));
    let out = dir.join(format!("{name}.vdg"));
    std::fs::write(&map, bytes).unwrap();
    pipeline::compile(
        &map,
        &CompileOptions::new(out.clone()),
        &Log::new(Verbosity::Quiet, true),
        &NoProgress,
    )
    .unwrap();
    std::fs::read(out).unwrap()
}

/// The graph of a .vdg file: positions, clearances and faces (the header also holds
/// the source map's hash, which a mutation changes).
type Graph = (Vec<([f32; 3], f32)>, Vec<[u32; 3]>);

fn graph(vdg: &[u8]) -> Graph {
    let file = vdgformat::VdgFile::from_bytes(vdg).unwrap();
    let g = file.graph();
    let v = g.vertices().iter().map(|v| (v.pos, v.clearance)).collect();
    (v, g.faces().to_vec())
}

/// Every vertex of the graph lies in free space as the map's own oracle says.
fn leaks(bsp: &Bsp, vdg: &[u8]) -> usize {
    let file = vdgformat::VdgFile::from_bytes(vdg).unwrap();
    let oracle = Oracle::new(bsp, &OracleOptions::default());
    file.graph()
        .vertices()
        .iter()
        .filter(|v| !oracle.is_free(v.pos.map(f64::from)))
        .count()
}

/// A brush model whose clip hulls have the clip node count as root (what compilers
/// write for a hull without nodes; the engines copy it unchecked).
fn clip_root_at_count(bytes: &[u8], model: usize) -> Vec<u8> {
    let mut b = bytes.to_vec();
    let count = (lump(bytes, CLIPNODES).1 / 8) as i32;
    let at = lump(bytes, MODELS).0 + 64 * model + 36;
    for h in 1..4 {
        b[at + 4 * h..at + 4 * h + 4].copy_from_slice(&count.to_le_bytes());
    }
    b
}

/// Garbage records nothing refers to, as decompiler "protection" adds them (a clip
/// node only where the map has clip hulls: without, every model's root 0 would
/// reach it).
fn unused_garbage(bytes: &[u8]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    if lump(bytes, CLIPNODES).1 > 0 {
        // Clip node: plane -2136128596, children far out of range.
        let mut clip = le(&[-2136128596]);
        clip.extend_from_slice(&[0x10, 0x7f, 0x20, 0x7f]);
        b = append_record(&b, CLIPNODES, &clip);
    }
    let b = append_record(&b, SURFEDGES, &le(&[2136128757]));
    // Edge with vertex indices past the vertices.
    let b = append_record(&b, EDGES, &[0xff, 0xff, 0xfe, 0xff]);
    // Node: plane 999999, children 30000 / leaf 30000, faces 60000..60010.
    let mut node = le(&[999_999]);
    node.extend_from_slice(&30000i16.to_le_bytes());
    node.extend_from_slice(&(-30001i16).to_le_bytes());
    node.extend_from_slice(&[0; 12]);
    node.extend_from_slice(&60000u16.to_le_bytes());
    node.extend_from_slice(&10u16.to_le_bytes());
    let b = append_record(&b, NODES, &node);
    // Face: plane 65000, edges 2000000000.., texinfo 65000.
    let mut face = Vec::new();
    face.extend_from_slice(&65000u16.to_le_bytes());
    face.extend_from_slice(&0u16.to_le_bytes());
    face.extend_from_slice(&2_000_000_000i32.to_le_bytes());
    face.extend_from_slice(&4u16.to_le_bytes());
    face.extend_from_slice(&65000u16.to_le_bytes());
    face.extend_from_slice(&[0; 8]);
    append_record(&b, FACES, &face)
}

/// Entity text as only the engine's `COM_Parse` reads it: a comment, bare words.
fn lenient_entities(bytes: &[u8]) -> Vec<u8> {
    let (o, l) = lump(bytes, ENTITIES);
    let text = String::from_utf8_lossy(&bytes[o..o + l]).into_owned();
    let text = text.replacen('{', "// written by hand\n{\nzhlt_version 3 ", 1);
    with_lump(bytes, ENTITIES, text.as_bytes())
}

#[test]
fn maps_the_engine_loads_compile_to_the_same_graph() {
    let original = testdata("complex.bsp");
    let reference = compile(&original, "original");
    let bsp = Bsp::parse(&original).unwrap();
    assert_eq!(leaks(&bsp, &reference), 0);
    let last = bsp.models.len() - 1;
    assert!(last > 0, "complex.bsp has brush models");
    for (name, bytes) in [
        ("clip-root", clip_root_at_count(&original, last)),
        ("garbage", unused_garbage(&original)),
        ("entities", lenient_entities(&original)),
    ] {
        let mutated = Bsp::parse(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        let vdg = compile(&bytes, name);
        assert!(
            graph(&vdg) == graph(&reference),
            "{name}: the graph changed"
        );
        assert_eq!(leaks(&mutated, &vdg), 0, "{name}");
    }
}

#[test]
fn unused_records_are_neutralised_and_counted() {
    let original = testdata("complex.bsp");
    let bsp = Bsp::parse(&unused_garbage(&original)).unwrap();
    assert_eq!(bsp.unused_bad_records, 5);
    assert_eq!(Bsp::parse(&original).unwrap().unused_bad_records, 0);
    // The neutralised records are safe to walk: every clip node's plane exists.
    assert!(
        bsp.clipnodes
            .iter()
            .all(|c| (c.plane as usize) < bsp.planes.len())
    );
    let bsp = Bsp::parse(&clip_root_at_count(&original, 1)).unwrap();
    let n = bsp.clipnodes.len();
    assert_eq!(bsp.models[1].clip_headnode(1, n), None);
    assert!(bsp.models[0].clip_headnode(1, n).is_some());
}

/// The map with face `face`'s first surfedge (`edge`) or plane (`plane`) set to garbage.
fn garbage_in_face(bytes: &[u8], bsp: &Bsp, face: usize, edge: bool) -> Vec<u8> {
    let mut b = bytes.to_vec();
    if edge {
        let first = bsp.faces[face].first_edge as usize;
        let at = lump(bytes, SURFEDGES).0 + 4 * first;
        b[at..at + 4].copy_from_slice(&2136128767i32.to_le_bytes());
    } else {
        let at = lump(bytes, FACES).0 + 20 * face;
        b[at..at + 2].copy_from_slice(&17376u16.to_le_bytes());
    }
    b
}

/// Protectors write garbage into the edges or plane of faces the engine never draws:
/// such a face is not sampled but named, the map compiles, its walls come from the tree.
#[test]
fn faces_with_garbage_indices_are_unusable_not_fatal() {
    let original = testdata("complex.bsp");
    let bsp = Bsp::parse(&original).unwrap();
    assert!(bsp.unusable_faces.is_empty());
    let face = bsp.world().first_face as usize;
    for edge in [true, false] {
        let b = garbage_in_face(&original, &bsp, face, edge);
        let m = Bsp::parse(&b).unwrap_or_else(|e| panic!("edge {edge}: {e}"));
        assert_eq!(m.unusable_faces.len(), 1, "edge {edge}");
        assert_eq!(m.unusable_faces[0].index as usize, face);
        let reason = &m.unusable_faces[0].reason;
        assert!(
            reason.contains(if edge {
                "edge 2136128767"
            } else {
                "plane 17376"
            }),
            "{reason}"
        );
        assert!(bsp::faces::polygons(&m, 0).all(|f| f.index as usize != face));
        let vdg = compile(&b, if edge { "bad-edge" } else { "bad-plane" });
        assert_eq!(leaks(&m, &vdg), 0, "edge {edge}");
    }
    // A world clip hull reaching a garbage node is still an error: the engine walks it.
    let mut b = original.clone();
    let root = bsp.world().headnode[1] as usize;
    let at = lump(&original, CLIPNODES).0 + 8 * root;
    b[at..at + 4].copy_from_slice(&(-2136128596i32).to_le_bytes());
    let msg = Bsp::parse(&b).unwrap_err().to_string();
    assert!(msg.starts_with("lump clipnodes: record"), "{msg}");
}

/// Where more than half of the world's faces are unusable the map is not what its
/// file claims: the compile fails with that reason instead of a quiet poor graph.
#[test]
fn a_map_with_mostly_unusable_faces_fails_with_the_reason() {
    let original = testdata("complex.bsp");
    let bsp = Bsp::parse(&original).unwrap();
    let w = bsp.world();
    let mut b = original.clone();
    let half = w.num_faces as usize / 2 + 1;
    for f in w.first_face as usize..w.first_face as usize + half {
        b = garbage_in_face(&b, &bsp, f, false);
    }
    let m = Bsp::parse(&b).unwrap();
    assert_eq!(m.unusable_world_faces(), (half, w.num_faces as usize));
    let dir = tempdir();
    let map = dir.join("mostly-bad.bsp");
    std::fs::write(&map, &b).unwrap();
    let err = pipeline::compile(
        &map,
        &CompileOptions::new(dir.join("mostly-bad.vdg")),
        &Log::new(Verbosity::Quiet, true),
        &NoProgress,
    )
    .unwrap_err();
    assert!(
        matches!(err, pipeline::CompileError::UnusableFaces { .. }),
        "{err}"
    );
    assert!(
        err.to_string().contains(&format!("{half} of the world's")),
        "{err}"
    );
}

/// The same mutations on every shared GoldSrc map (skipped when they are absent).
#[test]
fn shared_maps_survive_the_same_mutations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/testmaps/goldsrc");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("skipped: {} is absent", dir.display());
        return;
    };
    let mut maps: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        .collect();
    maps.sort();
    for map in maps {
        let bytes = std::fs::read(&map).unwrap();
        let bsp = Bsp::parse(&bytes).unwrap();
        let last = bsp.models.len() - 1;
        for (name, mutated) in [
            ("clip-root", clip_root_at_count(&bytes, last)),
            ("garbage", unused_garbage(&bytes)),
            ("entities", lenient_entities(&bytes)),
        ] {
            let m =
                Bsp::parse(&mutated).unwrap_or_else(|e| panic!("{} {name}: {e}", map.display()));
            assert_eq!(
                m.faces.len() - bsp.faces.len(),
                (name == "garbage") as usize
            );
            assert_eq!(m.entities.len(), bsp.entities.len(), "{}", map.display());
        }
    }
}
