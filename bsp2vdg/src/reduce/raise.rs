//! Raising the clearances the reduction lowered, as far as condition A
//! allows (issue 5; not in the thesis).
//!
//! Every swap and removal case proves condition A against the two or three
//! faces it replaces, so it lowers `k3`/`k4` until the new face's radius at
//! the split point `q` is at most the clearance of those faces — which are
//! themselves the product of earlier, lowered operations. The lowerings
//! compound: on de_dust2 at 2.5 % the kept vertices lost a median of 20
//! units of clearance, and the reduced volume missed 12 % of the free points
//! with clearance ≥ 32 (SPEC §8 coverage), lying a median of 10 units
//! outside it, while the same faces with the vertices' unreduced clearances
//! would have covered 99.99 %. The unreduced volume is much larger than the
//! replaced faces' volumes, so there is room to raise.
//!
//! A raise must keep condition A against the *unreduced* volume `U` (the
//! guarded graph the reduction started from, which lies in free space). As
//! in the `swap` module, a face volume is the union of the balls
//! `B(x, r(x))` over its triangle, so a reduced face lies in `U` if at every
//! point `x` of it `r(x)` is at most the clearance `u_f(x)` of some
//! unreduced face `f` (its ball then lies in `f`'s volume). `u_f` is concave
//! and `r` linear, so it suffices to cover the reduced face by small
//! triangles and to find for each one unreduced face `f` with `r ≤ u_f` at
//! its three corners. Each reduced face is cut into a barycentric grid of
//! cells of about [`CELL`] units; at every grid node the unreduced face of
//! largest clearance is found by a walk over the unreduced faces, and each
//! cell is offered the best faces of its corners. Raising vertex `v` by `δ`
//! adds `δ·λ_v` (its barycentric weight) to `r`, so a cell allows
//! `δ ≤ min_corners (u_f − r)/λ_v` for its best face `f`; a vertex is raised
//! by the least allowance over the cells of its faces, at most back to its
//! unreduced clearance, less [`MARGIN`].
//!
//! The cell data of every face are computed once, in parallel (the walks are
//! the cost); then the vertices are raised one by one in id order, each
//! seeing the raises before it, so the result is the same for any thread
//! count.

use rayon::prelude::*;

use super::mesh::Mesh;
use super::swap::MARGIN;
use super::volume::{P3, add, dist, scale};
use crate::voronoi::Graph;

/// Edge length (units) of the grid cells a reduced face is cut into.
const CELL: f64 = 16.0;
/// Most grid divisions per face edge.
const MAX_DIVISIONS: usize = 16;

/// The unreduced graph with its faces per vertex, for walks.
struct Unreduced<'g> {
    graph: &'g Graph,
    start: Vec<u32>,
    list: Vec<u32>,
    /// Per face: a bounding sphere of its triangle and its largest
    /// clearance, so `u_f(x) ≤ top − (|x − centre| − radius)`.
    sphere: Vec<(P3, f64, f64)>,
}

