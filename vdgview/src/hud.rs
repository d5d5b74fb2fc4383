//! Text over the picture (status line, messages, console) drawn from the 8×8
//! bitmap glyphs of `font8x8` straight into the framebuffer, with a dark
//! shadow so it stays readable on any background.

use crate::raster::{Framebuffer, Rgb};

/// Glyph cell size in pixels.
pub const CELL: usize = 8;

/// Draws `text` with its top-left corner at (x, y); characters outside ASCII
/// are shown as `?`.
pub fn text(fb: &mut Framebuffer, x: i64, y: i64, s: &str, color: Rgb) {
    for (i, ch) in s.chars().enumerate() {
        let code = if ch.is_ascii() {
            ch as usize
        } else {
            '?' as usize
        };
        let glyph = font8x8::legacy::BASIC_LEGACY[code];
        let gx = x + (i * CELL) as i64;
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..8 {
                if bits & (1 << col) != 0 {
                    let (px, py) = (gx + col as i64, y + row as i64);
                    fb.put(px + 1, py + 1, [0, 0, 0]);
                    fb.put(px, py, color);
                }
            }
        }
    }
}

/// A filled rectangle (console background).
pub fn rect(fb: &mut Framebuffer, x: i64, y: i64, w: usize, h: usize, color: Rgb) {
    for dy in 0..h as i64 {
        for dx in 0..w as i64 {
            fb.put(x + dx, y + dy, color);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::raster::pack;
    use glam::Vec3;

    #[test]
    fn text_draws_glyph_pixels_and_nothing_for_spaces() {
        let cam = Camera::look_at(Vec3::ZERO, Vec3::X, 60.0);
        let mut fb = Framebuffer::new(40, 10, &cam, [50, 50, 50]);
        text(&mut fb, 0, 0, "  ", [255, 255, 255]);
        assert!(!fb.color.contains(&pack([255, 255, 255])));
        text(&mut fb, 0, 0, "H", [255, 255, 255]);
        let lit = fb
            .color
            .iter()
            .filter(|&&c| c == pack([255, 255, 255]))
            .count();
        assert!(lit > 10, "{lit}");
    }
}
