//! Exact distance from a point to the map's obstacle faces: the ground truth for
//! "clearance" in quality measurements (docs/design/quality.md).
//!
//! The obstacles are bounded by the pieces of the BSP tree's boundary between free and
//! obstacle leaves ([`boundary`]); the map's faces cover the same walls but miss those
//! the compiler left faceless. A bounding-volume hierarchy over the polygons answers
//! "the nearest wall within r" by testing the few whose boxes come near, each exactly.
//!
//! ```no_run
//! use bsp::{Bsp, walls::Walls};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let walls = Walls::of_map(&bsp, &Default::default());
//! let d = walls.distance_within([0.0, 0.0, 64.0], 128.0); // None: no wall within 128
//! # Ok::<(), bsp::BspError>(())
//! ```

use crate::Bsp;
use crate::boundary::{self, BoundaryPolygon};
use crate::faces::FaceClass;
use crate::oracle::OracleOptions;
use toolbox::vec3::{cross, dot, sub};

/// A classified face polygon, as [`Walls::from_faces`] takes it.
pub trait WallFace {
    /// The convex polygon in world coordinates.
    fn polygon(&self) -> &[[f64; 3]];
    /// Its unit normal towards the side it is seen from.
    fn normal(&self) -> [f64; 3];
    fn class(&self) -> FaceClass;
}

/// Obstacle polygons in a bounding-volume hierarchy for nearest-wall queries.
#[derive(Debug, Clone)]
pub struct Walls {
    /// In tree order: every leaf owns a contiguous range. What a query reads of a
    /// polygon before it measures it exactly (its plane and box), apart from its
    /// vertices, so that a leaf's candidates share a few cache lines.
    polygons: Vec<Polygon>,
    /// Per polygon (same order), its vertices: a range of `vertices`.
    spans: Vec<(u32, u32)>,
    vertices: Vec<[f64; 3]>,
    nodes: Vec<BvhNode>,
    /// At least the largest length of a normal, and 1: the distance
    /// [`point_polygon_distance`] gives is at least a box or plane distance over
    /// this (normals of unit length only to rounding measure the plane distance a
    /// little long). The tests compare the distances found times this.
    scale: f64,
}

#[derive(Debug, Clone, Copy)]
struct Polygon {
    normal: [f64; 3],
    /// `normal · first vertex`: the plane distance is a cheap lower bound of the
    /// distance (see `slack`).
    offset: f64,
    /// How far the vertices stray from that plane (the pieces of the BSP boundary
    /// are planar only to rounding), plus a micro-unit for the rounding of the
    /// tests: the plane distance less this is a true lower bound.
    slack: f64,
    /// The vertices' bounding box grown by `slack`.
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Polygon {
    /// Whether the polygon may lie within `reach` of `p` (`reach2` = `reach²`,
    /// both [`Walls::scale`]d): its plane and its bounding box both come that near.
    /// A polygon this refuses is farther than `reach / scale` by
    /// [`point_polygon_distance`], so a query's answer is the least distance over
    /// all polygons, whatever order it tests them in.
    #[inline]
    fn may_beat(&self, p: [f64; 3], reach: f64, reach2: f64) -> bool {
        (dot(p, self.normal) - self.offset).abs() - self.slack <= reach
            && box_distance2(p, self.lo, self.hi) <= reach2
    }
}

/// A node of the hierarchy: a box around polygons `first..first + count` when a leaf
/// (`count > 0`); otherwise its children are the next node and node `first`.
#[derive(Debug, Clone, Copy)]
struct BvhNode {
    lo: [f64; 3],
    hi: [f64; 3],
    first: u32,
    count: u32,
}

/// Most pending nodes of a query: one per level of the hierarchy, whose median
/// splits keep its depth at about `log2(polygons / LEAF_SIZE)` (32 for 2^34 polygons).
const STACK: usize = 64;

/// Polygons per leaf: a few exact tests are cheaper than another level of boxes.
const LEAF_SIZE: usize = 4;

impl Walls {
    /// The boundary of `bsp`'s free space under `options`, taken from its BSP trees
    /// (see [`boundary`]): the faces alone miss walls the compiler left faceless.
    pub fn of_map(bsp: &Bsp, options: &OracleOptions) -> Walls {
        Walls::from_boundary(&boundary::of_map(bsp, options))
    }

