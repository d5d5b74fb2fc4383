//! Drawing the editor with egui: the grid over an optional background,
//! tiles as arrows or streamlines, particles moving through the placed
//! tiles, the tools, the palette of the selected slot (allowed tiles and the
//! greyed ones with the reason), undo/redo, save and bake.
//!
//! Everything goes through [`EditorView::ui`], which takes an [`egui::Ui`]:
//! the window (`app`, feature `window`) calls it every frame, and
//! [`screenshot`] runs it without a display and rasterises egui's output on
//! the CPU, so a scripted session's picture is the same bytes every time.
//!
//! One file per area: `toolbar.rs` (top), `status.rs` (bottom), `tools.rs`
//! (left), `palette.rs` (right), `grid.rs` (centre), with `keys.rs` (the
//! shortcuts); `tiles.rs` and `particles.rs` hold what the grid draws,
//! `background.rs` the picture under it, `screenshot.rs` the headless
//! rendering.

mod background;
mod grid;
mod keys;
mod palette;
mod particles;
mod screenshot;
mod status;
mod tiles;
mod toolbar;
mod tools;

use std::collections::HashMap;
use std::path::PathBuf;

use egui::Ui;

use super::commands::{Command, ViewSettings};
use super::model::{Editor, Palette};
use crate::tileset::TileKey;
pub use background::Background;
use particles::Particles;
pub use screenshot::screenshot;
use tiles::TileDraw;

/// What a click on the grid does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Select a slot and open its palette; right click clears a tile.
    Tiles,
    /// Paint blocked slots.
    Block,
    /// Erase blocked slots.
    Open,
    /// Fix (or free) the flux of the clicked edge.
    Flux,
    /// Fix (or free) the velocity of the clicked vertex.
    Corner,
}

/// The editor's view state and drawing.
pub struct EditorView {
    /// Settings scripts can set.
    pub settings: ViewSettings,
    /// The current tool.
    pub tool: Tool,
    /// Flux the flux tool fixes (`None`: frees the edge).
    pub flux_value: Option<i32>,
    /// Velocity index the corner tool fixes (`None`: frees the vertex).
    pub corner_value: Option<u16>,
    /// Where "save" writes the spec.
    pub save_path: PathBuf,
    /// Where "bake" writes the tiling.
    pub bake_path: PathBuf,
    /// True when the last status message is an error.
    pub status_is_error: bool,
    background: Option<Background>,
    bg_texture: Option<egui::TextureHandle>,
    palette: Option<(u64, (u32, u32), Palette)>,
    pick: Option<[i32; 4]>,
    pick_corners: [u16; 4],
    tiles: HashMap<TileKey, TileDraw>,
    tiles_for: Option<u64>,
    particles: Particles,
    /// Undo depth when the current paint stroke began.
    stroke: Option<usize>,
}

impl EditorView {
    /// A view writing to `save_path` and `bake_path`.
    pub fn new(save_path: PathBuf, bake_path: PathBuf, background: Option<Background>) -> Self {
        EditorView {
            settings: ViewSettings::default(),
            tool: Tool::Tiles,
            flux_value: Some(1),
            corner_value: Some(0),
            save_path,
            bake_path,
            status_is_error: false,
            background,
            bg_texture: None,
            palette: None,
            pick: None,
            pick_corners: [0; 4],
            tiles: HashMap::new(),
            tiles_for: None,
            particles: Particles::new(),
            stroke: None,
        }
    }

    /// Runs a command from the UI and shows its message.
    pub fn run(&mut self, ed: &mut Editor, cmd: Command) {
        match cmd.apply(ed, &mut self.settings) {
            Ok(msg) => {
                self.settings.status = msg;
                self.status_is_error = false;
            }
            Err(e) => {
                self.settings.status = format!("{cmd}: {e}");
                self.status_is_error = true;
            }
        }
    }

    /// Draws the whole editor into `ui` and handles its input.
    pub fn ui(&mut self, ui: &mut Ui, ed: &mut Editor) {
        self.keys(ui, ed);
        egui::Panel::top("toolbar").show_inside(ui, |ui| self.toolbar(ui, ed));
        egui::Panel::bottom("status").show_inside(ui, |ui| self.status_bar(ui, ed));
        egui::Panel::left("tools")
            .exact_size(215.0)
            .show_inside(ui, |ui| self.tools(ui, ed));
        egui::Panel::right("palette")
            .exact_size(300.0)
            .show_inside(ui, |ui| self.palette_panel(ui, ed));
        egui::CentralPanel::default().show_inside(ui, |ui| self.grid(ui, ed));
    }
}

/// The largest flux multiple of the tile set in either direction (at least
/// 1): what arrows in tiles and palette icons are scaled to.
fn largest_flux(set: &crate::tileset::TileSet) -> i32 {
    set.mx
        .min
        .abs()
        .max(set.mx.max.abs())
        .max(set.my.min.abs())
        .max(set.my.max.abs())
        .max(1)
}

#[cfg(test)]
mod tests;
