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

use super::face_cache::round_up_f32;
use super::{BoxProbe, FaceCache};
use crate::geom::{FaceEval, V3};
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
/// How many candidate faces of a cover step are ordered by their reach
/// bound (a face's neighbourhood rarely has more).
const SORTED_CANDIDATES: usize = 128;
/// How many faces of a tree leaf that pass a leaf search's box test are
/// gathered in one plain loop before the search (see
/// [`Vdg::leaf_cover_step`]); more than the sorted candidates, so the search
/// rarely reaches the lazily filtered rest.
const LEAF_HELD: usize = 256;

/// A cover step's bracket may stay this long (world units): far below a
/// face's extent, so hops stay few, and it costs about half the evaluations.
const COVER_TOL: f64 = 0.125;

/// How far short of the closed-form exit of a face (world units) a cover
/// first tries to certify its point: far above the rounding of an
/// evaluation, far below anything that matters.
const EXIT_BACKOFF: f64 = 1e-6;

/// A visibility trace gives up (answers "not visible") after this many hops.
const MAX_HOPS: usize = 4096;

/// The exact evaluations a cover step made, and how many it may make.
struct Evals {
    made: u32,
    limit: u32,
}

impl Evals {
    fn unlimited() -> Evals {
        Evals::at_most(u32::MAX)
    }

    fn at_most(limit: u32) -> Evals {
        Evals { made: 0, limit }
    }

    /// Counts one evaluation; `false` when the limit is reached (the
    /// evaluation must not be made).
    #[inline]
    fn take(&mut self) -> bool {
        if self.made >= self.limit {
            return false;
        }
        self.made += 1;
        true
    }
}

#[derive(Clone, Copy)]
struct Seg {
    s: V3,
    d: V3,
    len: f64,
    /// `1 / len`, for the many reach bounds of a cover.
    inv_len: f64,
}

impl Seg {
    fn new(s: V3, e: V3) -> Seg {
        let d = e - s;
        let len = d.norm();
        Seg {
            s,
            d,
            len,
            inv_len: 1.0 / len,
        }
    }
    #[inline]
    fn at(&self, t: f64) -> V3 {
        self.s + self.d * t
    }
}

/// How much work a sight-line test may do: face volumes crossed (`hops`)
/// and tree-leaf searches (`leaf_searches`, each worth a dozen hops; one
/// bridges the rare gap where no face sharing a vertex with the current one
/// continues the line). Both count down as a test spends them, so one
/// budget can bound several tests, e.g. all the tests of a camera update;
/// a test that runs out answers "not visible".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CoverBudget {
    pub hops: u32,
    pub leaf_searches: u32,
}

impl CoverBudget {
    /// No practical bound (what [`Vdg::visible`] uses).
    pub const UNBOUNDED: CoverBudget = CoverBudget {
        hops: MAX_HOPS as u32,
        leaf_searches: u32::MAX,
    };
}

/// Faces a hint remembers (a camera's sight lines cross a few).
const HINT_LEN: usize = 32;

/// What a step of a hinted cover that its hint does not guide costs of the
/// hop budget. A guided step evaluates one face; the search of the current
/// face's neighbourhood evaluates about ten, so counting it as one hop let
/// a camera update whose sight lines had all lost their way (the target
/// just moved behind a wall) do three times the work of a guided one.
const UNGUIDED_STEP_HOPS: u32 = 3;

/// How many faces of the old way a hinted cover step tries, nearest first,
/// before it searches the neighbourhood: the next one, and where the cover
/// strayed from the old way, the ones after it that may take it back.
const REJOIN_TRIES: usize = 3;

/// Where a sight line blocked last time counts as blocked again without a
/// tree-leaf search while the new blocking point is this close (units).
const DEAD_END_RADIUS: f64 = 4.0;

/// The way an earlier cover took, for a caller that tests nearly the same
/// segment again and again (a camera candidate's sight line, frame after
/// frame): the faces it crossed and where it found no way on. Start with
/// [`CoverHint::default`]; a hint never changes an answer's certainty, only
/// how fast it is found.
#[derive(Clone, Copy, Debug)]
pub struct CoverHint {
    chain: [u32; HINT_LEN],
    len: usize,
    dead_end: Option<[f32; 3]>,
}

impl Default for CoverHint {
    fn default() -> Self {
        CoverHint {
            chain: [0; HINT_LEN],
            len: 0,
            dead_end: None,
        }
    }
}

impl CoverHint {
    fn restart(&mut self, first: u32) {
        self.chain[0] = first;
        self.len = 1;
        self.dead_end = None;
    }

    fn push(&mut self, f: u32) {
        if self.len < HINT_LEN {
            self.chain[self.len] = f;
            self.len += 1;
        }
    }

    /// The faces the earlier cover took after `f`, nearest first, when `f`
    /// is on its way; else the ones after `from`, the place on the way the
    /// cover last matched: a cover that left the old way for a face of its
    /// own usually meets it again a face or two later.
    fn ahead_of(&self, f: u32, from: usize) -> (usize, &[u32]) {
        let way = &self.chain[..self.len];
        let at = way.iter().position(|&g| g == f).unwrap_or(from);
        (at + 1, way.get(at + 1..).unwrap_or(&[]))
    }

    fn dead_end_near(&self, p: V3) -> bool {
        self.dead_end
            .is_some_and(|d| (V3::from_f32(d) - p).norm() < DEAD_END_RADIUS)
    }
}

