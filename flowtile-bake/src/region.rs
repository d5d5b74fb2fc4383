//! Regions from a level: the walkable floor of a map at one level, read
//! through the `bsp` crate, turned into a tiling spec.
//!
//! A column of the map is walkable at the level when a standing player fits
//! there: a downward trace through the player's clip hull (hull 1: the
//! standing player of GoldSrc and Quake) from above the level finds a floor
//! whose height lies within `band` of the level (Quake 2 keeps no clip hulls:
//! the point hull finds the floor and the oracle's player box, the brushes
//! expanded by it, checks that the player fits). Or, with a bot navigation
//! mesh ([`Floors::Nav`]), a column is walkable where an area of the mesh
//! lies over it with its floor within `band` of the level. The map's area is cut into
//! square slots of `tile` world units; a slot is open when most of its
//! sample columns are walkable. Walls, pits, other levels and everything
//! outside are blocked slots (zero flux), the grid's borders are walls.
//! Spawns and named entities become sources and sinks of a designed flow:
//! every open slot prefers the direction towards the nearest sink slot
//! (breadth-first distance over the open slots), which `tile` turns into
//! weights (see [`crate::prefer`]). A closed level has no inflow, so the
//! flow circulates; the preference decides which way.

use std::collections::VecDeque;
use std::fmt;

use bsp::Bsp;
use bsp::oracle::{Hull, Oracle, OracleOptions, PlayerHull};
use bsp::player::{ground_below, standing_origin_above_ground, top_floor};
use navmesh::NavMesh;

use crate::render::Canvas;
use crate::world::{View, draw_axes};

/// Errors while extracting a region.
#[derive(Debug)]
pub enum RegionError {
    /// Impossible options.
    Options(String),
    /// Nothing walkable at the level.
    Empty(String),
}

impl fmt::Display for RegionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RegionError::Options(why) => write!(f, "{why}"),
            RegionError::Empty(why) => write!(f, "no walkable floor: {why}"),
        }
    }
}

impl std::error::Error for RegionError {}

/// Options of [`extract`].
#[derive(Clone, Debug)]
pub struct RegionOptions {
    /// Floor height of the level (world z); `None`: the floor under the spawns.
    pub floor: Option<f64>,
    /// Slot side in world units.
    pub tile: f64,
    /// Floors within `band` of the level belong to it (ramps, stairs).
    pub band: f64,
    /// Share of walkable sample columns that opens a slot.
    pub open_share: f64,
    /// Class names whose entities are flow sources (the flow leaves them).
    pub sources: Vec<String>,
    /// Class names whose entities are flow sinks (the flow heads to them).
    pub sinks: Vec<String>,
    /// Strength of the designed direction.
    pub strength: f64,
}

impl Default for RegionOptions {
    fn default() -> Self {
        RegionOptions {
            floor: None,
            tile: 64.0,
            band: 48.0,
            open_share: 0.5,
            sources: Vec::new(),
            sinks: Vec::new(),
            strength: 4.0,
        }
    }
}

/// A walkable region at one level of a map, on a grid of slots.
#[derive(Clone, Debug)]
pub struct Region {
    /// World (x, y) of the grid's lower-left corner.
    pub origin: [f64; 2],
    /// Slot side in world units.
    pub tile: f64,
    /// Slots per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Open slots, row-major from the bottom row.
    pub open: Vec<bool>,
    /// Floor height of the level.
    pub floor: f64,
    /// Height band around the floor.
    pub band: f64,
    /// Sample columns per slot side.
    pub per_slot: u32,
    /// Ground height of every sample column: the floor within the band if
    /// there is one, else the highest floor of the column (NaN: none),
    /// row-major from the bottom, `width·per_slot` columns per row.
    pub ground: Vec<f32>,
    /// Source entity origins.
    pub sources: Vec<[f64; 3]>,
    /// Sink entity origins.
    pub sinks: Vec<[f64; 3]>,
    /// Preferred direction per slot (unit vector or zero), row-major.
    pub directions: Vec<[f64; 2]>,
    /// Strength of the preferred direction.
    pub strength: f64,
    /// Which map (file name) and game.
    pub source: String,
    /// Where the floors came from (for the spec's comment).
    pub floors_from: String,
}

/// Entity origins whose class name is one of `names`.
fn origins(bsp: &Bsp, names: &[String]) -> Vec<[f64; 3]> {
    bsp.entities
        .iter()
        .filter(|e| names.iter().any(|n| n == e.classname()))
        .filter_map(|e| e.origin())
        .map(|o| o.map(f64::from))
        .collect()
}

/// Where the walkable floor of a column comes from.
#[derive(Clone, Copy, Debug)]
pub enum Floors<'a> {
    /// The map's own collision: where a standing player fits.
    Hulls,
    /// The areas of a bot navigation mesh made for the map.
    Nav(&'a NavMesh),
}

/// The map's collision as [`extract`] uses it: the standing player's clip hull,
/// or (maps without clip hulls) the point hull to find floors and a check that
/// the player stands there.
struct Collision<'a> {
    hull: &'a Hull,
    /// Height of the player's origin above its feet (0 with the point hull).
    half: f64,
    stand: Stand<'a>,
}

/// How [`Collision`] checks that a standing player fits on a floor found.
enum Stand<'a> {
    /// The hull is the player's clip hull: every floor it finds fits.
    Hull,
    /// The oracle's player box (Quake 2: brushes expanded by the player's
    /// box, player clip included) at the floor.
    Box(&'a Oracle, f64),
    /// Nothing knows the player's width: free height above the floor.
    Headroom(f64),
}

