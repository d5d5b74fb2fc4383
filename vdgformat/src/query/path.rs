//! Voronoi distance and paths by A* over the vertex graph (thesis 5.1).

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::hash::{BuildHasherDefault, Hasher};

use crate::geom::V3;
use crate::read::Vdg;

/// A path through the VDG: from a start point over graph vertices to a goal.
#[derive(Clone, Debug, PartialEq)]
pub struct VdgPath {
    /// Total length: start → first vertex → … → last vertex → goal.
    pub length: f32,
    /// The vertices visited, in order (empty when start and goal share a
    /// face and the path is the straight segment).
    pub vertices: Vec<u32>,
}

/// Multiplicative hasher for u32 keys (A* state lives in a hash map so a
/// query costs O(vertices visited), not O(graph)).
#[derive(Default)]
struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn write_u32(&mut self, n: u32) {
        self.0 = u64::from(n).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

type IdMap<V> = HashMap<u32, V, BuildHasherDefault<IdHasher>>;

/// Virtual goal node behind the goal vertices.
const TARGET: u32 = u32::MAX;

impl<'a> Vdg<'a> {
    /// `VDistance(p, q)` (thesis 5.1): the length of the shortest path from
    /// `p` into the graph at a vertex of its face, along graph edges, and out
    /// at a vertex of `q`'s face to `q`; the straight distance when both
    /// points have the same face. Faces are found with [`Self::nearest_face`].
    /// `None` when the graph has no faces or the faces are not connected.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// assert_eq!(g.vdistance([0.0, 0.0, 0.0], [30.0, 40.0, 0.0]), Some(50.0));
    /// ```
    pub fn vdistance(&self, p: [f32; 3], q: [f32; 3]) -> Option<f32> {
        self.path(p, q).map(|path| path.length)
    }

    /// The path behind [`Self::vdistance`].
    pub fn path(&self, p: [f32; 3], q: [f32; 3]) -> Option<VdgPath> {
        let fs = self.nearest_face(p)?.face;
        let fg = self.nearest_face(q)?.face;
        self.path_between_faces(fs, p, fg, q)
    }

    /// [`Self::path`] with known faces for `p` and `q` (e.g. tracked ones),
    /// skipping the two tree searches. Panics if a face is out of range.
    pub fn path_between_faces(
        &self,
        p_face: u32,
        p: [f32; 3],
        q_face: u32,
        q: [f32; 3],
    ) -> Option<VdgPath> {
        let (ps, qs) = (V3::from_f32(p), V3::from_f32(q));
        if p_face == q_face {
            return Some(VdgPath {
                length: (qs - ps).norm() as f32,
                vertices: Vec::new(),
            });
        }
        let starts = self
            .faces
            .get(p_face)
            .map(|v| (v, (self.pos(v) - ps).norm()));
        let goals = self.faces.get(q_face);
        self.astar(&starts, &goals, qs)
    }

    /// [`Self::path`] for an agent of radius `radius`: the path uses only
    /// vertices whose clearance is at least `radius`, so along every edge
    /// between them (where the clearance is interpolated linearly) an agent
    /// of that size keeps `radius` from the walls. One graph serves every
    /// agent size — what navigation-mesh users otherwise bake one mesh per
    /// size for. The first and last legs (from `p` to the first vertex, from
    /// the last vertex to `q`) run inside the faces' volumes; when `p` and
    /// `q` share a face the path is the straight segment. `None` when no
    /// such path exists (e.g. a door narrower than the agent).
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v: Vec<u32> = [([0.0, 0.0], 40.0), ([100.0, 0.0], 40.0), ([0.0, 100.0], 40.0), ([100.0, 100.0], 10.0), ([200.0, 100.0], 40.0)]
    /// #     .iter().map(|&([x, y], c)| b.add_vertex([x, y, 0.0], c)).collect();
    /// # b.add_face([v[0], v[1], v[2]]); b.add_face([v[1], v[3], v[2]]); b.add_face([v[1], v[4], v[3]]);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// let (p, q) = ([10.0, 10.0, 0.0], [190.0, 98.0, 0.0]);
    /// assert!(g.path_with_clearance(p, q, 8.0).is_some());
    /// // Vertex 3 (clearance 10) is too tight for radius 16, but the edge
    /// // 1–4 still carries it.
    /// let wide = g.path_with_clearance(p, q, 16.0).unwrap();
    /// assert!(!wide.vertices.contains(&3));
    /// assert!(g.path_with_clearance(p, q, 64.0).is_none());
    /// ```
    pub fn path_with_clearance(&self, p: [f32; 3], q: [f32; 3], radius: f32) -> Option<VdgPath> {
        PathFinder::new().path_with_clearance(self, p, q, radius)
    }

    /// Shortest path between two vertices along graph edges. Panics if a
    /// vertex is out of range.
    pub fn vertex_path(&self, from: u32, to: u32) -> Option<VdgPath> {
        self.astar(&[(from, 0.0)], &[to], self.pos(to))
    }

    /// A* from `starts` (vertex, initial cost) to the virtual target behind
    /// `goals` (edge cost |P(v) − goal|). The heuristic |P(v) − goal| is
    /// consistent for both graph and target edges (triangle inequality), so
    /// a settled vertex is final.
    fn astar(&self, starts: &[(u32, f64)], goals: &[u32], goal: V3) -> Option<VdgPath> {
        let mut state = MapState(IdMap::default());
        let mut heap = BinaryHeap::new();
        self.astar_in(
            &mut state,
            &mut heap,
            starts,
            goals,
            goal,
            f32::NEG_INFINITY,
        )
    }

    pub(crate) fn astar_in<S: SearchState>(
        &self,
        state: &mut S,
        heap: &mut BinaryHeap<(Reverse<u64>, u32)>,
        starts: &[(u32, f64)],
        goals: &[u32],
        goal: V3,
        min_clearance: f32,
    ) -> Option<VdgPath> {
        heap.clear();
        let admit = |v: u32| self.vertices[v as usize].clearance >= min_clearance;
        let key = |g: f64, h: f64| Reverse((g + h).max(0.0).to_bits());
        let h = |v: u32| (self.pos(v) - goal).norm();
        for &(v, g) in starts {
            if admit(v) && g < state.get(v).0 {
                state.set(v, (g, TARGET, false));
                heap.push((key(g, h(v)), v));
            }
        }
        let mut target: (f64, u32) = (f64::INFINITY, TARGET);
        while let Some((Reverse(bits), v)) = heap.pop() {
            if v == TARGET {
                if f64::from_bits(bits) >= target.0 {
                    return Some(unwind(state, target));
                }
                continue;
            }
            let (g, pred, settled) = state.get(v);
            if settled {
                continue;
            }
            state.set(v, (g, pred, true));
            if goals.contains(&v) && admit(v) {
                let total = g + h(v);
                if total < target.0 {
                    target = (total, v);
                    heap.push((Reverse(total.to_bits()), TARGET));
                }
            }
            let pv = self.pos(v);
            for w in self.vertex_neighbours(v) {
                if !admit(w) {
                    continue;
                }
                let gw = g + (self.pos(w) - pv).norm();
                let (old, _, done) = state.get(w);
                if !done && gw < old {
                    state.set(w, (gw, v, false));
                    heap.push((key(gw, h(w)), w));
                }
            }
        }
        None
    }
}

fn unwind<S: SearchState>(state: &S, target: (f64, u32)) -> VdgPath {
    let mut vertices = vec![target.1];
    let mut v = target.1;
    loop {
        let (_, pred, _) = state.get(v);
        if pred == TARGET {
            break;
        }
        vertices.push(pred);
        v = pred;
    }
    vertices.reverse();
    VdgPath {
        length: target.0 as f32,
        vertices,
    }
}

/// Per-vertex A* state: (best cost, predecessor, settled).
pub(crate) trait SearchState {
    fn get(&self, v: u32) -> (f64, u32, bool);
    fn set(&mut self, v: u32, s: (f64, u32, bool));
}

const UNSEEN: (f64, u32, bool) = (f64::INFINITY, TARGET, false);

/// Hash-map state: O(vertices visited) per query, no set-up.
struct MapState(IdMap<(f64, u32, bool)>);

impl SearchState for MapState {
    fn get(&self, v: u32) -> (f64, u32, bool) {
        self.0.get(&v).copied().unwrap_or(UNSEEN)
    }
    fn set(&mut self, v: u32, s: (f64, u32, bool)) {
        self.0.insert(v, s);
    }
}

/// Reusable scratch for repeated path queries: flat arrays indexed by
/// vertex and stamped with a query number, so a query neither hashes nor
/// clears anything. Grows to the graph's vertex count on first use
/// (16 bytes per vertex). Faster than [`Vdg::path`] on large searches
/// (no hashing, no clearing); results are identical.
///
/// ```
/// # let mut b = vdgformat::VdgBuilder::new();
/// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
/// # b.add_face(v);
/// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
/// let g = file.graph();
/// let mut finder = vdgformat::query::PathFinder::new();
/// let path = finder.vertex_path(&g, 1, 2).unwrap();
/// assert_eq!(path.vertices, vec![1, 2]);
/// ```
#[derive(Debug, Default)]
pub struct PathFinder {
    cost: Vec<f64>,
    pred: Vec<u32>,
    stamp: Vec<u32>,
    epoch: u32,
    heap: BinaryHeap<(Reverse<u64>, u32)>,
}

struct StampState<'s> {
    cost: &'s mut [f64],
    pred: &'s mut [u32],
    stamp: &'s mut [u32],
    epoch: u32,
}

