//! Removing one vertex (thesis 4.4 `EntferneKnoten`, 4.6): lower its edge
//! degree by the cheapest swaps until it is 3 or less, then remove it by the
//! case that applies. Returns the total lost volume, or `None` if the vertex
//! cannot be removed without breaking a condition (the edit must then be
//! discarded).

use super::mesh::{Edit, Op};
use super::swap::{self, MARGIN, third};
use super::volume::{
    add, closest_on_triangle, dist, optimal_linear_reduction, optimal_planar_reduction,
    perpendicular_feet, scale, sub,
};

/// Vertices with more neighbours are left alone until swaps elsewhere lower
/// their degree: removing one takes `d − 3` swaps, each choosing among `d`
/// edges, and such hubs are touched by every removal around them, so costing
/// them would dominate the run time. (Not in the thesis; a speed guard.)
pub(crate) const MAX_DEGREE: usize = 20;

pub(crate) fn remove_vertex(e: &mut Edit, k: u32) -> Option<f64> {
    let mut cost = 0.0;
    if e.faces_of(k).len() > 2 * MAX_DEGREE {
        return None;
    }
    let mut nb = e.neighbours(k);
    if nb.len() > MAX_DEGREE {
        return None;
    }
    if nb.len() > 3 {
        let mut candidates = swap::Candidates::new(e, k, &nb);
        while nb.len() > 3 {
            let s = candidates.best()?;
            let [_, _, k3, k4] = s.k;
            let lowered: Vec<u32> = [(k3, s.r3), (k4, s.r4)]
                .into_iter()
                .filter(|&(v, r)| r < e.radius(v))
                .map(|x| x.0)
                .collect();
            swap::apply(e, &s);
            cost += s.cost;
            candidates.after(e, &s, &lowered);
            nb = e.neighbours(k);
        }
    }
    match nb.len() {
        2 => Some(cost + one_face(e, k, &nb)?),
        3 => Some(cost + degree_three(e, k, &nb)?),
        _ => None,
    }
}

/// Edge degree 2: one face `f = (k1,k2,k3)` (4.4, fig. 4.6). An isolated
/// face is kept (it is a connected component of its own, condition C). If
/// `k2` or `k3` has no other face, `f` hangs off the graph by one vertex and
/// goes. If both have other faces, `f` goes only if `k2–k3` stays an edge
/// (another face uses it), otherwise it is a connecting face.
fn one_face(e: &mut Edit, k: u32, nb: &[u32]) -> Option<f64> {
    let [f] = e.faces_of(k)[..] else { return None };
    let (a, b) = (nb[0], nb[1]);
    let alone = |v: u32| e.faces_of(v).len() == 1;
    let removable = match (alone(a), alone(b)) {
        (true, true) => false,
        (true, false) | (false, true) => true,
        (false, false) => e.edge_faces(a, b).0 >= 2,
    };
    if !removable {
        return None;
    }
    let v = e.volume(e.face(f), &[]);
    e.remove_face(f);
    e.count(Op::OneFace);
    Some(v)
}

fn degree_three(e: &mut Edit, k: u32, nb: &[u32]) -> Option<f64> {
    match e.faces_of(k).len() {
        3 => three_faces(e, k, nb),
        2 => two_faces(e, k),
        _ => None,
    }
}

