//! Serialisation: the bounds, adjacency, tree and info record derived
//! from a validated builder, the sections (16-bit where every index fits),
//! their layout behind the header and section table, and the checksum.

use std::borrow::Cow;
use std::path::Path;

use super::adjacency::{vertex_faces, vertex_neighbours};
use super::tree::{Reach, Tree, build_tree, face_box, face_reach, node_bounds};
use super::{BuildError, VdgBuilder, WriteError};
use crate::geom::Aabb;
use crate::hash::xxh64;
use crate::index::{FaceList, IndexList};
use crate::layout::{
    CHECKSUM_END, CHECKSUM_OFFSET, FORMAT_VERSION, Header, Info, MAGIC,
    MAX_FACES_FOR_NARROW_LEAVES, MAX_VERTICES_FOR_NARROW_INDICES, NodeBounds, SECTION_ALIGN,
    SectionEntry, section,
};

/// The boxes a file records: every face volume's (the tree is built from
/// them), the whole volume's (the tree's root cell) and the vertices', with
/// the largest clearance.
struct Bounds {
    face_boxes: Vec<Aabb>,
    volume: Aabb,
    vertices: Aabb,
    max_clearance: f32,
}

/// Everything the file holds beyond the builder's own vertices and faces.
struct Derived {
    /// The `FACE_RADII` section (empty when no face has its own radii).
    radii: Vec<[f32; 3]>,
    info: Info,
    vf_offsets: Vec<u32>,
    vf_targets: Vec<u32>,
    vn_offsets: Vec<u32>,
    vn_targets: Vec<u32>,
    tree: Tree,
    node_bounds: Vec<NodeBounds>,
    metadata: String,
}

impl VdgBuilder {
    /// The file of a validated builder: what it derives from the builder,
    /// then those parts laid out as sections.
    pub(super) fn serialise(&self) -> Result<Vec<u8>, BuildError> {
        Ok(self.sections(&self.derive()?))
    }

    /// Bounds, adjacency, the tree with its node bounds, the info record
    /// and the metadata text.
    fn derive(&self) -> Result<Derived, BuildError> {
        let vcount = self.vertices.len();
        let radii = self.corner_radii();
        let bounds = self.bounds(&radii);
        let (vf_offsets, vf_targets) = vertex_faces(vcount, &self.faces);
        let (vn_offsets, vn_targets) = vertex_neighbours(vcount, &self.faces);
        let (tree, node_bounds) = self.tree(&radii, &bounds)?;
        let info = self.info(&bounds, &tree);
        Ok(Derived {
            radii,
            info,
            vf_offsets,
            vf_targets,
            vn_offsets,
            vn_targets,
            tree,
            node_bounds,
            metadata: self.metadata_text(),
        })
    }

    /// Face `i`'s corner radii: its own, or its vertices' clearances.
    fn corners(&self, radii: &[[f32; 3]], i: usize) -> [f32; 3] {
        crate::layout::corner_radii(FaceList::wide(&self.faces), &self.vertices, radii, i)
    }

    fn bounds(&self, radii: &[[f32; 3]]) -> Bounds {
        let face_boxes: Vec<Aabb> = (0..self.faces.len())
            .map(|i| face_box(&self.vertices, &self.faces[i], self.corners(radii, i)))
            .collect();
        let mut volume = Aabb::EMPTY;
        for b in &face_boxes {
            volume.grow(b);
        }
        let mut vbox = Aabb::EMPTY;
        let mut max_clearance = 0.0f32;
        for v in &self.vertices {
            vbox.grow(&Aabb {
                min: v.pos,
                max: v.pos,
            });
            max_clearance = max_clearance.max(v.clearance);
        }
        Bounds {
            face_boxes,
            volume: zero_if_empty(volume),
            vertices: zero_if_empty(vbox),
            max_clearance,
        }
    }

