//! Removing one vertex (thesis 4.4 `EntferneKnoten`, 4.6): lower its edge
//! degree by the cheapest swaps until it is 3 or less, then remove it by the
//! case that applies. Returns the total lost volume, or `None` if the vertex
//! cannot be removed without breaking a condition (the edit must then be
//! discarded).

use super::mesh::{Edit, Op};
use super::seam;
use super::swap::{self, MARGIN, third};
use super::volume::{
    add, closest_on_triangle, dist, loss, optimal_linear_reduction, optimal_planar_reduction,
    perpendicular_feet, scale, sub,
};

/// Vertices with more neighbours are left alone until swaps elsewhere lower
/// their degree: removing one takes `d − 3` swaps, each choosing among `d`
/// edges, and such hubs are touched by every removal around them, so costing
/// them would dominate the run time. (Not in the thesis; a speed guard.)
pub(crate) const MAX_DEGREE: usize = 20;

/// Why a vertex cannot be removed now (the refusal histogram of
/// [`super::refusals`]): the first condition that failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Refusal {
    /// No faces left (not a live vertex).
    Dead,
    /// More than [`MAX_DEGREE`] neighbours (waits).
    DegreeWait,
    /// Degree > 3 and no swap admissible; the most frequent reason among
    /// its edges is one of the `Swap*` ones.
    SwapBorderEdge,
    SwapNonManifold,
    SwapDegenerate,
    SwapEdgeExists,
    SwapParallel,
    SwapFeetOutside,
    SwapMissesCylinder,
    SwapClearanceBound,
    /// Degree ≤ 3 but the edge/face counts fit no case (e.g. non-manifold
    /// fan, degree 3 with 1 or more than 3 faces).
    NoCase,
    /// One face that is isolated (a component of its own).
    IsolatedFace,
    /// One face connecting two parts (its edge k2–k3 is used by no other face).
    ConnectingFace,
    /// 4.6.2: the new face misses the ball of k1.
    ThreeFacesMissBall,
    /// 4.6.2: no radius reduction meets the bound.
    ThreeFacesBound,
    /// 4.6.1 concave case: k3 = k4 or the edge k3–k4 exists.
    TwoFacesEdgeExists,
    /// 4.6.1 concave case: k3–k4 misses the ball of k1.
    TwoFacesMissBall,
    /// 4.6.1 concave case: no radius reduction meets the bound.
    TwoFacesBound,
    /// 4.6.1 with t_p ∈ ]0,1[: the swap is refused, or the one face left is.
    TwoFacesSwap,
    /// Seam vertex (module `seam`): the edge between its seam neighbours exists.
    SeamEdgeExists,
    /// Seam vertex: a fan cannot be swapped down to two faces.
    SeamSwap,
    /// Seam vertex: no radius reduction of the seam neighbours meets the bound.
    SeamBound,
    /// Collapse along a seam or border edge: the link condition fails for
    /// every such edge.
    CollapseLink,
    /// Collapse: the radius at the target would have to drop to zero.
    CollapseBound,
}

impl Refusal {
    pub const COUNT: usize = 24;
    pub const ALL: [Refusal; Refusal::COUNT] = [
        Refusal::Dead,
        Refusal::DegreeWait,
        Refusal::SwapBorderEdge,
        Refusal::SwapNonManifold,
        Refusal::SwapDegenerate,
        Refusal::SwapEdgeExists,
        Refusal::SwapParallel,
        Refusal::SwapFeetOutside,
        Refusal::SwapMissesCylinder,
        Refusal::SwapClearanceBound,
        Refusal::NoCase,
        Refusal::IsolatedFace,
        Refusal::ConnectingFace,
        Refusal::ThreeFacesMissBall,
        Refusal::ThreeFacesBound,
        Refusal::TwoFacesEdgeExists,
        Refusal::TwoFacesMissBall,
        Refusal::TwoFacesBound,
        Refusal::TwoFacesSwap,
        Refusal::SeamEdgeExists,
        Refusal::SeamSwap,
        Refusal::SeamBound,
        Refusal::CollapseLink,
        Refusal::CollapseBound,
    ];

