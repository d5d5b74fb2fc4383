//! Building a `.vdg` file: adjacency, the BBox tree, layout and checksum.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

use crate::geom::{Aabb, V3};
use crate::hash::xxh64;
use crate::index::{FaceList, IndexList};
use crate::layout::{
    CHECKSUM_END, CHECKSUM_OFFSET, FORMAT_VERSION, Header, Info, MAGIC, MAX_BUILD_DEPTH,
    MAX_FACES_FOR_NARROW_LEAVES, MAX_VERTICES_FOR_NARROW_INDICES, NodeBounds, SECTION_ALIGN,
    SectionEntry, TreeNode, Vertex, section,
};

/// Default minimum leaf extent of the BBox tree (thesis 6.1.6, `-bb`).
pub const DEFAULT_LEAF_SIZE: f32 = 256.0;

/// A leaf is not split further once it lists this many faces or fewer.
const LEAF_TARGET: usize = 8;

/// Why a [`VdgBuilder`] cannot produce a file.
#[derive(Debug, Clone, PartialEq)]
pub enum BuildError {
    /// A vertex position or clearance is NaN or infinite.
    NonFiniteVertex { vertex: u32 },
    /// A vertex has a negative clearance.
    NegativeClearance { vertex: u32, clearance: f32 },
    /// A face refers to a vertex that does not exist.
    FaceIndexOutOfRange {
        face: u32,
        vertex: u32,
        vertex_count: u32,
    },
    /// A face uses the same vertex twice (thesis 3.7 forbids it).
    DegenerateFace { face: u32 },
    /// A face's own corner radius is not finite or below its vertex's clearance.
    BadCornerRadius { face: u32, corner: u8, radius: f32 },
    /// `-bb` must be finite and positive.
    BadLeafSize(f32),
    /// Metadata keys are non-empty `[A-Za-z0-9._-]` words.
    BadMetadataKey(String),
    /// Metadata values are one line (no `\n` or `\r`).
    BadMetadataValue { key: String },
    /// More vertices, faces or tree entries than 32-bit indices can address.
    TooLarge(&'static str),
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::NonFiniteVertex { vertex } => {
                write!(f, "vertex {vertex} has a non-finite position or clearance")
            }
            BuildError::NegativeClearance { vertex, clearance } => {
                write!(f, "vertex {vertex} has negative clearance {clearance}")
            }
            BuildError::FaceIndexOutOfRange {
                face,
                vertex,
                vertex_count,
            } => write!(
                f,
                "face {face} refers to vertex {vertex}, but there are only {vertex_count} vertices"
            ),
            BuildError::BadCornerRadius {
                face,
                corner,
                radius,
            } => write!(
                f,
                "corner {corner} of face {face} has radius {radius}: it must be finite and at least its vertex's clearance"
            ),
            BuildError::DegenerateFace { face } => {
                write!(f, "face {face} uses the same vertex twice")
            }
            BuildError::BadLeafSize(bb) => {
                write!(f, "tree leaf size (-bb) must be finite and > 0, got {bb}")
            }
            BuildError::BadMetadataKey(k) => write!(
                f,
                "metadata key {k:?} is not a non-empty word of [A-Za-z0-9._-]"
            ),
            BuildError::BadMetadataValue { key } => {
                write!(f, "metadata value of {key:?} contains a line break")
            }
            BuildError::TooLarge(what) => write!(f, "too many {what} for 32-bit indices"),
        }
    }
}

impl std::error::Error for BuildError {}

/// Why [`VdgBuilder::write_atomic`] failed. No partial file is left behind.
#[derive(Debug)]
pub enum WriteError {
    /// The graph itself is invalid.
    Build(BuildError),
    /// Creating, writing, syncing or renaming the file failed.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WriteError::Build(e) => write!(f, "cannot build .vdg: {e}"),
            WriteError::Io { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for WriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WriteError::Build(e) => Some(e),
            WriteError::Io { source, .. } => Some(source),
        }
    }
}

impl From<BuildError> for WriteError {
    fn from(e: BuildError) -> Self {
        WriteError::Build(e)
    }
}

