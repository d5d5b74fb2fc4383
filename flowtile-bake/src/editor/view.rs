//! Drawing the editor with egui: the grid over an optional background,
//! tiles as arrows or streamlines, particles moving through the placed
//! tiles, the tools, the palette of the selected slot (allowed tiles and the
//! greyed ones with the reason), undo/redo, save and bake.
//!
//! Everything goes through [`EditorView::ui`], which takes an [`egui::Ui`]:
//! the window (`app`, feature `window`) calls it every frame, and
//! [`screenshot`] runs it without a display and rasterises egui's output on
//! the CPU, so a scripted session's picture is the same bytes every time.

use std::collections::HashMap;
use std::path::PathBuf;

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Ui, Vec2, pos2, vec2};

use super::commands::{Command, TileChoice, TileStyle, ViewSettings};
use super::model::{Editor, Origin, Palette};
use crate::fill::{Tile, fill_tile};
use crate::rng::Rng;
use crate::tileset::TileKey;
use crate::tiling::{Border, Edge};

/// A picture under the grid: RGB rows top first, spanning the whole grid.
#[derive(Clone, Debug, PartialEq)]
pub struct Background {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGB bytes, rows top first.
    pub rgb: Vec<u8>,
}

impl Background {
    /// Reads a PNG (RGB or RGBA, 8 bits).
    pub fn read_png(path: &std::path::Path) -> Result<Background, String> {
        let file = std::fs::File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let mut dec = png::Decoder::new(std::io::BufReader::new(file));
        dec.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
        let mut reader = dec
            .read_info()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| format!("{}: image too large", path.display()))?;
        let mut buf = vec![0; size];
        let info = reader
            .next_frame(&mut buf)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        let px = (info.width * info.height) as usize;
        let rgb = match info.color_type {
            png::ColorType::Rgb => buf[..px * 3].to_vec(),
            png::ColorType::Rgba => buf[..px * 4]
                .chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect(),
            png::ColorType::Grayscale => buf[..px].iter().flat_map(|&g| [g, g, g]).collect(),
            png::ColorType::GrayscaleAlpha => buf[..px * 2]
                .chunks_exact(2)
                .flat_map(|p| [p[0], p[0], p[0]])
                .collect(),
            other => {
                return Err(format!(
                    "{}: unsupported colour type {other:?}",
                    path.display()
                ));
            }
        };
        Ok(Background {
            width: info.width,
            height: info.height,
            rgb,
        })
    }
}

/// What a click on the grid does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Select a slot and open its palette; right click clears a tile.
    Tiles,
    /// Paint blocked slots.
    Block,
    /// Erase blocked slots.
    Open,
    /// Fix (or free) the flux of the clicked edge.
    Flux,
    /// Fix (or free) the velocity of the clicked vertex.
    Corner,
}

/// A filled tile and its drawing, in tile coordinates (0..1, y up).
struct TileDraw {
    tile: Tile,
    /// Arrow shafts (from, to) at 4×4 points, lengths scaled to the set.
    arrows: Vec<([f32; 2], [f32; 2])>,
    /// Short streamlines.
    lines: Vec<Vec<[f32; 2]>>,
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

/// Particles advected through the placed tiles, a function of time only
/// (fixed steps from a fixed seed), so a screenshot at time `t` is
/// reproducible.
struct Particles {
    pos: Vec<[f64; 2]>,
    age: Vec<f64>,
    rng: Rng,
    steps: u64,
}

/// Particle step in seconds.
const PARTICLE_DT: f64 = 1.0 / 30.0;
/// Particle lifetime in seconds.
const PARTICLE_LIFE: f64 = 4.0;

impl Particles {
    fn new() -> Particles {
        Particles {
            pos: Vec::new(),
            age: Vec::new(),
            rng: Rng::new(1),
            steps: 0,
        }
    }
}

/// The editor's view state and drawing.
pub struct EditorView {
    /// Settings scripts can set.
    pub settings: ViewSettings,
    /// The current tool.
    pub tool: Tool,
    /// Flux the flux tool fixes (`None`: frees the edge).
    pub flux_value: Option<i32>,
    /// Velocity index the corner tool fixes (`None`: frees the vertex).
    pub corner_value: Option<u16>,
    /// Where "save" writes the spec.
    pub save_path: PathBuf,
    /// Where "bake" writes the tiling.
    pub bake_path: PathBuf,
    /// True when the last status message is an error.
    pub status_is_error: bool,
    background: Option<Background>,
    bg_texture: Option<egui::TextureHandle>,
    palette: Option<(u64, (u32, u32), Palette)>,
    pick: Option<[i32; 4]>,
    pick_corners: [u16; 4],
    tiles: HashMap<TileKey, TileDraw>,
    tiles_for: Option<u64>,
    particles: Particles,
    /// Undo depth when the current paint stroke began.
    stroke: Option<usize>,
}

impl EditorView {
    /// A view writing to `save_path` and `bake_path`.
    pub fn new(save_path: PathBuf, bake_path: PathBuf, background: Option<Background>) -> Self {
        EditorView {
            settings: ViewSettings::default(),
            tool: Tool::Tiles,
            flux_value: Some(1),
            corner_value: Some(0),
            save_path,
            bake_path,
            status_is_error: false,
            background,
            bg_texture: None,
            palette: None,
            pick: None,
            pick_corners: [0; 4],
            tiles: HashMap::new(),
            tiles_for: None,
            particles: Particles::new(),
            stroke: None,
        }
    }

