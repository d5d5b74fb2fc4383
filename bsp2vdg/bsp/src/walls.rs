//! Exact distance from a point to the map's obstacle faces: the ground truth for
//! "clearance" in quality measurements (SPEC §8).
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
use crate::util::{cross, dot, sub};

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
    /// In tree order: every leaf owns a contiguous range.
    polygons: Vec<Polygon>,
    nodes: Vec<BvhNode>,
}

#[derive(Debug, Clone)]
struct Polygon {
    vertices: Vec<[f64; 3]>,
    normal: [f64; 3],
    /// `normal · vertex`: the plane distance is a cheap lower bound of the distance.
    offset: f64,
    lo: [f64; 3],
    hi: [f64; 3],
}

impl Polygon {
    /// A lower bound of the distance from `p`: to the plane and to the bounding box.
    fn lower_bound(&self, p: [f64; 3]) -> f64 {
        let plane = (dot(p, self.normal) - self.offset).abs();
        plane.max(box_distance2(p, self.lo, self.hi).sqrt())
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
        let mut polygons: Vec<Polygon> = polygons
            .into_iter()
            .filter(|(v, _)| !v.is_empty())
            .map(|(vertices, normal)| {
                let (lo, hi) = bounds(&vertices);
                let offset = dot(vertices[0], normal);
                Polygon {
                    vertices,
                    normal,
                    offset,
                    lo,
                    hi,
                }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * polygons.len() / LEAF_SIZE + 1);
        if !polygons.is_empty() {
            build(&mut polygons, 0, &mut nodes);
        }
        Walls { polygons, nodes }
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
        let mut found = false;
        // Depth is about log2(n / LEAF_SIZE) plus skew; 64 is ample for any map, and
        // a deeper stack only grows the array.
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        let mut at = 0u32;
        loop {
            let node = &self.nodes[at as usize];
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                for poly in &self.polygons[range] {
                    if poly.lower_bound(p) > best {
                        continue;
                    }
                    let d = point_polygon_distance(p, &poly.vertices, poly.normal);
                    if d <= best {
                        best = d;
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
                if df <= best * best {
                    stack.push(far);
                }
                if dn <= best * best {
                    at = near;
                    continue;
                }
            }
            // Next pending node that can still hold something nearer.
            loop {
                match stack.pop() {
                    None => return found.then_some(best),
                    Some(n) if self.box_distance(n, p) <= best * best => {
                        at = n;
                        break;
                    }
                    Some(_) => {}
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
fn build(polys: &mut [Polygon], offset: usize, nodes: &mut Vec<BvhNode>) {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in polys.iter() {
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
    polys.select_nth_unstable_by(mid, |a, b| {
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
    // Inside when q is on the same side of every edge (either winding).
    let (mut pos, mut neg) = (false, false);
    for i in 0..v.len() {
        let s = dot(cross(sub(v[(i + 1) % v.len()], v[i]), sub(q, v[i])), n);
        pos |= s > 0.0;
        neg |= s < 0.0;
    }
    if !(pos && neg) {
        return h.abs();
    }
    let mut best = f64::INFINITY;
    for i in 0..v.len() {
        let (a, b) = (v[i], v[(i + 1) % v.len()]);
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

    /// The hierarchy answers exactly what testing every polygon answers.
    #[test]
    fn hierarchy_matches_brute_force() {
        let mut rng = crate::util::SplitMix64::new(5);
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
    }
}
