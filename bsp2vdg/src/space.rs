//! Free space as the stages after the Delaunay ask about it: point and segment tests
//! and exact wall distances. The stages take it as a trait so that they run against
//! analytic worlds in tests as well as against a map's BSP ([`MapSpace`]).

use bsp::oracle::Oracle;
use bsp::walls::Walls;

/// The questions the extraction asks about free space.
pub trait FreeSpace: Sync {
    /// Whether `p` is in free space.
    fn is_free(&self, p: [f64; 3]) -> bool;
    /// Whether the whole segment `a`–`b` is in free space.
    fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool;
    /// The exact distance from a free point to the nearest obstacle.
    fn wall_distance(&self, p: [f64; 3]) -> f64;
    /// The exact distance to the nearest obstacle if it is at most `radius` (cheaper
    /// than [`wall_distance`](Self::wall_distance) when only near walls matter).
    fn wall_distance_within(&self, p: [f64; 3], radius: f64) -> Option<f64> {
        Some(self.wall_distance(p)).filter(|&d| d <= radius)
    }
    /// [`wall_distance_within`](Self::wall_distance_within) for each point with its
    /// radius, into `out` (cleared first): the same answers, for implementations
    /// that answer points close together faster at once (a face's grid).
    fn wall_distances_within(
        &self,
        points: &[[f64; 3]],
        radii: &[f64],
        out: &mut Vec<Option<f64>>,
    ) {
        out.clear();
        out.extend(
            points
                .iter()
                .zip(radii)
                .map(|(&p, &r)| self.wall_distance_within(p, r)),
        );
    }
}

/// A map's free space: the BSP oracle for points and segments, the tree's obstacle
/// boundary for exact wall distances.
pub struct MapSpace<'a> {
    pub oracle: &'a Oracle,
    pub walls: Walls,
    /// The world's bounds (mins, maxs).
    pub bounds: ([f64; 3], [f64; 3]),
    /// The map's game: how its players crouch (see `bsp::player::Crouching`).
    pub game: bsp::Game,
}

impl FreeSpace for MapSpace<'_> {
    fn is_free(&self, p: [f64; 3]) -> bool {
        self.oracle.is_free(p)
    }
    fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        self.oracle.segment_free(a, b)
    }
    fn wall_distance(&self, p: [f64; 3]) -> f64 {
        self.walls.distance(p)
    }
    fn wall_distance_within(&self, p: [f64; 3], radius: f64) -> Option<f64> {
        self.walls.distance_within(p, radius)
    }
    fn wall_distances_within(
        &self,
        points: &[[f64; 3]],
        radii: &[f64],
        out: &mut Vec<Option<f64>>,
    ) {
        self.walls.distances_within(points, radii, out)
    }
}