    /// Runs a command from the UI and shows its message.
    pub fn run(&mut self, ed: &mut Editor, cmd: Command) {
        match cmd.apply(ed, &mut self.settings) {
            Ok(msg) => {
                self.settings.status = msg;
                self.status_is_error = false;
            }
            Err(e) => {
                self.settings.status = format!("{cmd}: {e}");
                self.status_is_error = true;
            }
        }
    }

    /// The palette of the selected slot, recomputed after edits.
    fn current_palette(&mut self, ed: &Editor) -> Option<&Palette> {
        let slot = self.settings.selected?;
        let fresh =
            matches!(&self.palette, Some((rev, s, _)) if *rev == ed.revision() && *s == slot);
        if !fresh {
            self.palette = ed
                .palette(slot.0, slot.1)
                .ok()
                .map(|p| (ed.revision(), slot, p));
            let p = self.palette.as_ref().map(|(_, _, p)| p);
            let keep = p.is_some_and(|p| {
                self.pick
                    .is_some_and(|f| p.allowed_fluxes().any(|a| a == f))
            });
            if !keep {
                self.pick = p.and_then(|p| p.allowed_fluxes().next());
            }
            if let Some(p) = p {
                for k in 0..4 {
                    let ok = |c: u16| {
                        p.corners[k]
                            .iter()
                            .any(|o| o.index == c && o.why_not.is_none())
                    };
                    if !ok(self.pick_corners[k]) {
                        self.pick_corners[k] = p.corners[k]
                            .iter()
                            .find(|o| o.why_not.is_none())
                            .map_or(0, |o| o.index);
                    }
                }
            }
        }
        self.palette.as_ref().map(|(_, _, p)| p)
    }