    /// Short snake-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            Refusal::Dead => "dead",
            Refusal::DegreeWait => "degree_wait",
            Refusal::SwapBorderEdge => "swap_border_edge",
            Refusal::SwapNonManifold => "swap_non_manifold",
            Refusal::SwapDegenerate => "swap_degenerate",
            Refusal::SwapEdgeExists => "swap_edge_exists",
            Refusal::SwapParallel => "swap_parallel",
            Refusal::SwapFeetOutside => "swap_feet_outside",
            Refusal::SwapMissesCylinder => "swap_misses_cylinder",
            Refusal::SwapClearanceBound => "swap_clearance_bound",
            Refusal::NoCase => "no_case",
            Refusal::IsolatedFace => "isolated_face",
            Refusal::ConnectingFace => "connecting_face",
            Refusal::ThreeFacesMissBall => "three_faces_miss_ball",
            Refusal::ThreeFacesBound => "three_faces_bound",
            Refusal::TwoFacesEdgeExists => "two_faces_edge_exists",
            Refusal::TwoFacesMissBall => "two_faces_miss_ball",
            Refusal::TwoFacesBound => "two_faces_bound",
            Refusal::TwoFacesSwap => "two_faces_swap",
            Refusal::SeamEdgeExists => "seam_edge_exists",
            Refusal::SeamSwap => "seam_swap",
            Refusal::SeamBound => "seam_bound",
            Refusal::CollapseLink => "collapse_link",
            Refusal::CollapseBound => "collapse_bound",
        }
    }
}

pub(crate) fn remove_vertex(e: &mut Edit, k: u32) -> Option<f64> {
    remove_vertex_why(e, k).ok()
}

/// [`remove_vertex`] naming the first condition that refused. `e` must
/// hold no changes yet. When the thesis' cases (and the seam contraction)
/// refuse, the vertex is collapsed into a neighbour along one of its
/// edges if that is possible (module `seam`; second phase only).
pub(crate) fn remove_vertex_why(e: &mut Edit, k: u32) -> Result<f64, Refusal> {
    debug_assert!(e.changes().new_faces.is_empty() && e.changes().removed.is_empty());
    if !e.base.seam_ops {
        return thesis_remove(e, k);
    }
    let mut t = Edit::new(e.base);
    match thesis_remove(&mut t, k) {
        Ok(c) => {
            *e = t;
            Ok(c)
        }
        Err(r @ (Refusal::Dead | Refusal::DegreeWait | Refusal::IsolatedFace)) => Err(r),
        Err(r) => {
            // The cheaper of the collapse along an edge and the fan
            // removal (module `border`), if either applies.
            let mut f = Edit::new(e.base);
            let fan = super::border::remove(&mut f, k);
            match (seam::collapse_cheapest(e, k), fan) {
                (Ok(c), Ok(d)) if d < c => {
                    *e = f;
                    Ok(d)
                }
                (Ok(c), _) => Ok(c),
                (Err(_), Ok(d)) => {
                    *e = f;
                    Ok(d)
                }
                (Err(_), Err(_)) => Err(r),
            }
        }
    }
}

