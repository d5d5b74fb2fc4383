//! The interpolation guard: a face's volume is the union of balls whose radius is
//! interpolated linearly between its vertices' clearances (thesis 3.7). Near a convex
//! obstacle (a pillar's edge, a corner jutting into a room) the true wall distance is
//! convex along the face, so the interpolated radius exceeds it between exact vertices
//! and the volume pokes through the wall (thesis fig. 3.9).
//!
//! We bound that excess per face and lower the face's vertices by it. Each face is
//! evaluated on a barycentric grid of spacing h ≤ 10 units. The wall distance is the
//! minimum of distances to convex faces, each convex with curvature at most 1/d, so the
//! excess `r − d` can exceed its largest grid value by at most `h² / (6 d)` inside a
//! grid cell (`curvature_margin`): lowering by the grid maximum plus that margin makes
//! every ball of the face lie in free space. The cost is local and small (the margin is
//! about half a unit for 10-unit cells at 30 units of clearance), not a global shrink.

use crate::graph::Graph;
use crate::progress::{NoProgress, Progress, Ticker};
use crate::space::FreeSpace;
use rayon::prelude::*;

/// Largest grid spacing on a face. 10 since the margin is `h²/(6d)`
/// ([`curvature_margin`]): at 8 the guard asked half again as many wall distances,
/// and its reduced graphs missed more sight lines, not fewer (Visible's false
/// negatives inside, over the shared maps, with this grid at 8 and the wall raise's
/// at 6 against 10 and 7).
const CELL: f64 = 10.0;
/// Most grid divisions per face edge (faces are rarely longer than 64 units).
const MAX_DIVISIONS: usize = 16;

/// The compiler's guard keeps a vertex it lowered while its clearance stays at least
/// this (units; or `-md` where that is less): a camera with the default near-plane
/// margin (6.4 units) still passes there. The guard used to drop every vertex it
/// lowered below `-md`, and the vertices of a passage just wider than `-md` allows
/// went with their faces: the graph came apart at doorways players walk through, and
/// a camera on one side was cut to the player on the other (8 of the 10 cuts of the
/// replays' route sets over one cut a minute).
pub const KEEP_CLEARANCE: f64 = 8.0;

/// What the guard did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GuardStats {
    /// Vertices whose clearance was lowered, and by how much at most.
    pub lowered: usize,
    pub max_lowering: f64,
    /// Vertices removed because they fell below the minimum clearance.
    pub removed: usize,
}

/// How the guard treats a face whose grid shows no excess.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GuardMode {
    /// Lower every face by its bound (grid maximum plus curvature margin): a proof.
    Bound,
    /// Lower only faces whose grid shows an actual excess, by their full bound: a
    /// check of a graph that should already be safe (after the reduction, whose
    /// condition A keeps its volume inside the guarded one), repairing where not.
    Repair,
}

/// Lowers vertex clearances so that no face's volume leaves free space; vertices that
/// fall below `min_clearance` are removed with their faces. Run it on the graph that
/// is written: any later change of clearances would void the guarantee.
pub fn guard_interpolation(
    graph: Graph,
    space: &dyn FreeSpace,
    min_clearance: f64,
) -> (Graph, GuardStats) {
    guard_with(graph, space, min_clearance, GuardMode::Bound, &NoProgress)
}