    fn refresh_tiles(&mut self, ed: &Editor) {
        if self.tiles_for == Some(ed.revision()) {
            return;
        }
        let set = ed.tiling().set();
        let vscale = set
            .mx
            .min
            .abs()
            .max(set.mx.max.abs())
            .max(set.my.min.abs())
            .max(set.my.max.abs())
            .max(1) as f64
            * set.f_base.abs().max(1e-12);
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
    fn velocity(&self, ed: &Editor, p: [f64; 2]) -> Option<[f64; 2]> {
        let (w, h) = ed.size();
        if p[0] < 0.0 || p[1] < 0.0 || p[0] >= w as f64 || p[1] >= h as f64 {
            return None;
        }
        let (x, y) = (p[0] as u32, p[1] as u32);
        let key = ed.tiling().tile(x, y)?;
        let t = &self.tiles.get(&key)?.tile;
        Some(tile_velocity(t, [p[0] - x as f64, p[1] - y as f64]))
    }

    /// Advances the particles to time `t` (re-running from zero when `t`
    /// lies before the current time).
    fn advance_particles(&mut self, ed: &Editor, t: f64) {
        let target = (t / PARTICLE_DT).round() as u64;
        let (w, h) = ed.size();
        let want = ((w * h) as usize * 3).clamp(60, 2500);
        if target < self.particles.steps || self.particles.pos.len() != want {
            self.particles = Particles::new();
            for _ in 0..want {
                let p = [
                    self.particles.rng.unit() * w as f64,
                    self.particles.rng.unit() * h as f64,
                ];
                let age = self.particles.rng.unit() * PARTICLE_LIFE;
                self.particles.pos.push(p);
                self.particles.age.push(age);
            }
        }
        // At most 10 s of catching up per frame.
        let first = self.particles.steps.max(target.saturating_sub(300));
        for _ in first..target {
            for i in 0..self.particles.pos.len() {
                let p = self.particles.pos[i];
                let moved = self.velocity(ed, p).and_then(|v| {
                    let mid = [
                        p[0] + v[0] * PARTICLE_DT / 2.0,
                        p[1] + v[1] * PARTICLE_DT / 2.0,
                    ];
                    let v2 = self.velocity(ed, mid)?;
                    Some([p[0] + v2[0] * PARTICLE_DT, p[1] + v2[1] * PARTICLE_DT])
                });
                self.particles.age[i] += PARTICLE_DT;
                let rng = &mut self.particles.rng;
                let (rx, ry) = (rng.unit(), rng.unit());
                match moved {
                    Some(q) if self.particles.age[i] < PARTICLE_LIFE => self.particles.pos[i] = q,
                    _ => {
                        self.particles.pos[i] = [rx * w as f64, ry * h as f64];
                        self.particles.age[i] = 0.0;
                    }
                }
            }
        }
        self.particles.steps = target;
    }

    /// Draws the whole editor into `ui` and handles its input.
    pub fn ui(&mut self, ui: &mut Ui, ed: &mut Editor) {
        self.keys(ui, ed);
        egui::Panel::top("toolbar").show_inside(ui, |ui| self.toolbar(ui, ed));
        egui::Panel::bottom("status").show_inside(ui, |ui| self.status_bar(ui, ed));
        egui::Panel::left("tools")
            .exact_size(215.0)
            .show_inside(ui, |ui| self.tools(ui, ed));
        egui::Panel::right("palette")
            .exact_size(300.0)
            .show_inside(ui, |ui| self.palette_panel(ui, ed));
        egui::CentralPanel::default().show_inside(ui, |ui| self.grid(ui, ed));
    }

    fn keys(&mut self, ui: &mut Ui, ed: &mut Editor) {
        let (undo, redo, save, fill, clear, esc) = ui.input(|i| {
            let cmd = i.modifiers.command;
            (
                cmd && !i.modifiers.shift && i.key_pressed(egui::Key::Z),
                cmd && (i.key_pressed(egui::Key::Y)
                    || (i.modifiers.shift && i.key_pressed(egui::Key::Z))),
                cmd && i.key_pressed(egui::Key::S),
                !cmd && i.key_pressed(egui::Key::F),
                i.key_pressed(egui::Key::Delete),
                i.key_pressed(egui::Key::Escape),
            )
        });
        if ui.ctx().egui_wants_keyboard_input() {
            return;
        }
        if undo {
            self.run(ed, Command::Undo);
        }
        if redo {
            self.run(ed, Command::Redo);
        }
        if save {
            self.run(ed, Command::Save(self.save_path.clone()));
        }
        if fill {
            self.run(ed, Command::Fill(None));
        }
        if clear && let Some(s) = self.settings.selected {
            self.run(ed, Command::Clear(s, s));
        }
        if esc {
            self.settings.selected = None;
        }
    }

    fn toolbar(&mut self, ui: &mut Ui, ed: &mut Editor) {
        ui.horizontal(|ui| {
            if ui
                .button("Fill (F)")
                .on_hover_text("fill the empty slots at random with the spec's preferences")
                .clicked()
            {
                self.run(ed, Command::Fill(None));
            }
            if ui.button("Clear fill").clicked() {
                self.run(ed, Command::ClearFill);
            }
            let (u, r) = ed.history();
            if ui
                .add_enabled(u > 0, egui::Button::new("Undo"))
                .on_hover_text("Ctrl+Z")
                .clicked()
            {
                self.run(ed, Command::Undo);
            }
            if ui
                .add_enabled(r > 0, egui::Button::new("Redo"))
                .on_hover_text("Ctrl+Y")
                .clicked()
            {
                self.run(ed, Command::Redo);
            }
            ui.separator();
            if ui
                .button("Save spec")
                .on_hover_text(self.save_path.display().to_string())
                .clicked()
            {
                self.run(ed, Command::Save(self.save_path.clone()));
            }
            if ui
                .add_enabled(ed.tiling().is_complete(), egui::Button::new("Bake .ftb"))
                .on_hover_text(self.bake_path.display().to_string())
                .clicked()
            {
                self.run(ed, Command::Bake(self.bake_path.clone()));
            }
            ui.separator();
            ui.label("tiles as");
            ui.selectable_value(&mut self.settings.style, TileStyle::Arrows, "arrows");
            ui.selectable_value(
                &mut self.settings.style,
                TileStyle::Streamlines,
                "streamlines",
            );
            ui.checkbox(&mut self.settings.particles, "particles");
        });
    }

    fn status_bar(&mut self, ui: &mut Ui, ed: &Editor) {
        ui.horizontal(|ui| {
            let color = if self.status_is_error {
                Color32::from_rgb(200, 40, 30)
            } else {
                ui.visuals().text_color()
            };
            let (u, r) = ed.history();
            let (w, h) = ed.size();
            ui.label(format!(
                "{w}x{h} grid, {} open, {} empty, {} distinct tiles | undo {u}, redo {r}{} |",
                ed.tiling().open_slots(),
                ed.empty_slots(),
                ed.tiling().tiles_used().len(),
                if ed.is_modified() { " | modified" } else { "" },
            ));
            ui.colored_label(color, &self.settings.status);
        });
    }

    fn tools(&mut self, ui: &mut Ui, ed: &mut Editor) {
        ui.heading("Tools");
        for (t, name, tip) in [
            (
                Tool::Tiles,
                "Tiles",
                "click a slot: its palette; right click: clear its tile",
            ),
            (Tool::Block, "Paint wall", "drag: block slots (no flow)"),
            (Tool::Open, "Erase wall", "drag: open blocked slots"),
            (
                Tool::Flux,
                "Edge flux",
                "click an edge: fix its flux (towards +x / +y)",
            ),
            (
                Tool::Corner,
                "Corner velocity",
                "click a vertex: fix its velocity",
            ),
        ] {
            ui.selectable_value(&mut self.tool, t, name)
                .on_hover_text(tip);
        }
        ui.separator();
        let set = ed.tiling().set().clone();
        ui.label("Edge flux to fix");
        ui.horizontal(|ui| {
            let mut free = self.flux_value.is_none();
            ui.checkbox(&mut free, "free");
            let mut v = self.flux_value.unwrap_or(1);
            ui.add_enabled(
                !free,
                egui::DragValue::new(&mut v)
                    .range(set.mx.min.min(set.my.min)..=set.mx.max.max(set.my.max)),
            );
            self.flux_value = (!free).then_some(v);
        });
        ui.label("Corner velocity to fix");
        ui.horizontal(|ui| {
            let mut free = self.corner_value.is_none();
            ui.checkbox(&mut free, "free");
            let mut v = self.corner_value.unwrap_or(0);
            ui.add_enabled(
                !free,
                egui::DragValue::new(&mut v).range(0..=set.corners.len() as u16 - 1),
            );
            self.corner_value = (!free).then_some(v);
            if let Some(c) = set.corners.get(v as usize) {
                ui.label(format!("({:.2}, {:.2})", c[0], c[1]));
            }
        });
        ui.separator();
        ui.heading("Borders");
        let c = ed.problem().conditions.clone();
        for (x_axis, label, cur) in [
            (true, "left/right", c.border_x),
            (false, "bottom/top", c.border_y),
        ] {
            ui.horizontal(|ui| {
                ui.label(label);
                for (b, name) in [
                    (Border::Free, "free"),
                    (Border::Zero, "wall"),
                    (Border::Periodic, "wrap"),
                ] {
                    if ui.selectable_label(cur == b, name).clicked() && cur != b {
                        self.run(ed, Command::Border { x_axis, border: b });
                    }
                }
            });
        }
        ui.separator();
        ui.heading("Fill");
        let p = ed.problem().clone();
        let mut seed = p.seed;
        ui.horizontal(|ui| {
            ui.label("seed");
            if ui.add(egui::DragValue::new(&mut seed)).changed() {
                self.run(ed, Command::Seed(seed));
            }
        });
        let mut straight = p.preferences.straight;
        ui.horizontal(|ui| {
            ui.label("favour straight");
            let r = ui.add(
                egui::DragValue::new(&mut straight)
                    .range(0.0..=100.0)
                    .speed(0.1),
            );
            if r.drag_stopped() || (r.changed() && !r.dragged()) {
                self.run(ed, Command::Straight(straight));
            }
        });
        let mut reuse = p.preferences.reuse;
        ui.horizontal(|ui| {
            ui.label("favour reuse");
            let r = ui.add(
                egui::DragValue::new(&mut reuse)
                    .range(0.0..=100.0)
                    .speed(0.1),
            );
            if r.drag_stopped() || (r.changed() && !r.dragged()) {
                self.run(ed, Command::Reuse(reuse));
            }
        });
        ui.label(format!(
            "{} main direction regions",
            p.preferences.regions.len()
        ));
        if !p.preferences.regions.is_empty() && ui.button("clear directions").clicked() {
            self.run(ed, Command::ClearDirections);
        }
    }

    fn palette_panel(&mut self, ui: &mut Ui, ed: &mut Editor) {
        let Some((x, y)) = self.settings.selected else {
            ui.heading("Palette");
            ui.label("Click a slot with the Tiles tool to see the tiles that keep the tiling completable there.");
            return;
        };
        let Some(p) = self.current_palette(ed).cloned() else {
            ui.heading(format!("Slot ({x}, {y})"));
            ui.label("blocked: no tile");
            return;
        };
        ui.heading(format!("Slot ({x}, {y})"));
        if let Some((k, o)) = ed.slot(x, y) {
            ui.label(format!(
                "holds {k} ({})",
                if o == Origin::Designer {
                    "placed"
                } else {
                    "filled"
                }
            ));
        }
        let allowed = p.allowed_fluxes().count();
        ui.label(format!(
            "{} tiles allowed: {allowed} of {} flux tuples",
            p.allowed_count(),
            p.fluxes.len()
        ));
        let set = ed.tiling().set().clone();
        let fmax = set
            .mx
            .min
            .abs()
            .max(set.mx.max.abs())
            .max(set.my.min.abs())
            .max(set.my.max.abs())
            .max(1);
        egui::ScrollArea::vertical()
            .max_height(ui.available_height() - 240.0)
            .show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
                    // Allowed first, then greyed.
                    let mut order: Vec<&super::model::FluxChoice> = p.fluxes.iter().collect();
                    order.sort_by_key(|c| c.why_not.is_some());
                    for c in order {
                        let (rect, resp) = ui.allocate_exact_size(vec2(40.0, 40.0), Sense::click());
                        let picked = self.pick == Some(c.fluxes);
                        flux_icon(
                            ui.painter(),
                            rect,
                            c.fluxes,
                            fmax,
                            c.why_not.is_none(),
                            picked,
                        );
                        let resp = match c.why_not {
                            None => resp.on_hover_text(format!(
                                "L {} B {} R {} T {}: allowed",
                                c.fluxes[0], c.fluxes[1], c.fluxes[2], c.fluxes[3]
                            )),
                            Some(why) => resp.on_hover_text(format!(
                                "L {} B {} R {} T {}: {why}",
                                c.fluxes[0], c.fluxes[1], c.fluxes[2], c.fluxes[3]
                            )),
                        };
                        if c.why_not.is_none() && resp.clicked() {
                            self.pick = Some(c.fluxes);
                        }
                        if c.why_not.is_none() && resp.double_clicked() {
                            self.place_pick(ed, (x, y));
                        }
                    }
                });
            });
        ui.separator();
        // Why the others are greyed, grouped by reason.
        let mut reasons: Vec<(String, usize)> = Vec::new();
        for c in p.fluxes.iter() {
            if let Some(w) = c.why_not {
                let text = w.to_string();
                match reasons.iter_mut().find(|(t, _)| *t == text) {
                    Some(r) => r.1 += 1,
                    None => reasons.push((text, 1)),
                }
            }
        }
        ui.label("Greyed:");
        for (text, n) in reasons.iter().take(4) {
            ui.colored_label(Color32::from_gray(110), format!("{n} × {text}"));
        }
        ui.separator();
        let names = ["bottom-left", "bottom-right", "top-right", "top-left"];
        for (k, name) in names.iter().enumerate() {
            ui.horizontal(|ui| {
                ui.label(format!("{name} corner"));
                for o in &p.corners[k] {
                    let sel = self.pick_corners[k] == o.index;
                    let b = ui.add_enabled(
                        o.why_not.is_none(),
                        egui::Button::selectable(sel, o.index.to_string()),
                    );
                    let b = match o.why_not {
                        Some(w) => b.on_disabled_hover_text(w.to_string()),
                        None => b,
                    };
                    if b.clicked() {
                        self.pick_corners[k] = o.index;
                    }
                }
            });
        }
        ui.horizontal(|ui| {
            if ui
                .add_enabled(self.pick.is_some(), egui::Button::new("Place"))
                .clicked()
            {
                self.place_pick(ed, (x, y));
            }
            if ui
                .add_enabled(ed.slot(x, y).is_some(), egui::Button::new("Clear tile"))
                .clicked()
            {
                self.run(ed, Command::Clear((x, y), (x, y)));
            }
        });
    }

    fn place_pick(&mut self, ed: &mut Editor, slot: (u32, u32)) {
        if let Some(f) = self.pick {
            self.run(
                ed,
                Command::Place(slot, TileChoice::Key(f, Some(self.pick_corners))),
            );
        }
    }

    fn grid(&mut self, ui: &mut Ui, ed: &mut Editor) {
        self.refresh_tiles(ed);
        if self.settings.particles {
            self.advance_particles(ed, self.settings.time);
        }
        let (w, h) = ed.size();
        let avail = ui.available_rect_before_wrap();
        let s = ((avail.width() - 8.0) / w as f32)
            .min((avail.height() - 8.0) / h as f32)
            .max(1.0);
        let size = vec2(s * w as f32, s * h as f32);
        let origin = avail.center() - size / 2.0;
        let rect = Rect::from_min_size(origin, size);
        let resp = ui.allocate_rect(rect, Sense::click_and_drag());
        let painter = ui.painter_at(rect.expand(4.0));
        let to = |u: f64, v: f64| {
            pos2(
                origin.x + u as f32 * s,
                origin.y + (h as f64 - v) as f32 * s,
            )
        };
        let slot_rect = |x: u32, y: u32| {
            Rect::from_min_max(to(x as f64, y as f64 + 1.0), to(x as f64 + 1.0, y as f64))
        };
        // Background.
        if let Some(bg) = &self.background {
            let tex = self.bg_texture.get_or_insert_with(|| {
                let img =
                    egui::ColorImage::from_rgb([bg.width as usize, bg.height as usize], &bg.rgb);
                ui.ctx()
                    .load_texture("background", img, egui::TextureOptions::LINEAR)
            });
            painter.image(
                tex.id(),
                rect,
                Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0)),
                Color32::WHITE,
            );
        } else {
            painter.rect_filled(rect, 0.0, Color32::from_rgb(246, 246, 242));
        }
        let alpha = if self.background.is_some() { 110 } else { 255 };
        for y in 0..h {
            for x in 0..w {
                let r = slot_rect(x, y);
                if ed.tiling().is_blocked(x, y) {
                    painter.rect_filled(
                        r,
                        0.0,
                        Color32::from_rgba_unmultiplied(
                            95,
                            95,
                            100,
                            if self.background.is_some() { 150 } else { 255 },
                        ),
                    );
                } else if let Some((_, o)) = ed.slot(x, y) {
                    let c = if o == Origin::Designer {
                        Color32::from_rgba_unmultiplied(200, 222, 255, alpha)
                    } else {
                        Color32::from_rgba_unmultiplied(250, 250, 247, alpha)
                    };
                    painter.rect_filled(r, 0.0, c);
                } else if self.background.is_none() {
                    painter.rect_filled(r, 0.0, Color32::from_rgb(232, 232, 226));
                }
            }
        }
        // Grid lines.
        let line = Stroke::new(
            if s > 6.0 { 1.0 } else { 0.5 },
            Color32::from_rgba_unmultiplied(150, 155, 175, 160),
        );
        for x in 0..=w {
            painter.line_segment([to(x as f64, 0.0), to(x as f64, h as f64)], line);
        }
        for y in 0..=h {
            painter.line_segment([to(0.0, y as f64), to(w as f64, y as f64)], line);
        }
        // Tiles.
        let ink = Color32::from_rgb(25, 60, 130);
        for y in 0..h {
            for x in 0..w {
                let Some(k) = ed.tiling().tile(x, y) else {
                    continue;
                };
                let Some(d) = self.tiles.get(&k) else {
                    continue;
                };
                let at = |p: [f32; 2]| to(x as f64 + p[0] as f64, y as f64 + p[1] as f64);
                match self.settings.style {
                    TileStyle::Arrows => {
                        let step = if s >= 48.0 {
                            1
                        } else if s >= 20.0 {
                            2
                        } else {
                            16
                        };
                        for (i, (a, b)) in d.arrows.iter().enumerate() {
                            if step == 16 && i != 5 || step == 2 && (i % 2 == 1 || (i / 4) % 2 == 1)
                            {
                                continue;
                            }
                            let (pa, pb) = (at(*a), at(*b));
                            let (pa, pb) = if step == 1 {
                                (pa, pb)
                            } else {
                                let c = pa + (pb - pa) / 2.0;
                                let half = (pb - pa) * step as f32 / 2.0;
                                (c - half / 1.3, c + half / 1.3)
                            };
                            arrow(&painter, pa, pb, ink);
                        }
                    }
                    TileStyle::Streamlines => {
                        for l in &d.lines {
                            let pts: Vec<Pos2> = l.iter().map(|&p| at(p)).collect();
                            painter.add(egui::Shape::line(pts, Stroke::new(1.2, ink)));
                        }
                    }
                }
            }
        }
        // Fixed fluxes and corners of the spec.
        let c = ed.problem().conditions.clone();
        for &(e, m) in &c.fluxes {
            let (a, b, n) = match e {
                Edge::Vertical { x, y } => (
                    to(x as f64, y as f64),
                    to(x as f64, y as f64 + 1.0),
                    vec2(1.0, 0.0),
                ),
                Edge::Horizontal { x, y } => (
                    to(x as f64, y as f64),
                    to(x as f64 + 1.0, y as f64),
                    vec2(0.0, -1.0),
                ),
            };
            let col = Color32::from_rgb(220, 90, 20);
            painter.line_segment([a, b], Stroke::new(3.0, col));
            let mid = a + (b - a) / 2.0;
            if m != 0 {
                let len = (s * 0.3).clamp(6.0, 16.0) * m.signum() as f32;
                arrow(&painter, mid - n * len, mid + n * len, col);
            }
            if s >= 18.0 {
                painter.text(
                    mid + vec2(3.0, -3.0),
                    Align2::LEFT_BOTTOM,
                    m.to_string(),
                    FontId::proportional(11.0),
                    col,
                );
            }
        }
        for &((x, y), v) in &c.corners {
            painter.circle_filled(
                to(x as f64, y as f64),
                (s * 0.12).clamp(2.5, 5.0),
                Color32::from_rgb(150, 40, 160),
            );
            if s >= 18.0 {
                painter.text(
                    to(x as f64, y as f64) + vec2(4.0, 2.0),
                    Align2::LEFT_TOP,
                    v.to_string(),
                    FontId::proportional(11.0),
                    Color32::from_rgb(150, 40, 160),
                );
            }
        }
        // Particles.
        if self.settings.particles {
            let r = (s * 0.04).clamp(1.0, 2.2);
            for p in &self.particles.pos {
                if self.velocity(ed, *p).is_some() {
                    painter.circle_filled(to(p[0], p[1]), r, Color32::from_rgb(230, 60, 40));
                }
            }
        }
        // Selection.
        if let Some((x, y)) = self.settings.selected
            && x < w
            && y < h
        {
            painter.rect_stroke(
                slot_rect(x, y),
                0.0,
                Stroke::new(2.5, Color32::from_rgb(255, 190, 0)),
                egui::StrokeKind::Middle,
            );
        }
        // Input. A painted stroke is one undo step.
        if matches!(self.tool, Tool::Block | Tool::Open) && resp.drag_started() {
            self.stroke = Some(ed.history().0);
        }
        if resp.drag_stopped()
            && let Some(mark) = self.stroke.take()
        {
            ed.squash_undo(mark);
        }
        let Some(pos) = resp.interact_pointer_pos().or(resp.hover_pos()) else {
            return;
        };
        let u = ((pos.x - origin.x) / s) as f64;
        let v = h as f64 - ((pos.y - origin.y) / s) as f64;
        let slot =
            (u >= 0.0 && v >= 0.0 && u < w as f64 && v < h as f64).then_some((u as u32, v as u32));
        let pressed = resp.clicked() || resp.dragged();
        match self.tool {
            Tool::Tiles => {
                if let Some(sl) = slot {
                    if resp.clicked() {
                        self.settings.selected = Some(sl);
                    }
                    if resp.secondary_clicked() {
                        self.run(ed, Command::Clear(sl, sl));
                    }
                }
            }
            Tool::Block | Tool::Open => {
                if let Some(sl) = slot
                    && pressed
                {
                    let blocked = self.tool == Tool::Block;
                    if ed.tiling().is_blocked(sl.0, sl.1) != blocked {
                        self.run(
                            ed,
                            Command::Mask {
                                from: sl,
                                to: sl,
                                blocked,
                            },
                        );
                    }
                }
            }
            Tool::Flux => {
                let e = nearest_edge(u, v, w, h);
                let (a, b) = match e {
                    Edge::Vertical { x, y } => {
                        (to(x as f64, y as f64), to(x as f64, y as f64 + 1.0))
                    }
                    Edge::Horizontal { x, y } => {
                        (to(x as f64, y as f64), to(x as f64 + 1.0, y as f64))
                    }
                };
                painter.line_segment(
                    [a, b],
                    Stroke::new(3.0, Color32::from_rgba_unmultiplied(220, 90, 20, 120)),
                );
                if resp.clicked() {
                    self.run(ed, Command::Flux(e, self.flux_value));
                }
            }
            Tool::Corner => {
                let (x, y) = (
                    u.round().clamp(0.0, w as f64) as u32,
                    v.round().clamp(0.0, h as f64) as u32,
                );
                painter.circle_stroke(
                    to(x as f64, y as f64),
                    6.0,
                    Stroke::new(2.0, Color32::from_rgb(150, 40, 160)),
                );
                if resp.clicked() {
                    self.run(ed, Command::Corner((x, y), self.corner_value));
                }
            }
        }
    }
}

