//! Flow tiles (placeholder; see issue 6).
