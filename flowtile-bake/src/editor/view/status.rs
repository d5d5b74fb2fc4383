//! The bottom bar: the grid's counts, the history and the last message.

use egui::{Color32, Ui};

use super::EditorView;
use crate::editor::model::Editor;

impl EditorView {
    /// The status line (an error message in red).
    pub(super) fn status_bar(&mut self, ui: &mut Ui, ed: &Editor) {
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
}
