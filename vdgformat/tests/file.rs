//! Writing, reading, determinism, and one test per malformed-file error.

mod common;

use bytemuck::Pod;
use common::{Rng, flat, open, random_soup};
use vdgformat::layout::{Header, Info, SectionEntry, TreeNode, Vertex, section};
use vdgformat::{ReadError, Vdg, VdgBuilder, VdgFile, xxh64};

fn sample() -> VdgBuilder {
    let mut b = random_soup(300, 900, &mut Rng::new(1));
    b.set_leaf_size(32.0)
        .set_source("maps/test.bsp", xxh64(b"pretend map", 0))
        .set_tool("bsp2vdg", "0.1.0")
        .set_metadata("option.rl", "1.0")
        .set_metadata("option.bb", "32");
    b
}

fn temp_dir(name: &str) -> toolbox::ScratchDir {
    toolbox::ScratchDir::new(&format!("vdgformat-{name}")).unwrap()
}

#[test]
fn round_trip_preserves_everything() {
    let b = sample();
    let bytes = b.to_bytes().unwrap();
    let file = VdgFile::from_bytes(&bytes).unwrap();
    let g = file.graph();
    assert_eq!(g.vertex_count(), b.vertex_count());
    assert_eq!(g.face_count(), b.face_count());
    assert_eq!(g.source_hash(), xxh64(b"pretend map", 0));
    assert_eq!(g.metadata_value("source.name"), Some("maps/test.bsp"));
    assert_eq!(g.metadata_value("tool.name"), Some("bsp2vdg"));
    assert_eq!(g.metadata_value("option.rl"), Some("1.0"));
    assert_eq!(g.info().leaf_size, 32.0);
    // Re-building from what was read gives the same bytes.
    let mut again = VdgBuilder::new();
    for v in g.vertices() {
        again.add_vertex(v.pos, v.clearance);
    }
    for f in g.faces() {
        again.add_face(f);
    }
    for (k, v) in g.metadata() {
        again.set_metadata(k, v);
    }
    again.set_leaf_size(32.0);
    let hash = g.source_hash();
    again.set_source(g.metadata_value("source.name").unwrap(), hash);
    assert_eq!(again.to_bytes().unwrap(), bytes);
    // Adjacency is the face incidence.
    for (fi, f) in g.faces().iter().enumerate() {
        for v in f {
            assert!(g.vertex_faces(v).contains(fi as u32));
            for w in f {
                assert_eq!(v == w, !g.vertex_neighbours(v).contains(w));
            }
        }
    }
}

#[test]
fn writes_are_byte_identical_and_atomic() {
    let dir = temp_dir("atomic");
    let path = dir.join("g.vdg");
    let b = sample();
    b.write_atomic(&path).unwrap();
    let first = std::fs::read(&path).unwrap();
    b.clone().write_atomic(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), first);
    assert_eq!(b.to_bytes().unwrap(), first);
    // Memory-mapped open sees the same graph.
    let mapped = VdgFile::open(&path).unwrap();
    assert_eq!(mapped.as_bytes(), &first[..]);
    assert_eq!(mapped.graph().face_count(), b.face_count());
    // Only the final file is left in the directory.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("g.vdg")]);
    // An unwritable destination is an error, not a partial file.
    let bad = dir.join("missing-dir").join("g.vdg");
    let err = b.write_atomic(&bad).unwrap_err();
    assert!(err.to_string().contains("cannot write"), "{err}");
    assert!(!bad.exists());
}

#[test]
fn sections_are_aligned_and_in_file_order() {
    let bytes = sample().to_bytes().unwrap();
    let table = entries(&bytes);
    assert_eq!(table.len(), 11);
    for (_, e) in &table {
        assert_eq!(e.offset % 16, 0);
    }
    assert!(table.windows(2).all(|w| w[0].1.offset < w[1].1.offset));
}

