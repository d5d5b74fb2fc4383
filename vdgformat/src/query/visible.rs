//! Segment queries: Trace, Visible (thesis 3.9) and Reachable (thesis 5.3).
//!
//! A face volume is convex (the convex hull of its three vertex balls) and
//! the clearance along a segment is concave, so a segment meets a volume in
//! one interval. Visibility is proved by covering the segment from its start
//! with such intervals: the current face covers `[0, t]`; a face containing
//! the point at `t` covers a further interval that starts before `t`. Every
//! piece is certified by clearance evaluations above a margin at both of its
//! ends, so a `true` answer means the whole segment lies in Volume(VDG) —
//! never through a wall. Any doubt (no progress, step limit) answers `false`.

use crate::geom::V3;
use crate::read::Vdg;

/// Clearance a point must exceed to count as inside a face volume in the
/// visibility certificate: far above the f64 rounding of the evaluation,
/// far below anything that matters in game units.
const INSIDE_EPS: f64 = 1e-4;

/// Trace stops this much clearance short of the boundary so that rounding
/// its answer to f32 keeps it inside the volume.
const TRACE_MARGIN: f64 = 1e-2;

/// Bisection stops when the bracket is this short (world units)…
const BISECT_TOL: f64 = 1e-3;
/// A cover step's bracket may stay this long (world units): far below a
/// face's extent, so hops stay few, and it costs about half the evaluations.
const COVER_TOL: f64 = 0.125;
/// …or after this many halvings.
const BISECT_MAX: usize = 60;

/// A visibility trace gives up (answers "not visible") after this many hops.
const MAX_HOPS: usize = 4096;

#[derive(Clone, Copy)]
struct Seg {
    s: V3,
    d: V3,
    len: f64,
}

impl Seg {
    fn new(s: V3, e: V3) -> Seg {
        let d = e - s;
        Seg {
            s,
            d,
            len: d.norm(),
        }
    }
    #[inline]
    fn at(&self, t: f64) -> V3 {
        self.s + self.d * t
    }
}

impl<'a> Vdg<'a> {
    /// Largest `t ∈ [lo, 1]` found with clearance of `at(t)` for `f` above
    /// `eps`, given that `at(lo)` is above it.
    ///
    /// The clearance along a segment is concave, so the crossing of `eps` is
    /// bracketed by one point above and one below. Regula falsi with the
    /// Illinois modification (the stale end's value is halved when the same
    /// end moves twice) converges in a handful of evaluations where bisection
    /// needs 20–40; every third step is a bisection all the same, so a kink in
    /// the clearance cannot stall it. The bracket's low end is always a point
    /// evaluated above `eps`, and that is what is returned: the answer stays
    /// certified however the search ends.
    fn exit_param(&self, f: u32, seg: &Seg, lo: f64, eps: f64) -> f64 {
        self.exit_param_tol(f, seg, lo, eps, BISECT_TOL)
    }

    /// [`Self::exit_param`] with the bracket's stopping length `tol` (world
    /// units): a cover step only needs to know roughly where a face ends
    /// (the next face takes over from a certified point either way), so it
    /// stops early; points handed back to callers use the fine tolerance.
    fn exit_param_tol(&self, f: u32, seg: &Seg, lo: f64, eps: f64, tol: f64) -> f64 {
        let g_end = self.fc(f, seg.at(1.0)) - eps;
        if g_end > 0.0 {
            return 1.0;
        }
        let (mut lo, mut hi) = (lo, 1.0);
        let (mut g_lo, mut g_hi) = (self.fc(f, seg.at(lo)) - eps, g_end);
        if g_lo <= 0.0 {
            // The caller's point was above eps by a bound, not by value: fall
            // back on it unchanged (bisection would also return `lo`).
            return lo;
        }
        let tol = if seg.len > 0.0 { tol / seg.len } else { 1.0 };
        let mut last_side = 0i8;
        for step in 0..BISECT_MAX {
            if hi - lo <= tol {
                break;
            }
            let secant = lo + (hi - lo) * g_lo / (g_lo - g_hi);
            let mid = if step % 3 == 2 || !(secant > lo && secant < hi) {
                0.5 * (lo + hi)
            } else {
                secant
            };
            let g = self.fc(f, seg.at(mid)) - eps;
            if g > 0.0 {
                (lo, g_lo) = (mid, g);
                if last_side == 1 {
                    g_hi *= 0.5;
                }
                last_side = 1;
            } else {
                (hi, g_hi) = (mid, g);
                if last_side == -1 {
                    g_lo *= 0.5;
                }
                last_side = -1;
            }
        }
        lo
    }

