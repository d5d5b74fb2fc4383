//! Where a standing player is (GoldSrc/Quake clip hull 1): the places the camera's
//! target occupies. `vdgview check` measures the graph's walkable coverage on them and
//! the reduction keeps them inside the volume (`reduce::reduce_keeping`).
//!
//! A place is a player origin with clip hull 1 free there and the floor right below
//! (the origin dropped onto a floor), on a slope a player can stand on.
//!
//! GoldSrc, Quake 2 and Quake 3 players also crouch (clip hull 3; GoldSrc's is 36 units
//! tall) where they cannot stand: vents, crawl spaces, low gaps. Those places
//! ([`Crouching::column_places`], with each game's heights: [`Body`]) are kept too, at
//! the crouched eye the camera follows.
//!
//! ```no_run
//! use bsp::{Bsp, oracle::Oracle, player};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let oracle = Oracle::new(&bsp, &Default::default());
//! let hull = oracle.clip_hull(1).expect("the map has clip hulls");
//! let origins = player::column_floors(hull, &oracle, 0.0, 0.0, 4096.0, -4096.0);
//! # Ok::<(), bsp::BspError>(())
//! ```

use crate::Game;
use crate::oracle::{Body, Hull, Oracle, PlayerHull, Stance};

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
/// some maps a share of the places clip hull 1 offered had their origin inside solid
/// for hull 0, hundreds of units from any wall of free space — no player stands there,
/// and no graph of free space can contain them (they were nearly all the places an
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

/// A map's crouching players: their game's two stances ([`Body`]: GoldSrc crouches
/// with the origin 18 units up and the eye 12 above it, standing 72 units tall; Quake 2
/// 24 up in both stances, the eye 2 below it, 56 tall; Quake 3 24 up, the eye 12 above
/// it, 56 tall) and the two hulls that say where they fit, the duck hull (clip hull 3)
/// and the standing hull (clip hull 1).
#[derive(Clone, Copy)]
pub struct Crouching<'o> {
    pub standing: Stance,
    pub crouched: Stance,
    duck: &'o Hull,
    stand: &'o Hull,
    oracle: &'o Oracle,
}

