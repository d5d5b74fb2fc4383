//! The selection function (which tiles keep the tiling completable at a
//! slot), and placing and removing single tiles.

use super::{Border, Tiling, TilingError};
use crate::flow::ArcId;
use crate::tileset::TileKey;

/// The tiles the selection function offers for one slot: every listed flux
/// tuple combined with every choice of the four corner lists.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// Flux tuples `(left, bottom, right, top)` that keep the tiling completable.
    pub fluxes: Vec<[i32; 4]>,
    /// Allowed corner indices: bottom-left, bottom-right, top-right, top-left.
    pub corners: [Vec<u16>; 4],
    /// `Some(j)` when corner `k` is the same grid vertex as corner `j < k`
    /// (periodic grids one slot wide or high) and must repeat its choice.
    pub same_as: [Option<usize>; 4],
}

impl Selection {
    /// Number of tiles offered.
    pub fn len(&self) -> u64 {
        self.fluxes.len() as u64 * self.corner_choices()
    }

    fn corner_choices(&self) -> u64 {
        (0..4)
            .filter(|&k| self.same_as[k].is_none())
            .map(|k| self.corners[k].len() as u64)
            .product()
    }

    /// True when nothing fits (never happens for a completable tiling).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The `i`-th offered tile (`i < len()`).
    pub fn key(&self, i: u64) -> TileKey {
        let per_flux = self.corner_choices();
        let fluxes = self.fluxes[(i / per_flux) as usize];
        let mut rest = i % per_flux;
        let mut corners = [0u16; 4];
        for k in (0..4).rev() {
            if self.same_as[k].is_none() {
                let len = self.corners[k].len() as u64;
                corners[k] = self.corners[k][(rest % len) as usize];
                rest /= len;
            }
        }
        for k in 0..4 {
            if let Some(j) = self.same_as[k] {
                corners[k] = corners[j];
            }
        }
        TileKey::from_fluxes(fluxes, corners)
    }

    /// Every offered tile.
    pub fn keys(&self) -> impl Iterator<Item = TileKey> + '_ {
        (0..self.len()).map(|i| self.key(i))
    }
}

impl Tiling {
    /// The selection function: every tile that fits slot `(x, y)` and keeps
    /// the tiling completable.
    ///
    /// Each free edge's exact flux interval comes from max-flow on the
    /// residual graph. With at most two free edges (scan-line order) every
    /// value in the interval is feasible, since conservation leaves one degree
    /// of freedom; with more, each candidate tuple is tested by fixing it
    /// tentatively and rolling back (the paper's second step, needed only
    /// then).
    pub fn select(&mut self, x: u32, y: u32) -> Result<Selection, TilingError> {
        self.check_slot(x, y)?;
        let arcs = self.slot_arcs(x, y);
        let mut ranges = [(0i32, 0i32); 4];
        let mut free_arcs: Vec<ArcId> = Vec::with_capacity(4);
        for (k, &a) in arcs.iter().enumerate() {
            let arc = self.net.arc(a);
            if arc.lo == arc.hi {
                ranges[k] = (arc.lo, arc.hi);
            } else {
                if !free_arcs.contains(&a) {
                    free_arcs.push(a);
                }
                ranges[k] = (arc.lo, arc.hi); // refined below
            }
        }
        for &a in &free_arcs {
            let r = self.net.range(a);
            for k in 0..4 {
                if arcs[k] == a {
                    ranges[k] = r;
                }
            }
        }
        let mut fluxes = Vec::new();
        let test_each = free_arcs.len() >= 3;
        for l in ranges[0].0..=ranges[0].1 {
            for b in ranges[1].0..=ranges[1].1 {
                for r in ranges[2].0..=ranges[2].1 {
                    let t = l + b - r;
                    if t < ranges[3].0 || t > ranges[3].1 {
                        continue;
                    }
                    let values = [l, b, r, t];
                    if !self.same_arc_consistent(&arcs, &values) {
                        continue;
                    }
                    if test_each && !self.tuple_feasible(&arcs, &values) {
                        continue;
                    }
                    fluxes.push(values);
                }
            }
        }
        let c = self.set.corners.len() as u16;
        let verts = self.slot_vertices(x, y);
        let corners = verts.map(|v| match self.corner_fixed[v] {
            Some(i) => vec![i],
            None => (0..c).collect(),
        });
        let same_as = std::array::from_fn(|k| (0..k).find(|&j| verts[j] == verts[k]));
        Ok(Selection {
            fluxes,
            corners,
            same_as,
        })
    }

