//! bsp2vdg compiles a compiled BSP map (GoldSrc, Quake 1, 2 and 3) into a Voronoi
//! Distance Graph: an approximate medial axis of the level's free space whose vertices
//! carry their clearance to the nearest wall, for the runtime crate `vdgformat`.
//!
//! The map crate `bsp` reads the map and answers point-contents, traces and wall
//! distances. The compiler is its pipeline, one module per stage in the order they
//! run ([`pipeline::compile`] is the driver): [`sample`] places points on the walls,
//! [`delaunay`] tetrahedralizes them, [`voronoi`] extracts the graph in free space,
//! [`guard`] proves its volume free, [`reduce`] shrinks it, [`raise`] lets the
//! clearances reach back to the walls, [`write`] writes the `.vdg`. The graph they pass
//! on is [`graph::Graph`]; free space reaches them through [`space::FreeSpace`];
//! every setting is declared in [`options`].

pub mod delaunay;
pub mod graph;
pub mod guard;
pub mod log;
pub mod options;
pub mod pipeline;
pub mod progress;
pub mod raise;
pub mod reduce;
pub mod sample;
pub mod space;
pub mod uptodate;
pub mod voronoi;
pub mod write;
