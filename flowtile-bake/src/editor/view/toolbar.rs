//! The top bar: fill, clear, undo/redo, save, bake, how tiles are drawn.

use egui::Ui;

use super::EditorView;
use crate::editor::commands::{Command, TileStyle};
use crate::editor::model::Editor;

impl EditorView {
    /// The buttons of the top bar.
    pub(super) fn toolbar(&mut self, ui: &mut Ui, ed: &mut Editor) {
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
}
