//! The on-disk records of a `.vdg` file (see `FORMAT.md`).
//!
//! Every record is `#[repr(C)]`, padding-free and `bytemuck::Pod`, so a
//! validated section is viewed in place with `bytemuck::cast_slice`. All
//! integers and floats are little endian; the crate refuses to build on
//! big-endian targets rather than silently byte-swapping.

use bytemuck::{Pod, Zeroable};

#[cfg(target_endian = "big")]
compile_error!("vdgformat views little-endian files in place and needs a little-endian target");

/// The first eight bytes of every `.vdg` file. The high-bit byte and the
/// CR LF / ^Z / LF tail catch 7-bit and text-mode transfers (the PNG trick).
pub const MAGIC: [u8; 8] = *b"\x89VDG\r\n\x1a\n";

/// The format version this crate writes. It reads this one and every older one
/// ([`OLDEST_READABLE_VERSION`]..=`FORMAT_VERSION`).
///
/// Version 2 added the 16-bit tree leaf faces ([`section::TREE_LEAF_FACES16`]),
/// written instead of the 32-bit ones when every face index fits in 16 bits.
/// Version 3 added the faces' own corner radii ([`section::FACE_RADII`]).
/// Version 4 added 16-bit faces, vertex faces and vertex neighbours
/// ([`section::FACES16`], [`section::VERTEX_FACES16`],
/// [`section::VERTEX_NEIGHBOURS16`]), written instead of the 32-bit ones when
/// every index fits in 16 bits.
pub const FORMAT_VERSION: u32 = 4;

/// The oldest format version the reader still opens (version 1: 32-bit leaf faces only).
pub const OLDEST_READABLE_VERSION: u32 = 1;

/// Graphs with at most this many faces get 16-bit tree leaf faces and
/// 16-bit vertex faces.
pub const MAX_FACES_FOR_NARROW_LEAVES: usize = 1 << 16;

/// Graphs with at most this many vertices get 16-bit faces and vertex
/// neighbours.
pub const MAX_VERTICES_FOR_NARROW_INDICES: usize = 1 << 16;

/// Every section starts at a multiple of this many bytes.
pub const SECTION_ALIGN: u64 = 16;

/// Deepest BBox tree the reader accepts; the writer stops at [`MAX_BUILD_DEPTH`].
pub const MAX_TREE_DEPTH: usize = 64;

/// Deepest BBox tree the writer builds.
pub const MAX_BUILD_DEPTH: usize = 48;

/// Offset of the checksum field; the checksum covers `bytes[CHECKSUM_END..]`.
pub const CHECKSUM_OFFSET: usize = 8;
/// First byte covered by the checksum.
pub const CHECKSUM_END: usize = 16;

/// File header, at offset 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Header {
    pub magic: [u8; 8],
    /// XXH64 (seed 0) of every byte after this field.
    pub checksum: u64,
    pub version: u32,
    /// `size_of::<Header>()`, i.e. 64.
    pub header_len: u32,
    /// Total file length in bytes.
    pub file_len: u64,
    pub section_count: u32,
    /// Byte offset of the section table (64: right after the header).
    pub section_table_offset: u32,
    /// Must be zero.
    pub reserved: [u32; 6],
}

/// One row of the section table.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SectionEntry {
    pub id: u32,
    /// Size of one element; fixed per section id.
    pub elem_size: u32,
    /// Byte offset from the file start; a multiple of [`SECTION_ALIGN`].
    pub offset: u64,
    /// Number of elements.
    pub count: u64,
    /// `elem_size * count`, stored so a table edit cannot go unnoticed.
    pub byte_len: u64,
}

