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
    let fs = e.edge_faces(k1, k2);
    let [fi, fj] = fs[..] else { return None };
    let k3 = third(e, fi, k1, k2);
    let k4 = third(e, fj, k1, k2);
    if k3 == k4 || k3 == k1 || k4 == k1 {
        return None;
    }
    // The new edge must be new, except on a seam where sheets meet: there
    // the face `(k1,k3,k4)` may exist already (made by a swap in another
    // sheet) and the two merge; `(k2,k3,k4)` must still be new.
    let merge = e.has_edge(k3, k4);
    if merge && (!e.has_face(k1, k3, k4) || e.has_face(k2, k3, k4)) {
        return None;
    }
    let (p1, p2, p3, p4) = (e.pos(k1), e.pos(k2), e.pos(k3), e.pos(k4));
    let (tp, tq) = perpendicular_feet(p1, p2, p3, p4)?;
    if !(0.0..=1.0).contains(&tp) || !(0.0..=1.0).contains(&tq) {
        return None;
    }
    let p = add(p1, scale(sub(p2, p1), tp));
    let q = add(p3, scale(sub(p4, p3), tq));
    let d = dist(p, q);
    let (r1, r2, r3, r4) = (e.radius(k1), e.radius(k2), e.radius(k3), e.radius(k4));
    let cp = r1 + tp * (r2 - r1);
    if d >= cp {
        return None; // the new edge misses the cylinder of the old one
    }
    let bound = e.clearance_at(fi, q).min(e.clearance_at(fj, q)) - MARGIN;
    let (n3, n4) = optimal_linear_reduction(r3, r4, tq, bound)?;
    if n3 <= 0.0 || n4 <= 0.0 {
        return None;
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
    Some(Swap {
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

/// The cheapest allowed swap of an edge at `k` (thesis `EntferneKnoten`:
/// all face pairs at `k` are tried, the one losing least is taken; ties go
/// to the lower neighbour id).
pub(crate) fn best_at(e: &Edit, k: u32, neighbours: &[u32]) -> Option<Swap> {
    let mut best: Option<Swap> = None;
    for &n in neighbours {
        if let Some(s) = plan(e, k, n)
            && best.is_none_or(|b| s.cost < b.cost)
        {
            best = Some(s);
        }
    }
    best
}