impl Collision<'_> {
    /// The floor under column `(x, y)` below origin height `top`.
    fn ground_below(&self, x: f64, y: f64, top: f64, bottom: f64) -> Option<f64> {
        ground_below(self.hull, x, y, top, bottom, self.half)
    }

    /// Whether a player stands on floor `g` of column `(x, y)`.
    fn stands(&self, x: f64, y: f64, g: f64) -> bool {
        match self.stand {
            Stand::Hull => true,
            Stand::Box(oracle, origin_height) => {
                // Just above the floor: touching it is not meeting it.
                let p = [x, y, g + origin_height + 0.5];
                oracle
                    .player_contents(PlayerHull::Standing, p)
                    .is_some_and(|c| c != bsp::contents::SOLID)
            }
            Stand::Headroom(h) => self
                .hull
                .segment_clear([x, y, g + 1.0], [x, y, g + h], |c| {
                    c == bsp::contents::SOLID
                }),
        }
    }

    /// The floor of column `(x, y)` in `floor ± band` (the highest one, found from
    /// the top of the band or below a ceiling or wall there: a low passage counts).
    fn floor_in_band(&self, x: f64, y: f64, floor: f64, band: f64) -> Option<f64> {
        let top = floor + band + self.half;
        let bottom = floor - band + self.half - 1.0;
        let mut z = top;
        while z > bottom && self.hull.contents([x, y, z]) == bsp::contents::SOLID {
            z -= 8.0;
        }
        self.ground_below(x, y, z, bottom)
            .filter(|&g| self.stands(x, y, g))
    }

    /// The most common top floor height (16-unit bins) over a 64-unit grid.
    fn commonest_floor(&self, lo: [f64; 3], hi: [f64; 3]) -> Option<f64> {
        let mut bins = std::collections::BTreeMap::<i64, u32>::new();
        let mut y = lo[1] + 32.0;
        while y < hi[1] {
            let mut x = lo[0] + 32.0;
            while x < hi[0] {
                if let Some(g) = top_floor(self.hull, x, y, lo[2], hi[2], self.half) {
                    *bins.entry((g / 16.0).round() as i64).or_insert(0) += 1;
                }
                x += 64.0;
            }
            y += 64.0;
        }
        let best = bins.iter().max_by_key(|&(k, n)| (*n, -*k));
        best.map(|(k, _)| *k as f64 * 16.0)
    }
}

/// The areas of a nav mesh bucketed by slot, to find the areas over a column fast.
struct NavIndex<'a> {
    mesh: &'a NavMesh,
    origin: [f64; 2],
    tile: f64,
    width: u32,
    height: u32,
    /// Area indices per slot, row-major.
    buckets: Vec<Vec<u32>>,
}

impl<'a> NavIndex<'a> {
    fn new(mesh: &'a NavMesh, origin: [f64; 2], tile: f64, width: u32, height: u32) -> Self {
        let mut buckets = vec![Vec::new(); (width * height) as usize];
        let cell = |v: f32, o: f64, n: u32| {
            ((v as f64 - o) / tile).floor().clamp(0.0, n as f64 - 1.0) as u32
        };
        for (i, a) in mesh.areas.iter().enumerate() {
            let outside = (a.hi[0] as f64) < origin[0]
                || (a.hi[1] as f64) < origin[1]
                || a.lo[0] as f64 > origin[0] + width as f64 * tile
                || a.lo[1] as f64 > origin[1] + height as f64 * tile;
            if outside {
                continue;
            }
            let (x0, x1) = (
                cell(a.lo[0], origin[0], width),
                cell(a.hi[0], origin[0], width),
            );
            let (y0, y1) = (
                cell(a.lo[1], origin[1], height),
                cell(a.hi[1], origin[1], height),
            );
            for y in y0..=y1 {
                for x in x0..=x1 {
                    buckets[(y * width + x) as usize].push(i as u32);
                }
            }
        }
        NavIndex {
            mesh,
            origin,
            tile,
            width,
            height,
            buckets,
        }
    }

    /// The floor heights of the areas over `(x, y)`.
    fn floors(&self, x: f64, y: f64) -> impl Iterator<Item = f64> + '_ {
        let sx = ((x - self.origin[0]) / self.tile).floor();
        let sy = ((y - self.origin[1]) / self.tile).floor();
        let inside = sx >= 0.0 && sy >= 0.0 && sx < self.width as f64 && sy < self.height as f64;
        let bucket: &[u32] = if inside {
            &self.buckets[(sy as u32 * self.width + sx as u32) as usize]
        } else {
            &[]
        };
        let (xf, yf) = (x as f32, y as f32);
        bucket
            .iter()
            .map(|&i| &self.mesh.areas[i as usize])
            .filter(move |a| a.contains_xy(xf, yf))
            .map(move |a| a.z_at(xf, yf) as f64)
    }

    /// The area floor of column `(x, y)` nearest to `floor`, if within `band`.
    fn floor_in_band(&self, x: f64, y: f64, floor: f64, band: f64) -> Option<f64> {
        self.floors(x, y)
            .filter(|g| (g - floor).abs() <= band)
            .min_by(|a, b| (a - floor).abs().total_cmp(&(b - floor).abs()))
    }
}

