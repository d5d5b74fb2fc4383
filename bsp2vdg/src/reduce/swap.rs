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
use super::volume::{add, dist, optimal_linear_reduction, perpendicular_feet, scale, sub};

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
    /// Lost volume (4.3 model).
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
    plan_why(e, k1, k2).ok()
}

/// [`plan`] naming the condition that fails.
pub(crate) fn plan_why(e: &Edit, k1: u32, k2: u32) -> Result<Swap, Refusal> {
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
    // about a quarter of the unremovable vertices (seam vertices whose seam
    // bends slightly) on de_dust2.
    let tp = tp.clamp(0.0, 1.0);
    if !(0.0..=1.0).contains(&tq) {
        return Err(Refusal::SwapFeetOutside);
    }
    let p = add(p1, scale(sub(p2, p1), tp));
    let q = add(p3, scale(sub(p4, p3), tq));
    let d = dist(p, q);
    let (r1, r2, r3, r4) = (e.radius(k1), e.radius(k2), e.radius(k3), e.radius(k4));
    let cp = r1 + tp * (r2 - r1);
    if d >= cp {
        return Err(Refusal::SwapMissesCylinder);
    }
    let bound = e.clearance_at(fi, q).min(e.clearance_at(fj, q)) - MARGIN;
    let (n3, n4) =
        optimal_linear_reduction(r3, r4, tq, bound).ok_or(Refusal::SwapClearanceBound)?;
    if n3 <= 0.0 || n4 <= 0.0 {
        return Err(Refusal::SwapClearanceBound);
    }
    let lowered = [(k3, n3), (k4, n4)];
    let old = e.volume(e.face(fi), &[]) + e.volume(e.face(fj), &[]);
    let kept = if merge {
        0.0
    } else {
        e.volume([k1, k3, k4], &lowered)
    };
    let new = kept + e.volume([k2, k3, k4], &lowered);
    let cost = old - new + e.lowering_cost(&lowered, &[fi, fj]);
    Ok(Swap {
        k: [k1, k2, k3, k4],
        fi,
        fj,
        merge,
        r3: n3,
        r4: n4,
        cost,
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
    /// Per neighbour (sorted): the plan and the vertices it read.
    plans: Vec<(u32, Option<Swap>, [u32; 2])>,
}

impl Candidates {
    pub fn new(e: &Edit, k: u32, neighbours: &[u32]) -> Candidates {
        let plans = neighbours
            .iter()
            .map(|&n| (n, plan(e, k, n), plan_deps(e, k, n)))
            .collect();
        Candidates { k, plans }
    }

    /// Why no swap at `k` is admissible: the most frequent failed condition
    /// among its edges (ties to the earlier [`Refusal`]).
    pub fn why_none(&self, e: &Edit) -> Refusal {
        let mut n = [0usize; Refusal::COUNT];
        for (nb, _, _) in &self.plans {
            if let Err(r) = plan_why(e, self.k, *nb) {
                n[r as usize] += 1;
            }
        }
        let best = (0..Refusal::COUNT).max_by_key(|&i| (n[i], usize::MAX - i));
        Refusal::ALL[best.unwrap_or(0)]
    }

    pub fn best(&self) -> Option<Swap> {
        let mut best: Option<Swap> = None;
        for (_, s, _) in &self.plans {
            if let Some(s) = s
                && best.is_none_or(|b| s.cost < b.cost)
            {
                best = Some(*s);
            }
        }
        best
    }

    /// Updates the plans after `done` was applied to `e`.
    /// A plan also reads the clearances of the faces around its third
    /// vertices (the cost of lowering them), so when the swap lowered the
    /// clearance of `k3` or `k4` the plans next to those are redone too.
    pub fn after(&mut self, e: &Edit, done: &Swap, lowered: &[u32]) {
        let [_, k2, k3, k4] = done.k;
        let changed =
            |v: u32| v == k2 || v == k3 || v == k4 || lowered.iter().any(|&l| e.has_edge(v, l));
        self.plans.retain(|x| x.0 != k2);
        for x in &mut self.plans {
            if changed(x.0) || changed(x.2[0]) || changed(x.2[1]) {
                x.1 = plan(e, self.k, x.0);
                x.2 = plan_deps(e, self.k, x.0);
            }
        }
    }
}
