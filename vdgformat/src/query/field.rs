//! Voronoi distances from many points to one source: a lazily grown,
//! bounded single-source distance field (thesis 5.1, used by the camera).
//!
//! The thesis runs one A* per candidate and frame for `VDistance(c, t)`; all
//! of those searches share the target `t`. Here one Dijkstra runs *from the
//! target*, and only as far as the questions asked need: a vertex's distance
//! is final once it is settled, so asking for a vertex settles vertices in
//! increasing distance until that one is reached. Everything near the camera
//! is then O(1) per query. A settle budget bounds the work per
//! [`DistanceField::reset`]; beyond it distances are lower bounds.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::geom::V3;
use crate::read::Vdg;

/// Default number of vertices one field may settle (see
/// [`DistanceField::set_budget`]).
pub const DEFAULT_SETTLE_BUDGET: u32 = 1 << 16;

/// Voronoi distances `VDistance(·, source)` from many points to one source
/// point, grown on demand from the source outwards.
///
/// All scratch memory is sized once for a graph ([`DistanceField::reserve`],
/// also done by the first [`DistanceField::reset`]); after that no call
/// allocates, which is what a per-frame camera needs.
///
/// ```
/// # let mut b = vdgformat::VdgBuilder::new();
/// # let v: Vec<u32> = [[0.0, 0.0], [100.0, 0.0], [0.0, 100.0], [100.0, 100.0]]
/// #     .iter().map(|&[x, y]| b.add_vertex([x, y, 0.0], 10.0)).collect();
/// # b.add_face([v[0], v[1], v[2]]);
/// # b.add_face([v[1], v[3], v[2]]);
/// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
/// let g = file.graph();
/// let mut field = vdgformat::query::DistanceField::new();
/// // Source in face 0 at its corner (0, 0); ask from face 1 near (100, 100).
/// field.reset(&g, 0, [0.0, 0.0, 0.0]);
/// let d = field.vdistance(&g, 1, [100.0, 100.0, 0.0]);
/// // Into the graph at vertex 0, along an edge of 100 and out over 100 more.
/// assert!((d - 200.0).abs() < 1e-3);
/// // The same as the A* of `Vdg::path_between_faces`.
/// let a = g.path_between_faces(1, [100.0, 100.0, 0.0], 0, [0.0, 0.0, 0.0]).unwrap();
/// assert!((a.length - d).abs() < 1e-3);
/// ```
#[derive(Debug, Clone)]
pub struct DistanceField {
    dist: Vec<f32>,
    /// `epoch << 1 | settled` per vertex; other epochs mean "unseen".
    stamp: Vec<u32>,
    epoch: u32,
    heap: BinaryHeap<Reverse<u64>>,
    source: V3,
    source_face: u32,
    /// Every vertex closer than this is settled.
    frontier: f32,
    settled: u32,
    budget: u32,
    active: bool,
}

impl Default for DistanceField {
    fn default() -> Self {
        DistanceField::new()
    }
}

impl DistanceField {
    /// An empty field; it sizes itself for a graph on first use.
    pub fn new() -> DistanceField {
        DistanceField {
            dist: Vec::new(),
            stamp: Vec::new(),
            epoch: 0,
            heap: BinaryHeap::new(),
            source: V3(0.0, 0.0, 0.0),
            source_face: u32::MAX,
            frontier: 0.0,
            settled: 0,
            budget: DEFAULT_SETTLE_BUDGET,
            active: false,
        }
    }

    /// Caps how many vertices one field may settle (default
    /// [`DEFAULT_SETTLE_BUDGET`]): the worst case of a query is then bounded
    /// whatever the graph's size. Past the budget, [`Self::vertex_distance`]
    /// returns a lower bound (the larger of the settled radius and the
    /// straight distance).
    pub fn set_budget(&mut self, budget: u32) {
        self.budget = budget.max(1);
    }

    /// Sizes the scratch memory for `g` (8 bytes per vertex plus 8 per
    /// directed edge, the most the heap can ever hold), so that later calls
    /// never allocate.
    pub fn reserve(&mut self, g: &Vdg<'_>) {
        let n = g.vertex_count();
        if self.dist.len() < n {
            self.dist.resize(n, f32::INFINITY);
            self.stamp.resize(n, 0);
        }
        let edges = g.vn.len() + 4;
        if self.heap.capacity() < edges {
            self.heap.reserve(edges - self.heap.len());
        }
    }

    /// Starts a new field from `source`, which lies in (or is attached to)
    /// face `face`: the graph is entered at the face's three vertices, as in
    /// `VDistance`. Panics if `face` is out of range.
    pub fn reset(&mut self, g: &Vdg<'_>, face: u32, source: [f32; 3]) {
        self.reserve(g);
        self.epoch = (self.epoch + 1) & (u32::MAX >> 1);
        if self.epoch == 0 {
            self.stamp.fill(0);
            self.epoch = 1;
        }
        self.heap.clear();
        self.source = V3::from_f32(source);
        self.source_face = face;
        self.frontier = 0.0;
        self.settled = 0;
        self.active = true;
        for v in g.faces[face as usize] {
            let d = (g.pos(v) - self.source).norm() as f32;
            self.relax(v, d);
        }
    }

    /// The face the field was started from (`None` before the first reset).
    pub fn source_face(&self) -> Option<u32> {
        self.active.then_some(self.source_face)
    }

