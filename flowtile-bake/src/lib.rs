//! Flow tiles (Chenney, SCA 2004): divergence-free 2D velocity fields built
//! from small square tiles, laid out under boundary conditions and baked into
//! a compact file that a game runtime samples.
//!
//! The pipeline is [`tileset`] (which tiles exist: counting, indexing,
//! symmetry classes) → [`tiling`] (which tile goes where: a grid with
//! boundary conditions and a selection function that guarantees every
//! partial tiling can be completed, decided exactly by max-flow on a residual
//! graph in [`flow`]) → [`fill`] (stream functions, filled lazily for the
//! tiles actually used) → [`bake`] (the versioned binary file, see
//! `FORMAT.md`) → [`runtime`] (velocity lookup, flow coordinates, blending of
//! key tilings) and [`render`] (PNG pictures). [`spec`] reads the TOML tiling
//! specs the `flowtile-bake` binary takes (and writes back); [`editor`] is the
//! interactive editor's model, command language and drawing; [`rng`] is a small seeded
//! generator so the same seed gives the same tiling everywhere.
//!
//! ```
//! use flowtile_bake::{bake::BakedTiling, rng::Rng, tileset::TileSet};
//! use flowtile_bake::tiling::{Border, Conditions, Tiling};
//! let set = TileSet::paper(5, 5, 1, 8).unwrap();
//! let mut tiling = Tiling::new(set, 8, 8, &Conditions::borders(Border::Periodic, Border::Periodic)).unwrap();
//! tiling.random_fill(&mut Rng::new(1)).unwrap();
//! let baked = BakedTiling::from_tiling(&tiling).unwrap();
//! assert!(baked.max_cell_divergence() <= 1e-12);
//! let v = baked.velocity(3.3, 4.7);
//! assert!(v[0].is_finite() && v[1].is_finite());
//! ```

pub mod bake;
pub mod editor;
pub mod fill;
pub mod flow;
pub mod prefer;
pub mod region;
pub mod render;
pub mod rng;
pub mod runtime;
pub mod spec;
pub mod stats;
pub mod tileset;
pub mod tiling;
pub mod world;
