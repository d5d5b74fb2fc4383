//! The wall raise: the clearances of the graph to be written rise towards the exact
//! wall distance, as far as a certificate against the walls allows, and then each
//! face raises its own three corner radii on the same certificate.
//!
//! The reduction keeps its volume inside the unreduced one (condition A), whose
//! clearances the guard lowered and whose faces lie on the sampled medial sheets; a
//! reduced face spans several of them with one plane, and its volume misses a skin
//! along the walls, where sight lines pass. The walls, not the unreduced volume,
//! bound what a face may hold, so the raise measures against them. The certificate is
//! the interpolation guard's argument with the sign turned: on a face's barycentric
//! grid, if every node keeps `d − r ≥ h²/(6 d_low)` ([`curvature_margin`]), no ball of
//! the face leaves free space.

use crate::graph::Graph;
use crate::guard::curvature_margin;
use crate::progress::{NoProgress, Progress, Ticker};
use crate::space::FreeSpace;
use rayon::prelude::*;

/// Grid spacing (units) of the certificate of [`raise_to_walls`]: finer than the
/// guard's, since the curvature margin `h²/(6d)` is paid near walls, where the raise
/// is wanted. 7 and 6 gave the same volume within the sampling noise since the
/// margin shrank to a third; 7 asks a quarter fewer wall distances.
const RAISE_CELL: f64 = 7.0;
/// Most grid divisions per face edge in [`raise_to_walls`] (reduced faces are long:
/// on open maps some span over a thousand units). At 64 the grid of such a face grew
/// coarse and its curvature margin with it; once the reduction's own raise no longer
/// ran first, such maps lost coverage of the points far from walls that 128 won
/// back, and the few faces that long cost little.
const RAISE_MAX_DIVISIONS: usize = 128;

/// What [`raise_to_walls`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RaiseStats {
    /// Vertices raised and the mean raise over them (units).
    pub raised: usize,
    pub mean_raise: f64,
}

/// A face's certificate grid: per node its barycentric weights and its slack
/// `d − r − margin` (the room left before the node's ball, grown by the curvature
/// margin of its cell, would reach a wall).
struct SlackGrid {
    weights: Vec<[f32; 3]>,
    slack: Vec<f64>,
}

/// Raises vertex clearances towards the exact wall distance at each vertex, as far as
/// a certificate against the walls allows: the guard's argument with a sign. On a
/// face's barycentric grid (spacing `h` ≤ `RAISE_CELL` (7 units), corners included with their
/// exact wall distance), if every node keeps `d − r ≥ h²/(6 d_low)` (the curvature
/// margin of the guard), no ball of the face leaves free space. Raising vertex `v` by
/// `δ` raises `r` by `δ·λ_v` at a node, so `v` may rise by the least `slack/λ_v` over
/// the nodes of its faces; the vertices are raised one by one (largest room first,
/// ties by id; in two rounds, half the allowance and then the rest), each taking
/// its raise out of its faces' slacks, so the certificate holds after every step.
/// The wall distances are measured once, in parallel; the result is the same for
/// any thread count.
///
/// Why: the reduction keeps its volume inside the unreduced one
/// (condition A), whose clearances the guard lowered and whose faces lie on the
/// sampled medial sheets; a reduced face spans them with one plane, and its volume
/// misses a skin along the walls — where sight lines pass, so `Visible` missed many
/// of the free ones between points of the volume. The walls, not the
/// unreduced volume, bound what a face may hold.
pub fn raise_to_walls(graph: &mut Graph, space: &dyn FreeSpace) -> RaiseStats {
    raise_with_grids(graph, space, &NoProgress).0
}

