//! Generated GoldSrc test maps whose free space is known exactly.
//!
//! A [`World`] is a union of axis-aligned boxes of free space (rooms,
//! corridors, door openings), minus solid boxes (pillars, steps) and solid
//! wedges with a slanted plane (ramps, slanted walls), with SKY boxes above
//! open courtyards and WATER boxes in pools. The crate answers questions about
//! it exactly — point contents, clip-hull contents, segment freedom, clearance,
//! the boundary polygons — and compiles it into a valid BSP v30 file (hull 0
//! nodes and leaves, clip hulls 1–3, faces with named textures, brush
//! entities, player starts). The compiler in `bsp2vdg` reads those files with
//! its own reader; comparing its answers with the exact ones here tests both
//! codecs against each other. The standard maps ([`worlds::worlds`]) are
//! committed in `testdata/maps/` with a JSON manifest each.
//!
//! ```
//! use mapgen::world::Contents;
//! let w = mapgen::worlds::two_rooms();
//! assert_eq!(w.contents([500.0, 192.0, 50.0]), Contents::Empty); // corridor
//! assert!(w.segment_free([192.0, 192.0, 50.0], [832.0, 192.0, 50.0]));
//! let bytes = mapgen::bsp::write_world(&w);
//! assert!(bytes.len() < 200_000);
//! ```

pub mod bsp;
pub mod geometry;
pub mod manifest;
pub mod tree;
pub mod world;
pub mod worlds;

#[cfg(test)]
mod testutil;

pub use world::{Aabb, Contents, Ramp, SurfaceClass, WallPolygon, World};
pub use worlds::worlds;