    /// The BBox tree over the face volumes and its nodes' search bounds.
    fn tree(
        &self,
        radii: &[[f32; 3]],
        bounds: &Bounds,
    ) -> Result<(Tree, Vec<NodeBounds>), BuildError> {
        let reach: Vec<Reach> = (0..self.faces.len())
            .map(|i| face_reach(&self.vertices, &self.faces[i], self.corners(radii, i)))
            .collect();
        let tree = build_tree(&bounds.face_boxes, &reach, bounds.volume, self.leaf_size);
        let node_bounds = node_bounds(
            &tree.nodes,
            IndexList::wide(&tree.leaf_faces),
            FaceList::wide(&self.faces),
            &self.vertices,
            radii,
        );
        if tree.leaf_faces.len() >= u32::MAX as usize || tree.nodes.len() >= u32::MAX as usize {
            return Err(BuildError::TooLarge("tree entries"));
        }
        Ok((tree, node_bounds))
    }

    fn info(&self, bounds: &Bounds, tree: &Tree) -> Info {
        Info {
            vertex_count: self.vertices.len() as u32,
            face_count: self.faces.len() as u32,
            tree_node_count: tree.nodes.len() as u32,
            leaf_size: self.leaf_size,
            vertex_min: bounds.vertices.min,
            max_clearance: bounds.max_clearance,
            vertex_max: bounds.vertices.max,
            reserved0: 0,
            volume_min: bounds.volume.min,
            reserved1: 0,
            volume_max: bounds.volume.max,
            reserved2: 0,
            source_hash: self.source_hash,
            reserved3: 0,
        }
    }

    /// The `METADATA` section: one `key=value` line per entry, by key.
    fn metadata_text(&self) -> String {
        let mut meta = String::new();
        for (k, v) in &self.metadata {
            meta.push_str(k);
            meta.push('=');
            meta.push_str(v);
            meta.push('\n');
        }
        meta
    }

    /// The sections in file order, laid out with header and checksum.
    fn sections(&self, d: &Derived) -> Vec<u8> {
        let vcount = self.vertices.len();
        // 16-bit indices wherever every index fits (leaf faces since version
        // 2, the rest since version 4): indices are most of a reduced graph's
        // bytes, and halving them keeps the file within its size bound both
        // on open maps, where the leaf lists swell, and on tiny maps, where
        // the fixed header weighs most.
        let narrow_faces = self.faces.len() <= MAX_FACES_FOR_NARROW_LEAVES;
        let narrow_vertices = vcount <= MAX_VERTICES_FOR_NARROW_INDICES;
        let (faces_id, faces_bytes) = index_section(
            (section::FACES, section::FACES16),
            narrow_vertices,
            bytemuck::cast_slice(&self.faces),
        );
        let (vf_id, vf_bytes) = index_section(
            (section::VERTEX_FACES, section::VERTEX_FACES16),
            narrow_faces,
            &d.vf_targets,
        );
        let (vn_id, vn_bytes) = index_section(
            (section::VERTEX_NEIGHBOURS, section::VERTEX_NEIGHBOURS16),
            narrow_vertices,
            &d.vn_targets,
        );
        let (leaf_id, leaf_bytes) = index_section(
            (section::TREE_LEAF_FACES, section::TREE_LEAF_FACES16),
            narrow_faces,
            &d.tree.leaf_faces,
        );
        let mut sections: Vec<(u32, &[u8], u64)> = vec![
            (section::INFO, bytemuck::bytes_of(&d.info), 1),
            (
                section::VERTICES,
                bytemuck::cast_slice(&self.vertices),
                vcount as u64,
            ),
            (faces_id, &faces_bytes, self.faces.len() as u64),
            (
                section::VERTEX_FACE_OFFSETS,
                bytemuck::cast_slice(&d.vf_offsets),
                d.vf_offsets.len() as u64,
            ),
            (vf_id, &vf_bytes, d.vf_targets.len() as u64),
            (
                section::VERTEX_NEIGHBOUR_OFFSETS,
                bytemuck::cast_slice(&d.vn_offsets),
                d.vn_offsets.len() as u64,
            ),
            (vn_id, &vn_bytes, d.vn_targets.len() as u64),
            (
                section::TREE_NODES,
                bytemuck::cast_slice(&d.tree.nodes),
                d.tree.nodes.len() as u64,
            ),
            (leaf_id, &leaf_bytes, d.tree.leaf_faces.len() as u64),
            (
                section::METADATA,
                d.metadata.as_bytes(),
                d.metadata.len() as u64,
            ),
            (
                section::TREE_NODE_BOUNDS,
                bytemuck::cast_slice(&d.node_bounds),
                d.node_bounds.len() as u64,
            ),
        ];
        if !d.radii.is_empty() {
            sections.push((
                section::FACE_RADII,
                bytemuck::cast_slice(&d.radii),
                d.radii.len() as u64,
            ));
        }
        assemble(&sections)
    }
}

