//! The central area: the grid over the background, slots, tiles, the
//! spec's fixed fluxes and corners, particles, the selection, and the
//! clicks and strokes of the tools. Drawn back to front, one step each.

use egui::{Align2, Color32, FontId, Pos2, Rect, Response, Sense, Stroke, Ui, pos2, vec2};

use super::{EditorView, Tool};
use crate::editor::commands::{Command, TileStyle};
use crate::editor::model::{Editor, Origin};
use crate::tiling::Edge;

/// Where the grid lies on the screen: `s` points per tile, `origin` the
/// top-left corner, `h` slots high (grid `y` points up, screen `y` down).
#[derive(Clone, Copy)]
struct Frame {
    origin: Pos2,
    s: f32,
    w: u32,
    h: u32,
}

impl Frame {
    /// The screen point of grid point `(u, v)` (tile units).
    fn to(&self, u: f64, v: f64) -> Pos2 {
        pos2(
            self.origin.x + u as f32 * self.s,
            self.origin.y + (self.h as f64 - v) as f32 * self.s,
        )
    }

    /// The screen rectangle of slot `(x, y)`.
    fn slot_rect(&self, x: u32, y: u32) -> Rect {
        Rect::from_min_max(
            self.to(x as f64, y as f64 + 1.0),
            self.to(x as f64 + 1.0, y as f64),
        )
    }

    /// The screen segment of a grid edge.
    fn edge(&self, e: Edge) -> (Pos2, Pos2) {
        match e {
            Edge::Vertical { x, y } => (
                self.to(x as f64, y as f64),
                self.to(x as f64, y as f64 + 1.0),
            ),
            Edge::Horizontal { x, y } => (
                self.to(x as f64, y as f64),
                self.to(x as f64 + 1.0, y as f64),
            ),
        }
    }
}

impl EditorView {
    /// The grid fitted into the area, drawn and its input handled.
    pub(super) fn grid(&mut self, ui: &mut Ui, ed: &mut Editor) {
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
        let frame = Frame { origin, s, w, h };
        self.paint_background(ui, &painter, rect);
        self.paint_slots(&painter, ed, frame);
        paint_grid_lines(&painter, frame);
        self.paint_tiles(&painter, ed, frame);
        paint_conditions(&painter, ed, frame);
        self.paint_particles(&painter, ed, frame);
        self.paint_selection(&painter, frame);
        self.grid_input(&resp, &painter, ed, frame);
    }

    /// The background picture spanning the grid, or a plain fill.
    fn paint_background(&mut self, ui: &Ui, painter: &egui::Painter, rect: Rect) {
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
    }

    /// Blocked slots, placed and filled tiles' slots, empty slots (see-through
    /// over a background).
    fn paint_slots(&self, painter: &egui::Painter, ed: &Editor, frame: Frame) {
        let alpha = if self.background.is_some() { 110 } else { 255 };
        for y in 0..frame.h {
            for x in 0..frame.w {
                let r = frame.slot_rect(x, y);
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
    }

    /// Each placed tile as arrows (fewer when small) or streamlines.
    fn paint_tiles(&self, painter: &egui::Painter, ed: &Editor, frame: Frame) {
        let s = frame.s;
        let ink = Color32::from_rgb(25, 60, 130);
        for y in 0..frame.h {
            for x in 0..frame.w {
                let Some(k) = ed.tiling().tile(x, y) else {
                    continue;
                };
                let Some(d) = self.tiles.get(&k) else {
                    continue;
                };
                let at = |p: [f32; 2]| frame.to(x as f64 + p[0] as f64, y as f64 + p[1] as f64);
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
                            arrow(painter, pa, pb, ink);
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
    }

    /// The particles inside placed tiles.
    fn paint_particles(&self, painter: &egui::Painter, ed: &Editor, frame: Frame) {
        if !self.settings.particles {
            return;
        }
        let r = (frame.s * 0.04).clamp(1.0, 2.2);
        for p in &self.particles.pos {
            if self.velocity(ed, *p).is_some() {
                painter.circle_filled(frame.to(p[0], p[1]), r, Color32::from_rgb(230, 60, 40));
            }
        }
    }

    /// The selected slot's outline.
    fn paint_selection(&self, painter: &egui::Painter, frame: Frame) {
        if let Some((x, y)) = self.settings.selected
            && x < frame.w
            && y < frame.h
        {
            painter.rect_stroke(
                frame.slot_rect(x, y),
                0.0,
                Stroke::new(2.5, Color32::from_rgb(255, 190, 0)),
                egui::StrokeKind::Middle,
            );
        }
    }

    /// The tools' clicks and strokes on the grid (a painted stroke is one
    /// undo step), and the edge or vertex under the pointer for the flux
    /// and corner tools.
    fn grid_input(
        &mut self,
        resp: &Response,
        painter: &egui::Painter,
        ed: &mut Editor,
        frame: Frame,
    ) {
        let Frame { origin, s, w, h } = frame;
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
                let (a, b) = frame.edge(e);
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
                    frame.to(x as f64, y as f64),
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

/// The grid lines, thinner when the tiles are small.
fn paint_grid_lines(painter: &egui::Painter, frame: Frame) {
    let (w, h) = (frame.w, frame.h);
    let line = Stroke::new(
        if frame.s > 6.0 { 1.0 } else { 0.5 },
        Color32::from_rgba_unmultiplied(150, 155, 175, 160),
    );
    for x in 0..=w {
        painter.line_segment(
            [frame.to(x as f64, 0.0), frame.to(x as f64, h as f64)],
            line,
        );
    }
    for y in 0..=h {
        painter.line_segment(
            [frame.to(0.0, y as f64), frame.to(w as f64, y as f64)],
            line,
        );
    }
}

/// The spec's fixed fluxes (a thick edge, an arrow, the value) and fixed
/// corners (a dot, the index); the values only where tiles are large enough.
fn paint_conditions(painter: &egui::Painter, ed: &Editor, frame: Frame) {
    let s = frame.s;
    let c = ed.problem().conditions.clone();
    for &(e, m) in &c.fluxes {
        let (a, b) = frame.edge(e);
        let n = match e {
            Edge::Vertical { .. } => vec2(1.0, 0.0),
            Edge::Horizontal { .. } => vec2(0.0, -1.0),
        };
        let col = Color32::from_rgb(220, 90, 20);
        painter.line_segment([a, b], Stroke::new(3.0, col));
        let mid = a + (b - a) / 2.0;
        if m != 0 {
            let len = (s * 0.3).clamp(6.0, 16.0) * m.signum() as f32;
            arrow(painter, mid - n * len, mid + n * len, col);
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
            frame.to(x as f64, y as f64),
            (s * 0.12).clamp(2.5, 5.0),
            Color32::from_rgb(150, 40, 160),
        );
        if s >= 18.0 {
            painter.text(
                frame.to(x as f64, y as f64) + vec2(4.0, 2.0),
                Align2::LEFT_TOP,
                v.to_string(),
                FontId::proportional(11.0),
                Color32::from_rgb(150, 40, 160),
            );
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

pub(super) fn arrow(p: &egui::Painter, a: Pos2, b: Pos2, col: Color32) {
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
