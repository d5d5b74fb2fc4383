//! What a compile measured, for the log's summary, `--json` and the CI baseline.

use crate::voronoi::VoronoiStats;
use std::path::PathBuf;

/// What a compile measured, for the log summary and `--json`.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub version: String,
    pub file_size: usize,
    pub bounds: ([f32; 3], [f32; 3]),
    pub faces: usize,
    pub sampled_faces: usize,
    pub sky_faces: usize,
    pub samples: usize,
    pub sample_spacing: f64,
    pub requested_spacing: f64,
    pub subfaces: usize,
    pub merged_samples: usize,
    /// Samples on walls the BSP tree has but no face shows.
    pub hidden_samples: usize,
    pub entity_models: usize,
    /// Seconds per stage, in order.
    pub seconds: Vec<(&'static str, f64)>,
    pub samples_file: Option<PathBuf>,
    /// Delaunay and Voronoi counts (thesis table 7.1), once those stages ran.
    pub tetrahedra: Option<usize>,
    pub duplicate_samples: usize,
    pub voronoi: Option<VoronoiStats>,
    /// The written graph: vertices, faces, bytes.
    pub vdg: Option<(usize, usize, usize)>,
    /// The reduction's counts, when it ran (`-rl` < 1).
    pub reduce: Option<crate::reduce::ReduceStats>,
    pub output: Option<PathBuf>,
    /// The game the map was read as, and why (see [`bsp::game`]).
    pub game: String,
    pub game_reason: String,
    /// Faces the engine could not draw (not sampled), and the first few named.
    pub unusable_faces: usize,
    pub unusable_examples: String,
    /// Where the map leaks (free space reaching outside the world's bounds), and the
    /// pointfile written for the editor.
    pub leak: Option<String>,
    pub pointfile: Option<PathBuf>,
    /// Standing places outside the written graph's volume (see
    /// [`super::pointfiles`]), and the pointfile through them when there are any.
    pub missed_places: Option<usize>,
    pub missed_pointfile: Option<PathBuf>,
}
