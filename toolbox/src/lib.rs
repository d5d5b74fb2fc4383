//! The few helpers every tool of the workspace shares, kept in one place so there is
//! one implementation of each: [`write_atomic`] (a file replaced by a synced temporary
//! sibling and a rename, then the directory synced) with [`clean_stale_temps`] for the
//! leftovers of killed runs, and [`SplitMix64`], the small seeded generator that tests,
//! benchmarks and samplers draw from. It knows nothing of maps or graphs, so the
//! runtime crate `vdgformat` can use it as well as the compiler and the viewers.
//! Tests and examples take their scratch folders from [`ScratchDir`], which removes
//! them when they are done. The [`console`] macros print without ever panicking on a
//! closed pipe or a full disk. [`table`] lays out text tables whose columns line up.

mod atomic;
pub mod console;
mod rng;
mod scratch;
pub mod table;

pub mod vec3;
pub use atomic::{clean_stale_temps, temp_path, write_atomic, write_bytes_atomic};
pub use rng::SplitMix64;
pub use scratch::ScratchDir;