/// Checks the options of [`extract`].
fn check_options(opt: &RegionOptions) -> Result<(), RegionError> {
    if !(opt.tile.is_finite() && (8.0..=4096.0).contains(&opt.tile)) {
        return Err(RegionError::Options(format!(
            "--tile {} must lie in 8..=4096 world units",
            opt.tile
        )));
    }
    if !(opt.band.is_finite() && (0.0..=4096.0).contains(&opt.band)) {
        return Err(RegionError::Options(format!(
            "--band {} must lie in 0..=4096",
            opt.band
        )));
    }
    match opt.floor {
        Some(z) if !z.is_finite() => {
            Err(RegionError::Options(format!("--floor {z} is not a number")))
        }
        _ => Ok(()),
    }
}

/// Extracts the walkable region at one level of `bsp` from the map's hulls
/// (see [`extract_with`]).
pub fn extract(bsp: &Bsp, source: &str, opt: &RegionOptions) -> Result<Region, RegionError> {
    extract_with(bsp, Floors::Hulls, source, opt)
}

/// Extracts the walkable region at one level of `bsp`, its floors from the
/// map's hulls or from a bot navigation mesh. The level is `opt.floor`, else
/// the median floor under the spawns (nav areas under them with a mesh),
/// else the map's commonest floor height.
///
/// ```no_run
/// use flowtile_bake::region::{Floors, RegionOptions, extract_with};
/// let bsp = bsp::Bsp::open("maps/de_dust2.bsp")?;
/// let nav = navmesh::NavMesh::open("maps/de_dust2.nav".as_ref())?;
/// let region = extract_with(&bsp, Floors::Nav(&nav), "de_dust2", &RegionOptions::default())?;
/// std::fs::write("dust2.toml", region.to_spec_toml(1))?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn extract_with(
    bsp: &Bsp,
    floors: Floors<'_>,
    source: &str,
    opt: &RegionOptions,
) -> Result<Region, RegionError> {
    check_options(opt)?;
    let oracle = Oracle::new(bsp, &OracleOptions::default());
    // Without clip hulls (maps compiled for tools, not the game) the point
    // hull stands in: origins at the feet, with a headroom check; the
    // player's width is then not accounted for.
    let point_hull;
    let hulls = match oracle.clip_hull(1) {
        Some(hull) => Collision {
            hull,
            half: standing_origin_above_ground(bsp.game),
            stand: Stand::Hull,
        },
        None => {
            point_hull = Hull::from_nodes(bsp, 0);
            // Quake 2 keeps no clip hulls: the common oracle's player box
            // (brushes expanded by it) says where a standing player fits.
            let probe = [0.0, 0.0, 1.0e5];
            let stand = if oracle
                .player_contents(PlayerHull::Standing, probe)
                .is_some()
            {
                Stand::Box(&oracle, standing_origin_above_ground(bsp.game))
            } else {
                Stand::Headroom(2.0 * standing_origin_above_ground(bsp.game))
            };
            Collision {
                hull: &point_hull,
                half: 0.0,
                stand,
            }
        }
    };
    let (mins, maxs) = bsp.bounds();
    let (lo, hi) = (mins.map(f64::from), maxs.map(f64::from));
    let per_slot = ((opt.tile / 8.0).round() as u32).clamp(2, 16);
    let step = opt.tile / per_slot as f64;
    let width = ((hi[0] - lo[0]) / opt.tile).ceil().max(1.0) as u32;
    let height = ((hi[1] - lo[1]) / opt.tile).ceil().max(1.0) as u32;
    if width as u64 * height as u64 > 1 << 22 {
        return Err(RegionError::Options(format!(
            "--tile {} gives {width}x{height} slots; choose a larger tile",
            opt.tile
        )));
    }
    let origin = [lo[0], lo[1]];
    let nav = match floors {
        Floors::Hulls => None,
        Floors::Nav(mesh) => Some(NavIndex::new(mesh, origin, opt.tile, width, height)),
    };
    let floor = match opt.floor {
        Some(z) => z,
        None => level_under_spawns(bsp, &hulls, nav.as_ref())
            .or_else(|| hulls.commonest_floor(lo, hi))
            .ok_or_else(|| RegionError::Empty("no floor anywhere in the map".into()))?,
    };
    let (cols, rows) = (width * per_slot, height * per_slot);
    let ground: Vec<f32> = (0..rows)
        .flat_map(|r| (0..cols).map(move |c| (r, c)))
        .map(|(r, c)| {
            let x = origin[0] + (c as f64 + 0.5) * step;
            let y = origin[1] + (r as f64 + 0.5) * step;
            let g = match &nav {
                Some(nav) => nav.floor_in_band(x, y, floor, opt.band),
                None => hulls.floor_in_band(x, y, floor, opt.band),
            };
            g.map_or(f32::NAN, |g| g as f32)
        })
        .collect();
    let walkable = |g: f32| g.is_finite() && (g as f64 - floor).abs() <= opt.band;
    // For the picture: the highest floor of each slot's centre column where
    // the slot has no floor at this level (one trace per slot, not per column).
    let background: Vec<f32> = (0..height)
        .flat_map(|sy| (0..width).map(move |sx| (sx, sy)))
        .map(|(sx, sy)| {
            let x = origin[0] + (sx as f64 + 0.5) * opt.tile;
            let y = origin[1] + (sy as f64 + 0.5) * opt.tile;
            top_floor(hulls.hull, x, y, lo[2], hi[2], hulls.half).map_or(f32::NAN, |g| g as f32)
        })
        .collect();
    let mut ground = ground;
    for (k, g) in ground.iter_mut().enumerate() {
        if g.is_nan() {
            let (c, r) = (k as u32 % cols, k as u32 / cols);
            *g = background[((r / per_slot) * width + c / per_slot) as usize];
        }
    }
    let need = (opt.open_share * (per_slot * per_slot) as f64).ceil() as u32;
    let open = open_slots(&ground, (width, height), per_slot, need, walkable);
    if !open.iter().any(|&o| o) {
        return Err(RegionError::Empty(format!(
            "no slot of {} units at floor {floor:.0} ± {}",
            opt.tile, opt.band
        )));
    }
    let mut region = Region {
        origin,
        tile: opt.tile,
        width,
        height,
        open,
        floor,
        band: opt.band,
        per_slot,
        ground,
        sources: origins(bsp, &opt.sources),
        sinks: origins(bsp, &opt.sinks),
        directions: Vec::new(),
        strength: opt.strength,
        source: source.to_string(),
        floors_from: floors_from(floors, &hulls.stand),
    };
    region.directions = region.sink_directions();
    Ok(region)
}

