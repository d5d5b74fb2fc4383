//! The `.vdg` file format and runtime queries (placeholder; see issue 4).