/// An empty box (no faces, no vertices) as the zero box at the origin.
fn zero_if_empty(b: Aabb) -> Aabb {
    if b.is_empty() {
        Aabb {
            min: [0.0; 3],
            max: [0.0; 3],
        }
    } else {
        b
    }
}

/// An index list's section: the 16-bit one of `ids` (`.1`) with its bytes when
/// `narrow` (the caller checked every index fits), else the 32-bit one (`.0`),
/// borrowed as it is.
fn index_section(ids: (u32, u32), narrow: bool, indices: &[u32]) -> (u32, Cow<'_, [u8]>) {
    if narrow {
        let short = indices.iter().flat_map(|&i| (i as u16).to_le_bytes());
        (ids.1, Cow::Owned(short.collect()))
    } else {
        (ids.0, Cow::Borrowed(bytemuck::cast_slice(indices)))
    }
}

fn align_up(x: u64) -> u64 {
    x.div_ceil(SECTION_ALIGN) * SECTION_ALIGN
}

/// Lays out header, section table and sections; fills in the checksum.
fn assemble(sections: &[(u32, &[u8], u64)]) -> Vec<u8> {
    let header_len = size_of::<Header>() as u64;
    let table_len = (sections.len() * size_of::<SectionEntry>()) as u64;
    let mut offset = align_up(header_len + table_len);
    let mut entries = Vec::with_capacity(sections.len());
    for &(id, bytes, count) in sections {
        entries.push(SectionEntry {
            id,
            elem_size: section::elem_size(id).expect("known section"),
            offset,
            count,
            byte_len: bytes.len() as u64,
        });
        offset = align_up(offset + bytes.len() as u64);
    }
    let file_len = offset;
    let header = Header {
        magic: MAGIC,
        checksum: 0,
        version: FORMAT_VERSION,
        header_len: header_len as u32,
        file_len,
        section_count: sections.len() as u32,
        section_table_offset: header_len as u32,
        reserved: [0; 6],
    };
    let mut out = vec![0u8; file_len as usize];
    out[..header_len as usize].copy_from_slice(bytemuck::bytes_of(&header));
    out[header_len as usize..(header_len + table_len) as usize]
        .copy_from_slice(bytemuck::cast_slice(&entries));
    for (e, &(_, bytes, _)) in entries.iter().zip(sections) {
        out[e.offset as usize..e.offset as usize + bytes.len()].copy_from_slice(bytes);
    }
    seal(&mut out);
    out
}

/// Recomputes and stores the checksum of a complete file image.
pub fn seal(bytes: &mut [u8]) {
    let sum = xxh64(&bytes[CHECKSUM_END..], 0);
    bytes[CHECKSUM_OFFSET..CHECKSUM_END].copy_from_slice(&sum.to_le_bytes());
}

pub(super) fn write_file_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    toolbox::write_bytes_atomic(path, bytes).map_err(|source| WriteError::Io {
        path: path.to_path_buf(),
        source,
    })
}
