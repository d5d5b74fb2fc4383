//! World space and time: a tiling placed onto world triangles through flow
//! coordinates (paper §5), a time-varying flow blended from key tilings, a
//! velocity lookup in world coordinates, a sampler grid for engines, and
//! pictures — streamlines or particle trails over the
//! level's top view, and an animated GIF of advected particles.
//!
//! The mesh is a Wavefront OBJ: `v x y z` world positions (the top view uses
//! x and y; z is ignored), `vt u v` flow coordinates in tile lengths, and
//! faces `f a/ta b/tb c/tc …` (polygons are split into fans). The world
//! velocity inside a triangle is the flow velocity pushed through the
//! triangle's constant Jacobian, so a divergence-free tiling stays
//! divergence-free under any affine piece (up to the area ratio) and the
//! field is continuous where neighbouring triangles agree on their shared
//! vertices' flow coordinates.

use std::fmt;
use std::io::Write;

use crate::bake::BakedTiling;
use crate::render::{Canvas, MAX_PX, ramp};
use crate::rng::Rng;
use crate::runtime::{FlowMap, KeyBlend, MapError};

/// Errors of the world-space tools.
#[derive(Debug)]
pub enum WorldError {
    /// The OBJ text is malformed (line number and reason).
    Obj(usize, String),
    /// The mesh or keys cannot be used.
    Map(MapError),
    /// Bad options (sizes, counts, periods).
    Options(String),
    /// Encoding a picture failed.
    Encode(String),
}

impl fmt::Display for WorldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WorldError::Obj(line, why) => write!(f, "OBJ line {line}: {why}"),
            WorldError::Map(e) => write!(f, "{e}"),
            WorldError::Options(why) => write!(f, "{why}"),
            WorldError::Encode(why) => write!(f, "encoding failed: {why}"),
        }
    }
}

impl std::error::Error for WorldError {}

impl From<MapError> for WorldError {
    fn from(e: MapError) -> Self {
        WorldError::Map(e)
    }
}

/// Triangles with world positions (top view) and flow coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// World position of each corner (x, y).
    pub world: Vec<[f64; 2]>,
    /// Flow coordinates of each corner (tile lengths).
    pub flow: Vec<[f64; 2]>,
    /// Corner indices of each triangle.
    pub triangles: Vec<[u32; 3]>,
}

/// Largest number of OBJ elements of each kind accepted.
const MAX_ELEMENTS: usize = 1 << 22;