/// The grid edge nearest to point `(u, v)` (tile units).
fn nearest_edge(u: f64, v: f64, w: u32, h: u32) -> Edge {
    let (fx, fy) = (u - u.floor(), v - v.floor());
    let dv = fx.min(1.0 - fx);
    let dh = fy.min(1.0 - fy);
    if dv <= dh {
        Edge::Vertical {
            x: u.round().clamp(0.0, w as f64) as u32,
            y: v.floor().clamp(0.0, h as f64 - 1.0) as u32,
        }
    } else {
        Edge::Horizontal {
            x: u.floor().clamp(0.0, w as f64 - 1.0) as u32,
            y: v.round().clamp(0.0, h as f64) as u32,
        }
    }
}

fn arrow(p: &egui::Painter, a: Pos2, b: Pos2, col: Color32) {
    let d = b - a;
    let len = d.length();
    if len < 0.8 {
        p.circle_filled(a, 0.7, col);
        return;
    }
    let stroke = Stroke::new(1.2, col);
    p.line_segment([a, b], stroke);
    let dir = d / len;
    let n = vec2(-dir.y, dir.x);
    let head = (len * 0.35).min(5.0);
    p.line_segment([b, b - dir * head + n * head * 0.55], stroke);
    p.line_segment([b, b - dir * head - n * head * 0.55], stroke);
}

