//! The picture under the grid (a map's top view): read from a PNG.

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