/// Section ids.
pub mod section {
    /// One [`super::Info`] record.
    pub const INFO: u32 = 1;
    /// [`super::Vertex`] records.
    pub const VERTICES: u32 = 2;
    /// Faces: `[u32; 3]` vertex indices.
    pub const FACES: u32 = 3;
    /// CSR offsets of vertex → faces (`vertex_count + 1` × u32).
    pub const VERTEX_FACE_OFFSETS: u32 = 4;
    /// CSR targets of vertex → faces (u32 face indices, ascending per vertex).
    pub const VERTEX_FACES: u32 = 5;
    /// CSR offsets of vertex → vertices (`vertex_count + 1` × u32).
    pub const VERTEX_NEIGHBOUR_OFFSETS: u32 = 6;
    /// CSR targets of vertex → vertices (u32 vertex indices, ascending per vertex).
    pub const VERTEX_NEIGHBOURS: u32 = 7;
    /// [`super::TreeNode`] records in preorder, root first.
    pub const TREE_NODES: u32 = 8;
    /// u32 face indices referenced by the tree leaves (graphs of more than
    /// 65 536 faces, and every version-1 file). A file holds this section or
    /// [`TREE_LEAF_FACES16`], never both.
    pub const TREE_LEAF_FACES: u32 = 9;
    /// UTF-8 text, `key=value` lines.
    pub const METADATA: u32 = 10;
    /// [`super::NodeBounds`] records, one per tree node.
    pub const TREE_NODE_BOUNDS: u32 = 11;
    /// u16 face indices referenced by the tree leaves (version 2, graphs of at
    /// most 65 536 faces): the same lists as [`TREE_LEAF_FACES`] in half the bytes.
    pub const TREE_LEAF_FACES16: u32 = 12;
    /// `[f32; 3]` per face (version 3, optional): the radius of each corner's
    /// ball in that face's volume, at least the corner vertex's clearance. A
    /// vertex's clearance must hold in every face around it; a face's corner may
    /// reach further where only that face's own volume has to stay free. Absent:
    /// every face takes its vertices' clearances.
    pub const FACE_RADII: u32 = 13;
    /// Faces as `[u16; 3]` vertex indices (version 4, graphs of at most 65 536
    /// vertices): [`FACES`] in half the bytes.
    pub const FACES16: u32 = 14;
    /// u16 face indices of vertex → faces (version 4, graphs of at most 65 536
    /// faces): [`VERTEX_FACES`] in half the bytes.
    pub const VERTEX_FACES16: u32 = 15;
    /// u16 vertex indices of vertex → vertices (version 4, graphs of at most
    /// 65 536 vertices): [`VERTEX_NEIGHBOURS`] in half the bytes.
    pub const VERTEX_NEIGHBOURS16: u32 = 16;

    /// The 32- and 16-bit forms of the same list: a file holds exactly one of
    /// each pair.
    pub const ALTERNATIVES: [(u32, u32); 4] = [
        (FACES, FACES16),
        (VERTEX_FACES, VERTEX_FACES16),
        (VERTEX_NEIGHBOURS, VERTEX_NEIGHBOURS16),
        (TREE_LEAF_FACES, TREE_LEAF_FACES16),
    ];

    /// The format version that introduced a known section id.
    pub fn since_version(id: u32) -> u32 {
        match id {
            TREE_LEAF_FACES16 => 2,
            FACE_RADII => 3,
            FACES16 | VERTEX_FACES16 | VERTEX_NEIGHBOURS16 => 4,
            _ => 1,
        }
    }

    /// Every section id a reader knows, in file order; the pairs in
    /// [`ALTERNATIVES`] are alternatives (exactly one of each is present),
    /// [`FACE_RADII`] is optional, all others are required.
    pub const KNOWN: [u32; 16] = [
        INFO,
        VERTICES,
        FACES,
        VERTEX_FACE_OFFSETS,
        VERTEX_FACES,
        VERTEX_NEIGHBOUR_OFFSETS,
        VERTEX_NEIGHBOURS,
        TREE_NODES,
        TREE_LEAF_FACES,
        METADATA,
        TREE_NODE_BOUNDS,
        TREE_LEAF_FACES16,
        FACE_RADII,
        FACES16,
        VERTEX_FACES16,
        VERTEX_NEIGHBOURS16,
    ];

    /// Element size of a known section id.
    pub fn elem_size(id: u32) -> Option<u32> {
        Some(match id {
            INFO => size_of::<super::Info>() as u32,
            VERTICES => size_of::<super::Vertex>() as u32,
            FACES | FACE_RADII => 12,
            VERTEX_FACE_OFFSETS
            | VERTEX_FACES
            | VERTEX_NEIGHBOUR_OFFSETS
            | VERTEX_NEIGHBOURS
            | TREE_LEAF_FACES => 4,
            TREE_NODES => size_of::<super::TreeNode>() as u32,
            METADATA => 1,
            TREE_NODE_BOUNDS => size_of::<super::NodeBounds>() as u32,
            TREE_LEAF_FACES16 | VERTEX_FACES16 | VERTEX_NEIGHBOURS16 => 2,
            FACES16 => 6,
            _ => return None,
        })
    }

