//! Figures of merit of a baked tiling that say whether a designed flow does
//! what its designer asked: area flowing against the main direction, streets
//! (one-tile corridors) that carry no flow, tile reuse, and the net flux
//! through random boxes (divergence at every point, not only on the grid).

use crate::bake::BakedTiling;
use crate::rng::Rng;

/// Samples per tile side used by [`against_fraction`].
pub const SAMPLES_PER_TILE: u32 = 16;

/// Fraction of the open area (with a main direction) where the velocity
/// points against the slot's main direction (`v · d < 0`), sampled at
/// `SAMPLES_PER_TILE²` cell-centred points per slot. `dirs` is the per-slot
/// direction (zero = no direction, not counted). Returns `None` when no slot
/// has a direction.
///
/// ```
/// use flowtile_bake::{bake::BakedTiling, rng::Rng, stats::against_fraction, tileset::TileSet};
/// use flowtile_bake::tiling::{Border, Conditions, Edge, Tiling};
/// let set = TileSet::paper(3, 3, 1, 6).unwrap();
/// let mut c = Conditions::borders(Border::Free, Border::Zero);
/// c.fluxes.push((Edge::Vertical { x: 0, y: 0 }, 1));
/// let mut t = Tiling::new(set, 3, 1, &c).unwrap();
/// t.random_fill(&mut Rng::new(1)).unwrap();
/// let b = BakedTiling::from_tiling(&t).unwrap();
/// assert_eq!(against_fraction(&b, &vec![[1.0, 0.0]; 3]), Some(0.0));
/// ```
pub fn against_fraction(b: &BakedTiling, dirs: &[[f64; 2]]) -> Option<f64> {
    let k = SAMPLES_PER_TILE;
    let (mut against, mut total) = (0u64, 0u64);
    for y in 0..b.height {
        for x in 0..b.width {
            let d = dirs[(y * b.width + x) as usize];
            if d == [0.0, 0.0] || b.tile_at(x, y).is_none() {
                continue;
            }
            for j in 0..k {
                for i in 0..k {
                    let u = x as f64 + (i as f64 + 0.5) / k as f64;
                    let v = y as f64 + (j as f64 + 0.5) / k as f64;
                    let vel = b.velocity(u, v);
                    let speed = vel[0].hypot(vel[1]);
                    let along = vel[0] * d[0] + vel[1] * d[1];
                    total += 1;
                    against += (along < -1e-9 * (1.0 + speed)) as u64;
                }
            }
        }
    }
    (total > 0).then(|| against as f64 / total as f64)
}

/// One street: a maximal run of open one-tile-wide corridor slots.
#[derive(Clone, Debug, PartialEq)]
pub struct Corridor {
    /// First slot of the run.
    pub start: (u32, u32),
    /// Slots in the run.
    pub len: u32,
    /// True for a run along x (walls above and below).
    pub along_x: bool,
    /// Flux multiple along the run (constant, by conservation).
    pub flux: i32,
}

/// The corridors of a baked tiling: runs of open slots whose two sides
/// across the run are walls (blocked slots or closed borders). In the city
/// spec these are the street segments between crossings.
pub fn corridors(b: &BakedTiling) -> Vec<Corridor> {
    let open = |x: i64, y: i64| {
        let (w, h) = (b.width as i64, b.height as i64);
        let xx = if b.periodic_x { x.rem_euclid(w) } else { x };
        let yy = if b.periodic_y { y.rem_euclid(h) } else { y };
        (0..w).contains(&xx) && (0..h).contains(&yy) && b.tile_at(xx as u32, yy as u32).is_some()
    };
    let mut out = Vec::new();
    for along_x in [true, false] {
        let is_corr = |x: i64, y: i64| {
            open(x, y)
                && if along_x {
                    !open(x, y - 1) && !open(x, y + 1)
                } else {
                    !open(x - 1, y) && !open(x + 1, y)
                }
        };
        let (outer, inner) = if along_x {
            (b.height, b.width)
        } else {
            (b.width, b.height)
        };
        for o in 0..outer as i64 {
            let mut i = 0i64;
            while i < inner as i64 {
                let at = |i: i64| if along_x { (i, o) } else { (o, i) };
                let (x, y) = at(i);
                if !is_corr(x, y) {
                    i += 1;
                    continue;
                }
                let start = i;
                while i < inner as i64 && {
                    let (x, y) = at(i);
                    is_corr(x, y)
                } {
                    i += 1;
                }
                let t = b.tile_at(x as u32, y as u32).expect("open");
                out.push(Corridor {
                    start: (x as u32, y as u32),
                    len: (i - start) as u32,
                    along_x,
                    flux: if along_x { t.key.left } else { t.key.bottom },
                });
            }
        }
    }
    out
}

/// Distinct tiles per open slot (1 = every slot its own tile; smaller is
/// more reuse, the paper's river used 21 tiles for 220 slots).
pub fn reuse_ratio(b: &BakedTiling) -> f64 {
    let slots = b
        .grid
        .iter()
        .filter(|&&g| g != crate::bake::BLOCKED)
        .count();
    b.tiles.len() as f64 / slots.max(1) as f64
}

/// Largest |net flux| / boundary flux over `count` random boxes of sizes
/// from a hundredth of a tile to two tiles anywhere in the grid (boxes with
/// no flow through their boundary are skipped).
pub fn max_box_net_flux(b: &BakedTiling, count: usize, seed: u64) -> f64 {
    let mut rng = Rng::new(seed);
    let mut worst = 0.0f64;
    for k in 0..count {
        let size = [0.01, 0.1, 0.5, 2.0][k % 4];
        let lo = [rng.unit() * b.width as f64, rng.unit() * b.height as f64];
        let hi = [
            (lo[0] + size * (0.2 + rng.unit())).min(b.width as f64),
            (lo[1] + size * (0.2 + rng.unit())).min(b.height as f64),
        ];
        let (net, total) = b.box_flux(lo, hi);
        if total > 1e-9 * size {
            worst = worst.max(net.abs() / total);
        }
    }
    worst
}