#[test]
fn empty_graph_is_valid_and_answers_nothing() {
    let file = VdgFile::from_bytes(&VdgBuilder::new().to_bytes().unwrap()).unwrap();
    let g = file.graph();
    assert_eq!(g.face_count(), 0);
    assert_eq!(g.nearest_face([0.0; 3]), None);
    assert!(!g.visible([0.0; 3], [1.0; 3]));
    assert_eq!(g.clearance([0.0; 3]), f32::NEG_INFINITY);
}

#[test]
fn builder_rejects_invalid_input() {
    use vdgformat::BuildError;
    let mut b = VdgBuilder::new();
    let v = b.add_vertex([0.0; 3], 1.0);
    b.add_face([v, v, v]);
    assert_eq!(b.to_bytes(), Err(BuildError::DegenerateFace { face: 0 }));
    let mut b = VdgBuilder::new();
    b.add_face([0, 1, 2]);
    assert!(matches!(
        b.to_bytes(),
        Err(BuildError::FaceIndexOutOfRange { .. })
    ));
    let mut b = VdgBuilder::new();
    b.add_vertex([f32::NAN, 0.0, 0.0], 1.0);
    assert_eq!(b.to_bytes(), Err(BuildError::NonFiniteVertex { vertex: 0 }));
    let mut b = VdgBuilder::new();
    b.add_vertex([0.0; 3], -1.0);
    assert!(matches!(
        b.to_bytes(),
        Err(BuildError::NegativeClearance { .. })
    ));
    assert!(matches!(
        VdgBuilder::new().set_leaf_size(0.0).to_bytes(),
        Err(BuildError::BadLeafSize(_))
    ));
    assert!(matches!(
        VdgBuilder::new().set_metadata("a b", "x").to_bytes(),
        Err(BuildError::BadMetadataKey(_))
    ));
    assert!(matches!(
        VdgBuilder::new().set_metadata("a", "x\ny").to_bytes(),
        Err(BuildError::BadMetadataValue { .. })
    ));
}

// ---- corruption: one test per ReadError variant ----------------------------

fn entries(bytes: &[u8]) -> Vec<(usize, SectionEntry)> {
    let h: Header = bytemuck::pod_read_unaligned(&bytes[..64]);
    (0..h.section_count as usize)
        .map(|i| {
            let at = 64 + i * 32;
            (at, bytemuck::pod_read_unaligned(&bytes[at..at + 32]))
        })
        .collect()
}

fn section_of(bytes: &[u8], id: u32) -> (usize, SectionEntry) {
    entries(bytes)
        .into_iter()
        .find(|(_, e)| e.id == id)
        .unwrap()
}

fn put<T: Pod>(bytes: &mut [u8], at: usize, value: T) {
    bytes[at..at + size_of::<T>()].copy_from_slice(bytemuck::bytes_of(&value));
}

fn get<T: Pod>(bytes: &[u8], at: usize) -> T {
    bytemuck::pod_read_unaligned(&bytes[at..at + size_of::<T>()])
}

/// Applies `edit` and fixes the checksum so validation reaches the edit.
fn corrupt(edit: impl FnOnce(&mut Vec<u8>)) -> ReadError {
    let mut bytes = sample().to_bytes().unwrap();
    edit(&mut bytes);
    vdgformat::__private::seal(&mut bytes);
    let err = VdgFile::from_bytes(&bytes).unwrap_err();
    assert!(!err.to_string().is_empty() && !err.to_string().contains('\n'));
    err
}

fn elem_at(bytes: &[u8], id: u32, index: usize) -> usize {
    let (_, e) = section_of(bytes, id);
    e.offset as usize + index * e.elem_size as usize
}

#[test]
fn io_error() {
    let err = VdgFile::open("/nonexistent/dir/x.vdg").unwrap_err();
    assert!(matches!(err, ReadError::Io(_)), "{err}");
}

#[test]
fn truncated() {
    let bytes = sample().to_bytes().unwrap();
    for len in [0, 3, 40, bytes.len() - 16] {
        let err = VdgFile::from_bytes(&bytes[..len]).unwrap_err();
        assert!(matches!(err, ReadError::Truncated { .. }), "{len}: {err}");
    }
}