impl Mesh {
    /// Parses an OBJ: `v`, `vt` and `f` lines (with `v/vt` or `v/vt/vn`
    /// references, 1-based or negative); other lines are ignored. Each face
    /// corner becomes a mesh corner with its own flow coordinate, so a vertex
    /// may carry different flow coordinates in different faces (a seam).
    ///
    /// ```
    /// use flowtile_bake::world::Mesh;
    /// let m = Mesh::from_obj("v 0 0 0\nv 2 0 0\nv 0 2 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n").unwrap();
    /// assert_eq!(m.triangles.len(), 1);
    /// assert_eq!(m.flow[1], [1.0, 0.0]);
    /// ```
    pub fn from_obj(text: &str) -> Result<Mesh, WorldError> {
        let (mut pos, mut tex) = (Vec::new(), Vec::new());
        let mut mesh = Mesh {
            world: Vec::new(),
            flow: Vec::new(),
            triangles: Vec::new(),
        };
        for (i, line) in text.lines().enumerate() {
            let ln = i + 1;
            let mut it = line.split_whitespace();
            let Some(kind) = it.next() else { continue };
            let nums =
                |it: std::str::SplitWhitespace, want: usize| -> Result<Vec<f64>, WorldError> {
                    let v: Vec<f64> = it
                        .take(want)
                        .map(|s| s.parse::<f64>())
                        .collect::<Result<_, _>>()
                        .map_err(|e| WorldError::Obj(ln, format!("bad number: {e}")))?;
                    if v.len() < want || v.iter().any(|x| !x.is_finite()) {
                        return Err(WorldError::Obj(
                            ln,
                            format!("{kind} needs {want} finite numbers"),
                        ));
                    }
                    Ok(v)
                };
            match kind {
                "v" => {
                    let v = nums(it, 2)?;
                    pos.push([v[0], v[1]]);
                }
                "vt" => {
                    let v = nums(it, 2)?;
                    tex.push([v[0], v[1]]);
                }
                "f" => {
                    let mut corners = Vec::new();
                    for r in it {
                        let mut parts = r.split('/');
                        let resolve = |s: Option<&str>, len: usize, what: &str| {
                            let s = s.filter(|s| !s.is_empty()).ok_or_else(|| {
                                WorldError::Obj(
                                    ln,
                                    format!("face corner {r:?} lacks a {what} index"),
                                )
                            })?;
                            let k: i64 = s
                                .parse()
                                .map_err(|_| WorldError::Obj(ln, format!("bad index {s:?}")))?;
                            let idx = if k > 0 { k - 1 } else { len as i64 + k };
                            if k == 0 || idx < 0 || idx >= len as i64 {
                                return Err(WorldError::Obj(
                                    ln,
                                    format!("{what} index {k} out of range (1..={len})"),
                                ));
                            }
                            Ok(idx as usize)
                        };
                        let p = resolve(parts.next(), pos.len(), "vertex")?;
                        let t = resolve(parts.next(), tex.len(), "texture (flow coordinate)")?;
                        corners.push((p, t));
                    }
                    if corners.len() < 3 {
                        return Err(WorldError::Obj(
                            ln,
                            "a face needs at least 3 corners".into(),
                        ));
                    }
                    let base = mesh.world.len() as u32;
                    for &(p, t) in &corners {
                        mesh.world.push(pos[p]);
                        mesh.flow.push(tex[t]);
                    }
                    for k in 1..corners.len() as u32 - 1 {
                        mesh.triangles.push([base, base + k, base + k + 1]);
                    }
                }
                _ => {}
            }
            if pos.len().max(tex.len()).max(mesh.world.len()) > MAX_ELEMENTS {
                return Err(WorldError::Obj(ln, "mesh too large".into()));
            }
        }
        if mesh.triangles.is_empty() {
            return Err(WorldError::Obj(0, "no faces".into()));
        }
        Ok(mesh)
    }
}

/// A flow in flow space: one baked tiling, or key tilings blended in time.
#[derive(Clone, Debug)]
pub enum Flow {
    /// A steady flow.
    Steady(BakedTiling),
    /// A time-varying flow.
    Keys(KeyBlend),
}

impl Flow {
    /// Flow-space velocity at `(u, v)` and time `t`.
    pub fn velocity(&self, uv: [f64; 2], t: f64) -> [f64; 2] {
        match self {
            Flow::Steady(b) => b.velocity(uv[0], uv[1]),
            Flow::Keys(k) => k.velocity(uv[0], uv[1], t),
        }
    }

    /// True where the tiling is blocked (or outside it).
    pub fn is_blocked_at(&self, uv: [f64; 2]) -> bool {
        match self {
            Flow::Steady(b) => b.is_blocked_at(uv[0], uv[1]),
            Flow::Keys(k) => k.key(0).is_blocked_at(uv[0], uv[1]),
        }
    }
}

/// A flow placed in the world: the runtime lookup in world coordinates.
#[derive(Clone, Debug)]
pub struct WorldField {
    map: FlowMap,
    flow: Flow,
    lo: [f64; 2],
    hi: [f64; 2],
}

