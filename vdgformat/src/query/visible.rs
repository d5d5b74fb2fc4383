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
        let tol = if seg.len > 0.0 {
            BISECT_TOL / seg.len
        } else {
            1.0
        };
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
        match self.best_cover_step(start.iter().copied(), &seg, 0.0) {
            Some((f, t)) => t >= 1.0 || self.cover_from(f, &seg, t),
            None => false,
        }
    }

    /// `Visible(s, e, f)` (thesis 3.9) with a known face `face` whose volume
    /// contains `s` (e.g. from [`Self::track`]). `false` if it does not.
    /// Panics if `face` is out of range.
    pub fn visible_from(&self, face: u32, s: [f32; 3], e: [f32; 3]) -> bool {
        let seg = Seg::new(V3::from_f32(s), V3::from_f32(e));
        if self.fc(face, seg.s) <= INSIDE_EPS {
            return false;
        }
        let t = self.exit_param(face, &seg, 0.0, INSIDE_EPS);
        t >= 1.0 || self.cover_from(face, &seg, t)
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
    ) -> Option<(u32, f64)> {
        let here = seg.at(t);
        let mut best: Option<(u32, f64)> = None;
        for f in candidates {
            let reach = best.map_or(t, |b| b.1);
            if reach >= 1.0 {
                break;
            }
            if reach > t && self.fc_above(f, seg.at(reach), INSIDE_EPS) <= INSIDE_EPS {
                continue;
            }
            if self.fc_above(f, here, INSIDE_EPS) <= INSIDE_EPS {
                continue;
            }
            let exit = self.exit_param(f, seg, reach, INSIDE_EPS);
            if best.is_none_or(|b| exit > b.1) {
                best = Some((f, exit));
            }
        }
        best
    }

    /// Extends a cover `[0, t]` ending in face `cur` to the end of the
    /// segment: neighbours of the current face first (the thesis'
    /// recursion, kept greedy: the neighbour reaching farthest), and the
    /// faces of the tree leaf at the cover's end when no neighbour helps.
    fn cover_from(&self, mut cur: u32, seg: &Seg, mut t: f64) -> bool {
        // A hop must gain at least this much (a thousandth of a unit), so
        // the hop limit bounds the work; smaller gains answer "not visible".
        let min_gain = if seg.len > 0.0 { 1e-3 / seg.len } else { 0.0 };
        for _ in 0..MAX_HOPS {
            // The face and every face sharing a vertex with it (thesis:
            // Neighbours(f)), without collecting them.
            let neighbours = std::iter::once(cur).chain(
                self.faces[cur as usize]
                    .into_iter()
                    .flat_map(|v| self.vertex_faces(v).iter().copied())
                    .filter(move |&g| g != cur),
            );
            let mut step = self
                .best_cover_step(neighbours, seg, t)
                .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
            if step.is_none() {
                let leaf = self.leaf_faces_at(seg.at(t));
                step = self
                    .best_cover_step(leaf.iter().copied(), seg, t)
                    .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
            }
            match step {
                Some((_, r)) if r >= 1.0 => return true,
                Some((f, r)) => {
                    cur = f;
                    t = r;
                }
                None => return false,
            }
        }
        false
    }

    /// `Reachable(p, f)` (thesis 5.3): the vertices of `face` and their
    /// neighbours that can be reached from `p` on a straight line inside the
    /// volume of `face` and its neighbour faces. Ascending vertex indices.
    /// Panics if `face` is out of range.
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
        let mut region = Vec::with_capacity(64);
        self.for_face_and_neighbours(face, |f| region.push(f));
        region.sort_unstable();
        region.dedup();
        let mut candidates: Vec<u32> = Vec::with_capacity(64);
        for &v in &self.faces[face as usize] {
            candidates.push(v);
            candidates.extend_from_slice(self.vertex_neighbours(v));
        }
        candidates.sort_unstable();
        candidates.dedup();
        let start = V3::from_f32(p);
        candidates.retain(|&v| {
            let seg = Seg::new(start, self.pos(v));
            let mut t = 0.0;
            for _ in 0..MAX_HOPS {
                match self
                    .best_cover_step(region.iter().copied(), &seg, t)
                    .filter(|&(_, r)| r > t || r >= 1.0)
                {
                    Some((_, r)) if r >= 1.0 => return true,
                    Some((_, r)) => t = r,
                    None => return false,
                }
            }
            false
        });
        candidates
    }
}