impl<'o> Crouching<'o> {
    /// The crouching players of a `game` map: `None` unless they crouch (not in
    /// Quake 1) and the map has clip hulls 1 and 3 (Quake 2 and 3: built from the
    /// brushes).
    pub fn of(oracle: &'o Oracle, game: Game) -> Option<Crouching<'o>> {
        let body = Body::of(game);
        Some(Crouching {
            standing: body.standing,
            crouched: body.crouched?,
            duck: oracle.clip_hull(3)?,
            stand: oracle.clip_hull(1)?,
            oracle,
        })
    }

    /// The crouched origins in the column (`x`, `y`) where only a crouching player
    /// fits: the duck hull has a floor there ([`column_floors`]), the standing hull is
    /// blocked where a standing player's origin would be, the point hull's floor lies
    /// right below (within 2 units: the hulls' expansions also find "floors" on the
    /// tops of walls and clip brushes with open space below) and its ceiling less than
    /// a standing player's height above it (straight up), a ceiling that is not the
    /// sky. Crouch-only places are a small share of the places a player fits.
    ///
    /// The sky is the map's lid, not a ceiling: without that test most of the
    /// crouch-only places on open outdoor maps were the tops of walls and buildings a
    /// few dozen units under the sky, out of bounds, which the reduction kept and the
    /// crouch coverage counted.
    pub fn column_places(&self, x: f64, y: f64, top: f64, bottom: f64) -> Vec<f64> {
        let oracle = self.oracle;
        let mut out = column_floors(self.duck, oracle, x, y, top, bottom);
        out.retain(|&z| {
            let floor = z - self.crouched.origin_above_ground();
            let standing_origin = floor + self.standing.origin_above_ground();
            oracle.blocks(self.stand.contents([x, y, standing_origin]))
                && !oracle.is_free([x, y, floor - 2.0])
                && low_ceiling(oracle, [x, y, floor + 0.5], self.standing.height())
        });
        out
    }

    /// The crouched eye's height above its origin (the engine's view offset).
    pub fn eye_above_origin(&self) -> f64 {
        self.crouched.view
    }
}

/// Whether something other than the sky lies straight up from the free point `a`
/// within `reach` units: the segment is blocked, and where the world's point trace
/// (hull 0) stops is not the sky, or a solid model blocks before that.
fn low_ceiling(oracle: &Oracle, a: [f64; 3], reach: f64) -> bool {
    let b = [a[0], a[1], a[2] + reach];
    if oracle.segment_free(a, b) {
        return false;
    }
    match oracle.trace(0, a, b) {
        Some(t) if t.fraction < 1.0 => {
            let hit = t.end;
            oracle.contents([hit[0], hit[1], hit[2] + 0.25]) != crate::contents::SKY
                || !oracle.segment_free(a, hit)
        }
        // Only a solid model blocks the way up.
        _ => true,
    }
}

/// The crouched eyes ([`Crouching::eye_above_origin`] above the origin) of the
/// crouch-only places ([`Crouching::column_places`]) on the grid of [`grid_origins`],
/// where the eye is free. Empty unless `game`'s players crouch and the map has the
/// hulls for it ([`Crouching::of`]).
pub fn grid_crouch_eyes(
    oracle: &Oracle,
    game: Game,
    lo: [f64; 3],
    hi: [f64; 3],
    spacing: f64,
) -> Vec<[f64; 3]> {
    let Some(crouching) = Crouching::of(oracle, game) else {
        return Vec::new();
    };
    let eye = crouching.eye_above_origin();
    on_grid(lo, hi, spacing, |x, y, top, bottom| {
        crouching
            .column_places(x, y, top, bottom)
            .into_iter()
            .map(|z| [x, y, z + eye])
            .filter(|&p| oracle.is_free(p))
            .collect()
    })
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
    on_grid(lo, hi, spacing, |x, y, top, bottom| {
        column_floors(hull, oracle, x, y, top, bottom)
            .into_iter()
            .map(|z| [x, y, z])
            .collect()
    })
}

/// The points `column(x, y, top, bottom)` gives for every column of a regular grid
/// `spacing` units apart over the box `lo`–`hi` (column centres, the box's height a
/// unit wider), row by row: in a fixed order, whatever the thread count.
fn on_grid(
    lo: [f64; 3],
    hi: [f64; 3],
    spacing: f64,
    column: impl Fn(f64, f64, f64, f64) -> Vec<[f64; 3]> + Sync,
) -> Vec<[f64; 3]> {
    use rayon::prelude::*;
    let nx = ((hi[0] - lo[0]) / spacing).ceil().max(1.0) as usize;
    let ny = ((hi[1] - lo[1]) / spacing).ceil().max(1.0) as usize;
    (0..ny)
        .into_par_iter()
        .flat_map_iter(|j| {
            let y = lo[1] + (j as f64 + 0.5) * spacing;
            let column = &column;
            (0..nx).flat_map(move |i| {
                let x = lo[0] + (i as f64 + 0.5) * spacing;
                column(x, y, hi[2] + 1.0, lo[2] - 1.0)
            })
        })
        .collect()
}

/// How far a standing player's origin is above its feet in `game` (GoldSrc 36, the
/// middle of its 72-unit hull; Quake 1, 2 and 3 24).
pub fn standing_origin_above_ground(game: Game) -> f64 {
    Body::of(game).standing.origin_above_ground()
}

/// How far the player's origin is above the floor, standing or crouched, in the map's
/// game ([`Body::of`]: GoldSrc 36 and 18, the middle of its hulls; Quake 1, 2 and 3
/// 24 in both stances).
pub fn above_floor(oracle: &Oracle, crouch: bool) -> f64 {
    Body::of(oracle.game())
        .stance(player_hull(crouch))
        .origin_above_ground()
}

/// The player's box for a stance: crouched (clip hull 3) or standing (clip hull 1).
pub fn player_hull(crouch: bool) -> PlayerHull {
    if crouch {
        PlayerHull::Crouched
    } else {
        PlayerHull::Standing
    }
}

/// Whether the hull of `hull` (1 standing, 3 crouched) fits at `origin`.
pub fn hull_fits(oracle: &Oracle, hull: usize, origin: [f64; 3]) -> bool {
    oracle
        .clip_contents(hull, origin)
        .is_some_and(|c| !oracle.blocks(c))
}

/// Whether the map's players crouch (Quake 1's do not, though its maps keep a third
/// clip hull).
pub fn crouches(oracle: &Oracle) -> bool {
    Body::of(oracle.game()).crouched.is_some()
}

/// The clip hulls a player may move with, in the order to try them: the crouched
/// one (3) when `crouch` asks for it, else the standing one (1) and then the
/// crouched one; only the standing one where players do not crouch ([`crouches`]).
pub fn clip_hulls(oracle: &Oracle, crouch: bool) -> &'static [usize] {
    match (crouch, crouches(oracle)) {
        (_, false) => &[1],
        (true, true) => &[3],
        (false, true) => &[1, 3],
    }
}

