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
        let starts = self.faces[p_face as usize].map(|v| (v, (self.pos(v) - ps).norm()));
        let goals = self.faces[q_face as usize];
        self.astar(&starts, &goals, qs)
    }

    /// Shortest path between two vertices along graph edges. Panics if a
    /// vertex is out of range.
    pub fn vertex_path(&self, from: u32, to: u32) -> Option<VdgPath> {
        self.astar(&[(from, 0.0)], &[to], self.pos(to))
    }

    /// A* from `starts` (vertex, initial cost) to the virtual target behind
    /// `goals` (edge cost |P(v) − goal|). The heuristic |P(v) − goal| is
    /// consistent for both graph and target edges (triangle inequality).
    fn astar(&self, starts: &[(u32, f64)], goals: &[u32], goal: V3) -> Option<VdgPath> {
        // vertex → (best cost, predecessor, settled)
        let mut state: IdMap<(f64, u32, bool)> = IdMap::default();
        let mut heap: BinaryHeap<(Reverse<u64>, u32)> = BinaryHeap::new();
        let key = |g: f64, h: f64| Reverse((g + h).max(0.0).to_bits());
        let h = |v: u32| (self.pos(v) - goal).norm();
        for &(v, g) in starts {
            let e = state.entry(v).or_insert((f64::INFINITY, TARGET, false));
            if g < e.0 {
                *e = (g, TARGET, false);
                heap.push((key(g, h(v)), v));
            }
        }
        let mut target: (f64, u32) = (f64::INFINITY, TARGET);
        while let Some((Reverse(bits), v)) = heap.pop() {
            if v == TARGET {
                if f64::from_bits(bits) >= target.0 {
                    return Some(self.unwind(&state, target));
                }
                continue;
            }
            let (g, _, settled) = state[&v];
            if settled {
                continue;
            }
            state.get_mut(&v).expect("present").2 = true;
            if goals.contains(&v) {
                let total = g + h(v);
                if total < target.0 {
                    target = (total, v);
                    heap.push((Reverse(total.to_bits()), TARGET));
                }
            }
            let pv = self.pos(v);
            for &w in self.vertex_neighbours(v) {
                let gw = g + (self.pos(w) - pv).norm();
                let e = state.entry(w).or_insert((f64::INFINITY, TARGET, false));
                if !e.2 && gw < e.0 {
                    *e = (gw, v, false);
                    heap.push((key(gw, h(w)), w));
                }
            }
        }
        None
    }

    fn unwind(&self, state: &IdMap<(f64, u32, bool)>, target: (f64, u32)) -> VdgPath {
        let mut vertices = vec![target.1];
        let mut v = target.1;
        while let Some(&(_, pred, _)) = state.get(&v) {
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
}