/// Collects a VDG (vertices with clearance, triangular faces, metadata) and
/// serialises it as a `.vdg` file.
///
/// The writer derives everything the runtime needs — bounds, vertex→faces and
/// vertex→vertices adjacency, the BBox tree over face volumes, the checksum —
/// so the reader never computes anything but validation. Output is a pure
/// function of the builder's contents (byte-identical on every run).
///
/// ```
/// use vdgformat::{VdgBuilder, VdgFile};
///
/// let mut b = VdgBuilder::new();
/// let v0 = b.add_vertex([0.0, 0.0, 0.0], 16.0);
/// let v1 = b.add_vertex([64.0, 0.0, 0.0], 16.0);
/// let v2 = b.add_vertex([0.0, 64.0, 0.0], 24.0);
/// b.add_face([v0, v1, v2]);
/// b.set_source("demo.bsp", vdgformat::xxh64(b"map bytes", 0));
/// let bytes = b.to_bytes().unwrap();
///
/// let file = VdgFile::from_bytes(&bytes).unwrap();
/// let g = file.graph();
/// assert_eq!(g.face_count(), 1);
/// assert!(g.clearance([10.0, 10.0, 0.0]) > 15.0);
/// ```
#[derive(Debug, Clone)]
pub struct VdgBuilder {
    vertices: Vec<Vertex>,
    faces: Vec<[u32; 3]>,
    /// Per face its own corner radii, if given ([`Self::add_face_with_radii`]).
    face_radii: Vec<Option<[f32; 3]>>,
    metadata: BTreeMap<String, String>,
    source_hash: u64,
    leaf_size: f32,
}

impl Default for VdgBuilder {
    fn default() -> Self {
        Self::new()
    }
}

impl VdgBuilder {
    /// An empty graph with tool metadata preset to this crate and `-bb 256`.
    pub fn new() -> Self {
        let mut metadata = BTreeMap::new();
        metadata.insert("tool.name".to_owned(), "vdgformat".to_owned());
        metadata.insert(
            "tool.version".to_owned(),
            env!("CARGO_PKG_VERSION").to_owned(),
        );
        VdgBuilder {
            vertices: Vec::new(),
            faces: Vec::new(),
            face_radii: Vec::new(),
            metadata,
            source_hash: 0,
            leaf_size: DEFAULT_LEAF_SIZE,
        }
    }

    /// Adds a Voronoi vertex and returns its index.
    pub fn add_vertex(&mut self, pos: [f32; 3], clearance: f32) -> u32 {
        self.vertices.push(Vertex { pos, clearance });
        (self.vertices.len() - 1) as u32
    }

    /// Adds a triangular face over three vertex indices and returns its index.
    pub fn add_face(&mut self, vertices: [u32; 3]) -> u32 {
        self.faces.push(vertices);
        self.face_radii.push(None);
        (self.faces.len() - 1) as u32
    }

    /// Adds a face whose corner balls have radii of their own, each at least
    /// its vertex's clearance (checked by [`Self::to_bytes`]): a vertex's
    /// clearance must keep every face around it free, one face's corner only
    /// that face (see [`crate::Vdg::face_radii`]). A file with such faces is
    /// format version 3 with the `FACE_RADII` section.
    pub fn add_face_with_radii(&mut self, vertices: [u32; 3], radii: [f32; 3]) -> u32 {
        self.faces.push(vertices);
        self.face_radii.push(Some(radii));
        (self.faces.len() - 1) as u32
    }

    /// The corner radii of every face (their own or their vertices'
    /// clearances), or nothing when no face has its own: the `FACE_RADII`
    /// section. Call after [`Self::validate`] (indices in range).
    fn corner_radii(&self) -> Vec<[f32; 3]> {
        if self.face_radii.iter().all(Option::is_none) {
            return Vec::new();
        }
        self.faces
            .iter()
            .zip(&self.face_radii)
            .map(|(f, r)| r.unwrap_or(f.map(|v| self.vertices[v as usize].clearance)))
            .collect()
    }

    /// Number of vertices added so far.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Number of faces added so far.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Sets a metadata entry (build options, creation parameters, …).
    /// Keys are words of `[A-Za-z0-9._-]`; checked by [`Self::to_bytes`].
    pub fn set_metadata(&mut self, key: &str, value: &str) -> &mut Self {
        self.metadata.insert(key.to_owned(), value.to_owned());
        self
    }

    /// Records the source map: its file name (metadata `source.name`) and the
    /// XXH64 (seed 0, see [`crate::xxh64`]) of its bytes.
    pub fn set_source(&mut self, name: &str, hash: u64) -> &mut Self {
        self.source_hash = hash;
        self.set_metadata("source.name", name)
    }

    /// Records only the XXH64 of the source map's bytes, not its name: the output then
    /// does not depend on what the map file was called (hermetic builds).
    pub fn set_source_hash(&mut self, hash: u64) -> &mut Self {
        self.source_hash = hash;
        self
    }

