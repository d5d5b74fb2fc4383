//! Pictures of baked tilings: arrows, streamlines or particle trails over the
//! flow, blocked slots shaded, tile seams optional, written as PNG. Arrowheads show
//! which way the flow goes (on every arrow, along each streamline, at each particle's
//! head); a legend strip under the tiling says what the colours mean (speed, with its
//! scale and units), what the grey hatch is, and carries a scale bar (in map units with
//! `tile_units`, else in tiles).

use std::fmt;
use std::path::Path;

use crate::bake::{BakedTiling, write_atomic};
use crate::rng::Rng;

/// What to draw over the tiling.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// One arrow per cell (or per few cells), length by speed.
    Arrows,
    /// Streamlines from jittered seeds, coloured by speed.
    Streamlines,
    /// Particles advected through the flow, drawn as fading trails
    /// (leaves on the river, a crowd in the streets).
    Particles,
}

/// Rendering options.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// Pixels per tile side.
    pub px_per_tile: u32,
    /// What to draw.
    pub style: Style,
    /// Draw the tile grid.
    pub seams: bool,
    /// Number of particles (particle style).
    pub particles: usize,
    /// Advection steps per particle (particle style).
    pub steps: usize,
    /// Seed for seeds and particles.
    pub seed: u64,
    /// Draw the legend strip under the tiling.
    pub legend: bool,
    /// Map units per tile side, for the scale bar and the speed's units; `None`: tiles.
    pub tile_units: Option<f64>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            px_per_tile: 48,
            style: Style::Streamlines,
            seams: true,
            particles: 600,
            steps: 400,
            seed: 1,
            legend: true,
            tile_units: None,
        }
    }
}

/// Errors while rendering.
#[derive(Debug)]
pub enum RenderError {
    /// The picture would be empty or unreasonably large.
    Size(u64, u64),
    /// Writing the PNG failed.
    Write(String),
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Size(w, h) => {
                write!(
                    f,
                    "picture would be {w}x{h} pixels; allowed is 1..={MAX_PX} per side"
                )
            }
            RenderError::Write(why) => write!(f, "cannot write picture: {why}"),
        }
    }
}

impl std::error::Error for RenderError {}

/// Largest picture side in pixels.
pub const MAX_PX: u64 = 16384;

/// An RGB picture with alpha-blended drawing.
#[derive(Clone, Debug)]
pub struct Canvas {
    width: u32,
    height: u32,
    rgb: Vec<[f32; 3]>,
}

impl Canvas {
    /// A canvas filled with `bg`.
    pub fn new(width: u32, height: u32, bg: [f32; 3]) -> Canvas {
        Canvas {
            width,
            height,
            rgb: vec![bg; (width * height) as usize],
        }
    }