impl WorldField {
    /// Places `flow` onto the triangles of `mesh`.
    pub fn new(mesh: &Mesh, flow: Flow) -> Result<WorldField, WorldError> {
        let map = FlowMap::new(&mesh.world, &mesh.flow, &mesh.triangles)?;
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for p in &mesh.world {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        Ok(WorldField { map, flow, lo, hi })
    }

    /// World velocity at world point `p` and time `t` (zero off the mesh
    /// and in blocked slots).
    ///
    /// ```
    /// use flowtile_bake::world::{Flow, Mesh, WorldField};
    /// use flowtile_bake::{bake::BakedTiling, rng::Rng, tileset::TileSet};
    /// use flowtile_bake::tiling::{Border, Conditions, Edge, Tiling};
    /// let set = TileSet::paper(3, 3, 1, 6).unwrap();
    /// let mut c = Conditions::borders(Border::Free, Border::Zero);
    /// c.fluxes.push((Edge::Vertical { x: 0, y: 0 }, 1));
    /// let mut t = Tiling::new(set, 2, 1, &c).unwrap();
    /// t.random_fill(&mut Rng::new(1)).unwrap();
    /// let flow = Flow::Steady(BakedTiling::from_tiling(&t).unwrap());
    /// // A 200×100 world rectangle carrying the 2×1 tiling: x scaled by 100.
    /// let mesh = Mesh::from_obj("v 0 0 0\nv 200 0 0\nv 200 100 0\nv 0 100 0\n\
    ///     vt 0 0\nvt 2 0\nvt 2 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n").unwrap();
    /// let w = WorldField::new(&mesh, flow).unwrap();
    /// assert!(w.velocity([150.0, 50.0], 0.0)[0] > 0.0);
    /// assert_eq!(w.velocity([500.0, 50.0], 0.0), [0.0, 0.0]);
    /// ```
    pub fn velocity(&self, p: [f64; 2], t: f64) -> [f64; 2] {
        match self.map.locate(p) {
            Some((tri, uv)) => self.map.world_velocity(tri, self.flow.velocity(uv, t)),
            None => [0.0, 0.0],
        }
    }

    /// True when `p` lies on the mesh in an open slot.
    pub fn is_open(&self, p: [f64; 2]) -> bool {
        self.map
            .locate(p)
            .is_some_and(|(_, uv)| !self.flow.is_blocked_at(uv))
    }

    /// True when `p` lies on the mesh.
    pub fn on_mesh(&self, p: [f64; 2]) -> bool {
        self.map.locate(p).is_some()
    }

    /// The mesh's world bounding box.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        (self.lo, self.hi)
    }

    /// Samples the world velocity at the centres of a regular grid of
    /// `cell`-sized squares over the mesh's bounding box, at time `t`.
    pub fn sample(&self, cell: f64, t: f64) -> Result<Sampler, WorldError> {
        let ext = [self.hi[0] - self.lo[0], self.hi[1] - self.lo[1]];
        if !(cell.is_finite() && cell > 0.0) {
            return Err(WorldError::Options(format!(
                "sampler cell {cell} must be positive"
            )));
        }
        let cols = (ext[0] / cell).ceil().max(1.0);
        let rows = (ext[1] / cell).ceil().max(1.0);
        if cols * rows > 1.6e7 {
            return Err(WorldError::Options(format!(
                "sampler cell {cell} gives {cols}x{rows} samples (at most 16 million)"
            )));
        }
        let (cols, rows) = (cols as u32, rows as u32);
        let mut velocity = Vec::with_capacity((cols * rows) as usize);
        let mut open = Vec::with_capacity((cols * rows) as usize);
        for r in 0..rows {
            for c in 0..cols {
                let p = [
                    self.lo[0] + (c as f64 + 0.5) * cell,
                    self.lo[1] + (r as f64 + 0.5) * cell,
                ];
                velocity.push(self.velocity(p, t));
                open.push(self.is_open(p));
            }
        }
        Ok(Sampler {
            origin: self.lo,
            cell,
            cols,
            rows,
            velocity,
            open,
        })
    }

    /// Largest world speed over a grid of samples at time `t` (for colour
    /// scales and time steps).
    pub fn max_speed(&self, t: f64) -> f64 {
        let ext = (self.hi[0] - self.lo[0]).max(self.hi[1] - self.lo[1]);
        self.sample(ext / 200.0, t)
            .map(|s| {
                s.velocity
                    .iter()
                    .map(|v| v[0].hypot(v[1]))
                    .fold(0.0, f64::max)
            })
            .unwrap_or(0.0)
    }

    /// One midpoint (RK2) step of particle advection.
    pub fn advect(&self, p: [f64; 2], t: f64, dt: f64) -> [f64; 2] {
        let v0 = self.velocity(p, t);
        let mid = [p[0] + v0[0] * dt / 2.0, p[1] + v0[1] * dt / 2.0];
        let v1 = self.velocity(mid, t + dt / 2.0);
        [p[0] + v1[0] * dt, p[1] + v1[1] * dt]
    }
}