#[test]
fn trailing_data() {
    let mut bytes = sample().to_bytes().unwrap();
    bytes.extend_from_slice(&[0; 16]);
    assert!(matches!(
        VdgFile::from_bytes(&bytes),
        Err(ReadError::TrailingData { .. })
    ));
}

#[test]
fn bad_magic() {
    let mut bytes = sample().to_bytes().unwrap();
    bytes[1] = b'X';
    assert!(matches!(
        VdgFile::from_bytes(&bytes),
        Err(ReadError::BadMagic)
    ));
    assert!(matches!(
        VdgFile::from_bytes(b"PK\x03\x04 zip"),
        Err(ReadError::BadMagic)
    ));
}

#[test]
fn unsupported_version() {
    for v in [0u32, 5, 0x0100_0000] {
        let mut bytes = sample().to_bytes().unwrap();
        put(&mut bytes, 16, v);
        let err = VdgFile::from_bytes(&bytes).unwrap_err();
        assert!(
            matches!(
                err,
                ReadError::UnsupportedVersion {
                    found,
                    supported: 4
                } if found == v
            ),
            "{err}"
        );
        assert!(err.to_string().contains("supports 1 to 4"), "{err}");
    }
}

#[test]
fn checksum_mismatch() {
    let mut bytes = sample().to_bytes().unwrap();
    let at = elem_at(&bytes, section::VERTICES, 5);
    bytes[at] ^= 1;
    assert!(matches!(
        VdgFile::from_bytes(&bytes),
        Err(ReadError::ChecksumMismatch { .. })
    ));
}

#[test]
fn bad_header() {
    assert!(matches!(
        corrupt(|b| put(b, 20, 72u32)),
        ReadError::BadHeader(_)
    ));
    assert!(matches!(
        corrupt(|b| put(b, 40, 1u32)),
        ReadError::BadHeader(_)
    ));
    assert!(matches!(
        corrupt(|b| put(b, 36, 96u32)),
        ReadError::BadHeader(_)
    ));
}

#[test]
fn section_table_out_of_bounds() {
    let err = corrupt(|b| put(b, 32, 1_000_000u32));
    assert!(matches!(err, ReadError::SectionTableOutOfBounds), "{err}");
}

#[test]
fn section_out_of_bounds() {
    let err = corrupt(|b| {
        let (at, e) = section_of(b, section::FACES16);
        put(b, at + 8, e.offset + 1_000_000 * 16);
    });
    assert!(
        matches!(
            err,
            ReadError::SectionOutOfBounds {
                id: section::FACES16
            }
        ),
        "{err}"
    );
    // Pointing into the header is out of bounds too.
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::FACES16);
        put(b, at + 8, 16u64);
    });
    assert!(matches!(err, ReadError::SectionOutOfBounds { .. }), "{err}");
}

#[test]
fn section_misaligned() {
    let err = corrupt(|b| {
        let (at, e) = section_of(b, section::VERTICES);
        put(b, at + 8, e.offset + 4);
    });
    assert!(
        matches!(
            err,
            ReadError::SectionMisaligned {
                id: section::VERTICES,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn section_overlap() {
    let err = corrupt(|b| {
        let (_, v) = section_of(b, section::VERTICES);
        let (at, _) = section_of(b, section::FACES16);
        put(b, at + 8, v.offset + 16);
    });
    assert!(matches!(err, ReadError::SectionOverlap { .. }), "{err}");
}

#[test]
fn section_size_mismatch() {
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::FACES16);
        put(b, at + 4, 16u32);
    });
    assert!(
        matches!(
            err,
            ReadError::SectionSizeMismatch {
                id: section::FACES16
            }
        ),
        "{err}"
    );
    let err = corrupt(|b| {
        let (at, e) = section_of(b, section::VERTICES);
        put(b, at + 16, e.count - 1);
    });
    assert!(
        matches!(err, ReadError::SectionSizeMismatch { .. }),
        "{err}"
    );
}

#[test]
fn duplicate_section() {
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::VERTEX_NEIGHBOURS16);
        put(b, at, section::VERTEX_FACES16);
    });
    assert!(
        matches!(
            err,
            ReadError::DuplicateSection {
                id: section::VERTEX_FACES16
            }
        ),
        "{err}"
    );
}

