//! Where a standing player is (GoldSrc/Quake clip hull 1): the places the camera's
//! target occupies. `vdgview check` measures the graph's walkable coverage on them and
//! the reduction keeps them inside the volume (`reduce::reduce_keeping`).
//!
//! A place is a player origin with clip hull 1 free there and the floor right below
//! (the origin dropped onto a floor), on a slope a player can stand on.
//!
//! ```no_run
//! use bsp2vdg::{bsp::Bsp, oracle::Oracle, standing};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let oracle = Oracle::new(&bsp, &Default::default());
//! let hull = oracle.clip_hull(1).expect("the map has clip hulls");
//! let origins = standing::column_floors(hull, &oracle, 0.0, 0.0, 4096.0, -4096.0);
//! # Ok::<(), bsp2vdg::bsp::BspError>(())
//! ```

use bsp::oracle::{Hull, Oracle};

/// The standing player's origin is 36 units above the ground (the middle of the
/// 72-unit clip hull 1), the head (eyes) 64 units above it.
pub const ORIGIN_ABOVE_GROUND: f64 = 36.0;
pub const HEAD_ABOVE_GROUND: f64 = 64.0;
/// The steepest floor a player stands on: the engine's ground test wants the plane's
/// normal to have z ≥ 0.7 (steeper slopes are slid down).
pub const MIN_FLOOR_NORMAL_Z: f32 = 0.7;

/// The player origins in the vertical column at (`x`, `y`) between heights `top` and
/// `bottom`, from the top down: every place where clip hull 1 turns from free to
/// blocked going down on a walkable slope, and whose origin the point hull (hull 0)
/// calls free too. The hulls are compiled separately and do not always agree: on
/// de_cbble 2 % of the places clip hull 1 offered had their origin inside solid for
/// hull 0, 100–600 units from any wall of free space — no player stands there, and no
/// graph of free space can contain them (they were 602 of the 603 places its
/// unreduced graph missed).
pub fn column_floors(
    hull: &Hull,
    oracle: &Oracle,
    x: f64,
    y: f64,
    top: f64,
    bottom: f64,
) -> Vec<f64> {
    let mut floors = Vec::new();
    // The exit plane of the last leaf when that leaf was free.
    let mut above_free: Option<[f32; 3]> = None;
    hull.segment_leaves([x, y, top], [x, y, bottom], |t0, t1, c, exit| {
        if !oracle.blocks(c) {
            above_free = Some(exit);
        } else if t1 > t0 {
            // A zero-length blocked piece is a touched edge, not a floor.
            if let Some(n) = above_free.take()
                && n[2].abs() >= MIN_FLOOR_NORMAL_Z
            {
                let z = top + t0 * (bottom - top);
                if oracle.is_free([x, y, z]) {
                    floors.push(z);
                }
            }
        }
    });
    floors
}

/// Spacing of the columns whose floors the reduction keeps inside the volume.
pub const KEEP_SPACING: f64 = 16.0;

/// Player origins on a regular grid of columns `spacing` units apart over the box
/// `lo`–`hi` (e.g. the world model's bounds; every floor of each column), in a fixed
/// order. Empty when the map has no clip hulls.
pub fn grid_origins(oracle: &Oracle, lo: [f64; 3], hi: [f64; 3], spacing: f64) -> Vec<[f64; 3]> {
    let Some(hull) = oracle.clip_hull(1) else {
        return Vec::new();
    };
    let nx = ((hi[0] - lo[0]) / spacing).ceil().max(1.0) as usize;
    let ny = ((hi[1] - lo[1]) / spacing).ceil().max(1.0) as usize;
    use rayon::prelude::*;
    (0..ny)
        .into_par_iter()
        .flat_map_iter(|j| {
            let y = lo[1] + (j as f64 + 0.5) * spacing;
            (0..nx).flat_map(move |i| {
                let x = lo[0] + (i as f64 + 0.5) * spacing;
                column_floors(hull, oracle, x, y, hi[2] + 1.0, lo[2] - 1.0)
                    .into_iter()
                    .map(move |z| [x, y, z])
            })
        })
        .collect()
}
