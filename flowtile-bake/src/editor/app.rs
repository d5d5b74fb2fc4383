//! The editor's window: eframe (egui's own native shell) with the OpenGL
//! (glow) backend on X11, which runs on Mesa's software rasteriser where
//! there is no GPU (Xvfb). All drawing and input handling is
//! [`super::view::EditorView::ui`]; this only hosts it and keeps the
//! particles moving in real time.

use super::model::Editor;
use super::view::EditorView;

struct EditorApp {
    editor: Editor,
    view: EditorView,
    start: std::time::Instant,
    /// Close after this many seconds (tests, screenshots under Xvfb).
    seconds: Option<f64>,
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let t = self.start.elapsed().as_secs_f64();
        if self.view.settings.particles {
            self.view.settings.time = t;
            ui.ctx().request_repaint();
        }
        self.view.ui(ui, &mut self.editor);
        if self.seconds.is_some_and(|s| t >= s) {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
        if self.seconds.is_some() {
            ui.ctx().request_repaint();
        }
    }
}

/// Opens the editor's window and runs until it is closed (or after
/// `seconds`). Fails with a message when no window can be opened (no
/// display, no OpenGL).
pub fn run_window(
    editor: Editor,
    view: EditorView,
    title: &str,
    size: [f32; 2],
    seconds: Option<f64>,
) -> Result<(), String> {
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size(size),
        ..Default::default()
    };
    eframe::run_native(
        title,
        options,
        Box::new(move |cc| {
            cc.egui_ctx.set_visuals(egui::Visuals::light());
            Ok(Box::new(EditorApp {
                editor,
                view,
                start: std::time::Instant::now(),
                seconds,
            }))
        }),
    )
    .map_err(|e| format!("cannot open the editor's window: {e}"))
}