#[test]
fn missing_section() {
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::METADATA);
        put(b, at, 99u32); // unknown ids are skipped
    });
    assert!(
        matches!(
            err,
            ReadError::MissingSection {
                id: section::METADATA
            }
        ),
        "{err}"
    );
}

#[test]
fn index_lists_are_one_of_two_sections() {
    // Both the 32- and the 16-bit form: a section of 4-byte elements renamed.
    for (wide, narrow) in [
        (section::TREE_LEAF_FACES, section::TREE_LEAF_FACES16),
        (section::VERTEX_FACES, section::VERTEX_FACES16),
        (section::VERTEX_NEIGHBOURS, section::VERTEX_NEIGHBOURS16),
    ] {
        let err = corrupt(|b| {
            let (at, _) = section_of(b, section::VERTEX_FACE_OFFSETS);
            put(b, at, wide);
        });
        assert!(
            matches!(
                err,
                ReadError::ConflictingSections { first, second } if (first, second) == (wide, narrow)
            ),
            "{err}"
        );
    }
    // Neither.
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::TREE_LEAF_FACES16);
        put(b, at, 99u32);
    });
    assert!(
        matches!(
            err,
            ReadError::MissingSection {
                id: section::TREE_LEAF_FACES
            }
        ),
        "{err}"
    );
    // Version 1 knew no 16-bit lists and version 3 no 16-bit faces: there
    // those sections are unknown ones.
    for (version, missing) in [(1u32, section::FACES), (3, section::FACES)] {
        let err = corrupt(|b| put(b, 16, version));
        assert!(
            matches!(err, ReadError::MissingSection { id } if id == missing),
            "{err}"
        );
    }
    let err = corrupt(|b| {
        let (at, _) = section_of(b, section::FACES16);
        put(b, at, 99u32);
    });
    assert!(
        matches!(err, ReadError::MissingSection { id: section::FACES }),
        "{err}"
    );
}

/// A strip of `n` cells (2n faces) along x: big enough for 32-bit leaf entries.
fn strip(n: usize) -> VdgBuilder {
    common::grid(
        n,
        1,
        4.0,
        |_, _| 0.0,
        |x, _| 3.0 + (x * 0.01).sin(),
        |_, _| true,
    )
}