/// A palette entry: a square with an arrow per edge (towards +x / +y for
/// positive flux, thicker for more), faded when greyed.
fn flux_icon(p: &egui::Painter, r: Rect, f: [i32; 4], fmax: i32, allowed: bool, picked: bool) {
    let bg = if picked {
        Color32::from_rgb(255, 226, 140)
    } else if allowed {
        Color32::from_rgb(214, 230, 255)
    } else {
        Color32::from_gray(228)
    };
    p.rect_filled(r, 3.0, bg);
    p.rect_stroke(
        r,
        3.0,
        Stroke::new(1.0, Color32::from_gray(if allowed { 90 } else { 185 })),
        egui::StrokeKind::Inside,
    );
    let col = if allowed {
        Color32::from_rgb(25, 60, 130)
    } else {
        Color32::from_gray(175)
    };
    let c = r.center();
    let half = r.width() / 2.0 - 3.0;
    // left, bottom, right, top: edge midpoints and the +x / +y direction
    let mids = [
        (c - vec2(half, 0.0), vec2(1.0, 0.0)),
        (c + vec2(0.0, half), vec2(0.0, -1.0)),
        (c + vec2(half, 0.0), vec2(1.0, 0.0)),
        (c - vec2(0.0, half), vec2(0.0, -1.0)),
    ];
    for (k, (m, dir)) in mids.iter().enumerate() {
        let v = f[k];
        if v == 0 {
            continue;
        }
        let len = 4.0 + 8.0 * v.abs() as f32 / fmax as f32;
        let d: Vec2 = *dir * len * v.signum() as f32;
        arrow(p, *m - d / 2.0, *m + d / 2.0, col);
    }
}

