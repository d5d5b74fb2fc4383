//! The left panel: the tool, the values the flux and corner tools fix,
//! the borders and the fill's seed and preferences.

use egui::Ui;

use super::{EditorView, Tool};
use crate::editor::commands::Command;
use crate::editor::model::Editor;
use crate::tiling::Border;

impl EditorView {
    /// The panel, section by section.
    pub(super) fn tools(&mut self, ui: &mut Ui, ed: &mut Editor) {
        self.tool_choice(ui);
        ui.separator();
        self.values_to_fix(ui, ed);
        ui.separator();
        self.borders(ui, ed);
        ui.separator();
        self.fill_settings(ui, ed);
    }

    /// The tool buttons.
    fn tool_choice(&mut self, ui: &mut Ui) {
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
    }

    /// The flux and the corner velocity the flux and corner tools fix.
    fn values_to_fix(&mut self, ui: &mut Ui, ed: &Editor) {
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
    }

    /// The border choices of both axes.
    fn borders(&mut self, ui: &mut Ui, ed: &mut Editor) {
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
    }

    /// The fill's seed and preference weights, the main directions' count.
    fn fill_settings(&mut self, ui: &mut Ui, ed: &mut Editor) {
        ui.heading("Fill");
        let p = ed.problem().clone();
        let mut seed = p.seed;
        ui.horizontal(|ui| {
            ui.label("seed");
            if ui.add(egui::DragValue::new(&mut seed)).changed() {
                self.run(ed, Command::Seed(seed));
            }
        });
        if let Some(w) = weight_row(ui, "favour straight", p.preferences.straight) {
            self.run(ed, Command::Straight(w));
        }
        if let Some(w) = weight_row(ui, "favour reuse", p.preferences.reuse) {
            self.run(ed, Command::Reuse(w));
        }
        ui.label(format!(
            "{} main direction regions",
            p.preferences.regions.len()
        ));
        if !p.preferences.regions.is_empty() && ui.button("clear directions").clicked() {
            self.run(ed, Command::ClearDirections);
        }
    }
}

/// A labelled preference weight (0 to 100): the new value once a drag ends
/// or a typed value changes it, not on every step of a drag.
fn weight_row(ui: &mut Ui, label: &str, value: f64) -> Option<f64> {
    let mut w = value;
    ui.horizontal(|ui| {
        ui.label(label);
        let r = ui.add(egui::DragValue::new(&mut w).range(0.0..=100.0).speed(0.1));
        r.drag_stopped() || (r.changed() && !r.dragged())
    })
    .inner
    .then_some(w)
}
