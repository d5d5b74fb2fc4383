//! `bsp` reads compiled BSP maps and answers what the tools ask of a level: which
//! contents a point has, whether a segment is free, where the walls are and how far
//! away, which faces are walls, sky or helpers, where the entities and spawns are.
//! The compiler (`bsp2vdg`), the viewer and checker (`vdgview`) and the flow-tile
//! baker all read maps through it.
//!
//! The layout follows the `object` crate's `read/`: one folder per file format
//! ([`goldsrc`]: GoldSrc v30, Quake BSP29, BSP2 and 2PSB; [`quake2`]: IBSP 38 and
//! Qbism's QBSP 38; [`quake3`]: IBSP 46), each producing the same
//! normalised [`Bsp`] (32-bit indices, contents in the Quake convention), one
//! dispatch on the file's first bytes ([`Bsp::parse`]), and the common interface on
//! top: [`oracle`] (point contents, traces, the player's clip hulls), [`boundary`]
//! (walls from the BSP tree), [`walls`] (exact wall distance), [`faces`] (face
//! classes), [`Entity`] and [`Bsp::spawns`]. A new format is a new folder.
//!
//! ```no_run
//! let bsp = bsp::Bsp::open("maps/de_dust2.bsp")?;
//! println!("{}: {} faces, {} entities", bsp.version.name(), bsp.faces.len(), bsp.entities.len());
//! let oracle = bsp::oracle::Oracle::new(&bsp, &Default::default());
//! let free = oracle.is_free([0.0, 0.0, 64.0]);
//! # Ok::<(), bsp::BspError>(())
//! ```

pub mod boundary;
mod carve;
mod entities;
mod error;
pub mod faces;
pub mod game;
pub mod goldsrc;
pub mod leak;
mod lumps;
mod map;
pub mod oracle;
pub mod player;
pub mod quake2;
pub mod quake3;
mod read;
mod validate;
pub mod walls;

pub use entities::{Entity, parse_entities};
pub use error::BspError;
pub use map::*;