/// The open slots of a `width`×`height` grid: those with at least `need`
/// (and at least one) of their `per_slot`² sample columns `walkable`.
fn open_slots(
    ground: &[f32],
    (width, height): (u32, u32),
    per_slot: u32,
    need: u32,
    walkable: impl Fn(f32) -> bool,
) -> Vec<bool> {
    let cols = width * per_slot;
    let mut open = vec![false; (width * height) as usize];
    for sy in 0..height {
        for sx in 0..width {
            let mut n = 0;
            for j in 0..per_slot {
                for i in 0..per_slot {
                    let (c, r) = (sx * per_slot + i, sy * per_slot + j);
                    n += walkable(ground[(r * cols + c) as usize]) as u32;
                }
            }
            open[(sy * width + sx) as usize] = n >= need.max(1);
        }
    }
    open
}

/// Where the region's floors come from, in words (`Region::floors_from`).
fn floors_from(floors: Floors<'_>, stand: &Stand<'_>) -> String {
    match (floors, stand) {
        (Floors::Hulls, Stand::Hull) => {
            "the map's player clip hull (a standing player fits)".into()
        }
        (Floors::Hulls, Stand::Box(..)) => {
            "the map's brushes expanded by the player's box (a standing player fits)".into()
        }
        (Floors::Hulls, Stand::Headroom(h)) => {
            format!("the map's point hull with {h} units of headroom (no player hull in the map)")
        }
        (Floors::Nav(m), _) => format!(
            "the areas of a bot navigation mesh (v{}, {} areas)",
            m.version,
            m.areas.len()
        ),
    }
}

/// The median floor under the player spawns: the nav area under each spawn
/// (the highest at most a step above its feet) with a mesh, else the hull's
/// floor below it. `None` when no spawn stands over a floor.
fn level_under_spawns(bsp: &Bsp, hulls: &Collision<'_>, nav: Option<&NavIndex<'_>>) -> Option<f64> {
    let mut heights: Vec<f64> = bsp
        .spawns()
        .iter()
        .filter_map(|s| {
            let s = s.map(f64::from);
            let feet = hulls.ground_below(s[0], s[1], s[2] + 1.0, s[2] - 512.0);
            match nav {
                Some(nav) => {
                    let limit =
                        feet.unwrap_or(s[2] - standing_origin_above_ground(bsp.game)) + 18.0;
                    nav.floors(s[0], s[1])
                        .filter(|&g| g <= limit)
                        .max_by(f64::total_cmp)
                }
                None => feet,
            }
        })
        .collect();
    if heights.is_empty() {
        return None;
    }
    heights.sort_by(f64::total_cmp);
    Some(heights[heights.len() / 2])
}

impl Region {
    /// The slot containing world point `(x, y)`, if inside the grid.
    pub fn slot_of(&self, x: f64, y: f64) -> Option<(u32, u32)> {
        let sx = ((x - self.origin[0]) / self.tile).floor();
        let sy = ((y - self.origin[1]) / self.tile).floor();
        (sx >= 0.0 && sy >= 0.0 && sx < self.width as f64 && sy < self.height as f64)
            .then_some((sx as u32, sy as u32))
    }

    /// Number of open slots.
    pub fn open_slots(&self) -> usize {
        self.open.iter().filter(|&&o| o).count()
    }

