//! Point location by a visibility walk from the tetrahedron of the previous insertion.
//!
//! From the current cell, cross any facet whose plane strictly separates the cell from the
//! query point (exact `orient3d`); stop when no facet does: the query lies in the closed
//! cell. The facet to try first is chosen by a seeded xorshift generator, which is the
//! "stochastic walk" of Devillers, Pion & Teillaud (it cannot cycle forever, unlike a fixed
//! facet order on degenerate inputs) while staying deterministic. The facet we came through
//! is never re-tested ("remembering" walk). An infinite cell `(…, ∞, …)` contains the query
//! when it lies strictly outside the cell's hull facet; otherwise the walk steps back into
//! the finite cell behind that facet.
//!
//! A cell reached this way is always in conflict with the query: a finite closed
//! tetrahedron lies strictly inside its circumsphere except at its vertices, and the vertex
//! case is exactly a duplicate point, reported instead.

use super::INFINITE;
use super::build::{Builder, DEAD};
use super::predicates::{facet_orientations, in_conflict, orient_ids};

/// Where a query point was found.
pub(super) enum Location {
    /// A cell in conflict with the point.
    Cell(u32),
    /// The point coincides with this existing vertex.
    Duplicate(u32),
}

impl Builder<'_> {
    #[inline]
    fn next_walk_bits(&mut self) -> usize {
        let mut x = self.walk_rng;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.walk_rng = x;
        (x >> 7) as usize
    }

    #[inline(never)]
    pub(super) fn locate(&mut self, q: u32) -> Location {
        let pq = self.pts[q as usize];
        let mut t = self.last;
        let mut prev = u32::MAX;
        // A walk in a Delaunay triangulation visits O(n^(1/3)) cells at worst in practice;
        // the bound only protects against an unforeseen cycle.
        let limit = 64 + 8 * self.cells.len();
        for _ in 0..limit {
            let v = self.cells[t as usize].v;
            if let Some(k) = v.iter().position(|&x| x == INFINITE) {
                let mut w = v;
                w[k] = q;
                if orient_ids_with(self.pts, w, q, &pq) > 0.0 {
                    return Location::Cell(t);
                }
                prev = t;
                t = self.cells[t as usize].n[k] >> 2;
                continue;
            }
            let r = self.next_walk_bits();
            // The filter for all four facets at once (they share their arithmetic); a
            // facet it cannot decide is asked exactly, so the walk takes the same steps.
            let (det, bound) = facet_orientations(v.map(|x| &self.pts[x as usize]), &pq);
            let mut moved = false;
            for j in 0..4 {
                let i = (r + j) & 3;
                let n = self.cells[t as usize].n[i] >> 2;
                if n == prev {
                    continue;
                }
                let separates = if det[i] > bound {
                    false
                } else if -det[i] > bound {
                    true
                } else {
                    let mut w = v;
                    w[i] = q;
                    orient_ids_with(self.pts, w, q, &pq) < 0.0
                };
                if separates {
                    prev = t;
                    t = n;
                    moved = true;
                    break;
                }
            }
            if !moved {
                for &x in &v {
                    if self.pts[x as usize] == pq {
                        return Location::Duplicate(x);
                    }
                }
                return Location::Cell(t);
            }
        }
        self.locate_brute_force(q)
    }

    /// Exhaustive fallback, never expected to run.
    #[cold]
    fn locate_brute_force(&mut self, q: u32) -> Location {
        let pq = self.pts[q as usize];
        for v in self.cells.iter().map(|c| &c.v) {
            if v[0] == DEAD {
                continue;
            }
            if let Some(&x) = v
                .iter()
                .find(|&&x| x != INFINITE && self.pts[x as usize] == pq)
            {
                return Location::Duplicate(x);
            }
        }
        for (t, v) in self.cells.iter().map(|c| &c.v).enumerate() {
            if v[0] == DEAD {
                continue;
            }
            let inside = match v.iter().position(|&x| x == INFINITE) {
                Some(k) => {
                    let mut w = *v;
                    w[k] = q;
                    orient_ids(self.pts, w) > 0.0
                }
                None => in_conflict(self.pts, *v, q),
            };
            if inside {
                return Location::Cell(t as u32);
            }
        }
        unreachable!("every point is in conflict with some cell of a triangulation of R^3")
    }
}

/// `orient_ids` where the id `q` is known to have coordinates `pq` (saves a lookup).
#[inline(always)]
fn orient_ids_with(pts: &[[f64; 3]], w: [u32; 4], q: u32, pq: &[f64; 3]) -> f64 {
    let p = |i: u32| if i == q { pq } else { &pts[i as usize] };
    super::predicates::orient3d(p(w[0]), p(w[1]), p(w[2]), p(w[3]))
}