/// World velocities on a regular grid: what an engine loads instead of the
/// tiling when it wants a plain lookup table.
#[derive(Clone, Debug, PartialEq)]
pub struct Sampler {
    /// World position of the grid's lower-left corner.
    pub origin: [f64; 2],
    /// Side of one grid square in world units.
    pub cell: f64,
    /// Columns.
    pub cols: u32,
    /// Rows.
    pub rows: u32,
    /// Velocity at each square's centre, row-major from the bottom row.
    pub velocity: Vec<[f64; 2]>,
    /// True where the centre lies on the mesh in an open slot.
    pub open: Vec<bool>,
}

impl Sampler {
    /// The sampler as JSON: `origin`, `cell`, `cols`, `rows`, and flat
    /// arrays `vx`, `vy` (row-major from the bottom row, velocities rounded
    /// to 1e-6) and `open` (0/1).
    pub fn to_json(&self) -> String {
        let round = |x: f64| (x * 1e6).round() / 1e6;
        serde_json::json!({
            "origin": self.origin,
            "cell": self.cell,
            "cols": self.cols,
            "rows": self.rows,
            "vx": self.velocity.iter().map(|v| round(v[0])).collect::<Vec<_>>(),
            "vy": self.velocity.iter().map(|v| round(v[1])).collect::<Vec<_>>(),
            "open": self.open.iter().map(|&o| o as u8).collect::<Vec<_>>(),
        })
        .to_string()
    }
}

/// World → pixel placement of a picture with room for axes and a legend.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// World point at the plot's lower-left corner.
    pub lo: [f64; 2],
    /// World point at the plot's upper-right corner.
    pub hi: [f64; 2],
    /// Pixels per world unit.
    pub scale: f64,
    /// Pixel column of the plot's left edge.
    pub left: f64,
    /// Pixel row of the plot's top edge.
    pub top: f64,
}

/// Margins around the plot (pixels).
const LEFT: f64 = 64.0;
const TOP: f64 = 28.0;
const RIGHT: f64 = 110.0;
const BOTTOM: f64 = 40.0;

impl View {
    /// A view of the world box `lo..hi`, `width` pixels wide for the plot.
    pub fn new(lo: [f64; 2], hi: [f64; 2], width: u32) -> Result<View, WorldError> {
        let ext = [(hi[0] - lo[0]).max(1e-9), (hi[1] - lo[1]).max(1e-9)];
        if !(64..=4096).contains(&width) {
            return Err(WorldError::Options(format!(
                "picture width {width} must lie in 64..=4096 pixels"
            )));
        }
        let scale = width as f64 / ext[0];
        if ext[1] * scale > MAX_PX as f64 / 4.0 {
            return Err(WorldError::Options(
                "the mesh is too tall for its width".into(),
            ));
        }
        Ok(View {
            lo,
            hi,
            scale,
            left: LEFT,
            top: TOP,
        })
    }

    /// Pixel position of world point `p` (y up in the world, down in pixels).
    pub fn px(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.left + (p[0] - self.lo[0]) * self.scale,
            self.top + (self.hi[1] - p[1]) * self.scale,
        ]
    }

    /// World point at pixel `(x, y)`.
    pub fn world(&self, x: f64, y: f64) -> [f64; 2] {
        [
            self.lo[0] + (x - self.left) / self.scale,
            self.hi[1] - (y - self.top) / self.scale,
        ]
    }

    /// Plot size in pixels.
    pub fn plot_size(&self) -> [f64; 2] {
        [
            ((self.hi[0] - self.lo[0]) * self.scale).round(),
            ((self.hi[1] - self.lo[1]) * self.scale).round(),
        ]
    }

    /// Size of the whole picture in pixels.
    pub fn canvas_size(&self) -> (u32, u32) {
        let [w, h] = self.plot_size();
        ((w + LEFT + RIGHT) as u32, (h + TOP + BOTTOM) as u32)
    }
}

/// A "nice" tick step (1, 2 or 5 × 10^k) for about `count` ticks over `extent`.
fn tick_step(extent: f64, count: f64) -> f64 {
    let raw = extent / count;
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * p)
}

const INK: [f32; 3] = [0.15, 0.15, 0.18];