impl<'a> Vdg<'a> {
    /// Largest `t ∈ [lo, 1]` found with clearance of `at(t)` for face `f`
    /// (set up as `fe`) above `eps`, given that `at(lo)` is above it.
    ///
    /// The exit comes in closed form and the point returned is certified
    /// by an evaluation ([`exit_with`]), so the answer is right however
    /// rounding treats the closed form. `tol` is the bracket's stopping
    /// length (world units) when rounding spoils the closed form: a cover
    /// step only needs to know roughly where a face ends (the next face
    /// takes over from a certified point either way), so it stops early;
    /// points handed back to callers use the fine tolerance.
    fn exit_param(&self, fe: &FaceEval, f: u32, seg: &Seg, lo: f64, eps: f64, tol: f64) -> f64 {
        let g_lo = fe.eval(seg.at(lo)) - eps;
        exit_with(fe, seg, lo, g_lo, self.reach_bound(f, seg), eps, tol)
    }

    /// An upper bound on the parameter of any point of the segment inside
    /// face `f`'s volume. The volume is the convex hull of the three vertex
    /// balls, so its extent along the segment's direction is the largest of
    /// `(P(v) − s)·d̂ + r(v)`: three dot products, no square root, and a
    /// face that cannot beat the current reach is dropped without one
    /// clearance evaluation.
    #[inline]
    fn reach_bound(&self, f: u32, seg: &Seg) -> f64 {
        if seg.len.is_nan() || seg.len <= 0.0 {
            return f64::INFINITY;
        }
        // Scaled by the length, so one multiplication by its inverse at
        // the end instead of a division per vertex.
        let mut scaled = f64::NEG_INFINITY;
        let radii = self.face_radii(f);
        for (v, r) in self.faces.get(f).into_iter().zip(radii) {
            let vx = self.vertices[v as usize];
            let x = (V3::from_f32(vx.pos) - seg.s).dot(seg.d) + f64::from(r) * seg.len;
            scaled = if x > scaled { x } else { scaled };
        }
        let best = scaled * seg.inv_len;
        // Slack for the f32 data and f64 rounding of the evaluations.
        (best + 1e-6 * (1.0 + best.abs())) * seg.inv_len
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
        // The face set up once for all its evaluations.
        let fe = self.face_eval(face);
        if fe.eval(seg.s) <= TRACE_MARGIN {
            return s;
        }
        let mut t = self.exit_param(&fe, face, &seg, 0.0, TRACE_MARGIN, BISECT_TOL);
        if t >= 1.0 {
            return e;
        }
        // Rounding to f32 may move the point by half an ulp; back off until
        // the rounded point is certified inside.
        loop {
            let p = seg.at(t).to_f32();
            if t == 0.0 || fe.eval(V3::from_f32(p)) > 0.0 {
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
        let mut evals = Evals::unlimited();
        match self.best_cover_step(start.iter(), None, &seg, 0.0, INSIDE_EPS, None, &mut evals) {
            Some((f, t)) => {
                let mut budget = CoverBudget::UNBOUNDED;
                t >= 1.0 || self.cover(f, &seg, t, INSIDE_EPS, &mut budget).1 >= 1.0
            }
            None => false,
        }
    }

    /// `Visible(s, e, f)` (thesis 3.9) with a known face `face` whose volume
    /// contains `s` (e.g. from [`Self::track`]). `false` if it does not.
    /// Panics if `face` is out of range.
    pub fn visible_from(&self, face: u32, s: [f32; 3], e: [f32; 3]) -> bool {
        let mut budget = CoverBudget::UNBOUNDED;
        self.visible_within(face, s, e, &mut budget)
    }

    /// [`Self::visible_from`] spending at most `budget` (and counting it
    /// down): "not visible" when the budget runs out first. A per-frame
    /// caller bounds its worst case this way.
    ///
    /// ```
    /// # let mut b = vdgformat::VdgBuilder::new();
    /// # let v = [b.add_vertex([0., 0., 0.], 10.), b.add_vertex([100., 0., 0.], 10.), b.add_vertex([0., 100., 0.], 10.)];
    /// # b.add_face(v);
    /// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
    /// use vdgformat::CoverBudget;
    /// let g = file.graph();
    /// let mut budget = CoverBudget { hops: 8, leaf_searches: 1 };
    /// assert!(g.visible_within(0, [1.0, 1.0, 0.0], [90.0, 1.0, 0.0], &mut budget));
    /// ```
    pub fn visible_within(
        &self,
        face: u32,
        s: [f32; 3],
        e: [f32; 3],
        budget: &mut CoverBudget,
    ) -> bool {
        self.visible_hinted(face, s, e, budget, None)
    }

    /// [`Self::visible_within`] guided by (and updating) the hint of a
    /// similar earlier test: the same answers' certainty, found faster when
    /// the segment moved little. A step the hint does not guide (a search
    /// of the neighbourhood, about ten face evaluations) costs three hops
    /// of `budget`, a guided one one.
    pub fn visible_hinted(
        &self,
        face: u32,
        s: [f32; 3],
        e: [f32; 3],
        budget: &mut CoverBudget,
        hint: Option<&mut CoverHint>,
    ) -> bool {
        self.visible_hinted_cached(face, s, e, budget, hint, None, u32::MAX)
    }

    /// [`Self::visible_hinted`] with a caller's [`FaceCache`] of the graph
    /// (a camera's): cheaper tree-leaf searches and face set-ups, the same
    /// answers; a searching step makes at most `step_evals` exact
    /// evaluations (see [`Self::cover_hinted`]; `u32::MAX`: no limit).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn visible_hinted_cached(
        &self,
        face: u32,
        s: [f32; 3],
        e: [f32; 3],
        budget: &mut CoverBudget,
        hint: Option<&mut CoverHint>,
        cache: Option<&FaceCache>,
        step_evals: u32,
    ) -> bool {
        let seg = Seg::new(V3::from_f32(s), V3::from_f32(e));
        // The face once, from the memo when there is one; `None` when the
        // start is not inside it.
        let exit = self.with_face(cache, face, |fe| {
            let g_start = fe.eval(seg.s);
            if g_start <= INSIDE_EPS {
                return None;
            }
            // `exit_param` from 0, whose point is the start (to the bit, but
            // for the sign of a zero).
            let at0 = seg.at(0.0);
            let same = [(at0.0, seg.s.0), (at0.1, seg.s.1), (at0.2, seg.s.2)]
                .iter()
                .all(|(a, b)| a.to_bits() == b.to_bits());
            let g0 = if same { g_start } else { fe.eval(at0) };
            Some(exit_with(
                fe,
                &seg,
                0.0,
                g0 - INSIDE_EPS,
                self.reach_bound(face, &seg),
                INSIDE_EPS,
                BISECT_TOL,
            ))
        });
        let Some(t) = exit else {
            return false;
        };
        if t >= 1.0 {
            if let Some(h) = hint {
                h.restart(face);
            }
            return true;
        }
        self.cover_hinted(face, &seg, t, INSIDE_EPS, budget, hint, cache, step_evals)
            .1
            >= 1.0
    }

    /// Runs `use_face` on face `f`'s clearance function, from `cache`'s
    /// memo when there is one.
    #[inline]
    fn with_face<R>(
        &self,
        cache: Option<&FaceCache>,
        f: u32,
        use_face: impl FnOnce(&FaceEval) -> R,
    ) -> R {
        match cache {
            Some(c) => c.with_face(self, f, use_face),
            None => use_face(&self.face_eval(f)),
        }
    }

    /// Among `candidates` whose volume contains `at(t)`, the one reaching
    /// farthest along the segment, with that reach; `None` if none contains
    /// `at(t)`. Candidates that cannot beat the best so far cost one
    /// evaluation: their interval holds `at(t)`, so if it misses
    /// `at(best)` it ends before `best`.
    ///
    /// `skip` is a face whose exit `t` already is (the current face of a
    /// cover): searching it again would only find `t` once more. `cache`,
    /// when given, saves setting up the clearance functions of faces
    /// evaluated recently.
    #[allow(clippy::too_many_arguments)]
    fn best_cover_step(
        &self,
        candidates: impl Iterator<Item = u32>,
        skip: Option<u32>,
        seg: &Seg,
        t: f64,
        eps: f64,
        cache: Option<&FaceCache>,
        evals: &mut Evals,
    ) -> Option<(u32, f64)> {
        self.best_cover_step_where(candidates, skip, seg, t, eps, cache, evals, |_| true)
    }

    /// [`Self::best_cover_step`] that passes over the candidates `may_hold`
    /// proves do not hold `at(t)` (their stored box misses it) without
    /// bounding or sorting them: they could never have won, and they still
    /// count towards the sorted buffer, so the others are taken in the same
    /// order and the answer is the same. `evals` counts the exact
    /// evaluations and ends the search at its limit (see [`Evals`]).
    #[allow(clippy::too_many_arguments)]
    fn best_cover_step_where(
        &self,
        candidates: impl Iterator<Item = u32>,
        skip: Option<u32>,
        seg: &Seg,
        t: f64,
        eps: f64,
        cache: Option<&FaceCache>,
        evals: &mut Evals,
        may_hold: impl Fn(u32) -> bool,
    ) -> Option<(u32, f64)> {
        // Candidates by their reach bound, best first: the first exact exit
        // search usually settles the step and the bound cuts off the rest.
        // Each candidate is one integer — the bound rounded up to f32 (still
        // a bound) in its order-preserving bits, then the complemented face
        // index — so the sort is a plain integer sort: descending, that is
        // by bound, then by ascending face index, and the copies of a face
        // sharing two vertices with the current one come side by side.
        // (More candidates than the buffer holds are taken unsorted after.)
        let mut buf = [0u64; SORTED_CANDIDATES];
        let mut n = 0;
        let mut taken = 0;
        let mut rest = candidates.peekable();
        while taken < SORTED_CANDIDATES {
            let Some(f) = rest.next() else { break };
            if Some(f) == skip {
                continue;
            }
            taken += 1;
            if !may_hold(f) {
                continue;
            }
            let ub = self.reach_bound(f, seg);
            buf[n] = (u64::from(f32_order_bits(round_up_f32(ub))) << 32) | u64::from(!f);
            n += 1;
        }
        buf[..n].sort_unstable();
        let here = seg.at(t);
        let mut best: Option<(u32, f64)> = None;
        let mut previous = None;
        for &key in buf[..n].iter().rev() {
            if previous.replace(key) == Some(key) {
                continue;
            }
            let reach = best.map_or(t, |b| b.1);
            if reach >= 1.0 {
                return best;
            }
            let ub = f64::from(f32_from_order_bits((key >> 32) as u32));
            if ub <= reach {
                // Sorted: no later candidate can reach farther.
                break;
            }
            if !evals.take() {
                return best;
            }
            self.try_cover_candidate(!(key as u32), ub, seg, t, here, eps, cache, &mut best);
        }
        for f in rest {
            let reach = best.map_or(t, |b| b.1);
            if reach >= 1.0 {
                break;
            }
            if !may_hold(f) {
                continue;
            }
            let ub = self.reach_bound(f, seg);
            if ub > reach && Some(f) != skip {
                if !evals.take() {
                    break;
                }
                self.try_cover_candidate(f, ub, seg, t, here, eps, cache, &mut best);
            }
        }
        best
    }

    /// One candidate of [`Self::best_cover_step`] with reach bound `ub`:
    /// makes it the best when it holds `here` (= `at(t)`) and the current
    /// reach and goes farther.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn try_cover_candidate(
        &self,
        f: u32,
        ub: f64,
        seg: &Seg,
        t: f64,
        here: V3,
        eps: f64,
        cache: Option<&FaceCache>,
        best: &mut Option<(u32, f64)>,
    ) {
        // The best one never helps again.
        if best.is_some_and(|b| b.0 == f) {
            return;
        }

        let reach = best.map_or(t, |b| b.1);
        // The clearance at `reach`: the face must hold both that point and
        // `here` to extend the cover.
        let at_reach = seg.at(reach);
        let exit = self.with_face(cache, f, |fe| {
            let g_reach = fe.eval_above(at_reach, eps) - eps;
            if g_reach <= 0.0 || (reach > t && fe.eval_above(here, eps) <= eps) {
                return None;
            }
            Some(exit_with(fe, seg, reach, g_reach, ub, eps, COVER_TOL))
        });
        if let Some(exit) = exit
            && best.is_none_or(|b| exit > b.1)
        {
            *best = Some((f, exit));
        }
    }