    /// Records the producing tool (`tool.name`, `tool.version`).
    pub fn set_tool(&mut self, name: &str, version: &str) -> &mut Self {
        self.set_metadata("tool.name", name);
        self.set_metadata("tool.version", version)
    }

    /// Minimum extent of a BBox-tree leaf (`-bb`, default 256 units).
    pub fn set_leaf_size(&mut self, bb: f32) -> &mut Self {
        self.leaf_size = bb;
        self
    }

    fn validate(&self) -> Result<(), BuildError> {
        if self.vertices.len() >= u32::MAX as usize {
            return Err(BuildError::TooLarge("vertices"));
        }
        if self.faces.len() >= (u32::MAX / 3) as usize {
            return Err(BuildError::TooLarge("faces"));
        }
        if !(self.leaf_size.is_finite() && self.leaf_size > 0.0) {
            return Err(BuildError::BadLeafSize(self.leaf_size));
        }
        for (i, v) in self.vertices.iter().enumerate() {
            if !(v.pos.iter().all(|c| c.is_finite()) && v.clearance.is_finite()) {
                return Err(BuildError::NonFiniteVertex { vertex: i as u32 });
            }
            if v.clearance < 0.0 {
                return Err(BuildError::NegativeClearance {
                    vertex: i as u32,
                    clearance: v.clearance,
                });
            }
        }
        let n = self.vertices.len() as u32;
        for (i, f) in self.faces.iter().enumerate() {
            if let Some(&bad) = f.iter().find(|&&v| v >= n) {
                return Err(BuildError::FaceIndexOutOfRange {
                    face: i as u32,
                    vertex: bad,
                    vertex_count: n,
                });
            }
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
                return Err(BuildError::DegenerateFace { face: i as u32 });
            }
            if let Some(r) = self.face_radii[i] {
                for k in 0..3 {
                    if !(r[k].is_finite() && r[k] >= self.vertices[f[k] as usize].clearance) {
                        return Err(BuildError::BadCornerRadius {
                            face: i as u32,
                            corner: k as u8,
                            radius: r[k],
                        });
                    }
                }
            }
        }
        for (k, v) in &self.metadata {
            if !is_metadata_key(k) {
                return Err(BuildError::BadMetadataKey(k.clone()));
            }
            if v.contains(['\n', '\r']) {
                return Err(BuildError::BadMetadataValue { key: k.clone() });
            }
        }
        Ok(())
    }

    /// Serialises the graph (see `FORMAT.md`).
    pub fn to_bytes(&self) -> Result<Vec<u8>, BuildError> {
        self.validate()?;
        let vcount = self.vertices.len();
        let radii = self.corner_radii();
        let corners = |i: usize| {
            crate::layout::corner_radii(FaceList::wide(&self.faces), &self.vertices, &radii, i)
        };
        let face_boxes: Vec<Aabb> = (0..self.faces.len())
            .map(|i| self.face_box(&self.faces[i], corners(i)))
            .collect();
        let mut volume = Aabb::EMPTY;
        for b in &face_boxes {
            volume.grow(b);
        }
        if volume.is_empty() {
            volume = Aabb {
                min: [0.0; 3],
                max: [0.0; 3],
            };
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
        if vbox.is_empty() {
            vbox = Aabb {
                min: [0.0; 3],
                max: [0.0; 3],
            };
        }

        let (vf_offsets, vf_targets) = vertex_faces(vcount, &self.faces);
        let (vn_offsets, vn_targets) = vertex_neighbours(vcount, &self.faces);
        let reach: Vec<Reach> = (0..self.faces.len())
            .map(|i| self.face_reach(&self.faces[i], corners(i)))
            .collect();
        let tree = build_tree(&face_boxes, &reach, volume, self.leaf_size);
        let node_bounds = node_bounds(
            &tree.nodes,
            IndexList::wide(&tree.leaf_faces),
            FaceList::wide(&self.faces),
            &self.vertices,
            &radii,
        );
        if tree.leaf_faces.len() >= u32::MAX as usize || tree.nodes.len() >= u32::MAX as usize {
            return Err(BuildError::TooLarge("tree entries"));
        }

        let info = Info {
            vertex_count: vcount as u32,
            face_count: self.faces.len() as u32,
            tree_node_count: tree.nodes.len() as u32,
            leaf_size: self.leaf_size,
            vertex_min: vbox.min,
            max_clearance,
            vertex_max: vbox.max,
            reserved0: 0,
            volume_min: volume.min,
            reserved1: 0,
            volume_max: volume.max,
            reserved2: 0,
            source_hash: self.source_hash,
            reserved3: 0,
        };
        let mut meta = String::new();
        for (k, v) in &self.metadata {
            meta.push_str(k);
            meta.push('=');
            meta.push_str(v);
            meta.push('\n');
        }

        // 16-bit indices wherever every index fits (leaf faces since version
        // 2, the rest since version 4): indices are most of a reduced graph's
        // bytes, and half of them is the difference between ~75 and ~100
        // bytes per face on open maps, or on tiny maps between a file the
        // fixed header dominates and one it does not.
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
            &vf_targets,
        );
        let (vn_id, vn_bytes) = index_section(
            (section::VERTEX_NEIGHBOURS, section::VERTEX_NEIGHBOURS16),
            narrow_vertices,
            &vn_targets,
        );
        let (leaf_id, leaf_bytes) = index_section(
            (section::TREE_LEAF_FACES, section::TREE_LEAF_FACES16),
            narrow_faces,
            &tree.leaf_faces,
        );
        let mut sections: Vec<(u32, &[u8], u64)> = vec![
            (section::INFO, bytemuck::bytes_of(&info), 1),
            (
                section::VERTICES,
                bytemuck::cast_slice(&self.vertices),
                vcount as u64,
            ),
            (faces_id, &faces_bytes, self.faces.len() as u64),
            (
                section::VERTEX_FACE_OFFSETS,
                bytemuck::cast_slice(&vf_offsets),
                vf_offsets.len() as u64,
            ),
            (vf_id, &vf_bytes, vf_targets.len() as u64),
            (
                section::VERTEX_NEIGHBOUR_OFFSETS,
                bytemuck::cast_slice(&vn_offsets),
                vn_offsets.len() as u64,
            ),
            (vn_id, &vn_bytes, vn_targets.len() as u64),
            (
                section::TREE_NODES,
                bytemuck::cast_slice(&tree.nodes),
                tree.nodes.len() as u64,
            ),
            (leaf_id, &leaf_bytes, tree.leaf_faces.len() as u64),
            (section::METADATA, meta.as_bytes(), meta.len() as u64),
            (
                section::TREE_NODE_BOUNDS,
                bytemuck::cast_slice(&node_bounds),
                node_bounds.len() as u64,
            ),
        ];
        if !radii.is_empty() {
            sections.push((
                section::FACE_RADII,
                bytemuck::cast_slice(&radii),
                radii.len() as u64,
            ));
        }
        Ok(assemble(&sections))
    }

    /// Writes the file atomically: a temporary file in the same directory,
    /// fsync, then rename over `path` (and a best-effort directory fsync).
    /// Readers see either the old file or the complete new one, never a
    /// half-written file; on error the temporary file is removed.
    pub fn write_atomic(&self, path: impl AsRef<Path>) -> Result<(), WriteError> {
        let bytes = self.to_bytes()?;
        write_file_atomic(path.as_ref(), &bytes)
    }

    /// Bounds of the three balls: the box of the face's volume (the volume
    /// is the convex hull of the vertex balls). Rounded outwards to f32 so
    /// every point of the volume is inside the stored box.
    /// The triangle's box and its largest vertex clearance (see [`Reach`]).
    fn face_reach(&self, f: &[u32; 3], radii: [f32; 3]) -> Reach {
        let mut tri = Aabb::EMPTY;
        let mut r_max = 0.0f32;
        for (&vi, &r) in f.iter().zip(&radii) {
            let v = self.vertices[vi as usize];
            tri.grow(&Aabb {
                min: v.pos,
                max: v.pos,
            });
            r_max = r_max.max(r);
        }
        let balls = [0, 1, 2].map(|k| {
            let v = self.vertices[f[k] as usize];
            (V3::from_f32(v.pos), f64::from(radii[k]))
        });
        Reach { tri, r_max, balls }
    }

    fn face_box(&self, f: &[u32; 3], radii: [f32; 3]) -> Aabb {
        let mut b = Aabb::EMPTY;
        for (&vi, &r) in f.iter().zip(&radii) {
            let v = self.vertices[vi as usize];
            for i in 0..3 {
                let c = f64::from(v.pos[i]);
                let r = f64::from(r);
                b.min[i] = b.min[i].min(f32_down(c - r));
                b.max[i] = b.max[i].max(f32_up(c + r));
            }
        }
        b
    }
}