/// Draws axes with ticks in world units, a title, and (with `vmax`) a speed legend.
pub fn draw_axes(c: &mut Canvas, v: &View, title: &str, vmax: Option<f64>, units: &str) {
    let [w, h] = v.plot_size();
    let (l, t) = (v.left, v.top);
    for (a, b) in [
        ([l, t], [l + w, t]),
        ([l + w, t], [l + w, t + h]),
        ([l + w, t + h], [l, t + h]),
        ([l, t + h], [l, t]),
    ] {
        c.line(a[0], a[1], b[0], b[1], INK, 1.0);
    }
    for axis in 0..2 {
        let (lo, hi) = (v.lo[axis], v.hi[axis]);
        let step = tick_step(hi - lo, 6.0);
        let mut k = (lo / step).ceil() * step;
        while k <= hi + 1e-9 * step {
            let label = format_tick(k, step);
            if axis == 0 {
                let x = v.px([k, v.lo[1]])[0];
                c.line(x, t + h, x, t + h + 5.0, INK, 1.0);
                c.text(x - 4.0 * label.len() as f64, t + h + 8.0, &label, INK);
            } else {
                let y = v.px([v.lo[0], k])[1];
                c.line(l - 5.0, y, l, y, INK, 1.0);
                c.text(l - 8.0 - 8.0 * label.len() as f64, y - 4.0, &label, INK);
            }
            k += step;
        }
    }
    let xl = format!("x ({units})");
    c.text(l + w / 2.0 - 4.0 * xl.len() as f64, t + h + 24.0, &xl, INK);
    c.text(4.0, t - 18.0, &format!("y ({units})"), INK);
    c.text(l + 40.0, 8.0, title, INK);
    // Legend: speed colour bar.
    let Some(vmax) = vmax else { return };
    let (bx, by, bh) = (l + w + 16.0, t + 16.0, (h - 32.0).clamp(40.0, 300.0));
    c.text(bx, t, "speed", INK);
    for i in 0..bh as i64 {
        let f = 1.0 - i as f64 / bh;
        c.fill_rect(
            bx,
            by + i as f64,
            bx + 14.0,
            by + i as f64 + 1.0,
            ramp(f),
            1.0,
        );
    }
    c.text(bx + 18.0, by - 4.0, &format_tick(vmax, vmax / 10.0), INK);
    c.text(bx + 18.0, by + bh - 4.0, "0", INK);
    c.text(bx, by + bh + 8.0, &format!("{units}/s"), INK);
}

fn format_tick(x: f64, step: f64) -> String {
    let digits = if step >= 1.0 {
        0
    } else {
        (-step.log10().floor()) as usize
    };
    let s = format!("{x:.digits$}");
    if s == "-0" { "0".into() } else { s }
}

/// Draws under the flow before the mesh (for example the level's top view).
pub type Background<'a> = &'a dyn Fn(&mut Canvas, &View);

/// Options for world pictures and animations.
#[derive(Clone, Debug)]
pub struct PictureOptions {
    /// Plot width in pixels.
    pub width: u32,
    /// Particles (trails and animations).
    pub particles: usize,
    /// Seed for particle starts and streamline seeds.
    pub seed: u64,
    /// Title drawn above the plot.
    pub title: String,
    /// Name of the world length unit for the axes.
    pub units: String,
}

/// Draws the mesh (light where open, grey where blocked) under the flow.
/// `background`, if given, draws first (for example the level's top view).
fn base_canvas(field: &WorldField, view: &View, background: Option<Background>) -> Canvas {
    let (cw, ch) = view.canvas_size();
    let mut c = Canvas::new(cw, ch, [1.0, 1.0, 1.0]);
    let [w, h] = view.plot_size();
    c.fill_rect(
        view.left,
        view.top,
        view.left + w,
        view.top + h,
        [0.93, 0.93, 0.91],
        1.0,
    );
    if let Some(bg) = background {
        bg(&mut c, view);
    }
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let (px, py) = (view.left + x as f64 + 0.5, view.top + y as f64 + 0.5);
            let p = view.world(px, py);
            if field.on_mesh(p) {
                // Over a background only the open area is tinted.
                let (col, a) = match (field.is_open(p), background.is_some()) {
                    (true, false) => ([0.80, 0.90, 0.97], 0.55),
                    (true, true) => ([0.80, 0.90, 0.97], 0.35),
                    (false, false) => ([0.45, 0.45, 0.48], 0.8),
                    (false, true) => ([0.45, 0.45, 0.48], 0.0),
                };
                c.fill_rect(px - 0.5, py - 0.5, px + 0.5, py + 0.5, col, a);
            }
        }
    }
    c
}