    fn blend(&mut self, x: i64, y: i64, c: [f32; 3], a: f32) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 || a <= 0.0 {
            return;
        }
        let p = &mut self.rgb[(y as u32 * self.width + x as u32) as usize];
        for k in 0..3 {
            p[k] += (c[k] - p[k]) * a.min(1.0);
        }
    }

    /// Fills the pixel rectangle `[x0, x1) × [y0, y1)`.
    pub fn fill_rect(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: [f32; 3], a: f32) {
        for y in y0.round() as i64..y1.round() as i64 {
            for x in x0.round() as i64..x1.round() as i64 {
                self.blend(x, y, c, a);
            }
        }
    }

    /// An anti-aliased line, drawn by splatting bilinear samples every half pixel.
    pub fn line(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: [f32; 3], a: f32) {
        let len = ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
        if !len.is_finite() || len > 4.0 * MAX_PX as f64 {
            return;
        }
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let (x, y) = (x0 + (x1 - x0) * t - 0.5, y0 + (y1 - y0) * t - 0.5);
            let (ix, iy) = (x.floor(), y.floor());
            let (fx, fy) = ((x - ix) as f32, (y - iy) as f32);
            let k = a * 0.55;
            self.blend(ix as i64, iy as i64, c, k * (1.0 - fx) * (1.0 - fy));
            self.blend(ix as i64 + 1, iy as i64, c, k * fx * (1.0 - fy));
            self.blend(ix as i64, iy as i64 + 1, c, k * (1.0 - fx) * fy);
            self.blend(ix as i64 + 1, iy as i64 + 1, c, k * fx * fy);
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Draws `text` in 8×8 bitmap glyphs (`font8x8`) with its top-left
    /// corner at pixel `(x, y)`; non-ASCII characters show as `?`.
    pub fn text(&mut self, x: f64, y: f64, text: &str, c: [f32; 3]) {
        let (x, y) = (x.round() as i64, y.round() as i64);
        for (i, ch) in text.chars().enumerate() {
            let code = if ch.is_ascii() {
                ch as usize
            } else {
                '?' as usize
            };
            let glyph = font8x8::legacy::BASIC_LEGACY[code];
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) != 0 {
                        self.blend(x + (i * 8) as i64 + col, y + row as i64, c, 1.0);
                    }
                }
            }
        }
    }

    /// The pixels as 8-bit RGB triples, row by row from the top.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.rgb
            .iter()
            .flat_map(|p| p.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }

    /// Encodes the canvas as an 8-bit RGB PNG.
    pub fn to_png(&self) -> Result<Vec<u8>, RenderError> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgb);
            enc.set_depth(png::BitDepth::Eight);
            enc.set_compression(png::Compression::High);
            let mut w = enc
                .write_header()
                .map_err(|e| RenderError::Write(e.to_string()))?;
            w.write_image_data(&self.to_rgb8())
                .map_err(|e| RenderError::Write(e.to_string()))?;
        }
        Ok(out)
    }
}

/// Speed colour ramp: deep blue → teal → yellow → orange-red.
pub fn ramp(t: f64) -> [f32; 3] {
    const STOPS: [[f32; 3]; 5] = [
        [0.10, 0.18, 0.45],
        [0.05, 0.45, 0.60],
        [0.20, 0.65, 0.45],
        [0.92, 0.78, 0.20],
        [0.85, 0.30, 0.15],
    ];
    let t = t.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let f = (t - i as f64) as f32;
    std::array::from_fn(|k| STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f)
}

const BACKGROUND: [f32; 3] = [0.97, 0.97, 0.95];
const BLOCKED: [f32; 3] = [0.42, 0.42, 0.44];
const SEAM: [f32; 3] = [0.55, 0.58, 0.68];
const INK: [f32; 3] = [0.15, 0.15, 0.18];

/// Height of the legend strip under the tiling (pixels).
pub const LEGEND_HEIGHT: u32 = 60;
/// The picture is at least this wide when it has a legend, so the legend fits.
pub const LEGEND_WIDTH: u32 = 400;

/// The picture's size and the tiling's part of it (pixels): `(width, height, plot
/// width, plot height)`; the legend strip lies below the plot, across the picture.
pub fn picture_size(baked: &BakedTiling, opt: &RenderOptions) -> Result<[u64; 4], RenderError> {
    let ppt = opt.px_per_tile as u64;
    let (w, h) = (baked.width as u64 * ppt, baked.height as u64 * ppt);
    let (cw, ch) = if opt.legend {
        (w.max(LEGEND_WIDTH as u64), h + LEGEND_HEIGHT as u64)
    } else {
        (w, h)
    };
    if w == 0 || h == 0 || cw > MAX_PX || ch > MAX_PX {
        return Err(RenderError::Size(cw, ch));
    }
    Ok([cw, ch, w, h])
}

/// Renders `baked` to a PNG image in memory.
pub fn render(baked: &BakedTiling, opt: &RenderOptions) -> Result<Vec<u8>, RenderError> {
    render_canvas(baked, opt)?.to_png()
}