    /// Per open slot, the unit direction towards the nearest sink slot
    /// (mean of the steps to neighbours closer to a sink), zero where no
    /// sink is reachable. Without sinks, the direction away from the
    /// nearest source.
    fn sink_directions(&self) -> Vec<[f64; 2]> {
        let (targets, sign) = if !self.sinks.is_empty() {
            (&self.sinks, 1.0)
        } else {
            (&self.sources, -1.0)
        };
        let (w, h) = (self.width as i64, self.height as i64);
        let idx = |x: i64, y: i64| (y * w + x) as usize;
        let mut dist = vec![u32::MAX; self.open.len()];
        let mut queue = VecDeque::new();
        for t in targets {
            if let Some((x, y)) = self.slot_of(t[0], t[1])
                && self.open[idx(x as i64, y as i64)]
                && dist[idx(x as i64, y as i64)] != 0
            {
                dist[idx(x as i64, y as i64)] = 0;
                queue.push_back((x as i64, y as i64));
            }
        }
        while let Some((x, y)) = queue.pop_front() {
            let d = dist[idx(x, y)];
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if (0..w).contains(&nx) && (0..h).contains(&ny) {
                    let k = idx(nx, ny);
                    if self.open[k] && dist[k] == u32::MAX {
                        dist[k] = d + 1;
                        queue.push_back((nx, ny));
                    }
                }
            }
        }
        let mut out = vec![[0.0; 2]; self.open.len()];
        for y in 0..h {
            for x in 0..w {
                let d = dist[idx(x, y)];
                if d == u32::MAX || d == 0 {
                    continue;
                }
                let mut v = [0.0, 0.0];
                for (dx, dy) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1)] {
                    let (nx, ny) = (x + dx, y + dy);
                    if (0..w).contains(&nx) && (0..h).contains(&ny) && dist[idx(nx, ny)] < d {
                        v[0] += dx as f64;
                        v[1] += dy as f64;
                    }
                }
                let len = v[0].hypot(v[1]);
                if len > 0.0 {
                    out[idx(x, y)] = [sign * v[0] / len, sign * v[1] / len];
                }
            }
        }
        out
    }

    /// The tiling spec: mask (top row first), zero borders, the (5,5,5) tile
    /// set, and the designed directions as one-row regions (runs of equal
    /// direction merged), with the world placement in comments.
    pub fn to_spec_toml(&self, seed: u64) -> String {
        let mut s = String::new();
        s += &format!(
            "# Walkable region of {} at floor z = {:.1} (± {}), from\n\
             # {}; written by flowtile-bake region.\n\
             # World placement: slot (x, y) covers world x {:.1} + {} x .. + {}, y {:.1} + {} y .. + {}.\n\
             # {} of {} slots open; {} sources, {} sinks.\n",
            self.source,
            self.floor,
            self.band,
            self.floors_from,
            self.origin[0],
            self.tile,
            self.tile,
            self.origin[1],
            self.tile,
            self.tile,
            self.open_slots(),
            self.open.len(),
            self.sources.len(),
            self.sinks.len()
        );
        s += &format!(
            "description = \"walkable floor of {} at z {:.0}\"\nseed = {seed}\n\n",
            self.source.replace(['"', '\\'], "_"),
            self.floor
        );
        s += "[tileset]\nmx = 5\nmy = 5\ncorners = 5\nf_base = 1.0\nn = 8\n\n";
        s += &format!(
            "[grid]\nwidth = {}\nheight = {}\nborder_x = \"zero\"\nborder_y = \"zero\"\nmask = \"\"\"\n",
            self.width, self.height
        );
        for y in (0..self.height).rev() {
            for x in 0..self.width {
                s.push(if self.open[(y * self.width + x) as usize] {
                    '.'
                } else {
                    '#'
                });
            }
            s.push('\n');
        }
        s += "\"\"\"\n\n[prefer]\nreuse = 4.0\n";
        for y in 0..self.height {
            let mut x = 0;
            while x < self.width {
                let d = self.directions[(y * self.width + x) as usize];
                let start = x;
                while x < self.width && self.directions[(y * self.width + x) as usize] == d {
                    x += 1;
                }
                if d != [0.0, 0.0] {
                    s += &format!(
                        "\n[[prefer.direction]]\nx = [{start}, {}]\ny = {y}\ndirection = [{:.4}, {:.4}]\nstrength = {}\n",
                        x - 1,
                        d[0],
                        d[1],
                        self.strength
                    );
                }
            }
        }
        s
    }

    /// The grid as two world triangles with flow coordinates (slot units),
    /// to place a tiling of the region's spec back onto the map.
    pub fn mesh(&self) -> crate::world::Mesh {
        let (lo, hi) = self.bounds();
        let (w, h) = (self.width as f64, self.height as f64);
        crate::world::Mesh {
            world: vec![lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]],
            flow: vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        }
    }

    /// World box of the grid.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let lo = self.origin;
        (
            lo,
            [
                lo[0] + self.width as f64 * self.tile,
                lo[1] + self.height as f64 * self.tile,
            ],
        )
    }

    /// Draws the map's top view into the plot of `view`: the level's floor
    /// in grey (darker lower), other levels light, no floor dark, sources
    /// red and sinks green.
    pub fn draw_top_view(&self, c: &mut Canvas, view: &View) {
        let lo = self.origin;
        let step = self.tile / self.per_slot as f64;
        let cols = self.width * self.per_slot;
        for (k, &g) in self.ground.iter().enumerate() {
            let (col, row) = (k as u32 % cols, k as u32 / cols);
            let p0 = view.px([lo[0] + col as f64 * step, lo[1] + (row + 1) as f64 * step]);
            let p1 = view.px([lo[0] + (col + 1) as f64 * step, lo[1] + row as f64 * step]);
            let shade = if !g.is_finite() {
                [0.18, 0.18, 0.2]
            } else if (g as f64 - self.floor).abs() <= self.band {
                let t = ((g as f64 - self.floor) / self.band.max(1.0) * 0.15 + 0.6) as f32;
                [t, t, t * 0.97]
            } else {
                [0.86, 0.84, 0.80]
            };
            c.fill_rect(
                p0[0],
                p0[1],
                p1[0].max(p0[0] + 1.0),
                p1[1].max(p0[1] + 1.0),
                shade,
                1.0,
            );
        }
        for (list, col) in [
            (&self.sources, [0.85, 0.2, 0.1]),
            (&self.sinks, [0.1, 0.6, 0.2]),
        ] {
            for p in list.iter() {
                let q = view.px([p[0], p[1]]);
                c.fill_rect(q[0] - 3.0, q[1] - 3.0, q[0] + 4.0, q[1] + 4.0, col, 1.0);
            }
        }
    }

    /// The map's top view over exactly the grid (no axes): `scale` pixels
    /// per sample column, rows top first. The editor shows it under the
    /// grid (`background` in the spec `region` writes).
    pub fn top_view_image(&self, scale: u32) -> Result<Canvas, crate::world::WorldError> {
        let scale = scale.clamp(1, 16);
        let (w, h) = (
            self.width * self.per_slot * scale,
            self.height * self.per_slot * scale,
        );
        if w as u64 * h as u64 > 1 << 26 {
            return Err(crate::world::WorldError::Options(format!(
                "top view of {w}x{h} pixels is too large"
            )));
        }
        let mut c = Canvas::new(w, h, [1.0, 1.0, 1.0]);
        let (lo, hi) = self.bounds();
        let view = View {
            lo,
            hi,
            scale: w as f64 / (hi[0] - lo[0]),
            left: 0.0,
            top: 0.0,
        };
        self.draw_top_view(&mut c, &view);
        Ok(c)
    }

    /// A top view: ground heights of the level in grey (other levels
    /// lighter, no floor dark), open slots tinted blue with their designed
    /// directions, sources and sinks marked, axes in world units, legend.
    pub fn picture(&self, width: u32) -> Result<Canvas, crate::world::WorldError> {
        let (lo, hi) = self.bounds();
        let view = View::new(lo, hi, width)?;
        let title = format!(
            "{}: floor z {:.0} +- {:.0}, {} slots of {:.0} units",
            self.source,
            self.floor,
            self.band,
            self.open_slots(),
            self.tile
        );
        let (cw, ch) = picture_size(&view, &title);
        let mut c = Canvas::new(cw, ch, [1.0, 1.0, 1.0]);
        self.draw_top_view(&mut c, &view);
        for y in 0..self.height {
            for x in 0..self.width {
                let i = (y * self.width + x) as usize;
                if !self.open[i] {
                    continue;
                }
                let a = view.px([
                    lo[0] + x as f64 * self.tile,
                    lo[1] + (y + 1) as f64 * self.tile,
                ]);
                let b = view.px([
                    lo[0] + (x + 1) as f64 * self.tile,
                    lo[1] + y as f64 * self.tile,
                ]);
                c.fill_rect(a[0], a[1], b[0], b[1], [0.25, 0.5, 0.95], 0.35);
                let d = self.directions[i];
                if d != [0.0, 0.0] {
                    let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
                    let r = (b[0] - a[0]) * 0.35;
                    let (ex, ey) = (m[0] + d[0] * r, m[1] - d[1] * r);
                    c.line(
                        m[0] - d[0] * r,
                        m[1] + d[1] * r,
                        ex,
                        ey,
                        [0.05, 0.15, 0.5],
                        0.9,
                    );
                    c.fill_rect(
                        ex - 1.0,
                        ey - 1.0,
                        ex + 2.0,
                        ey + 2.0,
                        [0.05, 0.15, 0.5],
                        1.0,
                    );
                }
            }
        }
        draw_axes(&mut c, &view, &title, None, "units");
        let [lx, mut ly, _, _] = legend_box(&view);
        for (col, label) in LEGEND {
            c.fill_rect(lx, ly, lx + 10.0, ly + 10.0, col, 1.0);
            c.text(lx + 14.0, ly + 1.0, label, [0.15, 0.15, 0.18]);
            ly += 16.0;
        }
        for (k, line) in LEGEND_ARROW.iter().enumerate() {
            c.text(lx, ly + 4.0 + 10.0 * k as f64, line, [0.15, 0.15, 0.18]);
        }
        Ok(c)
    }
}