    /// Walls from the pieces of a BSP tree's obstacle boundary.
    pub fn from_boundary(boundary: &[BoundaryPolygon]) -> Walls {
        let polygons = boundary
            .iter()
            .filter(|b| b.vertices.len() >= 3)
            .map(|b| (b.vertices.clone(), b.normal))
            .collect();
        Walls::new(polygons)
    }

    /// The faces not classified as skipped (e.g. the compiler's sampled faces).
    pub fn from_faces<F: WallFace>(faces: &[F]) -> Walls {
        let polygons = faces
            .iter()
            .filter(|f| !matches!(f.class(), FaceClass::Skip(_)) && f.polygon().len() >= 3)
            .map(|f| (f.polygon().to_vec(), f.normal()))
            .collect::<Vec<_>>();
        Walls::new(polygons)
    }

    /// Walls from convex planar polygons with their unit normals.
    pub fn new(polygons: Vec<(Vec<[f64; 3]>, [f64; 3])>) -> Walls {
        let mut vertices = Vec::new();
        let mut polygons: Vec<(Polygon, (u32, u32))> = polygons
            .into_iter()
            .filter(|(v, _)| !v.is_empty())
            .map(|(v, normal)| {
                let (lo, hi) = bounds(&v);
                let span = (vertices.len() as u32, v.len() as u32);
                vertices.extend_from_slice(&v);
                let offset = dot(v[0], normal);
                let stray = v
                    .iter()
                    .map(|&x| (dot(x, normal) - offset).abs())
                    .fold(0.0, f64::max);
                let slack = stray + 1e-6;
                let polygon = Polygon {
                    normal,
                    offset,
                    slack,
                    lo: lo.map(|x| x - slack),
                    hi: hi.map(|x| x + slack),
                };
                (polygon, span)
            })
            .collect();
        let scale = polygons
            .iter()
            .map(|(p, _)| dot(p.normal, p.normal).sqrt())
            .fold(1.0, f64::max)
            * (1.0 + 1e-12);
        let mut nodes = Vec::with_capacity(2 * polygons.len() / LEAF_SIZE + 1);
        if !polygons.is_empty() {
            build(&mut polygons, 0, &mut nodes);
        }
        Walls {
            scale,
            spans: polygons.iter().map(|p| p.1).collect(),
            polygons: polygons.into_iter().map(|p| p.0).collect(),
            vertices,
            nodes,
        }
    }

    /// Number of obstacle polygons.
    pub fn len(&self) -> usize {
        self.polygons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// The exact distance to the nearest obstacle face (infinite when there is none).
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        self.distance_within(p, f64::INFINITY)
            .unwrap_or(f64::INFINITY)
    }

    /// The exact distance to the nearest obstacle face if it is at most `radius`.
    ///
    /// Branch and bound over the hierarchy, nearer box first: a query touches the
    /// few boxes that can still beat the best distance found, and allocates nothing.
    pub fn distance_within(&self, p: [f64; 3], radius: f64) -> Option<f64> {
        if self.nodes.is_empty() || radius.is_nan() {
            return None;
        }
        let mut best = radius;
        let mut reach = best * self.scale;
        let mut reach2 = reach * reach;
        let mut found = false;
        // Pending nodes with their squared box distances.
        let mut stack = [(0u32, 0.0f64); STACK];
        let mut pending = 0usize;
        let mut at = 0u32;
        loop {
            let node = &self.nodes[at as usize];
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                for (poly, &(start, len)) in
                    self.polygons[range.clone()].iter().zip(&self.spans[range])
                {
                    if !poly.may_beat(p, reach, reach2) {
                        continue;
                    }
                    let v = &self.vertices[start as usize..(start + len) as usize];
                    let d = point_polygon_distance(p, v, poly.normal);
                    if d <= best {
                        best = d;
                        reach = best * self.scale;
                        reach2 = reach * reach;
                        found = true;
                    }
                }
            } else {
                let (a, b) = (at + 1, node.first);
                let da = self.box_distance(a, p);
                let db = self.box_distance(b, p);
                let (near, far, dn, df) = if da <= db {
                    (a, b, da, db)
                } else {
                    (b, a, db, da)
                };
                if df <= reach2 {
                    stack[pending] = (far, df);
                    pending += 1;
                }
                if dn <= reach2 {
                    at = near;
                    continue;
                }
            }
            // Next pending node that can still hold something nearer.
            loop {
                if pending == 0 {
                    return found.then_some(best);
                }
                pending -= 1;
                let (n, d) = stack[pending];
                if d <= reach2 {
                    at = n;
                    break;
                }
            }
        }
    }

