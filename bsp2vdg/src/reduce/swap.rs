//! The edge swap of thesis 4.5: faces `fi = (k1,k2,k3)` and `fj = (k1,k2,k4)`
//! sharing the edge `k1–k2` become `fk = (k1,k3,k4)` and `fl = (k2,k3,k4)`.
//!
//! Conditions, as in the thesis: the edge belongs to exactly these two faces
//! (non-manifold edges are never swapped, condition C), the perpendicular
//! feet of the two edges lie inside both (`t_p, t_q ∈ [0,1]`) and the new
//! edge passes through the free-space cylinder of the old one (`d < c_p`).
//! Added here for topology: the new edge and faces must not exist yet.
//!
//! Why this keeps condition A: a face volume is the union of the balls
//! `B(x, r(x))` over its triangle, so it contains the new face's ball at `x`
//! wherever the old face's clearance at `x` is at least `r'(x)`. That
//! clearance is concave in `x` and `r'` is linear, so on any triangle the
//! check reduces to its corners. Splitting `fk` at `q` into `(k1,k3,q)` ⊂
//! vol(`fi`) and `(k1,q,k4)` ⊂ vol(`fj`) (and `fl` likewise) leaves a single
//! corner to check, `q`: the new radius there, `c_q`, must not exceed the
//! old clearance at `q`. The thesis bounds that clearance by the cylinder,
//! `c_p − d`; the exact value `min(clearance_fi(q), clearance_fj(q)) ≥ c_p − d`
//! is used instead, which loses less. If `c_q` is too large the clearances of
//! `k3`, `k4` are lowered by the optimal linear reduction (6.1.5) and the
//! volume this takes from their other faces is added to the cost.

use super::mesh::{Edit, Op};
use super::remove::Refusal;
use super::volume::{
    Shape, add, dist, face_shape, loss, optimal_linear_reduction, perpendicular_feet, scale,
    shape_volume, sub,
};

/// Safety distance (game units) kept below the exact bound, covering the
/// rounding of positions and clearances to f32 in the file.
pub(crate) const MARGIN: f64 = 1e-3;

/// A planned swap, not yet applied.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Swap {
    pub k: [u32; 4],
    pub fi: u32,
    pub fj: u32,
    /// `(k1,k3,k4)` exists already (seam merge, see [`plan`]).
    pub merge: bool,
    /// Clearances of k3 and k4 after the swap.
    pub r3: f64,
    pub r4: f64,
    /// Lost volume (4.3 model, see [`loss`]).
    pub cost: f64,
}

/// The vertex of face `f` that is neither `a` nor `b`.
pub(crate) fn third(e: &Edit, f: u32, a: u32, b: u32) -> u32 {
    e.face(f)
        .into_iter()
        .find(|&v| v != a && v != b)
        .unwrap_or(a)
}

/// Plans swapping the edge `k1–k2`; `None` if a condition fails.
pub(crate) fn plan(e: &Edit, k1: u32, k2: u32) -> Option<Swap> {
    let mut s = plan_why(e, k1, k2).ok()?;
    s.cost += lowering_cost(e, &s);
    Some(s)
}

/// The volume the other faces of `k3` and `k4` lose when their clearances
/// are lowered as `s` plans; [`plan_why`] leaves it out of `s.cost`. It is
/// never negative (the model volume grows with every radius), so
/// `s.cost` without it is a lower bound of the full cost.
pub(crate) fn lowering_cost(e: &Edit, s: &Swap) -> f64 {
    let [_, _, k3, k4] = s.k;
    e.lowering_cost(&[(k3, s.r3), (k4, s.r4)], &[s.fi, s.fj])
}

/// [`plan`] naming the condition that fails; the cost of the plan does
/// not include its [`lowering_cost`] yet.
pub(crate) fn plan_why(e: &Edit, k1: u32, k2: u32) -> Result<Swap, Refusal> {
    finish(e, &screen(e, k1, k2)?)
}