/// Renders the editor once without a display: runs the UI for a few frames
/// of `width`×`height` points at one pixel per point and rasterises egui's
/// output on the CPU. Same editor, view and size → the same bytes.
pub fn screenshot(
    ed: &mut Editor,
    view: &mut EditorView,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, String> {
    if width == 0 || height == 0 || width > 8192 || height > 8192 {
        return Err(format!(
            "screenshot size {width}x{height}: allowed is 1..=8192 per side"
        ));
    }
    let ctx = egui::Context::default();
    ctx.set_visuals(egui::Visuals::light());
    let mut sw = egui_software_backend::EguiSoftwareRender::new(
        egui_software_backend::ColorFieldOrder::Rgba,
    )
    .with_caching(false);
    let mut buf = vec![[0u8; 4]; (width * height) as usize];
    // Egui lays text out in the first frames (sizing passes); the third is settled.
    for frame in 0..3 {
        let input = egui::RawInput {
            screen_rect: Some(Rect::from_min_size(
                Pos2::ZERO,
                vec2(width as f32, height as f32),
            )),
            time: Some(frame as f64 / 60.0),
            predicted_dt: 1.0 / 60.0,
            ..Default::default()
        };
        let out = ctx.run_ui(input, |ui| view.ui(ui, ed));
        let prims = ctx.tessellate(out.shapes, out.pixels_per_point);
        let bg = ctx.global_style().visuals.panel_fill;
        buf.iter_mut()
            .for_each(|p| *p = [bg.r(), bg.g(), bg.b(), 255]);
        let mut target =
            egui_software_backend::BufferMutRef::new(&mut buf, width as usize, height as usize);
        sw.render(
            &mut target,
            &prims,
            &out.textures_delta,
            out.pixels_per_point,
        );
    }
    let rgb: Vec<u8> = buf.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let mut png_bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut png_bytes, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        w.write_image_data(&rgb).map_err(|e| e.to_string())?;
    }
    Ok(png_bytes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::editor::commands::run_script;
    use crate::spec::Problem;

    fn demo() -> (Editor, EditorView) {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/flowtiles");
        let text = std::fs::read_to_string(dir.join("river.toml")).unwrap();
        let mut ed = Editor::new(Problem::from_toml(&text).unwrap()).unwrap();
        let script = std::fs::read_to_string(dir.join("editor-demo.txt")).unwrap();
        // The demo saves and bakes into the working directory: not here.
        let script: String = script
            .lines()
            .filter(|l| !l.starts_with("save") && !l.starts_with("bake"))
            .map(|l| format!("{l}\n"))
            .collect();
        let mut view = EditorView::new("unused.toml".into(), "unused.ftb".into(), None);
        run_script(&mut ed, &script, Some(&mut view.settings)).unwrap();
        (ed, view)
    }

    /// The demo session's screenshot: a real picture (many colours, the
    /// palette panel drawn), the same bytes from two fresh runs.
    #[test]
    fn headless_screenshots_are_pictures_and_deterministic() {
        let (mut ed, mut view) = demo();
        assert_eq!(view.settings.selected, Some((7, 3)));
        let a = screenshot(&mut ed, &mut view, 640, 400).unwrap();
        let (mut ed2, mut view2) = demo();
        let b = screenshot(&mut ed2, &mut view2, 640, 400).unwrap();
        assert_eq!(a, b, "two runs of the same session differ");
        let dec = png::Decoder::new(std::io::Cursor::new(&a));
        let mut r = dec.read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size().unwrap()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (640, 400));
        let mut colours: Vec<[u8; 3]> = buf.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        colours.sort_unstable();
        colours.dedup();
        assert!(colours.len() > 200, "only {} colours", colours.len());
        // Particles move: another time gives another picture.
        view.settings.time = 0.5;
        let c = screenshot(&mut ed, &mut view, 640, 400).unwrap();
        assert_ne!(a, c);
        assert!(screenshot(&mut ed, &mut view, 0, 10).is_err());
    }

    #[test]
    fn backgrounds_read_from_png() {
        let dir = std::env::temp_dir().join(format!("ftb-bg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut c = crate::render::Canvas::new(4, 3, [1.0, 0.0, 0.0]);
        c.fill_rect(0.0, 0.0, 1.0, 1.0, [0.0, 0.0, 1.0], 1.0);
        std::fs::write(dir.join("bg.png"), c.to_png().unwrap()).unwrap();
        let bg = Background::read_png(&dir.join("bg.png")).unwrap();
        assert_eq!((bg.width, bg.height, bg.rgb.len()), (4, 3, 36));
        assert_eq!(&bg.rgb[..3], &[0, 0, 255]);
        std::fs::write(dir.join("bad.png"), b"not a png").unwrap();
        assert!(Background::read_png(&dir.join("bad.png")).is_err());
        assert!(Background::read_png(&dir.join("missing.png")).is_err());
        let mut ed = Editor::blank(4, 3).unwrap();
        let mut view = EditorView::new("a.toml".into(), "a.ftb".into(), Some(bg));
        let png = screenshot(&mut ed, &mut view, 500, 300).unwrap();
        assert!(png.len() > 1000);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