/// The region picture's legend: colour and label per row.
const LEGEND: [([f32; 3], &str); 6] = [
    ([0.6, 0.6, 0.58], "floor"),
    ([0.86, 0.84, 0.80], "other lvl"),
    ([0.18, 0.18, 0.2], "no floor"),
    ([0.45, 0.6, 0.9], "open slot"),
    ([0.85, 0.2, 0.1], "source"),
    ([0.1, 0.6, 0.2], "sink"),
];
/// The legend's last rows: what the arrows are.
const LEGEND_ARROW: [&str; 3] = ["arrow:", "designed", "direction"];

/// The legend's box `[left, top, right, bottom]` in pixels: right of the plot, from its
/// top.
fn legend_box(view: &View) -> [f64; 4] {
    let [pw, _] = view.plot_size();
    let (l, t) = (view.left + pw + 8.0, view.top);
    let widest = LEGEND
        .iter()
        .map(|(_, label)| 14 + 8 * label.len())
        .chain(LEGEND_ARROW.iter().map(|line| 8 * line.len()))
        .max()
        .unwrap_or(0) as f64;
    let rows = 16.0 * LEGEND.len() as f64 + 4.0 + 10.0 * LEGEND_ARROW.len() as f64;
    [l, t, l + widest, t + rows]
}

