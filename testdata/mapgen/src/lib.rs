//! Test map generator (placeholder; see issue 2).
