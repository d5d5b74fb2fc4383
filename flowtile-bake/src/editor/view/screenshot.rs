//! Headless screenshots: the editor's frames rasterised on the CPU.

use egui::{Pos2, Rect, vec2};

use super::EditorView;
use crate::editor::model::Editor;

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