#[test]
fn indices_are_16_bit_exactly_when_every_index_fits() {
    let has = |bytes: &[u8], id| entries(bytes).iter().any(|(_, e)| e.id == id);
    // Which of each pair a file holds: true for the 16-bit one.
    let widths = |bytes: &[u8]| {
        section::ALTERNATIVES.map(|(w, n)| {
            assert!(has(bytes, w) != has(bytes, n), "exactly one of {w} and {n}");
            has(bytes, n)
        })
    };
    // Pairs: faces, vertex faces, vertex neighbours, leaf faces.
    let all = strip(32_767).to_bytes().unwrap(); // 65 536 vertices, 65 534 faces
    assert_eq!(widths(&all), [true; 4]);
    let narrow = strip(32_768).to_bytes().unwrap(); // 65 538 vertices, 65 536 faces
    assert_eq!(widths(&narrow), [false, true, false, true]);
    let wide = strip(32_769).to_bytes().unwrap(); // 65 540 vertices, 65 538 faces
    assert_eq!(widths(&wide), [false; 4]);
    // All answer like the faces themselves; the last face is found through the tree.
    for bytes in [&all, &narrow, &wide] {
        let file = VdgFile::from_bytes(bytes).unwrap();
        let g = file.graph();
        // The views say which width they read.
        let w = widths(bytes);
        assert_eq!(g.faces().is_16_bit(), w[0]);
        assert_eq!(g.vertex_faces(0).is_16_bit(), w[1]);
        assert_eq!(g.vertex_neighbours(0).is_16_bit(), w[2]);
        assert_eq!(g.format_version(), vdgformat::layout::FORMAT_VERSION);
        let last = g.face_count() as u32 - 1;
        let f = g.face(last);
        let c = [0, 1, 2].map(|k| {
            f.iter()
                .map(|&v| g.vertices()[v as usize].pos[k])
                .sum::<f32>()
                / 3.0
        });
        let hit = g.nearest_face(c).unwrap();
        assert!(g.faces_containing(c).contains(&last));
        assert!((hit.clearance - g.face_clearance(last, c)).abs() < 1e-4);
        assert!(g.contains([c[0], c[1], 1.0]) && !g.contains([c[0], c[1], 9.0]));
    }
    // A version-1 file (32-bit leaf entries were its only kind) still opens.
    let mut v1 = wide.clone();
    put(&mut v1, 16, 1u32);
    vdgformat::__private::seal(&mut v1);
    let file = VdgFile::from_bytes(&v1).unwrap();
    assert_eq!(file.graph().face_count(), 65_538);
    assert_eq!(file.graph().format_version(), 1);
}

#[test]
fn count_mismatch() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::INFO, 0);
        let mut info: Info = get(b, at);
        info.vertex_count += 1;
        put(b, at, info);
    });
    assert!(matches!(err, ReadError::CountMismatch { .. }), "{err}");
}

#[test]
fn non_finite() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::VERTICES, 7);
        put(b, at + 4, f32::NAN);
    });
    assert!(
        matches!(
            err,
            ReadError::NonFinite {
                what: "vertex",
                index: 7
            }
        ),
        "{err}"
    );
}

#[test]
fn negative_clearance() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::VERTICES, 9);
        let mut v: Vertex = get(b, at);
        v.clearance = -1.0;
        put(b, at, v);
    });
    assert!(
        matches!(err, ReadError::NegativeClearance { vertex: 9 }),
        "{err}"
    );
}

#[test]
fn degenerate_face() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::FACES16, 3);
        let f: [u16; 3] = get(b, at);
        put(b, at, [f[0], f[0], f[2]]);
    });
    assert!(
        matches!(err, ReadError::DegenerateFace { face: 3 }),
        "{err}"
    );
}

#[test]
fn index_out_of_range() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::FACES16, 3);
        put(b, at + 2, 300u16);
    });
    assert!(
        matches!(
            err,
            ReadError::IndexOutOfRange {
                what: "face vertex",
                ..
            }
        ),
        "{err}"
    );
    let err = corrupt(|b| {
        let at = elem_at(b, section::TREE_LEAF_FACES16, 0);
        put(b, at, 900u16);
    });
    assert!(
        matches!(
            err,
            ReadError::IndexOutOfRange {
                what: "tree leaf face",
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn bad_offsets() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::VERTEX_FACE_OFFSETS, 0);
        put(b, at, 1u32);
    });
    assert!(matches!(err, ReadError::BadOffsets { .. }), "{err}");
    let err = corrupt(|b| {
        let at = elem_at(b, section::VERTEX_NEIGHBOUR_OFFSETS, 10);
        put(b, at, u32::MAX);
    });
    assert!(matches!(err, ReadError::BadOffsets { .. }), "{err}");
}

#[test]
fn inconsistent_adjacency() {
    // A face listed under a vertex it does not use.
    let err = corrupt(|b| {
        let at = elem_at(b, section::VERTEX_FACES16, 0);
        let f: u16 = get(b, at);
        put(b, at, if f == 0 { 1u16 } else { 0u16 });
    });
    assert!(
        matches!(err, ReadError::InconsistentAdjacency { .. }),
        "{err}"
    );
}