/// The thesis' removal (swaps, then 4.4/4.6), with the seam contraction for
/// seam vertices in the second phase.
fn thesis_remove(e: &mut Edit, k: u32) -> Result<f64, Refusal> {
    let mut cost = 0.0;
    if e.faces_of(k).is_empty() {
        return Err(Refusal::Dead);
    }
    if e.faces_of(k).len() > 2 * MAX_DEGREE {
        return Err(Refusal::DegreeWait);
    }
    let mut nb = e.neighbours(k);
    if nb.len() > MAX_DEGREE {
        return Err(Refusal::DegreeWait);
    }
    if nb.len() > 3
        && e.base.seam_ops
        && let Some(s) = seam::classify(e, k)
    {
        return seam::remove(e, k, s);
    }
    if nb.len() > 3 {
        let mut candidates = swap::Candidates::new(e, k, &nb);
        while nb.len() > 3 {
            let Some(s) = candidates.best(e) else {
                return Err(candidates.why_none(e));
            };
            cost += candidates.apply(e, &s);
            // The swap took away the edge k–k2 and no other (k3, k4 were
            // neighbours already).
            nb.retain(|v| *v != s.k[1]);
            debug_assert_eq!(nb, e.neighbours(k));
        }
    }
    match nb.len() {
        2 => Ok(cost + one_face(e, k, &nb)?),
        3 => Ok(cost + degree_three(e, k, &nb)?),
        _ => Err(Refusal::NoCase),
    }
}

/// Edge degree 2: one face `f = (k1,k2,k3)` (4.4, fig. 4.6). An isolated
/// face is kept (it is a connected component of its own, condition C). If
/// `k2` or `k3` has no other face, `f` hangs off the graph by one vertex and
/// goes. If both have other faces, `f` goes only if `k2–k3` stays an edge
/// (another face uses it), otherwise it is a connecting face.
fn one_face(e: &mut Edit, k: u32, nb: &[u32]) -> Result<f64, Refusal> {
    let [f] = e.faces_of(k)[..] else {
        return Err(Refusal::NoCase);
    };
    let (a, b) = (nb[0], nb[1]);
    let alone = |v: u32| e.faces_of(v).len() == 1;
    match (alone(a), alone(b)) {
        (true, true) => return Err(Refusal::IsolatedFace),
        (true, false) | (false, true) => {}
        (false, false) => {
            if e.edge_faces(a, b).0 < 2 {
                return Err(Refusal::ConnectingFace);
            }
        }
    }
    let v = e.face_volume(f);
    e.remove_face(f);
    e.count(Op::OneFace);
    Ok(v)
}

fn degree_three(e: &mut Edit, k: u32, nb: &[u32]) -> Result<f64, Refusal> {
    match e.faces_of(k).len() {
        3 => three_faces(e, k, nb),
        2 => two_faces(e, k),
        _ => Err(Refusal::NoCase),
    }
}

/// 4.6.2: three faces around `k1` are replaced by `(k2,k3,k4)`. If that face
/// exists already the three just go. Otherwise the point `q` of the new face
/// nearest to `k1` must lie in the ball of `k1` and the new face's radius at
/// `q` must not exceed the old clearance there (lowering the radii of
/// `k2,k3,k4` optimally if it does; the same corner argument as for swaps,
/// with the new face split at `q` into three triangles, one per old face).
fn three_faces(e: &mut Edit, k: u32, nb: &[u32]) -> Result<f64, Refusal> {
    let old: Vec<u32> = e.faces_of(k).to_vec();
    let old_volume: f64 = old.iter().map(|&f| e.face_volume(f)).sum();
    let [a, b, c] = [nb[0], nb[1], nb[2]];
    if e.has_face(a, b, c) {
        for &f in &old {
            e.remove_face(f);
        }
        e.count(Op::ThreeFacesExisting);
        return Ok(old_volume);
    }
    let pk = e.pos(k);
    let (q, w) = closest_on_triangle(pk, e.pos(a), e.pos(b), e.pos(c));
    if dist(q, pk) >= e.radius(k) {
        return Err(Refusal::ThreeFacesMissBall);
    }
    let bound = old
        .iter()
        .map(|&f| e.clearance_at(f, q))
        .fold(f64::INFINITY, f64::min)
        - MARGIN;
    let r = [a, b, c].map(|v| e.radius(v));
    let nr = optimal_planar_reduction(r, w, bound).ok_or(Refusal::ThreeFacesBound)?;
    if nr.iter().any(|&x| x <= 0.0) {
        return Err(Refusal::ThreeFacesBound);
    }
    let lowered = [(a, nr[0]), (b, nr[1]), (c, nr[2])];
    let cost = loss(old_volume, e.volume([a, b, c], &lowered)) + e.lowering_cost(&lowered, &old);
    for &f in &old {
        e.remove_face(f);
    }
    for (v, r) in lowered {
        if r < e.radius(v) {
            e.set_radius(v, r);
        }
    }
    e.add_face([a, b, c]);
    e.count(Op::ThreeFaces);
    Ok(cost)
}

