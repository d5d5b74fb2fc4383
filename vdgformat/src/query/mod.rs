//! Runtime queries on a validated [`Vdg`] (thesis 3.7–3.9, 5.1, 5.3).
//!
//! Everything here reads the mapped sections in place. The open-time
//! validation guarantees every index is in range, so queries do no checks
//! of their own beyond Rust's slice bounds checks (which then never fire).
//! Geometry is evaluated in f64 on the stored f32 values.

mod face_cache;
mod field;
mod path;
mod visible;

pub(crate) use face_cache::{BoxProbe, FaceCache};

pub use field::{DEFAULT_SETTLE_BUDGET, DistanceField};
pub use path::{PathFinder, VdgPath};
pub use visible::{Advance, CoverBudget, CoverHint};

use std::collections::BinaryHeap;

use crate::geom::{Aabb, Ball, FaceEval, V3};
use crate::index::{FaceList, IndexList};
use crate::layout::{Info, TreeNode, Vertex};
use crate::read::Vdg;

/// Best-first search entry, ordered by `key` (largest first).
struct Candidate {
    key: f64,
    node: u32,
    cell: u32,
}

impl PartialEq for Candidate {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == std::cmp::Ordering::Equal
    }
}
impl Eq for Candidate {}
impl PartialOrd for Candidate {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Candidate {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.key.total_cmp(&o.key).then(o.node.cmp(&self.node))
    }
}

/// A face and the clearance of the query point for it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHit {
    /// Face index.
    pub face: u32,
    /// Clearance of the query point for this face (> 0 inside its volume).
    pub clearance: f32,
}

