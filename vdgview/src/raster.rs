//! A small deterministic software rasterizer: z-buffered triangles with per-vertex
//! colours, depth-tested lines and dots, into a `0x00RRGGBB` framebuffer.
//!
//! Why our own: renders must be byte-identical run to run and machine to machine
//! without a GPU, and the interactive window shows the very same framebuffer, so
//! a render and a fly-through never disagree. Everything runs on one thread in a
//! fixed order; the depth buffer holds view-space depth (distance along the
//! viewing direction), so overlays on surfaces (samples on walls) can be tested
//! with a bias in world units.

use crate::camera::{Camera, Projection, ViewBasis};
use glam::{Vec2, Vec3};

/// Nearest distance drawn (world units) for perspective views.
const NEAR: f32 = 1.0;

/// An RGB colour (0..=255 per channel).
pub type Rgb = [u8; 3];

/// Packs a colour the way minifb and the framebuffer store it.
pub fn pack(c: Rgb) -> u32 {
    (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2])
}

/// Unpacks a `0x00RRGGBB` pixel.
pub fn unpack(p: u32) -> Rgb {
    [(p >> 16) as u8, (p >> 8) as u8, p as u8]
}

/// Colour and depth buffers plus the camera that projects into them.
pub struct Framebuffer {
    pub width: usize,
    pub height: usize,
    pub color: Vec<u32>,
    /// View-space depth per pixel; `f32::INFINITY` where nothing was drawn.
    pub depth: Vec<f32>,
    view: View,
}

/// A projected vertex: pixel coordinates and the value interpolated linearly in
/// screen space for depth (1/z for perspective, z for orthographic).
#[derive(Debug, Clone, Copy)]
struct ScreenVertex {
    p: Vec2,
    key: f32,
    color: Vec3,
}

/// The camera reduced to what projection needs.
#[derive(Debug, Clone, Copy)]
struct View {
    basis: ViewBasis,
    /// Pixels per unit at depth 1 (perspective) or per world unit (orthographic).
    scale: f32,
    ortho: bool,
    half: Vec2,
}

impl View {
    fn new(camera: &Camera, width: usize, height: usize) -> View {
        let half = Vec2::new(width as f32 * 0.5, height as f32 * 0.5);
        let (scale, ortho) = match camera.projection {
            Projection::Perspective { fov_deg } => {
                (half.y / (fov_deg.to_radians() * 0.5).tan(), false)
            }
            Projection::Orthographic { half_height } => (half.y / half_height, true),
        };
        View {
            basis: camera.basis(),
            scale,
            ortho,
            half,
        }
    }

    /// World → camera space (x right, y up, z forward).
    fn camera_space(&self, p: Vec3) -> Vec3 {
        let d = p - self.basis.pos;
        Vec3::new(
            d.dot(self.basis.right),
            d.dot(self.basis.up),
            d.dot(self.basis.forward),
        )
    }

    /// The near limit in camera z (orthographic views draw everything in front).
    fn near(&self) -> f32 {
        if self.ortho { 0.0 } else { NEAR }
    }

    fn project(&self, c: Vec3, color: Vec3) -> ScreenVertex {
        if self.ortho {
            ScreenVertex {
                p: Vec2::new(
                    self.half.x + c.x * self.scale,
                    self.half.y - c.y * self.scale,
                ),
                key: c.z,
                color,
            }
        } else {
            let inv = 1.0 / c.z;
            ScreenVertex {
                p: Vec2::new(
                    self.half.x + c.x * inv * self.scale,
                    self.half.y - c.y * inv * self.scale,
                ),
                key: inv,
                color,
            }
        }
    }

    fn depth_of_key(&self, key: f32) -> f32 {
        if self.ortho { key } else { 1.0 / key }
    }
}

impl Framebuffer {
    /// A cleared framebuffer for `camera`.
    pub fn new(width: usize, height: usize, camera: &Camera, background: Rgb) -> Framebuffer {
        Framebuffer {
            width,
            height,
            color: vec![pack(background); width * height],
            depth: vec![f32::INFINITY; width * height],
            view: View::new(camera, width, height),
        }
    }

    /// Clears for a new frame with another camera, keeping the allocation.
    pub fn reset(&mut self, camera: &Camera, background: Rgb) {
        self.color.fill(pack(background));
        self.depth.fill(f32::INFINITY);
        self.view = View::new(camera, self.width, self.height);
    }