    /// [`Walls::distance_within`] for many points at once: `out` gets the answer
    /// for `points[i]` within `radii[i]`, the same answers, bit for bit. Faster for
    /// points close together (a grid on a face of the graph): the polygons that can
    /// come within the largest radius of their bounding box are gathered once, and
    /// each point measures first the polygon nearest to the point before it, so
    /// the others mostly fail the cheap plane and box tests.
    ///
    /// ```
    /// use bsp::walls::Walls;
    /// let floor = vec![[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [100.0, 100.0, 0.0], [0.0, 100.0, 0.0]];
    /// let walls = Walls::new(vec![(floor, [0.0, 0.0, 1.0])]);
    /// let mut out = Vec::new();
    /// walls.distances_within(&[[50.0, 50.0, 8.0], [50.0, 50.0, 30.0]], &[16.0, 16.0], &mut out);
    /// assert_eq!(out, vec![Some(8.0), None]);
    /// ```
    pub fn distances_within(&self, points: &[[f64; 3]], radii: &[f64], out: &mut Vec<Option<f64>>) {
        assert_eq!(points.len(), radii.len(), "one radius per point");
        out.clear();
        out.resize(points.len(), None);
        if self.nodes.is_empty() {
            return;
        }
        let mut order: Vec<u32> = (0..points.len() as u32)
            .filter(|&i| !radii[i as usize].is_nan())
            .collect();
        let mut near = Vec::new();
        self.answer_group(&mut order, points, radii, out, &mut near);
    }

    /// Answers the points `group` of [`Walls::distances_within`]: split in two
    /// along their widest extent while they are many and spread out (the polygons
    /// near a big group are many, and every point would test them all), then
    /// gathered, or asked one by one when few.
    fn answer_group(
        &self,
        group: &mut [u32],
        points: &[[f64; 3]],
        radii: &[f64],
        out: &mut [Option<f64>],
        near: &mut Vec<(f64, u32)>,
    ) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let mut reach = f64::NEG_INFINITY;
        for &i in group.iter() {
            let p = points[i as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            reach = reach.max(radii[i as usize]);
        }
        if group.len() < GATHER_MIN || !reach.is_finite() {
            for &i in group.iter() {
                out[i as usize] = self.distance_within(points[i as usize], radii[i as usize]);
            }
            return;
        }
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        if group.len() >= 2 * GATHER_MIN && hi[axis] - lo[axis] > GROUP_EXTENT {
            let mid = group.len() / 2;
            group.select_nth_unstable_by(mid, |&a, &b| {
                points[a as usize][axis]
                    .total_cmp(&points[b as usize][axis])
                    .then(a.cmp(&b))
            });
            let (left, right) = group.split_at_mut(mid);
            self.answer_group(left, points, radii, out, near);
            self.answer_group(right, points, radii, out, near);
            return;
        }
        near.clear();
        self.gather(lo, hi, reach, near);
        // Nearest boxes first: a point stops at the first polygon whose box is
        // farther from the group's box than its best distance so far (that box is
        // as far from the point, so `may_beat` refuses it and all after it).
        // (Squares are never negative: their bits order them.)
        near.sort_unstable_by_key(|x| x.0.to_bits());
        let mut hint = u32::MAX;
        for &i in group.iter() {
            let (p, radius) = (points[i as usize], radii[i as usize]);
            let mut best = radius;
            let mut reach = best * self.scale;
            let mut reach2 = reach * reach;
            let mut found = u32::MAX;
            // The polygon nearest to the point before first: the others then
            // mostly fail the plane and box tests.
            for (box2, j) in std::iter::once((0.0, hint)).chain(near.iter().copied()) {
                if j == u32::MAX {
                    continue;
                }
                if box2 > reach2 {
                    break;
                }
                let poly = &self.polygons[j as usize];
                if !poly.may_beat(p, reach, reach2) {
                    continue;
                }
                let (start, len) = self.spans[j as usize];
                let v = &self.vertices[start as usize..(start + len) as usize];
                let d = point_polygon_distance(p, v, poly.normal);
                if d <= best {
                    best = d;
                    reach = best * self.scale;
                    reach2 = reach * reach;
                    found = j;
                }
            }
            if found != u32::MAX {
                hint = found;
                out[i as usize] = Some(best);
            }
        }
    }