/// A random open point of the mesh (rejection sampling in the bounding box).
fn random_open_point(field: &WorldField, rng: &mut Rng) -> Option<[f64; 2]> {
    let (lo, hi) = field.bounds();
    for _ in 0..1000 {
        let p = [
            lo[0] + rng.unit() * (hi[0] - lo[0]),
            lo[1] + rng.unit() * (hi[1] - lo[1]),
        ];
        if field.is_open(p) {
            return Some(p);
        }
    }
    None
}

/// Streamlines over the mesh at time `t`, coloured by speed, with axes and
/// legend.
pub fn streamlines(
    field: &WorldField,
    opt: &PictureOptions,
    t: f64,
    background: Option<Background>,
) -> Result<Canvas, WorldError> {
    let (lo, hi) = field.bounds();
    let view = View::new(lo, hi, opt.width)?;
    let mut c = base_canvas(field, &view, background);
    let vmax = field.max_speed(t).max(1e-12);
    let mut rng = Rng::new(opt.seed);
    let spacing = 12.0 / view.scale; // world units between seeds
    let h = 1.0 / view.scale; // one pixel per step
    let steps = 160;
    let mut y = lo[1];
    while y < hi[1] {
        let mut x = lo[0];
        while x < hi[0] {
            let seed = [x + rng.unit() * spacing, y + rng.unit() * spacing];
            x += spacing;
            if !field.is_open(seed) {
                continue;
            }
            for dir in [1.0, -1.0] {
                let mut p = seed;
                for k in 0..steps {
                    let v = field.velocity(p, t);
                    let s = v[0].hypot(v[1]);
                    if s < 1e-9 * vmax {
                        break;
                    }
                    let q = [p[0] + dir * v[0] / s * h, p[1] + dir * v[1] / s * h];
                    if !field.is_open(q) {
                        break;
                    }
                    let (a, b) = (view.px(p), view.px(q));
                    let fade = 1.0 - k as f32 / steps as f32;
                    c.line(a[0], a[1], b[0], b[1], ramp(s / vmax), 0.6 * fade);
                    p = q;
                }
            }
        }
        y += spacing;
    }
    draw_axes(&mut c, &view, &opt.title, Some(vmax), &opt.units);
    Ok(c)
}

/// Options of an animation.
#[derive(Clone, Debug)]
pub struct AnimationOptions {
    /// Frames in the GIF.
    pub frames: usize,
    /// Flow time between frames.
    pub dt: f64,
    /// Frame delay in hundredths of a second.
    pub delay: u16,
}

