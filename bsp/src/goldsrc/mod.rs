//! The Quake 1 family: GoldSrc v30 (Half-Life, Counter-Strike, ...), Quake BSP29
//! (Half-Life's oldest retail maps are v29 too), BSP2 and its predecessor 2PSB.
//!
//! [`parse`] reads every lump we need into the normalised [`crate::Bsp`] and checks
//! every record the engines read (see `read::validate`), so the rest of the tools can
//! index freely. Memory stays bounded by the file size: no record count is trusted
//! before the lump's bytes are known to exist.

mod raw;
mod read;

pub use read::parse;