/// A player origin on the floor below `(x, y)` near floor height `floor_hint`, the
/// way a moving player meets the ground: the standing hull traced down from up to one
/// step (18 units, tried from 20, 10 and 1 unit up) above, or the crouched hull where
/// the standing one does not fit (or `crouch` asks for it; never where players do
/// not crouch, see [`crouches`]). Returns the origin and whether it is crouched;
/// `None` where neither stands on walkable ground (normal z ≥ 0.7) within 40 units.
/// Unlike [`column_floors`], which lists every floor of a column for sampling, this
/// finds the one floor a player at a known height lands on.
pub fn settle(
    oracle: &Oracle,
    x: f64,
    y: f64,
    floor_hint: f64,
    crouch: bool,
) -> Option<([f64; 3], bool)> {
    for &hull in clip_hulls(oracle, crouch) {
        let half = above_floor(oracle, hull == 3);
        for lift in [20.0, 10.0, 1.0] {
            let top = [x, y, floor_hint + half + lift];
            if !hull_fits(oracle, hull, top) {
                continue;
            }
            let tr = oracle.trace(hull, top, [x, y, floor_hint + half - 40.0])?;
            if tr.start_solid || tr.fraction >= 1.0 || tr.normal[2] < 0.7 {
                break;
            }
            return Some((tr.end, hull == 3));
        }
    }
    None
}

/// Whether a player origin stands free and on the ground: its hull fits and the
/// ground lies within 2 units below.
pub fn on_floor(oracle: &Oracle, origin: [f64; 3], crouch: bool) -> bool {
    let hull = if crouch { 3 } else { 1 };
    hull_fits(oracle, hull, origin)
        && oracle
            .trace(hull, origin, [origin[0], origin[1], origin[2] - 2.0])
            .is_some_and(|t| t.fraction < 1.0 && t.normal[2] >= 0.7)
}

/// The feet under column `(x, y)` found going down `hull` (a clip hull, or the point
/// hull for maps without them) from origin height `top` to `bottom`: the z of the
/// first solid leaf minus `half` (the origin's height above the feet, 0 with the point
/// hull), or `None` when the column is solid at `top` or has no floor above `bottom`.
/// Any solid counts, whatever its slope: a flow field's floor map wants the ground
/// under every column, where [`column_floors`] wants only places a player stands.
pub fn ground_below(hull: &Hull, x: f64, y: f64, top: f64, bottom: f64, half: f64) -> Option<f64> {
    let (a, b) = ([x, y, top], [x, y, bottom]);
    let mut first: Option<(f64, i32)> = None;
    let mut hit = None;
    hull.segment_leaves(a, b, |t0, _t1, c, _n| {
        if hit.is_some() {
            return;
        }
        if first.is_none() {
            first = Some((t0, c));
        }
        if c == crate::contents::SOLID {
            hit = Some(t0);
        }
    });
    let (_, c0) = first?;
    if c0 == crate::contents::SOLID {
        return None;
    }
    let t = hit?;
    Some(top + t * (bottom - top) - half)
}

