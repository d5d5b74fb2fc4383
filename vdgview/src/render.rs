//! `vdgview render`: draws a scene into the software framebuffer and writes a
//! PNG. The drawing itself ([`draw_scene`]) is shared with the interactive
//! viewer.
//!
//! Render modes follow the thesis' VDGView (6.3): 1 wireframe, 2 faces coloured
//! by reduction cost, 3 faces coloured by clearance — blue large, red small.
//! Walls are grey with Lambert shading from a fixed light, seen only from their
//! free side (back faces are culled), so a camera outside the level looks
//! straight into it.

use crate::camera::Camera;
use crate::raster::{Framebuffer, Rgb, unpack};
use crate::scene::Scene;
use anyhow::{Context, Result, bail};
use glam::Vec3;
use std::path::Path;

/// How the graph is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Walls only.
    Hidden,
    /// Mode 1: graph edges, coloured by clearance.
    Wireframe,
    /// Mode 2: faces coloured by reduction cost.
    ReductionCost,
    /// Mode 3: faces coloured by clearance.
    Clearance,
}

impl Mode {
    /// The thesis' mode number (0 = graph hidden).
    pub fn from_number(n: u32) -> Option<Mode> {
        Some(match n {
            0 => Mode::Hidden,
            1 => Mode::Wireframe,
            2 => Mode::ReductionCost,
            3 => Mode::Clearance,
            _ => return None,
        })
    }
}

/// Why mode 2 cannot be drawn: `.vdg` files (versions 1 and 2) carry no per-face or
/// per-vertex reduction cost (the reduction removes vertices but does not store
/// what each removal cost).
pub const NO_REDUCTION_COST: &str = "render mode 2 (reduction cost) is not available: \
     this .vdg carries no reduction cost (the .vdg format stores none)";

/// Appearance options.
#[derive(Debug, Clone, Copy)]
pub struct Style {
    pub mode: Mode,
    pub samples: bool,
    /// Draw sky faces. Views from outside the level leave them out: an open-air
    /// level's sky would hide everything below it.
    pub sky: bool,
    /// Pixel size of sample dots and wireframe lines (scaled for supersampling).
    pub pixel: usize,
    pub background: Rgb,
}

impl Default for Style {
    fn default() -> Style {
        Style {
            mode: Mode::Clearance,
            samples: true,
            sky: true,
            pixel: 1,
            background: [28, 30, 36],
        }
    }
}

/// The direction light comes from (normalised at use).
const LIGHT: Vec3 = Vec3::new(0.35, 0.55, 0.75);
/// Sample points sit on walls: let them win depth ties up to this many units.
const SAMPLE_BIAS: f32 = 4.0;

/// Draws walls, graph and samples into `fb` (already reset for its camera).
pub fn draw_scene(fb: &mut Framebuffer, scene: &Scene, style: &Style) -> Result<()> {
    let light = LIGHT.normalize();
    for t in &scene.walls {
        if (t.sky && !style.sky) || !fb.faces_camera(t.pts[0], t.normal) {
            continue;
        }
        let lambert = t.normal.dot(light);
        let grey = 120.0 + 90.0 * lambert;
        let c = if t.sky {
            Vec3::new(grey * 0.8, grey * 0.9, grey * 1.05)
        } else {
            Vec3::splat(grey)
        };
        fb.triangle(t.pts, [c; 3]);
    }
    if let Some(g) = &scene.graph {
        match style.mode {
            Mode::Hidden => {}
            Mode::ReductionCost => bail!(NO_REDUCTION_COST),
            Mode::Clearance => {
                // Shared vertices are transformed once per frame, not per face.
                let cam: Vec<Vec3> = g.positions.iter().map(|&p| fb.camera_space(p)).collect();
                for f in &g.faces {
                    let idx = f.map(|v| v as usize);
                    fb.triangle_in_camera_space(idx.map(|i| cam[i]), idx.map(|i| g.colours[i]));
                }
            }
            Mode::Wireframe => {
                let cam: Vec<Vec3> = g.positions.iter().map(|&p| fb.camera_space(p)).collect();
                for &[a, b] in &g.edges {
                    let (a, b) = (a as usize, b as usize);
                    let c = (g.colours[a] + g.colours[b]) * 0.5;
                    fb.line_in_camera_space(
                        cam[a],
                        cam[b],
                        [c.x, c.y, c.z].map(|v| v as u8),
                        style.pixel,
                        0.0,
                    );
                }
            }
        }
    }
    if style.samples {
        for &p in &scene.samples {
            fb.dot(p, [0, 0, 0], (2 * style.pixel).max(2), SAMPLE_BIAS);
        }
    }
    Ok(())
}

