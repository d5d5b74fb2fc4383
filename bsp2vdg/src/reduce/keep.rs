//! Points the reduction keeps inside the volume (not in the thesis): the places where
//! a standing player is, so that the camera's target stays where `Visible` can see it.
//! Where keeping them and reaching `-rl` conflict, keeping them wins.
//!
//! A kept point keeps a ball around it inside the volume: a standing place one of
//! radius [`KEEP_MARGIN`], so that the places between the kept grid's columns stay
//! inside too; a deep point of the reduction's second phase ([`Keep::deep`]) its
//! vertex's ball shrunk by the coverage clearance. If the unreduced volume holds a
//! smaller ball, that one is kept.
//!
//! Each kept point is held by one face whose volume contains it. A removal is refused
//! when a point held by a face it removes or lowers is then inside none of the faces
//! around the removal (the faces of the vertices it touches — inside the two-ring
//! that the batches keep independent); after a removal those points move to such a
//! face. Points the unreduced volume does not contain are not kept.

use smallvec::SmallVec;

use super::mesh::{Changes, Edit, Mesh};
use super::volume::P3;

pub(crate) struct Keep {
    points: Vec<P3>,
    /// Per point, a lower bound of its clearance for the face that holds it. Radii
    /// only fall during the reduction, and lowering a face's radii by at most `δ`
    /// lowers its clearance anywhere by at most `δ`: a point deeper than the
    /// lowering needs no evaluation (most points, most of the time).
    depth: Vec<f64>,
    /// Per face id, the points it holds.
    held: Vec<SmallVec<[u32; 2]>>,
    /// Per face id, whether it holds points: every costing asks this of the faces an
    /// edit removes or lowers, and a byte per face stays in the cache.
    holding: Vec<bool>,
    /// Per point, the clearance it must keep (0: inside is enough). Deep points
    /// ([`Keep::deep`]) keep a ball around them inside the volume.
    want: Vec<f64>,
}

fn face_balls(mesh: &Mesh, f: u32) -> [(P3, f64); 3] {
    mesh.faces[f as usize].map(|v| (mesh.pos[v as usize], mesh.clearance[v as usize]))
}

fn face_clearance(mesh: &Mesh, f: u32, p: P3) -> f64 {
    vdgformat::triangle_clearance(face_balls(mesh, f), p)
}

/// An upper bound of a face's clearance at `p`, a few times cheaper than the exact
/// one: the largest clearance of its vertices less the distance of `p` to the
/// triangle's box (the clearance is `max_q r(q) − |p − q|` over the triangle).
#[inline]
fn clearance_bound(balls: &[(P3, f64); 3], p: P3) -> f64 {
    let mut d2 = 0.0;
    for (i, &c) in p.iter().enumerate() {
        let lo = balls[0].0[i].min(balls[1].0[i]).min(balls[2].0[i]);
        let hi = balls[0].0[i].max(balls[1].0[i]).max(balls[2].0[i]);
        let d = (lo - c).max(c - hi).max(0.0);
        d2 += d * d;
    }
    balls[0].1.max(balls[1].1).max(balls[2].1) - d2.sqrt()
}

/// Whether the face with these balls gives `p` a clearance above `need`.
#[inline]
fn inside_by(balls: [(P3, f64); 3], p: P3, need: f64) -> bool {
    clearance_bound(&balls, p) > need && vdgformat::triangle_clearance(balls, p) > need
}

/// A bounding volume hierarchy over the live faces, for the one-off search of each
/// point's deepest face. A node bounds its faces' triangles (not their volumes) and
/// knows their largest clearance: `max_r − dist(p, box)` bounds the clearance any of
/// its faces has at `p` (the clearance is `max_q r(q) − |p − q|` over the triangle),
/// so a best-first descent prunes everything that cannot beat the best face so far.
/// On an open map a face's volume box spans hundreds of units, and a grid of cells
/// had each point test thousands of faces.
struct Bvh {
    nodes: Vec<Node>,
    /// Face ids, each leaf a range of them.
    faces: Vec<u32>,
}