    /// Extends a cover `[0, t]` ending in face `cur` as far along the segment
    /// as it goes, with every point certified above clearance `eps`:
    /// neighbours of the current face first (the thesis' recursion, kept
    /// greedy: the neighbour reaching farthest), and the faces of the tree
    /// leaf at the cover's end when no neighbour helps. Returns the last face
    /// and the reach (`>= 1.0` when the whole segment is covered). Leaf
    /// searches and hops count `budget` down; the cover stops when it is
    /// spent.
    fn cover(&self, cur: u32, seg: &Seg, t: f64, eps: f64, budget: &mut CoverBudget) -> (u32, f64) {
        self.cover_hinted(cur, seg, t, eps, budget, None, None, u32::MAX)
    }

    /// [`Self::cover`] that first tries the way a similar earlier cover
    /// took (`hint`) and records its own way there for the next one. A
    /// hinted step costs one exit search instead of a search over the whole
    /// neighbourhood; any face that continues the line is as good a proof
    /// as the farthest-reaching one. A leaf search is skipped where the
    /// hinted cover already found no way on (a camera's sight line blocked
    /// at the same place frame after frame). `cache`, when given, makes
    /// leaf searches and face set-ups cheap. A step that searches for a way
    /// on makes at most `step_evals` exact evaluations and then takes the
    /// farthest step it has proved, or none: the hop budget bounds how many
    /// steps a cover takes, this what one step costs where hundreds of face
    /// volumes overlap. A limited cover can only end short, so a sight line
    /// can only turn "not visible", never "visible". (Only faces actually
    /// evaluated count: with a cache, those whose box misses the point are
    /// passed over free, so a limit binds later than without one.)
    #[allow(clippy::too_many_arguments)]
    fn cover_hinted(
        &self,
        mut cur: u32,
        seg: &Seg,
        mut t: f64,
        eps: f64,
        budget: &mut CoverBudget,
        mut hint: Option<&mut CoverHint>,
        cache: Option<&FaceCache>,
        step_evals: u32,
    ) -> (u32, f64) {
        // A hop must gain at least this much (a thousandth of a unit), so
        // the hop limit bounds the work; smaller gains end the cover.
        let min_gain = if seg.len > 0.0 { 1e-3 / seg.len } else { 0.0 };
        let old = hint.as_deref().copied();
        if let Some(h) = hint.as_deref_mut() {
            h.restart(cur);
        }
        // Where on the old way the cover last was (an index into its faces).
        let mut on_way = 0;
        while budget.hops > 0 {
            budget.hops -= 1;
            let here = seg.at(t);
            let mut step = None;
            if let Some(o) = old.as_ref() {
                let (first, ahead) = o.ahead_of(cur, on_way);
                for (i, &f) in ahead.iter().enumerate().take(REJOIN_TRIES) {
                    step = self
                        .hinted_step(f, seg, t, here, eps, cache)
                        .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
                    if step.is_some() {
                        on_way = first + i;
                        break;
                    }
                }
            }
            if step.is_none() {
                if old.is_some() {
                    budget.hops = budget.hops.saturating_sub(UNGUIDED_STEP_HOPS - 1);
                }
                // With a cache, faces whose stored box misses `here` are
                // passed over unbounded (most of an open map's big
                // neighbourhoods).
                let probe = BoxProbe::at(here);
                let mut evals = Evals::at_most(step_evals);
                step = self
                    .best_cover_step_where(
                        self.neighbourhood(cur),
                        Some(cur),
                        seg,
                        t,
                        eps,
                        cache,
                        &mut evals,
                        |f| cache.is_none_or(|c| c.holds(f, &probe)),
                    )
                    .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
            }
            let dead_end = old.and_then(|o| o.dead_end.filter(|_| o.dead_end_near(here)));
            if step.is_none()
                && dead_end.is_some()
                && let Some(h) = hint.as_deref_mut()
            {
                // Kept where it was found: a blocking point that drifts
                // away gets a fresh search.
                h.dead_end = dead_end;
            }
            if step.is_none() && budget.leaf_searches > 0 && dead_end.is_none() {
                budget.leaf_searches -= 1;
                let mut evals = Evals::at_most(step_evals);
                step = self
                    .leaf_cover_step(cur, seg, t, here, eps, cache, &mut evals)
                    .filter(|&(_, r)| r >= 1.0 || r > t + min_gain);
                if step.is_none()
                    && let Some(h) = hint.as_deref_mut()
                {
                    h.dead_end = Some(here.to_f32());
                }
            }
            match step {
                Some((f, r)) => {
                    if let Some(h) = hint.as_deref_mut() {
                        h.push(f);
                    }
                    if r >= 1.0 {
                        return (f, 1.0);
                    }
                    cur = f;
                    t = r;
                }
                None => break,
            }
        }
        (cur, t)
    }

