//! bsp2vdg compiles a compiled BSP map (GoldSrc v30/v29, Quake BSP29/BSP2) into a
//! Voronoi Distance Graph: an approximate medial axis of the level's free space whose
//! vertices carry their clearance to the nearest wall.
//!
//! The pipeline has one module per stage: the map crate [`bsp`] reads the map and
//! answers point-contents and segment queries (`oracle`) and finds the walls in the
//! BSP tree (`boundary`, `walls`); `sample` places points on the walls, `delaunay`
//! tetrahedralizes them, `voronoi` extracts the graph, `reduce` shrinks it; `standing` finds where a standing
//! player is.

/// The map crate, re-exported: reading moved out of the compiler into `bsp` so that
/// the viewer and the flow-tile baker read maps without the compiler. New code should
/// depend on `bsp` directly; these paths stay for code written before the split.
pub use ::bsp;
/// The map crate's tree boundary (re-exported, see [`bsp`]).
pub use ::bsp::boundary;
/// The map crate's oracle (re-exported, see [`bsp`]).
pub use ::bsp::oracle;
/// The map crate's shared helpers (re-exported, see [`bsp`]).
pub use ::bsp::util;
/// The map crate's exact wall distance (re-exported, see [`bsp`]).
pub use ::bsp::walls;
pub mod check;
pub mod delaunay;
pub mod log;
pub mod pipeline;
pub mod progress;
pub mod reduce;
pub mod sample;
pub mod standing;
pub mod uptodate;
pub mod voronoi;
