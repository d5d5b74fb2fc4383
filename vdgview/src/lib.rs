//! vdgview: the tool a level designer opens after a compile. It measures a `.vdg`
//! against its map's own BSP (`check`), and (issue 7) inspects, queries, renders and
//! flies through it. One module per subcommand.

pub mod camera;
pub mod check;
pub mod hud;
pub mod info;
pub mod query;
pub mod raster;
pub mod render;
pub mod scene;
pub mod view;
pub mod viewer;
