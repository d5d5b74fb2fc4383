//! Flow tiles (Chenney, SCA 2004): divergence-free 2D velocity fields built
//! from small square tiles, tiled under boundary conditions and baked into a
//! compact file a game runtime can sample.
//!
//! The pipeline is [`tileset`] (which tiles exist) → [`tiling`] (which tile
//! goes where, with a selection function that guarantees every partial tiling
//! can be completed, decided exactly by max-flow in [`flow`]) → [`fill`]
//! (stream functions of only the tiles used) → [`bake`] (the binary file) →
//! [`runtime`] (velocity lookup, flow coordinates, blending of key tilings)
//! → [`render`] (PNG pictures).

pub mod bake;
pub mod fill;
pub mod flow;
pub mod render;
pub mod rng;
pub mod runtime;
pub mod spec;
pub mod tileset;
pub mod tiling;