    /// True when the triangle's front (counter-clockwise seen from the camera, i.e.
    /// its normal `n`) faces the eye.
    pub fn faces_camera(&self, a: Vec3, n: Vec3) -> bool {
        if self.view.ortho {
            n.dot(self.view.basis.forward) < 0.0
        } else {
            n.dot(a - self.view.basis.pos) < 0.0
        }
    }

    /// The world point seen at pixel (x, y), from the depth buffer.
    pub fn unproject(&self, x: usize, y: usize) -> Option<Vec3> {
        let d = *self.depth.get(y * self.width + x)?;
        if !d.is_finite() {
            return None;
        }
        let b = &self.view.basis;
        let sx = (x as f32 + 0.5 - self.view.half.x) / self.view.scale;
        let sy = (self.view.half.y - (y as f32 + 0.5)) / self.view.scale;
        Some(if self.view.ortho {
            b.pos + b.right * sx + b.up * sy + b.forward * d
        } else {
            b.pos + (b.right * sx + b.up * sy + b.forward) * d
        })
    }

    /// A z-buffered triangle with colours (0..=255 floats) interpolated per vertex.
    pub fn triangle(&mut self, pts: [Vec3; 3], colors: [Vec3; 3]) {
        let cam = pts.map(|p| self.view.camera_space(p));
        self.triangle_in_camera_space(cam, colors);
    }

    /// World → camera space (x right, y up, z forward), for callers that
    /// transform shared vertices once per frame.
    pub fn camera_space(&self, p: Vec3) -> Vec3 {
        self.view.camera_space(p)
    }

    /// [`Self::triangle`] with vertices already in camera space.
    pub fn triangle_in_camera_space(&mut self, cam: [Vec3; 3], colors: [Vec3; 3]) {
        let near = self.view.near();
        let inside = cam.map(|c| c.z >= near);
        if inside.iter().all(|&i| i) {
            let sv = [0, 1, 2].map(|i| self.view.project(cam[i], colors[i]));
            self.fill(sv);
            return;
        }
        if !inside.iter().any(|&i| i) {
            return;
        }
        // Clip against the near plane (Sutherland–Hodgman on one plane).
        let mut poly: Vec<(Vec3, Vec3)> = Vec::with_capacity(4);
        for i in 0..3 {
            let j = (i + 1) % 3;
            let (a, b) = ((cam[i], colors[i]), (cam[j], colors[j]));
            if inside[i] {
                poly.push(a);
            }
            if inside[i] != inside[j] {
                let t = (near - a.0.z) / (b.0.z - a.0.z);
                poly.push((a.0.lerp(b.0, t), a.1.lerp(b.1, t)));
            }
        }
        let sv: Vec<ScreenVertex> = poly
            .iter()
            .map(|&(c, col)| self.view.project(c, col))
            .collect();
        for k in 1..sv.len() - 1 {
            self.fill([sv[0], sv[k], sv[k + 1]]);
        }
    }