/// [`raise_to_walls`], then each face's own corner radii (format version 3,
/// `FACE_RADII`): starting from the raised vertex clearances, each corner rises towards its vertex's wall distance as
/// far as that face's certificate alone allows — the certificate of
/// [`raise_to_walls`] (a barycentric grid of spacing ≤ `RAISE_CELL` whose every
/// node keeps `d − r ≥ h²/(6 d_low)`), on one face instead of all faces around a
/// vertex.
///
/// Why: a vertex's clearance must keep every face around it free, so the
/// face that bends closest to a wall holds the vertex down for all the others;
/// many reduced vertices stay well below their wall distance after
/// [`raise_to_walls`]. A face volume only depends on its own three
/// corner radii, so each face may raise its corners on its own: the volume is
/// still the union of certified-free face volumes, and sight lines that graze the
/// walls stay in it (Visible's false negatives inside the volume fell by about
/// half). Per face two rounds, largest room
/// first, half the allowance and then the rest (as [`raise_to_walls`] shares a
/// face's slack between its corners). Corners never fall below the vertex
/// clearance, which the runtime reader checks. The corners are raised on the
/// vertex raise's own certificate grids (their slacks less what the vertices
/// took), so they ask no wall distance of their own (on grids of their own they
/// cost a noticeable share of a dense compile's time). A later lowering of vertex clearances (the
/// reduction check's repair) leaves them certified and above the clearances; the
/// faces whose volume it found reaching a wall are [`check_corners`](crate::guard::check_corners)' to catch.
/// The result does not depend on the thread count. The wall distances and the
/// certificate grids, its costly part, are reported to `progress` as "Wall raise".
pub fn raise_to_walls_and_corners(
    graph: &mut Graph,
    space: &dyn FreeSpace,
    progress: &dyn Progress,
) -> (RaiseStats, Vec<[f64; 3]>, CornerStats) {
    let (stats, grids, target) = raise_with_grids(graph, space, progress);
    let radii: Vec<[f64; 3]> = graph
        .faces
        .par_iter()
        .zip(grids)
        .map(|(f, g)| {
            let c = f.map(|v| graph.clearance[v as usize]);
            let room = f.map(|v| (target[v as usize] - graph.clearance[v as usize]).max(0.0));
            raise_corners_on(g, c, room)
        })
        .collect();
    let corners = corner_stats(graph, &radii);
    (stats, radii, corners)
}

/// [`raise_to_walls`] keeping every face's certificate grid (empty where no
/// corner has room) and the vertices' wall distances.
fn raise_with_grids(
    graph: &mut Graph,
    space: &dyn FreeSpace,
    progress: &dyn Progress,
) -> (RaiseStats, Vec<SlackGrid>, Vec<f64>) {
    let work = (graph.vertices.len() + graph.faces.len()) as u64;
    let ticker = Ticker::start(progress, "Wall raise", work, Ticker::BLOCK);
    let target: Vec<f64> = graph
        .vertices
        .par_iter()
        .map_init(
            || ticker.local(),
            |done, &p| {
                done.tick();
                space.wall_distance(p)
            },
        )
        .collect();
    let room: Vec<f64> = target
        .iter()
        .zip(&graph.clearance)
        .map(|(t, c)| (t - c).max(0.0))
        .collect();
    // A face where no vertex has room gets no grid (nothing can grow it).
    let most = |f: &[u32; 3]| f.iter().map(|&v| room[v as usize]).fold(0.0f64, f64::max);
    let mut faces_of: Vec<Vec<(u32, u8)>> = vec![Vec::new(); graph.vertices.len()];
    for (i, f) in graph.faces.iter().enumerate() {
        for (k, &v) in f.iter().enumerate() {
            faces_of[v as usize].push((i as u32, k as u8));
        }
    }
    let mut grids: Vec<SlackGrid> = graph
        .faces
        .par_iter()
        .map_init(
            || ticker.local(),
            |done, f| {
                done.tick();
                let most = most(f);
                if most <= 0.0 {
                    return SlackGrid {
                        weights: Vec::new(),
                        slack: Vec::new(),
                    };
                }
                slack_grid(
                    f.map(|v| graph.vertices[v as usize]),
                    f.map(|v| graph.clearance[v as usize]),
                    f.map(|v| target[v as usize]),
                    most,
                    space,
                )
            },
        )
        .collect();
    let mut order: Vec<u32> = (0..graph.vertices.len() as u32)
        .filter(|&v| room[v as usize] > 0.0)
        .collect();
    order.sort_by(|&a, &b| {
        room[b as usize]
            .total_cmp(&room[a as usize])
            .then(a.cmp(&b))
    });
    // Two rounds: each vertex takes half of what it may in the first, the rest
    // in the second, so that one early in the order does not take all the slack
    // it shares with its neighbours (as the reduction's own raise does; two rounds
    // left Visible fewer false negatives inside than one, and three no fewer).
    let mut risen = vec![0.0f64; graph.vertices.len()];
    raise_round(graph, &order, &room, &faces_of, &mut grids, &mut risen, 0.5);
    // A vertex that could not rise in the first round cannot in the second:
    // its room is the same and its faces' slacks have only fallen.
    order.retain(|&v| risen[v as usize] > 0.0);
    raise_round(graph, &order, &room, &faces_of, &mut grids, &mut risen, 1.0);
    let raised = risen.iter().filter(|&&r| r > 0.0).count();
    let stats = RaiseStats {
        raised,
        mean_raise: risen.iter().sum::<f64>() / raised.max(1) as f64,
    };
    (stats, grids, target)
}

/// What [`raise_to_walls_and_corners`] did to the corners.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CornerStats {
    /// Faces with at least one corner above its vertex's clearance.
    pub faces: usize,
    /// Corners raised, and their mean raise (units).
    pub corners: usize,
    pub mean_raise: f64,
}

