//! A uniform hash grid over points: merging near-duplicates and nearest-sample lookups.
//!
//! Sampling needs two neighbourhood queries on a few hundred thousand points, both with
//! a known radius. A hash grid answers them in O(1) per query and, unlike a balanced
//! tree, can be filled incrementally in a fixed order, which keeps merging deterministic.

use rustc_hash::FxHashMap;
use smallvec::SmallVec;

/// Points bucketed by a cubic cell of a fixed size.
#[derive(Debug, Clone)]
pub struct PointGrid {
    cell: f64,
    points: Vec<[f64; 3]>,
    /// Only looked up by key, never iterated: the hash cannot change a result. A cell
    /// mostly holds one or two points (merging keeps near-duplicates out): inline, so
    /// that an insert does not allocate (a million Voronoi vertices are merged so).
    buckets: FxHashMap<[i64; 3], SmallVec<[u32; 2]>>,
}

impl PointGrid {
    /// An empty grid with cells of edge `cell` (> 0).
    pub fn new(cell: f64) -> PointGrid {
        assert!(cell > 0.0 && cell.is_finite(), "grid cell must be positive");
        PointGrid {
            cell,
            points: Vec::new(),
            buckets: FxHashMap::default(),
        }
    }

    /// A grid holding `points`, indexed in order.
    pub fn from_points(points: &[[f64; 3]], cell: f64) -> PointGrid {
        let mut g = PointGrid::new(cell);
        for &p in points {
            g.insert(p);
        }
        g
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        p.map(|c| (c / self.cell).floor() as i64)
    }

    /// Adds a point; returns its index.
    pub fn insert(&mut self, p: [f64; 3]) -> u32 {
        let i = self.points.len() as u32;
        self.points.push(p);
        let k = self.key(p);
        self.buckets.entry(k).or_default().push(i);
        i
    }

    /// The points in insertion order.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// The nearest point within `radius` of `p` (ties: lowest index), with its distance.
    pub fn nearest_within(&self, p: [f64; 3], radius: f64) -> Option<(u32, f64)> {
        let lo = self.key(p.map(|c| c - radius));
        let hi = self.key(p.map(|c| c + radius));
        let mut best: Option<(u32, f64)> = None;
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    let Some(bucket) = self.buckets.get(&[x, y, z]) else {
                        continue;
                    };
                    for &i in bucket {
                        let d = dist(self.points[i as usize], p);
                        let better = match best {
                            None => true,
                            Some((bi, bd)) => d < bd || (d == bd && i < bi),
                        };
                        if d <= radius && better {
                            best = Some((i, d));
                        }
                    }
                }
            }
        }
        best
    }
}

/// Euclidean distance.
pub fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_matches_brute_force() {
        let mut rng = toolbox::SplitMix64::new(7);
        let mut rnd = || rng.range(-50.0, 50.0);
        let pts: Vec<[f64; 3]> = (0..2000).map(|_| [rnd(), rnd(), rnd()]).collect();
        let g = PointGrid::from_points(&pts, 7.0);
        for _ in 0..500 {
            let q = [rnd(), rnd(), rnd()];
            let brute = pts
                .iter()
                .enumerate()
                .map(|(i, &p)| (i as u32, dist(p, q)))
                .filter(|&(_, d)| d <= 12.0)
                .min_by(|a, b| a.1.total_cmp(&b.1));
            assert_eq!(g.nearest_within(q, 12.0), brute);
        }
    }
}