    /// Scan-converts one projected triangle (either winding) by edge functions at
    /// pixel centres; a pixel belongs to the triangle when all three agree in sign.
    fn fill(&mut self, v: [ScreenVertex; 3]) {
        let area = edge(v[0].p, v[1].p, v[2].p);
        if area.abs() < 1e-9 || !area.is_finite() {
            return;
        }
        let min = v[0].p.min(v[1].p).min(v[2].p);
        let max = v[0].p.max(v[1].p).max(v[2].p);
        let x0 = (min.x - 0.5).ceil().max(0.0) as usize;
        let y0 = (min.y - 0.5).ceil().max(0.0) as usize;
        let x1 = ((max.x - 0.5).floor() as i64).min(self.width as i64 - 1);
        let y1 = ((max.y - 0.5).floor() as i64).min(self.height as i64 - 1);
        if x1 < x0 as i64 || y1 < y0 as i64 {
            return;
        }
        let inv_area = 1.0 / area;
        // Each barycentric weight is linear along a row: w_i(x) = k_i·x + m_i(y).
        // Solving w_i ≥ 0 for x gives the row's span, so long thin triangles cost
        // their area, not their bounding box. The span is widened by a pixel and
        // every pixel is still tested exactly, so the result does not depend on
        // the span arithmetic.
        let edges = [(v[1].p, v[2].p), (v[2].p, v[0].p), (v[0].p, v[1].p)];
        let k = edges.map(|(a, b)| -(b.y - a.y) * inv_area);
        for y in y0..=y1 as usize {
            let py = y as f32 + 0.5;
            let m = edges.map(|(a, b)| ((b.x - a.x) * (py - a.y) + (b.y - a.y) * a.x) * inv_area);
            // The span where all weights are ≥ 0, in pixel-centre coordinates.
            let (mut lo, mut hi) = (f32::NEG_INFINITY, f32::INFINITY);
            for i in 0..3 {
                if k[i] > 0.0 {
                    lo = lo.max(-m[i] / k[i]);
                } else if k[i] < 0.0 {
                    hi = hi.min(-m[i] / k[i]);
                } else if m[i] < 0.0 {
                    hi = f32::NEG_INFINITY;
                }
            }
            if lo.is_nan() || hi.is_nan() || lo > hi {
                continue;
            }
            // Pixels well inside the span are inside; the two at each end are
            // decided by the exact shared-edge test, so neighbours never leave
            // a crack between them.
            let first = (lo - 0.5).ceil();
            let last = (hi - 0.5).floor();
            let xa = (first - 1.0).max(x0 as f32) as usize;
            let xb = (last + 1.0).min(x1 as f32);
            if xb < xa as f32 {
                continue;
            }
            for x in xa..=xb as usize {
                let fx = x as f32;
                let px = fx + 0.5;
                if fx <= first + 1.0 || fx >= last - 1.0 {
                    let p = Vec2::new(px, py);
                    if shared_edge(v[1].p, v[2].p, p) * inv_area < 0.0
                        || shared_edge(v[2].p, v[0].p, p) * inv_area < 0.0
                        || shared_edge(v[0].p, v[1].p, p) * inv_area < 0.0
                    {
                        continue;
                    }
                }
                let w = [0, 1, 2].map(|i| (k[i] * px + m[i]).max(0.0));
                let sum = w[0] + w[1] + w[2];
                if sum <= 0.0 {
                    continue;
                }
                let w = w.map(|wi| wi / sum);
                let key = w[0] * v[0].key + w[1] * v[1].key + w[2] * v[2].key;
                let depth = self.view.depth_of_key(key);
                let i = y * self.width + x;
                if depth < self.depth[i] {
                    self.depth[i] = depth;
                    let c = v[0].color * w[0] + v[1].color * w[1] + v[2].color * w[2];
                    self.color[i] = pack(to_rgb(c));
                }
            }
        }
    }

    /// A depth-tested line, `thickness` pixels wide. `bias` (world units) lets a
    /// line lying on a surface show through it.
    pub fn line(&mut self, a: Vec3, b: Vec3, color: Rgb, thickness: usize, bias: f32) {
        let (ca, cb) = (self.view.camera_space(a), self.view.camera_space(b));
        self.line_in_camera_space(ca, cb, color, thickness, bias);
    }

    /// [`Self::line`] with endpoints already in camera space.
    pub fn line_in_camera_space(
        &mut self,
        mut ca: Vec3,
        mut cb: Vec3,
        color: Rgb,
        thickness: usize,
        bias: f32,
    ) {
        let near = self.view.near();
        if ca.z < near && cb.z < near {
            return;
        }
        if ca.z < near {
            ca = ca.lerp(cb, (near - ca.z) / (cb.z - ca.z));
        } else if cb.z < near {
            cb = cb.lerp(ca, (near - cb.z) / (ca.z - cb.z));
        }
        let (sa, sb) = (
            self.view.project(ca, Vec3::ZERO),
            self.view.project(cb, Vec3::ZERO),
        );
        // Clip the projected segment to the image (plus the line's width), so a
        // line reaching far off-screen costs only its visible pixels.
        let margin = thickness as f32 + 1.0;
        let Some((t0, t1)) = clip_to_rect(
            sa.p,
            sb.p,
            Vec2::splat(-margin),
            Vec2::new(self.width as f32 + margin, self.height as f32 + margin),
        ) else {
            return;
        };
        let (pa, pb) = (sa.p.lerp(sb.p, t0), sa.p.lerp(sb.p, t1));
        let (ka, kb) = (
            sa.key + (sb.key - sa.key) * t0,
            sa.key + (sb.key - sa.key) * t1,
        );
        let d = pb - pa;
        let steps = d.x.abs().max(d.y.abs()).ceil();
        if !steps.is_finite() {
            return;
        }
        let steps = steps as usize + 1;
        let packed = pack(color);
        for s in 0..steps {
            let t = if steps == 1 {
                0.0
            } else {
                s as f32 / (steps - 1) as f32
            };
            let p = pa + d * t;
            let depth = self.view.depth_of_key(ka + (kb - ka) * t);
            self.splat(p, depth, packed, thickness, bias);
        }
    }

