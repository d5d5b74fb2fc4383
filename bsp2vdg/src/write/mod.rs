//! The last stage: the graph written as a `.vdg` (with the build's options and the
//! source map's hash, so an up-to-date check can trust it), and the optional samples
//! file, each through a temporary file and a rename so no half-written file is left.

use crate::graph::Graph;
use crate::options::{CompileOptions, SamplesFormat, recorded_options};
use crate::pipeline::CompileError;
use std::io::Write;
use std::path::Path;

/// Writes the graph with its build parameters and the source map's name and hash.
/// `corners`: the faces' own corner radii, one per face, if raised
/// ([`crate::raise::raise_to_walls_and_corners`]). `source`: the game the map was read
/// as and its format's name (`Bsp::format_name`), recorded for `vdgview info`.
pub fn write_vdg(
    map: &Path,
    options: &CompileOptions,
    graph: &Graph,
    corners: Option<&[[f64; 3]]>,
    source: (&str, &str),
) -> Result<usize, CompileError> {
    let vdg_err = |error: String| CompileError::Vdg {
        path: options.output.clone(),
        error,
    };
    let source_bytes =
        std::fs::read(map).map_err(|e| vdg_err(format!("cannot read the map again: {e}")))?;
    let mut b = graph.to_builder(corners);
    b.set_source_hash(vdgformat::xxh64(&source_bytes, 0))
        .set_leaf_size(options.tree_leaf_size as f32);
    for (key, value) in recorded_options(options) {
        b.set_metadata(&key, &value);
    }
    // What the source is, for `vdgview info` (no path recorded).
    b.set_metadata("source.game", source.0);
    b.set_metadata("source.format", source.1);
    let bytes = b.to_bytes().map_err(|e| vdg_err(e.to_string()))?;
    let len = bytes.len();
    write_atomic(&options.output, |w| w.write_all(&bytes))?;
    Ok(len)
}

/// Writes the samples through a temporary file, so no half-written file is left behind.
pub fn write_samples(
    path: &Path,
    points: &[[f64; 3]],
    format: SamplesFormat,
) -> Result<(), CompileError> {
    write_atomic(path, |w| {
        if format == SamplesFormat::Qhull {
            writeln!(w, "3\n{}", points.len())?;
        }
        for p in points {
            writeln!(w, "{} {} {}", p[0], p[1], p[2])?;
        }
        Ok(())
    })
}

/// Writes a file via a synced temporary sibling and a rename ([`toolbox::write_atomic`]).
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), CompileError> {
    toolbox::write_atomic(path, body).map_err(|error| CompileError::Write {
        path: path.to_path_buf(),
        error,
    })
}