/// A swap that passed the cheap conditions (topology, feet, cylinder), with
/// a lower bound of its cost: the loss when no clearance has to be lowered
/// (lowering only shrinks the new faces and costs the other faces volume).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Screened {
    k: [u32; 4],
    fi: u32,
    fj: u32,
    merge: bool,
    tq: f64,
    q: super::volume::P3,
    old: f64,
    bound: f64,
    /// `c_p − d`: the radius at the foot `p` on the old edge less the distance to
    /// `q`, a lower bound of both old faces' clearance at `q` (see [`finish`]).
    cylinder: f64,
    /// Shapes of `(k1,k3,k4)` and `(k2,k3,k4)`: positions do not change.
    shapes: [Shape; 2],
}

/// The cheap conditions of a swap of `k1–k2` (see the module docs).
pub(crate) fn screen(e: &Edit, k1: u32, k2: u32) -> Result<Screened, Refusal> {
    let [fi, fj] = match e.edge_faces(k1, k2) {
        (2, f) => f,
        (1, _) => return Err(Refusal::SwapBorderEdge),
        _ => return Err(Refusal::SwapNonManifold),
    };
    let k3 = third(e, fi, k1, k2);
    let k4 = third(e, fj, k1, k2);
    if k3 == k4 || k3 == k1 || k4 == k1 {
        return Err(Refusal::SwapDegenerate);
    }
    // The new edge must be new, except on a seam where sheets meet: there
    // the face `(k1,k3,k4)` may exist already (made by a swap in another
    // sheet) and the two merge; `(k2,k3,k4)` must still be new.
    let merge = e.has_edge(k3, k4);
    if merge && (!e.has_face(k1, k3, k4) || e.has_face(k2, k3, k4)) {
        return Err(Refusal::SwapEdgeExists);
    }
    let (p1, p2, p3, p4) = (e.pos(k1), e.pos(k2), e.pos(k3), e.pos(k4));
    let (tp, tq) = perpendicular_feet(p1, p2, p3, p4).ok_or(Refusal::SwapParallel)?;
    // Only `q` must lie on the new edge (it is the split point of the
    // condition-A argument above, which holds wherever `p` falls since the
    // bound at `q` is the exact clearance of the old faces). The thesis
    // also asks `t_p ∈ [0,1]` for its cylinder estimate; requiring it left
    // many vertices unremovable (seam vertices whose seam bends slightly).
    let tp = tp.clamp(0.0, 1.0);
    if !(0.0..=1.0).contains(&tq) {
        return Err(Refusal::SwapFeetOutside);
    }
    let p = add(p1, scale(sub(p2, p1), tp));
    let q = add(p3, scale(sub(p4, p3), tq));
    let d = dist(p, q);
    let (r1, r2) = (e.radius(k1), e.radius(k2));
    let cp = r1 + tp * (r2 - r1);
    if d >= cp {
        return Err(Refusal::SwapMissesCylinder);
    }
    let old = e.face_volume(fi) + e.face_volume(fj);
    let shapes = [face_shape([p1, p3, p4]), face_shape([p2, p3, p4])];
    let (r3, r4) = (e.radius(k3), e.radius(k4));
    let kept = if merge {
        0.0
    } else {
        shape_volume(&shapes[0], [r1, r3, r4])
    };
    // Lowering clearances only shrinks the new faces, so `old − new` only
    // grows with it: its value without lowering bounds the loss from below.
    let bound = (old - (kept + shape_volume(&shapes[1], [r2, r3, r4]))).max(0.0);
    Ok(Screened {
        k: [k1, k2, k3, k4],
        fi,
        fj,
        merge,
        tq,
        q,
        old,
        bound,
        cylinder: cp - d,
        shapes,
    })
}

/// Whether face `f`'s exact clearance ([`Edit::clearance_at`]) is computed
/// without cancellation: its triangle is not needle-thin (the sine of its
/// angle at the first vertex is at least 1e-3, so the closed form's 2×2
/// system has a condition number below about 1e6).
fn well_shaped(e: &Edit, f: u32) -> bool {
    let s = e.shape(f);
    s[0] >= 1e-3 * s[1] * s[3]
}

/// How far below [`Screened::cylinder`] the new radius at `q` must be for
/// [`finish`] to skip the exact clearances: covers the rounding of both
/// (about 1e-12 units on map coordinates) by six orders of magnitude.
fn cylinder_slack(s: &Screened) -> f64 {
    1e-6 * (1.0 + s.cylinder.abs())
}

