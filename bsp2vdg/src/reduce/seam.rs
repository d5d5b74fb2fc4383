//! Removing a vertex on a seam (not in the thesis): the operation for the
//! vertices the thesis' cases leave behind.
//!
//! A Voronoi graph is no surface: where three or more sheets of faces meet
//! (the medial sheets of two walls meeting a floor's, say) an edge belongs
//! to three or more faces. The thesis never swaps such a non-manifold edge
//! (condition C) and only removes a vertex of edge degree 2 or 3 (4.6), so a
//! vertex in the middle of a seam, with two sheets or more around it, keeps
//! at least two neighbours on the seam plus one in each sheet: degree ≥ 4
//! forever. On most real maps these vertices were a few per cent of the graph
//! when the reduction stopped with "nothing removable".
//! Two operations take them, both keeping conditions A–C of 4.2:
//!
//! **Seam contraction.** A *seam vertex* `k` has exactly two *seam
//! neighbours* `s1`, `s2` — neighbours whose edge to `k` does not have
//! exactly two faces — and its faces fall into `m ≥ 2` *fans*: the classes
//! of faces joined across edges `k–x` with exactly two faces. Every fan must
//! be a path of faces from the edge `k–s1` to the edge `k–s2` (so `m` is the
//! number of faces on either seam edge). The seam is a line `… s1 – k – s2 …`
//! with `m` sheets hanging off it, and `k` goes in two steps:
//!
//! 1. **Swaps inside the fans.** The thesis' edge swap (4.5, with all its
//!    conditions, module `swap`) on the edges `k–x` inside a fan, cheapest
//!    first over all fans, until every fan has two faces
//!    `(k, s1, x_i)`, `(k, x_i, s2)`. A fan is never swapped down to one face.
//! 2. **Seam contraction.** In every fan the two faces become one,
//!    `(s1, x_i, s2)`: the seam loses `k` and its edge `s1–s2` carries the
//!    same `m` sheets. This is the thesis' concave two-face case (4.6.1)
//!    done in all fans at once with one shared new edge.
//!
//! **Conditions.** *A* (the volume never grows): split each new face at the
//! point `q` of `s1–s2` nearest to `k` into `(x_i, s1, q)` and
//! `(x_i, q, s2)`. A face volume is the union of balls of linearly
//! interpolated radius over its triangle, and the clearance an old face
//! gives at a point is concave, so a new triangle lies in an old face's
//! volume when its radius at each corner is at most the old face's
//! clearance there (the argument of module `swap`). `x_i` and `s1` are
//! corners of the old face `(k, s1, x_i)` and keep or lower their radii;
//! the radius at `q`, linear between `s1` and `s2`, must not exceed the
//! smallest clearance the old faces of any fan give at `q` (the thesis'
//! optimal linear reduction, 6.1.5, checks it; see `MAX_LOWERING`). *C* (components and topology): the edge `s1–s2` must not exist
//! before, so the new faces are new and no hole closes; each fan is a disc
//! that stays a disc, the seam keeps its sheets, only `k` is taken out of
//! it — the complex after is homeomorphic to the one before. *B* (the
//! continuous map ρ) follows from the topology as in the thesis (4.2).
//!
//! **Collapse along an edge.** What neither the thesis' cases nor the seam
//! contraction remove — seam ends and crossings (one, or three or more,
//! seam neighbours), where a seam meets a border, border vertices whose
//! swaps are refused — is collapsed into one of its neighbours `s` (a
//! half-edge collapse, Hoppe's edge collapse without a new vertex, so the
//! thesis' objection to it, 4.2, does not apply): the faces `(k, s, v)` go
//! and every other face `(k, a, b)` becomes `(s, a, b)`.
//! *C:* the link condition of Dey, Edelsbrunner et al. ("Topology
//! preserving edge contraction", 1999) for 2-complexes — every common
//! neighbour `v` of `k` and `s` spans a face `(k, s, v)`, and no moved face
//! lands on an existing one (which would flatten a closed shell) — plus:
//! each edge `s–v` keeps a face, so no component splits. *A:* the moved face
//! `(s, a, b)` lies in the volume of the old face `(k, a, b)` when the
//! radius at `s` is at most that face's clearance at `s` (corners `a`, `b`
//! are its own; concavity as above), so `s`'s radius must not exceed the
//! least of those clearances — or, where both other corners `a`, `b` span
//! faces `(k, s, a)`, `(k, s, b)` (a junction of seams), the bound of a split
//! of `(s, a, b)` at an inner point between those three old faces, if that
//! asks less (`border::split_bound`). The cheapest collapse over all edges
//! of `k` is taken.
//!
//! Both operations could lower the clearances of `s1`, `s2` or `s` to meet
//! their bounds, as the thesis' cases do; they do not (`MAX_LOWERING`): on
//! the shared maps that cost walkable coverage and coverage ≥ 32, and where
//! coverage and ratio conflict, coverage wins.
//!
//! **Keeping standing places.** With kept points (`reduce_keeping`) a
//! removal that would take one's ball of `KEEP_MARGIN` (module `keep`) out
//! of the volume is refused, in both phases; in the second, if the vertex's
//! usual removal fails that, its cheapest collapse that passes is taken
//! instead. Where keeping the points and reaching the limit conflict, the
//! points win.
//!
//! **Keeping coverage.** The second phase also keeps *deep points*: every
//! vertex `v` of the unreduced graph with clearance `r > DEEP_CLEARANCE`
//! (32) keeps the ball of radius `r − 32` around it inside the volume, or
//! what the volume held of that ball when the phase began (module `keep`,
//! `Keep::deep`; a point held less than 1 unit deep is not kept). The free
//! space is the union of its medial balls, so the points of clearance ≥ 32
//! are about the union of the shrunk balls, and `vdgview check`'s coverage
//! counts exactly those: the phase cannot take it. Without them it took a
//! visible share of it; with them coverage stays as the
//! thesis' cases left it, and the phase stops earlier.
//!
//! **When.** These operations run in a second phase only: the reduction
//! first runs with the thesis' cases alone, exactly as before, and only if
//! that stops above the limit with nothing removable are all vertices
//! costed again with the seam operations allowed. Maps that reached the
//! limit before get the identical graph; the others go on towards it.
//! Cheapest first still holds within the phase (the same cost, the
//! model-volume loss of 4.3, orders all operations).
//!
//! A border vertex (one fan, its two special edges with one face each) is
//! the `m = 1` case of the contraction and already handled by the thesis'
//! path (swaps down to degree 3, then 4.6.1); so is a seam vertex whose
//! fans are each swapped down to the one face `(k, s1, s2)` (the merge of
//! module `swap`).