/// Renders `baked` to a canvas.
pub fn render_canvas(baked: &BakedTiling, opt: &RenderOptions) -> Result<Canvas, RenderError> {
    let [cw, ch, w, h] = picture_size(baked, opt)?;
    let ppt = opt.px_per_tile as u64;
    let mut c = Canvas::new(cw as u32, ch as u32, BACKGROUND);
    let s = ppt as f64;
    let to_px = |u: f64, v: f64| (u * s, (baked.height as f64 - v) * s);
    // Blocked slots: solid with a light hatch.
    for y in 0..baked.height {
        for x in 0..baked.width {
            if baked.tile_at(x, y).is_none() {
                let (px, py) = to_px(x as f64, y as f64 + 1.0);
                hatch(&mut c, px, py, s, s);
            }
        }
    }
    if opt.seams {
        for x in 0..=baked.width {
            let (px, _) = to_px(x as f64, 0.0);
            c.line(px, 0.0, px, h as f64, SEAM, 0.5);
        }
        for y in 0..=baked.height {
            let (_, py) = to_px(0.0, y as f64);
            c.line(0.0, py, w as f64, py, SEAM, 0.5);
        }
    }
    let vmax = max_speed(baked).max(1e-12);
    let mut rng = Rng::new(opt.seed);
    match opt.style {
        Style::Arrows => draw_arrows(&mut c, baked, s, vmax),
        Style::Streamlines => {
            draw_streamlines(&mut c, baked, s, vmax, &mut rng);
        }
        Style::Particles => draw_particles(&mut c, baked, s, vmax, opt, &mut rng),
    }
    if opt.legend {
        draw_legend(&mut c, h as f64, s, vmax, opt);
    }
    Ok(c)
}

/// A blocked slot: grey with a light hatch.
fn hatch(c: &mut Canvas, px: f64, py: f64, sw: f64, sh: f64) {
    c.fill_rect(px, py, px + sw, py + sh, BLOCKED, 1.0);
    let mut k = 0.0;
    let step = (sw.min(sh) / 6.0).max(3.0);
    while k < sw + sh {
        let (a, b) = ((k).min(sw), (k - sw).max(0.0));
        let (d, e) = ((k - sh).max(0.0), k.min(sh));
        c.line(px + a, py + b, px + d, py + e, [0.55; 3], 0.6);
        k += step;
    }
}

/// An arrowhead with its tip at `(x, y)` pointing along the unit pixel direction
/// `(dx, dy)`, `size` pixels long.
fn arrowhead(
    c: &mut Canvas,
    (x, y): (f64, f64),
    (dx, dy): (f64, f64),
    size: f64,
    col: [f32; 3],
    a: f32,
) {
    for side in [-1.0, 1.0] {
        let (hx, hy) = (-dx * 0.87 - side * dy * 0.5, -dy * 0.87 + side * dx * 0.5);
        c.line(x, y, x + hx * size, y + hy * size, col, a);
    }
}

/// A "nice" length (1, 2 or 5 × 10^k) at most `raw`.
fn nice_below(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    [5.0, 2.0, 1.0]
        .iter()
        .map(|m| m * p)
        .find(|&l| l <= raw)
        .unwrap_or(p)
}

/// A number with two significant digits (the speed scale's end).
fn two_digits(x: f64) -> String {
    if x >= 10.0 {
        format!("{x:.0}")
    } else if x >= 1.0 {
        format!("{x:.1}")
    } else {
        let digits = (-x.log10().floor()) as usize + 1;
        format!("{x:.digits$}")
    }
}

