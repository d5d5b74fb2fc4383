//! `--frames DIR`: a contact sheet per replay: what the spectator would see from each
//! camera (rows) at evenly spaced moments of the longest route (columns), rendered by
//! vdgview's own software rasterizer with the followed player drawn as a red box.
//! A cell's caption gives the camera, the time and whether the target's eye is
//! visible (BSP trace); a camera inside a wall shows the wall's inside, as it would.

use super::Report;
use super::route::TargetState;
use crate::camera::Camera;
use crate::hud;
use crate::raster::Framebuffer;
use crate::render::{Mode, Style, draw_scene};
use crate::scene::Scene;
use anyhow::Result;
use glam::Vec3;
use std::path::Path;

/// Size of one cell.
const CW: usize = 320;
const CH: usize = 240;
/// Vertical field of view of the spectator (90° × 74° at 4:3).
const FOV_Y: f32 = 74.0;

/// Draws the player's hull as a red box.
fn draw_player(fb: &mut Framebuffer, t: &TargetState) {
    let o = Vec3::from(t.origin);
    let s = t.stance();
    let (lo, hi) = (s.mins.map(|x| x as f32), s.maxs.map(|x| x as f32));
    let c = |i: usize| {
        o + Vec3::new(
            if i & 1 == 1 { hi[0] } else { lo[0] },
            if i & 2 == 2 { hi[1] } else { lo[1] },
            if i & 4 == 4 { hi[2] } else { lo[2] },
        )
    };
    let faces = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    for (k, f) in faces.iter().enumerate() {
        let shade = 150.0 + 20.0 * k as f32;
        let col = [Vec3::new(shade + 50.0, 30.0, 30.0); 3];
        fb.triangle([c(f[0]), c(f[1]), c(f[2])], col);
        fb.triangle([c(f[0]), c(f[2]), c(f[3])], col);
    }
}

/// Writes `DIR/contact-sheet.png`: `columns` moments × every camera.
pub fn contact_sheet(report: &Report, scene: &Scene, dir: &Path, columns: usize) -> Result<()> {
    std::fs::create_dir_all(dir)?;
    let k = (0..report.routes.routes.len())
        .max_by_key(|&i| report.cameras.first().map_or(0, |c| c.routes[i].len()))
        .unwrap_or(0);
    let states = report.routes.routes[k].resample(report.dt);
    let n = states.len();
    let rows = report.cameras.len();
    let (w, h) = (CW * columns, CH * rows);
    let mut sheet = vec![0u32; w * h];
    let style = Style {
        mode: Mode::Hidden,
        samples: false,
        ..Style::default()
    };
    for (ri, cam) in report.cameras.iter().enumerate() {
        let ms = &cam.routes[k];
        for col in 0..columns {
            let i = ((col as f64 + 0.5) / columns as f64 * n as f64) as usize;
            let (Some(m), Some(t)) = (ms.get(i), states.get(i)) else {
                continue;
            };
            let eye = Vec3::from(m.eye);
            let look = Vec3::from(t.origin);
            let view = if (look - eye).length() < 1.0 {
                Camera::look_at(eye, eye + Vec3::from(t.heading()), FOV_Y)
            } else {
                Camera::look_at(eye, look, FOV_Y)
            };
            let mut fb = Framebuffer::new(CW, CH, &view, style.background);
            draw_scene(&mut fb, scene, &style)?;
            draw_player(&mut fb, t);
            let caption = format!(
                "{} t={:.1}s {}{}",
                cam.name,
                m.t,
                if m.eye_visible { "seen" } else { "HIDDEN" },
                if m.solid { " IN WALL" } else { "" }
            );
            hud::text(&mut fb, 4, 4, &caption, [255, 255, 255]);
            for y in 0..CH {
                let dst = (ri * CH + y) * w + col * CW;
                sheet[dst..dst + CW].copy_from_slice(&fb.color[y * CW..(y + 1) * CW]);
            }
        }
    }
    let png = crate::render::encode_png(&sheet, w, h)?;
    crate::render::write_atomic(&dir.join("contact-sheet.png"), &png)
}
