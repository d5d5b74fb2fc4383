//! bsp2vdg compiles a compiled BSP map (GoldSrc v30/v29, Quake BSP29/BSP2) into a
//! Voronoi Distance Graph: an approximate medial axis of the level's free space whose
//! vertices carry their clearance to the nearest wall.
//!
//! The pipeline has one module per stage: the map crate [`bsp`] reads the map and
//! answers point-contents and segment queries (`oracle`) and finds the walls in the
//! BSP tree (`boundary`, `walls`); `sample` places points on the walls, `delaunay`
//! tetrahedralizes them, `voronoi` extracts the graph, `reduce` shrinks it; `standing` finds where a standing
//! player is.

pub mod delaunay;
pub mod log;
pub mod pipeline;
pub mod progress;
pub mod reduce;
pub mod sample;
pub mod uptodate;
pub mod voronoi;