/// The legend strip under the plot (which is `plot_h` pixels high): the speed colour
/// bar with its range and units, the blocked slot's hatch, the tile seam, a scale bar
/// and the arrow of the flow's direction.
fn draw_legend(c: &mut Canvas, plot_h: f64, s: f64, vmax: f64, opt: &RenderOptions) {
    let y0 = plot_h;
    c.fill_rect(
        0.0,
        y0,
        c.width() as f64,
        c.height() as f64,
        BACKGROUND,
        1.0,
    );
    c.line(0.0, y0 + 0.5, c.width() as f64, y0 + 0.5, INK, 0.8);
    let (unit, per_tile) = match opt.tile_units {
        Some(u) if u.is_finite() && u > 0.0 => ("units", u),
        _ => ("tiles", 1.0),
    };
    // Row 1: speed colour bar (particles: what their colours are), blocked slot, seam.
    let (bx, by, bw) = (8.0, y0 + 17.0, 128.0);
    let top = if opt.style == Style::Particles {
        c.text(8.0, y0 + 6.0, "trail: one colour per particle,", INK);
        c.text(8.0, y0 + 17.0, "fading into its past", INK);
        String::new()
    } else {
        c.text(8.0, y0 + 6.0, &format!("speed ({unit}/s)"), INK);
        for i in 0..bw as i64 {
            let x = bx + i as f64;
            c.fill_rect(x, by, x + 1.0, by + 8.0, ramp(i as f64 / bw), 1.0);
        }
        let top = two_digits(vmax * per_tile);
        c.text(bx + bw + 4.0, by, &top, INK);
        c.text(bx, by + 10.0, "0", INK);
        top
    };
    let lx = if opt.style == Style::Particles {
        8.0 + 8.0 * 32.0
    } else {
        bx + bw + 12.0 + 8.0 * top.len() as f64
    };
    hatch(c, lx, by - 2.0, 12.0, 12.0);
    c.text(lx + 16.0, by, "blocked", INK);
    if opt.seams {
        let sx = lx + 16.0 + 8.0 * 8.0 + 4.0;
        c.line(sx, by + 4.0, sx + 14.0, by + 4.0, SEAM, 1.0);
        c.text(sx + 18.0, by, "seam", INK);
    }
    // Row 2: scale bar, flow arrow.
    let ry = y0 + 44.0;
    let units_per_px = per_tile / s;
    let length = nice_below(110.0 * units_per_px);
    let px = length / units_per_px;
    c.line(8.0, ry, 8.0 + px, ry, INK, 1.0);
    for x in [8.0, 8.0 + px] {
        c.line(x, ry - 4.0, x, ry + 4.0, INK, 1.0);
    }
    let label = if unit == "tiles" && length == 1.0 {
        "1 tile".to_string()
    } else {
        format!("{} {unit}", format_length(length))
    };
    c.text(8.0 + px + 6.0, ry - 4.0, &label, INK);
    let ax = 8.0 + 110.0 + 6.0 + 8.0 * 12.0 + 12.0;
    c.line(ax, ry, ax + 26.0, ry, ramp(0.6), 1.0);
    arrowhead(c, (ax + 26.0, ry), (1.0, 0.0), 6.0, ramp(0.6), 1.0);
    c.text(ax + 34.0, ry - 4.0, "flow direction", INK);
}

/// A scale bar's length as written: no decimals unless it is below one.
fn format_length(x: f64) -> String {
    if x >= 1.0 {
        format!("{x:.0}")
    } else {
        let digits = (-x.log10().floor()) as usize;
        format!("{x:.digits$}")
    }
}

/// Renders and writes atomically to `path`.
pub fn render_to_file(
    baked: &BakedTiling,
    opt: &RenderOptions,
    path: &Path,
) -> Result<(), RenderError> {
    let png = render(baked, opt)?;
    write_atomic(path, &png).map_err(|e| RenderError::Write(e.to_string()))
}

fn max_speed(b: &BakedTiling) -> f64 {
    let n = b.set.n as f64;
    let mut m = 0.0f64;
    for y in 0..(b.height as usize * b.set.n) {
        for x in 0..(b.width as usize * b.set.n) {
            let v = b.velocity((x as f64 + 0.5) / n, (y as f64 + 0.5) / n);
            m = m.max(v[0].hypot(v[1]));
        }
    }
    m
}