impl<'g> Unreduced<'g> {
    fn new(graph: &'g Graph) -> Unreduced<'g> {
        let n = graph.vertices.len();
        let mut start = vec![0u32; n + 1];
        for f in &graph.faces {
            for &v in f {
                start[v as usize + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[n] as usize];
        for (i, f) in graph.faces.iter().enumerate() {
            for &v in f {
                list[fill[v as usize] as usize] = i as u32;
                fill[v as usize] += 1;
            }
        }
        let sphere = graph
            .faces
            .iter()
            .map(|t| {
                let p = t.map(|v| graph.vertices[v as usize]);
                let c = scale(add(add(p[0], p[1]), p[2]), 1.0 / 3.0);
                let rho = p.iter().map(|&q| dist(q, c)).fold(0.0, f64::max) * (1.0 + 1e-9);
                let top = t
                    .iter()
                    .map(|&v| graph.clearance[v as usize])
                    .fold(f64::NEG_INFINITY, f64::max);
                (c, rho, top + 1e-9 * (1.0 + top.abs()))
            })
            .collect();
        Unreduced {
            graph,
            start,
            list,
            sphere,
        }
    }

    fn faces_of(&self, v: u32) -> &[u32] {
        &self.list[self.start[v as usize] as usize..self.start[v as usize + 1] as usize]
    }

    /// Clearance of `x` for the unreduced face `f`.
    fn clearance(&self, f: u32, x: P3) -> f64 {
        let t = self.graph.faces[f as usize];
        vdgformat::triangle_clearance(
            t.map(|v| {
                (
                    self.graph.vertices[v as usize],
                    self.graph.clearance[v as usize],
                )
            }),
            x,
        )
    }

    /// The unreduced face of (locally) largest clearance at `x`, found by
    /// climbing from `seed` over faces sharing a vertex. A face whose
    /// bounding sphere shows it cannot beat the best so far is skipped.
    fn best(&self, x: P3, seed: u32, seen: &mut Vec<u32>) -> (u32, f64) {
        let mut best = (seed, self.clearance(seed, x));
        seen.clear();
        seen.push(seed);
        loop {
            let from = best.0;
            let tri = self.graph.faces[from as usize];
            for v in tri {
                for &f in self.faces_of(v) {
                    if seen.contains(&f) {
                        continue;
                    }
                    seen.push(f);
                    let (c, rho, top) = self.sphere[f as usize];
                    if top - (dist(x, c) - rho) < best.1 {
                        continue;
                    }
                    let c = self.clearance(f, x);
                    if c > best.1 || (c == best.1 && f < best.0) {
                        best = (f, c);
                    }
                }
            }
            if best.0 == from {
                return best;
            }
        }
    }
}

/// What one reduced face allows: its grid and, per cell, the clearances of
/// its candidate unreduced faces at the cell's corners.
struct FaceCells {
    n: u16,
    /// Per cell (in [`cells`] order): the range of its candidates in `u`.
    cand: Vec<(u32, u8)>,
    /// Per candidate, the clearances at the three corners (rounded down).
    u: Vec<[f32; 3]>,
}

/// The cells of a grid with `n` divisions: corner nodes `(i, j)` (weight
/// `i/n` on the face's second vertex, `j/n` on its third).
fn cells(n: usize) -> impl Iterator<Item = [(usize, usize); 3]> {
    (0..n).flat_map(move |j| {
        (0..n - j).flat_map(move |i| {
            let up = [(i, j), (i + 1, j), (i, j + 1)];
            let down = (i + j + 2 <= n).then_some([(i + 1, j), (i + 1, j + 1), (i, j + 1)]);
            std::iter::once(up).chain(down)
        })
    })
}

fn bary(n: usize, (i, j): (usize, usize)) -> [f64; 3] {
    let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
    [1.0 - a - b, a, b]
}

/// Rounds down to f32 (so a stored clearance never exceeds the exact one).
fn down(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) > x { y.next_down() } else { y }
}

fn face_cells(mesh: &Mesh, un: &Unreduced, face: u32) -> FaceCells {
    let t = mesh.faces[face as usize];
    let p = t.map(|v| mesh.pos[v as usize]);
    let longest = dist(p[0], p[1]).max(dist(p[1], p[2])).max(dist(p[2], p[0]));
    let n = ((longest / CELL).ceil() as usize).clamp(1, MAX_DIVISIONS);
    let at = |b: [f64; 3]| add(add(scale(p[0], b[0]), scale(p[1], b[1])), scale(p[2], b[2]));
    // Best unreduced face per node, row by row, each walk starting from the
    // previous node's face.
    let node = |i: usize, j: usize| j * (n + 1) + i;
    let mut best = vec![(u32::MAX, 0.0f64); (n + 1) * (n + 1)];
    let mut seed = un.faces_of(t[0]).first().copied();
    let mut row_seed = seed;
    let mut seen = Vec::with_capacity(64);
    for j in 0..=n {
        seed = row_seed;
        for i in 0..=n - j {
            let Some(s) = seed else { break };
            let b = un.best(at(bary(n, (i, j))), s, &mut seen);
            best[node(i, j)] = b;
            seed = Some(b.0);
            if i == 0 {
                row_seed = Some(b.0);
            }
        }
    }
    let mut cand = Vec::new();
    let mut u = Vec::new();
    for c in cells(n) {
        let first = u.len() as u32;
        let mut faces: Vec<u32> = Vec::with_capacity(3);
        for &k in &c {
            let f = best[node(k.0, k.1)].0;
            if f != u32::MAX && !faces.contains(&f) {
                faces.push(f);
            }
        }
        for f in faces {
            let vals = c.map(|k| {
                let b = best[node(k.0, k.1)];
                if b.0 == f {
                    down(b.1)
                } else {
                    down(un.clearance(f, at(bary(n, k))))
                }
            });
            u.push(vals);
        }
        cand.push((first, (u.len() as u32 - first) as u8));
    }
    FaceCells {
        n: n as u16,
        cand,
        u,
    }
}

/// How far the vertex at position `k` of the face may rise with the
/// current clearances `r` of the face's vertices (negative: not at all).
fn allowance(fc: &FaceCells, k: usize, r: [f64; 3]) -> f64 {
    let n = fc.n as usize;
    let mut least = f64::INFINITY;
    for (c, &(first, count)) in cells(n).zip(&fc.cand) {
        let w = c.map(|x| bary(n, x));
        let have = w.map(|b| b[0] * r[0] + b[1] * r[1] + b[2] * r[2]);
        let mut cell = f64::NEG_INFINITY;
        for vals in &fc.u[first as usize..(first + u32::from(count)) as usize] {
            let mut a = f64::INFINITY;
            for i in 0..3 {
                let slack = f64::from(vals[i]) - have[i];
                let l = w[i][k];
                if l > 0.0 {
                    a = a.min(slack / l);
                } else if slack < 0.0 {
                    a = f64::NEG_INFINITY;
                }
            }
            cell = cell.max(a);
        }
        least = least.min(cell);
        if least <= 0.0 {
            return least;
        }
    }
    least
}

/// What [`raise`] did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RaiseStats {
    /// Vertices whose clearance was raised, and the sum of the raises.
    pub raised: usize,
    pub total: f64,
}

/// Raises the clearances of the live vertices of `mesh` (reduced from
/// `unreduced`, same vertex ids) towards their unreduced values, keeping
/// every face volume inside the unreduced volume (see the module docs).
pub(crate) fn raise(unreduced: &Graph, mesh: &mut Mesh) -> RaiseStats {
    let un = Unreduced::new(unreduced);
    let live: Vec<u32> = (0..mesh.faces.len() as u32)
        .filter(|&f| mesh.alive[f as usize])
        .collect();
    // Faces with a vertex that can rise.
    let wanted = |f: u32| {
        mesh.faces[f as usize]
            .iter()
            .any(|&v| mesh.clearance[v as usize] < unreduced.clearance[v as usize] - MARGIN)
    };
    let data: Vec<Option<FaceCells>> = live
        .par_iter()
        .map(|&f| wanted(f).then(|| face_cells(mesh, &un, f)))
        .collect();
    let mut index = vec![u32::MAX; mesh.faces.len()];
    for (i, &f) in live.iter().enumerate() {
        index[f as usize] = i as u32;
    }
    let mut stats = RaiseStats::default();
    for v in 0..mesh.pos.len() {
        let room = unreduced.clearance[v] - MARGIN - mesh.clearance[v];
        if mesh.vfaces[v].is_empty() || room <= 0.0 {
            continue;
        }
        let mut delta = room;
        for &f in &mesh.vfaces[v] {
            let Some(fc) = &data[index[f as usize] as usize] else {
                delta = 0.0;
                break;
            };
            let t = mesh.faces[f as usize];
            let k = t.iter().position(|&x| x as usize == v).unwrap_or(0);
            let r = t.map(|x| mesh.clearance[x as usize]);
            delta = delta.min(allowance(fc, k, r) - MARGIN);
            if delta <= 0.0 {
                break;
            }
        }
        if delta > 0.0 {
            mesh.clearance[v] += delta;
            stats.raised += 1;
            stats.total += delta;
        }
    }
    stats
}