/// The exact clearance condition at `q` of a screened swap, and its cost
/// without the [`lowering_cost`].
pub(crate) fn finish(e: &Edit, s: &Screened) -> Result<Swap, Refusal> {
    let [k1, k2, k3, k4] = s.k;
    let (r3, r4) = (e.radius(k3), e.radius(k4));
    // Most swaps need no lowering: the new radius at `q` is below `c_p − d`,
    // which both old faces' clearances at `q` are at least (`p` lies on their
    // common edge). Then the optimal reduction keeps `r3`, `r4` whatever the
    // exact bound, and the two exact clearances, the dearest part of a plan,
    // are not needed. The same outcome as computing them (see
    // `well_shaped` and `cylinder_slack` for the rounding).
    let rq = (1.0 - s.tq) * r3 + s.tq * r4;
    let (n3, n4) = if rq <= s.cylinder - MARGIN - cylinder_slack(s)
        && well_shaped(e, s.fi)
        && well_shaped(e, s.fj)
    {
        (r3, r4)
    } else {
        let bound = e.clearance_at(s.fi, s.q).min(e.clearance_at(s.fj, s.q)) - MARGIN;
        optimal_linear_reduction(r3, r4, s.tq, bound).ok_or(Refusal::SwapClearanceBound)?
    };
    if n3 <= 0.0 || n4 <= 0.0 {
        return Err(Refusal::SwapClearanceBound);
    }
    let kept = if s.merge {
        0.0
    } else {
        shape_volume(&s.shapes[0], [e.radius(k1), n3, n4])
    };
    let new = kept + shape_volume(&s.shapes[1], [e.radius(k2), n3, n4]);
    Ok(Swap {
        k: s.k,
        fi: s.fi,
        fj: s.fj,
        merge: s.merge,
        r3: n3,
        r4: n4,
        cost: loss(s.old, new),
    })
}

/// Performs a planned swap on the edit.
pub(crate) fn apply(e: &mut Edit, s: &Swap) {
    let [k1, k2, k3, k4] = s.k;
    e.remove_face(s.fi);
    e.remove_face(s.fj);
    if s.r3 < e.radius(k3) {
        e.set_radius(k3, s.r3);
    }
    if s.r4 < e.radius(k4) {
        e.set_radius(k4, s.r4);
    }
    if !s.merge {
        e.add_face([k1, k3, k4]);
    }
    e.add_face([k2, k4, k3]);
    e.count(Op::Swap);
}

/// The vertices besides `k1` and `k2` that a plan for the edge `k1–k2`
/// reads: the third vertices of its two faces (or `k2` when there are not two).
fn plan_deps(e: &Edit, k1: u32, k2: u32) -> [u32; 2] {
    match e.edge_faces(k1, k2) {
        (2, [fi, fj]) => [third(e, fi, k1, k2), third(e, fj, k1, k2)],
        _ => [k2, k2],
    }
}

/// The candidate swaps at one vertex while its degree is lowered (thesis
/// `EntferneKnoten`: all face pairs at `k` are tried, the one losing least is
/// taken, ties to the lower neighbour id). After a swap `(k, k2 → k3, k4)`
/// only plans that read `k2`, `k3` or `k4` can change — the other faces and
/// clearances they read are untouched — so only those are planned again.
pub(crate) struct Candidates {
    k: u32,
    /// Per neighbour (sorted): the plan (its cost without the lowering
    /// cost), the vertices it read, and its full cost once computed.
    plans: smallvec::SmallVec<[Candidate; 12]>,
}

struct Candidate {
    nb: u32,
    state: Stage,
    deps: [u32; 2],
}

/// How far a candidate has been evaluated: each stage is dearer and gives a
/// tighter lower bound of the cost (the last one the cost itself).
#[derive(Clone, Copy)]
enum Stage {
    Refused,
    Screened(Screened),
    Planned(Swap),
    /// With the cost without the lowering cost.
    Costed(Swap, f64),
}

impl Stage {
    fn bound(&self) -> Option<f64> {
        match self {
            Stage::Refused => None,
            Stage::Screened(s) => Some(s.bound),
            Stage::Planned(s) | Stage::Costed(s, _) => Some(s.cost),
        }
    }
}

