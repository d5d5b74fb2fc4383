//! Filling: the forced positions, the random scan-line fill (uniform or
//! with preferences) and the placement of one drawn tile.

use super::chooser::Chooser;
use super::{Border, Tiling, TilingError};
use crate::flow::ArcId;
use crate::prefer::{Preferences, normalise_log_weights};
use crate::rng::Rng;
use crate::tileset::TileKey;

impl Tiling {
    /// Fills every slot that has exactly one option, repeatedly, until none
    /// is left (the paper's automatic filling of forced positions). Returns
    /// the number of tiles placed.
    pub fn fill_forced(&mut self) -> Result<usize, TilingError> {
        let mut placed = 0;
        loop {
            let mut changed = false;
            for y in 0..self.height {
                for x in 0..self.width {
                    if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                        continue;
                    }
                    let sel = self.select(x, y)?;
                    if sel.len() == 1 {
                        self.place(x, y, sel.key(0))?;
                        placed += 1;
                        changed = true;
                    }
                }
            }
            if !changed {
                return Ok(placed);
            }
        }
    }

    /// Fills every empty slot in scan-line order (bottom row first) with a
    /// tile chosen uniformly from the selection.
    pub fn random_fill(&mut self, rng: &mut Rng) -> Result<(), TilingError> {
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                    continue;
                }
                self.place_random(x, y, rng)?;
            }
        }
        Ok(())
    }

    /// Fills every empty slot in scan-line order like [`Tiling::random_fill`],
    /// drawing each tile with the weights of `prefs` among the tiles the
    /// selection function allows (so the fill always completes). Uniform
    /// preferences give exactly [`Tiling::random_fill`].
    ///
    /// ```
    /// use flowtile_bake::{tileset::TileSet, rng::Rng};
    /// use flowtile_bake::prefer::{DirectionRegion, Preferences};
    /// use flowtile_bake::tiling::{Border, Conditions, Tiling};
    /// let set = TileSet::paper(5, 3, 1, 4).unwrap();
    /// let mut t = Tiling::new(set, 12, 4, &Conditions::borders(Border::Periodic, Border::Zero)).unwrap();
    /// let p = Preferences {
    ///     regions: vec![DirectionRegion { x: (0, 11), y: (0, 3), direction: [1.0, 0.0], strength: 3.0 }],
    ///     ..Default::default()
    /// };
    /// t.random_fill_preferring(&mut Rng::new(1), &p).unwrap();
    /// assert!(t.is_complete());
    /// ```
    pub fn random_fill_preferring(
        &mut self,
        rng: &mut Rng,
        prefs: &Preferences,
    ) -> Result<(), TilingError> {
        if prefs.is_uniform() {
            return self.random_fill(rng);
        }
        let mut chooser = Chooser::new(prefs, self.width, self.height);
        for key in self.slots.iter().flatten() {
            chooser.placed(*key);
        }
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                    continue;
                }
                let key = self.place_chosen(x, y, rng, Some(&mut chooser))?;
                chooser.placed(key);
            }
        }
        Ok(())
    }

    /// Places a tile drawn uniformly from the selection of `(x, y)`.
    ///
    /// When at most two of the slot's edges are free (always so in scan-line
    /// order) the feasible values of the first free edge form an interval
    /// `F` and the second follows by conservation. Rather than computing `F`
    /// exactly (two full max-flow queries, then moving the flux back to the
    /// chosen value) we draw from a candidate interval `C ⊇ F` given by the
    /// edges' own bounds and try to move the flux there; a failed move proves
    /// where `F` ends, so `C` shrinks to it and we draw again. Conditioned on
    /// acceptance the draw is uniform over `F`, and the expected work is one
    /// short move instead of three long ones.
    pub fn place_random(&mut self, x: u32, y: u32, rng: &mut Rng) -> Result<TileKey, TilingError> {
        self.place_chosen(x, y, rng, None)
    }

    /// [`Tiling::place_random`] with optional preference weights.
    fn place_chosen(
        &mut self,
        x: u32,
        y: u32,
        rng: &mut Rng,
        mut chooser: Option<&mut Chooser>,
    ) -> Result<TileKey, TilingError> {
        self.check_slot(x, y)?;
        let arcs = self.slot_arcs(x, y);
        let distinct = (0..4).all(|i| (0..i).all(|j| arcs[i] != arcs[j]));
        // The slot's free edges, in side order (no allocation: this runs for
        // every slot of the fill).
        let mut free = [0usize; 4];
        let mut free_count = 0;
        for (k, &a) in arcs.iter().enumerate() {
            let a = self.net.arc(a);
            if a.lo < a.hi {
                free[free_count] = k;
                free_count += 1;
            }
        }
        let free = &free[..free_count];
        if !distinct {
            return self.place_from_selection(x, y, rng, chooser);
        }
        if free.len() > 2 {
            return self.place_random_tuple(x, y, arcs, rng, chooser);
        }
        let values = if free.len() == 2 {
            self.draw_pair(x, y, arcs, (free[0], free[1]), rng, chooser.as_deref_mut())?
        } else {
            arcs.map(|a| self.net.arc(a).x)
        };
        for (&a, &v) in arcs.iter().zip(&values) {
            if !self.net.fix(a, v) {
                return Err(TilingError::Infeasible(format!(
                    "internal: flux {v} became infeasible at ({x}, {y})"
                )));
            }
        }
        Ok(self.commit_slot(x, y, values, rng, chooser))
    }

    /// [`Tiling::place_chosen`] for a slot whose edges are not distinct arcs
    /// (periodic grids one slot wide or high): a key drawn from the whole
    /// selection, placed the ordinary way.
    fn place_from_selection(
        &mut self,
        x: u32,
        y: u32,
        rng: &mut Rng,
        chooser: Option<&mut Chooser>,
    ) -> Result<TileKey, TilingError> {
        let slot = (y * self.width + x) as usize;
        let sel = self.select(x, y)?;
        if sel.is_empty() {
            return Err(TilingError::Infeasible(format!(
                "no tile fits slot ({x}, {y})"
            )));
        }
        let key = match chooser {
            None => sel.key(rng.below(sel.len())),
            Some(c) => {
                let keys: Vec<TileKey> = sel.keys().collect();
                let mut logs: Vec<f64> = keys
                    .iter()
                    .map(|k| c.key_log_weight(slot, k, &self.set))
                    .collect();
                normalise_log_weights(&mut logs);
                keys[rng.weighted(&logs)]
            }
        };
        self.place(x, y, key)?;
        Ok(key)
    }

    /// The draw of [`Tiling::place_random`] for a slot with two free sides
    /// `(k, f)`: a value of side `k` from its candidate interval, the flux
    /// moved there (the interval shrinking where a move falls short), side
    /// `f` following by conservation. Returns the slot's four fluxes, not
    /// yet fixed.
    fn draw_pair(
        &mut self,
        x: u32,
        y: u32,
        arcs: [ArcId; 4],
        (k, f): (usize, usize),
        rng: &mut Rng,
        chooser: Option<&mut Chooser>,
    ) -> Result<[i32; 4], TilingError> {
        // Conservation l + b - r - t = 0 with signs per side.
        const SIGN: [i32; 4] = [1, 1, -1, -1];
        let slot = (y * self.width + x) as usize;
        let fixed = self.slot_vertices(x, y).map(|v| self.corner_fixed[v]);
        let mut values = arcs.map(|a| self.net.arc(a).x);
        let (ek, ef) = (self.net.arc(arcs[k]), self.net.arc(arcs[f]));
        let rest: i32 = (0..4)
            .filter(|&i| i != k && i != f)
            .map(|i| SIGN[i] * values[i])
            .sum();
        // value of side f given value v of side k
        let partner = |v: i32| -(rest + SIGN[k] * v) * SIGN[f];
        let mut lo = ek.lo;
        let mut hi = ek.hi;
        while lo <= hi && !(ef.lo..=ef.hi).contains(&partner(lo)) {
            lo += 1;
        }
        while hi >= lo && !(ef.lo..=ef.hi).contains(&partner(hi)) {
            hi -= 1;
        }
        let e = arcs[k];
        let tuple = |v: i32| {
            let mut t = values;
            t[k] = v;
            t[f] = partner(v);
            t
        };
        // Log-weights of every candidate value (only with preferences).
        let logs: Vec<f64> = match chooser {
            Some(c) => (lo..=hi)
                .map(|v| c.flux_log_weight(slot, tuple(v), fixed, &self.set))
                .collect(),
            None => Vec::new(),
        };
        let first = lo;
        loop {
            if lo > hi {
                return Err(TilingError::Infeasible(format!(
                    "no tile fits slot ({x}, {y})"
                )));
            }
            let v = if logs.is_empty() {
                lo + rng.below((hi - lo + 1) as u64) as i32
            } else {
                let mut w = logs[(lo - first) as usize..=(hi - first) as usize].to_vec();
                normalise_log_weights(&mut w);
                lo + rng.weighted(&w) as i32
            };
            let cur = self.net.arc(e).x;
            if k == 2 && f == 3 && v != cur {
                self.ladder_move(x, y, v);
            } else if k == 1 && y == 0 && self.border_y == Border::Periodic && v != cur {
                self.seam_move(x, v);
            }
            let cur = self.net.arc(e).x;
            if v > cur {
                let reached = self.net.raise(e, v);
                if reached < v {
                    hi = reached;
                    continue;
                }
            } else if v < cur {
                let reached = self.net.lower(e, v);
                if reached > v {
                    lo = reached;
                    continue;
                }
            }
            values[k] = v;
            values[f] = partner(v);
            return Ok(values);
        }
    }

    /// Rejection sampling over whole flux tuples for slots with three or four
    /// free edges (the first row and column of a free-bordered grid): draw a
    /// tuple allowed by the edges' own bounds, keep it if fixing it stays
    /// feasible, otherwise drop it and draw again. Uniform over the
    /// selection, and usually one feasibility test instead of one per tuple.
    fn place_random_tuple(
        &mut self,
        x: u32,
        y: u32,
        arcs: [ArcId; 4],
        rng: &mut Rng,
        mut chooser: Option<&mut Chooser>,
    ) -> Result<TileKey, TilingError> {
        let slot = (y * self.width + x) as usize;
        let fixed = self.slot_vertices(x, y).map(|v| self.corner_fixed[v]);
        let b = arcs.map(|a| {
            let a = self.net.arc(a);
            (a.lo, a.hi)
        });
        let mut candidates = Vec::new();
        for l in b[0].0..=b[0].1 {
            for bo in b[1].0..=b[1].1 {
                for r in b[2].0..=b[2].1 {
                    let t = l + bo - r;
                    if (b[3].0..=b[3].1).contains(&t) {
                        candidates.push([l, bo, r, t]);
                    }
                }
            }
        }
        let mut logs: Vec<f64> = match chooser.as_deref_mut() {
            Some(c) => candidates
                .iter()
                .map(|&t| c.flux_log_weight(slot, t, fixed, &self.set))
                .collect(),
            None => Vec::new(),
        };
        while !candidates.is_empty() {
            let i = if logs.is_empty() {
                rng.below(candidates.len() as u64) as usize
            } else {
                let mut w = logs.clone();
                normalise_log_weights(&mut w);
                rng.weighted(&w)
            };
            let values = candidates[i];
            let mark = self.net.checkpoint();
            // The row's first slot of a periodic grid: its left edge is the
            // right edge of the row's last slot, across the seam.
            if x == 0 && self.border_x == Border::Periodic && self.width > 1 {
                self.ladder_move(self.width - 1, y, values[0]);
            }
            // The first row of a grid periodic in y: its bottom edge is the
            // top edge of the last row, across the seam.
            if y == 0 && self.border_y == Border::Periodic && self.height > 1 {
                self.seam_move(x, values[1]);
            }
            self.ladder_move(x, y, values[2]);
            // Fixing the left and bottom edges may route flux through the
            // right edge (the short way round); a ladder puts it back before
            // the right edge is fixed, which otherwise takes a long search.
            // Whether the tuple fits does not depend on the order.
            let fits = self.net.fix(arcs[0], values[0]) && self.net.fix(arcs[1], values[1]) && {
                self.ladder_move(x, y, values[2]);
                self.net.fix(arcs[2], values[2]) && self.net.fix(arcs[3], values[3])
            };
            if fits {
                self.net.commit();
                return Ok(self.commit_slot(x, y, values, rng, chooser));
            }
            self.net.rollback(mark);
            candidates.swap_remove(i);
            if !logs.is_empty() {
                logs.swap_remove(i);
            }
        }
        Err(TilingError::Infeasible(format!(
            "no tile fits slot ({x}, {y})"
        )))
    }

    /// Records a slot whose fluxes are already fixed in the network, drawing
    /// its free corners uniformly.
    /// With preferences, a placed tile with these fluxes and fitting corners
    /// is copied with probability `reuse / (1 + reuse)`; otherwise free
    /// corners are drawn with the main direction's weights.
    fn commit_slot(
        &mut self,
        x: u32,
        y: u32,
        values: [i32; 4],
        rng: &mut Rng,
        chooser: Option<&mut Chooser>,
    ) -> TileKey {
        let c = self.set.corners.len() as u64;
        let verts = self.slot_vertices(x, y);
        let fixed = verts.map(|v| self.corner_fixed[v]);
        let corners = match chooser {
            None => fixed.map(|f| f.unwrap_or_else(|| rng.below(c) as u16)),
            Some(ch) => ch.corners((y * self.width + x) as usize, values, fixed, &self.set, rng),
        };
        let key = TileKey::from_fluxes(values, corners);
        for (k, &v) in verts.iter().enumerate() {
            self.corner_fixed[v] = Some(key.corners[k]);
        }
        self.slots[(y * self.width + x) as usize] = Some(key);
        key
    }
}