/// Basic accessors.
impl<'a> Vdg<'a> {
    /// Global counts, bounds and build parameters.
    pub fn info(&self) -> &'a Info {
        self.info
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// All vertices (position and clearance).
    pub fn vertices(&self) -> &'a [Vertex] {
        self.vertices
    }

    /// All faces (three vertex indices each), as stored (16- or 32-bit).
    pub fn faces(&self) -> FaceList<'a> {
        self.faces
    }

    /// The three vertex indices of face `f`. Panics if `f` is out of range.
    #[inline]
    pub fn face(&self, f: u32) -> [u32; 3] {
        self.faces.get(f)
    }

    /// Faces using vertex `v`, ascending. Panics if `v` is out of range.
    #[inline]
    pub fn vertex_faces(&self, v: u32) -> IndexList<'a> {
        let v = v as usize;
        self.vf.between(self.vf_offsets[v], self.vf_offsets[v + 1])
    }

    /// Vertices sharing a face with `v`, ascending. Panics if `v` is out of range.
    #[inline]
    pub fn vertex_neighbours(&self, v: u32) -> IndexList<'a> {
        let v = v as usize;
        self.vn.between(self.vn_offsets[v], self.vn_offsets[v + 1])
    }

    /// The file's format version (1 to [`crate::layout::FORMAT_VERSION`]).
    pub fn format_version(&self) -> u32 {
        self.version
    }

    /// XXH64 of the source map (0 when the producer did not record it).
    pub fn source_hash(&self) -> u64 {
        self.info.source_hash
    }

    /// Metadata entries (`key`, `value`) in key order.
    pub fn metadata(&self) -> impl Iterator<Item = (&'a str, &'a str)> + 'a {
        self.metadata.lines().filter_map(|l| l.split_once('='))
    }

    /// The value of one metadata key, e.g. `"source.name"` or `"tool.version"`.
    pub fn metadata_value(&self, key: &str) -> Option<&'a str> {
        self.metadata().find(|(k, _)| *k == key).map(|(_, v)| v)
    }

    /// The radii of face `face`'s corner balls: the face's own (format version
    /// 3 files written with them; at least each vertex's clearance, where only
    /// this face's volume had to stay free) or else its vertices' clearances.
    /// Face volumes and every clearance query use these. Panics if `face` is
    /// out of range.
    ///
    /// ```
    /// let mut b = vdgformat::VdgBuilder::new();
    /// let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// b.add_face_with_radii(v, [10.0, 10.0, 30.0]);
    /// let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// assert_eq!(g.face_radii(0), [10.0, 10.0, 30.0]);
    /// // 25 units above the third corner: inside its face's ball of 30.
    /// assert!(g.contains([0.0, 100.0, 25.0]));
    /// assert_eq!(g.vertices()[2].clearance, 10.0);
    /// ```
    #[inline]
    pub fn face_radii(&self, face: u32) -> [f32; 3] {
        crate::layout::corner_radii(self.faces, self.vertices, self.own_radii, face as usize)
    }

    /// Whether the file gives its faces their own corner radii (see
    /// [`Self::face_radii`]).
    pub fn has_face_radii(&self) -> bool {
        !self.own_radii.is_empty()
    }

    #[inline]
    pub(crate) fn pos(&self, v: u32) -> V3 {
        V3::from_f32(self.vertices[v as usize].pos)
    }

    /// Clearance of `p` for face `f`, in f64.
    #[inline]
    pub(crate) fn fc(&self, f: u32, p: V3) -> f64 {
        self.face_eval(f).eval(p)
    }

    /// Face `f`'s clearance function with its invariants worked out once:
    /// for several evaluations of one face (an exit search), or the exit
    /// of a line in closed form.
    #[inline]
    pub(crate) fn face_eval(&self, f: u32) -> FaceEval {
        let [a, b, c] = self.faces.get(f);
        let r = self.face_radii(f).map(f64::from);
        FaceEval::new(
            Ball {
                c: self.pos(a),
                r: r[0],
            },
            Ball {
                c: self.pos(b),
                r: r[1],
            },
            Ball {
                c: self.pos(c),
                r: r[2],
            },
        )
    }

    /// Clearance of `p` for face `f` when it may exceed `floor`; otherwise
    /// some value `≤ floor`. A face's volume lies in the box of its three
    /// vertex balls, and for `p` outside that box the clearance is at most
    /// minus the distance to it — a test far cheaper than the exact
    /// evaluation that culls most candidates of a leaf.
    #[inline]
    pub(crate) fn fc_above(&self, f: u32, p: V3, floor: f64) -> f64 {
        match self.box_bound(f, p, floor) {
            Some(bound) => bound,
            None => self.fc(f, p),
        }
    }

    /// Minus the distance of `p` to the box of face `f`'s vertex balls when
    /// that proves the clearance at `p` is at most `floor` (then `p` lies
    /// outside the box); `None` when the exact value is needed.
    #[inline]
    pub(crate) fn box_bound(&self, f: u32, p: V3, floor: f64) -> Option<f64> {
        let corners = self.faces.get(f).map(|v| self.vertices[v as usize].pos);
        let radii = self.face_radii(f);
        let d2 = outside_box_d2(p, |i| ball_box_axis(&corners, &radii, i));
        let bound = -d2.sqrt();
        (bound <= floor && d2 > 0.0).then_some(bound)
    }

    /// Whether `p` lies in the box of face `f`'s three vertex balls (widened
    /// for rounding), which holds the face's volume: `false` proves `p` is
    /// outside the volume, without a square root and usually after one axis.
    #[inline]
    ///
    /// The widening is a millionth relative to the point's coordinate
    /// (not the box's, as in [`Self::box_bound`]): cheaper, and still far
    /// above the rounding of an evaluation, so a face it rules out has a
    /// clearance below any margin the callers ask for.
    pub(crate) fn box_holds(&self, f: u32, p: V3) -> bool {
        let [a, b, c] = self.faces.get(f).map(|v| self.vertices[v as usize]);
        let r = self.face_radii(f).map(f64::from);
        for (i, q) in [p.0, p.1, p.2].into_iter().enumerate() {
            let c = [a.pos[i], b.pos[i], c.pos[i]].map(f64::from);
            let (l0, l1, l2) = (c[0] - r[0], c[1] - r[1], c[2] - r[2]);
            let (h0, h1, h2) = (c[0] + r[0], c[1] + r[1], c[2] + r[2]);
            let lo = if l0 < l1 { l0 } else { l1 };
            let lo = if l2 < lo { l2 } else { lo };
            let hi = if h0 > h1 { h0 } else { h1 };
            let hi = if h2 > hi { h2 } else { hi };
            let slack = 1e-6 * (1.0 + q.abs());
            // Written so that a NaN anywhere answers false.
            if !(q >= lo - slack && q <= hi + slack) {
                return false;
            }
        }
        true
    }

    /// Calls `visit` for `f` and every face sharing a vertex with it
    /// (thesis: Neighbours(f)); faces sharing an edge are visited more than
    /// once, which is cheaper than deduplicating.
    #[inline]
    pub(crate) fn for_face_and_neighbours(&self, f: u32, mut visit: impl FnMut(u32)) {
        visit(f);
        for &v in &self.faces.get(f) {
            for g in self.vertex_faces(v) {
                if g != f {
                    visit(g);
                }
            }
        }
    }

    /// [`Self::for_face_and_neighbours`] visiting each face once: a face
    /// sharing an edge with `f`, met again through its second shared
    /// corner, is skipped.
    #[inline]
    pub(crate) fn for_face_and_neighbours_once(&self, f: u32, mut visit: impl FnMut(u32)) {
        visit(f);
        let corners = self.faces.get(f);
        for (i, &v) in corners.iter().enumerate() {
            for g in self.vertex_faces(v) {
                if g != f && !self.faces.get(g).iter().any(|u| corners[..i].contains(u)) {
                    visit(g);
                }
            }
        }
    }

    fn root_cell(&self) -> Aabb {
        Aabb {
            min: self.info.volume_min,
            max: self.info.volume_max,
        }
    }

    /// Faces of the tree leaf whose cell contains `p` — a superset of the
    /// faces whose volume contains `p`. Empty outside the root cell.
    pub(crate) fn leaf_faces_at(&self, p: V3) -> IndexList<'a> {
        let c = [p.0, p.1, p.2];
        let root = self.root_cell();
        if (0..3).any(|i| c[i] < f64::from(root.min[i]) || c[i] > f64::from(root.max[i])) {
            return self.leaf_faces.range(0, 0);
        }
        let mut n = 0usize;
        loop {
            let node = self.nodes[n];
            if node.kind == TreeNode::LEAF {
                return self.leaf_faces.range(node.a, node.b);
            }
            n = if c[node.kind as usize] < f64::from(node.split) {
                node.a as usize
            } else {
                node.b as usize
            };
        }
    }
}