    /// The thesis' `Trace(s, e, f)`: the farthest point of the segment `s→e`
    /// reachable from `s` inside Volume(`face`) (a little short of the
    /// boundary so the f32 result stays inside). Returns `e` when `e` is in
    /// the volume and `s` when `s` is not. Used to pull camera candidates
    /// back into the solution space (thesis 5.3). Panics if `face` is out of range.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// // Straight up from the triangle: the volume ends 10 units above it.
    /// let top = g.trace(0, [20.0, 20.0, 0.0], [20.0, 20.0, 50.0]);
    /// assert!((top[2] - 10.0).abs() < 0.05 && g.face_clearance(0, top) > 0.0);
    /// ```
    pub fn trace(&self, face: u32, s: [f32; 3], e: [f32; 3]) -> [f32; 3] {
        let seg = Seg::new(V3::from_f32(s), V3::from_f32(e));
        if self.fc(face, seg.s) <= TRACE_MARGIN {
            return s;
        }
        let mut t = self.exit_param(face, &seg, 0.0, TRACE_MARGIN);
        if t >= 1.0 {
            return e;
        }
        // Rounding to f32 may move the point by half an ulp; back off until
        // the rounded point is certified inside.
        loop {
            let p = seg.at(t).to_f32();
            if t == 0.0 || self.fc(face, V3::from_f32(p)) > 0.0 {
                return if t == 0.0 { s } else { p };
            }
            t *= 0.5;
        }
    }

    /// `Visible(s, e)` (thesis 3.9): whether the segment `s→e` lies inside
    /// Volume(VDG), proved by a trace through neighbouring face volumes.
    /// `true` is never wrong; `false` may be (a segment grazing the volume
    /// boundary, or through free space the graph does not cover).
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// assert!(g.visible([0.0, 0.0, 5.0], [90.0, 0.0, 5.0]));
    /// assert!(!g.visible([0.0, 0.0, 5.0], [0.0, 0.0, 50.0]));
    /// ```
    pub fn visible(&self, s: [f32; 3], e: [f32; 3]) -> bool {
        let seg = Seg::new(V3::from_f32(s), V3::from_f32(e));
        let start = self.leaf_faces_at(seg.s);
        match self.best_cover_step(start.iter().copied(), &seg, 0.0, INSIDE_EPS) {
            Some((f, t)) => t >= 1.0 || self.cover(f, &seg, t, INSIDE_EPS, MAX_HOPS).1 >= 1.0,
            None => false,
        }
    }

    /// `Visible(s, e, f)` (thesis 3.9) with a known face `face` whose volume
    /// contains `s` (e.g. from [`Self::track`]). `false` if it does not.
    /// Panics if `face` is out of range.
    pub fn visible_from(&self, face: u32, s: [f32; 3], e: [f32; 3]) -> bool {
        self.visible_from_within(face, s, e, MAX_HOPS)
    }

