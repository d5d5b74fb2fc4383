//! Building a `.vdg` file: adjacency, the BBox tree, layout and checksum.
//!
//! | file | what |
//! |---|---|
//! | `builder.rs` | [`VdgBuilder`]: what a caller adds, its validation, `to_bytes` and `write_atomic` |
//! | `error.rs` | [`BuildError`], [`WriteError`] |
//! | `adjacency.rs` | vertex → faces and vertex → vertices in CSR form |
//! | `tree.rs` | the face volume boxes, the BBox tree and its node bounds |
//! | `write.rs` | the sections, their layout behind the header, the checksum |

mod adjacency;
mod builder;
mod error;
mod tree;
mod write;

pub use builder::{DEFAULT_LEAF_SIZE, VdgBuilder};
pub use error::{BuildError, WriteError};
pub(crate) use tree::node_bounds;
pub use write::seal;
