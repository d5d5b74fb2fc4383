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

/// The share of a distance's lower bound that [`DistanceField::vdistance`]
/// trusts: the distances are f32 sums of up to thousands of edges, which
/// may come out below the exact bound by their rounding (a few millionths
/// each), so a vertex is only passed over when it loses by more.
const LOWER_BOUND_SHARE: f32 = 0.999;

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
    /// Where the questions will come from, and how far around it: the
    /// search is steered there (A* with a consistent heuristic).
    goal: Option<(V3, f64)>,
    /// Vertices with less clearance are not entered (the source face's own
    /// vertices excepted): distances for an agent of this radius.
    min_clearance: f32,
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
            goal: None,
            min_clearance: 0.0,
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

    /// Distances for an agent of radius `r`: ways through vertices of
    /// clearance below `r` are not taken (the source's face is always
    /// entered; an agent standing there is where it stands). The default
    /// 0 gives the thesis' Voronoi distance. A camera asks with its
    /// near-plane margin: a way through a gap it cannot pass is no way to
    /// its target. Takes effect at the next reset.
    pub fn set_min_clearance(&mut self, r: f32) {
        self.min_clearance = if r.is_finite() { r.max(0.0) } else { 0.0 };
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
        self.start(g, face, source, None);
    }

    /// [`Self::reset`] for questions that will come from within about
    /// `radius` of `near` (e.g. a camera's candidates): the search grows
    /// towards there first (A* with the heuristic
    /// `max(0, |P(v) − near| − radius)`, which is consistent, so every
    /// settled distance is still exact and questions from anywhere else are
    /// still answered exactly, only with more work).
    pub fn reset_towards(
        &mut self,
        g: &Vdg<'_>,
        face: u32,
        source: [f32; 3],
        near: [f32; 3],
        radius: f32,
    ) {
        let goal = (V3::from_f32(near), f64::from(radius.max(0.0)));
        self.start(g, face, source, Some(goal));
    }

    fn start(&mut self, g: &Vdg<'_>, face: u32, source: [f32; 3], goal: Option<(V3, f64)>) {
        self.goal = goal.filter(|(p, r)| p.norm().is_finite() && r.is_finite());
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
        for v in g.faces.get(face) {
            let d = (g.pos(v) - self.source).norm() as f32;
            self.relax(g, v, d);
        }
    }

    /// The face the field was started from (`None` before the first reset).
    pub fn source_face(&self) -> Option<u32> {
        self.active.then_some(self.source_face)
    }

    /// The last key settled: without a goal, the radius within which every
    /// vertex is settled so far.
    pub fn frontier(&self) -> f32 {
        self.frontier
    }

    /// How many vertices this field has settled since its reset.
    pub fn settled(&self) -> u32 {
        self.settled
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

    /// Whether `v` is left out for want of clearance (see
    /// [`Self::set_min_clearance`]) and was not entered as a corner of the
    /// source's face: proving it unreachable would settle its whole
    /// component, so its distance is `INFINITY` at once.
    #[inline]
    fn never_entered(&self, g: &Vdg<'_>, v: u32) -> bool {
        !self.seen(v) && g.vertices[v as usize].clearance < self.min_clearance
    }

    #[inline]
    fn is_settled(&self, v: u32) -> bool {
        self.stamp[v as usize] == (self.epoch << 1 | 1)
    }

    /// The A* heuristic of vertex position `p` (0 without a goal).
    #[inline]
    fn h(&self, p: V3) -> f32 {
        match self.goal {
            Some((q, r)) => ((p - q).norm() - r).max(0.0) as f32,
            None => 0.0,
        }
    }

    #[inline]
    fn relax_h(&mut self, v: u32, d: f32, h: f32) {
        let i = v as usize;
        self.dist[i] = d;
        self.stamp[i] = self.epoch << 1;
        // Non-negative f32 bits order like the values.
        let key = d + h;
        self.heap
            .push(Reverse(u64::from(key.to_bits()) << 32 | u64::from(v)));
    }

    #[inline]
    fn relax(&mut self, g: &Vdg<'_>, v: u32, d: f32) {
        if !self.seen(v) || d < self.dist[v as usize] {
            let h = self.h(g.pos(v));
            self.relax_h(v, d, h);
        }
    }

    /// Settles vertices until `v` is settled, the heap is empty or the
    /// budget is spent.
    fn grow_until(&mut self, g: &Vdg<'_>, v: u32) {
        while !self.is_settled(v) && self.settled < self.budget {
            let Some(Reverse(key)) = self.heap.pop() else {
                return;
            };
            let (f, u) = (f32::from_bits((key >> 32) as u32), key as u32);
            if self.is_settled(u) {
                continue;
            }
            let d = self.dist[u as usize];
            let pu = g.pos(u);
            if f > d + self.h(pu) {
                continue; // stale entry
            }
            self.stamp[u as usize] |= 1;
            self.settled += 1;
            self.frontier = f;
            for w in g.vertex_neighbours(u) {
                if !self.is_settled(w) && g.vertices[w as usize].clearance >= self.min_clearance {
                    let pw = g.pos(w);
                    let dw = d + (pw - pu).norm() as f32;
                    if !self.seen(w) || dw < self.dist[w as usize] {
                        let h = self.h(pw);
                        self.relax_h(w, dw, h);
                    }
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
        if self.never_entered(g, v) {
            return f32::INFINITY;
        }
        self.grow_until(g, v);
        if self.is_settled(v) {
            return self.dist[v as usize];
        }
        if self.heap.is_empty() && !self.exhausted() {
            return f32::INFINITY;
        }
        // Every unsettled vertex has g + h ≥ the last key settled.
        let p = g.pos(v);
        (self.frontier - self.h(p)).max((p - self.source).norm() as f32)
    }

    /// The distance of `v` if it is settled already, without growing the
    /// field. The next vertex of a shortest way from a settled vertex to
    /// the source is settled too (the heuristic is consistent), so a walk
    /// towards the source along settled vertices never needs to grow it.
    pub fn settled_distance(&self, v: u32) -> Option<f32> {
        (self.active && (v as usize) < self.stamp.len() && self.is_settled(v))
            .then(|| self.dist[v as usize])
    }

    /// `VDistance(p, source)` for a point `p` in face `face` (thesis 5.1):
    /// the straight distance when `face` is the source's face, otherwise
    /// the best of `|p − P(v)| + D(v)` over the face's three vertices.
    /// Panics if `face` is out of range or the field was never reset.
    ///
    /// The vertices are asked most promising first, and one whose lower
    /// bound (see [`Self::lower_bound`]) already loses is not asked at all:
    /// the answer is the same, but the field need not grow to a far corner
    /// of a large face. Growing there was most of the cost of a camera
    /// update whose target hid behind a wall (hundreds of vertices settled
    /// for a corner 200 units beyond the candidates).
    pub fn vdistance(&mut self, g: &Vdg<'_>, face: u32, p: [f32; 3]) -> f32 {
        let q = V3::from_f32(p);
        if face == self.source_face {
            return (q - self.source).norm() as f32;
        }
        assert!(self.active, "DistanceField::vdistance before reset");
        let corners = g.faces.get(face);
        let legs = corners.map(|v| (g.pos(v) - q).norm() as f32);
        let mut order = [0usize, 1, 2];
        let guess = [0, 1, 2].map(|i| self.lower_bound(g, corners[i]) + legs[i]);
        order.sort_by(|&a, &b| guess[a].total_cmp(&guess[b]).then(a.cmp(&b)));
        let mut best = f32::INFINITY;
        for i in order {
            let v = corners[i];
            if self.lower_bound(g, v) + legs[i] > best {
                continue;
            }
            best = best.min(self.vertex_distance(g, v) + legs[i]);
        }
        best
    }

    /// A lower bound of what [`Self::vertex_distance`] would answer for `v`,
    /// without growing the field: the distance itself once settled;
    /// otherwise the straight distance from the source and the A* bound
    /// (every unsettled vertex has `D + h ≥` the last key settled), less a
    /// thousandth for the rounding of the f32 sums the distances are. A
    /// vertex never entered for want of clearance answers `INFINITY`.
    fn lower_bound(&self, g: &Vdg<'_>, v: u32) -> f32 {
        if self.is_settled(v) {
            return self.dist[v as usize];
        }
        if self.never_entered(g, v) {
            return f32::INFINITY;
        }
        let p = g.pos(v);
        let straight = (p - self.source).norm() as f32;
        let astar = self.frontier - self.h(p);
        straight.max(astar) * LOWER_BOUND_SHARE
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
            let [a, b, c] = g.face(f).map(|v| g.vertices()[v as usize].pos);
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
    fn a_goal_steers_the_search_without_changing_the_answers() {
        let bytes = strip(120);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let src = [12.0, 10.0, 1.0];
        let far = g.face_count() as u32 - 1;
        let [a, b, c] = g.face(far).map(|v| g.vertices()[v as usize].pos);
        let near = [0, 1, 2].map(|i| (a[i] + b[i] + c[i]) / 3.0);
        let mut plain = DistanceField::new();
        plain.reset(&g, 0, src);
        let mut steered = DistanceField::new();
        steered.reset_towards(&g, 0, src, near, 30.0);
        // Ask at the goal first (the steered field settles less), then
        // everywhere: the same distances.
        let d0 = steered.vdistance(&g, far, near);
        let settled_steered = steered.settled;
        assert!((plain.vdistance(&g, far, near) - d0).abs() < 1e-2);
        assert!(
            settled_steered <= plain.settled,
            "{settled_steered} vs {}",
            plain.settled
        );
        for f in 0..g.face_count() as u32 {
            let p = g.vertices()[g.face(f)[0] as usize].pos;
            let (x, y) = (plain.vdistance(&g, f, p), steered.vdistance(&g, f, p));
            assert!((x - y).abs() < 1e-2, "face {f}: {x} vs {y}");
        }
    }

    /// A ring of 8 vertices round a square hole, one of them narrow: an
    /// agent too wide for it goes the long way round.
    #[test]
    fn a_minimum_clearance_takes_the_way_an_agent_fits_through() {
        let mut b = VdgBuilder::new();
        let ring: Vec<[f32; 2]> = vec![
            [0.0, 0.0],
            [100.0, 0.0],
            [200.0, 0.0],
            [200.0, 100.0],
            [200.0, 200.0],
            [100.0, 200.0],
            [0.0, 200.0],
            [0.0, 100.0],
        ];
        let outer: Vec<u32> = ring
            .iter()
            .enumerate()
            .map(|(i, &[x, y])| b.add_vertex([x, y, 0.0], if i == 1 { 2.0 } else { 16.0 }))
            .collect();
        // An inner ring, so that every outer edge has a triangle.
        let inner: Vec<u32> = ring
            .iter()
            .map(|&[x, y]| b.add_vertex([50.0 + x / 2.0, 50.0 + y / 2.0, 0.0], 16.0))
            .collect();
        for i in 0..8 {
            let j = (i + 1) % 8;
            b.add_face([outer[i], outer[j], inner[i]]);
            b.add_face([outer[j], inner[j], inner[i]]);
        }
        let bytes = b.to_bytes().unwrap();
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut field = DistanceField::new();
        // From a face at outer vertex 0 (not touching vertex 1) to outer
        // vertex 2.
        field.reset(&g, 15, [1.0, 1.0, 0.0]);
        let thin = field.vertex_distance(&g, outer[2]);
        field.set_min_clearance(8.0);
        field.reset(&g, 15, [1.0, 1.0, 0.0]);
        let wide = field.vertex_distance(&g, outer[2]);
        // The thin way runs along the bottom edge through the narrow
        // vertex; the wide one must leave it out.
        assert!((thin - 200.0).abs() < 2.0, "thin {thin}");
        assert!(wide > thin + 10.0, "wide {wide} vs thin {thin}");
        assert_eq!(field.settled_distance(outer[1]), None);
        // Settled distances never grow the field.
        let settled = field.settled();
        assert!(field.settled_distance(outer[2]).is_some());
        assert_eq!(field.settled(), settled);
    }

    /// What `vdistance` answered before it passed over corners: the best
    /// of all three, each grown to.
    fn every_corner(field: &mut DistanceField, g: &Vdg<'_>, face: u32, p: [f32; 3]) -> f32 {
        if Some(face) == field.source_face() {
            return (V3::from_f32(p) - field.source).norm() as f32;
        }
        let q = V3::from_f32(p);
        g.faces
            .get(face)
            .into_iter()
            .map(|v| field.vertex_distance(g, v) + (g.pos(v) - q).norm() as f32)
            .fold(f32::INFINITY, f32::min)
    }

    #[test]
    fn passing_over_corners_gives_the_same_answers() {
        let bytes = strip(160);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut rng = toolbox::SplitMix64::new(17);
        let mut next = move || rng.next_f32();
        for round in 0..20 {
            let src_face = (round * 7) % g.face_count() as u32;
            let src = g.vertices()[g.face(src_face)[0] as usize]
                .pos
                .map(|c| c + 1.0);
            let near = [next() * 4000.0, next() * 40.0, 0.0];
            let (mut fast, mut all) = (DistanceField::new(), DistanceField::new());
            fast.reset_towards(&g, src_face, src, near, 48.0);
            all.reset_towards(&g, src_face, src, near, 48.0);
            for _ in 0..40 {
                let f = (next() * g.face_count() as f32) as u32 % g.face_count() as u32;
                let [a, b, c] = g.face(f).map(|v| g.vertices()[v as usize].pos);
                let (s, t) = (next(), next());
                let (s, t) = if s + t > 1.0 {
                    (1.0 - s, 1.0 - t)
                } else {
                    (s, t)
                };
                let p = [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * s + (c[i] - a[i]) * t);
                let (x, y) = (fast.vdistance(&g, f, p), every_corner(&mut all, &g, f, p));
                assert_eq!(x.to_bits(), y.to_bits(), "face {f}: {x} vs {y}");
            }
            assert!(fast.settled() <= all.settled());
        }
    }

    #[test]
    fn a_far_corner_that_cannot_win_is_not_grown_to() {
        // A strip along x, and one long face from its first two vertices
        // to a vertex 500 units off to the side.
        let mut b = VdgBuilder::new();
        let mut ids = Vec::new();
        for i in 0..40 {
            ids.push(b.add_vertex([i as f32 * 50.0, 0.0, 0.0], 8.0));
            ids.push(b.add_vertex([i as f32 * 50.0 + 25.0, 40.0, 0.0], 8.0));
        }
        for i in 0..ids.len() - 2 {
            b.add_face([ids[i], ids[i + 1], ids[i + 2]]);
        }
        let far = b.add_vertex([0.0, 540.0, 0.0], 8.0);
        let long = b.add_face([ids[0], ids[1], far]);
        let bytes = b.to_bytes().unwrap();
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        // The source a few faces along the strip; the question near the
        // long face's strip end.
        let src = [130.0, 15.0, 0.0];
        let p = [14.0, 30.0, 0.0];
        let (mut fast, mut all) = (DistanceField::new(), DistanceField::new());
        fast.reset(&g, 4, src);
        all.reset(&g, 4, src);
        let (x, y) = (
            fast.vdistance(&g, long, p),
            every_corner(&mut all, &g, long, p),
        );
        assert_eq!(x.to_bits(), y.to_bits(), "{x} vs {y}");
        assert!(
            fast.settled() * 2 < all.settled(),
            "{} vs {}",
            fast.settled(),
            all.settled()
        );
        assert_eq!(fast.settled_distance(far), None);
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
        let far = g.face(g.face_count() as u32 - 1)[2];
        let exact = g.vertex_path(0, far).unwrap().length;
        let d = field.vertex_distance(&g, far);
        assert!(field.exhausted());
        assert!(d <= exact + 1e-3 && d > 0.0, "{d} vs {exact}");
        assert_eq!(field.heap.capacity(), cap);
    }
}