/// [`guard_interpolation`] with a choice of [`GuardMode`], reporting the faces it
/// bounds to `progress` (as "Guard", or "Check" in repair mode).
pub fn guard_with(
    graph: Graph,
    space: &dyn FreeSpace,
    min_clearance: f64,
    mode: GuardMode,
    progress: &dyn Progress,
) -> (Graph, GuardStats) {
    let mut stats = GuardStats::default();
    let label = match mode {
        GuardMode::Bound => "Guard",
        GuardMode::Repair => "Check",
    };
    let ticker = Ticker::start(progress, label, graph.faces.len() as u64, Ticker::BLOCK);
    let lowering: Vec<f64> = graph
        .faces
        .par_iter()
        .map_init(
            || (Recent::new(), ticker.local()),
            |(recent, done), f| {
                done.tick();
                let (seen, bound) = face_excess(
                    f.map(|v| graph.vertices[v as usize]),
                    f.map(|v| graph.clearance[v as usize]),
                    space,
                    recent,
                );
                match mode {
                    GuardMode::Repair if seen <= 0.0 => 0.0,
                    _ => bound,
                }
            },
        )
        .collect();
    let mut lower = vec![0.0f64; graph.vertices.len()];
    for (f, &l) in graph.faces.iter().zip(&lowering) {
        for &v in f {
            lower[v as usize] = lower[v as usize].max(l);
        }
    }
    stats.lowered = lower.iter().filter(|&&l| l > 0.0).count();
    stats.max_lowering = lower.iter().fold(0.0f64, |a, &b| a.max(b));
    let clearance: Vec<f64> = graph
        .clearance
        .iter()
        .zip(&lower)
        .map(|(c, l)| c - l)
        .collect();
    // Repair keeps every vertex: removing one could split the graph the reduction
    // kept connected (condition C); a vertex at a free point with clearance 0 adds
    // no volume.
    let clearance: Vec<f64> = match mode {
        GuardMode::Repair => clearance.iter().map(|&c| c.max(0.0)).collect(),
        GuardMode::Bound => clearance,
    };
    let keep: Vec<bool> = clearance
        .iter()
        .map(|&c| mode == GuardMode::Repair || (c >= min_clearance && c > 0.0))
        .collect();
    stats.removed = keep.iter().filter(|&&k| !k).count();

    // Drop faces with a removed vertex and renumber in order of first use.
    let mut new_id = vec![u32::MAX; graph.vertices.len()];
    let mut out = Graph::default();
    for f in &graph.faces {
        if f.iter().any(|&v| !keep[v as usize]) {
            continue;
        }
        let face = f.map(|v| {
            if new_id[v as usize] == u32::MAX {
                new_id[v as usize] = out.vertices.len() as u32;
                out.vertices.push(graph.vertices[v as usize]);
                out.clearance.push(clearance[v as usize]);
            }
            new_id[v as usize]
        });
        out.faces.push(face);
    }
    (out, stats)
}

/// The largest excess `r(q) − d(q)` seen on the face's grid (corners excluded, so
/// `-inf` when nothing was sampled), and an upper bound of it over the whole face
/// (at least 0).
fn face_excess(
    p: [[f64; 3]; 3],
    c: [f64; 3],
    space: &dyn FreeSpace,
    recent: &mut Recent,
) -> (f64, f64) {
    let edge = |i: usize, j: usize| {
        let d = [p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]];
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    };
    let longest = edge(0, 1).max(edge(1, 2)).max(edge(2, 0));
    let n = ((longest / CELL).ceil() as usize).clamp(1, MAX_DIVISIONS);
    let h = longest / n as f64;
    let mut max_excess = 0.0f64;
    let mut seen = f64::NEG_INFINITY;
    let mut min_distance = c[0].min(c[1]).min(c[2]);
    // The grid's nodes but the corners (exact clearance: excess 0 there), with
    // their radii; only walls closer than r matter, farther ones bound d from below.
    // The buffers are the worker's (a face's grid is a few dozen nodes, and growing
    // fresh vectors for each face was a tenth of the guard's work).
    let mut scratch = std::mem::take(&mut recent.scratch);
    let Scratch {
        points,
        radii,
        reach,
        found,
    } = &mut scratch;
    points.clear();
    radii.clear();
    reach.clear();
    for i in 0..=n {
        for j in 0..=(n - i) {
            let k = n - i - j;
            if i == n || j == n || k == n {
                continue;
            }
            let b = [
                i as f64 / n as f64,
                j as f64 / n as f64,
                k as f64 / n as f64,
            ];
            points.push([0, 1, 2].map(|a| b[0] * p[0][a] + b[1] * p[1][a] + b[2] * p[2][a]));
            radii.push(b[0] * c[0] + b[1] * c[1] + b[2] * c[2]);
        }
    }
    reach.extend(radii.iter().map(|r| r + 1.0));
    recent.wall_distances_within(space, points, reach, found);
    for ((&r, &far), &d) in radii.iter().zip(reach.iter()).zip(found.iter()) {
        let d = d.unwrap_or(far);
        min_distance = min_distance.min(d);
        max_excess = max_excess.max(r - d);
        seen = seen.max(r - d);
    }
    recent.scratch = scratch;
    // Curvature margin inside one grid cell (`curvature_margin`): the wall distance
    // there is at least the smallest grid value less the cell size.
    let d_low = (min_distance - h).max(1.0);
    (seen, max_excess + curvature_margin(h, d_low))
}