#[derive(Clone, Copy)]
struct Node {
    lo: P3,
    hi: P3,
    max_r: f64,
    /// Leaf: `first..first + count` of `Bvh::faces`; inner: children `first`, `first + 1`.
    first: u32,
    count: u32,
}

/// Faces per leaf.
const LEAF: usize = 4;

impl Bvh {
    fn new(mesh: &Mesh) -> Bvh {
        let mut faces: Vec<u32> = (0..mesh.faces.len() as u32)
            .filter(|&f| mesh.alive[f as usize])
            .collect();
        let centre: Vec<P3> = mesh
            .faces
            .iter()
            .map(|t| {
                let p = t.map(|v| mesh.pos[v as usize]);
                [0, 1, 2].map(|i| (p[0][i] + p[1][i] + p[2][i]) / 3.0)
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * faces.len() / LEAF + 1);
        nodes.push(Node {
            lo: [0.0; 3],
            hi: [0.0; 3],
            max_r: 0.0,
            first: 0,
            count: 0,
        });
        let n = faces.len();
        Self::build(mesh, &centre, &mut faces, 0, n, 0, &mut nodes);
        Bvh { nodes, faces }
    }

    /// Fills node `at` with the faces `faces[a..b]`, splitting at the median of
    /// their centres along the longest axis.
    fn build(
        mesh: &Mesh,
        centre: &[P3],
        faces: &mut [u32],
        a: usize,
        b: usize,
        at: usize,
        nodes: &mut Vec<Node>,
    ) {
        let (mut lo, mut hi, mut max_r) = ([f64::MAX; 3], [f64::MIN; 3], f64::MIN);
        for &f in &faces[a..b] {
            for v in mesh.faces[f as usize] {
                let p = mesh.pos[v as usize];
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
                max_r = max_r.max(mesh.clearance[v as usize]);
            }
        }
        if b - a <= LEAF {
            nodes[at] = Node {
                lo,
                hi,
                max_r,
                first: a as u32,
                count: (b - a) as u32,
            };
            return;
        }
        let axis = (0..3)
            .max_by(|&i, &j| (hi[i] - lo[i]).total_cmp(&(hi[j] - lo[j])))
            .unwrap_or(0);
        let mid = (a + b) / 2;
        faces[a..b].select_nth_unstable_by(mid - a, |&f, &g| {
            centre[f as usize][axis]
                .total_cmp(&centre[g as usize][axis])
                .then(f.cmp(&g))
        });
        let child = nodes.len();
        let empty = nodes[at];
        nodes.push(empty);
        nodes.push(empty);
        nodes[at] = Node {
            lo,
            hi,
            max_r,
            first: child as u32,
            count: 0,
        };
        Self::build(mesh, centre, faces, a, mid, child, nodes);
        Self::build(mesh, centre, faces, mid, b, child + 1, nodes);
    }

    /// A face whose volume holds `p` at least `enough` deep, else the one that
    /// holds it deepest (ties: the smaller id), with that clearance; `None` outside
    /// the volume.
    ///
    /// `hint` is a face to try first, usually the home of the point searched
    /// before (the points come in spatial order, and neighbours mostly share a
    /// home). It changes how much is searched, never what is found: the answer
    /// holds `p` at least `floor = min(hint's clearance at p, enough)` deep
    /// (the search stops only at a face at least `enough` deep, and else
    /// returns the deepest face, which is at least as deep as the hint), so no
    /// node or face whose bound is more than [`SKIP_MARGIN`] under `floor` can
    /// hold the answer or change the order in which the others are visited, and
    /// the search skips them.
    fn deep_face(&self, mesh: &Mesh, p: P3, enough: f64, hint: Option<u32>) -> Option<(u32, f64)> {
        let bound = |n: &Node| {
            let d2: f64 = (0..3)
                .map(|i| (n.lo[i] - p[i]).max(p[i] - n.hi[i]).max(0.0).powi(2))
                .sum();
            n.max_r - d2.sqrt()
        };
        let floor = hint
            .filter(|&f| mesh.alive[f as usize])
            .map_or(f64::NEG_INFINITY, |f| {
                vdgformat::triangle_clearance(face_balls(mesh, f), p).min(enough)
            });
        let mut best: Option<(f64, u32)> = None;
        // Nodes with their bounds, each bound worked out once.
        let mut stack: SmallVec<[(u32, f64); 64]> = SmallVec::new();
        stack.push((0, bound(&self.nodes[0])));
        while let Some((i, b)) = stack.pop() {
            let n = &self.nodes[i as usize];
            // The floor prunes with the margin the face test uses: a node's bound
            // bounds its faces' clearances only up to rounding.
            if b <= 0.0 || b + SKIP_MARGIN < floor || best.is_some_and(|x| b < x.0) {
                continue;
            }
            if n.count > 0 || n.first == 0 {
                let range = n.first as usize..(n.first + n.count) as usize;
                for &f in &self.faces[range] {
                    let balls = face_balls(mesh, f);
                    // A face whose bound lies well below the best (or the floor)
                    // cannot beat it: no need for its exact clearance (see
                    // `SKIP_MARGIN`).
                    let beat = best.map_or(0.0, |x| x.0).max(floor);
                    if clearance_bound(&balls, p) + SKIP_MARGIN < beat {
                        continue;
                    }
                    let c = vdgformat::triangle_clearance(balls, p);
                    let better = match best {
                        None => c > 0.0,
                        Some((d, g)) => c > d || (c == d && f < g),
                    };
                    if better {
                        best = Some((c, f));
                    }
                }
                if best.is_some_and(|x| x.0 >= enough) {
                    break;
                }
                continue;
            }
            // The child with the higher bound goes on the stack last, so it is
            // searched first.
            let (l, r) = (n.first, n.first + 1);
            let (bl, br) = (
                bound(&self.nodes[l as usize]),
                bound(&self.nodes[r as usize]),
            );
            if bl > br {
                stack.push((r, br));
                stack.push((l, bl));
            } else {
                stack.push((l, bl));
                stack.push((r, br));
            }
        }
        best.map(|x| (x.1, x.0))
    }
}

/// How far below the best clearance found so far a face's cheap bound
/// ([`clearance_bound`]) must lie for [`Bvh::deep_face`] to skip its exact
/// clearance. The bound is an upper bound of the exact clearance; the margin
/// covers the rounding of both by twelve orders of magnitude (the exact value
/// exceeded the bound only by rounding, around 1e-13 units, on the faces the
/// searches evaluated), so a skipped face would never have been chosen and the
/// search finds the same face. It skips most of the exact clearances.
const SKIP_MARGIN: f64 = 1.0;

/// The radius of the ball each standing place keeps inside the volume: half the
/// spacing of the kept grid ([`bsp::player::KEEP_SPACING`]). With the places
/// kept only inside, standing places fell out between the kept columns and walkable
/// coverage dropped below the unreduced graph's; with this ball it matches it.
pub(crate) const KEEP_MARGIN: f64 = 8.0;

/// How deep (units) a point's first holder must hold it for the search to stop
/// there: deep enough that the first lowerings around it need no evaluation.
const DEEP_ENOUGH: f64 = 8.0;

/// A deep point keeps its ball this much smaller than the volume held it when it
/// became kept, so that the face holding it then passes the strict test.
const DEEP_EPSILON: f64 = 1e-3;

/// Deep points that would keep a ball smaller than this are not kept: they cover
/// next to nothing.
const DEEP_MIN: f64 = 1.0;

impl Keep {
    /// The points of `points` inside the mesh's volume, each held by a face whose
    /// volume holds it (see [`Bvh::deep_face`]).
    /// Each point keeps a ball of radius `margin` around it inside the volume, or
    /// the ball the mesh's volume holds now if that is smaller (a point held less
    /// than [`DEEP_EPSILON`] deep only stays inside).
    pub fn new(mesh: &Mesh, points: &[P3], margin: f64) -> Keep {
        Self::build(
            mesh,
            points,
            |_| margin.max(DEEP_ENOUGH),
            |_, c| Some((margin.min(c) - DEEP_EPSILON).max(0.0)),
        )
    }