/// The squared distance of `p` to the box whose extent along axis `i` is
/// `axis(i)` (0 inside).
#[inline]
pub(crate) fn outside_box_d2(p: V3, axis: impl Fn(usize) -> (f64, f64)) -> f64 {
    let mut d2 = 0.0;
    for (i, q) in [p.0, p.1, p.2].into_iter().enumerate() {
        let (lo, hi) = axis(i);
        let e = if lo - q > q - hi { lo - q } else { q - hi };
        if e > 0.0 {
            d2 += e * e;
        }
    }
    d2
}

/// The extent along axis `i` of three vertex balls, in f64 (exact for the
/// f32 data up to one rounding) and widened by a relative millionth, so a
/// box test never culls a face it should not. Plain comparisons instead of
/// `f64::min`, whose NaN rules cost more than the test itself: a NaN makes
/// the bounds NaN and every containment test false.
#[inline]
fn ball_box_axis(corners: &[[f32; 3]; 3], radii: &[f32; 3], i: usize) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for (v, &r) in corners.iter().zip(radii) {
        let (c, r) = (f64::from(v[i]), f64::from(r));
        let (l, h) = (c - r, c + r);
        lo = if l < lo { l } else { lo };
        hi = if h > hi { h } else { hi };
    }
    let slack = 1e-6 * (1.0 + if -lo > hi { -lo } else { hi }.abs());
    (lo - slack, hi + slack)
}