/// How far the wall distance `d` can fall below the linear interpolation `L` of its
/// values at the corners of a grid cell (a triangle whose longest edge is `h`) inside
/// the cell, where `d ≥ d_low`: `h² / (6 d_low)`.
///
/// Why: `d` is the least distance to a wall point `s`, and each `|x − s|` has a
/// Hessian of at most `1/|x − s| ≤ 1/d_low` over the cell, so `|x − s| − |x|²/(2 d_low)`
/// is concave there and lies above its own interpolation. That gives `|x − s| ≥ L_s(x)
/// − Σ λᵢ |xᵢ − x|² / (2 d_low)` (λ the barycentric weights of `x`, `xᵢ` the corners),
/// `L_s ≥ L` since `|xᵢ − s| ≥ d(xᵢ)`, and the weighted spread `Σ λᵢ |xᵢ − x|²` is at
/// most the squared radius of the cell's smallest enclosing circle, at most `h²/3`
/// (an equilateral cell). The guard's first margin, `h² / (2 d_low)`, was three times
/// this: it lowered clearances and held back the raise to the walls for nothing.
pub(crate) fn curvature_margin(h: f64, d_low: f64) -> f64 {
    h * h / (6.0 * d_low)
}

/// The reduction check of the corner radii: every face whose corner radii raise it
/// and whose grid sees a ball reach into a wall (as [`guard_with`]'s repair mode
/// looks) falls back to its vertices' clearances. Returns how many did. The
/// certificate allows none; this is the same safety net the vertex clearances get.
///
/// The faces are reported to `progress` as "Corner check".
pub fn check_corners(
    graph: &Graph,
    radii: &mut [[f64; 3]],
    space: &dyn FreeSpace,
    progress: &dyn Progress,
) -> usize {
    let ticker = Ticker::start(
        progress,
        "Corner check",
        graph.faces.len() as u64,
        Ticker::BLOCK,
    );
    let failed: Vec<bool> = graph
        .faces
        .par_iter()
        .zip(radii.par_iter())
        .map_init(
            || (Recent::new(), ticker.local()),
            |(recent, done), (f, r)| {
                done.tick();
                let c = f.map(|v| graph.clearance[v as usize]);
                *r != c
                    && face_excess(f.map(|v| graph.vertices[v as usize]), *r, space, recent).0 > 0.0
            },
        )
        .collect();
    let mut n = 0;
    for ((f, r), bad) in graph.faces.iter().zip(radii.iter_mut()).zip(failed) {
        if bad {
            *r = f.map(|v| graph.clearance[v as usize]);
            n += 1;
        }
    }
    n
}

/// The last wall-distance queries of one worker, by their exact bits. Faces next
/// to each other in the list (the triangles of one Voronoi polygon) share edges,
/// and a grid point on a shared edge is the same point with the same radius, bit
/// for bit, when both faces cut the edge alike: the answer is the same query's
/// answer, so the guard's result does not depend on what the cache holds.
struct Recent {
    slots: Vec<Option<([u64; 4], Option<f64>)>>,
    /// The worker's buffers for [`face_excess`] and for the queries the slots
    /// do not answer, reused from face to face.
    scratch: Scratch,
    ask: Vec<usize>,
    ask_points: Vec<[f64; 3]>,
    ask_radii: Vec<f64>,
    answers: Vec<Option<f64>>,
}