/// [`NodeBounds`] of every tree node. Nodes are in preorder, so a reverse
/// sweep sees children before parents. Shared by the writer and by the
/// reader, which recomputes them to validate the stored ones.
pub(crate) fn node_bounds(
    nodes: &[TreeNode],
    leaf_faces: IndexList<'_>,
    faces: FaceList<'_>,
    vertices: &[Vertex],
    face_radii: &[[f32; 3]],
) -> Vec<NodeBounds> {
    let empty = NodeBounds {
        tri_min: [0.0; 3],
        r_max: -1.0,
        tri_max: [0.0; 3],
        reserved: 0,
    };
    let mut out = vec![empty; nodes.len()];
    for i in (0..nodes.len()).rev() {
        let node = nodes[i];
        let mut acc = (Aabb::EMPTY, -1.0f32);
        let mut add = |min: [f32; 3], max: [f32; 3], r: f32| {
            if r >= 0.0 {
                acc.0.grow(&Aabb { min, max });
                acc.1 = acc.1.max(r);
            }
        };
        if node.kind == TreeNode::LEAF {
            for f in leaf_faces.range(node.a, node.b).iter() {
                let radii = crate::layout::corner_radii(faces, vertices, face_radii, f as usize);
                for (v, r) in faces.get(f).into_iter().zip(radii) {
                    let v = vertices[v as usize];
                    add(v.pos, v.pos, r);
                }
            }
        } else {
            for c in [node.a, node.b] {
                let b = out[c as usize];
                add(b.tri_min, b.tri_max, b.r_max);
            }
        }
        if acc.1 >= 0.0 {
            out[i] = NodeBounds {
                tri_min: acc.0.min,
                r_max: acc.1,
                tri_max: acc.0.max,
                reserved: 0,
            };
        }
    }
    out
}