use smallvec::SmallVec;

use super::mesh::{Edit, Op};
use super::remove::Refusal;
use super::swap::{self, MARGIN};
use super::volume::{add, dot, loss, optimal_linear_reduction, scale, sub};

/// The fans of a seam vertex (see the module docs).
#[derive(Debug, Clone)]
pub(crate) struct Seam {
    pub s: [u32; 2],
    /// Per interior neighbour (sorted by id): its fan.
    interior: SmallVec<[(u32, u8); 16]>,
    /// Faces per fan.
    faces: SmallVec<[u8; 4]>,
}

impl Seam {
    /// Number of fans (sheets meeting at the seam).
    pub fn fans(&self) -> usize {
        self.faces.len()
    }
}

/// The seam structure of `k`, or `None` if `k` is not a seam vertex with
/// two fans or more (an interior or border vertex, a seam end or crossing).
pub(crate) fn classify(e: &Edit, k: u32) -> Option<Seam> {
    let faces = e.faces_of(k);
    if faces.len() < 4 || faces.len() > 64 {
        return None;
    }
    let nb = e.neighbours(k);
    let mut special: SmallVec<[u32; 4]> = SmallVec::new();
    let mut regular: SmallVec<[u32; 16]> = SmallVec::new();
    for &n in &nb {
        if e.edge_faces(k, n).0 == 2 {
            regular.push(n);
        } else {
            special.push(n);
            if special.len() > 2 {
                return None;
            }
        }
    }
    let [s1, s2] = special[..] else {
        return None;
    };
    // Fans: union-find over k's faces through regular edges.
    let n = faces.len();
    let mut parent: SmallVec<[u8; 32]> = (0..n as u8).collect();
    fn find(p: &mut [u8], mut x: u8) -> u8 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let tris: SmallVec<[[u32; 3]; 32]> = faces.iter().map(|&f| e.face(f)).collect();
    for &x in &regular {
        let mut with = tris
            .iter()
            .enumerate()
            .filter(|(_, t)| t.contains(&x))
            .map(|(i, _)| i as u8);
        let (Some(a), Some(b)) = (with.next(), with.next()) else {
            return None;
        };
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        parent[ra as usize] = rb;
    }
    // Per fan: faces, and its ends on s1 and s2 (exactly one each).
    let mut root_fan: SmallVec<[(u8, u8); 4]> = SmallVec::new();
    let mut count: SmallVec<[u8; 4]> = SmallVec::new();
    let mut ends: SmallVec<[[u8; 2]; 4]> = SmallVec::new();
    for (i, t) in tris.iter().enumerate() {
        let r = find(&mut parent, i as u8);
        let fan = match root_fan.iter().find(|x| x.0 == r) {
            Some(x) => x.1,
            None => {
                root_fan.push((r, count.len() as u8));
                count.push(0);
                ends.push([0, 0]);
                count.len() as u8 - 1
            }
        };
        count[fan as usize] += 1;
        ends[fan as usize][0] += t.contains(&s1) as u8;
        ends[fan as usize][1] += t.contains(&s2) as u8;
    }
    // A fan of one face (k, s1, s2) means the edge s1–s2 exists: refused
    // later anyway, and not a path of two ends.
    if count.len() < 2 || ends.iter().zip(&count).any(|(e, &c)| *e != [1, 1] || c < 2) {
        return None;
    }
    let interior = regular
        .iter()
        .map(|&x| {
            let i = tris.iter().position(|t| t.contains(&x)).unwrap_or(0);
            let r = find(&mut parent, i as u8);
            let fan = root_fan.iter().find(|y| y.0 == r).map_or(0, |y| y.1);
            (x, fan)
        })
        .collect();
    Some(Seam {
        s: [s1, s2],
        interior,
        faces: count,
    })
}

