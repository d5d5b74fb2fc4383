//! Regions from a level (issue 17, part 1): the walkable floor of a map at one
//! level, read through the `bsp` crate, turned into a tiling spec.
//!
//! A column of the map is walkable at the level when a standing player fits
//! there: a downward trace through the player's clip hull (hull 1: the
//! standing player of GoldSrc and Quake) from above the level finds a floor
//! whose height lies within `band` of the level. The map's area is cut into
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
use bsp::oracle::{Hull, Oracle, OracleOptions};

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
}

/// Half height of the standing player's box below its origin (hull 1).
fn player_half_height(bsp: &Bsp) -> f64 {
    match bsp.version.game() {
        bsp::Game::GoldSrc => 36.0,
        // Quake 2: the player box is -24..32 about the origin.
        bsp::Game::Quake | bsp::Game::Quake2 => 24.0,
    }
}

/// The ground height under column `(x, y)` found by a downward trace through
/// the clip hull from origin height `top` to `bottom`: the z of the first
/// solid leaf minus the player's half height, or `None` when the column is
/// solid at `top` or has no floor above `bottom`.
fn ground_below(hull: &Hull, x: f64, y: f64, top: f64, bottom: f64, half: f64) -> Option<f64> {
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
        if c == bsp::contents::SOLID {
            hit = Some(t0);
        }
    });
    let (_, c0) = first?;
    if c0 == bsp::contents::SOLID {
        return None;
    }
    let t = hit?;
    Some(top + t * (bottom - top) - half)
}

