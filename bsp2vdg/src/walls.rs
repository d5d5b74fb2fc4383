//! Exact distance from a point to the map's obstacle faces: the ground truth for
//! "clearance" in quality measurements (SPEC §8).
//!
//! The obstacles are bounded by the pieces of the BSP tree's boundary between free and
//! obstacle leaves ([`boundary`]); the map's faces cover the same walls but miss those
//! the compiler left faceless. A uniform grid over the polygons' bounding boxes answers
//! "the nearest wall within r" by testing the few whose boxes come near, each exactly.
//!
//! ```no_run
//! use bsp2vdg::{bsp::Bsp, walls::Walls};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let walls = Walls::of_map(&bsp, &Default::default());
//! let d = walls.distance_within([0.0, 0.0, 64.0], 128.0); // None: no wall within 128
//! # Ok::<(), bsp2vdg::bsp::BspError>(())
//! ```

use crate::boundary::{self, BoundaryPolygon};
use crate::bsp::Bsp;
use crate::oracle::OracleOptions;
use crate::sample::{self, classify::FaceClass};
use std::collections::HashMap;

/// Obstacle polygons with a grid for nearby-face lookups.
#[derive(Debug, Clone)]
pub struct Walls {
    polygons: Vec<Polygon>,
    cell: f64,
    grid: HashMap<[i64; 3], Vec<u32>>,
    /// Polygons spanning many cells (sky planes, long floors): tested on every query,
    /// mostly rejected by their lower bound.
    large: Vec<u32>,
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
        let b2: f64 = (0..3)
            .map(|i| (self.lo[i] - p[i]).max(p[i] - self.hi[i]).max(0.0).powi(2))
            .sum();
        plane.max(b2.sqrt())
    }
}

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
        Walls::new(polygons, 64.0)
    }

    /// The faces the sampler keeps (those not classified as skipped).
    pub fn from_faces(faces: &[sample::SampledFace]) -> Walls {
        let polygons = faces
            .iter()
            .filter(|f| !matches!(f.class, FaceClass::Skip(_)) && f.polygon.len() >= 3)
            .map(|f| (f.polygon.clone(), f.normal))
            .collect::<Vec<_>>();
        Walls::new(polygons, 64.0)
    }

    /// Walls from convex planar polygons with their unit normals; `cell` is the grid's
    /// cell size (about the query radius works well).
    pub fn new(polygons: Vec<(Vec<[f64; 3]>, [f64; 3])>, cell: f64) -> Walls {
        let polygons: Vec<Polygon> = polygons
            .into_iter()
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
        let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
        let mut large = Vec::new();
        for (i, p) in polygons.iter().enumerate() {
            let (a, b) = (key(p.lo, cell), key(p.hi, cell));
            // Saturating: corrupt maps can carry absurd coordinates.
            let span = (0..3).fold(1i64, |s, k| {
                s.saturating_mul(b[k].saturating_sub(a[k]).saturating_add(1))
            });
            if span > 64 {
                large.push(i as u32);
                continue;
            }
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        grid.entry([x, y, z]).or_default().push(i as u32);
                    }
                }
            }
        }
        Walls {
            polygons,
            cell,
            grid,
            large,
        }
    }

    /// Number of obstacle polygons.
    pub fn len(&self) -> usize {
        self.polygons.len()
    }

    pub fn is_empty(&self) -> bool {
        self.polygons.is_empty()
    }

    /// The exact distance to the nearest obstacle face (infinite when there is none),
    /// searching outwards in growing balls so nearby walls cost little.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        let mut r = self.cell * 0.5;
        while r < 1e7 {
            if let Some(d) = self.distance_within(p, r) {
                return d;
            }
            r *= 2.0;
        }
        f64::INFINITY
    }

    /// The exact distance to the nearest obstacle face if it is at most `radius`.
    pub fn distance_within(&self, p: [f64; 3], radius: f64) -> Option<f64> {
        let (a, b) = (
            key(p.map(|c| c - radius), self.cell),
            key(p.map(|c| c + radius), self.cell),
        );
        let mut candidates: Vec<u32> = Vec::new();
        let cells = (0..3).fold(1i64, |s, k| {
            s.saturating_mul(b[k].saturating_sub(a[k]).saturating_add(1))
        });
        if cells > self.polygons.len() as i64 {
            // A big ball: visiting its cells costs more than testing every polygon.
            return self.nearest_of(p, radius, 0..self.polygons.len() as u32);
        }
        for x in a[0]..=b[0] {
            for y in a[1]..=b[1] {
                for z in a[2]..=b[2] {
                    if let Some(v) = self.grid.get(&[x, y, z]) {
                        candidates.extend_from_slice(v);
                    }
                }
            }
        }
        candidates.sort_unstable();
        candidates.dedup();
        candidates.extend_from_slice(&self.large);
        self.nearest_of(p, radius, candidates.into_iter())
    }

    /// The nearest of the given polygons if within `radius`, skipping polygons whose
    /// lower bound (plane or box distance) cannot beat the best so far.
    fn nearest_of(
        &self,
        p: [f64; 3],
        radius: f64,
        candidates: impl Iterator<Item = u32>,
    ) -> Option<f64> {
        let mut best = f64::INFINITY;
        for i in candidates {
            let poly = &self.polygons[i as usize];
            let bound = poly.lower_bound(p);
            if bound > radius || bound >= best {
                continue;
            }
            best = best.min(point_polygon_distance(p, &poly.vertices, poly.normal));
        }
        (best <= radius).then_some(best)
    }
}

fn key(p: [f64; 3], cell: f64) -> [i64; 3] {
    p.map(|c| (c / cell).floor() as i64)
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

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
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
        let walls = Walls::new(vec![(sq.clone(), n)], 4.0);
        assert_eq!(walls.distance_within([5.0, 5.0, 3.0], 2.0), None);
        assert_eq!(walls.distance_within([5.0, 5.0, 3.0], 3.5), Some(3.0));
        assert_eq!(walls.distance_within([50.0, 5.0, 3.0], 10.0), None);
        assert!((walls.distance([50.0, 5.0, 3.0]) - 1609f64.sqrt()).abs() < 1e-12);
    }
}