/// Particles advected through the (time-varying) field, drawn with short
/// fading trails, encoded as a looping animated GIF. Particles that leave
/// the open mesh or stall are reborn at a random open point.
pub fn animate_gif(
    field: &WorldField,
    opt: &PictureOptions,
    anim: &AnimationOptions,
    background: Option<Background>,
    mut out: impl Write,
) -> Result<(), WorldError> {
    if anim.frames == 0 || anim.frames > 2000 {
        return Err(WorldError::Options(format!(
            "{} frames; give 1..=2000",
            anim.frames
        )));
    }
    if !(anim.dt.is_finite() && anim.dt > 0.0) {
        return Err(WorldError::Options(format!(
            "time step {} must be positive",
            anim.dt
        )));
    }
    if opt.particles == 0 || opt.particles > 200_000 {
        return Err(WorldError::Options(format!(
            "{} particles; give 1..=200000",
            opt.particles
        )));
    }
    let (lo, hi) = field.bounds();
    let view = View::new(lo, hi, opt.width)?;
    let base = base_canvas(field, &view, background);
    let vmax = field.max_speed(0.0).max(1e-12);
    let (cw, ch) = view.canvas_size();
    if cw > u16::MAX as u32 || ch > u16::MAX as u32 {
        return Err(WorldError::Options("picture too large for a GIF".into()));
    }
    let mut rng = Rng::new(opt.seed);
    const TRAIL: usize = 6;
    let mut parts: Vec<Vec<[f64; 2]>> = (0..opt.particles)
        .filter_map(|_| random_open_point(field, &mut rng).map(|p| vec![p]))
        .collect();
    if parts.is_empty() {
        return Err(WorldError::Options("the mesh has no open area".into()));
    }
    let mut enc = gif::Encoder::new(&mut out, cw as u16, ch as u16, &[])
        .map_err(|e| WorldError::Encode(e.to_string()))?;
    enc.set_repeat(gif::Repeat::Infinite)
        .map_err(|e| WorldError::Encode(e.to_string()))?;
    // Sub-steps so a particle moves at most about two pixels per step.
    let sub = ((vmax * anim.dt * view.scale / 2.0).ceil() as usize).clamp(1, 64);
    let h = anim.dt / sub as f64;
    let mut t = 0.0;
    for frame in 0..anim.frames {
        let mut c = base.clone();
        for trail in &mut parts {
            let mut p = *trail.last().expect("non-empty trail");
            let mut reborn = false;
            for _ in 0..sub {
                let q = field.advect(p, t, h);
                if !field.is_open(q) || (q == p) {
                    reborn = true;
                    break;
                }
                p = q;
            }
            if reborn {
                if let Some(q) = random_open_point(field, &mut rng) {
                    trail.clear();
                    trail.push(q);
                }
            } else {
                trail.push(p);
                if trail.len() > TRAIL {
                    trail.remove(0);
                }
            }
            for (k, w) in trail.windows(2).enumerate() {
                let (a, b) = (view.px(w[0]), view.px(w[1]));
                let v = field.velocity(w[1], t);
                let a_f = 0.3 + 0.7 * (k + 1) as f32 / TRAIL as f32;
                c.line(a[0], a[1], b[0], b[1], ramp(v[0].hypot(v[1]) / vmax), a_f);
            }
        }
        t += anim.dt;
        draw_axes(
            &mut c,
            &view,
            &format!(
                "{}  t = {:.2}  (frame {}/{})",
                opt.title,
                t,
                frame + 1,
                anim.frames
            ),
            Some(vmax),
            &opt.units,
        );
        let mut f = gif::Frame::from_rgb_speed(cw as u16, ch as u16, &c.to_rgb8(), 10);
        f.delay = anim.delay;
        enc.write_frame(&f)
            .map_err(|e| WorldError::Encode(e.to_string()))?;
    }
    drop(enc);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tileset::TileSet;
    use crate::tiling::{Border, Conditions, Edge, Tiling};

    fn river(seed: u64) -> BakedTiling {
        let set = TileSet::paper(5, 3, 5, 6).unwrap();
        let mut c = Conditions::borders(Border::Free, Border::Zero);
        for y in 0..3 {
            c.fluxes.push((Edge::Vertical { x: 0, y }, 1));
        }
        let mut t = Tiling::new(set, 6, 3, &c).unwrap();
        t.random_fill(&mut Rng::new(seed)).unwrap();
        BakedTiling::from_tiling(&t).unwrap()
    }

    /// A quarter annulus carrying the 6×3 tiling: u along the arc, v across.
    fn bend_obj() -> String {
        let mut s = String::new();
        let (nu, nv) = (12, 3);
        for j in 0..=nv {
            for i in 0..=nu {
                let a = std::f64::consts::FRAC_PI_2 * i as f64 / nu as f64;
                let r = 300.0 - 60.0 * j as f64;
                s += &format!(
                    "v {} {} 0\nvt {} {}\n",
                    r * a.cos(),
                    r * a.sin(),
                    6.0 * i as f64 / nu as f64,
                    j as f64
                );
            }
        }
        for j in 0..nv {
            for i in 0..nu {
                let k = |i: usize, j: usize| j * (nu + 1) + i + 1;
                let (a, b, c, d) = (k(i, j), k(i + 1, j), k(i + 1, j + 1), k(i, j + 1));
                s += &format!("f {a}/{a} {b}/{b} {c}/{c} {d}/{d}\n");
            }
        }
        s
    }

    #[test]
    fn world_motion_is_flow_motion_through_the_map() {
        let mesh = Mesh::from_obj(&bend_obj()).unwrap();
        let w = WorldField::new(&mesh, Flow::Steady(river(3))).unwrap();
        // Off the mesh and in the hole of the annulus nothing moves.
        assert_eq!(w.velocity([50.0, 50.0], 0.0), [0.0, 0.0]);
        assert_eq!(w.velocity([400.0, 400.0], 0.0), [0.0, 0.0]);
        // Paper §5: world motion is flow-space motion seen through the map.
        // A particle advected in the world lands where the same particle
        // advected in flow space maps to (up to the RK2 midpoints falling in
        // different triangles near triangle edges).
        let baked = river(3);
        let mut rng = Rng::new(5);
        let mut checked = 0;
        for _ in 0..40 {
            let p0 = [120.0 + 180.0 * rng.unit(), 0.0];
            let p0 = [p0[0] * 0.8, p0[0] * 0.6];
            let Some((_, mut uv)) = w.map.locate(p0) else {
                continue;
            };
            let mut p = p0;
            let dt = 1e-3;
            for _ in 0..200 {
                p = w.advect(p, 0.0, dt);
                let v0 = baked.velocity(uv[0], uv[1]);
                let mid = [uv[0] + v0[0] * dt / 2.0, uv[1] + v0[1] * dt / 2.0];
                let v1 = baked.velocity(mid[0], mid[1]);
                uv = [uv[0] + v1[0] * dt, uv[1] + v1[1] * dt];
            }
            let Some((_, got)) = w.map.locate(p) else {
                continue;
            };
            assert!(
                (got[0] - uv[0]).abs() < 1e-2 && (got[1] - uv[1]).abs() < 1e-2,
                "{got:?} vs {uv:?}"
            );
            checked += 1;
        }
        assert!(checked > 20, "{checked}");
    }

    /// Random damage to a valid OBJ: an error or a mesh, never a panic.
    #[test]
    fn damaged_obj_never_panics() {
        let good = bend_obj().into_bytes();
        let mut rng = Rng::new(17);
        for _ in 0..2000 {
            let mut b = good.clone();
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(b.len() as u64) as usize;
                const ALPHABET: &[u8] = b"0123456789-./ \nvtfe+x";
                b[i] = ALPHABET[rng.below(ALPHABET.len() as u64) as usize];
            }
            let cut = rng.below(b.len() as u64 + 1) as usize;
            let text = String::from_utf8_lossy(&b[..cut]);
            if let Ok(m) = Mesh::from_obj(&text) {
                let _ = WorldField::new(&m, Flow::Steady(river(1)));
            }
        }
    }

    #[test]
    fn bad_obj_is_a_clear_error() {
        for (text, needle) in [
            ("v 0 0 0\nf 1 2 3\n", "index"),
            ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n", "texture"),
            ("v 0 nan 0\n", "finite"),
            ("v 0 0\nvt 0\n", "finite"),
            ("", "no faces"),
            ("v 0 0 0\nvt 0 0\nf 1/1 1/1\n", "3 corners"),
        ] {
            let e = Mesh::from_obj(text).unwrap_err().to_string();
            assert!(e.contains(needle), "{needle}: {e}");
        }
    }

    #[test]
    fn animation_and_pictures_are_deterministic() {
        let keys: Vec<BakedTiling> = (0..3).map(river).collect();
        let flow = Flow::Keys(KeyBlend::new(keys, 1.0).unwrap());
        let mesh = Mesh::from_obj(&bend_obj()).unwrap();
        let w = WorldField::new(&mesh, flow).unwrap();
        let opt = PictureOptions {
            width: 160,
            particles: 50,
            seed: 2,
            title: "test".into(),
            units: "u".into(),
        };
        let anim = AnimationOptions {
            frames: 3,
            dt: 0.2,
            delay: 5,
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        animate_gif(&w, &opt, &anim, None, &mut a).unwrap();
        animate_gif(&w, &opt, &anim, None, &mut b).unwrap();
        assert_eq!(a, b);
        assert_eq!(&a[..6], b"GIF89a");
        let s = streamlines(&w, &opt, 0.5, None).unwrap();
        assert!(s.to_png().unwrap().len() > 1000);
        let bad = AnimationOptions { frames: 0, ..anim };
        assert!(animate_gif(&w, &opt, &bad, None, Vec::new()).is_err());
        let sampler = w.sample(10.0, 0.0).unwrap();
        assert_eq!(
            sampler.velocity.len(),
            (sampler.cols * sampler.rows) as usize
        );
        assert!(sampler.open.iter().any(|&o| o));
        assert!(w.sample(0.0, 0.0).is_err());
    }
}