    /// [`Self::visible_from`] giving up ("not visible") after `max_hops`
    /// face volumes: a per-frame caller bounds its worst case this way.
    pub(crate) fn visible_from_within(
        &self,
        face: u32,
        s: [f32; 3],
        e: [f32; 3],
        max_hops: usize,
    ) -> bool {
        let seg = Seg::new(V3::from_f32(s), V3::from_f32(e));
        if self.fc(face, seg.s) <= INSIDE_EPS {
            return false;
        }
        let t = self.exit_param(face, &seg, 0.0, INSIDE_EPS);
        t >= 1.0 || self.cover(face, &seg, t, INSIDE_EPS, max_hops).1 >= 1.0
    }

    /// Among `candidates` whose volume contains `at(t)`, the one reaching
    /// farthest along the segment, with that reach; `None` if none contains
    /// `at(t)`. Candidates that cannot beat the best so far cost one
    /// evaluation: their interval holds `at(t)`, so if it misses
    /// `at(best)` it ends before `best`.
    fn best_cover_step(
        &self,
        candidates: impl Iterator<Item = u32>,
        seg: &Seg,
        t: f64,
        eps: f64,
    ) -> Option<(u32, f64)> {
        let here = seg.at(t);
        let mut best: Option<(u32, f64)> = None;
        for f in candidates {
            let reach = best.map_or(t, |b| b.1);
            if reach >= 1.0 {
                break;
            }
            if reach > t && self.fc_above(f, seg.at(reach), eps) <= eps {
                continue;
            }
            if self.fc_above(f, here, eps) <= eps {
                continue;
            }
            let exit = self.exit_param_tol(f, seg, reach, eps, COVER_TOL);
            if best.is_none_or(|b| exit > b.1) {
                best = Some((f, exit));
            }
        }
        best
    }

    /// Extends a cover `[0, t]` ending in face `cur` as far along the segment
    /// as it goes, with every point certified above clearance `eps`:
    /// neighbours of the current face first (the thesis' recursion, kept
    /// greedy: the neighbour reaching farthest), and the faces of the tree
    /// leaf at the cover's end when no neighbour helps. Returns the last face
    /// and the reach (`>= 1.0` when the whole segment is covered).
    fn cover(&self, mut cur: u32, seg: &Seg, mut t: f64, eps: f64, max_hops: usize) -> (u32, f64) {
        // A hop must gain at least this much (a thousandth of a unit), so
        // the hop limit bounds the work; smaller gains end the cover.
        let min_gain = if seg.len > 0.0 { 1e-3 / seg.len } else { 0.0 };
        for _ in 0..max_hops {
            let mut step = self
                .best_cover_step(self.neighbourhood(cur), seg, t, eps)
                .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
            if step.is_none() {
                let leaf = self.leaf_faces_at(seg.at(t));
                step = self
                    .best_cover_step(leaf.iter().copied(), seg, t, eps)
                    .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
            }
            match step {
                Some((f, r)) if r >= 1.0 => return (f, 1.0),
                Some((f, r)) => {
                    cur = f;
                    t = r;
                }
                None => break,
            }
        }
        (cur, t)
    }