/// Index of the first inner node of the sample's tree and its children.
fn inner_node(b: &[u8]) -> (usize, TreeNode) {
    let (_, e) = section_of(b, section::TREE_NODES);
    (0..e.count as usize)
        .map(|i| (i, get::<TreeNode>(b, elem_at(b, section::TREE_NODES, i))))
        .find(|(_, n)| n.kind != TreeNode::LEAF)
        .expect("sample tree has inner nodes")
}

#[test]
fn bad_tree_structure() {
    // A child pointing back to the root: a cycle.
    let err = corrupt(|b| {
        let (i, mut n) = inner_node(b);
        n.b = 0;
        let at = elem_at(b, section::TREE_NODES, i);
        put(b, at, n);
    });
    assert!(matches!(err, ReadError::BadTreeStructure { .. }), "{err}");
    // Both children the same node: a DAG, not a tree.
    let err = corrupt(|b| {
        let (i, mut n) = inner_node(b);
        n.b = n.a;
        let at = elem_at(b, section::TREE_NODES, i);
        put(b, at, n);
    });
    assert!(matches!(err, ReadError::BadTreeStructure { .. }), "{err}");
}

#[test]
fn bad_tree_node() {
    let err = corrupt(|b| {
        let (i, mut n) = inner_node(b);
        n.kind = 7;
        let at = elem_at(b, section::TREE_NODES, i);
        put(b, at, n);
    });
    assert!(matches!(err, ReadError::BadTreeNode { .. }), "{err}");
    let err = corrupt(|b| {
        let (i, mut n) = inner_node(b);
        n.split = 1e30;
        let at = elem_at(b, section::TREE_NODES, i);
        put(b, at, n);
    });
    assert!(matches!(err, ReadError::BadTreeNode { .. }), "{err}");
}

#[test]
fn bad_metadata() {
    let err = corrupt(|b| {
        let at = elem_at(b, section::METADATA, 2);
        b[at] = 0xFF;
    });
    assert!(matches!(err, ReadError::BadMetadata { line: 1 }), "{err}");
}

#[test]
fn unaligned_buffer() {
    let file = open(&flat(2, 2, 10.0, 3.0));
    let mut copy = vec![0u8; file.as_bytes().len() + 1];
    copy[1..].copy_from_slice(file.as_bytes());
    // One of the two starts is misaligned whatever the allocator did.
    let a = Vdg::from_aligned_bytes(&copy[1..]);
    let b = Vdg::from_aligned_bytes(file.as_bytes());
    assert!(b.is_ok());
    let misaligned = !(copy.as_ptr() as usize + 1).is_multiple_of(16);
    if misaligned {
        assert!(matches!(a, Err(ReadError::UnalignedBuffer)));
    }
    assert!(matches!(
        Vdg::from_aligned_bytes(&file.as_bytes()[1..]),
        Err(ReadError::UnalignedBuffer)
    ));
}

// ---- faces' own corner radii (format version 3) ------------------------------

/// Two faces sharing the edge 1–2 in the plane z = 0, all vertex clearances 10;
/// the first face's corner at vertex 0 has a radius of its own, 40.
fn corner_pair() -> VdgBuilder {
    let mut b = VdgBuilder::new();
    let v = [
        b.add_vertex([0.0, 0.0, 0.0], 10.0),
        b.add_vertex([200.0, 0.0, 0.0], 10.0),
        b.add_vertex([0.0, 200.0, 0.0], 10.0),
        b.add_vertex([200.0, 200.0, 0.0], 10.0),
    ];
    b.add_face_with_radii([v[0], v[1], v[2]], [40.0, 10.0, 10.0]);
    b.add_face([v[1], v[3], v[2]]);
    b.set_leaf_size(16.0);
    b
}