fn is_metadata_key(k: &str) -> bool {
    !k.is_empty()
        && k.bytes()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, b'.' | b'_' | b'-'))
}

/// Largest f32 ≤ x.
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x {
        step_f32(f, false)
    } else {
        f
    }
}

/// Smallest f32 ≥ x.
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x {
        step_f32(f, true)
    } else {
        f
    }
}

/// The neighbouring f32 towards +∞ (`up`) or −∞; for finite non-NaN input.
fn step_f32(f: f32, up: bool) -> f32 {
    if f == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = f.to_bits();
    let away_from_zero = (f > 0.0) == up;
    f32::from_bits(if away_from_zero { bits + 1 } else { bits - 1 })
}

/// CSR vertex → faces, faces ascending per vertex.
fn vertex_faces(vcount: usize, faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; vcount + 1];
    for f in faces {
        for &v in f {
            offsets[v as usize + 1] += 1;
        }
    }
    for i in 0..vcount {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut targets = vec![0u32; faces.len() * 3];
    for (fi, f) in faces.iter().enumerate() {
        for &v in f {
            targets[fill[v as usize] as usize] = fi as u32;
            fill[v as usize] += 1;
        }
    }
    (offsets, targets)
}

/// CSR vertex → adjacent vertices (sharing a face), ascending and unique.
fn vertex_neighbours(vcount: usize, faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let (fo, ft) = vertex_faces(vcount, faces);
    let mut offsets = Vec::with_capacity(vcount + 1);
    let mut targets = Vec::with_capacity(faces.len() * 3);
    offsets.push(0u32);
    let mut row = Vec::new();
    for v in 0..vcount {
        row.clear();
        for &f in &ft[fo[v] as usize..fo[v + 1] as usize] {
            row.extend(
                faces[f as usize]
                    .iter()
                    .copied()
                    .filter(|&w| w as usize != v),
            );
        }
        row.sort_unstable();
        row.dedup();
        targets.extend_from_slice(&row);
        offsets.push(targets.len() as u32);
    }
    (offsets, targets)
}

pub(crate) struct Tree {
    pub nodes: Vec<TreeNode>,
    pub leaf_faces: Vec<u32>,
}

/// The thesis' BBox tree (6.1.6): the root cell is the box of Volume(VDG);
/// a cell is halved across its longest axis while the halves stay at least
/// `leaf_size` wide; a leaf lists every face whose volume box meets its cell.
/// We also stop when a cell holds few faces or a split separates nothing.
/// Nodes are stored in preorder (children after their parent).
pub(crate) fn build_tree(boxes: &[Aabb], reach: &[Reach], root: Aabb, leaf_size: f32) -> Tree {
    let mut tree = Tree {
        nodes: Vec::new(),
        leaf_faces: Vec::new(),
    };
    let all: Vec<u32> = (0..boxes.len() as u32).collect();
    let faces = Faces { boxes, reach };
    build_node(&mut tree, &faces, root, all, leaf_size, 0);
    tree
}