    /// Deep points: each point `points[i]` keeps a ball of radius `reach[i]`
    /// inside the volume, or the ball the mesh's volume holds around it now if
    /// that is smaller (less [`DEEP_EPSILON`]); points that keep less than
    /// [`DEEP_MIN`] are left out. The reduction's second phase keeps the balls of
    /// the unreduced vertices shrunk by the coverage clearance (module `seam`).
    pub fn deep(mesh: &Mesh, points: &[P3], reach: &[f64]) -> Keep {
        debug_assert_eq!(points.len(), reach.len());
        Self::build(
            mesh,
            points,
            |i| reach[i],
            |i, c| {
                let want = reach[i].min(c) - DEEP_EPSILON;
                (want >= DEEP_MIN).then_some(want)
            },
        )
    }

    /// The points whose home search (stopping at `enough(i)` deep) finds a face
    /// and `want(i, depth)` a clearance to keep.
    fn build(
        mesh: &Mesh,
        points: &[P3],
        enough: impl Fn(usize) -> f64 + Sync,
        want: impl Fn(usize, f64) -> Option<f64>,
    ) -> Keep {
        use rayon::prelude::*;
        let bvh = Bvh::new(mesh);
        // Each worker hints the home of the point it searched before (see
        // `Bvh::deep_face`: the hint saves work, the answer is the same).
        let homes: Vec<Option<(u32, f64)>> = points
            .par_iter()
            .enumerate()
            .map_init(
                || None,
                |last: &mut Option<u32>, (i, &p)| {
                    let home = bvh.deep_face(mesh, p, enough(i), *last);
                    if let Some((f, _)) = home {
                        *last = Some(f);
                    }
                    home
                },
            )
            .collect();
        let mut held = vec![SmallVec::new(); mesh.faces.len()];
        let mut kept = Vec::new();
        let mut depth = Vec::new();
        let mut wants = Vec::new();
        for (i, (&p, home)) in points.iter().zip(homes).enumerate() {
            if let Some((f, c)) = home
                && let Some(w) = want(i, c)
            {
                held[f as usize].push(kept.len() as u32);
                kept.push(p);
                depth.push(c);
                wants.push(w);
            }
        }
        let holding = held.iter().map(|h| !h.is_empty()).collect();
        Keep {
            points: kept,
            depth,
            held,
            holding,
            want: wants,
        }
    }