    /// [`Self::best_cover_step`] over the faces of the tree leaf at `here`
    /// (= `at(t)`) whose box holds it and that share no vertex with `cur`:
    /// the neighbourhood step just searched every face sharing a vertex
    /// with `cur` from this very point and none went far enough, so only
    /// the others can. The box test comes first: it rules out most of a
    /// leaf, which may hold hundreds of faces; the faces that pass it are
    /// gathered first in a plain loop, where the test is inlined, rather
    /// than filtered lazily, where it was a call per face (the same faces
    /// in the same order: the test has no side effects).
    #[allow(clippy::too_many_arguments)]
    fn leaf_cover_step(
        &self,
        cur: u32,
        seg: &Seg,
        t: f64,
        here: V3,
        eps: f64,
        cache: Option<&FaceCache>,
        evals: &mut Evals,
    ) -> Option<(u32, f64)> {
        let corners = self.faces.get(cur);
        let apart = |f: u32| !self.faces.get(f).iter().any(|v| corners.contains(v));
        let probe = BoxProbe::at(here);
        let holds = |f: u32| match cache {
            Some(c) => c.holds(f, &probe),
            None => self.box_holds(f, here),
        };
        let mut held = [0u32; LEAF_HELD];
        let mut n = 0;
        let mut leaf = self.leaf_faces_at(here).iter();
        for f in leaf.by_ref() {
            if holds(f) && apart(f) {
                held[n] = f;
                n += 1;
                if n == LEAF_HELD {
                    break;
                }
            }
        }
        // The rest of a leaf holding more (none seen yet) lazily, after.
        let holding = held[..n]
            .iter()
            .copied()
            .chain(leaf.filter(|&f| holds(f) && apart(f)));
        self.best_cover_step(holding, Some(cur), seg, t, eps, cache, evals)
    }