/// Clearance queries (thesis 3.7) and face lookup.
impl<'a> Vdg<'a> {
    /// Clearance of `p` for face `face`: `max_{q ∈ face} r(q) − |p − q|`
    /// with the vertex clearances linearly interpolated over the triangle.
    /// Positive exactly inside the face volume (the union of the balls
    /// `B(q, r(q))`); computed in closed form. Panics if `face` is out of range.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// // 4 units above a triangle of constant clearance 10: 10 − 4.
    /// assert!((g.face_clearance(0, [20.0, 20.0, 4.0]) - 6.0).abs() < 1e-5);
    /// ```
    pub fn face_clearance(&self, face: u32, p: [f32; 3]) -> f32 {
        self.fc(face, V3::from_f32(p)) as f32
    }

    /// Clearance of `p`: the maximum of [`Self::face_clearance`] over all
    /// faces (thesis 3.7), found through the BBox tree. `-∞` for an empty graph.
    pub fn clearance(&self, p: [f32; 3]) -> f32 {
        self.nearest_face(p)
            .map_or(f32::NEG_INFINITY, |h| h.clearance)
    }

    /// The face maximising the clearance of `p`, from scratch via the tree
    /// (thesis 5.2: the face of a new camera). Exact for points outside
    /// Volume(VDG) too (then the clearance is negative). `None` only for a
    /// graph without faces.
    ///
    /// Inside the volume one leaf suffices: every face whose volume holds
    /// `p` is listed in `p`'s leaf. Outside, tree nodes are visited in order
    /// of an upper bound on their faces' clearance (from the cell and the
    /// stored triangle box and largest clearance below the node) until the
    /// best face found beats every remaining bound. Far outside the volume
    /// this evaluates many faces; for a yes/no membership test use
    /// [`Self::contains`].
    pub fn nearest_face(&self, p: [f32; 3]) -> Option<FaceHit> {
        self.nearest_face_f64(V3::from_f32(p))
            .map(|(face, c)| FaceHit {
                face,
                clearance: c as f32,
            })
    }

    /// [`Self::nearest_face_f64`] for a caller with a [`FaceCache`] (a
    /// camera placed anew): the same answer, its first look (`p`'s leaf)
    /// made by [`Self::leaf_face_holding`].
    pub(crate) fn nearest_face_cached(&self, cache: &FaceCache, p: V3) -> Option<(u32, f64)> {
        self.leaf_face_holding(cache, p)
            .or_else(|| self.nearest_face_by_tree(p))
    }

    /// The face of `p`'s tree leaf whose volume holds `p` deepest (the
    /// first in the leaf's order among equals), with that clearance; `None`
    /// when none holds it. Faces whose stored box misses `p` are passed over
    /// with one box test (their clearance there is negative), where the
    /// plain search bounds each from its vertices: in a big room the leaf
    /// lists thousands of faces and few hold the point.
    pub(crate) fn leaf_face_holding(&self, cache: &FaceCache, p: V3) -> Option<(u32, f64)> {
        let probe = BoxProbe::at(p);
        let mut best = (u32::MAX, 0.0);
        for f in self.leaf_faces_at(p).iter() {
            if !cache.holds(f, &probe) {
                continue;
            }
            let c = cache.fc(self, f, p);
            if c > best.1 {
                best = (f, c);
            }
        }
        (best.1 > 0.0).then_some(best)
    }

    pub(crate) fn nearest_face_f64(&self, p: V3) -> Option<(u32, f64)> {
        if self.faces.is_empty() {
            return None;
        }
        // Faces with clearance ≤ floor may come back as bounds, so only
        // values above the floor are taken (those are exact).
        let mut best = (u32::MAX, f64::NEG_INFINITY);
        for f in self.leaf_faces_at(p).iter() {
            let floor = best.1.max(0.0);
            let c = self.fc_above(f, p, floor);
            if c > floor {
                best = (f, c);
            }
        }
        if best.1 > 0.0 {
            return Some(best);
        }
        // Nothing was taken (a taken value is above 0): `best` is as it began.
        self.nearest_face_by_tree(p)
    }