/// A face grid's nodes, their radii, how far their wall distances are looked
/// for, and the answers.
#[derive(Default)]
struct Scratch {
    points: Vec<[f64; 3]>,
    radii: Vec<f64>,
    reach: Vec<f64>,
    found: Vec<Option<f64>>,
}

/// Slots of [`Recent`] (a power of two).
const RECENT: usize = 1024;

impl Recent {
    fn new() -> Recent {
        Recent {
            slots: vec![None; RECENT],
            scratch: Scratch::default(),
            ask: Vec::new(),
            ask_points: Vec::new(),
            ask_radii: Vec::new(),
            answers: Vec::new(),
        }
    }

    /// [`FreeSpace::wall_distance_within`], answered from the slots when the
    /// same query was asked last there.
    #[cfg(test)]
    fn wall_distance_within(
        &mut self,
        space: &dyn FreeSpace,
        q: [f64; 3],
        radius: f64,
    ) -> Option<f64> {
        let mut out = Vec::with_capacity(1);
        self.wall_distances_within(space, &[q], &[radius], &mut out);
        out[0]
    }

    /// [`FreeSpace::wall_distances_within`], each answered from the slots when
    /// the same query was asked last there; the others are asked at once.
    fn wall_distances_within(
        &mut self,
        space: &dyn FreeSpace,
        points: &[[f64; 3]],
        radii: &[f64],
        out: &mut Vec<Option<f64>>,
    ) {
        out.clear();
        let (ask, ask_points, ask_radii) =
            (&mut self.ask, &mut self.ask_points, &mut self.ask_radii);
        ask.clear();
        ask_points.clear();
        ask_radii.clear();
        for (i, (&q, &radius)) in points.iter().zip(radii).enumerate() {
            let key = Self::key(q, radius);
            match self.slots[Self::slot(&key)] {
                Some((k, d)) if k == key => out.push(d),
                _ => {
                    out.push(None);
                    ask.push(i);
                    ask_points.push(q);
                    ask_radii.push(radius);
                }
            }
        }
        if ask.is_empty() {
            return;
        }
        let answers = &mut self.answers;
        answers.clear();
        space.wall_distances_within(ask_points, ask_radii, answers);
        for ((&i, (&q, &radius)), &d) in ask
            .iter()
            .zip(ask_points.iter().zip(ask_radii.iter()))
            .zip(answers.iter())
        {
            let key = Self::key(q, radius);
            self.slots[Self::slot(&key)] = Some((key, d));
            out[i] = d;
        }
    }

    fn key(q: [f64; 3], radius: f64) -> [u64; 4] {
        [q[0], q[1], q[2], radius].map(f64::to_bits)
    }