impl Candidate {
    fn new(e: &Edit, k: u32, nb: u32) -> Candidate {
        match screen(e, k, nb) {
            Ok(s) => Candidate {
                nb,
                deps: [s.k[2], s.k[3]],
                state: Stage::Screened(s),
            },
            Err(_) => Candidate {
                nb,
                state: Stage::Refused,
                deps: plan_deps(e, k, nb),
            },
        }
    }

    /// Evaluates one stage further.
    fn advance(&mut self, e: &Edit) {
        self.state = match self.state {
            Stage::Screened(s) => match finish(e, &s) {
                Ok(p) => Stage::Planned(p),
                Err(_) => Stage::Refused,
            },
            Stage::Planned(mut p) => {
                let partial = p.cost;
                p.cost += lowering_cost(e, &p);
                Stage::Costed(p, partial)
            }
            x => x,
        };
    }
}

impl Candidates {
    pub fn new(e: &Edit, k: u32, neighbours: &[u32]) -> Candidates {
        let plans = neighbours
            .iter()
            .map(|&n| Candidate::new(e, k, n))
            .collect();
        Candidates { k, plans }
    }

    /// Why no swap at `k` is admissible: the most frequent failed condition
    /// among its edges (ties to the earlier [`Refusal`]).
    pub fn why_none(&self, e: &Edit) -> Refusal {
        let mut n = [0usize; Refusal::COUNT];
        for c in &self.plans {
            if let Err(r) = plan_why(e, self.k, c.nb) {
                n[r as usize] += 1;
            }
        }
        let best = (0..Refusal::COUNT).max_by_key(|&i| (n[i], usize::MAX - i));
        Refusal::ALL[best.unwrap_or(0)]
    }

    /// The admissible swap losing least (ties to the lower neighbour id),
    /// with its full cost. Candidates are evaluated lazily, cheapest lower
    /// bound first (branch and bound): the exact clearance condition and the
    /// lowering cost, the dear parts of a plan, are computed only for
    /// candidates whose bound does not exceed the best cost found. The
    /// result is the one a full evaluation of every candidate would give.
    pub fn best(&mut self, e: &Edit) -> Option<Swap> {
        loop {
            // The candidate with the least bound (ties to the lower id).
            let mut min: Option<(f64, usize)> = None;
            for (i, c) in self.plans.iter().enumerate() {
                if let Some(b) = c.state.bound()
                    && min.is_none_or(|(m, _)| b < m)
                {
                    min = Some((b, i));
                }
            }
            let (_, i) = min?;
            match self.plans[i].state {
                Stage::Costed(s, _) => return Some(s),
                _ => self.plans[i].advance(e),
            }
        }
    }

    /// Never proposes swapping the edge `k–nb`.
    pub fn exclude(&mut self, nb: u32) {
        self.plans.retain(|x| x.nb != nb);
    }

    /// Updates the plans after `done` was applied to `e`. Only the faces
    /// of `k`, `k2`, `k3`, `k4` changed and only the clearances of `k3`,
    /// `k4` (those in `lowered`). A plan for the edge `k–n` reads the faces
    /// of `k` and `n` (which faces contain the edge, which third vertices
    /// `d1`, `d2` they have, whether `(k,d1,d2)` or `(n,d1,d2)` exists), the
    /// edge `d1–d2`, the clearances of `k`, `n`, `d1`, `d2`, and for its
    /// lowering cost the faces of `d1`, `d2` with their clearances. So:
    /// `n ∈ {k2,k3,k4}`, `{d1,d2} = {k3,k4}` (the new edge) or a lowered
    /// `d1`/`d2` need a new plan; a changed face list of `d1`/`d2` or a
    /// lowered vertex next to them only a new lowering cost.
    /// Applies `s` to `e` and updates the plans for it; returns its cost.
    /// The one way both reduction phases make a swap.
    pub fn apply(&mut self, e: &mut Edit, s: &Swap) -> f64 {
        let [_, _, k3, k4] = s.k;
        let lowered: smallvec::SmallVec<[u32; 2]> = [(k3, s.r3), (k4, s.r4)]
            .into_iter()
            .filter(|&(v, r)| r < e.radius(v))
            .map(|x| x.0)
            .collect();
        apply(e, s);
        self.after(e, s, &lowered);
        s.cost
    }