/// The picture's size: the view's, grown to hold the legend (a wide, flat region's plot
/// is lower than the legend) and the title (8 pixels a character, from 40 pixels right
/// of the plot's left edge).
fn picture_size(view: &View, title: &str) -> (u32, u32) {
    let (w, h) = view.canvas_size();
    let [_, _, right, bottom] = legend_box(view);
    let title_right = view.left + 40.0 + 8.0 * title.len() as f64;
    let w = (w as f64).max(right + 8.0).max(title_right + 8.0);
    let h = (h as f64).max(bottom + 8.0);
    (w.ceil() as u32, h.ceil() as u32)
}

/// Sources and sinks that the open slots do not connect (4-neighbour steps): the flow
/// from such a source reaches no sink, and its slots get no designed direction.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Unconnected {
    /// Sources from which no sink can be reached (or on no open slot).
    pub sources: Vec<[f64; 3]>,
    /// Sinks that no source reaches (or on no open slot).
    pub sinks: Vec<[f64; 3]>,
}

impl Unconnected {
    pub fn is_empty(&self) -> bool {
        self.sources.is_empty() && self.sinks.is_empty()
    }
}

impl Region {
    /// The open slots' connected parts: a part number per slot (`u32::MAX` for closed).
    fn parts(&self) -> Vec<u32> {
        let (w, h) = (self.width as i64, self.height as i64);
        let mut part = vec![u32::MAX; self.open.len()];
        let mut next = 0;
        for start in 0..self.open.len() {
            if !self.open[start] || part[start] != u32::MAX {
                continue;
            }
            part[start] = next;
            let mut stack = vec![start];
            while let Some(k) = stack.pop() {
                let (x, y) = (k as i64 % w, k as i64 / w);
                for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                    let (nx, ny) = (x + dx, y + dy);
                    if (0..w).contains(&nx) && (0..h).contains(&ny) {
                        let n = (ny * w + nx) as usize;
                        if self.open[n] && part[n] == u32::MAX {
                            part[n] = next;
                            stack.push(n);
                        }
                    }
                }
            }
            next += 1;
        }
        part
    }

    /// The sources and sinks the open slots do not connect (see [`Unconnected`]); empty
    /// when the region has no sources or no sinks (the flow then follows the ones it has).
    pub fn unconnected(&self) -> Unconnected {
        if self.sources.is_empty() || self.sinks.is_empty() {
            return Unconnected::default();
        }
        let part = self.parts();
        let part_of = |p: &[f64; 3]| {
            self.slot_of(p[0], p[1])
                .map(|(x, y)| part[(y * self.width + x) as usize])
                .filter(|&k| k != u32::MAX)
        };
        let sink_parts: Vec<u32> = self.sinks.iter().filter_map(part_of).collect();
        let source_parts: Vec<u32> = self.sources.iter().filter_map(part_of).collect();
        let cut = |points: &[[f64; 3]], others: &[u32]| {
            points
                .iter()
                .filter(|p| part_of(p).is_none_or(|k| !others.contains(&k)))
                .copied()
                .collect()
        };
        Unconnected {
            sources: cut(&self.sources, &sink_parts),
            sinks: cut(&self.sinks, &source_parts),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A region by hand: `rows` of `#` (open) and `.` (closed), top row first, slots
    /// of 64 units from the origin.
    fn region(rows: &[&str], sources: Vec<[f64; 3]>, sinks: Vec<[f64; 3]>) -> Region {
        let (width, height) = (rows[0].len() as u32, rows.len() as u32);
        let open: Vec<bool> = rows
            .iter()
            .rev()
            .flat_map(|r| r.chars().map(|c| c == '#'))
            .collect();
        let per_slot = 2;
        let ground = vec![0.0f32; (width * height * per_slot * per_slot) as usize];
        let mut r = Region {
            origin: [0.0, 0.0],
            tile: 64.0,
            width,
            height,
            open,
            floor: 0.0,
            band: 48.0,
            per_slot,
            ground,
            sources,
            sinks,
            directions: Vec::new(),
            strength: 4.0,
            source: "generated.bsp".into(),
            floors_from: "hand".into(),
        };
        r.directions = r.sink_directions();
        r
    }

    #[test]
    fn sources_and_sinks_in_separate_parts_are_unconnected() {
        // Two parts: slots 0–1 and 3–5 of one row; a source in each, a sink in the second.
        let r = region(
            &["##.###"],
            vec![[32.0, 32.0, 0.0], [224.0, 32.0, 0.0]],
            vec![[352.0, 32.0, 0.0]],
        );
        let u = r.unconnected();
        assert_eq!(u.sources, vec![[32.0, 32.0, 0.0]]);
        assert!(u.sinks.is_empty());
        // Joined, every source reaches the sink.
        let joined = region(&["######"], r.sources.clone(), r.sinks.clone());
        assert!(joined.unconnected().is_empty());
        // A sink that no source reaches.
        let lone = region(
            &["##.###"],
            vec![[32.0, 32.0, 0.0]],
            vec![[352.0, 32.0, 0.0]],
        );
        assert_eq!(lone.unconnected().sinks, vec![[352.0, 32.0, 0.0]]);
    }

    /// The legend lies inside the picture and off the plot, also for a region much wider
    /// than high (whose plot is lower than the legend is long), and the title fits.
    #[test]
    fn the_region_legend_is_inside_the_picture_and_off_the_plot() {
        for rows in [vec!["#".repeat(40)], vec!["######".to_string(); 20]] {
            let rows: Vec<&str> = rows.iter().map(|s| s.as_ref()).collect();
            let r = region(&rows, vec![], vec![]);
            for width in [200, 800] {
                let c = r.picture(width).unwrap();
                let (lo, hi) = r.bounds();
                let view = View::new(lo, hi, width).unwrap();
                let [l, t, rt, b] = legend_box(&view);
                assert!(
                    l >= 0.0 && t >= 0.0 && rt <= c.width() as f64 && b <= c.height() as f64,
                    "legend {:?} outside the {}x{} picture",
                    [l, t, rt, b],
                    c.width(),
                    c.height()
                );
                let [pw, ph] = view.plot_size();
                let plot = [view.left, view.top, view.left + pw, view.top + ph];
                assert!(
                    l >= plot[2] || rt <= plot[0] || t >= plot[3] || b <= plot[1],
                    "legend {:?} covers the plot {plot:?}",
                    [l, t, rt, b]
                );
            }
        }
    }

    /// The nav mesh's floors against the map's own hulls (the ground truth of
    /// where a player stands) on the shared Counter-Strike maps: most slots
    /// agree (an intersection over union above 0.8).
    #[test]
    fn nav_floors_agree_with_the_hulls_when_present() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../shared/testmaps/goldsrc/nonfree");
        let nav = dir.join("bspview-cstrike-de_dust2.nav");
        if !nav.is_file() {
            toolbox::errln!("skipped: {} absent", nav.display());
            return;
        }
        let bsp = Bsp::open(nav.with_extension("bsp")).unwrap();
        let mesh = NavMesh::open(&nav).unwrap();
        let opt = RegionOptions::default();
        let a = extract(&bsp, "de_dust2", &opt).unwrap();
        let b = extract_with(&bsp, Floors::Nav(&mesh), "de_dust2", &opt).unwrap();
        assert_eq!((a.width, a.height), (b.width, b.height));
        assert!((a.floor - b.floor).abs() <= 16.0, "{} {}", a.floor, b.floor);
        let both = a
            .open
            .iter()
            .zip(&b.open)
            .filter(|(x, y)| **x && **y)
            .count();
        let any = a
            .open
            .iter()
            .zip(&b.open)
            .filter(|(x, y)| **x || **y)
            .count();
        let iou = both as f64 / any as f64;
        toolbox::errln!(
            "de_dust2: hulls {} slots, nav {} slots, IoU {iou:.3}",
            a.open_slots(),
            b.open_slots()
        );
        assert!(b.open_slots() > 300 && iou > 0.8, "IoU {iou}");
        assert!(
            b.to_spec_toml(1)
                .contains("bot navigation mesh (v5, 718 areas)")
        );
    }

    /// Quake 2 keeps no clip hulls: the oracle builds the player's hull 1 from
    /// the brushes, and the region's floors come from it. The point hull with
    /// the oracle's player box is checked too: on every floor it finds the
    /// player's box is free and rests on something solid, and the box rejects
    /// columns the point hull alone would take (those hugging walls).
    #[test]
    fn quake2_floors_fit_the_players_box_when_present() {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../shared/testmaps/quake2/lq_e0m1-quake2.bsp");
        if !map.is_file() {
            toolbox::errln!("skipped: {} absent", map.display());
            return;
        }
        let bsp = Bsp::open(&map).unwrap();
        let region = extract(&bsp, "lq_e0m1-quake2", &RegionOptions::default()).unwrap();
        assert!(
            region.floors_from.contains("player clip hull"),
            "{}",
            region.floors_from
        );
        assert!(region.open_slots() > 300, "{}", region.open_slots());
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let hull = Hull::from_nodes(&bsp, 0);
        let boxed = Collision {
            hull: &hull,
            half: 0.0,
            stand: Stand::Box(&oracle, 24.0),
        };
        let point = Collision {
            hull: &hull,
            half: 0.0,
            stand: Stand::Hull,
        };
        let (mut found, mut only_point) = (0, 0);
        for r in (0..region.height * 8).step_by(3) {
            for c in (0..region.width * 8).step_by(3) {
                let (x, y) = (
                    region.origin[0] + c as f64 * 8.0,
                    region.origin[1] + r as f64 * 8.0,
                );
                let Some(g) = boxed.floor_in_band(x, y, region.floor, region.band) else {
                    only_point += point
                        .floor_in_band(x, y, region.floor, region.band)
                        .is_some() as u32;
                    continue;
                };
                let stand =
                    |dz: f64| oracle.player_contents(PlayerHull::Standing, [x, y, g + 24.0 + dz]);
                assert_ne!(stand(0.5), Some(bsp::contents::SOLID), "({x}, {y}, {g})");
                assert_eq!(
                    stand(-2.0),
                    Some(bsp::contents::SOLID),
                    "({x}, {y}, {g}) floats"
                );
                found += 1;
            }
        }
        toolbox::errln!(
            "lq_e0m1-quake2: {found} columns stand, {only_point} only for the point hull"
        );
        assert!(found > 1000 && only_point > 50, "{found} {only_point}");
    }

    #[test]
    fn bad_options_are_errors() {
        for opt in [
            RegionOptions {
                tile: 2.0,
                ..Default::default()
            },
            RegionOptions {
                band: f64::NAN,
                ..Default::default()
            },
            RegionOptions {
                floor: Some(f64::INFINITY),
                ..Default::default()
            },
        ] {
            assert!(matches!(check_options(&opt), Err(RegionError::Options(_))));
        }
        assert!(check_options(&RegionOptions::default()).is_ok());
    }
}