    /// The polygons whose plane and box both come within `reach` of the box
    /// `lo`–`hi`: every polygon within `reach` of a point of the box is among them,
    /// each with the squared distance between its box and `lo`–`hi`.
    fn gather(&self, lo: [f64; 3], hi: [f64; 3], reach: f64, out: &mut Vec<(f64, u32)>) {
        // Scaled as the queries' tests (see `Walls::scale`), and a hair more, so
        // that rounding never leaves out a polygon at the reach.
        let reach = reach * self.scale * (1.0 + 1e-9) + 1e-6;
        let reach2 = reach * reach;
        let mut stack = [0u32; STACK];
        let mut pending = 1usize;
        while pending > 0 {
            pending -= 1;
            let at = stack[pending];
            let node = &self.nodes[at as usize];
            if box_box_distance2(lo, hi, node.lo, node.hi) > reach2 {
                continue;
            }
            if node.count == 0 {
                stack[pending] = node.first;
                stack[pending + 1] = at + 1;
                pending += 2;
                continue;
            }
            for i in node.first..node.first + node.count {
                let poly = &self.polygons[i as usize];
                let box2 = box_box_distance2(lo, hi, poly.lo, poly.hi);
                if box2 <= reach2
                    && plane_box_distance(poly.normal, poly.offset, lo, hi) - poly.slack <= reach
                {
                    out.push((box2, i));
                }
            }
        }
    }

    fn box_distance(&self, node: u32, p: [f64; 3]) -> f64 {
        let n = &self.nodes[node as usize];
        box_distance2(p, n.lo, n.hi)
    }
}

/// Builds the subtree over `polys` (which it reorders), whose first polygon has index
/// `offset` in the final order, appending nodes in depth-first order.
fn build(polys: &mut [(Polygon, (u32, u32))], offset: usize, nodes: &mut Vec<BvhNode>) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for (p, _) in polys.iter() {
        for i in 0..3 {
            lo[i] = lo[i].min(p.lo[i]);
            hi[i] = hi[i].max(p.hi[i]);
            let c = 0.5 * (p.lo[i] + p.hi[i]);
            clo[i] = clo[i].min(c);
            chi[i] = chi[i].max(c);
        }
    }
    let me = nodes.len();
    nodes.push(BvhNode {
        lo,
        hi,
        first: offset as u32,
        count: polys.len() as u32,
    });
    if polys.len() <= LEAF_SIZE {
        return;
    }
    // Median split along the widest spread of centres (select_nth is deterministic,
    // so the tree, and any output built from it, is the same run to run).
    let axis = (0..3)
        .max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b])))
        .unwrap_or(0);
    let mid = polys.len() / 2;
    let centre = |p: &Polygon| p.lo[axis] + p.hi[axis];
    polys.select_nth_unstable_by(mid, |(a, _), (b, _)| {
        centre(a)
            .total_cmp(&centre(b))
            .then(a.offset.total_cmp(&b.offset))
    });
    let (left, right) = polys.split_at_mut(mid);
    build(left, offset, nodes);
    let right_index = nodes.len() as u32;
    build(right, offset + mid, nodes);
    nodes[me].first = right_index;
    nodes[me].count = 0;
}

/// Fewest points for which [`Walls::distances_within`] gathers the polygons near
/// them first (fewer are asked one by one).
const GATHER_MIN: usize = 4;

/// Largest extent (units) of a group of points that [`Walls::distances_within`]
/// answers from one gathering: more are split.
const GROUP_EXTENT: f64 = 32.0;

/// Squared distance between the boxes `alo`–`ahi` and `blo`–`bhi` (0 if they meet).
fn box_box_distance2(alo: [f64; 3], ahi: [f64; 3], blo: [f64; 3], bhi: [f64; 3]) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        let d = (blo[i] - ahi[i]).max(alo[i] - bhi[i]).max(0.0);
        s += d * d;
    }
    s
}

/// Distance from the plane `n · x = offset` to the box `lo`–`hi` (0 if it cuts it).
fn plane_box_distance(n: [f64; 3], offset: f64, lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
    let extent: f64 = (0..3).map(|i| 0.5 * (hi[i] - lo[i]) * n[i].abs()).sum();
    ((dot(centre, n) - offset).abs() - extent).max(0.0)
}

