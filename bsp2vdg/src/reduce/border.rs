//! Removing a vertex where sheets end (not in the thesis): the **fan
//! removal**, for the border and seam-end vertices that neither the thesis'
//! cases, the seam contraction nor the collapse along an edge (module
//! `seam`) remove.
//!
//! **Where.** With the coverage guards off (`--no-coverage-guards`)
//! the reduction stopped above `-rl` on several maps with
//! the vertices left mostly on borders: a vertex whose faces form one fan
//! between two border edges (`special[1, 1]`: the thesis swaps the fan down
//! to two faces and then needs the concave case 4.6.1, whose new edge must
//! pass through the vertex's ball), and the corner of a *book* — a seam
//! ending where the border of each of its sheets ends (`special[1, 1, 1, 3]`:
//! three border edges and one seam edge with three faces, a large part of
//! what was left). The collapse along an edge cannot take such a corner
//! without lowering its target to nothing: collapsing it into the seam's
//! next vertex moves every sheet's faces onto that vertex, whose ball lies
//! far outside them.
//!
//! **The operation.** Let `k`'s faces fall into *fans*: the classes of faces
//! joined across edges `k–x` with exactly two faces (as in module `seam`).
//! Every fan must be a path of faces from a *special* edge `k–u` (one face,
//! or three or more) to another `k–w`, `u ≠ w`. Each fan is treated on its
//! own, as the thesis treats a vertex of one fan:
//!
//! 1. **Swaps inside the fans.** The thesis' edge swap (4.5, all its
//!    conditions, module `swap`) on the edges `k–x` inside a fan, cheapest
//!    first over all fans, until every fan has one or two faces.
//! 2. **Contraction of each fan.** A fan `(k, u, x)`, `(k, x, w)` becomes
//!    `(u, x, w)`; a fan of one face `(k, u, w)` just goes. Fans with the same
//!    ends share their new edge `u–w` (with two ends for all fans this is the
//!    seam contraction of module `seam`).
//!
//! **Condition C.** Let `K'` be the complex without `k`'s open star, `L` the
//! link of `k` (its neighbours, and an edge `x–y` per face `(k, x, y)`), and
//! `H` the graph on the special neighbours with an edge `u–w` per distinct
//! pair of fan ends. Before, `K = K' ∪ cone(L)` glued along `L`; after,
//! `K' ∪ U` with `U` the union of the new discs (a fan's path plus its new
//! edge bounds a disc; a one-face fan's disc is its edge `u–w`, part of `L`).
//! Interior vertices of a fan belong to no other fan (their edge to `k` has
//! two faces, both in the fan), so the discs meet only at their ends and
//! along shared new edges, and `U` is homotopy equivalent to `H`. The
//! operation requires `H` to be a tree: then `U` is contractible like the
//! cone, and by the gluing lemma `K' ∪ U ≃ K' ∪ cone(L) = K` — connected
//! components and homotopy type are kept. Also required: a new edge `u–w`
//! must not exist before (it would close a loop of `K'`), so new faces are
//! new; a one-face fan's edge `u–w` must keep another face, or `u` or `w`
//! must have no other face (then it goes with it, a leaf of `H`; the thesis'
//! one-face case 4.4). A vertex of two fans sharing only `k` (two sheets
//! pinched together, `H` two separate edges) is refused: removing it would
//! cut them apart. Condition B (continuity of ρ) follows from the topology
//! as in the thesis (4.2).
//!
//! **Condition A** (the volume never grows), per step: the swaps by module
//! `swap`'s proof. The contraction of a fan with two faces: split the new face
//! `(u, x, w)` at a point `q` of `u–w` into `(x, u, q)` and `(x, q, w)`; `x`
//! and `u` are corners of the old face `(k, u, x)` and keep or lower their
//! radii, so by the concavity of an old face's clearance (module `swap`)
//! `(x, u, q)` lies in that face's volume once the radius at `q`, linear
//! between `u` and `w`, is at most that face's clearance at `q`; likewise
//! `(x, q, w)` in `(k, x, w)`. Any `q` on the segment gives a valid split;
//! the one taken is where `u–w` passes the old edge `k–x` (the
//! perpendicular foot, as for a swap), inside both old faces when the fan is
//! flat — the point nearest to `k` may lie outside one of them (a test
//! below shows such a fan). Where the radius at `q` exceeds the bound, the
//! radii of `u` and `w` are lowered by the thesis' optimal linear reduction
//! (6.1.5), fan after fan of the pair (a lowering only lowers the radius at
//! the earlier fans' `q` further); lowering a radius only shrinks the other
//! faces of that vertex, and a vertex that ends several pairs takes the
//! least radius any of them
//! asks. Removing a face only takes volume away. Each step's volume lies in
//! the one before it, so the whole operation's does.
//!
//! **Lowering and coverage.** A radius may be lowered by at most
//! [`MAX_LOWERING`] of its value; below that the vertex is left. The coverage
//! guards (kept standing places, deep points: module `keep`) refuse any
//! removal that takes what they keep, so where ratio and coverage conflict
//! coverage still wins.