#[test]
fn face_radii_round_trip_and_widen_only_their_face() {
    let bytes = corner_pair().to_bytes().unwrap();
    assert_eq!(get::<u32>(&bytes, 16), 4, "format version");
    let file = VdgFile::from_bytes(&bytes).unwrap();
    let g = file.graph();
    assert!(g.has_face_radii());
    assert_eq!(g.face_radii(0), [40.0, 10.0, 10.0]);
    // The face without radii of its own takes its vertices' clearances.
    assert_eq!(g.face_radii(1), [10.0; 3]);
    assert_eq!(g.vertices()[0].clearance, 10.0);
    // 30 above vertex 0: inside its corner ball in face 0 (clearance 10), found
    // through the tree from scratch; the vertex ball alone would miss it.
    let p = [0.0, 0.0, 30.0];
    assert!(g.contains(p));
    assert!((g.clearance(p) - 10.0).abs() < 1e-4, "{}", g.clearance(p));
    assert_eq!(g.nearest_face(p).unwrap().face, 0);
    // The radius falls linearly to 10 at the other corners: over the middle of
    // the edge 0–1 it is 25, so 20 above it is inside, 30 above it not.
    assert!(g.contains([100.0, 0.0, 20.0]) && !g.contains([100.0, 0.0, 30.0]));
    // Face 1 keeps clearance 10 everywhere: 15 above its far corner is outside.
    assert!(!g.contains([200.0, 200.0, 15.0]));
    // A sight line through the raised corner ball only.
    assert!(g.visible([-20.0, 5.0, 25.0], [20.0, 5.0, 25.0]));
    assert!(!g.visible([-20.0, 5.0, 45.0], [20.0, 5.0, 45.0]));
}

#[test]
fn files_without_own_radii_have_no_radii_section() {
    let bytes = sample().to_bytes().unwrap();
    assert!(
        entries(&bytes)
            .iter()
            .all(|(_, e)| e.id != section::FACE_RADII)
    );
    let file = VdgFile::from_bytes(&bytes).unwrap();
    assert!(!file.graph().has_face_radii());
    let with = corner_pair().to_bytes().unwrap();
    let (_, e) = section_of(&with, section::FACE_RADII);
    assert_eq!((e.count, e.elem_size), (2, 12));
}

#[test]
fn builder_rejects_corner_radii_below_the_vertex_clearance() {
    for bad in [9.5, f32::NAN, f32::INFINITY] {
        let mut b = VdgBuilder::new();
        let v = [
            b.add_vertex([0.0, 0.0, 0.0], 10.0),
            b.add_vertex([1.0, 0.0, 0.0], 10.0),
            b.add_vertex([0.0, 1.0, 0.0], 10.0),
        ];
        b.add_face_with_radii(v, [10.0, bad, 10.0]);
        let err = b.to_bytes().unwrap_err();
        assert!(
            matches!(
                err,
                vdgformat::BuildError::BadCornerRadius {
                    face: 0,
                    corner: 1,
                    ..
                }
            ),
            "{err}"
        );
    }
}

#[test]
fn corner_below_clearance() {
    let mut bytes = corner_pair().to_bytes().unwrap();
    let at = elem_at(&bytes, section::FACE_RADII, 1);
    put(&mut bytes, at + 8, 9.0f32);
    vdgformat::__private::seal(&mut bytes);
    let err = VdgFile::from_bytes(&bytes).unwrap_err();
    assert!(
        matches!(err, ReadError::CornerBelowClearance { face: 1, corner: 2 }),
        "{err}"
    );
    assert!(!err.to_string().contains('\n'));
    // A NaN radius is named as such.
    let mut bytes = corner_pair().to_bytes().unwrap();
    let at = elem_at(&bytes, section::FACE_RADII, 0);
    put(&mut bytes, at, f32::NAN);
    vdgformat::__private::seal(&mut bytes);
    let err = VdgFile::from_bytes(&bytes).unwrap_err();
    assert!(
        matches!(
            err,
            ReadError::NonFinite {
                what: "face corner radius",
                index: 0
            }
        ),
        "{err}"
    );
}
