//! The right panel: the palette of the selected slot (the tiles that keep
//! the tiling completable, the others greyed with the reason), the corner
//! choices and placing the picked tile.

use egui::{Color32, Rect, Sense, Stroke, Ui, Vec2, vec2};

use super::grid::arrow;
use super::{EditorView, largest_flux};
use crate::editor::commands::{Command, TileChoice};
use crate::editor::model::{Editor, FluxChoice, Origin, Palette};

impl EditorView {
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

    /// The panel: the selected slot's tile and counts, the flux tuples, why
    /// the others are greyed, the corners, Place and Clear.
    pub(super) fn palette_panel(&mut self, ui: &mut Ui, ed: &mut Editor) {
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
        self.flux_choices(ui, ed, &p, (x, y));
        ui.separator();
        greyed_reasons(ui, &p);
        ui.separator();
        self.corner_choices(ui, &p);
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

    /// The flux tuples of the palette as icons, allowed first: a click picks
    /// one, a double click places it at slot `(x, y)`.
    fn flux_choices(&mut self, ui: &mut Ui, ed: &mut Editor, p: &Palette, (x, y): (u32, u32)) {
        let set = ed.tiling().set().clone();
        let fmax = largest_flux(&set);
        egui::ScrollArea::vertical()
            .max_height(ui.available_height() - 240.0)
            .show(ui, |ui| {
                ui.horizontal_wrapped(|ui| {
                    ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
                    // Allowed first, then greyed.
                    let mut order: Vec<&FluxChoice> = p.fluxes.iter().collect();
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
    }

    /// A row of corner choices for each corner of the slot (the ones that
    /// do not fit disabled, with the reason on hover).
    fn corner_choices(&mut self, ui: &mut Ui, p: &Palette) {
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
    }

    /// Places the picked tuple with the picked corners at `slot`.
    fn place_pick(&mut self, ed: &mut Editor, slot: (u32, u32)) {
        if let Some(f) = self.pick {
            self.run(
                ed,
                Command::Place(slot, TileChoice::Key(f, Some(self.pick_corners))),
            );
        }
    }
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

/// Why the palette's other tuples are greyed: the commonest reasons with
/// their counts.
fn greyed_reasons(ui: &mut Ui, p: &Palette) {
    // Grouped by reason.
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
}