use smallvec::SmallVec;

use super::mesh::{Edit, Op};
use super::remove::Refusal;
use super::swap::{self, MARGIN};
use super::volume::{add, dot, loss, optimal_linear_reduction, perpendicular_feet, scale, sub};

/// The largest share of a vertex's clearance the fan removal may take off
/// (see the module docs): half. With the coverage guards on, walkable
/// coverage and coverage ≥ 32 stayed within sampling noise of the figures
/// without the fan removal on the shared maps, with none allowed as with
/// half (see the README's reduction paragraph); half removes about half as
/// many vertices again as none allowed does.
pub(crate) const MAX_LOWERING: f64 = 0.5;

/// The fans of a vertex.
type Fans = SmallVec<[Fan; 6]>;
/// Per interior neighbour, its fan.
type Interior = SmallVec<[(u32, u8); 16]>;

/// A fan of `k`: its two special ends and its faces (path order not kept).
#[derive(Debug, Clone)]
struct Fan {
    ends: [u32; 2],
    faces: u8,
}

/// The fans of `k` and, per interior neighbour (edge to `k` with two faces),
/// its fan; `None` if `k` does not qualify (see the module docs).
fn fans(e: &Edit, k: u32) -> Option<(Fans, Interior)> {
    let faces = e.faces_of(k);
    if faces.is_empty() || faces.len() > 48 {
        return None;
    }
    let tris: SmallVec<[[u32; 3]; 32]> = faces.iter().map(|&f| e.face(f)).collect();
    let nb = e.neighbours(k);
    let mut special: SmallVec<[u32; 8]> = SmallVec::new();
    let mut parent: SmallVec<[u8; 64]> = (0..tris.len() as u8).collect();
    fn find(p: &mut [u8], mut x: u8) -> u8 {
        while p[x as usize] != x {
            p[x as usize] = p[p[x as usize] as usize];
            x = p[x as usize];
        }
        x
    }
    let mut regular: SmallVec<[u32; 16]> = SmallVec::new();
    for &n in &nb {
        let mut with = tris
            .iter()
            .enumerate()
            .filter(|(_, t)| t.contains(&n))
            .map(|(i, _)| i as u8);
        match (with.next(), with.next(), with.next()) {
            (Some(a), Some(b), None) => {
                let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                parent[ra as usize] = rb;
                regular.push(n);
            }
            _ => special.push(n),
        }
    }
    if special.len() < 2 {
        return None; // an interior vertex (a closed fan): the thesis' case
    }
    let mut roots: SmallVec<[u8; 6]> = SmallVec::new();
    let mut out: SmallVec<[Fan; 6]> = SmallVec::new();
    let mut ends: SmallVec<[SmallVec<[u32; 2]>; 6]> = SmallVec::new();
    for (i, t) in tris.iter().enumerate() {
        let r = find(&mut parent, i as u8);
        let j = match roots.iter().position(|&x| x == r) {
            Some(j) => j,
            None => {
                roots.push(r);
                out.push(Fan {
                    ends: [0; 2],
                    faces: 0,
                });
                ends.push(SmallVec::new());
                roots.len() - 1
            }
        };
        out[j].faces += 1;
        for &v in t {
            if special.contains(&v) {
                ends[j].push(v);
            }
        }
    }
    for (fan, e) in out.iter_mut().zip(&ends) {
        // A path from one special edge to another, distinct one.
        let [a, b] = e[..] else { return None };
        if a == b {
            return None;
        }
        fan.ends = [a.min(b), a.max(b)];
    }
    let interior = regular
        .iter()
        .map(|&x| {
            let i = tris.iter().position(|t| t.contains(&x)).unwrap_or(0);
            let r = find(&mut parent, i as u8);
            (x, roots.iter().position(|&y| y == r).unwrap_or(0) as u8)
        })
        .collect();
    if !is_tree(&special, &out) {
        return None;
    }
    Some((out, interior))
}