/// 4.6.1: two faces `fi = (k1,k2,k3)`, `fj = (k1,k2,k4)`. With the foot
/// `t_p ∈ ]0,1[` the edge `k1–k2` is swapped and `k1` is left with one face;
/// with `t_p ≤ 0` (`k1` a concave corner) both faces become `(k2,k3,k4)` if
/// the new edge `k3–k4` passes through the ball of `k1`, with the
/// clearances of `k3`, `k4` corrected as for a swap. The thesis leaves `k1`
/// for `k2` when `t_p ≥ 1`; but the replacement keeps condition A for any
/// `t_p` (split `(k2,k3,k4)` at `q` into `(k2,k3,q) ⊂ vol(fi)` and
/// `(k2,q,k4) ⊂ vol(fj)`: `k2`, `k3`, `k4` are corners of the old faces and
/// the radius at `q` is bounded by both old clearances), and `k2` may never
/// go (a seam vertex), so it is used there too, and when the swap of the
/// middle case is refused or the edges are parallel.
fn two_faces(e: &mut Edit, k1: u32) -> Result<f64, Refusal> {
    let [fi, fj] = e.faces_of(k1)[..] else {
        return Err(Refusal::NoCase);
    };
    let ti = e.face(fi);
    let k2 = e
        .face(fj)
        .into_iter()
        .find(|&v| v != k1 && ti.contains(&v))
        .ok_or(Refusal::NoCase)?;
    let k3 = third(e, fi, k1, k2);
    let k4 = third(e, fj, k1, k2);
    let (p1, p2, p3, p4) = (e.pos(k1), e.pos(k2), e.pos(k3), e.pos(k4));
    let feet = perpendicular_feet(p1, p2, p3, p4);
    if let Some((tp, _)) = feet
        && tp > 0.0
        && tp < 1.0
        && let Some(s) = swap::plan(e, k1, k2)
    {
        swap::apply(e, &s);
        let nb = e.neighbours(k1);
        return Ok(s.cost + one_face(e, k1, &nb).map_err(|_| Refusal::TwoFacesSwap)?);
    }
    if k3 == k4 || e.has_edge(k3, k4) {
        return Err(Refusal::TwoFacesEdgeExists);
    }
    // Point of k3–k4 nearest to k1.
    let v = sub(p4, p3);
    let tq = (crate::reduce::volume::dot(sub(p1, p3), v) / crate::reduce::volume::dot(v, v))
        .clamp(0.0, 1.0);
    let q = add(p3, scale(v, tq));
    if dist(q, p1) >= e.radius(k1) {
        return Err(Refusal::TwoFacesMissBall);
    }
    let bound = e.clearance_at(fi, q).min(e.clearance_at(fj, q)) - MARGIN;
    let (n3, n4) = optimal_linear_reduction(e.radius(k3), e.radius(k4), tq, bound)
        .ok_or(Refusal::TwoFacesBound)?;
    if n3 <= 0.0 || n4 <= 0.0 {
        return Err(Refusal::TwoFacesBound);
    }
    let lowered = [(k3, n3), (k4, n4)];
    let old = e.face_volume(fi) + e.face_volume(fj);
    let cost = loss(old, e.volume([k2, k3, k4], &lowered)) + e.lowering_cost(&lowered, &[fi, fj]);
    e.remove_face(fi);
    e.remove_face(fj);
    for (v, r) in lowered {
        if r < e.radius(v) {
            e.set_radius(v, r);
        }
    }
    e.add_face([k2, k3, k4]);
    e.count(Op::TwoFacesConcave);
    Ok(cost)
}