    /// The face maximising the clearance of `p`, by a search of the whole
    /// tree: what [`Self::nearest_face_f64`] does once no face of `p`'s leaf
    /// holds `p` (callers that already looked at the leaf skip that look).
    /// `None` only for a graph without faces.
    pub(crate) fn nearest_face_by_tree(&self, p: V3) -> Option<(u32, f64)> {
        if self.faces.is_empty() {
            return None;
        }
        let mut best = (u32::MAX, f64::NEG_INFINITY);
        // Best-first over tree nodes by an upper bound on the clearance of
        // any face listed below them: the smaller of minus the distance to
        // the node's cell (a face's volume box is covered by the cells
        // listing it) and `r_max − dist(p, triangle box)`. Both shrink
        // from parent to child, so once the best clearance found reaches
        // the largest bound left, no unvisited face can beat it.
        let root = self.root_cell();
        let mut cells = vec![root];
        let mut heap = BinaryHeap::new();
        if let Some(k) = self.node_key(0, &root, p) {
            heap.push(Candidate {
                key: k,
                node: 0,
                cell: 0,
            });
        }
        while let Some(Candidate {
            key,
            node: n,
            cell: ci,
        }) = heap.pop()
        {
            if best.1 >= key {
                break;
            }
            let cell = cells[ci as usize];
            let node = self.nodes[n as usize];
            if node.kind == TreeNode::LEAF {
                for f in self.leaf_faces.range(node.a, node.b).iter() {
                    let c = self.fc_above(f, p, best.1);
                    if c > best.1 {
                        best = (f, c);
                    }
                }
            } else {
                let ax = node.kind as usize;
                let (mut lo, mut hi) = (cell, cell);
                lo.max[ax] = node.split;
                hi.min[ax] = node.split;
                for (child, c) in [(node.a, lo), (node.b, hi)] {
                    if let Some(k) = self.node_key(child, &c, p) {
                        heap.push(Candidate {
                            key: k,
                            node: child,
                            cell: cells.len() as u32,
                        });
                        cells.push(c);
                    }
                }
            }
        }
        if best.0 == u32::MAX {
            // Unreachable for validated files (every face is in a leaf and
            // the bounds are checked); kept so a query can never index out
            // of range.
            best = (0..self.faces.len() as u32)
                .map(|f| (f, self.fc(f, p)))
                .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
        }
        Some(best)
    }

    /// Upper bound on the clearance at `p` of faces listed under `node`
    /// (`None` for a node without faces).
    #[inline]
    fn node_key(&self, node: u32, cell: &Aabb, p: V3) -> Option<f64> {
        let b = self.node_bounds[node as usize];
        if b.r_max < 0.0 {
            return None;
        }
        let tri = Aabb {
            min: b.tri_min,
            max: b.tri_max,
        };
        Some((-cell.distance(p)).min(f64::from(b.r_max) - tri.distance(p)))
    }

    /// Tracks a moving point (thesis 3.3/5.2, the continuity trick): tests
    /// `hint` and the faces sharing a vertex with it, climbing to the best
    /// neighbour while that improves the clearance. If the best face found
    /// does not contain `p` (the point jumped or left the volume) — or the
    /// hint is not a face — it falls back to [`Self::nearest_face`].
    ///
    /// For small moves this finds the same face as the tree search at a
    /// fraction of the cost; it is a local search, so after a large jump
    /// inside the volume it may return a face of lower (still positive)
    /// clearance than the global maximum.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// let mut hit = g.nearest_face([5.0, 5.0, 0.0]).unwrap();
    /// for step in 0..10 {
    ///     hit = g.track(hit.face, [5.0 + step as f32, 5.0, 1.0]).unwrap();
    /// }
    /// assert_eq!(hit.face, 0);
    /// ```
    pub fn track(&self, hint: u32, p: [f32; 3]) -> Option<FaceHit> {
        let q = V3::from_f32(p);
        if (hint as usize) < self.faces.len() {
            let cur = self.climb(hint, q, 32);
            if cur.1 > 0.0 {
                return Some(FaceHit {
                    face: cur.0,
                    clearance: cur.1 as f32,
                });
            }
        }
        self.nearest_face(p)
    }