    /// The radius within which every vertex is settled so far.
    pub fn frontier(&self) -> f32 {
        self.frontier
    }

    /// Whether the settle budget ran out (distances beyond the frontier are
    /// then lower bounds).
    pub fn exhausted(&self) -> bool {
        self.settled >= self.budget
    }

    #[inline]
    fn seen(&self, v: u32) -> bool {
        self.stamp[v as usize] >> 1 == self.epoch
    }

    #[inline]
    fn is_settled(&self, v: u32) -> bool {
        self.stamp[v as usize] == (self.epoch << 1 | 1)
    }

    #[inline]
    fn relax(&mut self, v: u32, d: f32) {
        let i = v as usize;
        if !self.seen(v) || d < self.dist[i] {
            self.dist[i] = d;
            self.stamp[i] = self.epoch << 1;
            // Non-negative f32 bits order like the values.
            self.heap
                .push(Reverse(u64::from(d.to_bits()) << 32 | u64::from(v)));
        }
    }

    /// Settles vertices until `v` is settled, the heap is empty or the
    /// budget is spent.
    fn grow_until(&mut self, g: &Vdg<'_>, v: u32) {
        while !self.is_settled(v) && self.settled < self.budget {
            let Some(Reverse(key)) = self.heap.pop() else {
                return;
            };
            let (d, u) = (f32::from_bits((key >> 32) as u32), key as u32);
            if self.is_settled(u) || d > self.dist[u as usize] {
                continue;
            }
            self.stamp[u as usize] |= 1;
            self.settled += 1;
            self.frontier = d;
            let pu = g.pos(u);
            for &w in g.vertex_neighbours(u) {
                if !self.is_settled(w) {
                    let dw = d + (g.pos(w) - pu).norm() as f32;
                    self.relax(w, dw);
                }
            }
        }
    }

    /// The Voronoi distance of vertex `v` from the source: exact when
    /// settled within the budget, `INFINITY` when `v` cannot be reached,
    /// otherwise a lower bound. Panics if `v` is out of range or the field
    /// was never reset.
    pub fn vertex_distance(&mut self, g: &Vdg<'_>, v: u32) -> f32 {
        assert!(self.active, "DistanceField::vertex_distance before reset");
        self.grow_until(g, v);
        if self.is_settled(v) {
            return self.dist[v as usize];
        }
        if self.heap.is_empty() && !self.exhausted() {
            return f32::INFINITY;
        }
        self.frontier.max((g.pos(v) - self.source).norm() as f32)
    }

    /// `VDistance(p, source)` for a point `p` in face `face` (thesis 5.1):
    /// the straight distance when `face` is the source's face, otherwise
    /// the best of `|p − P(v)| + D(v)` over the face's three vertices.
    /// Panics if `face` is out of range or the field was never reset.
    pub fn vdistance(&mut self, g: &Vdg<'_>, face: u32, p: [f32; 3]) -> f32 {
        let q = V3::from_f32(p);
        if face == self.source_face {
            return (q - self.source).norm() as f32;
        }
        let mut best = f32::INFINITY;
        for v in g.faces[face as usize] {
            let d = self.vertex_distance(g, v) + (g.pos(v) - q).norm() as f32;
            best = best.min(d);
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VdgBuilder;

    /// A zig-zag strip of `n` triangles along x.
    fn strip(n: usize) -> Vec<u8> {
        let mut b = VdgBuilder::new();
        let mut ids = Vec::new();
        for i in 0..=n / 2 + 1 {
            ids.push(b.add_vertex([i as f32 * 50.0, 0.0, 0.0], 8.0));
            ids.push(b.add_vertex([i as f32 * 50.0 + 25.0, 40.0, 0.0], 8.0));
        }
        for i in 0..n {
            b.add_face([ids[i], ids[i + 1], ids[i + 2]]);
        }
        b.to_bytes().unwrap()
    }

    #[test]
    fn agrees_with_astar_everywhere() {
        let bytes = strip(40);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut field = DistanceField::new();
        let src = [12.0, 10.0, 1.0];
        field.reset(&g, 0, src);
        for f in 0..g.face_count() as u32 {
            let [a, b, c] = g.faces()[f as usize].map(|v| g.vertices()[v as usize].pos);
            let p = [0, 1, 2].map(|i| (a[i] + b[i] + c[i]) / 3.0);
            let want = g.path_between_faces(f, p, 0, src).unwrap().length;
            let got = field.vdistance(&g, f, p);
            assert!(
                (want - got).abs() < 1e-2,
                "face {f}: A* {want}, field {got}"
            );
        }
    }

    #[test]
    fn budget_gives_lower_bounds_and_no_allocation_growth() {
        let bytes = strip(200);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut field = DistanceField::new();
        field.set_budget(10);
        field.reset(&g, 0, [10.0, 5.0, 0.0]);
        let cap = field.heap.capacity();
        let far = g.faces()[g.face_count() - 1][2];
        let exact = g.vertex_path(0, far).unwrap().length;
        let d = field.vertex_distance(&g, far);
        assert!(field.exhausted());
        assert!(d <= exact + 1e-3 && d > 0.0, "{d} vs {exact}");
        assert_eq!(field.heap.capacity(), cap);
    }
}