    /// A depth-tested square dot of `size` pixels centred on a world point.
    pub fn dot(&mut self, p: Vec3, color: Rgb, size: usize, bias: f32) {
        let c = self.view.camera_space(p);
        if c.z < self.view.near() {
            return;
        }
        let s = self.view.project(c, Vec3::ZERO);
        self.splat(s.p, c.z, pack(color), size, bias);
    }

    /// Writes a `size`-pixel square at `p` where it passes the depth test.
    fn splat(&mut self, p: Vec2, depth: f32, packed: u32, size: usize, bias: f32) {
        let r = size as f32 * 0.5;
        // floor() without a libm call: shift into positive range and truncate.
        const SHIFT: f32 = 65536.0;
        let (fx, fy) = (p.x - r + 0.5, p.y - r + 0.5);
        if !(fx > -SHIFT && fy > -SHIFT && fx < SHIFT && fy < SHIFT) {
            return;
        }
        let x0 = (fx + SHIFT) as i64 - SHIFT as i64;
        let y0 = (fy + SHIFT) as i64 - SHIFT as i64;
        let (w, h) = (self.width as i64, self.height as i64);
        for y in y0.max(0)..(y0 + size as i64).min(h) {
            let row = y as usize * self.width;
            for x in x0.max(0)..(x0 + size as i64).min(w) {
                let i = row + x as usize;
                if depth - bias <= self.depth[i] {
                    self.color[i] = packed;
                    self.depth[i] = self.depth[i].min(depth);
                }
            }
        }
    }

    /// Sets a pixel without depth (HUD, crosshair).
    pub fn put(&mut self, x: i64, y: i64, color: Rgb) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.color[y as usize * self.width + x as usize] = pack(color);
        }
    }

    /// Averages `factor`×`factor` blocks (supersampling down to the output size).
    pub fn downsample(&self, factor: usize) -> Vec<u32> {
        if factor <= 1 {
            return self.color.clone();
        }
        let (w, h) = (self.width / factor, self.height / factor);
        let n = (factor * factor) as u32;
        let mut out = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0u32; 3];
                for sy in 0..factor {
                    for sx in 0..factor {
                        let c =
                            unpack(self.color[(y * factor + sy) * self.width + x * factor + sx]);
                        for k in 0..3 {
                            sum[k] += u32::from(c[k]);
                        }
                    }
                }
                out.push(pack(sum.map(|s| ((s + n / 2) / n) as u8)));
            }
        }
        out
    }
}

/// Liang–Barsky: the parameter range of segment a→b inside the box [lo, hi].
fn clip_to_rect(a: Vec2, b: Vec2, lo: Vec2, hi: Vec2) -> Option<(f32, f32)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some((t0, t1))
}

/// [`edge`] evaluated with the edge's endpoints in a canonical order, so the two
/// triangles sharing an edge get exactly opposite values at every pixel and no
/// pixel centre on the edge falls through both (no cracks between walls).
fn shared_edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    if (a.x, a.y) <= (b.x, b.y) {
        edge(a, b, p)
    } else {
        -edge(b, a, p)
    }
}

/// Twice the signed area of (a, b, p).
fn edge(a: Vec2, b: Vec2, p: Vec2) -> f32 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

