//! Compact adjacency of the graph under reduction, and [`Edit`]: a cheap
//! overlay that records an operation's changes without touching the mesh.
//!
//! The thesis computes a vertex's cost by removing it, measuring and
//! restoring a backup (`SaveBackup`/`RestoreBackup`, 6.1.5). Here the removal
//! runs on an [`Edit`] that reads through to the shared [`Mesh`]: costing is
//! read-only, so many vertices can be costed in parallel, and the very same
//! code path, committed with [`Mesh::apply`], performs the removal. That is
//! what keeps the result identical for any thread count.

use smallvec::SmallVec;

use super::volume::{P3, Shape, face_shape, face_volume, shape_volume};
use crate::graph::Graph;

/// The faces of a vertex. Most vertices have at most eight, kept inline:
/// the reduction reads face lists more than anything else, and one memory
/// access instead of two (list header, then the heap) is what costing and
/// batch picking wait for.
pub(crate) type FaceList = SmallVec<[u32; 8]>;

/// The graph being reduced: positions, clearances, faces (with a tombstone
/// per face) and for each vertex the ids of its live faces, in insertion
/// order (which makes every scan deterministic).
#[derive(Debug, Clone)]
pub(crate) struct Mesh {
    pub pos: Vec<P3>,
    pub clearance: Vec<f64>,
    pub faces: Vec<[u32; 3]>,
    pub alive: Vec<bool>,
    pub vfaces: Vec<FaceList>,
    /// Model volume (4.3) of each face with the current clearances: the
    /// costing reads the volumes of unchanged faces over and over.
    pub volume: Vec<f64>,
    /// The shape of each face (see [`Shape`]).
    pub shape: Vec<Shape>,
    /// Whether the seam operations (module `seam`) may be used: the
    /// reduction's second phase, after the thesis' cases alone stopped.
    pub seam_ops: bool,
    /// How removals are costed ([`super::ReduceOptions::cost`]).
    pub cost: super::ReductionCost,
}

