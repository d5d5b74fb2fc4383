//! The interactive flow tile editor (the paper's fig. 7 tool).
//!
//! The designer paints the region, fixes edge fluxes and corner velocities,
//! places tiles from a palette that offers only the tiles the exact
//! selection function allows (the others greyed with the reason), fills the
//! rest at random with the spec's preferences, and saves the spec or bakes
//! the `.ftb`. The editor never lets the tiling become incompletable: a
//! command whose result would admit no complete tiling is refused with the
//! reason, and nothing changes.
//!
//! The parts are kept apart so that the editing is tested without a display:
//! [`model`] is the state (a spec and a partial tiling), its edits, the
//! palette and undo/redo; [`commands`] is the one-line command language of
//! scripted sessions (`flowtile-bake edit --script FILE`). The drawing lives
//! in [`view`] (egui, also rendered on the CPU for headless screenshots) and
//! the window in `app` (eframe, feature `window`).
//!
//! ```
//! use flowtile_bake::editor::{commands::run_script, model::Editor};
//! let mut ed = Editor::blank(6, 4).unwrap();
//! let log = run_script(&mut ed, "border x zero\nflux v 0 1 1\nfill\n", None).unwrap();
//! assert!(ed.tiling().is_complete());
//! assert!(log.contains("filled"));
//! ```

pub mod commands;
pub mod model;
pub mod view;

#[cfg(feature = "window")]
pub mod app;