/// Removes the seam vertex `k` (see the module docs): the lost volume, or
/// why not.
pub(crate) fn remove(e: &mut Edit, k: u32, mut seam: Seam) -> Result<f64, Refusal> {
    let [s1, s2] = seam.s;
    if e.has_edge(s1, s2) {
        return Err(Refusal::SeamEdgeExists);
    }
    let mut cost = 0.0;
    let inner: SmallVec<[u32; 24]> = seam.interior.iter().map(|x| x.0).collect();
    let mut candidates = swap::Candidates::new(e, k, &inner);
    // A fan with two faces keeps its last interior vertex.
    for fan in 0..seam.fans() {
        if seam.faces[fan] == 2 {
            exclude_last(&mut candidates, &seam, fan as u8);
        }
    }
    while seam.faces.iter().any(|&c| c > 2) {
        let Some(s) = candidates.best(e) else {
            return Err(Refusal::SeamSwap);
        };
        let k2 = s.k[1];
        if s.merge {
            // (k, k3, k4) existed: only possible with k3–k4 = s1–s2,
            // which the check above excludes; refuse rather than merge.
            return Err(Refusal::SeamSwap);
        }
        cost += candidates.apply(e, &s);
        let Some(i) = seam.interior.iter().position(|x| x.0 == k2) else {
            return Err(Refusal::SeamSwap);
        };
        let fan = seam.interior.remove(i).1;
        seam.faces[fan as usize] -= 1;
        if seam.faces[fan as usize] == 2 {
            exclude_last(&mut candidates, &seam, fan);
        }
    }
    contract(e, k, &seam).map(|c| c + cost)
}

/// Takes the last interior vertex of `fan` out of the swap candidates.
fn exclude_last(candidates: &mut swap::Candidates, seam: &Seam, fan: u8) {
    for &(x, f) in &seam.interior {
        if f == fan {
            candidates.exclude(x);
        }
    }
}

