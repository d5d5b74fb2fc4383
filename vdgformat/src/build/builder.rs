//! The builder API: what a caller adds (vertices, faces, metadata, the
//! source and the tree's leaf size), its validation, and the entry points
//! that serialise it.

use std::collections::BTreeMap;
use std::path::Path;

use super::error::{BuildError, WriteError};
use super::write::write_file_atomic;
use crate::layout::{Vertex, is_metadata_key};

/// Default minimum leaf extent of the BBox tree (thesis 6.1.6, `-bb`).
pub const DEFAULT_LEAF_SIZE: f32 = 256.0;

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
    pub(super) vertices: Vec<Vertex>,
    pub(super) faces: Vec<[u32; 3]>,
    /// Per face its own corner radii, if given ([`Self::add_face_with_radii`]).
    pub(super) face_radii: Vec<Option<[f32; 3]>>,
    pub(super) metadata: BTreeMap<String, String>,
    pub(super) source_hash: u64,
    pub(super) leaf_size: f32,
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
    pub(super) fn corner_radii(&self) -> Vec<[f32; 3]> {
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
        self.serialise()
    }

    /// fsync, then rename over `path` (and a best-effort directory fsync).
    /// Readers see either the old file or the complete new one, never a
    /// half-written file; on error the temporary file is removed.
    pub fn write_atomic(&self, path: impl AsRef<Path>) -> Result<(), WriteError> {
        let bytes = self.to_bytes()?;
        write_file_atomic(path.as_ref(), &bytes)
    }
}