impl Mesh {
    /// Faces with a repeated vertex and repeated faces describe nothing the
    /// other faces do not, and would confuse the edge tests: they are dropped.
    pub fn new(graph: &Graph) -> Mesh {
        let n = graph.vertices.len();
        let mut seen = rustc_hash::FxHashSet::default();
        seen.reserve(graph.faces.len());
        let mut faces = Vec::with_capacity(graph.faces.len());
        for &f in &graph.faces {
            if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] || f.iter().any(|&v| v as usize >= n) {
                continue;
            }
            let mut key = f;
            key.sort_unstable();
            if seen.insert(key) {
                faces.push(f);
            }
        }
        let mut count = vec![0u32; n];
        for f in &faces {
            for &v in f {
                count[v as usize] += 1;
            }
        }
        let mut vfaces: Vec<FaceList> = count
            .iter()
            .map(|&c| FaceList::with_capacity(c as usize))
            .collect();
        for (i, f) in faces.iter().enumerate() {
            for &v in f {
                vfaces[v as usize].push(i as u32);
            }
        }
        let mut mesh = Mesh {
            pos: graph.vertices.clone(),
            clearance: graph.clearance.clone(),
            alive: vec![true; faces.len()],
            volume: Vec::with_capacity(faces.len()),
            shape: Vec::with_capacity(faces.len()),
            faces,
            vfaces,
            seam_ops: false,
            cost: super::ReductionCost::Volume,
        };
        mesh.shape = mesh
            .faces
            .iter()
            .map(|t| face_shape(t.map(|v| mesh.pos[v as usize])))
            .collect();
        mesh.volume = (0..mesh.faces.len())
            .map(|f| mesh.compute_volume(f as u32))
            .collect();
        mesh
    }

    fn compute_volume(&self, f: u32) -> f64 {
        let t = self.faces[f as usize];
        shape_volume(
            &self.shape[f as usize],
            t.map(|v| self.clearance[v as usize]),
        )
    }

    /// Vertices that still have a face.
    pub fn live_vertices(&self) -> usize {
        self.vfaces.iter().filter(|l| !l.is_empty()).count()
    }

    pub fn live_faces(&self) -> usize {
        self.alive.iter().filter(|&&a| a).count()
    }

    /// Commits an edit. New faces get the next ids in the order the edit
    /// created them. In debug builds condition A is checked first.
    pub fn apply(&mut self, mut ch: Changes) {
        // An edit made before other edits were applied numbered its new
        // faces from an older face count: shift them.
        let now = self.faces.len() as u32;
        if ch.base != now {
            let shift = |f: &mut u32| {
                if *f >= ch.base {
                    *f = *f - ch.base + now;
                }
            };
            ch.removed.iter_mut().for_each(shift);
            for (_, l) in &mut ch.lists {
                l.iter_mut().for_each(shift);
            }
            ch.base = now;
        }
        #[cfg(debug_assertions)]
        if let Err(e) = super::check::condition_a(self, &ch) {
            panic!("reduction broke condition A: {e}");
        }
        let base = self.faces.len() as u32;
        for (i, &f) in ch.new_faces.iter().enumerate() {
            let id = base + i as u32;
            self.faces.push(f);
            self.alive.push(!ch.removed.contains(&id));
        }
        for &f in &ch.removed {
            if f < base {
                self.alive[f as usize] = false;
            }
        }
        for (v, list) in ch.lists {
            self.vfaces[v as usize] = list;
        }
        for &(v, r) in &ch.radii {
            self.clearance[v as usize] = r;
        }
        for t in &ch.new_faces {
            self.shape.push(face_shape(t.map(|v| self.pos[v as usize])));
        }
        for i in 0..ch.new_faces.len() {
            let f = base + i as u32;
            let v = self.compute_volume(f);
            self.volume.push(v);
        }
        for &(v, _) in &ch.radii {
            for i in 0..self.vfaces[v as usize].len() {
                let f = self.vfaces[v as usize][i];
                self.volume[f as usize] = self.compute_volume(f);
            }
        }
    }

    /// The reduced graph: live faces in id order over the vertices that still
    /// have faces, renumbered in id order.
    pub fn to_graph(&self) -> Graph {
        let mut map = vec![u32::MAX; self.pos.len()];
        let mut g = Graph {
            vertices: Vec::new(),
            clearance: Vec::new(),
            faces: Vec::new(),
        };
        for (v, list) in self.vfaces.iter().enumerate() {
            if !list.is_empty() {
                map[v] = g.vertices.len() as u32;
                g.vertices.push(self.pos[v]);
                g.clearance.push(self.clearance[v]);
            }
        }
        for (f, tri) in self.faces.iter().enumerate() {
            if self.alive[f] {
                g.faces.push(tri.map(|v| map[v as usize]));
            }
        }
        g
    }
}

/// The owned outcome of an [`Edit`], ready for [`Mesh::apply`].
#[derive(Debug, Default)]
pub(crate) struct Changes {
    /// Replaced face lists of vertices.
    pub lists: SmallVec<[(u32, FaceList); 8]>,
    /// Faces created, with ids `mesh.faces.len() + index`.
    pub new_faces: SmallVec<[[u32; 3]; 8]>,
    /// Face ids removed (old ones, and new ones removed again).
    pub removed: SmallVec<[u32; 16]>,
    /// Lowered clearances.
    pub radii: SmallVec<[(u32, f64); 4]>,
    /// Operations performed, by kind (see [`Op`]).
    pub ops: [u32; Op::COUNT],
    /// `mesh.faces.len()` when the edit was made: the first new face id.
    pub base: u32,
}

impl Changes {
    /// Vertices whose faces or clearance changed, sorted: the ones whose cost
    /// must be recomputed (thesis: the neighbours of the removed vertex).
    pub fn touched(&self) -> SmallVec<[u32; 16]> {
        let mut t: SmallVec<[u32; 16]> = self
            .lists
            .iter()
            .map(|x| x.0)
            .chain(self.radii.iter().map(|x| x.0))
            .collect();
        t.sort_unstable();
        t.dedup();
        t
    }
}