/// Step 2: every fan is `(k, s1, x_i)`, `(k, x_i, s2)`; both become
/// `(s1, x_i, s2)`.
fn contract(e: &mut Edit, k: u32, seam: &Seam) -> Result<f64, Refusal> {
    let [s1, s2] = seam.s;
    let (p1, p2, pk) = (e.pos(s1), e.pos(s2), e.pos(k));
    let v = sub(p2, p1);
    let len2 = dot(v, v);
    if len2 <= 0.0 {
        return Err(Refusal::SeamBound);
    }
    let tq = (dot(sub(pk, p1), v) / len2).clamp(0.0, 1.0);
    let q = add(p1, scale(v, tq));
    let old: SmallVec<[u32; 8]> = SmallVec::from_slice(e.faces_of(k));
    debug_assert_eq!(old.len(), 2 * seam.fans());
    let mut bound = f64::INFINITY;
    for &f in &old {
        bound = bound.min(e.clearance_at(f, q));
    }
    let (n1, n2) = optimal_linear_reduction(e.radius(s1), e.radius(s2), tq, bound - MARGIN)
        .ok_or(Refusal::SeamBound)?;
    if n1 <= 0.0 || n2 <= 0.0 || !mild(e, s1, n1) || !mild(e, s2, n2) {
        return Err(Refusal::SeamBound);
    }
    let lowered = [(s1, n1), (s2, n2)];
    let new_tris: SmallVec<[[u32; 3]; 4]> = seam
        .interior
        .iter()
        .map(|&(x, _)| {
            // Orientation as the fan's face on s1: (…, s1, x) order kept.
            let f = old
                .iter()
                .copied()
                .find(|&f| {
                    let t = e.face(f);
                    t.contains(&s1) && t.contains(&x)
                })
                .unwrap_or(old[0]);
            let t = e.face(f);
            t.map(|v| if v == k { s2 } else { v })
        })
        .collect();
    let old_volume: f64 = old.iter().map(|&f| e.face_volume(f)).sum();
    let new_volume: f64 = new_tris.iter().map(|&t| e.volume(t, &lowered)).sum();
    let cost = loss(old_volume, new_volume) + e.lowering_cost(&lowered, &old);
    for &f in &old {
        e.remove_face(f);
    }
    for (v, r) in lowered {
        if r < e.radius(v) {
            e.set_radius(v, r);
        }
    }
    for t in new_tris {
        e.add_face(t);
    }
    e.count(Op::SeamContract);
    Ok(cost)
}

/// Topological class of `k` for diagnostics: special neighbours (edges
/// without exactly two faces: border 1, seam ≥ 3) and their face counts.
pub(crate) fn describe(e: &Edit, k: u32) -> String {
    let nb = e.neighbours(k);
    let mut sp: Vec<usize> = nb
        .iter()
        .map(|&n| e.edge_faces(k, n).0)
        .filter(|&c| c != 2)
        .collect();
    sp.sort_unstable();
    if sp.len() > 4 {
        return format!("special{}+", sp.len());
    }
    format!("special{:?}", sp)
}