/// Where a face's volume can be: the union of the balls `B(q, r(q))` over the
/// triangle with the vertex clearances interpolated (the convex hull of the
/// three vertex balls). A cell holds a point of the volume exactly when
/// `min_{q ∈ triangle} dist(q, cell) − r(q) < 0`. The box tests of the writer
/// (the volume's box, then the triangle's box against `r_max`) keep a face in
/// every cell that meets its box; on open maps, where clearances reach hundreds
/// of units and big faces lie slanted, most of those cells miss the volume
/// itself. [`Reach::may_meet`] drops them with a certified lower bound on that
/// minimum, so a leaf lists only faces whose volume can meet its cell.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reach {
    pub tri: Aabb,
    pub r_max: f32,
    /// The three vertices and their clearances, in f64.
    pub balls: [(V3, f64); 3],
}

/// Frank–Wolfe rounds [`Reach::may_meet`] spends before it keeps a face (conservatively).
const MEET_ROUNDS: usize = 24;

impl Reach {
    /// Whether the volume may meet `cell` (conservative: `true` when unsure).
    fn may_meet(&self, cell: &Aabb) -> bool {
        let mut d2 = 0.0f64;
        for i in 0..3 {
            let gap = (f64::from(cell.min[i]) - f64::from(self.tri.max[i]))
                .max(f64::from(self.tri.min[i]) - f64::from(cell.max[i]))
                .max(0.0);
            d2 += gap * gap;
        }
        let r = f64::from(self.r_max);
        // Slack for the f32 data and the rounding of the queries' evaluations.
        let slack = 1e-3 + 1e-6 * r;
        let r = r + slack;
        if d2 >= r * r {
            return false;
        }
        // Most faces that meet a cell have a corner ball in it: decided without a search.
        if self
            .balls
            .iter()
            .any(|&(v, r)| cell.distance2(v) < (r + slack) * (r + slack))
        {
            return true;
        }
        self.may_meet_exactly(cell, slack)
    }

    /// Minimises `f(λ) = dist(q(λ), cell) − r(λ)` over the triangle's barycentric
    /// coordinates by Frank–Wolfe. `f` is convex (a distance to a convex set minus
    /// a linear function), so at any `λ` the linearisation's minimum over the
    /// triangle's corners bounds `min f` from below (the duality gap): once that
    /// bound exceeds `slack`, no point of the volume lies in the cell. When a
    /// point with `f ≤ slack` turns up, or the rounds run out, the face is kept.
    fn may_meet_exactly(&self, cell: &Aabb, slack: f64) -> bool {
        let lo = V3(
            f64::from(cell.min[0]),
            f64::from(cell.min[1]),
            f64::from(cell.min[2]),
        );
        let hi = V3(
            f64::from(cell.max[0]),
            f64::from(cell.max[1]),
            f64::from(cell.max[2]),
        );
        let f_at = |lam: [f64; 3]| -> (f64, V3) {
            let q = self.balls[0].0 * lam[0] + self.balls[1].0 * lam[1] + self.balls[2].0 * lam[2];
            let r = self.balls[0].1 * lam[0] + self.balls[1].1 * lam[1] + self.balls[2].1 * lam[2];
            let clamp = V3(
                q.0.clamp(lo.0, hi.0),
                q.1.clamp(lo.1, hi.1),
                q.2.clamp(lo.2, hi.2),
            );
            let d = q - clamp;
            let n = d.norm();
            let grad = if n > 0.0 {
                d * (1.0 / n)
            } else {
                V3(0.0, 0.0, 0.0)
            };
            (n - r, grad)
        };
        // Start at the best corner.
        let mut lam = [0.0; 3];
        let mut best = (f64::INFINITY, 0);
        for (i, _) in self.balls.iter().enumerate() {
            let mut e = [0.0; 3];
            e[i] = 1.0;
            let v = f_at(e).0;
            if v < best.0 {
                best = (v, i);
            }
        }
        lam[best.1] = 1.0;
        for _ in 0..MEET_ROUNDS {
            let (f, g) = f_at(lam);
            if f <= slack {
                return true;
            }
            // Gradient in λ: ∂f/∂λ_i = g·v_i − r_i.
            let h = self.balls.map(|(v, r)| g.dot(v) - r);
            let (s, hmin) = (0..3).fold(
                (0, f64::INFINITY),
                |a, i| if h[i] < a.1 { (i, h[i]) } else { a },
            );
            let at = lam[0] * h[0] + lam[1] * h[1] + lam[2] * h[2];
            let lower = f + hmin - at;
            if lower > slack {
                return false;
            }
            // Golden-section line search towards corner s (f is convex along the segment).
            let towards = |t: f64| {
                let mut l = lam.map(|x| x * (1.0 - t));
                l[s] += t;
                l
            };
            let (mut a, mut b) = (0.0f64, 1.0f64);
            const PHI: f64 = 0.618_033_988_749_894_9;
            let mut c = b - PHI * (b - a);
            let mut d = a + PHI * (b - a);
            let (mut fc, mut fd) = (f_at(towards(c)).0, f_at(towards(d)).0);
            for _ in 0..16 {
                if fc < fd {
                    b = d;
                    d = c;
                    fd = fc;
                    c = b - PHI * (b - a);
                    fc = f_at(towards(c)).0;
                } else {
                    a = c;
                    c = d;
                    fc = fd;
                    d = a + PHI * (b - a);
                    fd = f_at(towards(d)).0;
                }
            }
            lam = towards(0.5 * (a + b));
        }
        true
    }
}

