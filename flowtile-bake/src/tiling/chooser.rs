//! Preference weights of a preferring fill: log-weights of flux tuples,
//! corners and whole keys (main direction, reuse, backflow of the filled
//! tile).

use crate::prefer::{Preferences, Usage, normalise_log_weights};
use crate::rng::Rng;
use crate::tileset::{TileKey, TileSet};

/// Preference state of one preferring fill.
pub(super) struct Chooser {
    /// Scaled main direction per slot.
    dirs: Vec<[f64; 2]>,
    prefs: Preferences,
    usage: Usage,
    /// Backflow of filled tiles per (key, unit direction bits).
    backflow: std::collections::HashMap<(TileKey, [u64; 2]), f64>,
}

impl Chooser {
    /// The state of a fill of a `width`×`height` grid with `prefs`, no tile
    /// placed yet.
    pub(super) fn new(prefs: &Preferences, width: u32, height: u32) -> Chooser {
        Chooser {
            dirs: prefs.slot_directions(width, height),
            prefs: prefs.clone(),
            usage: Usage::default(),
            backflow: Default::default(),
        }
    }

    /// Counts a placed tile (for the reuse weights).
    pub(super) fn placed(&mut self, key: TileKey) {
        self.usage.add(key);
    }

    /// Log-weight of a flux tuple in `slot`: the preferences' flux terms,
    /// the reuse bonus, and with a main direction the backflow of the best
    /// tile these fluxes allow with the slot's fixed corners (a one-tile
    /// lookahead: fluxes whose every tile turns flow back are avoided).
    pub(super) fn flux_log_weight(
        &mut self,
        slot: usize,
        f: [i32; 4],
        fixed: [Option<u16>; 4],
        set: &TileSet,
    ) -> f64 {
        let mut w = self.prefs.flux_log_weight(self.dirs[slot], f);
        if self.prefs.reuse > 0.0 && self.usage.has_tuple(f) {
            // Twice the bonus when a placed tile fits the fixed corners too.
            let fits = !self.usage.compatible(f, fixed).is_empty();
            w += self.prefs.reuse.ln_1p() * if fits { 2.0 } else { 1.0 };
        }
        let d = self.dirs[slot];
        let free = fixed.iter().filter(|c| c.is_none()).count() as u32;
        let c = set.corners.len();
        if d != [0.0, 0.0] && c.pow(free) <= MAX_SCORED_CORNERS {
            let best = (0..c.pow(free))
                .map(|combo| {
                    let key = key_with(f, fixed, combo, c);
                    self.tile_backflow(&key, d, set)
                })
                .fold(f64::INFINITY, f64::min);
            w -= BACKFLOW_WEIGHT * d[0].hypot(d[1]) * best / set.f_base.abs().max(1e-300);
        }
        w
    }

    /// Log-weight of a whole key (fluxes, corners, reuse, backflow).
    pub(super) fn key_log_weight(&mut self, slot: usize, k: &TileKey, set: &TileSet) -> f64 {
        let mut w = self.prefs.flux_log_weight(self.dirs[slot], k.fluxes());
        if self.prefs.reuse > 0.0 && self.usage.has_tuple(k.fluxes()) {
            w += self.prefs.reuse.ln_1p();
        }
        for &c in &k.corners {
            w += self.corner_log_weight(slot, c, set);
        }
        let d = self.dirs[slot];
        if d != [0.0, 0.0] {
            let back = self.tile_backflow(k, d, set);
            w -= BACKFLOW_WEIGHT * d[0].hypot(d[1]) * back / set.f_base.abs().max(1e-300);
        }
        w
    }

    /// Backflow of the filled tile `key` against direction `d` (cached).
    fn tile_backflow(&mut self, key: &TileKey, d: [f64; 2], set: &TileSet) -> f64 {
        let len = d[0].hypot(d[1]);
        let unit = [d[0] / len, d[1] / len];
        *self
            .backflow
            .entry((*key, unit.map(f64::to_bits)))
            .or_insert_with(|| crate::fill::fill_tile(set, key).backflow(unit))
    }

    /// Log-weight of a corner velocity option in `slot`.
    fn corner_log_weight(&self, slot: usize, c: u16, set: &TileSet) -> f64 {
        let d = self.dirs[slot];
        let vmax = set
            .corners
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        if vmax == 0.0 {
            return 0.0;
        }
        let v = set.corners[c as usize];
        let along = d[0] * v[0] + d[1] * v[1];
        let cross = (d[0] * v[1] - d[1] * v[0]).abs();
        (along.min(0.0) - cross) / vmax
    }

    /// Corner indices for a slot whose fluxes are chosen.
    pub(super) fn corners(
        &mut self,
        slot: usize,
        f: [i32; 4],
        fixed: [Option<u16>; 4],
        set: &TileSet,
        rng: &mut Rng,
    ) -> [u16; 4] {
        let r = self.prefs.reuse;
        if r > 0.0 && rng.unit() < r / (1.0 + r) {
            let reusable = self.usage.compatible(f, fixed);
            if !reusable.is_empty() {
                let w: Vec<f64> = reusable.iter().map(|&(_, n)| n as f64).collect();
                return reusable[rng.weighted(&w)].0.corners;
            }
        }
        let d = self.dirs[slot];
        let free = fixed.iter().filter(|c| c.is_none()).count() as u32;
        let c = set.corners.len();
        if d == [0.0, 0.0] || c.pow(free) > MAX_SCORED_CORNERS {
            let mut logs: Vec<f64> = (0..c as u16)
                .map(|i| self.corner_log_weight(slot, i, set))
                .collect();
            normalise_log_weights(&mut logs);
            return fixed.map(|fc| fc.unwrap_or_else(|| rng.weighted(&logs) as u16));
        }
        // With a main direction, score every choice of the free corners by
        // the backflow of the filled tile itself (cached per key), so the
        // corners that make flow turn back inside the tile are avoided.
        let strength = d[0].hypot(d[1]);
        let mut keys = Vec::new();
        let mut logs = Vec::new();
        for combo in 0..c.pow(free) {
            let key = key_with(f, fixed, combo, c);
            let corner_w: f64 = key
                .corners
                .iter()
                .zip(&fixed)
                .filter(|(_, f)| f.is_none())
                .map(|(&k, _)| self.corner_log_weight(slot, k, set))
                .sum();
            let back = self.tile_backflow(&key, d, set);
            let reused = if r > 0.0 && self.usage.contains(&key) {
                r.ln_1p()
            } else {
                0.0
            };
            keys.push(key.corners);
            logs.push(
                corner_w + reused
                    - BACKFLOW_WEIGHT * strength * back / set.f_base.abs().max(1e-300),
            );
        }
        normalise_log_weights(&mut logs);
        keys[rng.weighted(&logs)]
    }
}

/// The key with fluxes `f`, the fixed corners, and the free corners taken
/// from the digits of `combo` in base `c`.
fn key_with(f: [i32; 4], fixed: [Option<u16>; 4], combo: usize, c: usize) -> TileKey {
    let mut rest = combo;
    let corners = fixed.map(|fc| {
        fc.unwrap_or_else(|| {
            let v = (rest % c) as u16;
            rest /= c;
            v
        })
    });
    TileKey::from_fluxes(f, corners)
}

/// Most corner combinations scored by their tile's backflow per slot.
const MAX_SCORED_CORNERS: usize = 4096;
/// Log-weight per unit of mean backflow speed (in units of `f_base`), times
/// the direction's strength.
const BACKFLOW_WEIGHT: f64 = 8.0;