/// Clearance colour: t = 0 red (small) through yellow, green, cyan to t = 1 blue
/// (large), as 0..=255 floats.
pub fn ramp(t: f32) -> Vec3 {
    let h = t.clamp(0.0, 1.0) * 4.0; // 0 red, 1 yellow, 2 green, 3 cyan, 4 blue
    let (r, g, b) = match h {
        h if h < 1.0 => (1.0, h, 0.0),
        h if h < 2.0 => (2.0 - h, 1.0, 0.0),
        h if h < 3.0 => (0.0, 1.0, h - 2.0),
        h => (0.0, 4.0 - h, 1.0),
    };
    Vec3::new(r, g, b) * 235.0 + Vec3::splat(10.0)
}

/// Where the camera comes from.
#[derive(Debug, Clone, Copy)]
pub enum View {
    /// Given by the user.
    Camera(Camera),
    /// Perspective framing of the whole map from above at an angle.
    Auto,
    /// Top-down orthographic overview.
    Top,
}

/// A headless render request.
#[derive(Debug, Clone, Copy)]
pub struct RenderRequest {
    pub width: usize,
    pub height: usize,
    /// Render at this many times the size and average down (anti-aliasing).
    pub supersample: usize,
    pub view: View,
    pub style: Style,
}

/// Renders to a `0x00RRGGBB` image of `width × height` pixels.
pub fn render(scene: &Scene, req: &RenderRequest) -> Result<Vec<u32>> {
    let ss = req.supersample.max(1);
    let (w, h) = (req.width * ss, req.height * ss);
    if req.width == 0 || req.height == 0 || w > 16384 || h > 16384 {
        bail!(
            "image size {}x{} (x{ss} supersampling) is out of range",
            req.width,
            req.height
        );
    }
    let camera = camera_for(&req.view, scene, w as f32 / h as f32);
    let mut fb = Framebuffer::new(w, h, &camera, req.style.background);
    let style = Style {
        pixel: req.style.pixel * ss,
        sky: req.style.sky && matches!(req.view, View::Camera(_)),
        ..req.style
    };
    draw_scene(&mut fb, scene, &style)?;
    // The legend is drawn at the final size, so its text stays crisp.
    let mut out = Framebuffer::new(req.width, req.height, &camera, req.style.background);
    out.color = fb.downsample(ss);
    draw_legend(&mut out, scene, &camera, &style);
    Ok(out.color)
}

