//! The candidates of one update (thesis 5.2, 5.3): k_dist, k_angle,
//! k_inertia from the current configuration; k_clear, k_vis, k_neighb from
//! the reachable vertices; ours, k_path, while the target is hidden; each
//! clamped into the free volume, then their cost-weighted recombination
//! k_comb, and the cheapest chosen.

use super::motion::{CLAMP_TOL, MARGIN_SLACK};
use super::sight::STEP_EVALS;
use super::types::Ahead;
use super::{Camera, CandidateDebug, Costs, Scene, Slot, State};
use crate::geom::V3;
use crate::query::CoverBudget;
use crate::read::Vdg;

/// Which criterion a candidate stands for (thesis 5.2/5.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CandidateKind {
    /// The camera moved along target→camera to the ideal distance.
    #[default]
    Dist,
    /// The camera rotated about the target by a quarter of the way to a_n.
    Angle,
    /// Where inertia alone carries the camera.
    Inertia,
    /// The reachable vertex of least f_clear.
    Clear,
    /// The reachable vertex of least f_vis.
    Vis,
    /// The reachable vertex of least f_total.
    Neighb,
    /// Ours, while the target is hidden: a point further along the
    /// shortest way through the graph to the target (the distance field's
    /// descent from the reachable vertex nearest the target by VDistance).
    Path,
    /// The cost-weighted mean of the others.
    Comb,
}

/// Scratch for the reachable vertices of one frame (sized once per graph).
#[derive(Debug, Default)]
pub(super) struct Scratch {
    pub(super) reach: Vec<u32>,
    /// (sort key, index into `reach`).
    pub(super) order: Vec<(f64, u32)>,
    /// Per reachable vertex: cost terms without visibility, VDistance, and
    /// visibility (-1 unknown, 0 no, 1 yes).
    pub(super) base: Vec<f64>,
    pub(super) vd: Vec<f64>,
    pub(super) vis: Vec<i8>,
    /// Per graph vertex: the last line-of-sight answer to the target and
    /// where the target was then (see [`CameraParams::vertex_tests`](super::CameraParams::vertex_tests)).
    pub(super) memo: Vec<VisMemo>,
    /// Fresh vertex tests left in this update.
    pub(super) fresh_left: u32,
}

/// A remembered Visible(P(v), t).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct VisMemo {
    pub(super) target: [f32; 3],
    pub(super) visible: bool,
    pub(super) known: bool,
}

/// A vertex's remembered answer is reused without a test while the target
/// stays this close (units) to where it was tested: about four frames of
/// running at 60 Hz, two at 30 Hz.
const MEMO_FRESH: f64 = 16.0;

/// Past this distance (units) from where it was tested, a remembered answer
/// says nothing (a teleport, a long gap): the vertex counts as unknown
/// when the update's fresh tests are spent.
const MEMO_STALE: f64 = 64.0;

/// A candidate of the frame as rated: where it was clamped to, its face,
/// its f_total, and whether its sight ahead is still to be asked (it sees
/// the target and there is a point ahead).
#[derive(Clone, Copy, Debug)]
struct Rated {
    pos: V3,
    face: u32,
    total: f64,
    pending: bool,
}

/// The frame's sight-line answers by candidate point: candidates often
/// clamp to the same point (a blocked line, one vertex best by two
/// criteria), and each point's sight lines are tested once.
#[derive(Debug, Default)]
struct SightMemo {
    entries: [SightEntry; 8],
    n: usize,
}

#[derive(Clone, Copy, Debug)]
struct SightEntry {
    pos: V3,
    visible: bool,
    /// The sight line to the point ahead, once asked.
    ahead: Option<bool>,
}

impl Default for Rated {
    fn default() -> Self {
        Rated {
            pos: V3(0.0, 0.0, 0.0),
            face: 0,
            total: f64::INFINITY,
            pending: false,
        }
    }
}

impl Default for SightEntry {
    fn default() -> Self {
        SightEntry {
            pos: V3(0.0, 0.0, 0.0),
            visible: false,
            ahead: None,
        }
    }
}

impl SightMemo {
    fn find(&self, pos: V3) -> Option<SightEntry> {
        self.entries[..self.n]
            .iter()
            .find(|e| e.pos == pos)
            .copied()
    }