fn to_rgb(c: Vec3) -> Rgb {
    // Not `round()`: that is a libm call per channel per pixel.
    [c.x, c.y, c.z].map(|v| (v.clamp(0.0, 255.0) + 0.5) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera::look_at(Vec3::new(-100.0, 0.0, 0.0), Vec3::ZERO, 90.0)
    }

    #[test]
    fn nearer_triangle_wins_whatever_the_order() {
        let far = [
            Vec3::new(0.0, -50.0, -50.0),
            Vec3::new(0.0, 50.0, -50.0),
            Vec3::new(0.0, 0.0, 50.0),
        ];
        let near = far.map(|p| p - Vec3::new(50.0, 0.0, 0.0));
        let red = [Vec3::new(255.0, 0.0, 0.0); 3];
        let blue = [Vec3::new(0.0, 0.0, 255.0); 3];
        for order in [[far, near], [near, far]] {
            let mut fb = Framebuffer::new(64, 64, &camera(), [0, 0, 0]);
            fb.triangle(order[0], if order[0] == far { red } else { blue });
            fb.triangle(order[1], if order[1] == far { red } else { blue });
            assert_eq!(unpack(fb.color[32 * 64 + 32]), [0, 0, 255]);
            let p = fb.unproject(32, 32).unwrap();
            assert!((p.x + 50.0).abs() < 1.0, "{p}");
        }
    }

    #[test]
    fn triangles_crossing_the_near_plane_are_clipped_not_dropped() {
        let cam = camera();
        let mut fb = Framebuffer::new(32, 32, &cam, [0, 0, 0]);
        // A floor reaching behind the eye.
        let tri = [
            Vec3::new(-300.0, -300.0, -10.0),
            Vec3::new(300.0, 0.0, -10.0),
            Vec3::new(-300.0, 300.0, -10.0),
        ];
        fb.triangle(tri, [Vec3::splat(200.0); 3]);
        let lit = fb.color.iter().filter(|&&c| c != 0).count();
        assert!(lit > 100, "{lit}");
        // The upper half (above the horizon) stays empty.
        assert!(fb.color[..32 * 15].iter().all(|&c| c == 0));
    }

    #[test]
    fn lines_are_hidden_behind_surfaces_unless_biased() {
        let mut fb = Framebuffer::new(64, 64, &camera(), [0, 0, 0]);
        let wall = [
            Vec3::new(0.0, -80.0, -80.0),
            Vec3::new(0.0, 80.0, -80.0),
            Vec3::new(0.0, 0.0, 80.0),
        ];
        fb.triangle(wall, [Vec3::splat(100.0); 3]);
        fb.line(
            Vec3::new(10.0, -20.0, 0.0),
            Vec3::new(10.0, 20.0, 0.0),
            [255, 0, 0],
            1,
            0.0,
        );
        assert!(!fb.color.contains(&pack([255, 0, 0])));
        fb.line(
            Vec3::new(10.0, -20.0, 0.0),
            Vec3::new(10.0, 20.0, 0.0),
            [255, 0, 0],
            1,
            20.0,
        );
        assert!(fb.color.contains(&pack([255, 0, 0])));
        fb.dot(Vec3::new(-10.0, 0.0, 30.0), [0, 255, 0], 3, 0.0);
        assert_eq!(
            fb.color.iter().filter(|&&c| c == pack([0, 255, 0])).count(),
            9
        );
    }

    #[test]
    fn lines_far_off_screen_are_clipped_not_dropped() {
        let mut fb = Framebuffer::new(64, 64, &camera(), [0, 0, 0]);
        // Crosses the whole view and reaches ~1e6 pixels beyond it on both sides.
        fb.line(
            Vec3::new(0.0, -1e6, 0.0),
            Vec3::new(0.0, 1e6, 0.0),
            [255, 0, 0],
            1,
            0.0,
        );
        let red = fb.color.iter().filter(|&&c| c == pack([255, 0, 0])).count();
        assert!((60..=70).contains(&red), "{red}");
        assert_eq!(
            clip_to_rect(
                Vec2::new(-10.0, 5.0),
                Vec2::new(-5.0, 5.0),
                Vec2::ZERO,
                Vec2::splat(10.0)
            ),
            None
        );
    }

    #[test]
    fn downsample_averages_blocks() {
        let mut fb = Framebuffer::new(4, 2, &camera(), [0, 0, 0]);
        fb.put(0, 0, [255, 255, 255]);
        fb.put(1, 1, [255, 255, 255]);
        let out = fb.downsample(2);
        assert_eq!(out.len(), 2);
        assert_eq!(unpack(out[0]), [128, 128, 128]);
        assert_eq!(out[1], 0);
    }
}