/// Squared distance from `p` to the box `lo`–`hi` (0 inside).
fn box_distance2(p: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        let d = (lo[i] - p[i]).max(p[i] - hi[i]).max(0.0);
        s += d * d;
    }
    s
}

fn bounds(v: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in v {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (lo, hi)
}

/// Exact distance from `p` to a convex planar polygon with unit normal `n`.
pub fn point_polygon_distance(p: [f64; 3], v: &[[f64; 3]], n: [f64; 3]) -> f64 {
    let h = dot(sub(p, v[0]), n);
    let q = [p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]];
    // The edges (v[i], v[i + 1]), the last one closing the polygon.
    let edge = |i: usize| (v[i], v[if i + 1 == v.len() { 0 } else { i + 1 }]);
    // Inside when q is on the same side of every edge (either winding); outside as
    // soon as two edges disagree.
    let (mut pos, mut neg) = (false, false);
    for i in 0..v.len() {
        let (a, b) = edge(i);
        let s = dot(cross(sub(b, a), sub(q, a)), n);
        pos |= s > 0.0;
        neg |= s < 0.0;
        if pos && neg {
            break;
        }
    }
    if !(pos && neg) {
        return h.abs();
    }
    let mut best = f64::INFINITY;
    for i in 0..v.len() {
        let (a, b) = edge(i);
        let ab = sub(b, a);
        let l2 = dot(ab, ab);
        let t = if l2 > 0.0 {
            (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = sub(p, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]);
        best = best.min(dot(d, d));
    }
    best.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_square() {
        let sq = vec![
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.0],
            [0.0, 10.0, 0.0],
        ];
        let n = [0.0, 0.0, 1.0];
        assert_eq!(point_polygon_distance([5.0, 5.0, 3.0], &sq, n), 3.0);
        assert_eq!(point_polygon_distance([13.0, 5.0, 4.0], &sq, n), 5.0);
        assert!((point_polygon_distance([-1.0, -1.0, 0.0], &sq, n) - 2f64.sqrt()).abs() < 1e-12);
        let walls = Walls::new(vec![(sq.clone(), n)]);
        assert_eq!(walls.distance_within([5.0, 5.0, 3.0], 2.0), None);
        assert_eq!(walls.distance_within([5.0, 5.0, 3.0], 3.5), Some(3.0));
        assert_eq!(walls.distance_within([50.0, 5.0, 3.0], 10.0), None);
        assert!((walls.distance([50.0, 5.0, 3.0]) - 1609f64.sqrt()).abs() < 1e-12);
    }

    /// Polygons planar only to rounding, with normals of unit length only to
    /// rounding (as the BSP boundary's): the answer is still the least distance
    /// over all polygons, one by one or many at once.
    #[test]
    fn rounding_of_planes_and_normals_does_not_lose_the_nearest() {
        // A floor whose far corner strays 0.01 above its plane, its corner
        // 49.995 from p (its plane 50), and a wall 49.997 from p, met first.
        let floor = vec![
            [0.0, 0.0, 0.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, 0.01],
            [0.0, 10.0, 0.0],
        ];
        let x = 10.5 + 49.997;
        let wall = vec![
            [x, -100.0, -100.0],
            [x, 100.0, -100.0],
            [x, 100.0, 100.0],
            [x, -100.0, 100.0],
        ];
        let p = [10.5, 10.5, 50.0];
        let near = point_polygon_distance(p, &floor, [0.0, 0.0, 1.0]);
        assert!(near < 49.997 && near > 49.99, "{near}");
        let walls = Walls::new(vec![(wall, [1.0, 0.0, 0.0]), (floor, [0.0, 0.0, 1.0])]);
        assert_eq!(walls.distance_within(p, 60.0), Some(near));
        let mut out = Vec::new();
        walls.distances_within(&[p; 5], &[60.0; 5], &mut out);
        assert_eq!(out, vec![Some(near); 5]);

        let mut rng = toolbox::SplitMix64::new(11);
        let mut polys = Vec::new();
        for _ in 0..400 {
            let c = [0, 1, 2].map(|_| rng.range(-300.0, 300.0));
            let s = rng.range(5.0, 120.0);
            let axis = (rng.next_f64() * 3.0) as usize % 3;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut corner = |a: f64, b: f64| {
                let mut p = c;
                p[u] += a * s;
                p[v] += b * s;
                p[axis] += rng.range(-1e-4, 1e-4);
                p
            };
            let quad = vec![
                corner(0.0, 0.0),
                corner(1.0, 0.0),
                corner(1.0, 1.0),
                corner(0.0, 1.0),
            ];
            let mut n = [0.0; 3];
            n[axis] = 1.0 + rng.range(-1e-6, 1e-6);
            polys.push((quad, n));
        }
        let walls = Walls::new(polys.clone());
        let mut out = Vec::new();
        for _ in 0..300 {
            let c = [0, 1, 2].map(|_| rng.range(-320.0, 320.0));
            let points: Vec<[f64; 3]> = (0..20)
                .map(|_| [0, 1, 2].map(|i| c[i] + rng.range(-10.0, 10.0)))
                .collect();
            let radii: Vec<f64> = (0..20).map(|_| rng.range(0.0, 80.0)).collect();
            walls.distances_within(&points, &radii, &mut out);
            for ((&p, &r), &batch) in points.iter().zip(&radii).zip(&out) {
                let brute = polys
                    .iter()
                    .map(|(v, n)| point_polygon_distance(p, v, *n))
                    .fold(f64::INFINITY, f64::min);
                let want = (brute <= r).then_some(brute);
                assert_eq!(walls.distance_within(p, r), want);
                assert_eq!(batch, want);
            }
        }
    }

    /// The hierarchy answers exactly what testing every polygon answers.
    #[test]
    fn hierarchy_matches_brute_force() {
        let mut rng = toolbox::SplitMix64::new(5);
        let mut polys = Vec::new();
        for _ in 0..500 {
            let c = [0, 1, 2].map(|_| rng.range(-1000.0, 1000.0));
            let s = rng.range(1.0, 300.0);
            let axis = (rng.next_f64() * 3.0) as usize % 3;
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f64, b: f64| {
                let mut p = c;
                p[u] += a * s;
                p[v] += b * s;
                p
            };
            let mut n = [0.0; 3];
            n[axis] = 1.0;
            polys.push((
                vec![
                    corner(0.0, 0.0),
                    corner(1.0, 0.0),
                    corner(1.0, 0.7),
                    corner(0.0, 1.0),
                ],
                n,
            ));
        }
        let walls = Walls::new(polys.clone());
        for _ in 0..2000 {
            let p = [0, 1, 2].map(|_| rng.range(-1200.0, 1200.0));
            let brute = polys
                .iter()
                .map(|(v, n)| point_polygon_distance(p, v, *n))
                .fold(f64::INFINITY, f64::min);
            assert_eq!(walls.distance(p), brute);
            let r = rng.range(0.0, 150.0);
            assert_eq!(walls.distance_within(p, r), (brute <= r).then_some(brute));
        }
        // Many points at once, close together like a face's grid or scattered,
        // some with a radius too small: the same answers, bit for bit.
        let mut out = Vec::new();
        let (mut hits, mut misses) = (0, 0);
        for spread in [5.0, 60.0, 1500.0] {
            for n in [1, 7, 8, 40, 300] {
                let c = [0, 1, 2].map(|_| rng.range(-1000.0, 1000.0));
                let points: Vec<[f64; 3]> = (0..n)
                    .map(|_| [0, 1, 2].map(|i| c[i] + rng.range(-spread, spread)))
                    .collect();
                let radii: Vec<f64> = (0..n).map(|_| rng.range(0.0, 200.0)).collect();
                walls.distances_within(&points, &radii, &mut out);
                let one_by_one: Vec<Option<f64>> = points
                    .iter()
                    .zip(&radii)
                    .map(|(&p, &r)| walls.distance_within(p, r))
                    .collect();
                assert_eq!(out, one_by_one, "spread {spread}, {n} points");
                hits += out.iter().filter(|d| d.is_some()).count();
                misses += out.iter().filter(|d| d.is_none()).count();
            }
        }
        assert!(hits > 100 && misses > 100, "{hits} hits, {misses} misses");
        let radii = [f64::NAN, f64::INFINITY, 10.0];
        walls.distances_within(&[[0.0; 3]; 3], &radii, &mut out);
        assert_eq!(out[0], None);
        assert_eq!(out[1], Some(walls.distance([0.0; 3])));
    }
}
