//! The placed tiles' drawings (arrows and short streamlines, filled once
//! per key) and the velocity inside them.

use super::{EditorView, largest_flux};
use crate::editor::model::Editor;
use crate::fill::{Tile, fill_tile};
use crate::tileset::TileKey;

/// A filled tile and its drawing, in tile coordinates (0..1, y up).
pub(super) struct TileDraw {
    pub(super) tile: Tile,
    /// Arrow shafts (from, to) at 4×4 points, lengths scaled to the set.
    pub(super) arrows: Vec<([f32; 2], [f32; 2])>,
    /// Short streamlines.
    pub(super) lines: Vec<Vec<[f32; 2]>>,
}

impl TileDraw {
    fn new(set: &crate::tileset::TileSet, key: &TileKey, vscale: f64) -> TileDraw {
        let tile = fill_tile(set, key);
        let mut arrows = Vec::new();
        let k = 4;
        for j in 0..k {
            for i in 0..k {
                let p = [(i as f64 + 0.5) / k as f64, (j as f64 + 0.5) / k as f64];
                let v = tile_velocity(&tile, p);
                let s = 0.45 / k as f64 / vscale;
                let d = [v[0] * s, v[1] * s];
                arrows.push((
                    [(p[0] - d[0]) as f32, (p[1] - d[1]) as f32],
                    [(p[0] + d[0]) as f32, (p[1] + d[1]) as f32],
                ));
            }
        }
        let mut lines = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let mut p = [(i as f64 + 0.5) / 3.0, (j as f64 + 0.5) / 3.0];
                let mut line = vec![[p[0] as f32, p[1] as f32]];
                for _ in 0..14 {
                    let v = tile_velocity(&tile, p);
                    let sp = v[0].hypot(v[1]);
                    if sp < 1e-9 {
                        break;
                    }
                    let h = 0.025;
                    p = [p[0] + v[0] / sp * h, p[1] + v[1] / sp * h];
                    if !(0.0..=1.0).contains(&p[0]) || !(0.0..=1.0).contains(&p[1]) {
                        break;
                    }
                    line.push([p[0] as f32, p[1] as f32]);
                }
                if line.len() > 2 {
                    lines.push(line);
                }
            }
        }
        TileDraw {
            tile,
            arrows,
            lines,
        }
    }
}

/// Velocity inside a filled tile at local `p` in `[0, 1]²` (tile lengths
/// per unit time; one unit of flux across an edge is a speed of `f_base`):
/// face velocities interpolated linearly across each cell, so the
/// interpolant is divergence-free in every cell.
fn tile_velocity(t: &Tile, p: [f64; 2]) -> [f64; 2] {
    let n = t.n;
    let fx = (p[0] * n as f64).clamp(0.0, n as f64 - 1e-9);
    let fy = (p[1] * n as f64).clamp(0.0, n as f64 - 1e-9);
    let (i, j) = (fx as usize, fy as usize);
    let (a, b) = (fx - i as f64, fy - j as f64);
    let u = t.face_u(i, j) * (1.0 - a) + t.face_u(i + 1, j) * a;
    let v = t.face_v(i, j) * (1.0 - b) + t.face_v(i, j + 1) * b;
    [u, v]
}

impl EditorView {
    pub(super) fn refresh_tiles(&mut self, ed: &Editor) {
        if self.tiles_for == Some(ed.revision()) {
            return;
        }
        let set = ed.tiling().set();
        let vscale = largest_flux(set) as f64 * set.f_base.abs().max(1e-12);
        let (w, h) = ed.size();
        for y in 0..h {
            for x in 0..w {
                if let Some(k) = ed.tiling().tile(x, y) {
                    self.tiles
                        .entry(k)
                        .or_insert_with(|| TileDraw::new(set, &k, vscale));
                }
            }
        }
        self.tiles_for = Some(ed.revision());
    }

    /// Velocity at grid point `p` (tiles), `None` outside placed tiles.
    pub(super) fn velocity(&self, ed: &Editor, p: [f64; 2]) -> Option<[f64; 2]> {
        let (w, h) = ed.size();
        if p[0] < 0.0 || p[1] < 0.0 || p[0] >= w as f64 || p[1] >= h as f64 {
            return None;
        }
        let (x, y) = (p[0] as u32, p[1] as u32);
        let key = ed.tiling().tile(x, y)?;
        let t = &self.tiles.get(&key)?.tile;
        Some(tile_velocity(t, [p[0] - x as f64, p[1] - y as f64]))
    }
}