/// A half-edge collapse of `k` into its neighbour `s` (see the module
/// docs, "Collapse along an edge"): the lost volume, or why not. `e` must
/// not hold other changes of `k`'s faces yet; `nb` are `k`'s neighbours
/// (`e.neighbours(k)`, the same for every `s` the callers try).
pub(crate) fn collapse(e: &mut Edit, k: u32, s: u32, nb: &[u32]) -> Result<f64, Refusal> {
    let faces: SmallVec<[u32; 16]> = SmallVec::from_slice(e.faces_of(k));
    let mut moved: SmallVec<[[u32; 3]; 16]> = SmallVec::new();
    let mut around: SmallVec<[u32; 4]> = SmallVec::new();
    for &f in &faces {
        let t = e.face(f);
        if t.contains(&s) {
            around.push(t.into_iter().find(|&v| v != k && v != s).unwrap_or(s));
        } else {
            moved.push(t.map(|v| if v == k { s } else { v }));
        }
    }
    if around.is_empty() || moved.is_empty() {
        return Err(Refusal::CollapseLink);
    }
    // Link condition (Dey et al.): a common neighbour of k and s spans a
    // face with them, and no face moves onto an existing one (that would
    // flatten a closed shell). The edges s–v of the faces k–s–v that go
    // must stay edges of some face (else a component splits).
    for &n in nb {
        if n != s && !around.contains(&n) && e.has_edge(s, n) {
            return Err(Refusal::CollapseLink);
        }
    }
    for t in &moved {
        let [a, b] = other_two(t, s);
        if e.has_face(s, a, b) {
            return Err(Refusal::CollapseLink);
        }
    }
    for &v in &around {
        if e.edge_faces(s, v).0 + e.edge_faces(k, v).0 < 3 {
            return Err(Refusal::CollapseLink);
        }
    }
    // Condition A: a moved face (s, a, b) lies in the volume of the old face
    // (k, a, b) when the radius at s is at most that face's clearance at s
    // (the corners a, b are its own; concavity, see module `swap`).
    // The bound only falls: once it refuses, the faces left cannot help.
    let ps = e.pos(s);
    let mut bound = e.radius(s);
    for &f in &faces {
        if !e.face(f).contains(&s) {
            let mut b = e.clearance_at(f, ps) - MARGIN;
            if b < bound {
                // Or split the moved face between the old faces (module `border`).
                b = b.max(super::border::split_bound(e, k, s, f, &faces));
            }
            bound = bound.min(b);
            if bound <= 0.0 || !mild(e, s, bound) {
                return Err(Refusal::CollapseBound);
            }
        }
    }
    if bound <= 0.0 || !mild(e, s, bound) {
        return Err(Refusal::CollapseBound);
    }
    let lowered = [(s, bound)];
    let old_volume: f64 = faces.iter().map(|&f| e.face_volume(f)).sum();
    let new_volume: f64 = moved.iter().map(|&t| e.volume(t, &lowered)).sum();
    let cost = loss(old_volume, new_volume) + e.lowering_cost(&lowered, &faces);
    for &f in &faces {
        e.remove_face(f);
    }
    if bound < e.radius(s) {
        e.set_radius(s, bound);
    }
    for t in moved {
        e.add_face(t);
    }
    e.count(Op::SeamCollapse);
    Ok(cost)
}

/// Whether lowering `v`'s clearance to `r` is small enough for the seam
/// operations (see [`MAX_LOWERING`]).
fn mild(e: &Edit, v: u32, r: f64) -> bool {
    r >= (1.0 - MAX_LOWERING) * e.radius(v)
}

/// In the second phase every vertex of the unreduced graph with a clearance
/// `r` above this keeps its ball shrunk to `r − DEEP_CLEARANCE` inside the
/// volume (or what the volume held of it when the phase began): the points
/// with clearance ≥ 32, whose share inside the volume `vdgview check` reports
/// as coverage, lie in the union of those balls. Without them the phase took
/// a visible share of that coverage.
pub(crate) const DEEP_CLEARANCE: f64 = 32.0;

/// The largest share of a clearance the seam operations may take off: none.
/// Lowering the neighbour's clearance thins the volume around it, and on the
/// shared maps even a tenth cost walkable coverage, and coverage ≥ 32 fell
/// markedly with no bound at all. Where coverage and ratio conflict, coverage
/// wins.
const MAX_LOWERING: f64 = 0.0;

/// The two vertices of `t` besides `s`.
fn other_two(t: &[u32; 3], s: u32) -> [u32; 2] {
    let mut o = [s; 2];
    let mut i = 0;
    for &v in t {
        if v != s && i < 2 {
            o[i] = v;
            i += 1;
        }
    }
    o
}

