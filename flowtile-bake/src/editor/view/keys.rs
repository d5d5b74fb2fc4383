//! The keyboard shortcuts.

use egui::Ui;

use super::EditorView;
use crate::editor::commands::Command;
use crate::editor::model::Editor;

impl EditorView {
    /// Undo, redo, save, fill, clear the selected slot, drop the selection;
    /// not while a text field has the keyboard.
    pub(super) fn keys(&mut self, ui: &mut Ui, ed: &mut Editor) {
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
}