    fn slot(key: &[u64; 4]) -> usize {
        let mix = key.iter().fold(0u64, |h, &k| {
            (h ^ k).wrapping_mul(0x9E37_79B9_7F4A_7C15).rotate_left(29)
        });
        (mix >> 32) as usize & (RECENT - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A floor at z = 0, counting the distance queries it answers.
    struct Floor(AtomicUsize);

    impl FreeSpace for Floor {
        fn is_free(&self, p: [f64; 3]) -> bool {
            p[2] > 0.0
        }
        fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
            a[2] > 0.0 && b[2] > 0.0
        }
        fn wall_distance(&self, p: [f64; 3]) -> f64 {
            self.0.fetch_add(1, Ordering::Relaxed);
            p[2].abs()
        }
    }

    #[test]
    fn recent_answers_repeated_queries_alike_and_asks_the_space_once() {
        let floor = Floor(AtomicUsize::new(0));
        let mut recent = Recent::new();
        let queries: Vec<([f64; 3], f64)> = (0..2000)
            .map(|i| {
                (
                    [f64::from(i % 37), 1.0, f64::from(i % 50) * 0.5],
                    10.0 + f64::from(i % 3),
                )
            })
            .collect();
        for &(q, r) in &queries {
            assert_eq!(
                recent.wall_distance_within(&floor, q, r),
                floor.wall_distance_within(q, r)
            );
        }
        // The same query twice in a row: the second comes from the slots.
        let before = floor.0.load(Ordering::Relaxed);
        let q = [3.5, 2.0, 7.25];
        let first = recent.wall_distance_within(&floor, q, 20.0);
        let again = recent.wall_distance_within(&floor, q, 20.0);
        assert_eq!((first, again), (Some(7.25), Some(7.25)));
        assert_eq!(floor.0.load(Ordering::Relaxed), before + 1);
        // Another radius is another query.
        assert_eq!(recent.wall_distance_within(&floor, q, 5.0), None);
        assert_eq!(floor.0.load(Ordering::Relaxed), before + 2);
    }

    #[test]
    fn curvature_margin_bounds_the_distance_below_its_interpolation() {
        // Random cells (triangles of any shape, edges up to ~10 units) near random
        // wall triangles (the map's `Walls`, as the compiler asks them): inside each
        // cell the distance never falls below the interpolation of its corner values
        // by more than the margin, taken with the lower bound the certificates use
        // (least corner distance less `h`). Half the margin would not do: the worst
        // cell needs more than that.
        let mut rng = toolbox::SplitMix64::new(0x6d61_7267);
        let mut worst = 0.0f64;
        for _ in 0..3000 {
            let walls = bsp::walls::Walls::new(
                (0..3)
                    .map(|_| {
                        let t = [0; 3].map(|_| [0; 3].map(|_| rng.range(-20.0, 20.0)));
                        let (u, v) = (
                            [0, 1, 2].map(|i| t[1][i] - t[0][i]),
                            [0, 1, 2].map(|i| t[2][i] - t[0][i]),
                        );
                        let n = [
                            u[1] * v[2] - u[2] * v[1],
                            u[2] * v[0] - u[0] * v[2],
                            u[0] * v[1] - u[1] * v[0],
                        ];
                        let len = n.iter().map(|c| c * c).sum::<f64>().sqrt();
                        (t.to_vec(), n.map(|c| c / len))
                    })
                    .collect(),
            );
            let corners = [0; 3].map(|_| [0; 3].map(|_| rng.range(-3.0, 3.0)));
            let edge = |i: usize, j: usize| {
                (0..3)
                    .map(|a| (corners[i][a] - corners[j][a]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            };
            let h = edge(0, 1).max(edge(1, 2)).max(edge(2, 0));
            let d = corners.map(|c| walls.distance(c));
            let d_low = d[0].min(d[1]).min(d[2]) - h;
            if d_low < 1.0 {
                continue;
            }
            let margin = curvature_margin(h, d_low);
            let n = 24;
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let b = [i, j, n - i - j].map(|k| f64::from(k) / f64::from(n));
                    let x = [0, 1, 2].map(|a| (0..3).map(|k| b[k] * corners[k][a]).sum::<f64>());
                    let interpolated: f64 = (0..3).map(|k| b[k] * d[k]).sum();
                    let dip = interpolated - walls.distance(x);
                    assert!(
                        dip <= margin + 1e-9,
                        "dip {dip} > margin {margin} (h {h}, d_low {d_low})"
                    );
                    worst = worst.max(dip / margin);
                }
            }
        }
        assert!(worst > 0.5, "the margin is never approached ({worst})");
    }

    #[test]
    fn guard_lowers_a_face_whose_volume_pokes_through_the_floor() {
        // Corners 10 units above the floor with clearance 10: exact there, but
        // a face tilted down in the middle would not be; here a flat face at
        // z = 10 with clearances 12 pokes 2 units through.
        let g = Graph {
            vertices: vec![[0.0, 0.0, 10.0], [40.0, 0.0, 10.0], [0.0, 40.0, 10.0]],
            clearance: vec![12.0; 3],
            faces: vec![[0, 1, 2]],
        };
        let (out, stats) = guard_interpolation(g, &Floor(AtomicUsize::new(0)), 0.0);
        assert_eq!(stats.lowered, 3);
        assert!(
            out.clearance.iter().all(|&c| c <= 10.0),
            "{:?}",
            out.clearance
        );
    }
}