/// The cheapest [`collapse`] of `k` along one of its edges, applied to `e`
/// (which must hold no changes yet), or the last refusal.
pub(crate) fn collapse_cheapest(e: &mut Edit, k: u32) -> Result<f64, Refusal> {
    let mut best: Option<(f64, Edit)> = None;
    let mut why = Refusal::CollapseLink;
    let nb = e.neighbours(k);
    for &s in &nb {
        let mut t = Edit::new(e.base);
        match collapse(&mut t, k, s, &nb) {
            Ok(c) if best.as_ref().is_none_or(|b| c < b.0) => best = Some((c, t)),
            Ok(_) => {}
            Err(r) => why = r,
        }
    }
    let (c, t) = best.ok_or(why)?;
    *e = t;
    Ok(c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Graph;
    use crate::reduce::mesh::Mesh;
    use crate::reduce::remove::remove_vertex_why;

    /// A book of three pages (triangles) on the spine 0–1, vertex 0 at its
    /// end: every edge of 0 is a seam (three faces) or a border (one face),
    /// so no swap applies and the thesis' cases (degree ≤ 3) do not either.
    fn book() -> Graph {
        let mut g = Graph {
            vertices: vec![[0.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
            clearance: vec![12.0, 12.0],
            faces: vec![],
        };
        for j in 0..3 {
            let a = std::f64::consts::TAU * j as f64 / 3.0;
            g.vertices.push([6.0, 6.0 * a.cos(), 6.0 * a.sin()]);
            g.clearance.push(5.0);
            g.faces.push([0, 1, 2 + j as u32]);
        }
        g
    }

    #[test]
    fn a_seam_end_the_thesis_keeps_is_collapsed_inside_the_old_volume() {
        let mut mesh = Mesh::new(&book());
        assert!(remove_vertex_why(&mut Edit::new(&mesh), 0).is_err());
        mesh.seam_ops = true;
        let mut e = Edit::new(&mesh);
        let cost = remove_vertex_why(&mut e, 0).expect("collapsed");
        assert!(cost >= 0.0);
        let ch = e.into_changes();
        #[cfg(debug_assertions)]
        crate::reduce::check::condition_a(&mesh, &ch).unwrap();
        mesh.apply(ch);
        assert!(mesh.vfaces[0].is_empty());
        let g = mesh.to_graph();
        // Two pages are left on a new spine; one page folded into it.
        assert_eq!(g.faces.len(), 2);
        assert_eq!(g.vertices.len(), 4);
        // A lowered clearance, never a raised one.
        assert!(g.clearance.iter().all(|&c| c > 0.0 && c <= 12.0));
    }

    #[test]
    fn a_deep_point_refuses_the_collapse_that_takes_its_ball() {
        use crate::reduce::keep::Keep;
        let mesh = Mesh::new(&book());
        // Vertex 0's ball (radius 12) shrunk to 10 must stay inside; every
        // collapse of 0 (into a page's corner) takes it. A ball of 2 near
        // vertex 1 (radius 12, 3 units away) stays inside.
        let deep = Keep::deep(&mesh, &[[0.0, 0.0, 0.0], [17.0, 0.0, 0.0]], &[10.0, 2.0]);
        assert_eq!(deep.len(), 2);
        let far = Keep::deep(&mesh, &[[17.0, 0.0, 0.0]], &[2.0]);
        let mut collapses = 0;
        for s in Edit::new(&mesh).neighbours(0) {
            let mut e = Edit::new(&mesh);
            if collapse(&mut e, 0, s, &Edit::new(&mesh).neighbours(0)).is_err() {
                continue;
            }
            collapses += 1;
            assert!(!deep.holds(&e), "collapse into {s} kept the ball");
            assert!(far.holds(&e), "collapse into {s} took the far ball");
        }
        assert!(collapses > 0);
        // Not kept: a point outside the volume, and a ball that would be too small.
        assert_eq!(Keep::deep(&mesh, &[[0.0, 0.0, 50.0]], &[10.0]).len(), 0);
        assert_eq!(Keep::deep(&mesh, &[[0.0, 0.0, 0.0]], &[0.5]).len(), 0);
    }

    #[test]
    fn collapse_refuses_to_flatten_a_closed_shell() {
        // A tetrahedron's surface: collapsing any edge would flatten it.
        let g = Graph {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [20.0, 0.0, 0.0],
                [0.0, 20.0, 0.0],
                [0.0, 0.0, 20.0],
            ],
            clearance: vec![10.0; 4],
            faces: vec![[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]],
        };
        let mesh = Mesh::new(&g);
        for s in 1..4 {
            assert_eq!(
                collapse(&mut Edit::new(&mesh), 0, s, &Edit::new(&mesh).neighbours(0)),
                Err(Refusal::CollapseLink)
            );
        }
    }
}
