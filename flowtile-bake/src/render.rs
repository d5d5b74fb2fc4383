//! Pictures of baked tilings: arrows, streamlines or particle trails over the
//! flow, blocked slots shaded, tile seams optional, written as PNG.

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

/// Renders `baked` to a PNG image in memory.
pub fn render(baked: &BakedTiling, opt: &RenderOptions) -> Result<Vec<u8>, RenderError> {
    let ppt = opt.px_per_tile as u64;
    let (w, h) = (baked.width as u64 * ppt, baked.height as u64 * ppt);
    if w == 0 || h == 0 || w > MAX_PX || h > MAX_PX {
        return Err(RenderError::Size(w, h));
    }
    let mut c = Canvas::new(w as u32, h as u32, BACKGROUND);
    let s = ppt as f64;
    let to_px = |u: f64, v: f64| (u * s, (baked.height as f64 - v) * s);
    // Blocked slots: solid with a light hatch.
    for y in 0..baked.height {
        for x in 0..baked.width {
            if baked.tile_at(x, y).is_none() {
                let (px, py) = to_px(x as f64, y as f64 + 1.0);
                c.fill_rect(px, py, px + s, py + s, BLOCKED, 1.0);
                let mut k = 0.0;
                while k < 2.0 * s {
                    c.line(
                        px + k.min(s),
                        py + (k - s).max(0.0),
                        px + (k - s).max(0.0),
                        py + k.min(s),
                        [0.55; 3],
                        0.6,
                    );
                    k += (s / 6.0).max(3.0);
                }
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
        Style::Streamlines => draw_streamlines(&mut c, baked, s, vmax, &mut rng),
        Style::Particles => draw_particles(&mut c, baked, s, vmax, opt, &mut rng),
    }
    c.to_png()
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
                    let head = (len * 0.35).min(6.0);
                    for side in [-1.0, 1.0] {
                        let (hx, hy) = (-dx * 0.87 - side * dy * 0.5, -dy * 0.87 + side * dx * 0.5);
                        c.line(x1, y1, x1 + hx * head, y1 + hy * head, col, 1.0);
                    }
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

fn draw_streamlines(c: &mut Canvas, b: &BakedTiling, s: f64, vmax: f64, rng: &mut Rng) {
    let spacing = (10.0 / s).max(0.08); // tile units between seeds
    let h = 0.3 / b.set.n as f64;
    let steps = (1.2 / h) as usize;
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
                    p = wrap(b, q);
                }
            }
        }
        v += spacing;
    }
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
        // The particle itself: a small leaf / head.
        let (x, y) = (p[0] * s, (hgt - p[1]) * s);
        c.fill_rect(x - 1.5, y - 1.5, x + 1.5, y + 1.5, [0.1, 0.1, 0.1], 0.9);
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