/// The highest feet of column `(x, y)` between `lo_z` and `hi_z` ([`ground_below`]
/// from the first free height found stepping down 64 units at a time).
pub fn top_floor(hull: &Hull, x: f64, y: f64, lo_z: f64, hi_z: f64, half: f64) -> Option<f64> {
    let mut z = hi_z + half;
    while z > lo_z && hull.contents([x, y, z]) == crate::contents::SOLID {
        z -= 64.0;
    }
    ground_below(hull, x, y, z, lo_z - half, half)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A crouching GoldSrc player's eye above the floor: the duck hull's origin 18
    /// units up, the duck view 12 above it.
    const GOLDSRC_CROUCHED_EYE: f64 = 30.0;
    use crate::Bsp;
    use crate::oracle::OracleOptions;

    /// mapgen's `crawl_duct`: rooms `[0,256]` and `[512,768]` in x, a duct
    /// `[240,528]×[96,160]×[0,48]` between them, floors at z = 0.
    fn duct() -> (Bsp, Oracle) {
        let bytes = mapgen::bsp::write_world(&mapgen::worlds::crawl_duct());
        let bsp = Bsp::parse(&bytes).expect("generated map parses");
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        (bsp, oracle)
    }

    #[test]
    fn crouch_places_are_exactly_where_only_the_duck_hull_fits() {
        let (_, oracle) = duct();
        let crouching = Crouching::of(&oracle, Game::GoldSrc).expect("hulls 1 and 3");
        assert_eq!(crouching.crouched.origin_above_ground(), 18.0);
        assert_eq!(crouching.eye_above_origin(), 12.0);
        assert_eq!(crouching.standing.height(), 72.0);
        let at = |x: f64, y: f64| crouching.column_places(x, y, 200.0, -8.0);
        // Inside the duct, the duck hull's 16-unit half width clear of its side
        // walls: one place, the crouched origin 18 units above the floor.
        for (x, y) in [
            (300.0, 128.0),
            (384.0, 113.0),
            (480.0, 143.0),
            (272.5, 128.0),
        ] {
            let z = at(x, y);
            assert_eq!(z.len(), 1, "({x}, {y}): {z:?}");
            assert!(
                (z[0] - crouching.crouched.origin_above_ground()).abs() < 0.1,
                "({x}, {y}): {z:?}"
            );
        }
        // In the rooms a player stands; against the duct's side walls the duck hull
        // does not fit; under the duct's mouth the standing hull still fits.
        for (x, y) in [
            (128.0, 128.0),
            (640.0, 200.0),
            (384.0, 104.0),
            (384.0, 156.0),
            (230.0, 128.0),
        ] {
            assert_eq!(at(x, y), Vec::<f64>::new(), "({x}, {y})");
        }
    }

    /// A room whose ceiling is sky over its west half and solid over its east half,
    /// with a block in each half whose top lies 48 units under the ceiling: a
    /// crouching player fits on both tops, but only the east one is a crawl space —
    /// the west one is the top of a wall under the map's lid (on open outdoor maps such
    /// tops were most of the crouch-only places).
    #[test]
    fn crouch_places_under_the_sky_are_not_crawl_spaces() {
        use mapgen::world::{Aabb, World};
        let mut w = World::new("sky_lid", "blocks under a sky and under a ceiling");
        w.free
            .push(Aabb::new([0.0, 0.0, 0.0], [256.0, 256.0, 160.0]));
        w.sky
            .push(Aabb::new([-16.0, -16.0, 160.0], [128.0, 272.0, 176.0]));
        w.solids
            .push(Aabb::new([16.0, 64.0, 0.0], [112.0, 192.0, 112.0]));
        w.solids
            .push(Aabb::new([144.0, 64.0, 0.0], [240.0, 192.0, 112.0]));
        w.spawns = vec![[128.0, 32.0, 37.0]];
        let bytes = mapgen::bsp::write_world(&w);
        let bsp = Bsp::parse(&bytes).expect("generated map parses");
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let eyes = grid_crouch_eyes(
            &oracle,
            bsp.game,
            [0.0, 0.0, 0.0],
            [256.0, 256.0, 160.0],
            8.0,
        );
        // The east block's top, 12 × 16 columns of the 8-unit grid (x 144–240,
        // y 64–192), where the duck hull stands on it: all of them, and nothing west.
        assert_eq!(eyes.len(), 12 * 16, "{:?}", &eyes[..eyes.len().min(8)]);
        for e in &eyes {
            assert!(e[0] > 144.0 && e[0] < 240.0, "{e:?}");
            let eye = 112.0 + GOLDSRC_CROUCHED_EYE;
            assert!((e[2] - eye).abs() < 0.1, "{e:?}");
        }
    }

    #[test]
    fn crouch_eyes_cover_the_duct_floor_and_nothing_else() {
        let (bsp, oracle) = duct();
        let w = bsp.world();
        let (lo, hi) = (w.mins.map(f64::from), w.maxs.map(f64::from));
        let eyes = grid_crouch_eyes(&oracle, bsp.game, lo, hi, 8.0);
        // The duct's floor under its 48-unit ceiling (x from 256 to 512; in its
        // mouths, 16 units either side, a player cannot stand either, but the
        // ceiling straight up is the room's), where the duck hull clears the side
        // walls (y from 96 + 16 to 160 − 16): every column of the 8-unit grid there.
        let columns = |a: f64, b: f64, l: f64| {
            (0..1000)
                .map(|i| l + (i as f64 + 0.5) * 8.0)
                .filter(|&c| c > a && c < b)
                .count()
        };
        let want = columns(256.0, 512.0, lo[0]) * columns(112.0, 144.0, lo[1]);
        assert!(want > 100);
        assert_eq!(eyes.len(), want);
        for e in &eyes {
            assert!(
                e[0] > 256.0 && e[0] < 512.0 && e[1] > 112.0 && e[1] < 144.0,
                "{e:?}"
            );
            let eye = GOLDSRC_CROUCHED_EYE;
            assert!((e[2] - eye).abs() < 0.1, "{e:?}");
        }
    }
}