/// Kinds of elementary operations, counted for the statistics.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Op {
    /// 4.5 edge swap.
    Swap = 0,
    /// 4.4 a vertex with one face.
    OneFace = 1,
    /// 4.6.2 three faces replaced by one.
    ThreeFaces = 2,
    /// 4.6.2 three faces whose replacement already exists.
    ThreeFacesExisting = 3,
    /// 4.6.1 two faces at a concave corner replaced by one.
    TwoFacesConcave = 4,
    /// A seam vertex contracted out of its seam (module `seam`).
    SeamContract = 5,
    /// A seam or border vertex collapsed into a neighbour along its edge.
    SeamCollapse = 6,
    /// A border or seam-end vertex removed fan by fan (module `border`).
    FanRemove = 7,
}

impl Op {
    pub const COUNT: usize = 8;
}

/// An operation in progress over a [`Mesh`]: reads see the edit's changes,
/// writes stay in the edit.
pub(crate) struct Edit<'m> {
    pub base: &'m Mesh,
    ch: Changes,
}

impl<'m> Edit<'m> {
    pub fn new(base: &'m Mesh) -> Edit<'m> {
        Edit {
            base,
            ch: Changes {
                base: base.faces.len() as u32,
                ..Changes::default()
            },
        }
    }

    pub fn into_changes(self) -> Changes {
        self.ch
    }

    /// The changes so far.
    pub fn changes(&self) -> &Changes {
        &self.ch
    }

    pub fn count(&mut self, op: Op) {
        self.ch.ops[op as usize] += 1;
    }

    #[inline]
    pub fn faces_of(&self, v: u32) -> &[u32] {
        match self.ch.lists.iter().find(|x| x.0 == v) {
            Some((_, l)) => l,
            None => &self.base.vfaces[v as usize],
        }
    }

    #[inline]
    pub fn face(&self, f: u32) -> [u32; 3] {
        let base = self.base.faces.len();
        if (f as usize) < base {
            self.base.faces[f as usize]
        } else {
            self.ch.new_faces[f as usize - base]
        }
    }

    #[inline]
    pub fn pos(&self, v: u32) -> P3 {
        self.base.pos[v as usize]
    }

    #[inline]
    pub fn radius(&self, v: u32) -> f64 {
        match self.ch.radii.iter().find(|x| x.0 == v) {
            Some(&(_, r)) => r,
            None => self.base.clearance[v as usize],
        }
    }

    /// The distinct vertices sharing a face with `v`, sorted.
    pub fn neighbours(&self, v: u32) -> SmallVec<[u32; 24]> {
        let mut n = SmallVec::new();
        for &f in self.faces_of(v) {
            n.extend(self.face(f).into_iter().filter(|&x| x != v));
        }
        n.sort_unstable();
        n.dedup();
        n
    }

    /// How many faces contain the edge `a`–`b`, and the first two of them.
    pub fn edge_faces(&self, a: u32, b: u32) -> (usize, [u32; 2]) {
        let mut n = 0;
        let mut first = [u32::MAX; 2];
        for &f in self.faces_of(a) {
            if self.face(f).contains(&b) {
                if n < 2 {
                    first[n] = f;
                }
                n += 1;
            }
        }
        (n, first)
    }

    pub fn has_edge(&self, a: u32, b: u32) -> bool {
        self.faces_of(a).iter().any(|&f| self.face(f).contains(&b))
    }

    pub fn has_face(&self, a: u32, b: u32, c: u32) -> bool {
        self.faces_of(a).iter().any(|&f| {
            let t = self.face(f);
            t.contains(&b) && t.contains(&c)
        })
    }

    /// The balls of a face with the edit's clearances.
    pub fn balls(&self, f: u32) -> [(P3, f64); 3] {
        self.face(f).map(|v| (self.pos(v), self.radius(v)))
    }

    /// Model volume (4.3) of a face with the edit's clearances, or with the
    /// clearances overridden by `with`.
    pub fn volume(&self, tri: [u32; 3], with: &[(u32, f64)]) -> f64 {
        face_volume(tri.map(|v| self.pos(v)), self.radii_with(tri, with))
    }

    /// The clearances of `tri` in the edit, or as overridden by `with`.
    #[inline]
    fn radii_with(&self, tri: [u32; 3], with: &[(u32, f64)]) -> [f64; 3] {
        tri.map(|v| {
            with.iter()
                .find(|x| x.0 == v)
                .map_or_else(|| self.radius(v), |x| x.1)
        })
    }

    /// [`Edit::volume`] of the existing face `f`.
    #[inline]
    pub fn face_volume_with(&self, f: u32, with: &[(u32, f64)]) -> f64 {
        let t = self.face(f);
        let r = self.radii_with(t, with);
        if (f as usize) < self.base.faces.len() {
            shape_volume(&self.base.shape[f as usize], r)
        } else {
            shape_volume(&face_shape(t.map(|v| self.pos(v))), r)
        }
    }

    /// [`Edit::volume`] of face `f`, from the mesh's cache when the edit
    /// changed none of its clearances.
    #[inline]
    pub fn face_volume(&self, f: u32) -> f64 {
        let t = self.face(f);
        if (f as usize) < self.base.faces.len()
            && !self.ch.radii.iter().any(|&(v, _)| t.contains(&v))
        {
            self.base.volume[f as usize]
        } else {
            self.face_volume_with(f, &[])
        }
    }

    /// The shape of face `f` ([`Shape`]), cached for the mesh's faces.
    #[inline]
    pub fn shape(&self, f: u32) -> Shape {
        if (f as usize) < self.base.faces.len() {
            self.base.shape[f as usize]
        } else {
            face_shape(self.face(f).map(|v| self.pos(v)))
        }
    }

    /// Exact clearance of `p` for face `f` (its volume contains `p` iff > 0).
    pub fn clearance_at(&self, f: u32, p: P3) -> f64 {
        vdgformat::triangle_clearance(self.balls(f), p)
    }

    fn list_mut(&mut self, v: u32) -> &mut FaceList {
        let i = match self.ch.lists.iter().position(|x| x.0 == v) {
            Some(i) => i,
            None => {
                let list = FaceList::from_slice(&self.base.vfaces[v as usize]);
                self.ch.lists.push((v, list));
                self.ch.lists.len() - 1
            }
        };
        &mut self.ch.lists[i].1
    }

    pub fn remove_face(&mut self, f: u32) {
        for v in self.face(f) {
            self.list_mut(v).retain(|x| *x != f);
        }
        self.ch.removed.push(f);
    }

    pub fn add_face(&mut self, tri: [u32; 3]) -> u32 {
        let id = (self.base.faces.len() + self.ch.new_faces.len()) as u32;
        self.ch.new_faces.push(tri);
        for v in tri {
            self.list_mut(v).push(id);
        }
        id
    }

    /// Lowers a clearance (never raises one: condition A).
    pub fn set_radius(&mut self, v: u32, r: f64) {
        debug_assert!(r <= self.radius(v));
        match self.ch.radii.iter_mut().find(|x| x.0 == v) {
            Some(x) => x.1 = r,
            None => self.ch.radii.push((v, r)),
        }
    }

    /// Extra cost of lowering clearances (4.5, `CalcNodeReduceDistanceError`):
    /// the volume the other faces of those vertices lose.
    pub fn lowering_cost(&self, lowered: &[(u32, f64)], exclude: &[u32]) -> f64 {
        if lowered.iter().all(|&(v, r)| r >= self.radius(v)) {
            return 0.0;
        }
        // The faces of the lowered vertices, each once, in id order.
        let mut buf = [0u32; 64];
        let mut n = 0;
        let mut more: Vec<u32> = Vec::new();
        for &(v, r) in lowered {
            if r < self.radius(v) {
                for &f in self.faces_of(v) {
                    if exclude.contains(&f) {
                        continue;
                    }
                    if n < buf.len() {
                        buf[n] = f;
                        n += 1;
                    } else {
                        more.push(f);
                    }
                }
            }
        }
        let faces: &mut [u32] = if more.is_empty() {
            &mut buf[..n]
        } else {
            more.extend_from_slice(&buf[..n]);
            &mut more
        };
        faces.sort_unstable();
        let mut prev = u32::MAX;
        faces
            .iter()
            .filter(|&&f| std::mem::replace(&mut prev, f) != f)
            .map(|&f| self.face_volume(f) - self.face_volume_with(f, lowered))
            .sum()
    }
}