/// The per-face data the tree is built from.
struct Faces<'a> {
    /// The volume boxes (see [`VdgBuilder::face_box`]).
    boxes: &'a [Aabb],
    reach: &'a [Reach],
}

fn build_node(
    tree: &mut Tree,
    all: &Faces<'_>,
    cell: Aabb,
    faces: Vec<u32>,
    bb: f32,
    depth: usize,
) {
    let boxes = all.boxes;
    let me = tree.nodes.len();
    tree.nodes.push(TreeNode {
        kind: TreeNode::LEAF,
        split: 0.0,
        a: 0,
        b: 0,
    });
    let extent = |i: usize| cell.max[i] - cell.min[i];
    let axis = (0..3)
        .max_by(|&i, &j| extent(i).total_cmp(&extent(j)).then(j.cmp(&i)))
        .unwrap_or(0);
    let split = cell.min[axis] + 0.5 * extent(axis);
    let splittable = faces.len() > LEAF_TARGET
        && depth < MAX_BUILD_DEPTH
        && extent(axis) >= 2.0 * bb
        && split > cell.min[axis]
        && split < cell.max[axis];
    if splittable {
        let mut lcell = cell;
        lcell.max[axis] = split;
        let mut rcell = cell;
        rcell.min[axis] = split;
        let left: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| {
                boxes[f as usize].min[axis] <= split && all.reach[f as usize].may_meet(&lcell)
            })
            .collect();
        let right: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| {
                boxes[f as usize].max[axis] >= split && all.reach[f as usize].may_meet(&rcell)
            })
            .collect();
        if left.len() < faces.len() || right.len() < faces.len() {
            drop(faces);
            let l = tree.nodes.len() as u32;
            build_node(tree, all, lcell, left, bb, depth + 1);
            let r = tree.nodes.len() as u32;
            build_node(tree, all, rcell, right, bb, depth + 1);
            tree.nodes[me] = TreeNode {
                kind: axis as u32,
                split,
                a: l,
                b: r,
            };
            return;
        }
    }
    tree.nodes[me] = TreeNode {
        kind: TreeNode::LEAF,
        split: 0.0,
        a: tree.leaf_faces.len() as u32,
        b: faces.len() as u32,
    };
    tree.leaf_faces.extend_from_slice(&faces);
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

