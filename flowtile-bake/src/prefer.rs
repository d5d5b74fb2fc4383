//! Designed flows: soft preferences that weight the random choice among the
//! tiles the selection function allows.
//!
//! The selection function decides what is *possible*; preferences only change
//! how likely each possible tile is, so a preferring fill is exactly as
//! completable as the uniform one. Three kinds are offered:
//!
//! * a **main direction** `d` per rectangular region: an edge whose normal
//!   has component `a = d·n` costs `exp(strength · min(0, a·m − |a|))`, so
//!   one unit of flux or more along `d` is free and none or backwards costs
//!   (rewarding *more* flux instead would pile the conserved total into the
//!   first rows and force the rest backwards); corner velocities against or
//!   across `d` cost `exp(−strength · (max(0, −d·v) + |d×v|) / |v|max)`; and
//!   the backflow of the filled tile itself (mean face velocity against
//!   `d`) is scored for every corner choice, and for flux choices through
//!   the best tile they allow, so the continuous field flows along `d`;
//! * **favour straight**: `exp(−straight · (|l−r| + |b−t|))`, so flow that
//!   enters a tile leaves it on the opposite side;
//! * **favour reuse**: a flux tuple that some placed tile already has weighs
//!   `1 + reuse` (`(1 + reuse)²` when that tile also fits the fixed
//!   corners), with probability `reuse / (1 + reuse)` the corners of a
//!   placed tile are copied when they fit, and otherwise a corner choice
//!   that recreates a placed tile weighs `1 + reuse`, so the tiling needs
//!   fewer distinct tiles (smaller baked files).

use crate::tileset::TileKey;

/// A main direction for the slots `x0..=x1` × `y0..=y1`.
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionRegion {
    /// First and last slot column.
    pub x: (u32, u32),
    /// First and last slot row.
    pub y: (u32, u32),
    /// Main direction (any length; normalised when used).
    pub direction: [f64; 2],
    /// How strongly the direction is preferred (0 = not at all).
    pub strength: f64,
}

/// Soft preferences for the random fill.
///
/// ```
/// use flowtile_bake::prefer::{DirectionRegion, Preferences};
/// let p = Preferences {
///     regions: vec![DirectionRegion { x: (0, 9), y: (0, 3), direction: [1.0, 0.0], strength: 2.0 }],
///     straight: 1.0,
///     reuse: 4.0,
/// };
/// assert!(!p.is_uniform());
/// assert!(Preferences::default().is_uniform());
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Preferences {
    /// Main directions; where regions overlap their scaled directions add up
    /// (a street crossing can prefer east and north at once).
    pub regions: Vec<DirectionRegion>,
    /// Weight of going straight (0 = indifferent).
    pub straight: f64,
    /// Weight of reusing tiles already placed (0 = indifferent).
    pub reuse: f64,
}

impl Preferences {
    /// True when every allowed tile is equally likely.
    pub fn is_uniform(&self) -> bool {
        self.straight == 0.0 && self.reuse == 0.0 && self.regions.iter().all(|r| r.strength == 0.0)
    }

    /// Checks the numbers (finite, non-negative weights, non-zero directions).
    pub fn validate(&self) -> Result<(), String> {
        let ok = |v: f64| v.is_finite() && (0.0..=1e3).contains(&v);
        if !ok(self.straight) {
            return Err(format!("straight = {} must lie in 0..=1000", self.straight));
        }
        if !ok(self.reuse) {
            return Err(format!("reuse = {} must lie in 0..=1000", self.reuse));
        }
        for (i, r) in self.regions.iter().enumerate() {
            if !ok(r.strength) {
                return Err(format!("direction[{i}].strength must lie in 0..=1000"));
            }
            let len = r.direction[0].hypot(r.direction[1]);
            if !(len.is_finite() && len > 0.0) {
                return Err(format!("direction[{i}] must be a non-zero finite vector"));
            }
        }
        Ok(())
    }

    /// The per-slot main direction scaled by its strength (row-major, bottom
    /// row first): the sum over the regions covering the slot, zero where
    /// none does.
    pub fn slot_directions(&self, width: u32, height: u32) -> Vec<[f64; 2]> {
        let mut out = vec![[0.0; 2]; (width * height) as usize];
        for r in &self.regions {
            let len = r.direction[0].hypot(r.direction[1]);
            let d = [
                r.direction[0] / len * r.strength,
                r.direction[1] / len * r.strength,
            ];
            for y in r.y.0..=r.y.1.min(height.saturating_sub(1)) {
                for x in r.x.0..=r.x.1.min(width.saturating_sub(1)) {
                    let o = &mut out[(y * width + x) as usize];
                    o[0] += d[0];
                    o[1] += d[1];
                }
            }
        }
        out
    }

    /// Log-weight of a flux tuple `(l, b, r, t)` in a slot whose scaled main
    /// direction is `dir`, not counting reuse.
    pub fn flux_log_weight(&self, dir: [f64; 2], f: [i32; 4]) -> f64 {
        let [l, b, r, t] = f.map(|m| m as f64);
        // An edge whose normal makes a component `a` with the scaled
        // direction costs `min(0, a·m − |a|)`: nothing for one unit of flux
        // or more along the direction, more for none, more still against.
        let cost = |a: f64, m: f64| (a * m - a.abs()).min(0.0);
        let against = cost(dir[0], l) + cost(dir[0], r) + cost(dir[1], b) + cost(dir[1], t);
        let cross =
            (dir[1] * l).abs() + (dir[1] * r).abs() + (dir[0] * b).abs() + (dir[0] * t).abs();
        against - CROSS * cross - self.straight * ((l - r).abs() + (b - t).abs())
    }
}

/// Weight of flux across the main direction relative to flux against it.
const CROSS: f64 = 0.0;

/// Turns log-weights into weights without overflow (the largest becomes 1).
pub fn normalise_log_weights(logs: &mut [f64]) {
    let max = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    for w in logs.iter_mut() {
        *w = (*w - max).exp();
    }
}

/// Usage record of placed tiles for "favour reuse".
#[derive(Clone, Debug, Default)]
pub struct Usage {
    keys: std::collections::BTreeMap<TileKey, u32>,
    tuples: std::collections::BTreeSet<[i32; 4]>,
}

impl Usage {
    /// Records one placement.
    pub fn add(&mut self, key: TileKey) {
        *self.keys.entry(key).or_insert(0) += 1;
        self.tuples.insert(key.fluxes());
    }

    /// True when `key` has been placed.
    pub fn contains(&self, key: &TileKey) -> bool {
        self.keys.contains_key(key)
    }

    /// True when some placed tile has these fluxes.
    pub fn has_tuple(&self, f: [i32; 4]) -> bool {
        self.tuples.contains(&f)
    }

    /// Placed keys with fluxes `f` whose corners agree with `fixed`, with
    /// their use counts.
    pub fn compatible(&self, f: [i32; 4], fixed: [Option<u16>; 4]) -> Vec<(TileKey, u32)> {
        let lo = TileKey::from_fluxes(f, [0; 4]);
        let hi = TileKey::from_fluxes(f, [u16::MAX; 4]);
        self.keys
            .range(lo..=hi)
            .filter(|(k, _)| (0..4).all(|c| fixed[c].is_none_or(|v| v == k.corners[c])))
            .map(|(k, &n)| (*k, n))
            .collect()
    }
}