/// Whether the graph on `nodes` with an edge per distinct pair of fan ends
/// is a tree (see the module docs, condition C).
fn is_tree(nodes: &[u32], fans: &[Fan]) -> bool {
    let mut pairs: SmallVec<[[u32; 2]; 6]> = fans.iter().map(|f| f.ends).collect();
    pairs.sort_unstable();
    pairs.dedup();
    if pairs.len() + 1 != nodes.len() {
        return false;
    }
    // n − 1 edges: a tree iff connected (union-find over the nodes).
    let mut parent: SmallVec<[usize; 8]> = (0..nodes.len()).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    for [a, b] in pairs {
        let (Some(i), Some(j)) = (
            nodes.iter().position(|&n| n == a),
            nodes.iter().position(|&n| n == b),
        ) else {
            return false;
        };
        let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
        if ri == rj {
            return false;
        }
        parent[ri] = rj;
    }
    true
}

/// Removes `k` by the fan removal (see the module docs): the lost volume,
/// or why not. `e` must hold no changes of `k`'s faces yet.
pub(crate) fn remove(e: &mut Edit, k: u32) -> Result<f64, Refusal> {
    let (mut fans, mut interior) = fans(e, k).ok_or(Refusal::CollapseLink)?;
    // Topology of the contraction (step 2), checked before any swap: a pair
    // that gets a new edge must not have it yet, nor share it with a
    // one-face fan; a one-face fan's edge keeps a face or an end goes.
    for f in &fans {
        let [u, w] = f.ends;
        let twin_single = fans.iter().any(|g| g.ends == f.ends && g.faces == 1);
        if f.faces >= 2 && (e.has_edge(u, w) || twin_single) {
            return Err(Refusal::SeamEdgeExists);
        }
        if f.faces == 1
            && e.edge_faces(u, w).0 < 2
            && e.faces_of(u).len() > 1
            && e.faces_of(w).len() > 1
        {
            return Err(Refusal::CollapseLink);
        }
    }
    // Step 1: swaps inside the fans, down to two faces each.
    let mut cost = 0.0;
    if fans.iter().any(|f| f.faces > 2) {
        let inner: SmallVec<[u32; 24]> = interior.iter().map(|x| x.0).collect();
        let mut candidates = swap::Candidates::new(e, k, &inner);
        for (j, f) in fans.iter().enumerate() {
            if f.faces <= 2 {
                exclude_fan(&mut candidates, &interior, j as u8);
            }
        }
        while fans.iter().any(|f| f.faces > 2) {
            let s = candidates.best(e).ok_or(Refusal::SeamSwap)?;
            if s.merge {
                return Err(Refusal::SeamSwap);
            }
            cost += candidates.apply(e, &s);
            let i = interior
                .iter()
                .position(|x| x.0 == s.k[1])
                .ok_or(Refusal::SeamSwap)?;
            let j = interior.remove(i).1;
            fans[j as usize].faces -= 1;
            if fans[j as usize].faces == 2 {
                exclude_fan(&mut candidates, &interior, j);
            }
        }
    }
    contract(e, k, &fans, &interior).map(|c| c + cost)
}