    pub fn after(&mut self, e: &Edit, done: &Swap, lowered: &[u32]) {
        let [_, k2, k3, k4] = done.k;
        let topology = |v: u32| v == k2 || v == k3 || v == k4;
        self.plans.retain(|x| x.nb != k2);
        for x in &mut self.plans {
            let [d1, d2] = x.deps;
            let replan = topology(x.nb)
                || d1 == k2
                || d2 == k2
                || (d1 == k3 && d2 == k4)
                || (d1 == k4 && d2 == k3)
                || lowered.contains(&d1)
                || lowered.contains(&d2);
            if replan {
                *x = Candidate::new(e, self.k, x.nb);
            } else if let Stage::Costed(mut s, partial) = x.state
                && (topology(d1)
                    || topology(d2)
                    || lowered
                        .iter()
                        .any(|&l| e.has_edge(d1, l) || e.has_edge(d2, l)))
            {
                s.cost = partial;
                x.state = Stage::Planned(s);
            }
        }
        #[cfg(debug_assertions)]
        for x in &self.plans {
            let fresh = Candidate::new(e, self.k, x.nb);
            debug_assert_eq!(x.deps, fresh.deps, "deps of {}", x.nb);
            let s = match x.state {
                Stage::Refused => None,
                Stage::Screened(s) => Some((s.k, s.fi, s.fj, s.bound.to_bits())),
                Stage::Planned(s) | Stage::Costed(s, _) => {
                    finish(e, &screen(e, self.k, x.nb).unwrap())
                        .ok()
                        .map(|_| (s.k, s.fi, s.fj, 0))
                }
            };
            let f = match fresh.state {
                Stage::Screened(f) => Some((
                    f.k,
                    f.fi,
                    f.fj,
                    match x.state {
                        Stage::Screened(_) => f.bound.to_bits(),
                        _ => 0,
                    },
                )),
                _ => None,
            };
            if !matches!(x.state, Stage::Refused) {
                debug_assert_eq!(s, f, "plan for {} is stale", x.nb);
            }
            if let Stage::Costed(s, _) = x.state {
                let mut p = finish(e, &screen(e, self.k, x.nb).unwrap()).unwrap();
                p.cost += lowering_cost(e, &p);
                debug_assert_eq!(
                    s.cost.to_bits(),
                    p.cost.to_bits(),
                    "cost for {} is stale",
                    x.nb
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Graph;
    use crate::reduce::mesh::Mesh;
    use toolbox::SplitMix64;

    /// Two faces `(0,1,2)`, `(0,1,3)` sharing the edge 0–1.
    fn quad(p: [[f64; 3]; 4], r: [f64; 4]) -> Mesh {
        Mesh::new(&Graph {
            vertices: p.to_vec(),
            clearance: r.to_vec(),
            faces: vec![[0, 1, 2], [0, 1, 3]],
        })
    }

    #[test]
    fn swap_costs_are_never_negative_though_the_model_volume_can_grow() {
        let mut rng = SplitMix64::new(11);
        let (mut planned, mut grew) = (0, 0);
        for _ in 0..4000 {
            let mut p = [[0.0; 3]; 4];
            p[1] = [rng.range(4.0, 20.0), 0.0, 0.0];
            for (i, y) in [(2, -1.0), (3, 1.0)] {
                p[i] = [
                    rng.range(0.0, 20.0),
                    y * rng.range(5.0, 40.0),
                    rng.range(-15.0, 15.0),
                ];
            }
            let r = [
                rng.range(2.0, 12.0),
                rng.range(2.0, 12.0),
                rng.range(2.0, 60.0),
                rng.range(2.0, 60.0),
            ];
            let mesh = quad(p, r);
            let e = Edit::new(&mesh);
            let Some(s) = plan(&e, 0, 1) else { continue };
            planned += 1;
            assert!(s.cost >= 0.0, "{s:?}");
            let lowered = [(2, s.r3), (3, s.r4)];
            let old = e.face_volume(0) + e.face_volume(1);
            let new = e.volume([0, 2, 3], &lowered) + e.volume([1, 2, 3], &lowered);
            if new > old {
                grew += 1;
            }
        }
        // Both cases occur, so the test sees the one that used to give a
        // negative cost.
        assert!(planned > 100 && grew > 0, "{planned} {grew}");
    }
}