impl SearchState for StampState<'_> {
    #[inline]
    fn get(&self, v: u32) -> (f64, u32, bool) {
        let s = self.stamp[v as usize];
        if s >> 1 != self.epoch {
            return UNSEEN;
        }
        (self.cost[v as usize], self.pred[v as usize], s & 1 == 1)
    }
    #[inline]
    fn set(&mut self, v: u32, s: (f64, u32, bool)) {
        self.cost[v as usize] = s.0;
        self.pred[v as usize] = s.1;
        self.stamp[v as usize] = (self.epoch << 1) | u32::from(s.2);
    }
}

impl PathFinder {
    /// An empty finder; it sizes itself on first use.
    pub fn new() -> PathFinder {
        PathFinder::default()
    }

    fn run(
        &mut self,
        g: &Vdg<'_>,
        starts: &[(u32, f64)],
        goals: &[u32],
        goal: V3,
        min_clearance: f32,
    ) -> Option<VdgPath> {
        let n = g.vertex_count();
        if self.stamp.len() < n {
            self.cost.resize(n, f64::INFINITY);
            self.pred.resize(n, TARGET);
            self.stamp.resize(n, 0);
        }
        // Epochs live in the upper 31 bits of a stamp; on wrap-around clear.
        self.epoch = (self.epoch + 1) & (u32::MAX >> 1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        let mut state = StampState {
            cost: &mut self.cost,
            pred: &mut self.pred,
            stamp: &mut self.stamp,
            epoch: self.epoch,
        };
        g.astar_in(
            &mut state,
            &mut self.heap,
            starts,
            goals,
            goal,
            min_clearance,
        )
    }

    /// [`Vdg::path`] with reused scratch.
    pub fn path(&mut self, g: &Vdg<'_>, p: [f32; 3], q: [f32; 3]) -> Option<VdgPath> {
        let fs = g.nearest_face(p)?.face;
        let fg = g.nearest_face(q)?.face;
        self.path_between_faces(g, fs, p, fg, q)
    }

    /// [`Vdg::path_between_faces`] with reused scratch.
    pub fn path_between_faces(
        &mut self,
        g: &Vdg<'_>,
        p_face: u32,
        p: [f32; 3],
        q_face: u32,
        q: [f32; 3],
    ) -> Option<VdgPath> {
        // Every vertex admitted: the same search as for an agent of no size.
        self.path_between_faces_with_clearance(g, p_face, p, q_face, q, f32::NEG_INFINITY)
    }

    /// [`Vdg::path_with_clearance`] with reused scratch.
    pub fn path_with_clearance(
        &mut self,
        g: &Vdg<'_>,
        p: [f32; 3],
        q: [f32; 3],
        radius: f32,
    ) -> Option<VdgPath> {
        let fs = g.nearest_face(p)?.face;
        let fg = g.nearest_face(q)?.face;
        self.path_between_faces_with_clearance(g, fs, p, fg, q, radius)
    }

    /// [`Vdg::path_with_clearance`] with known faces for `p` and `q`.
    /// Panics if a face is out of range.
    pub fn path_between_faces_with_clearance(
        &mut self,
        g: &Vdg<'_>,
        p_face: u32,
        p: [f32; 3],
        q_face: u32,
        q: [f32; 3],
        radius: f32,
    ) -> Option<VdgPath> {
        let (ps, qs) = (V3::from_f32(p), V3::from_f32(q));
        if p_face == q_face {
            return Some(VdgPath {
                length: (qs - ps).norm() as f32,
                vertices: Vec::new(),
            });
        }
        if radius.is_nan() {
            return None;
        }
        let starts = g.faces.get(p_face).map(|v| (v, (g.pos(v) - ps).norm()));
        self.run(g, &starts, &g.faces.get(q_face), qs, radius)
    }

    /// [`Vdg::vertex_path`] with reused scratch.
    pub fn vertex_path(&mut self, g: &Vdg<'_>, from: u32, to: u32) -> Option<VdgPath> {
        self.run(g, &[(from, 0.0)], &[to], g.pos(to), f32::NEG_INFINITY)
    }
}
