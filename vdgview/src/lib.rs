//! vdgview: the tool a level designer opens after a compile. It measures a `.vdg`
//! against its map's own BSP (`check`), and inspects, queries, renders and
//! flies through it. One module per subcommand.
//!
//! Issue 7's part: `info` and `query` (thin layers over `vdgformat`'s runtime
//! queries), `render` (a headless, deterministic PNG from our own software
//! rasterizer: [`raster`] draws, [`render`] decides what, [`camera`] frames,
//! [`scene`] loads map walls, graph and samples) and `view` (the same
//! framebuffer in a minifb window: [`viewer`] is the window-independent state
//! and console, [`view`] the event loop, [`hud`] the text).
//!
//! Issue 13's part: `replay` ([`replay`]) measures cameras (the VDG camera, Half-Life's
//! chase cam, a spring arm) on routes made from the map against the BSP's ground truth.
//!
//! ```
//! use vdgview::camera::Camera;
//! use vdgview::raster::Framebuffer;
//! use glam::Vec3;
//!
//! // One red triangle in front of a camera at the origin looking along +x.
//! let cam = Camera::look_at(Vec3::ZERO, Vec3::X, 90.0);
//! let mut fb = Framebuffer::new(32, 32, &cam, [0, 0, 0]);
//! let tri = [Vec3::new(50.0, -40.0, -40.0), Vec3::new(50.0, 40.0, -40.0), Vec3::new(50.0, 0.0, 40.0)];
//! fb.triangle(tri, [Vec3::new(255.0, 0.0, 0.0); 3]);
//! assert_eq!(fb.color[16 * 32 + 16], 0xff0000);
//! ```

pub mod camera;
pub mod hud;
pub mod info;
pub mod query;
pub mod raster;
pub mod render;
pub mod replay;
pub mod scene;
pub mod view;
pub mod viewer;