/// How many corners (of how many faces) `radii` raise above their vertices'
/// clearances, and by how much on average.
fn corner_stats(graph: &Graph, radii: &[[f64; 3]]) -> CornerStats {
    let mut stats = CornerStats::default();
    let mut sum = 0.0;
    for (f, r) in graph.faces.iter().zip(radii) {
        let mut any = false;
        for k in 0..3 {
            let up = r[k] - graph.clearance[f[k] as usize];
            if up > 0.0 {
                stats.corners += 1;
                sum += up;
                any = true;
            }
        }
        stats.faces += any as usize;
    }
    stats.mean_raise = sum / stats.corners.max(1) as f64;
    stats
}

/// The corner radii of one face from clearances `c` with `room` up to the wall
/// distance at each corner, on the face's certificate grid `g` (its slacks for
/// the radii `c`; no nodes: the face has no room).
fn raise_corners_on(g: SlackGrid, c: [f64; 3], room: [f64; 3]) -> [f64; 3] {
    // A face not certified as it stands may not grow.
    if g.slack.is_empty() || g.slack.iter().any(|&s| s < 0.0) {
        return c;
    }
    let mut slack = g.slack;
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| room[b].total_cmp(&room[a]).then(a.cmp(&b)));
    let (mut out, mut risen) = (c, [0.0f64; 3]);
    for share in [0.5, 1.0] {
        for &k in &order {
            let mut allow = room[k] - risen[k];
            for (w, &s) in g.weights.iter().zip(&slack) {
                let l = f64::from(w[k]);
                if l > 0.0 {
                    allow = allow.min((s / l).max(0.0));
                }
            }
            if allow <= 1e-6 {
                continue;
            }
            let allow = allow * share;
            for (w, s) in g.weights.iter().zip(slack.iter_mut()) {
                *s -= allow * f64::from(w[k]);
            }
            out[k] += allow;
            risen[k] += allow;
        }
    }
    out
}

/// One round of [`raise_to_walls`]: each vertex of `order` in turn rises by
/// `share` of what its faces' certificates and its room (less what it rose
/// before, in `risen`) still allow, taking it out of their slacks.
fn raise_round(
    graph: &mut Graph,
    order: &[u32],
    room: &[f64],
    faces_of: &[Vec<(u32, u8)>],
    grids: &mut [SlackGrid],
    risen: &mut [f64],
    share: f64,
) {
    for &v in order {
        let mut allow = room[v as usize] - risen[v as usize];
        for &(f, k) in &faces_of[v as usize] {
            let g = &grids[f as usize];
            // No grid: a face without room, or a vertex that cannot rise.
            if g.slack.is_empty() {
                allow = 0.0;
                break;
            }
            for (w, &s) in g.weights.iter().zip(&g.slack) {
                let l = w[k as usize] as f64;
                if l > 0.0 {
                    allow = allow.min((s / l).max(0.0));
                } else if s < 0.0 {
                    // The face is not certified as it stands: nothing may grow it.
                    allow = 0.0;
                }
            }
            if allow <= 0.0 {
                break;
            }
        }
        if allow <= 1e-6 {
            continue;
        }
        let allow = allow * share;
        for &(f, k) in &faces_of[v as usize] {
            let g = &mut grids[f as usize];
            for (w, s) in g.weights.iter().zip(g.slack.iter_mut()) {
                *s -= allow * w[k as usize] as f64;
            }
        }
        graph.clearance[v as usize] += allow;
        risen[v as usize] += allow;
    }
}

/// The certificate grid of a face (see [`raise_to_walls`]). Wall distances are looked
/// up only within `r + room + 1`, since no raise goes beyond `room`: a capped
/// distance is less than the true one, so the slack stays a lower bound. The weights
/// are stored as `f32` rounded down, which only understates a raise's effect by
/// less than `f32` precision of a weight ≤ 1 — covered by the slack's own margin.
/// The divisions of a face grid along its longest edge.
fn divisions(longest: f64) -> usize {
    ((longest / RAISE_CELL).ceil() as usize).clamp(1, RAISE_MAX_DIVISIONS)
}

/// The most memory the certificate grids of [`raise_to_walls_and_corners`] can hold
/// at once (bytes): every face's grid, as if every face had room. The budget checks
/// it before the raise: a graph of long faces would otherwise ask for many gigabytes.
pub fn grid_bytes(graph: &Graph) -> f64 {
    let per_node = (std::mem::size_of::<[f32; 3]>() + std::mem::size_of::<f64>()) as f64;
    graph
        .faces
        .iter()
        .map(|f| {
            let p = f.map(|v| graph.vertices[v as usize]);
            let longest = (0..3)
                .map(|i| toolbox::vec3::dist(p[i], p[(i + 1) % 3]))
                .fold(0.0f64, f64::max);
            let n = divisions(longest) as f64;
            (n + 1.0) * (n + 2.0) / 2.0 * per_node
        })
        .sum()
}