    /// The reach of face `f` along the segment from `at(t)` (= `here`), if
    /// its volume holds `here`.
    fn hinted_step(
        &self,
        f: u32,
        seg: &Seg,
        t: f64,
        here: V3,
        eps: f64,
        cache: Option<&FaceCache>,
    ) -> Option<(u32, f64)> {
        let in_box = match cache {
            Some(c) => c.holds(f, &BoxProbe::at(here)),
            None => self.box_holds(f, here),
        };
        if !in_box {
            return None;
        }
        self.with_face(cache, f, |fe| {
            let at = fe.eval_above(here, eps);
            if at <= eps {
                return None;
            }
            let ub = self.reach_bound(f, seg);
            Some((f, exit_with(fe, seg, t, at - eps, ub, eps, COVER_TOL)))
        })
    }

    /// The face and every face sharing a vertex with it (thesis:
    /// Neighbours(f)), without collecting them; faces sharing an edge come
    /// more than once.
    #[inline]
    pub(crate) fn neighbourhood(&self, f: u32) -> impl Iterator<Item = u32> + '_ {
        std::iter::once(f).chain(
            self.faces
                .get(f)
                .into_iter()
                .flat_map(|v| self.vertex_faces(v).iter())
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
        let mut budget = CoverBudget {
            hops: max_hops,
            leaf_searches: u32::MAX,
        };
        self.advance_tol(
            face,
            from,
            to,
            margin,
            &mut budget,
            BISECT_TOL,
            None,
            None,
            u32::MAX,
        )
    }