    /// The face and every face sharing a vertex with it (thesis:
    /// Neighbours(f)), without collecting them; faces sharing an edge come
    /// more than once.
    #[inline]
    pub(crate) fn neighbourhood(&self, f: u32) -> impl Iterator<Item = u32> + '_ {
        std::iter::once(f).chain(
            self.faces[f as usize]
                .into_iter()
                .flat_map(|v| self.vertex_faces(v).iter().copied())
                .filter(move |&g| g != f),
        )
    }

    /// Moves from `from` (inside the volume of `face`) towards `to` as far as
    /// the straight segment stays inside Volume(VDG) with clearance above
    /// `margin`, crossing as many face volumes as needed (at most
    /// `max_hops`). This is [`Self::trace`] without the one-face limit: a
    /// camera whose step would leave a small face continues into the next
    /// one instead of stalling (thesis 7.2 proposes several steps per frame
    /// for exactly this). The returned point is certified: its clearance
    /// for the returned face exceeds `margin` (or it is `from` unchanged,
    /// with `moved == false`, when `from` itself is not that deep inside).
    /// Panics if `face` is out of range.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v: Vec<u32> = [[0.0, 0.0], [64.0, 0.0], [0.0, 64.0], [64.0, 64.0], [128.0, 0.0], [128.0, 64.0]]
    /// #     .iter().map(|&[x, y]| b.add_vertex([x, y, 0.0], 16.0)).collect();
    /// # for f in [[0, 1, 2], [1, 3, 2], [1, 4, 3], [4, 5, 3]] { b.add_face(f.map(|i| v[i])); }
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// // From the first triangle across three more to the far end of the strip.
    /// let a = g.advance(0, [5.0, 5.0, 0.0], [120.0, 50.0, 0.0], 2.0, 16);
    /// assert!(a.reached && a.point == [120.0, 50.0, 0.0]);
    /// // Straight up: stops 2 units below the top of the volume.
    /// let up = g.advance(0, [5.0, 5.0, 0.0], [5.0, 5.0, 100.0], 2.0, 16);
    /// assert!(!up.reached && (up.point[2] - 14.0).abs() < 0.1);
    /// ```
    pub fn advance(
        &self,
        face: u32,
        from: [f32; 3],
        to: [f32; 3],
        margin: f32,
        max_hops: u32,
    ) -> Advance {
        let eps = f64::from(margin).max(0.0) + TRACE_MARGIN;
        let seg = Seg::new(V3::from_f32(from), V3::from_f32(to));
        let stay = Advance {
            point: from,
            face,
            reached: from == to,
            moved: false,
        };
        let here = self.fc(face, seg.s);
        if here.is_nan() || here <= eps || !seg.len.is_finite() {
            return stay;
        }
        let mut t0 = 0.0;
        let mut cur = face;
        let mut t = self.exit_param(face, &seg, 0.0, eps);
        if t < 1.0 && max_hops > 0 {
            // The cover's last hop starts where the previous face ended;
            // remember that start so a rounding back-off stays in `cur`.
            let (f, r) = self.cover(face, &seg, t, eps, max_hops as usize);
            if f != face {
                t0 = t;
            }
            (cur, t) = (f, r);
        }
        if t >= 1.0 {
            return Advance {
                point: to,
                face: cur,
                reached: true,
                moved: true,
            };
        }
        // Rounding to f32 may move the point by half an ulp; back off
        // towards the start of the last face's interval until the rounded
        // point is certified (the interval is inside `cur`, which is convex).
        for _ in 0..64 {
            let p = seg.at(t).to_f32();
            if self.fc(cur, V3::from_f32(p)) > f64::from(margin).max(0.0) {
                return Advance {
                    point: p,
                    face: cur,
                    reached: false,
                    moved: p != from,
                };
            }
            t = t0 + (t - t0) * 0.5;
        }
        stay
    }

    /// `Reachable(p, f)` (thesis 5.3): the vertices of `face` and their
    /// neighbours that can be reached from `p` on a straight line inside the
    /// volume of `face` and its neighbour faces. Ascending vertex indices.
    /// Panics if `face` is out of range. [`Self::reachable_into`] is the
    /// allocation-free form.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// assert_eq!(g.reachable([10.0, 10.0, 2.0], 0), vec![0, 1, 2]);
    /// ```
    pub fn reachable(&self, p: [f32; 3], face: u32) -> Vec<u32> {
        let mut out = Vec::with_capacity(64);
        self.for_each_reachable(p, face, |v| out.push(v));
        out
    }

    /// [`Self::reachable`] written into `out` without allocating: returns
    /// how many vertices are reachable; when that is more than `out.len()`,
    /// the first `out.len()` (ascending) are written and the caller may
    /// retry with a larger buffer.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// let g = file.graph();
    /// let mut buf = [0u32; 2];
    /// assert_eq!(g.reachable_into([10.0, 10.0, 2.0], 0, &mut buf), 3);
    /// assert_eq!(buf, [0, 1]);
    /// ```
    pub fn reachable_into(&self, p: [f32; 3], face: u32, out: &mut [u32]) -> usize {
        let mut n = 0;
        self.for_each_reachable(p, face, |v| {
            if let Some(slot) = out.get_mut(n) {
                *slot = v;
            }
            n += 1;
        });
        n
    }

    /// Calls `visit` for every vertex of `Reachable(p, face)` in ascending
    /// order, allocating nothing: the candidates (the face's vertices and
    /// their neighbours) come from a merge of sorted lists, the region's
    /// faces from [`Self::neighbourhood`].
    pub(crate) fn for_each_reachable(&self, p: [f32; 3], face: u32, visit: impl FnMut(u32)) {
        self.for_each_local_vertex(p, face, true, visit);
    }

    /// The candidates of `Reachable(p, face)` (the face's vertices and
    /// their neighbours, ascending) that are certified reachable: by one
    /// face volume holding both `p` and the vertex (cheap), or — when
    /// `exact` — otherwise by a cover through the region (the thesis'
    /// definition; several times the cost). Without `exact` this is a
    /// subset of Reachable: what a per-frame camera can afford.
    pub(crate) fn for_each_local_vertex(
        &self,
        p: [f32; 3],
        face: u32,
        exact: bool,
        mut visit: impl FnMut(u32),
    ) {
        let start = V3::from_f32(p);
        let [a, b, c] = self.faces[face as usize];
        let mut lists: [&[u32]; 6] = [
            self.vertex_neighbours(a),
            self.vertex_neighbours(b),
            self.vertex_neighbours(c),
            std::slice::from_ref(&self.faces[face as usize][0]),
            std::slice::from_ref(&self.faces[face as usize][1]),
            std::slice::from_ref(&self.faces[face as usize][2]),
        ];
        while let Some(v) = lists.iter().filter_map(|l| l.first().copied()).min() {
            for l in &mut lists {
                if l.first() == Some(&v) {
                    *l = &l[1..];
                }
            }
            // A face volume is convex: if one of v's faces in the region
            // holds p, the segment p–P(v) lies in it (P(v) is inside every
            // face of v, with clearance r(v)). Only the rest need a cover.
            if self.faces[face as usize].contains(&v)
                || self.vertex_face_holds(face, v, start)
                || (exact && self.segment_in_region(face, start, self.pos(v)))
            {
                visit(v);
            }
        }
    }

    /// Whether some face of `v` that belongs to the region of `face` (shares
    /// a vertex with it) holds `p` with clearance above the certificate's
    /// margin.
    fn vertex_face_holds(&self, face: u32, v: u32, p: V3) -> bool {
        let corners = self.faces[face as usize];
        self.vertex_faces(v).iter().any(|&g| {
            self.faces[g as usize].iter().any(|c| corners.contains(c))
                && self.fc_above(g, p, INSIDE_EPS) > INSIDE_EPS
        })
    }

    /// Whether the segment `s`–`e` lies in the union of the volumes of
    /// `face` and its neighbours (the region of `Reachable`).
    fn segment_in_region(&self, face: u32, s: V3, e: V3) -> bool {
        let seg = Seg::new(s, e);
        let mut t = 0.0;
        for _ in 0..MAX_HOPS {
            match self
                .best_cover_step(self.neighbourhood(face), &seg, t, INSIDE_EPS)
                .filter(|&(_, r)| r > t || r >= 1.0)
            {
                Some((_, r)) if r >= 1.0 => return true,
                Some((_, r)) => t = r,
                None => return false,
            }
        }
        false
    }
}

/// The result of [`Vdg::advance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// Where the point ended: the goal, or the farthest certified point
    /// towards it.
    pub point: [f32; 3],
    /// A face whose volume contains `point` (with the requested margin).
    pub face: u32,
    /// Whether the goal was reached.
    pub reached: bool,
    /// Whether the point moved at all.
    pub moved: bool,
}