    /// Human-readable section name for error messages.
    pub fn name(id: u32) -> &'static str {
        match id {
            INFO => "info",
            VERTICES => "vertices",
            FACES => "faces",
            VERTEX_FACE_OFFSETS => "vertex-face offsets",
            VERTEX_FACES => "vertex faces",
            VERTEX_NEIGHBOUR_OFFSETS => "vertex-neighbour offsets",
            VERTEX_NEIGHBOURS => "vertex neighbours",
            TREE_NODES => "tree nodes",
            TREE_LEAF_FACES => "tree leaf faces",
            METADATA => "metadata",
            TREE_NODE_BOUNDS => "tree node bounds",
            TREE_LEAF_FACES16 => "tree leaf faces (16-bit)",
            FACE_RADII => "face corner radii",
            FACES16 => "faces (16-bit)",
            VERTEX_FACES16 => "vertex faces (16-bit)",
            VERTEX_NEIGHBOURS16 => "vertex neighbours (16-bit)",
            _ => "unknown",
        }
    }
}

/// Global counts, bounds and build parameters (the `INFO` section, one record).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Info {
    pub vertex_count: u32,
    pub face_count: u32,
    pub tree_node_count: u32,
    /// Minimum BBox-tree leaf extent (`-bb`) the tree was built with.
    pub leaf_size: f32,
    /// Bounds of the vertex positions.
    pub vertex_min: [f32; 3],
    /// Largest vertex clearance.
    pub max_clearance: f32,
    pub vertex_max: [f32; 3],
    pub reserved0: u32,
    /// Bounds of Volume(VDG) (the union of the face volumes' boxes): the
    /// tree's root cell.
    pub volume_min: [f32; 3],
    pub reserved1: u32,
    pub volume_max: [f32; 3],
    pub reserved2: u32,
    /// XXH64 (seed 0) of the source map file; 0 when unknown.
    pub source_hash: u64,
    pub reserved3: u64,
}

/// A Voronoi vertex: position and clearance (the radius of its free ball).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    pub pos: [f32; 3],
    pub clearance: f32,
}

/// The radii of face `f`'s corners: its own ([`section::FACE_RADII`], when
/// the file has them) or its vertices' clearances.
#[inline]
pub(crate) fn corner_radii(
    faces: crate::index::FaceList<'_>,
    vertices: &[Vertex],
    face_radii: &[[f32; 3]],
    f: usize,
) -> [f32; 3] {
    match face_radii.get(f) {
        Some(&r) => r,
        None => faces.get(f as u32).map(|v| vertices[v as usize].clearance),
    }
}

/// Whether `k` may be a metadata key: a non-empty word of
/// `[A-Za-z0-9._-]`. The writer refuses other keys and the reader other
/// files, so both ask this one rule.
pub(crate) fn is_metadata_key(k: &str) -> bool {
    !k.is_empty()
        && k.bytes()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, b'.' | b'_' | b'-'))
}

/// Node of the BBox (kd) tree. Inner nodes split their cell at `split` on
/// axis `kind` (0 = x, 1 = y, 2 = z) into children `a` (below) and `b`
/// (above); leaves (`kind == LEAF`) list `b` faces starting at entry `a` of
/// the leaf-face section (32- or 16-bit).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct TreeNode {
    pub kind: u32,
    pub split: f32,
    pub a: u32,
    pub b: u32,
}

impl TreeNode {
    /// `kind` of a leaf.
    pub const LEAF: u32 = 3;
}

/// Search bounds of a tree node, from the faces listed below it: the box of
/// their triangles (vertex positions, no radii) and their largest corner
/// radius (the vertex clearances, or the faces' own corner radii). Any listed face has clearance at most
/// `r_max − dist(p, [tri_min, tri_max])` at `p` — the bound that lets the
/// nearest-face search skip subtrees for points outside the volume. A node
/// without faces has `r_max = -1` and a zero box.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct NodeBounds {
    pub tri_min: [f32; 3],
    pub r_max: f32,
    pub tri_max: [f32; 3],
    pub reserved: u32,
}

#[cfg(test)]
mod tests {
    use super::section;

    #[test]
    fn every_listed_section_has_a_size_and_every_sized_one_is_listed() {
        // The reader takes a section's slot from `KNOWN` and its element size
        // from `elem_size`; a section in one and not the other would be
        // skipped as unknown.
        for id in 0..64 {
            assert_eq!(
                section::KNOWN.contains(&id),
                section::elem_size(id).is_some(),
                "section id {id}"
            );
        }
    }
}