/// 4.6.2: three faces around `k1` are replaced by `(k2,k3,k4)`. If that face
/// exists already the three just go. Otherwise the point `q` of the new face
/// nearest to `k1` must lie in the ball of `k1` and the new face's radius at
/// `q` must not exceed the old clearance there (lowering the radii of
/// `k2,k3,k4` optimally if it does; the same corner argument as for swaps,
/// with the new face split at `q` into three triangles, one per old face).
fn three_faces(e: &mut Edit, k: u32, nb: &[u32]) -> Option<f64> {
    let old: Vec<u32> = e.faces_of(k).to_vec();
    let old_volume: f64 = old.iter().map(|&f| e.volume(e.face(f), &[])).sum();
    let [a, b, c] = [nb[0], nb[1], nb[2]];
    if e.has_face(a, b, c) {
        for &f in &old {
            e.remove_face(f);
        }
        e.count(Op::ThreeFacesExisting);
        return Some(old_volume);
    }
    let pk = e.pos(k);
    let (q, w) = closest_on_triangle(pk, e.pos(a), e.pos(b), e.pos(c));
    if dist(q, pk) >= e.radius(k) {
        return None;
    }
    let bound = old
        .iter()
        .map(|&f| e.clearance_at(f, q))
        .fold(f64::INFINITY, f64::min)
        - MARGIN;
    let r = [a, b, c].map(|v| e.radius(v));
    let nr = optimal_planar_reduction(r, w, bound)?;
    if nr.iter().any(|&x| x <= 0.0) {
        return None;
    }
    let lowered = [(a, nr[0]), (b, nr[1]), (c, nr[2])];
    let cost = old_volume - e.volume([a, b, c], &lowered) + e.lowering_cost(&lowered, &old);
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
    Some(cost)
}

/// 4.6.1: two faces `fi = (k1,k2,k3)`, `fj = (k1,k2,k4)`. With the foot
/// `t_p ∈ ]0,1[` the edge `k1–k2` is swapped and `k1` is left with one face;
/// with `t_p ≤ 0` (`k1` a concave corner) both faces become `(k2,k3,k4)` if
/// the new edge `k3–k4` passes through the ball of `k1`, with the
/// clearances of `k3`, `k4` corrected as for a swap; with `t_p ≥ 1` the
/// vertex is left for `k2` (as in the thesis).
fn two_faces(e: &mut Edit, k1: u32) -> Option<f64> {
    let [fi, fj] = e.faces_of(k1)[..] else {
        return None;
    };
    let ti = e.face(fi);
    let k2 = e
        .face(fj)
        .into_iter()
        .find(|&v| v != k1 && ti.contains(&v))?;
    let k3 = third(e, fi, k1, k2);
    let k4 = third(e, fj, k1, k2);
    let (p1, p2, p3, p4) = (e.pos(k1), e.pos(k2), e.pos(k3), e.pos(k4));
    let (tp, _) = perpendicular_feet(p1, p2, p3, p4)?;
    if tp > 0.0 && tp < 1.0 {
        let s = swap::plan(e, k1, k2)?;
        swap::apply(e, &s);
        let nb = e.neighbours(k1);
        return Some(s.cost + one_face(e, k1, &nb)?);
    }
    if tp >= 1.0 || k3 == k4 || e.has_edge(k3, k4) {
        return None;
    }
    // Point of k3–k4 nearest to k1.
    let v = sub(p4, p3);
    let tq = (crate::reduce::volume::dot(sub(p1, p3), v) / crate::reduce::volume::dot(v, v))
        .clamp(0.0, 1.0);
    let q = add(p3, scale(v, tq));
    if dist(q, p1) >= e.radius(k1) {
        return None;
    }
    let bound = e.clearance_at(fi, q).min(e.clearance_at(fj, q)) - MARGIN;
    let (n3, n4) = optimal_linear_reduction(e.radius(k3), e.radius(k4), tq, bound)?;
    if n3 <= 0.0 || n4 <= 0.0 {
        return None;
    }
    let lowered = [(k3, n3), (k4, n4)];
    let old = e.volume(ti, &[]) + e.volume(e.face(fj), &[]);
    let cost = old - e.volume([k2, k3, k4], &lowered) + e.lowering_cost(&lowered, &[fi, fj]);
    e.remove_face(fi);
    e.remove_face(fj);
    for (v, r) in lowered {
        if r < e.radius(v) {
            e.set_radius(v, r);
        }
    }
    e.add_face([k2, k3, k4]);
    e.count(Op::TwoFacesConcave);
    Some(cost)
}