fn draw_arrows(c: &mut Canvas, b: &BakedTiling, s: f64, vmax: f64) {
    let n = b.set.n as f64;
    let cell_px = s / n;
    let stride = (12.0 / cell_px).ceil().max(1.0);
    let spacing = stride / n; // tile units
    let (mut v, mut u);
    v = spacing / 2.0;
    while v < b.height as f64 {
        u = spacing / 2.0;
        while u < b.width as f64 {
            if !b.is_blocked_at(u, v) {
                let vel = b.velocity(u, v);
                let speed = vel[0].hypot(vel[1]);
                let len = 0.9 * spacing * s * speed / vmax;
                if len > 0.5 {
                    let (dx, dy) = (vel[0] / speed, -vel[1] / speed);
                    let (cx, cy) = (u * s, (b.height as f64 - v) * s);
                    let (x0, y0) = (cx - dx * len / 2.0, cy - dy * len / 2.0);
                    let (x1, y1) = (cx + dx * len / 2.0, cy + dy * len / 2.0);
                    let col = ramp(speed / vmax);
                    c.line(x0, y0, x1, y1, col, 1.0);
                    arrowhead(c, (x1, y1), (dx, dy), (len * 0.35).min(6.0), col, 1.0);
                } else {
                    c.fill_rect(
                        u * s - 0.5,
                        (b.height as f64 - v) * s - 0.5,
                        u * s + 0.5,
                        (b.height as f64 - v) * s + 0.5,
                        ramp(0.0),
                        0.6,
                    );
                }
            }
            u += spacing;
        }
        v += spacing;
    }
}

/// One RK2 step of length `h` along the normalised direction field.
fn direction_step(b: &BakedTiling, p: [f64; 2], h: f64) -> Option<[f64; 2]> {
    let v0 = b.velocity(p[0], p[1]);
    let s0 = v0[0].hypot(v0[1]);
    if s0 < 1e-9 {
        return None;
    }
    let mid = [p[0] + v0[0] / s0 * h / 2.0, p[1] + v0[1] / s0 * h / 2.0];
    let v1 = b.velocity(mid[0], mid[1]);
    let s1 = v1[0].hypot(v1[1]);
    if s1 < 1e-9 {
        return None;
    }
    Some([p[0] + v1[0] / s1 * h, p[1] + v1[1] / s1 * h])
}

/// Streamlines from jittered seeds, each traced both ways from its seed; an arrowhead
/// sits on the downstream half of each, where it has gone a third of its length.
/// Returns the arrowheads (pixel tip and unit pixel direction).
fn draw_streamlines(
    c: &mut Canvas,
    b: &BakedTiling,
    s: f64,
    vmax: f64,
    rng: &mut Rng,
) -> Vec<((f64, f64), (f64, f64))> {
    let spacing = (10.0 / s).max(0.08); // tile units between seeds
    let h = 0.3 / b.set.n as f64;
    let steps = (1.2 / h) as usize;
    let mut heads = Vec::new();
    let mut v = 0.0;
    while v < b.height as f64 {
        let mut u = 0.0;
        while u < b.width as f64 {
            let seed = [u + rng.unit() * spacing, v + rng.unit() * spacing];
            u += spacing;
            if b.is_blocked_at(seed[0], seed[1]) {
                continue;
            }
            for dir in [1.0, -1.0] {
                let mut p = seed;
                for k in 0..steps {
                    let Some(q) = direction_step(b, p, h * dir) else {
                        break;
                    };
                    if b.is_blocked_at(q[0], q[1])
                        || (q[0] - p[0]).abs() > 0.5
                        || (q[1] - p[1]).abs() > 0.5
                    {
                        break;
                    }
                    let vel = b.velocity(q[0], q[1]);
                    let speed = vel[0].hypot(vel[1]) / vmax;
                    let fade = 1.0 - k as f32 / steps as f32;
                    let (x0, y0) = (p[0] * s, (b.height as f64 - p[1]) * s);
                    let (x1, y1) = (q[0] * s, (b.height as f64 - q[1]) * s);
                    c.line(x0, y0, x1, y1, ramp(speed), 0.55 * fade);
                    if dir > 0.0 && k == steps / 3 && speed > 0.0 {
                        // Along the flow at the tip (pixel y points down).
                        let n = vel[0].hypot(vel[1]);
                        let d = (vel[0] / n, -vel[1] / n);
                        arrowhead(c, (x1, y1), d, 4.0, ramp(speed), 0.9);
                        heads.push(((x1, y1), d));
                    }
                    p = wrap(b, q);
                }
            }
        }
        v += spacing;
    }
    heads
}