    /// The local search behind [`Self::track`]: from `hint`, move to the
    /// neighbour face of largest clearance at `q` while that improves it
    /// (at most `rounds` moves). Returns the face and its clearance, which
    /// is negative when `q` lies outside every face met. Panics if `hint`
    /// is out of range.
    pub(crate) fn climb(&self, hint: u32, q: V3, rounds: usize) -> (u32, f64) {
        let mut cur = (hint, self.fc(hint, q));
        for _ in 0..rounds {
            let mut best = cur;
            self.for_face_and_neighbours(cur.0, |f| {
                // Exact whenever it can beat the best, so the same answer as
                // evaluating every face, with most neighbours culled by box.
                let c = self.fc_above(f, q, best.1);
                if c > best.1 {
                    best = (f, c);
                }
            });
            if best.0 == cur.0 {
                break;
            }
            cur = best;
        }
        cur
    }

    /// [`Self::climb`] for a caller with a [`FaceCache`] (a camera): the
    /// stored boxes and balls cull, the memo sets faces up, and a face met
    /// before in this climb (a neighbour met again through a second shared
    /// vertex, or in an earlier round: the rounds' neighbourhoods overlap)
    /// is skipped. The same answer as `climb`: a culled face's clearance is
    /// at most minus its distance to the stored box, which holds the exact
    /// one, or below the best by the stored ball
    /// ([`FaceCache::reach_below`]), so it could not beat the best; and a
    /// face met before cannot beat the best it already lost to (or became),
    /// or was culled by, for the best only grows and the point stays.
    pub(crate) fn climb_cached(
        &self,
        cache: &FaceCache,
        hint: u32,
        q: V3,
        rounds: usize,
    ) -> (u32, f64) {
        let mut cur = (hint, cache.fc(self, hint, q));
        cache.new_face_set();
        cache.meet(hint);
        for _ in 0..rounds {
            let mut best = cur;
            self.for_face_and_neighbours(cur.0, |f| {
                if !cache.meet(f)
                    || cache.box_bound(f, q).is_some_and(|b| b <= best.1)
                    || cache.reach_below(f, q, best.1)
                {
                    return;
                }
                let c = cache.fc(self, f, q);
                if c > best.1 {
                    best = (f, c);
                }
            });
            if best.0 == cur.0 {
                break;
            }
            cur = best;
        }
        cur
    }

    /// Whether `p` lies in Volume(VDG) (some face clearance > 0). Always one
    /// tree leaf, however far `p` is from the volume — use this rather than
    /// `clearance(p) > 0` for membership tests of arbitrary points (the
    /// exact clearance of a point far outside needs a wider search).
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// assert!(g.contains([20.0, 20.0, 9.0]));
    /// assert!(!g.contains([20.0, 20.0, 11.0]));
    /// ```
    pub fn contains(&self, p: [f32; 3]) -> bool {
        let q = V3::from_f32(p);
        self.leaf_faces_at(q)
            .iter()
            .any(|f| self.fc_above(f, q, 0.0) > 0.0)
    }

    /// Every face whose volume contains `p` (clearance > 0), ascending.
    pub fn faces_containing(&self, p: [f32; 3]) -> Vec<u32> {
        let q = V3::from_f32(p);
        let mut out: Vec<u32> = self
            .leaf_faces_at(q)
            .iter()
            .filter(|&f| self.fc_above(f, q, 0.0) > 0.0)
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }
}