/// Takes the interior vertices of fan `j` out of the swap candidates.
fn exclude_fan(candidates: &mut swap::Candidates, interior: &[(u32, u8)], j: u8) {
    for &(x, f) in interior {
        if f == j {
            candidates.exclude(x);
        }
    }
}

/// Step 2: every fan has one or two faces; each pair of ends gets its
/// radius bound at `q`, then the old faces go and the new ones come.
fn contract(e: &mut Edit, k: u32, fans: &[Fan], interior: &[(u32, u8)]) -> Result<f64, Refusal> {
    let old: SmallVec<[u32; 12]> = SmallVec::from_slice(e.faces_of(k));
    debug_assert_eq!(
        old.len(),
        fans.iter().map(|f| f.faces as usize).sum::<usize>()
    );
    let pk = e.pos(k);
    let mut lowered: SmallVec<[(u32, f64); 8]> = SmallVec::new();
    let mut new_tris: SmallVec<[[u32; 3]; 6]> = SmallVec::new();
    let mut pairs: SmallVec<[[u32; 2]; 6]> = fans
        .iter()
        .filter(|f| f.faces == 2)
        .map(|f| f.ends)
        .collect();
    pairs.sort_unstable();
    pairs.dedup();
    for [u, w] in pairs {
        let (pu, pw) = (e.pos(u), e.pos(w));
        let v = sub(pw, pu);
        let len2 = dot(v, v);
        if len2 <= 0.0 {
            return Err(Refusal::SeamBound);
        }
        let at =
            |y: u32, l: &[(u32, f64)]| l.iter().find(|z| z.0 == y).map_or(e.radius(y), |z| z.1);
        for (j, fan) in fans.iter().enumerate() {
            if fan.ends != [u, w] {
                continue;
            }
            let x = interior
                .iter()
                .find(|y| y.1 == j as u8)
                .ok_or(Refusal::SeamSwap)?
                .0;
            // The split point: where the new edge passes the old edge k–x
            // (the nearest point to k where they are parallel).
            let tq = perpendicular_feet(pk, e.pos(x), pu, pw)
                .map_or_else(|| dot(sub(pk, pu), v) / len2, |f| f.1)
                .clamp(0.0, 1.0);
            let q = add(pu, scale(v, tq));
            let mut bound = f64::INFINITY;
            let mut on_u = None;
            for &f in &old {
                let t = e.face(f);
                if t.contains(&x) {
                    bound = bound.min(e.clearance_at(f, q));
                    if t.contains(&u) {
                        on_u = Some(t);
                    }
                }
            }
            // Orientation of the fan's face on u, k replaced by w.
            let t = on_u.ok_or(Refusal::SeamSwap)?;
            new_tris.push(t.map(|y| if y == k { w } else { y }));
            // Each fan bounds the radius at its own q; lowering for one
            // keeps the bounds met before.
            let (nu, nw) =
                optimal_linear_reduction(at(u, &lowered), at(w, &lowered), tq, bound - MARGIN)
                    .ok_or(Refusal::SeamBound)?;
            for (y, r) in [(u, nu), (w, nw)] {
                if r <= 0.0 || r < (1.0 - MAX_LOWERING) * e.radius(y) {
                    return Err(Refusal::SeamBound);
                }
                match lowered.iter_mut().find(|l| l.0 == y) {
                    Some(l) => l.1 = l.1.min(r),
                    None => lowered.push((y, r)),
                }
            }
        }
    }
    let old_volume: f64 = old.iter().map(|&f| e.face_volume(f)).sum();
    let new_volume: f64 = new_tris.iter().map(|&t| e.volume(t, &lowered)).sum();
    let cost = loss(old_volume, new_volume) + e.lowering_cost(&lowered, &old);
    for &f in &old {
        e.remove_face(f);
    }
    for &(v, r) in &lowered {
        if r < e.radius(v) {
            e.set_radius(v, r);
        }
    }
    for t in new_tris {
        e.add_face(t);
    }
    e.count(Op::FanRemove);
    Ok(cost)
}