/// Wraps a point back into a periodic grid.
fn wrap(b: &BakedTiling, p: [f64; 2]) -> [f64; 2] {
    [
        if b.periodic_x {
            p[0].rem_euclid(b.width as f64)
        } else {
            p[0]
        },
        if b.periodic_y {
            p[1].rem_euclid(b.height as f64)
        } else {
            p[1]
        },
    ]
}

fn draw_particles(
    c: &mut Canvas,
    b: &BakedTiling,
    s: f64,
    vmax: f64,
    opt: &RenderOptions,
    rng: &mut Rng,
) {
    // Time step: the fastest particle moves about a third of a cell.
    let dt = 0.33 / (b.set.n as f64 * vmax);
    let hgt = b.height as f64;
    for _ in 0..opt.particles {
        let mut p = [0.0; 2];
        let mut placed = false;
        for _ in 0..64 {
            p = [rng.unit() * b.width as f64, rng.unit() * hgt];
            if !b.is_blocked_at(p[0], p[1]) {
                placed = true;
                break;
            }
        }
        if !placed {
            continue;
        }
        let hue = rng.unit();
        let col = ramp(0.15 + 0.7 * hue);
        for k in 0..opt.steps {
            let v0 = b.velocity(p[0], p[1]);
            let mid = [p[0] + v0[0] * dt / 2.0, p[1] + v0[1] * dt / 2.0];
            let v1 = b.velocity(mid[0], mid[1]);
            let q = [p[0] + v1[0] * dt, p[1] + v1[1] * dt];
            if b.is_blocked_at(q[0], q[1]) {
                break;
            }
            let alpha = 0.15 + 0.75 * (k as f32 / opt.steps.max(1) as f32);
            c.line(
                p[0] * s,
                (hgt - p[1]) * s,
                q[0] * s,
                (hgt - q[1]) * s,
                col,
                alpha,
            );
            p = wrap(b, q);
        }
        // The particle itself: an arrowhead the way it last moved (a dot if it did not).
        let (x, y) = (p[0] * s, (hgt - p[1]) * s);
        let v = b.velocity(p[0], p[1]);
        let speed = v[0].hypot(v[1]);
        if speed > 1e-9 {
            arrowhead(
                c,
                (x, y),
                (v[0] / speed, -v[1] / speed),
                4.0,
                [0.1, 0.1, 0.1],
                0.95,
            );
        } else {
            c.fill_rect(x - 1.5, y - 1.5, x + 1.5, y + 1.5, [0.1, 0.1, 0.1], 0.9);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tileset::TileSet;
    use crate::tiling::{Border, Conditions, Tiling, parse_mask};

    fn baked() -> BakedTiling {
        let set = TileSet::paper(3, 3, 5, 6).unwrap();
        let mut cond = Conditions::borders(Border::Periodic, Border::Zero);
        cond.blocked = parse_mask("....\n.#..\n....", 4, 3).unwrap();
        let mut t = Tiling::new(set, 4, 3, &cond).unwrap();
        t.random_fill(&mut Rng::new(1)).unwrap();
        BakedTiling::from_tiling(&t).unwrap()
    }

    #[test]
    fn renders_every_style_deterministically() {
        let b = baked();
        for style in [Style::Arrows, Style::Streamlines, Style::Particles] {
            let opt = RenderOptions {
                px_per_tile: 24,
                style,
                particles: 30,
                steps: 50,
                legend: false,
                ..Default::default()
            };
            let a = render(&b, &opt).unwrap();
            assert_eq!(a, render(&b, &opt).unwrap());
            assert_eq!(&a[1..4], b"PNG");
            // Decode and check the blocked slot is shaded.
            let dec = png::Decoder::new(std::io::Cursor::new(a));
            let mut r = dec.read_info().unwrap();
            let mut buf = vec![0; r.output_buffer_size().unwrap()];
            let info = r.next_frame(&mut buf).unwrap();
            assert_eq!((info.width, info.height), (96, 72));
            // Pixel near the centre of slot (1, 1): image row 36, column 36.
            let px = &buf[(36 * 96 + 33) * 3..][..3];
            assert!(px[0] < 180, "blocked slot not shaded: {px:?}");
        }
    }

    /// The legend strip lies under the tiling, inside the picture, and the tiling's
    /// pixels are those of the picture without a legend.
    #[test]
    fn the_legend_lies_under_the_tiling() {
        let b = baked();
        for (px, units) in [(24, None), (48, Some(64.0)), (160, Some(128.0))] {
            let opt = RenderOptions {
                px_per_tile: px,
                tile_units: units,
                ..Default::default()
            };
            let [cw, ch, w, h] = picture_size(&b, &opt).unwrap();
            assert_eq!(ch, h + LEGEND_HEIGHT as u64);
            assert!(cw >= LEGEND_WIDTH as u64 && cw >= w);
            let with = render_canvas(&b, &opt).unwrap();
            let without = render_canvas(
                &b,
                &RenderOptions {
                    legend: false,
                    ..opt.clone()
                },
            )
            .unwrap();
            let (a, z) = (with.to_rgb8(), without.to_rgb8());
            for y in 0..h as usize {
                let row =
                    |img: &[u8], width: usize| img[y * width * 3..][..w as usize * 3].to_vec();
                assert!(
                    row(&a, cw as usize) == row(&z, w as usize),
                    "row {y} of the tiling differs"
                );
            }
            // Something is drawn in the strip: ink in both of its rows.
            let dark = |y0: usize, y1: usize| {
                (y0..y1).any(|y| (0..cw as usize).any(|x| a[(y * cw as usize + x) * 3] < 90))
            };
            assert!(dark(h as usize + 2, h as usize + 30) && dark(h as usize + 32, ch as usize));
        }
    }

    /// The scale bar's length is a round number of map units (or tiles), 40 to 110 px.
    #[test]
    fn the_scale_bar_is_round() {
        assert_eq!(nice_below(110.0 * 64.0 / 48.0), 100.0);
        assert_eq!(nice_below(110.0 / 48.0), 2.0);
        assert_eq!(nice_below(110.0 * 128.0 / 160.0), 50.0);
        for raw in [0.3, 1.7, 23.0, 999.0] {
            let l = nice_below(raw);
            assert!(l <= raw && l > raw / 2.6, "{raw} -> {l}");
        }
        assert_eq!(two_digits(0.0123), "0.012");
        assert_eq!(format_length(0.5), "0.5");
    }

    /// Every streamline's arrowhead points the way the flow goes at its tip.
    #[test]
    fn streamline_arrowheads_point_downstream() {
        let b = baked();
        let s = 48.0;
        let mut c = Canvas::new(4 * 48, 3 * 48, BACKGROUND);
        let vmax = max_speed(&b);
        let heads = draw_streamlines(&mut c, &b, s, vmax, &mut Rng::new(1));
        assert!(heads.len() > 20, "{} arrowheads", heads.len());
        for ((x, y), (dx, dy)) in heads {
            let v = b.velocity(x / s, b.height as f64 - y / s);
            let speed = v[0].hypot(v[1]);
            let along = (dx * v[0] - dy * v[1]) / speed;
            assert!(
                along > 0.9,
                "head at ({x:.1}, {y:.1}) points {along:.2} along the flow"
            );
        }
    }

    #[test]
    fn absurd_sizes_are_refused() {
        let b = baked();
        let opt = RenderOptions {
            px_per_tile: 100_000,
            ..Default::default()
        };
        assert!(matches!(render(&b, &opt), Err(RenderError::Size(..))));
        let opt = RenderOptions {
            px_per_tile: 0,
            ..Default::default()
        };
        assert!(render(&b, &opt).is_err());
    }
}