    /// [`Self::advance`] stopping within `tol` units of the boundary (the
    /// point is certified either way; a camera does not need to touch the
    /// boundary to a thousandth of a unit), crossing face volumes within
    /// `budget` (counted down), guided by (and updating) `hint` as
    /// [`Self::visible_hinted`] is.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn advance_tol(
        &self,
        face: u32,
        from: [f32; 3],
        to: [f32; 3],
        margin: f32,
        budget: &mut CoverBudget,
        tol: f64,
        hint: Option<&mut CoverHint>,
        cache: Option<&FaceCache>,
        step_evals: u32,
    ) -> Advance {
        let eps = f64::from(margin).max(0.0) + TRACE_MARGIN;
        let seg = Seg::new(V3::from_f32(from), V3::from_f32(to));
        let stay = Advance {
            point: from,
            face,
            reached: from == to,
            moved: false,
        };
        // The start face set up once (from the memo when there is one) for
        // its clearance at the start and its exit.
        let exit = self.with_face(cache, face, |fe| {
            let here = fe.eval(seg.s);
            if here.is_nan() || here <= eps || !seg.len.is_finite() {
                return None;
            }
            Some(self.exit_param(fe, face, &seg, 0.0, eps, tol))
        });
        let Some(mut t) = exit else {
            return stay;
        };
        let mut t0 = 0.0;
        let mut cur = face;
        if t < 1.0 && budget.hops > 0 {
            // The cover's last hop starts where the previous face ended;
            // remember that start so a rounding back-off stays in `cur`.
            let (f, r) = self.cover_hinted(face, &seg, t, eps, budget, hint, cache, step_evals);
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
            let clear = self.with_face(cache, cur, |fe| fe.eval(V3::from_f32(p)));
            if clear > f64::from(margin).max(0.0) {
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
        let corners = self.faces.get(face);
        let [a, b, c] = corners;
        // The union of the corners' neighbours and the corners, ascending:
        // a merge of four sorted lists.
        let mut lists = [a, b, c].map(|v| self.vertex_neighbours(v).iter().peekable());
        let mut own = corners;
        own.sort_unstable();
        let mut own = own.into_iter().peekable();
        loop {
            let next = lists
                .iter_mut()
                .filter_map(|l| l.peek().copied())
                .chain(own.peek().copied())
                .min();
            let Some(v) = next else { break };
            for l in &mut lists {
                if l.peek() == Some(&v) {
                    l.next();
                }
            }
            if own.peek() == Some(&v) {
                own.next();
            }
            // A face volume is convex: if one of v's faces in the region
            // holds p, the segment p–P(v) lies in it (P(v) is inside every
            // face of v, with clearance r(v)). Only the rest need a cover.
            if corners.contains(&v)
                || self.vertex_face_holds(face, v, start)
                || (exact && self.segment_in_region(face, start, self.pos(v)))
            {
                visit(v);
            }
        }
    }

    /// The vertices [`Self::for_each_local_vertex`] visits without `exact`,
    /// appended to `out` in ascending order, for a caller with a
    /// [`FaceCache`] (a camera). A neighbour of the face's corners is
    /// visited when a face of the region (the faces sharing a vertex with
    /// `face`) that holds it also holds `p`, and every vertex of a region
    /// face is a corner or a corner's neighbour: so the answer is the
    /// corners and the vertices of the region faces that hold `p`, each
    /// region face tested once (a neighbour's test asked the same faces up
    /// to three times) with the stored boxes culling and the memo setting
    /// faces up; the cache's vertex set keeps each vertex once.
    pub(crate) fn local_vertices_cached(
        &self,
        cache: &FaceCache,
        p: [f32; 3],
        face: u32,
        out: &mut Vec<u32>,
    ) {
        let start = V3::from_f32(p);
        let first = out.len();
        cache.new_vertex_set();
        out.extend(self.faces.get(face).into_iter().filter(|&v| cache.take(v)));
        self.for_face_and_neighbours_once(face, |g| {
            let holds =
                cache.box_bound(g, start).is_none() && cache.fc(self, g, start) > INSIDE_EPS;
            if holds {
                out.extend(self.faces.get(g).into_iter().filter(|&v| cache.take(v)));
            }
        });
        out[first..].sort_unstable();
    }

    /// Whether some face of `v` that belongs to the region of `face` (shares
    /// a vertex with it) holds `p` with clearance above the certificate's
    /// margin.
    fn vertex_face_holds(&self, face: u32, v: u32, p: V3) -> bool {
        let corners = self.faces.get(face);
        self.vertex_faces(v).iter().any(|g| {
            self.faces.get(g).iter().any(|c| corners.contains(c))
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
                .best_cover_step(
                    self.neighbourhood(face),
                    None,
                    &seg,
                    t,
                    INSIDE_EPS,
                    None,
                    &mut Evals::unlimited(),
                )
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

/// The bits of an f32 as an unsigned integer in the order of the numbers
/// (negative numbers complemented, positive ones with the sign bit set).
#[inline]
fn f32_order_bits(x: f32) -> u32 {
    let b = x.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
    }
}

/// The inverse of [`f32_order_bits`].
#[inline]
fn f32_from_order_bits(b: u32) -> f32 {
    f32::from_bits(if b & 0x8000_0000 != 0 {
        b & 0x7fff_ffff
    } else {
        !b
    })
}

/// The exit search of [`Vdg::exit_param`] for the face of `fe`, with
/// the value at `lo` (`g_lo`, minus `eps`) already known and the bracket's
/// far end at the reach bound `ub` instead of the segment's end when that is
/// closer.
///
/// The exit comes in closed form ([`FaceEval::line_exit`]); the point kept
/// is a little before it (half the tolerance, or half the way from `lo`) and
/// certified by one evaluation. Only when rounding spoils the closed form
/// (a line grazing the volume) does the search fall back on regula falsi.
fn exit_with(fe: &FaceEval, seg: &Seg, lo: f64, g_lo: f64, ub: f64, eps: f64, tol: f64) -> f64 {
    let hi = ub.min(1.0);
    let tol = if seg.len > 0.0 { tol / seg.len } else { 1.0 };
    // Where the volume may hold the segment's end, one evaluation there
    // settles the commonest case (a short move or clamp inside one face):
    // both ends above `eps`, so is everything between (the clearance along
    // a segment is concave), and the closed form is not needed.
    let g_end = if ub >= 1.0 && g_lo > 0.0 {
        let g = fe.eval(seg.at(1.0)) - eps;
        if g > 0.0 {
            return 1.0;
        }
        Some(g)
    } else {
        None
    };
    let exit = fe.line_exit(seg.s, seg.d, eps);
    if exit >= hi {
        let g_hi = g_end.unwrap_or_else(|| fe.eval(seg.at(hi)) - eps);
        if g_hi > 0.0 {
            return hi;
        }
        return regula_falsi(fe, seg, lo, g_lo, hi, g_hi, eps, tol);
    }
    if exit > lo && g_lo > 0.0 {
        // A millionth of a unit short of the exit is far above the
        // rounding of the evaluation wherever the line really crosses the
        // boundary; a grazing line gets a second, wider try.
        let near = if seg.len > 0.0 {
            EXIT_BACKOFF / seg.len
        } else {
            0.0
        };
        let mut hi_g = None;
        for back in [near, 0.5 * tol] {
            let t = exit - back.min(0.5 * (exit - lo));
            let g = fe.eval(seg.at(t)) - eps;
            if g > 0.0 {
                return t;
            }
            hi_g = Some((t, g));
        }
        let (t, g) = hi_g.expect("two tries");
        return regula_falsi(fe, seg, lo, g_lo, t, g, eps, tol);
    }
    // No exit past `lo` by the closed form (rounding, or a NaN): the
    // evaluated search decides.
    let g_hi = g_end.unwrap_or_else(|| fe.eval(seg.at(hi)) - eps);
    if g_hi > 0.0 {
        return hi;
    }
    regula_falsi(fe, seg, lo, g_lo, hi, g_hi, eps, tol)
}

/// Largest `t ∈ [lo, hi]` found with clearance above `eps`, given the
/// values `g_lo` (> 0, or `lo` comes back unchanged) and `g_hi` (≤ 0) minus
/// `eps` at the ends; stops when the bracket is shorter than `tol` (in
/// segment parameter).
///
/// The clearance along a segment is concave, so the crossing of `eps` is
/// bracketed by one point above and one below. Regula falsi with the
/// Illinois modification (the stale end's value is halved when the same
/// end moves twice) converges in a handful of evaluations where bisection
/// needs 20–40; every third step is a bisection all the same, so a kink in
/// the clearance cannot stall it. The bracket's low end is always a point
/// evaluated above `eps`, and that is what is returned: the answer stays
/// certified however the search ends.
#[allow(clippy::too_many_arguments)]
fn regula_falsi(
    fe: &FaceEval,
    seg: &Seg,
    lo: f64,
    g_lo: f64,
    hi: f64,
    g_hi: f64,
    eps: f64,
    tol: f64,
) -> f64 {
    let (mut lo, mut g_lo, mut hi, mut g_hi) = (lo, g_lo, hi, g_hi);
    if hi <= lo || g_lo <= 0.0 {
        // The caller's point was above eps by a bound, not by value: fall
        // back on it unchanged (bisection would also return `lo`).
        return lo;
    }
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
        let g = fe.eval(seg.at(mid)) - eps;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Ball;
    use crate::query::face_cache::tests::{random_sight_line, two_sheets};
    use toolbox::SplitMix64;

    /// `exit_with` on random faces and segments from a point inside: the
    /// parameter it returns is certified (clearance above `eps` there), and
    /// it is the segment's end exactly when the end is inside, else within
    /// the tolerance of the true exit (found by bisection on the concave
    /// clearance along the segment). Half the segments end inside the
    /// volume, where one evaluation at the end answers without the closed
    /// form; the other half leave it.
    #[test]
    fn the_exit_is_certified_and_the_end_is_taken_only_when_inside() {
        let mut rng = SplitMix64::new(41);
        let ball = |rng: &mut SplitMix64| Ball {
            c: V3(
                rng.range(-60.0, 60.0),
                rng.range(-60.0, 60.0),
                rng.range(-10.0, 10.0),
            ),
            r: rng.range(8.0, 40.0),
        };
        let (mut ends_inside, mut leaving) = (0, 0);
        for case in 0..4000 {
            let (a, b, c) = (ball(&mut rng), ball(&mut rng), ball(&mut rng));
            let fe = FaceEval::new(a, b, c);
            let eps = if case % 2 == 0 { INSIDE_EPS } else { 2.0 };
            // A start inside: a point of the triangle, lifted a little.
            let (u, v) = (rng.range(0.0, 1.0), rng.range(0.0, 1.0));
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let s = a.c + (b.c - a.c) * u + (c.c - a.c) * v + V3(0.0, 0.0, rng.range(-2.0, 2.0));
            let g0 = fe.eval(s) - eps;
            if g0 <= 0.0 {
                continue;
            }
            let reach = rng.range(1.0, 120.0);
            let dir = V3(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            let e = s + dir * (reach / dir.norm().max(1e-9));
            let seg = Seg::new(s, e);
            let ub = 2.0; // no bound: the end may be inside
            let t = exit_with(&fe, &seg, 0.0, g0, ub, eps, BISECT_TOL);
            assert!(
                fe.eval(seg.at(t)) - eps > 0.0,
                "case {case}: t = {t} not certified"
            );
            let end_inside = fe.eval(seg.at(1.0)) - eps > 0.0;
            if end_inside {
                ends_inside += 1;
                assert_eq!(t, 1.0, "case {case}: the end is inside");
                continue;
            }
            leaving += 1;
            // The true exit by bisection on [0, 1] (one crossing: concave).
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if fe.eval(seg.at(mid)) - eps > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let tol = BISECT_TOL / seg.len;
            assert!(
                t <= hi && t >= lo - 2.0 * tol,
                "case {case}: exit {t}, true exit {lo}..{hi} (tolerance {tol})"
            );
        }
        assert!(
            ends_inside > 500 && leaving > 500,
            "{ends_inside} / {leaving}"
        );
    }

    /// A fan of hundreds of faces around one vertex, all reaching about as
    /// far (a big open room: every face volume overlaps every other): a
    /// sight line out of it makes a neighbourhood search evaluate far more
    /// faces than the camera's limit (128) allows. The limited search stops there,
    /// and what it returns is still a certified step of the cover.
    #[test]
    fn a_searching_step_with_a_limit_evaluates_at_most_that_many_faces() {
        const LIMIT: u32 = 128;
        let mut b = crate::VdgBuilder::new();
        let n = 400;
        let centre = b.add_vertex([0.0, 0.0, 0.0], 120.0);
        let mut rng = SplitMix64::new(5);
        let ring: Vec<u32> = (0..n)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / n as f64;
                let r = rng.range(40.0, 60.0);
                let z = rng.range(-8.0, 8.0);
                b.add_vertex(
                    [(r * a.cos()) as f32, (r * a.sin()) as f32, z as f32],
                    rng.range(100.0, 120.0) as f32,
                )
            })
            .collect();
        for i in 0..n {
            b.add_face([centre, ring[i], ring[(i + 1) % n]]);
        }
        let bytes = b.to_bytes().unwrap();
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut most = 0;
        let mut limited = 0;
        for k in 0..200 {
            let a = k as f64 * 0.37;
            let seg = Seg::new(
                V3(1.0, 2.0, 3.0),
                V3(900.0 * a.cos(), 900.0 * a.sin(), rng.range(-400.0, 400.0)),
            );
            let search = |evals: &mut Evals| {
                g.best_cover_step(
                    g.neighbourhood(0),
                    Some(0),
                    &seg,
                    0.0,
                    INSIDE_EPS,
                    None,
                    evals,
                )
            };
            let mut free = Evals::unlimited();
            let full = search(&mut free);
            let mut capped = Evals::at_most(LIMIT);
            let step = search(&mut capped);
            most = most.max(free.made);
            assert!(capped.made <= LIMIT, "{} evaluations", capped.made);
            if free.made > LIMIT {
                limited += 1;
            } else {
                assert_eq!(step, full, "a search under the limit must not change");
            }
            // Whatever it returns, the step's face holds the segment from
            // its start to the reach it claims.
            if let Some((f, r)) = step {
                let fe = g.face_eval(f);
                for i in 0..=20 {
                    let p = seg.at(r.min(1.0) * f64::from(i) / 20.0);
                    assert!(fe.eval(p) > 0.0, "face {f} does not hold {p:?}");
                }
            }
        }
        assert!(
            limited > 10,
            "only {limited} searches over the limit (at most {most} evaluations): the fan shows nothing"
        );
    }

    /// A sight line tested again with its hint, where the hint's way has a
    /// stray face after the first one (as when last frame's cover took a
    /// face of its own there): the cover skips it and follows the rest of
    /// the old way, guided, spending the hops the true way costs and giving
    /// the same answer. Taking the stray face's place as the end of the
    /// guidance would cost an unguided search of the neighbourhood (three
    /// hops) and every step after it.
    #[test]
    fn a_hinted_cover_that_strays_from_the_old_way_rejoins_it() {
        let bytes = two_sheets(16);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut rng = SplitMix64::new(13);
        let mut rejoined = 0;
        for _ in 0..3000 {
            let (f, s, e) = random_sight_line(&g, &mut rng, 0.0);
            let start = CoverBudget {
                hops: 64,
                leaf_searches: 4,
            };
            let mut hint = CoverHint::default();
            let mut unbounded = CoverBudget::UNBOUNDED;
            g.visible_hinted(f, s, e, &mut unbounded, Some(&mut hint));
            if hint.len < 3 || hint.len == HINT_LEN {
                continue;
            }
            // A face whose box is far from the whole segment: it never
            // continues the line.
            let stray = (0..g.face_count() as u32)
                .map(|k| (f + 97 * k + 1) % g.face_count() as u32)
                .find(|&k| {
                    [0.0, 0.25, 0.5, 0.75, 1.0].iter().all(|&t| {
                        let p = V3::from_f32(s) + (V3::from_f32(e) - V3::from_f32(s)) * t;
                        !g.box_holds(k, p)
                    }) && !hint.chain[..hint.len].contains(&k)
                });
            let Some(stray) = stray else { continue };
            let mut strayed = hint;
            strayed.chain.copy_within(1..hint.len, 2);
            strayed.chain[1] = stray;
            strayed.len += 1;
            let (mut guided, mut rejoining) = (start, start);
            let mut h1 = hint;
            let a1 = g.visible_hinted(f, s, e, &mut guided, Some(&mut h1));
            let a2 = g.visible_hinted(f, s, e, &mut rejoining, Some(&mut strayed));
            assert_eq!(a1, a2, "{s:?} -> {e:?}");
            assert_eq!(guided, rejoining, "{s:?} -> {e:?}: hops spent differ");
            rejoined += 1;
        }
        assert!(
            rejoined > 300,
            "only {rejoined} covers of three faces or more"
        );
    }
}
