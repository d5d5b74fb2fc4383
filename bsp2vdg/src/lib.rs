//! bsp2vdg compiles a compiled BSP map (GoldSrc v30/v29, Quake BSP29/BSP2) into a
//! Voronoi Distance Graph: an approximate medial axis of the level's free space whose
//! vertices carry their clearance to the nearest wall.
//!
//! The pipeline has one module per stage: [`bsp`] reads the map, `oracle` answers
//! point-contents and segment queries, `boundary` finds the walls in the BSP tree,
//! `sample` places points on the walls, `delaunay` tetrahedralizes them, `voronoi`
//! extracts the graph, `reduce` shrinks it; `standing` finds where a standing player is.

pub mod boundary;
pub mod bsp;
pub mod check;
pub mod delaunay;
pub mod log;
pub mod oracle;
pub mod pipeline;
pub mod progress;
pub mod reduce;
pub mod sample;
pub mod standing;
pub mod uptodate;
pub mod util;
pub mod voronoi;
pub mod walls;