/// Every picture says what it shows: for graphs coloured by clearance, a colour bar
/// with the clearance in units at its ends and middle; and a scale bar of a round
/// number of units (exact in the top view; in a perspective view it holds at the depth
/// of the map's centre, and says so).
fn draw_legend(fb: &mut Framebuffer, scene: &Scene, camera: &Camera, style: &Style) {
    use crate::hud::{CELL, rect, text};
    let white = [235, 235, 235];
    let (w, h) = (fb.width as i64, fb.height as i64);
    if w < 160 || h < 60 {
        return; // too small for a readable legend
    }
    let x0 = 8;
    let mut y = h - 8 - CELL as i64;
    // Scale bar: the largest of 1, 2, 5 × 10^k units that fits in a fifth of the width.
    let px_per_unit = match camera.projection {
        crate::camera::Projection::Orthographic { half_height } => {
            Some(fb.height as f32 / (2.0 * half_height))
        }
        crate::camera::Projection::Perspective { fov_deg } => {
            let centre = (scene.bounds.min + scene.bounds.max) * 0.5;
            let depth = (centre - camera.pos).dot(camera.basis().forward);
            (depth > 1.0)
                .then(|| fb.height as f32 / (2.0 * (fov_deg.to_radians() * 0.5).tan() * depth))
        }
    };
    if let Some(ppu) = px_per_unit.filter(|p| p.is_finite() && *p > 0.0) {
        let max_units = (fb.width as f32 / 5.0) / ppu;
        let mut units = 1.0f32;
        for k in 0..8 {
            for m in [1.0, 2.0, 5.0] {
                let u = m * 10f32.powi(k);
                if u <= max_units {
                    units = u;
                }
            }
        }
        let len = (units * ppu).round() as usize;
        let label = match camera.projection {
            crate::camera::Projection::Orthographic { .. } => format!("{units} units"),
            _ => format!("{units} units at the map centre"),
        };
        rect(fb, x0, y + 2, len, 3, white);
        rect(fb, x0, y - 2, 2, 11, white);
        rect(fb, x0 + len as i64 - 2, y - 2, 2, 11, white);
        text(fb, x0 + len as i64 + 6, y, &label, white);
        y -= 2 * CELL as i64 + 4;
    }
    if let (Some(g), Mode::Clearance | Mode::Wireframe) = (&scene.graph, style.mode) {
        let (lo, hi) = g.colour_range;
        let bar = 160usize.min(fb.width / 3);
        for i in 0..bar {
            let c = ramp(i as f32 / (bar - 1) as f32);
            rect(
                fb,
                x0 + i as i64,
                y,
                1,
                CELL,
                [c.x as u8, c.y as u8, c.z as u8],
            );
        }
        let labels = format!("{lo:.0}");
        text(fb, x0, y + CELL as i64 + 2, &labels, white);
        let hi_label = format!("{hi:.0}");
        text(
            fb,
            x0 + bar as i64 - (hi_label.len() * CELL) as i64,
            y + CELL as i64 + 2,
            &hi_label,
            white,
        );
        text(
            fb,
            x0,
            y - CELL as i64 - 2,
            "colour = clearance (units)",
            white,
        );
    }
}

/// The camera for a view of a scene.
pub fn camera_for(view: &View, scene: &Scene, aspect: f32) -> Camera {
    match view {
        View::Camera(c) => *c,
        View::Auto => Camera::framing(&scene.bounds, scene.framing_points(), 60.0, aspect),
        View::Top => Camera::top(&scene.bounds, aspect),
    }
}

/// Encodes an image as an 8-bit RGB PNG.
pub fn encode_png(pixels: &[u32], width: usize, height: usize) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width as u32, height as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().context("png header")?;
        let data: Vec<u8> = pixels.iter().flat_map(|&p| unpack(p)).collect();
        w.write_image_data(&data).context("png data")?;
    }
    Ok(out)
}

/// Writes bytes via a synced temporary sibling and a rename ([`toolbox::write_bytes_atomic`]),
/// so a reader never sees a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    toolbox::write_bytes_atomic(path, bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_runs_red_to_blue() {
        let small = ramp(0.0);
        let large = ramp(1.0);
        assert!(small.x > 200.0 && small.z < 20.0);
        assert!(large.z > 200.0 && large.x < 20.0);
        let mid = ramp(0.5);
        assert!(mid.y > 200.0);
    }

    #[test]
    fn png_round_trips() {
        let px = vec![0x00ff0000, 0x0000ff00, 0x000000ff, 0x00ffffff];
        let bytes = encode_png(&px, 2, 2).unwrap();
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (2, 2));
        assert_eq!(&buf[..6], &[255, 0, 0, 0, 255, 0]);
    }
}