fn write_file_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    toolbox::write_bytes_atomic(path, bytes).map_err(|source| WriteError::Io {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outward_rounding() {
        for x in [0.1f64, -0.1, 1e-30, -1e-30, 12345.678, 0.0, -7.25] {
            assert!(f64::from(f32_down(x)) <= x);
            assert!(f64::from(f32_up(x)) >= x);
            assert!(f64::from(f32_up(x)) - f64::from(f32_down(x)) <= x.abs() * 1e-6 + 1e-40);
        }
    }

    #[test]
    fn csr_adjacency() {
        let faces = [[0, 1, 2], [1, 2, 3]];
        let (o, t) = vertex_faces(5, &faces);
        assert_eq!(o, vec![0, 1, 3, 5, 6, 6]);
        assert_eq!(t, vec![0, 0, 1, 0, 1, 1]);
        let (o, t) = vertex_neighbours(5, &faces);
        assert_eq!(o, vec![0, 2, 5, 8, 10, 10]);
        assert_eq!(t, vec![1, 2, 0, 2, 3, 0, 1, 3, 1, 2]);
    }

    /// `min_{q ∈ triangle} dist(q, cell) − r(q)` on a fine barycentric grid: an
    /// upper bound on the true minimum, within grid spacing of it.
    fn sampled_gap(reach: &Reach, cell: &Aabb) -> f64 {
        let n = 60;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let l = [
                    i as f64 / n as f64,
                    j as f64 / n as f64,
                    (n - i - j) as f64 / n as f64,
                ];
                let q = reach.balls[0].0 * l[0] + reach.balls[1].0 * l[1] + reach.balls[2].0 * l[2];
                let r = reach.balls[0].1 * l[0] + reach.balls[1].1 * l[1] + reach.balls[2].1 * l[2];
                best = best.min(cell.distance(q) - r);
            }
        }
        best
    }

    #[test]
    fn a_cell_is_dropped_only_when_the_volume_misses_it() {
        let mut rng = toolbox::SplitMix64::new(7);
        let (mut dropped, mut kept_far) = (0, 0);
        for _ in 0..4000 {
            let mut b = VdgBuilder::new();
            let vs: Vec<u32> = (0..3)
                .map(|_| {
                    let p = [0; 3].map(|_| rng.range(-300.0, 300.0) as f32);
                    b.add_vertex(p, rng.range(0.0, 200.0) as f32)
                })
                .collect();
            let f = [vs[0], vs[1], vs[2]];
            let reach = b.face_reach(&f, f.map(|v| b.vertices[v as usize].clearance));
            let lo = [0; 3].map(|_| rng.range(-500.0, 400.0) as f32);
            let size = [0; 3].map(|_| rng.range(10.0, 300.0) as f32);
            let cell = Aabb {
                min: lo,
                max: [0, 1, 2].map(|i| lo[i] + size[i]),
            };
            let gap = sampled_gap(&reach, &cell);
            if !reach.may_meet(&cell) {
                dropped += 1;
                assert!(gap > 0.0, "dropped a cell the volume meets (gap {gap})");
            } else if gap > 10.0 {
                kept_far += 1;
            }
        }
        // The test is tight: cells missed by more than 10 units are nearly always dropped.
        assert!(dropped > 500, "{dropped}");
        assert!(
            kept_far * 50 < dropped,
            "kept {kept_far} far cells, dropped {dropped}"
        );
    }

    #[test]
    fn tree_leaves_respect_leaf_size() {
        // 1000 tiny boxes spread over [0, 4096]: cells never shrink below bb.
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| {
                let x = (i as f32 * 37.0) % 4096.0;
                let y = (i as f32 * 91.0) % 4096.0;
                Aabb {
                    min: [x, y, 0.0],
                    max: [x + 1.0, y + 1.0, 1.0],
                }
            })
            .collect();
        let root = Aabb {
            min: [0.0; 3],
            max: [4097.0, 4097.0, 1.0],
        };
        // Point triangles at the box centres with radius 0.5: their volumes fill the boxes.
        let reach: Vec<Reach> = boxes
            .iter()
            .map(|b| {
                let c = [0, 1, 2].map(|i| 0.5 * (b.min[i] + b.max[i]));
                Reach {
                    tri: Aabb { min: c, max: c },
                    r_max: 0.5,
                    balls: [(V3::from_f32(c), 0.5); 3],
                }
            })
            .collect();
        let tree = build_tree(&boxes, &reach, root, 256.0);
        let mut stack = vec![(0usize, root)];
        let mut seen = vec![false; boxes.len()];
        while let Some((n, cell)) = stack.pop() {
            let node = tree.nodes[n];
            if node.kind == TreeNode::LEAF {
                for i in 0..3 {
                    assert!(cell.max[i] - cell.min[i] >= 256.0 || i == 2);
                }
                for &f in &tree.leaf_faces[node.a as usize..(node.a + node.b) as usize] {
                    seen[f as usize] = true;
                }
            } else {
                let ax = node.kind as usize;
                let (mut l, mut r) = (cell, cell);
                l.max[ax] = node.split;
                r.min[ax] = node.split;
                stack.push((node.a as usize, l));
                stack.push((node.b as usize, r));
            }
        }
        assert!(seen.iter().all(|&s| s));
        assert!(tree.nodes.len() > 1);
    }
}