    fn put(&mut self, pos: V3, visible: bool) {
        if self.n < self.entries.len() {
            self.entries[self.n] = SightEntry {
                pos,
                visible,
                ahead: None,
            };
            self.n += 1;
        }
    }

    fn put_ahead(&mut self, pos: V3, seen: bool) {
        if let Some(e) = self.entries[..self.n].iter_mut().find(|e| e.pos == pos) {
            e.ahead = Some(seen);
        }
    }
}

/// Edges the pursuit candidate's descent may follow (bounds its cost).
const PURSUIT_STEPS: usize = 8;

/// How close (units) a clamp must come to a vertex of the pursuit's way for
/// the straight line from the camera to count as reaching it (the clamps
/// stop [`CLAMP_TOL`](super::motion::CLAMP_TOL) short of the boundary).
const PURSUIT_REACHED: f64 = 0.25;

/// The farthest of the indices `0..=last` that `reaches`, asking the last
/// first, then by bisection (the straight line from the camera that reaches a
/// vertex of the way mostly reaches the ones before it); 0 when none is.
fn farthest_reached(last: usize, mut reaches: impl FnMut(usize) -> bool) -> usize {
    if last == 0 || reaches(last) {
        return last;
    }
    let (mut lo, mut hi) = (0, last);
    while hi - lo > 1 {
        let mid = (lo + hi) / 2;
        if reaches(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// The pursuit's way: the vertices of the distance field's descent, the
/// first one the reachable vertex nearest the target by VDistance.
#[derive(Clone, Copy)]
struct Pursuit {
    points: [V3; PURSUIT_STEPS + 1],
    n: usize,
}

impl Camera {
    /// Builds, clamps, recombines and rates the candidates (thesis 5.2,
    /// 5.3); returns the best position and its cost.
    pub(super) fn choose(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &State,
        margin: f32,
    ) -> (V3, f64) {
        let d_mu = scene.d_mu;
        let early_stop = f64::from(self.params.early_stop);
        let tc = s.pos - scene.t;
        let r = tc.norm();
        let u = if r > 1e-6 { tc * (1.0 / r) } else { scene.a_n };
        let k_dist = scene.t + u * d_mu;
        let k_angle = scene.t + slerp(u, scene.a_n, 0.25) * r;
        let k_inertia = s.pos + s.vel * scene.dt;
        let (k_clear, k_vis, k_neighb, k_path, reachable) = self.local_candidates(g, scene, s);
        self.debug.reachable = reachable;
        let wanted = [
            (CandidateKind::Dist, Some(k_dist)),
            (CandidateKind::Angle, Some(k_angle)),
            (CandidateKind::Inertia, Some(k_inertia)),
            (CandidateKind::Clear, Some(k_clear)),
            (CandidateKind::Vis, Some(k_vis)),
            (CandidateKind::Neighb, Some(k_neighb)),
            // The pursuit's point is found when its turn comes (it costs
            // clamps, which an early stop spares).
            (CandidateKind::Path, None),
        ];
        let mut n = 0;
        let mut rated = [Rated::default(); 8];
        let mut memo = SightMemo::default();
        let mut stop = false;
        for (kind, k) in wanted {
            // Only the pursuit is `None` here: its point, if it has a way.
            let k = match (k, &k_path) {
                (Some(k), _) => k,
                (None, Some(way)) => self.pursuit_point(g, s, way, margin, n),
                (None, None) => continue,
            };
            rated[n] = self.rate(g, scene, s, kind, k, margin, n, &mut memo);
            n += 1;
            if rated[n - 1].total < early_stop {
                self.settle_ahead(g, scene, &mut rated[n - 1], n - 1, &mut memo);
                if rated[n - 1].total < early_stop {
                    stop = true;
                    break;
                }
            }
        }
        let mut best = self.cheapest_settled(g, scene, &mut rated[..n], &mut memo);
        if !stop {
            // Weighted by the totals as they stand: those of candidates
            // whose sight ahead was never asked (they could not win) lack
            // its penalty.
            let (mut wsum, mut wpos) = (0.0, V3(0.0, 0.0, 0.0));
            for c in &rated[..n] {
                let w = 1.0 / c.total.max(1e-12);
                wsum += w;
                wpos = wpos + c.pos * w;
            }
            if wsum > 0.0 {
                let k = wpos * (1.0 / wsum);
                rated[n] = self.rate(g, scene, s, CandidateKind::Comb, k, margin, n, &mut memo);
                if best.is_none_or(|b| rated[n].total < rated[b].total) {
                    self.settle_ahead(g, scene, &mut rated[n], n, &mut memo);
                    if best.is_none_or(|b| rated[n].total < rated[b].total) {
                        best = Some(n);
                    }
                }
                n += 1;
            }
        }
        self.debug.count = n;
        self.debug.best = best.unwrap_or(0);
        match best {
            Some(b) => (rated[b].pos, rated[b].total),
            None => (s.pos, f64::INFINITY),
        }
    }

    /// Clamps candidate `k` (the `slot`-th of the frame) into the volume
    /// and rates it with the target where it is; its sight ahead is left
    /// for [`Camera::settle_ahead`].
    #[allow(clippy::too_many_arguments)]
    fn rate(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &State,
        kind: CandidateKind,
        k: V3,
        margin: f32,
        slot: usize,
        memo: &mut SightMemo,
    ) -> Rated {
        let (pos, face, clear) = self.clamp(g, s, k, margin, slot);
        let known = memo.find(pos);
        let costs = self.costs_at(
            g,
            scene,
            s,
            pos,
            face,
            clear,
            known.map(|e| e.visible),
            Some(Slot::Line(slot)),
        );
        let visible = costs.vis == 0.0;
        if known.is_none() {
            memo.put(pos, visible);
        }
        self.record(slot, kind, k, pos, costs, visible);
        Rated {
            pos,
            face,
            total: f64::from(costs.total),
            pending: visible && scene.ahead.is_some(),
        }
    }

    /// The cheapest of `rated` once its sight ahead is known: the penalty
    /// only adds cost, so asking it of the cheapest candidate until one
    /// keeps its place gives the choice asking every candidate would.
    fn cheapest_settled(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        rated: &mut [Rated],
        memo: &mut SightMemo,
    ) -> Option<usize> {
        loop {
            let mut best: Option<usize> = None;
            for (i, c) in rated.iter().enumerate() {
                if best.is_none_or(|b| c.total < rated[b].total) {
                    best = Some(i);
                }
            }
            let b = best?;
            if !rated[b].pending {
                return Some(b);
            }
            self.settle_ahead(g, scene, &mut rated[b], b, memo);
        }
    }

    /// Asks whether the `slot`-th candidate, which sees the target, also
    /// sees the point ahead of it; if not, rates it as hidden
    /// ([`Camera::hidden_ahead`]).
    fn settle_ahead(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        c: &mut Rated,
        slot: usize,
        memo: &mut SightMemo,
    ) {
        let Some(ahead) = scene.ahead.filter(|_| c.pending) else {
            return;
        };
        c.pending = false;
        let seen = match memo.find(c.pos).and_then(|e| e.ahead) {
            Some(seen) => seen,
            None => {
                let seen = self.sees_ahead(g, c.face, c.pos, &ahead, slot);
                memo.put_ahead(c.pos, seen);
                seen
            }
        };
        if !seen {
            let mut costs = self.debug.candidates[slot].costs;
            self.hidden_ahead(g, scene, c.face, c.pos, &ahead, &mut costs);
            self.debug.candidates[slot].costs = costs;
            c.total = f64::from(costs.total);
        }
    }

    fn record(
        &mut self,
        i: usize,
        kind: CandidateKind,
        wanted: V3,
        pos: V3,
        costs: Costs,
        visible: bool,
    ) {
        self.debug.candidates[i] = CandidateDebug {
            kind,
            wanted: wanted.to_f32(),
            pos: pos.to_f32(),
            visible,
            costs,
        };
    }

    /// Rates a candidate that sees the target but not the point ahead of
    /// it as hidden: f_vis with the way to that point (VDistance to the
    /// target, then the straight free segment on), f_total again.
    pub(super) fn hidden_ahead(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        face: u32,
        pos: V3,
        ahead: &Ahead,
        costs: &mut Costs,
    ) {
        let vd = self.vdistance(g, scene, face, pos) + ahead.lead;
        let vis = self.vis_cost(vd);
        let rest = f64::from(costs.dist)
            + f64::from(costs.angle)
            + f64::from(costs.inertia)
            + f64::from(costs.clear);
        costs.vis = vis as f32;
        costs.total = ((vis + scene.novis * rest) / 5.0) as f32;
    }

    /// Pulls a candidate back into the solution space: the thesis' Trace in
    /// Volume(f_i), or our advance across faces with the near-plane margin.
    /// Returns the point, a face holding it and its clearance there.
    /// `slot` is the candidate's place in the frame's list: its clamp
    /// follows the way the same candidate's took last frame.
    fn clamp(&mut self, g: &Vdg<'_>, s: &State, k: V3, margin: f32, slot: usize) -> (V3, u32, f64) {
        let (p, f) = if self.params.max_substeps == 0 {
            (
                V3::from_f32(g.trace(s.face, s.pos.to_f32(), k.to_f32())),
                s.face,
            )
        } else {
            // Candidates share the update's allowance of leaf searches
            // for their clamps (as their sight lines do).
            let mut budget = CoverBudget {
                hops: self.params.max_substeps,
                leaf_searches: self.clamp_leaf_searches,
            };
            let a = g.advance_tol(
                s.face,
                s.pos.to_f32(),
                k.to_f32(),
                margin,
                &mut budget,
                CLAMP_TOL,
                Some(&mut self.clamp_hints[slot]),
                Some(&self.faces),
                STEP_EVALS,
            );
            self.clamp_leaf_searches = budget.leaf_searches;
            (V3::from_f32(a.point), a.face)
        };
        (p, f, self.faces.fc(g, f, p))
    }

    /// k_clear, k_vis and k_neighb: the best vertices of
    /// Reachable(P(c_i), f_i) by f_clear, f_vis and f_total. Visibility is
    /// the expensive term, so it is tested lazily: k_vis is the first
    /// visible vertex in order of VDistance (all visible vertices cost 0;
    /// the nearest by VDistance breaks the tie), k_neighb a branch and bound
    /// over the cost without visibility (a lower bound).
    #[allow(clippy::type_complexity)]
    fn local_candidates(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &State,
    ) -> (V3, V3, V3, Option<Pursuit>, u32) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.reach.clear();
        // The thesis' exact Reachable, or (ours) the vertices reachable
        // within one face volume: the candidates are clamped into the free
        // volume anyway, and the exact set costs most of an update.
        let exact = self.params.exact_reachable;
        if exact {
            g.for_each_local_vertex(s.pos.to_f32(), s.face, true, |v| sc.reach.push(v));
        } else {
            g.local_vertices_cached(&self.faces, s.pos.to_f32(), s.face, &mut sc.reach);
        }
        let n = sc.reach.len();
        if n == 0 {
            self.scratch = sc;
            return (s.pos, s.pos, s.pos, None, 0);
        }
        sc.base.clear();
        sc.vd.clear();
        sc.vis.clear();
        sc.fresh_left = self.params.vertex_tests;
        let (mut k_clear, mut best_clear) = (sc.reach[0], f64::INFINITY);
        for &v in &sc.reach {
            let pv = g.pos(v);
            let r = f64::from(g.vertices[v as usize].clearance);
            let clear = self.clear_cost(scene, s, r);
            let base = self.dist_cost(scene, pv)
                + self.angle_cost(scene, pv)
                + self.inertia_cost(scene, pv)
                + clear;
            sc.base.push(base);
            sc.vd.push(f64::NAN);
            sc.vis.push(-1);
            if clear < best_clear {
                (k_clear, best_clear) = (v, clear);
            }
        }
        // k_vis: every visible vertex costs 0; the thesis leaves the tie
        // open, we take the one nearest the target (no VDistance needed).
        // Only when none is visible, the least VDistance.
        sc.order.clear();
        sc.order
            .extend((0..n).map(|i| ((g.pos(sc.reach[i]) - scene.t).norm(), i as u32)));
        sc.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut k_vis = None;
        for j in 0..n {
            let i = sc.order[j].1 as usize;
            if self.vertex_visible(g, scene, &mut sc, i) {
                k_vis = Some(sc.reach[i]);
                break;
            }
        }
        let nearest_by_vd = |this: &mut Self, sc: &mut Scratch| {
            let mut best = (f64::INFINITY, sc.reach[0]);
            for i in 0..n {
                let d = this.vertex_vd(g, scene, sc, i);
                if d < best.0 {
                    best = (d, sc.reach[i]);
                }
            }
            best.1
        };
        let k_vis = match k_vis {
            Some(v) => v,
            None => nearest_by_vd(self, &mut sc),
        };
        // k_path: only while the target is hidden (a visible target is
        // best served by the local candidates) and the field exists.
        let k_path = (self.params.pursuit_length > 0.0 && !s.visible && self.params.distance_field)
            .then(|| {
                let from = nearest_by_vd(self, &mut sc);
                self.descend(g, from)
            });
        // k_neighb: branch and bound on the cost without visibility, a
        // lower bound; VDistance only for hidden vertices.
        sc.order.clear();
        sc.order
            .extend((0..n).map(|i| (scene.novis * sc.base[i] / 5.0, i as u32)));
        sc.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let (mut k_neighb, mut best) = (sc.reach[sc.order[0].1 as usize], f64::INFINITY);
        for j in 0..n {
            let (lb, i) = (sc.order[j].0, sc.order[j].1 as usize);
            if lb >= best {
                break;
            }
            let vis = if self.vertex_visible(g, scene, &mut sc, i) {
                0.0
            } else {
                let d = self.vertex_vd(g, scene, &mut sc, i);
                self.vis_cost(d)
            };
            let total = vis / 5.0 + lb;
            if total < best {
                (k_neighb, best) = (sc.reach[i], total);
            }
        }
        self.scratch = sc;
        (
            g.pos(k_clear),
            g.pos(k_vis),
            g.pos(k_neighb),
            k_path,
            n as u32,
        )
    }

    /// The way [`CameraParams::pursuit_length`](super::CameraParams::pursuit_length) along the distance
    /// field's descent from vertex `from` towards the target: each step to
    /// the settled neighbour through which the target is nearest, never to
    /// a vertex with less clearance than the near-plane margin (the camera
    /// could not pass it). Bounded by [`PURSUIT_STEPS`] edges.
    fn descend(&mut self, g: &Vdg<'_>, from: u32) -> Pursuit {
        let min_clear = self.params.near_margin + MARGIN_SLACK as f32;
        let mut way = Pursuit {
            points: [g.pos(from); PURSUIT_STEPS + 1],
            n: 1,
        };
        let mut v = from;
        let mut walked = 0.0f64;
        for _ in 0..PURSUIT_STEPS {
            let Some(dv) = self.field.settled_distance(v) else {
                break;
            };
            let pv = g.pos(v);
            let mut next: Option<(f32, u32, f64)> = None;
            for u in g.vertex_neighbours(v) {
                let Some(du) = self.field.settled_distance(u) else {
                    continue;
                };
                if du >= dv || g.vertices[u as usize].clearance < min_clear {
                    continue;
                }
                let edge = (g.pos(u) - pv).norm();
                let via = du + edge as f32;
                if next.is_none_or(|b| via < b.0 || (via == b.0 && u < b.1)) {
                    next = Some((via, u, edge));
                }
            }
            let Some((_, u, edge)) = next else { break };
            v = u;
            way.points[way.n] = g.pos(v);
            way.n += 1;
            walked += edge;
            if walked >= f64::from(self.params.pursuit_length) {
                break;
            }
        }
        way
    }

    /// Where the pursuit candidate wants the camera: the farthest vertex of
    /// `way` that the straight line from the camera reaches (a binary search,
    /// the end first). Clamping the way's end alone stopped it at the first
    /// wall when the way turned a corner, next to the camera, where it
    /// promised nothing: the camera dithered between the local candidates
    /// for a second while the player climbed a stair round that corner.
    fn pursuit_point(
        &mut self,
        g: &Vdg<'_>,
        s: &State,
        way: &Pursuit,
        margin: f32,
        slot: usize,
    ) -> V3 {
        let at = farthest_reached(way.n - 1, |i| {
            let (q, _, _) = self.clamp(g, s, way.points[i], margin, slot);
            (q - way.points[i]).norm() <= PURSUIT_REACHED
        });
        way.points[at]
    }

    /// Visible(P(v), t) for the `i`-th reachable vertex: asked once per
    /// update, and with [`CameraParams::vertex_tests`](super::CameraParams::vertex_tests) answered from the
    /// vertex's memo when the target has hardly moved since its last test
    /// or the update's fresh tests are spent (unknown counts as hidden).
    fn vertex_visible(&mut self, g: &Vdg<'_>, scene: &Scene, sc: &mut Scratch, i: usize) -> bool {
        if sc.vis[i] < 0 {
            let v = sc.reach[i];
            let ok = if self.params.vertex_tests == 0 {
                self.sees_vertex(g, scene, v)
            } else {
                let memo = sc.memo[v as usize];
                let moved = (V3::from_f32(memo.target) - scene.t_vis).norm();
                if memo.known && moved < MEMO_FRESH {
                    memo.visible
                } else if sc.fresh_left > 0 {
                    sc.fresh_left -= 1;
                    let ok = self.sees_vertex(g, scene, v);
                    sc.memo[v as usize] = VisMemo {
                        target: scene.t_vis.to_f32(),
                        visible: ok,
                        known: true,
                    };
                    ok
                } else {
                    memo.known && moved < MEMO_STALE && memo.visible
                }
            };
            sc.vis[i] = i8::from(ok);
        }
        sc.vis[i] == 1
    }

    /// VDistance(P(v), t) for the `i`-th reachable vertex, computed once
    /// per update and only when asked.
    fn vertex_vd(&mut self, g: &Vdg<'_>, scene: &Scene, sc: &mut Scratch, i: usize) -> f64 {
        if sc.vd[i].is_nan() {
            let v = sc.reach[i];
            sc.vd[i] = self.vdistance(g, scene, g.vertex_faces(v).get(0), g.pos(v));
        }
        sc.vd[i]
    }
}

/// Rotates unit vector `u` towards unit vector `w` by `frac` of the angle
/// between them (about the axis `u × w`; for opposite vectors about z, or
/// x when they are vertical).
fn slerp(u: V3, w: V3, frac: f64) -> V3 {
    let cos = u.dot(w).clamp(-1.0, 1.0);
    let angle = cos.acos();
    if angle < 1e-9 {
        return u;
    }
    let mut axis = u.cross(w);
    if axis.norm() < 1e-9 {
        axis = if u.2.abs() < 0.9 {
            V3(0.0, 0.0, 1.0)
        } else {
            V3(1.0, 0.0, 0.0)
        };
        axis = axis - u * axis.dot(u);
    }
    let axis = axis * (1.0 / axis.norm());
    let (sin_t, cos_t) = (angle * frac).sin_cos();
    // Rodrigues' rotation of u about the axis (u ⟂ axis).
    u * cos_t + axis.cross(u) * sin_t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slerp_turns_by_the_fraction() {
        let u = V3(1.0, 0.0, 0.0);
        let w = V3(0.0, 1.0, 0.0);
        let q = slerp(u, w, 0.5);
        assert!((q.0 - q.1).abs() < 1e-12 && (q.norm() - 1.0).abs() < 1e-12);
        let opposite = slerp(u, V3(-1.0, 0.0, 0.0), 0.25);
        assert!((opposite.norm() - 1.0).abs() < 1e-12);
        assert!((opposite.0 - (std::f64::consts::FRAC_PI_4).cos()).abs() < 1e-12);
    }

    #[test]
    fn the_pursuit_takes_the_farthest_vertex_of_its_way_in_reach() {
        // A way of nine vertices of which the camera reaches the first k.
        for k in 1..=9 {
            let mut asked = 0;
            let at = farthest_reached(8, |i| {
                asked += 1;
                i < k
            });
            assert_eq!(at, k - 1, "reaching {k}");
            // The end first, then a bisection: at most 1 + 3 clamps.
            assert!(asked <= 4, "reaching {k}: {asked} clamps");
        }
        // None reached: the way's first vertex (the nearest reachable one).
        assert_eq!(farthest_reached(8, |_| false), 0);
        assert_eq!(farthest_reached(0, |_| false), 0);
    }
}