    /// How many points are kept.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Faces whose points an edit puts at risk: the old faces it removes and the
    /// old faces of the vertices it lowers.
    fn at_risk<'a>(&'a self, ch: &'a Changes, base: &'a Mesh) -> impl Iterator<Item = u32> + 'a {
        let old = base.faces.len() as u32;
        ch.removed
            .iter()
            .copied()
            .filter(move |&f| f < old)
            .chain(
                ch.radii
                    .iter()
                    .flat_map(move |&(v, _)| base.vfaces[v as usize].iter().copied()),
            )
            .filter(move |&f| self.holding[f as usize])
    }

    /// Whether every point the edit puts at risk keeps the clearance it must keep
    /// (inside, for a point that keeps none) in a face around the edit.
    pub fn holds(&self, e: &Edit) -> bool {
        let ch = e.changes();
        // Most edits put no kept point at risk: the touched vertices only when needed.
        let mut touched = None;
        self.at_risk(ch, e.base).all(|f| {
            let removed = ch.removed.contains(&f);
            let drop = if removed {
                f64::INFINITY
            } else {
                lowering(e.base, f, |v| e.radius(v))
            };
            self.held[f as usize].iter().all(|&i| {
                let p = self.points[i as usize];
                let need = self.want[i as usize];
                if self.depth[i as usize] - drop > need {
                    return true;
                }
                // The lowered face itself, then the edit's new faces (they cover
                // what the removed ones did), then the other faces around, each
                // once: a face of k touched vertices is in k of their lists.
                let mut tried: SmallVec<[u32; 32]> = SmallVec::new();
                (!removed && inside_by(e.balls(f), p, need))
                    || (0..ch.new_faces.len() as u32)
                        .map(|k| ch.base + k)
                        .any(|g| !ch.removed.contains(&g) && inside_by(e.balls(g), p, need))
                    || touched
                        .get_or_insert_with(|| ch.touched())
                        .iter()
                        .any(|&v| {
                            e.faces_of(v).iter().any(|&g| {
                                if g == f || g >= ch.base || tried.contains(&g) {
                                    return false;
                                }
                                tried.push(g);
                                inside_by(e.balls(g), p, need)
                            })
                        })
            })
        })
    }

    /// The faces at risk of `ch` before it is applied, each with how much the edit
    /// lowers its clearance at most (infinite for a removed face; see
    /// [`Keep::rehome`]).
    pub fn before_apply(&self, ch: &Changes, base: &Mesh) -> Vec<(u32, f64)> {
        let mut v: Vec<u32> = self.at_risk(ch, base).collect();
        v.sort_unstable();
        v.dedup();
        let radius = |u: u32| {
            ch.radii
                .iter()
                .find(|x| x.0 == u)
                .map_or(base.clearance[u as usize], |x| x.1)
        };
        v.into_iter()
            .map(|f| {
                let drop = if ch.removed.contains(&f) {
                    f64::INFINITY
                } else {
                    lowering(base, f, radius)
                };
                (f, drop)
            })
            .collect()
    }

    /// After an edit was applied: the points of the faces at risk move to a face
    /// that holds them: the deepest of the edit's new faces (ids from `first_new`
    /// on), which cover what the removed faces did, else the deepest of the faces
    /// around the edit.
    pub fn rehome(&mut self, mesh: &Mesh, at_risk: &[(u32, f64)], first_new: u32, touched: &[u32]) {
        self.held.resize(mesh.faces.len(), SmallVec::new());
        self.holding.resize(mesh.faces.len(), false);
        let new: Vec<u32> = (first_new..mesh.faces.len() as u32)
            .filter(|&g| mesh.alive[g as usize])
            .collect();
        // The faces around the edit, each once; made when a point first needs them.
        let mut around: Option<Vec<u32>> = None;
        for &(f, drop) in at_risk {
            let points = std::mem::take(&mut self.held[f as usize]);
            self.holding[f as usize] = false;
            for i in points {
                let p = self.points[i as usize];
                let want = self.want[i as usize];
                let d = self.depth[i as usize] - drop;
                let stays = if d > want {
                    Some(d)
                } else if mesh.alive[f as usize] {
                    Some(face_clearance(mesh, f, p)).filter(|&c| c > want)
                } else {
                    None
                };
                let home = if let Some(c) = stays {
                    Some((f, c))
                } else {
                    // A new face holding the point less deep than it must stay
                    // would not be asked when the deeper face around goes.
                    deepest_of(mesh, &new, p)
                        .filter(|x| x.1 > want)
                        .or_else(|| {
                            let around = around.get_or_insert_with(|| {
                                let mut faces: Vec<u32> = touched
                                    .iter()
                                    .flat_map(|&v| mesh.vfaces[v as usize].iter().copied())
                                    .collect();
                                faces.sort_unstable();
                                faces.dedup();
                                faces
                            });
                            deepest_of(mesh, around, p)
                        })
                };
                debug_assert!(home.is_some(), "kept point {p:?} lost its face");
                if let Some((g, c)) = home {
                    self.held[g as usize].push(i);
                    self.holding[g as usize] = true;
                    self.depth[i as usize] = c;
                }
            }
        }
    }
}