/// The highest floor of column `(x, y)` between `lo_z` and `hi_z`.
fn top_floor(hull: &Hull, x: f64, y: f64, lo_z: f64, hi_z: f64, half: f64) -> Option<f64> {
    let mut z = hi_z + half;
    while z > lo_z && hull.contents([x, y, z]) == bsp::contents::SOLID {
        z -= 64.0;
    }
    ground_below(hull, x, y, z, lo_z - half, half)
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

/// Extracts the walkable region at one level of `bsp`.
pub fn extract(bsp: &Bsp, source: &str, opt: &RegionOptions) -> Result<Region, RegionError> {
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
    let oracle = Oracle::new(bsp, &OracleOptions::default());
    // Without clip hulls (maps compiled for tools, not the game) the point
    // hull stands in: origins at the feet, with a headroom check; the
    // player's width is then not accounted for.
    let point_hull;
    let (hull, half, headroom) = match oracle.clip_hull(1) {
        Some(h) => (h, player_half_height(bsp), 0.0),
        None => {
            point_hull = Hull::from_nodes(bsp, 0);
            (&point_hull, 0.0, 2.0 * player_half_height(bsp))
        }
    };
    let stands = |x: f64, y: f64, g: f64| {
        headroom == 0.0
            || hull.segment_clear([x, y, g + 1.0], [x, y, g + headroom], |c| {
                c == bsp::contents::SOLID
            })
    };
    let (mins, maxs) = bsp.bounds();
    let (lo, hi) = (mins.map(f64::from), maxs.map(f64::from));
    // The level: given, or the floor under the spawns (median).
    let floor = match opt.floor {
        Some(z) if z.is_finite() => z,
        Some(z) => return Err(RegionError::Options(format!("--floor {z} is not a number"))),
        None => {
            let mut heights: Vec<f64> = bsp
                .spawns()
                .iter()
                .filter_map(|s| {
                    let s = s.map(f64::from);
                    ground_below(hull, s[0], s[1], s[2] + 1.0, s[2] - 512.0, half)
                })
                .collect();
            if heights.is_empty() {
                // No spawn over a floor: the most common top floor height
                // (16-unit bins) over a 64-unit grid.
                let mut bins = std::collections::BTreeMap::<i64, u32>::new();
                let mut y = lo[1] + 32.0;
                while y < hi[1] {
                    let mut x = lo[0] + 32.0;
                    while x < hi[0] {
                        if let Some(g) = top_floor(hull, x, y, lo[2], hi[2], half) {
                            *bins.entry((g / 16.0).round() as i64).or_insert(0) += 1;
                        }
                        x += 64.0;
                    }
                    y += 64.0;
                }
                let best = bins.iter().max_by_key(|&(k, n)| (*n, -*k)).map(|(k, _)| *k);
                heights.push(
                    best.ok_or_else(|| RegionError::Empty("no floor anywhere in the map".into()))?
                        as f64
                        * 16.0,
                );
            }
            heights.sort_by(f64::total_cmp);
            heights[heights.len() / 2]
        }
    };
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
    let (cols, rows) = (width * per_slot, height * per_slot);
    let top = floor + opt.band + half;
    let bottom = floor - opt.band + half - 1.0;
    let ground: Vec<f32> = (0..rows)
        .flat_map(|r| (0..cols).map(move |c| (r, c)))
        .map(|(r, c)| {
            let x = origin[0] + (c as f64 + 0.5) * step;
            let y = origin[1] + (r as f64 + 0.5) * step;
            // Start at the top of the band, or lower if a ceiling or a wall
            // is there (a low passage still counts).
            let mut z = top;
            while z > bottom && hull.contents([x, y, z]) == bsp::contents::SOLID {
                z -= 8.0;
            }
            match ground_below(hull, x, y, z, bottom, half) {
                Some(g) if stands(x, y, g) => g as f32,
                _ => f32::NAN,
            }
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
            top_floor(hull, x, y, lo[2], hi[2], half).map_or(f32::NAN, |g| g as f32)
        })
        .collect();
    let mut ground = ground;
    for (k, g) in ground.iter_mut().enumerate() {
        if g.is_nan() {
            let (c, r) = (k as u32 % cols, k as u32 / cols);
            *g = background[((r / per_slot) * width + c / per_slot) as usize];
        }
    }
    let mut open = vec![false; (width * height) as usize];
    let need = (opt.open_share * (per_slot * per_slot) as f64).ceil() as u32;
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
    };
    region.directions = region.sink_directions();
    Ok(region)
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
            "# Walkable region of {} at floor z = {:.1} (± {}), from the map's\n\
             # player clip hull (a standing player fits); written by flowtile-bake region.\n\
             # World placement: slot (x, y) covers world x {:.1} + {} x .. + {}, y {:.1} + {} y .. + {}.\n\
             # {} of {} slots open; {} sources, {} sinks.\n",
            self.source,
            self.floor,
            self.band,
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
        let (cw, ch) = view.canvas_size();
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
        draw_axes(
            &mut c,
            &view,
            &format!(
                "{}: floor z {:.0} +- {:.0}, {} slots of {:.0} units",
                self.source,
                self.floor,
                self.band,
                self.open_slots(),
                self.tile
            ),
            None,
            "units",
        );
        let [pw, _] = view.plot_size();
        let (lx, mut ly) = (view.left + pw + 8.0, view.top);
        for (col, label) in [
            ([0.6f32, 0.6, 0.58], "floor"),
            ([0.86, 0.84, 0.80], "other lvl"),
            ([0.18, 0.18, 0.2], "no floor"),
            ([0.45, 0.6, 0.9], "open slot"),
            ([0.85, 0.2, 0.1], "source"),
            ([0.1, 0.6, 0.2], "sink"),
        ] {
            c.fill_rect(lx, ly, lx + 10.0, ly + 10.0, col, 1.0);
            c.text(lx + 14.0, ly + 1.0, label, [0.15, 0.15, 0.18]);
            ly += 16.0;
        }
        c.text(lx, ly + 4.0, "arrow:", [0.15, 0.15, 0.18]);
        c.text(lx, ly + 14.0, "designed", [0.15, 0.15, 0.18]);
        c.text(lx, ly + 24.0, "direction", [0.15, 0.15, 0.18]);
        Ok(c)
    }
}