    /// With periodic borders of width or height 1 a slot's opposite edges are
    /// the same arc and must carry the same value.
    fn same_arc_consistent(&self, arcs: &[ArcId; 4], values: &[i32; 4]) -> bool {
        (0..4).all(|i| (0..4).all(|j| arcs[i] != arcs[j] || values[i] == values[j]))
    }

    fn tuple_feasible(&mut self, arcs: &[ArcId; 4], values: &[i32; 4]) -> bool {
        let mark = self.net.checkpoint();
        let ok = arcs.iter().zip(values).all(|(&a, &v)| self.net.fix(a, v));
        self.net.rollback(mark);
        ok
    }

    /// Places `key` at `(x, y)` if it keeps the tiling completable.
    pub fn place(&mut self, x: u32, y: u32, key: TileKey) -> Result<(), TilingError> {
        self.check_slot(x, y)?;
        if self.set.index_of(&key).is_none() {
            return Err(TilingError::TileNotAllowed(x, y, key));
        }
        let verts = self.slot_vertices(x, y);
        for (k, &v) in verts.iter().enumerate() {
            if let Some(c) = self.corner_fixed[v]
                && c != key.corners[k]
            {
                return Err(TilingError::TileNotAllowed(x, y, key));
            }
        }
        // Same vertex twice (periodic 1-wide grids) must get the same corner.
        for i in 0..4 {
            for j in 0..4 {
                if verts[i] == verts[j] && key.corners[i] != key.corners[j] {
                    return Err(TilingError::TileNotAllowed(x, y, key));
                }
            }
        }
        let arcs = self.slot_arcs(x, y);
        let values = key.fluxes();
        let mark = self.net.checkpoint();
        let ok = arcs.iter().zip(&values).all(|(&a, &v)| self.net.fix(a, v));
        if !ok {
            self.net.rollback(mark);
            return Err(TilingError::TileNotAllowed(x, y, key));
        }
        self.net.commit();
        for (k, &v) in verts.iter().enumerate() {
            self.corner_fixed[v] = Some(key.corners[k]);
        }
        self.slots[(y * self.width + x) as usize] = Some(key);
        Ok(())
    }

    /// Removes the tile at `(x, y)` and returns it (`None` for an empty or
    /// blocked slot). Fewer tiles never break completability: the current
    /// circulation stays feasible, and only the slot's edges and corners
    /// that no other tile holds go back to the conditions' bounds.
    ///
    /// ```
    /// use flowtile_bake::{tileset::TileSet, tiling::{Tiling, Conditions, Border}, rng::Rng};
    /// let set = TileSet::paper(3, 3, 1, 4).unwrap();
    /// let mut t = Tiling::new(set, 3, 3, &Conditions::borders(Border::Free, Border::Free)).unwrap();
    /// t.random_fill(&mut Rng::new(1)).unwrap();
    /// let k = t.remove(1, 1).unwrap();
    /// assert!(t.select(1, 1).unwrap().keys().any(|o| o == k));
    /// ```
    pub fn remove(&mut self, x: u32, y: u32) -> Option<TileKey> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let me = (y * self.width + x) as usize;
        let key = self.slots[me].take()?;
        for arc in self.slot_arcs(x, y) {
            let a = self.net.arc(arc);
            let other = if a.tail as usize == me {
                a.head
            } else {
                a.tail
            } as usize;
            let held = other < self.slots.len() && self.slots[other].is_some();
            if !held {
                let (lo, hi) = self.base_bounds[arc];
                self.net.set_bounds(arc, lo, hi);
            }
        }
        let (w, h) = (self.width as i64, self.height as i64);
        let (px, py) = (
            self.border_x == Border::Periodic,
            self.border_y == Border::Periodic,
        );
        for (vx, vy) in [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)] {
            let held = [(-1i64, -1i64), (0, -1), (-1, 0), (0, 0)]
                .iter()
                .any(|&(dx, dy)| {
                    let (mut sx, mut sy) = (vx as i64 + dx, vy as i64 + dy);
                    if px {
                        sx = sx.rem_euclid(w);
                    }
                    if py {
                        sy = sy.rem_euclid(h);
                    }
                    (0..w).contains(&sx)
                        && (0..h).contains(&sy)
                        && self.slots[(sy * w + sx) as usize].is_some()
                });
            if !held {
                let v = self.vertex(vx, vy);
                self.corner_fixed[v] = self.base_corners[v];
            }
        }
        Some(key)
    }
}