/// How much lower face `f`'s clearance can be anywhere with the radii `radius`
/// than with the mesh's: the largest drop of its vertices' radii (the clearance is
/// `max_q r(q) − |p − q|`, and `r` interpolates the vertex radii).
fn lowering(mesh: &Mesh, f: u32, radius: impl Fn(u32) -> f64) -> f64 {
    mesh.faces[f as usize]
        .iter()
        .map(|&v| mesh.clearance[v as usize] - radius(v))
        .fold(0.0, f64::max)
}

/// The face of `faces` whose volume holds `p` deepest (ties: the smaller id), with
/// that clearance, if any.
fn deepest_of(mesh: &Mesh, faces: &[u32], p: P3) -> Option<(u32, f64)> {
    let mut best: Option<(f64, u32)> = None;
    for &g in faces {
        let balls = face_balls(mesh, g);
        if clearance_bound(&balls, p) <= best.map_or(0.0, |x| x.0) {
            continue;
        }
        let c = vdgformat::triangle_clearance(balls, p);
        let better = match best {
            None => c > 0.0,
            Some((d, h)) => c > d || (c == d && g < h),
        };
        if better {
            best = Some((c, g));
        }
    }
    best.map(|x| (x.1, x.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::graph::Graph;

    /// A hint changes how much [`Bvh::deep_face`] searches, never what it finds:
    /// on a folded sheet of faces with uneven clearances, every point gets the
    /// same face and depth with any hint (its own answer, a far face, a dead
    /// one) as without, whether the search stops at `enough` or looks for the
    /// deepest face.
    #[test]
    fn a_hint_never_changes_the_face_found() {
        let mut rng = toolbox::SplitMix64::new(7);
        let n = 24;
        let mut g = Graph {
            vertices: vec![],
            clearance: vec![],
            faces: vec![],
        };
        for y in 0..n {
            for x in 0..n {
                let (fx, fy) = (x as f64 * 16.0, y as f64 * 16.0);
                g.vertices
                    .push([fx, fy, 40.0 * (fx / 90.0).sin() * (fy / 70.0).cos()]);
                g.clearance.push(rng.range(4.0, 60.0));
            }
        }
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let v = (y * n + x) as u32;
                let n = n as u32;
                g.faces.push([v, v + 1, v + n]);
                g.faces.push([v + 1, v + n + 1, v + n]);
            }
        }
        let mut mesh = Mesh::new(&g);
        // A dead face must not serve as a hint.
        mesh.alive[5] = false;
        let bvh = Bvh::new(&mesh);
        let faces = mesh.faces.len() as u32;
        let mut found = 0;
        for _ in 0..3000 {
            let p = [
                rng.range(-40.0, 16.0 * n as f64 + 40.0),
                rng.range(-40.0, 16.0 * n as f64 + 40.0),
                rng.range(-80.0, 80.0),
            ];
            let enough = if rng.next_u64().is_multiple_of(2) {
                8.0
            } else {
                f64::INFINITY
            };
            let plain = bvh.deep_face(&mesh, p, enough, None);
            found += usize::from(plain.is_some());
            let mut hints = vec![5, (rng.next_u64() % faces as u64) as u32];
            hints.extend(plain.map(|x| x.0));
            for h in hints {
                assert_eq!(
                    bvh.deep_face(&mesh, p, enough, Some(h)),
                    plain,
                    "{p:?} hint {h}"
                );
            }
        }
        // Most points lie inside the volume: the test compares real answers.
        assert!(found > 1500, "{found}");
    }
}