/// A second bound for the collapse of `k` into `s` (module `seam`) on the
/// radius of `s`, for a moved face `f = (k, a, b)` → `(s, a, b)` whose other
/// corners both span faces `(k, s, a)` and `(k, s, b)` with `k` and `s` (as
/// at a junction where seams meet, where the collapse's own bound — the
/// old face `f` alone holding `s`'s ball — asks most): split the moved face
/// at a point `p` inside it into `(s, a, p)`, `(a, b, p)`, `(b, s, p)`. The
/// corners `s`, `a` are corners of the old face `(k, s, a)`, so by the
/// concavity argument of module `swap` the piece `(s, a, p)` lies in its
/// volume once the new radius at `p` is at most that face's clearance at
/// `p`; likewise `(a, b, p)` in `f` and `(b, s, p)` in `(k, s, b)`. The new
/// radius at `p` is linear in the radius of `s` (only `s` is lowered), so
/// each `p` bounds it; the best of a few points inside is returned
/// (`-∞` where the split does not apply). `faces` are `k`'s faces.
pub(crate) fn split_bound(e: &Edit, k: u32, s: u32, f: u32, faces: &[u32]) -> f64 {
    let t = e.face(f);
    let mut ab = t.into_iter().filter(|&v| v != k);
    let (Some(a), Some(b)) = (ab.next(), ab.next()) else {
        return f64::NEG_INFINITY;
    };
    let with = |x: u32| {
        faces.iter().copied().find(|&g| {
            let t = e.face(g);
            t.contains(&s) && t.contains(&x)
        })
    };
    let (Some(fa), Some(fb)) = (with(a), with(b)) else {
        return f64::NEG_INFINITY;
    };
    let (ps, pa, pb) = (e.pos(s), e.pos(a), e.pos(b));
    let (ra, rb) = (e.radius(a), e.radius(b));
    let mut best = f64::NEG_INFINITY;
    for ws in [1.0 / 3.0, 0.5, 0.2] {
        let wo = (1.0 - ws) / 2.0;
        let p = add(scale(ps, ws), add(scale(pa, wo), scale(pb, wo)));
        let m = e
            .clearance_at(fa, p)
            .min(e.clearance_at(fb, p))
            .min(e.clearance_at(f, p))
            - MARGIN;
        best = best.max((m - wo * (ra + rb)) / ws);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Graph;
    use crate::reduce::mesh::Mesh;

    /// A book: `pages` sheets hanging off the spine 0–1 (x axis), each a fan
    /// of `fan` faces around vertex 0 from the spine to the page's border
    /// corner; beyond vertex 1 every page goes on by a strip, so that only
    /// vertex 0 is a corner. Clearance `r0` at the corner, 12 elsewhere.
    fn book(pages: usize, fan: usize, r0: f64) -> Graph {
        let mut g = Graph {
            vertices: vec![[0.0, 0.0, 0.0], [20.0, 0.0, 0.0], [40.0, 0.0, 0.0]],
            clearance: vec![r0, 12.0, 12.0],
            faces: vec![],
        };
        for j in 0..pages {
            let a = std::f64::consts::TAU * j as f64 / pages as f64;
            let dir = [0.0, a.cos(), a.sin()];
            // The fan's rim: from vertex 1 around to the corner's border
            // vertex straight out from vertex 0 along `dir`.
            let mut prev = 1u32;
            for i in 1..=fan {
                let t = i as f64 / fan as f64 * std::f64::consts::FRAC_PI_2;
                let p = [
                    20.0 * t.cos(),
                    20.0 * t.sin() * dir[1],
                    20.0 * t.sin() * dir[2],
                ];
                g.vertices.push(p);
                g.clearance.push(12.0);
                let id = g.vertices.len() as u32 - 1;
                g.faces.push([0, prev, id]);
                prev = id;
            }
            // A strip beyond the spine's next vertex keeps the page going.
            let far = [40.0, 20.0 * dir[1], 20.0 * dir[2]];
            g.vertices.push(far);
            g.clearance.push(12.0);
            let f = g.vertices.len() as u32 - 1;
            g.faces.push([1, 2, f]);
            let first_rim = f - fan as u32;
            g.faces.push([1, f, first_rim]);
        }
        g
    }

    fn components(g: &Graph) -> usize {
        let n = g.vertices.len();
        let mut p: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        for f in &g.faces {
            for w in [f[1], f[2]] {
                let (a, b) = (find(&mut p, f[0] as usize), find(&mut p, w as usize));
                p[a] = b;
            }
        }
        let mut used = vec![false; n];
        for f in &g.faces {
            for &v in f {
                used[v as usize] = true;
            }
        }
        (0..n).filter(|&v| used[v] && find(&mut p, v) == v).count()
    }

    /// Euler characteristic V − E + F of the faces of `g`.
    fn euler(g: &Graph) -> i64 {
        let mut edges = std::collections::BTreeSet::new();
        let mut verts = std::collections::BTreeSet::new();
        for f in &g.faces {
            for i in 0..3 {
                let (a, b) = (f[i], f[(i + 1) % 3]);
                edges.insert((a.min(b), a.max(b)));
                verts.insert(a);
            }
        }
        verts.len() as i64 - edges.len() as i64 + g.faces.len() as i64
    }

    #[test]
    fn a_book_corner_goes_keeping_topology_and_the_volume() {
        for (pages, fan) in [(3, 1), (3, 2), (3, 4), (4, 3), (1, 5)] {
            let g = book(pages, fan, 14.0);
            let mesh = Mesh::new(&g);
            let mut e = Edit::new(&mesh);
            let cost = remove(&mut e, 0).unwrap_or_else(|r| panic!("{pages}×{fan}: {r:?}"));
            assert!(cost >= 0.0);
            let ch = e.into_changes();
            // Condition A on a grid of every new or shrunk face.
            crate::reduce::check::condition_a(&mesh, &ch).unwrap();
            let mut m = Mesh::new(&g);
            m.apply(ch);
            assert!(m.vfaces[0].is_empty());
            let r = m.to_graph();
            assert_eq!(components(&r), components(&g), "{pages}×{fan}");
            assert_eq!(euler(&r), euler(&g), "{pages}×{fan}");
            for (p, &c) in r.vertices.iter().zip(&r.clearance) {
                let i = g.vertices.iter().position(|q| q == p).unwrap();
                assert!(c <= g.clearance[i] && c >= (1.0 - MAX_LOWERING) * g.clearance[i]);
            }
        }
    }

    #[test]
    fn the_second_phase_takes_the_corner_the_thesis_keeps() {
        // The book's corner: the thesis' cases refuse it (its edges are seam
        // and border edges once the fans are swapped down); in the second
        // phase the fan removal takes it, or the collapse where cheaper.
        for (pages, fan) in [(3, 2), (3, 3), (4, 2)] {
            let mut mesh = Mesh::new(&book(pages, fan, 14.0));
            assert!(
                crate::reduce::remove::remove_vertex_why(&mut Edit::new(&mesh), 0).is_err(),
                "{pages}×{fan}"
            );
            mesh.seam_ops = true;
            let mut e = Edit::new(&mesh);
            crate::reduce::remove::remove_vertex_why(&mut e, 0).expect("removed");
            let ch = e.into_changes();
            assert_eq!(ch.ops[Op::FanRemove as usize], 1, "{pages}×{fan}");
        }
    }

    #[test]
    fn a_junction_of_seams_collapses_by_the_split_bound() {
        // Four seams meeting at 0 (the cone over the six edges between the
        // corners of a regular tetrahedron: every edge of 0 has three
        // faces). The ball of a corner (radius 6, 10 units out) is not in
        // the old face (0, a, b) (clearance at it 12 − 10 = 2), so the
        // collapse's own bound refuses; split at the moved face's centroid
        // (3.3 units from 0) the old faces hold it.
        let d = 10.0 / 3f64.sqrt();
        let mut g = Graph {
            vertices: vec![[0.0; 3], [d, d, d], [d, -d, -d], [-d, d, -d], [-d, -d, d]],
            clearance: vec![12.0, 6.0, 6.0, 6.0, 6.0],
            faces: vec![],
        };
        for a in 1..5u32 {
            for b in a + 1..5 {
                g.faces.push([0, a, b]);
            }
        }
        let mesh = Mesh::new(&g);
        let e = Edit::new(&mesh);
        let f = e
            .faces_of(0)
            .iter()
            .copied()
            .find(|&f| !e.face(f).contains(&1))
            .unwrap();
        assert!(e.clearance_at(f, e.pos(1)) < 3.0);
        let nb = e.neighbours(0);
        let mut e = Edit::new(&mesh);
        crate::reduce::seam::collapse(&mut e, 0, 1, &nb).expect("collapsed");
        let ch = e.into_changes();
        crate::reduce::check::condition_a(&mesh, &ch).unwrap();
        let mut m = Mesh::new(&g);
        m.apply(ch);
        let r = m.to_graph();
        assert_eq!(r.faces.len(), 3);
        assert_eq!(euler(&r), euler(&g));
        // With a thin centre the split does not hold either.
        g.clearance[0] = 7.0;
        let mesh = Mesh::new(&g);
        assert!(crate::reduce::seam::collapse(&mut Edit::new(&mesh), 0, 1, &nb).is_err());
    }

    #[test]
    fn a_thin_corner_asks_more_lowering_than_allowed() {
        // With a clearance of 1 at the corner the new edges' radius of 12
        // at q would need the ends lowered almost to nothing.
        let mut g = book(3, 2, 1.0);
        // The fans' middle vertices thin too: the new edge 1–w passes
        // through the middle vertex's edge to 0, where the old radius is 1.
        for j in 0..3 {
            g.clearance[3 + 3 * j] = 1.0;
        }
        let mesh = Mesh::new(&g);
        assert_eq!(remove(&mut Edit::new(&mesh), 0), Err(Refusal::SeamBound));
    }

    #[test]
    fn two_sheets_pinched_at_a_vertex_stay_joined() {
        // Two separate fans (each a border fan) sharing only vertex 0: H is
        // two separate edges, not a tree; removing 0 would split the
        // component.
        let mut g = Graph {
            vertices: vec![[0.0; 3]],
            clearance: vec![10.0],
            faces: vec![],
        };
        for s in [1.0, -1.0] {
            let base = g.vertices.len() as u32;
            for i in 0..3 {
                let a = i as f64 * 0.6;
                g.vertices
                    .push([s * 20.0 * a.cos(), 20.0 * a.sin(), s * 5.0]);
                g.clearance.push(10.0);
            }
            g.faces.push([0, base, base + 1]);
            g.faces.push([0, base + 1, base + 2]);
        }
        let mesh = Mesh::new(&g);
        assert_eq!(remove(&mut Edit::new(&mesh), 0), Err(Refusal::CollapseLink));
    }

    #[test]
    fn a_new_edge_that_exists_is_refused() {
        // One border fan (1, 2, 3) around 0 whose ends 1 and 3 are joined
        // by another face: contracting would close the loop 1–3.
        let g = Graph {
            vertices: vec![
                [0.0, 0.0, 0.0],
                [20.0, 0.0, 0.0],
                [14.0, 14.0, 0.0],
                [0.0, 20.0, 0.0],
                [30.0, 30.0, 0.0],
            ],
            clearance: vec![12.0; 5],
            faces: vec![[0, 1, 2], [0, 2, 3], [1, 4, 3]],
        };
        let mesh = Mesh::new(&g);
        assert_eq!(
            remove(&mut Edit::new(&mesh), 0),
            Err(Refusal::SeamEdgeExists)
        );
    }
}