fn slack_grid(
    p: [[f64; 3]; 3],
    c: [f64; 3],
    t: [f64; 3],
    room: f64,
    space: &dyn FreeSpace,
) -> SlackGrid {
    let edge = |i: usize, j: usize| {
        let d = [p[i][0] - p[j][0], p[i][1] - p[j][1], p[i][2] - p[j][2]];
        (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
    };
    let longest = edge(0, 1).max(edge(1, 2)).max(edge(2, 0));
    let n = divisions(longest);
    let h = longest / n as f64;
    // Nodes in rows i = 0..=n, row i holding j = 0..=n − i; `row[i]` is its first index.
    let row: Vec<usize> = (0..=n + 1)
        .map(|i| i * (n + 1) - i * i.saturating_sub(1) / 2)
        .collect();
    let mut weights = Vec::with_capacity(row[n + 1]);
    let mut excess = Vec::with_capacity(row[n + 1]);
    let mut distance = Vec::with_capacity(row[n + 1]);
    // The nodes but the corners ask for their wall distance, all at once.
    let asking = row[n + 1].saturating_sub(3);
    let (mut points, mut radii) = (Vec::with_capacity(asking), Vec::with_capacity(asking));
    for i in 0..=n {
        for j in 0..=(n - i) {
            let k = n - i - j;
            let b = [i, j, k].map(|x| x as f64 / n as f64);
            if [i, j, k].contains(&n) {
                continue;
            }
            points.push([0, 1, 2].map(|a| b[0] * p[0][a] + b[1] * p[1][a] + b[2] * p[2][a]));
            let r = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
            radii.push(r + room + 1.0);
        }
    }
    let mut found = Vec::with_capacity(points.len());
    space.wall_distances_within(&points, &radii, &mut found);
    let mut asked = radii.iter().zip(&found);
    for i in 0..=n {
        for j in 0..=(n - i) {
            let k = n - i - j;
            let b = [i, j, k].map(|x| x as f64 / n as f64);
            let (r, d) = match [i, j, k].iter().position(|&x| x == n) {
                Some(a) => (c[a], t[a]),
                None => {
                    let r = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
                    let (&far, d) = asked.next().expect("one answer per node");
                    (r, d.unwrap_or(far))
                }
            };
            weights.push(b.map(|x| x as f32));
            excess.push(d - r);
            distance.push(d);
        }
    }
    // A node's margin is the largest over the cells it is a corner of: their
    // nodes are among its six grid neighbours, whose least wall distance less `h`
    // bounds the distance inside them from below.
    let at = |i: isize, j: isize| -> Option<f64> {
        (i >= 0 && j >= 0 && (i + j) as usize <= n).then(|| distance[row[i as usize] + j as usize])
    };
    let mut slack = Vec::with_capacity(excess.len());
    for i in 0..=n as isize {
        for j in 0..=(n as isize - i) {
            let near = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1), (1, -1), (-1, 1)]
                .iter()
                .filter_map(|&(di, dj)| at(i + di, j + dj))
                .fold(f64::INFINITY, f64::min);
            let margin = curvature_margin(h, (near - h).max(1.0));
            slack.push(excess[row[i as usize] + j as usize] - margin);
        }
    }
    SlackGrid { weights, slack }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_face(size: f64) -> Graph {
        Graph {
            vertices: vec![[0.0; 3], [size, 0.0, 0.0], [0.0, size, 0.0]],
            clearance: vec![1.0; 3],
            faces: vec![[0, 1, 2]],
        }
    }

    #[test]
    fn the_grid_bytes_grow_with_the_faces_up_to_the_largest_grid() {
        // An edge within one cell: the corners alone, 20 bytes each.
        assert_eq!(grid_bytes(&one_face(RAISE_CELL * 0.5)), 3.0 * 20.0);
        // Ten cells along the longest edge (the hypotenuse, 10 cells long).
        let ten = one_face(10.0 * RAISE_CELL / 2f64.sqrt());
        assert_eq!(grid_bytes(&ten), 66.0 * 20.0);
        // A face of any size holds at most the grid of RAISE_MAX_DIVISIONS divisions.
        let n = RAISE_MAX_DIVISIONS as f64;
        let cap = (n + 1.0) * (n + 2.0) / 2.0 * 20.0;
        assert_eq!(grid_bytes(&one_face(1e6)), cap);
        assert_eq!(grid_bytes(&one_face(1e9)), cap);
    }
}
