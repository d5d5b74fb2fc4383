//! The tiling's state and the grid's indexing: slots, edges and vertices to
//! network arcs and corner entries (with periodic wrap-around), and the
//! read-only accessors.

use super::{Border, Edge, TilingError};
use crate::flow::{ArcId, Network};
use crate::tileset::{TileKey, TileSet};

/// A partial or complete tiling together with its constraints.
///
/// ```
/// use flowtile_bake::{tileset::TileSet, tiling::{Tiling, Conditions, Border}, rng::Rng};
/// let set = TileSet::paper(3, 3, 1, 4).unwrap();
/// let mut t = Tiling::new(set, 3, 3, &Conditions::borders(Border::Zero, Border::Zero)).unwrap();
/// t.random_fill(&mut Rng::new(1)).unwrap();
/// assert!(t.is_complete());
/// ```
#[derive(Clone, Debug)]
pub struct Tiling {
    pub(super) set: TileSet,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) border_x: Border,
    pub(super) border_y: Border,
    pub(super) blocked: Vec<bool>,
    pub(super) net: Network,
    pub(super) v_arcs: Vec<ArcId>,
    pub(super) h_arcs: Vec<ArcId>,
    pub(super) corner_fixed: Vec<Option<u16>>,
    pub(super) slots: Vec<Option<TileKey>>,
    /// Arc bounds and fixed corners from the conditions alone (before any
    /// tile), restored by [`Tiling::remove`].
    pub(super) base_bounds: Vec<(i32, i32)>,
    pub(super) base_corners: Vec<Option<u16>>,
    /// Scratch buffer of [`Tiling::ladder_move`]'s cycles.
    pub(super) cycle: Vec<(u32, ArcId)>,
}

impl Tiling {
    /// Index of vertex `(x, y)` with periodic wrap-around.
    pub(super) fn vertex(&self, x: u32, y: u32) -> usize {
        let vw = grid_lines(self.border_x, self.width);
        let xw = if self.border_x == Border::Periodic {
            x % self.width
        } else {
            x
        };
        let yw = if self.border_y == Border::Periodic {
            y % self.height
        } else {
            y
        };
        (yw * vw + xw) as usize
    }

    /// The network arc of a grid edge.
    pub(super) fn edge_arc(&self, edge: Edge) -> Result<ArcId, TilingError> {
        match edge {
            Edge::Vertical { x, y } => {
                if x > self.width || y >= self.height {
                    return Err(TilingError::OutOfGrid(format!("{edge:?}")));
                }
                // Periodic in x: W arcs per row, the one at x = W is x = 0.
                let per_row = grid_lines(self.border_x, self.width);
                Ok(self.v_arcs[(y * per_row + x % per_row) as usize])
            }
            Edge::Horizontal { x, y } => {
                if x >= self.width || y > self.height {
                    return Err(TilingError::OutOfGrid(format!("{edge:?}")));
                }
                let rows = grid_lines(self.border_y, self.height);
                Ok(self.h_arcs[((y % rows) * self.width + x) as usize])
            }
        }
    }

    /// Arcs of slot `(x, y)` (inside the grid): left, bottom, right, top.
    /// Indexed directly, wrapping only the far edges of periodic grids: the
    /// fill asks for them at every slot.
    pub(super) fn slot_arcs(&self, x: u32, y: u32) -> [ArcId; 4] {
        debug_assert!(x < self.width && y < self.height);
        let w = self.width;
        let per_row = grid_lines(self.border_x, w);
        let right = if x + 1 == per_row { 0 } else { x + 1 };
        let above = if y + 1 == self.height && self.border_y == Border::Periodic {
            0
        } else {
            y + 1
        };
        [
            self.v_arcs[(y * per_row + x) as usize],
            self.h_arcs[(y * w + x) as usize],
            self.v_arcs[(y * per_row + right) as usize],
            self.h_arcs[(above * w + x) as usize],
        ]
    }

    /// Vertices of slot `(x, y)`: bottom-left, bottom-right, top-right, top-left.
    /// Indexed directly like [`Tiling::slot_arcs`] (`(x, y)` inside the grid).
    pub(super) fn slot_vertices(&self, x: u32, y: u32) -> [usize; 4] {
        debug_assert!(x < self.width && y < self.height);
        let (px, py) = (
            self.border_x == Border::Periodic,
            self.border_y == Border::Periodic,
        );
        let vw = grid_lines(self.border_x, self.width);
        let right = if px && x + 1 == self.width { 0 } else { x + 1 };
        let above = if py && y + 1 == self.height { 0 } else { y + 1 };
        let v = |xx: u32, yy: u32| (yy * vw + xx) as usize;
        [v(x, y), v(right, y), v(right, above), v(x, above)]
    }

    /// The tile set.
    pub fn set(&self) -> &TileSet {
        &self.set
    }

    /// Grid width in slots.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Grid height in slots.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Left/right and bottom/top borders.
    pub fn borders(&self) -> (Border, Border) {
        (self.border_x, self.border_y)
    }

    /// True when slot `(x, y)` is blocked by the mask.
    pub fn is_blocked(&self, x: u32, y: u32) -> bool {
        self.blocked[(y * self.width + x) as usize]
    }

    /// The tile at `(x, y)`, if one has been placed.
    pub fn tile(&self, x: u32, y: u32) -> Option<TileKey> {
        self.slots[(y * self.width + x) as usize]
    }

    /// Number of tile slots (excluding blocked ones).
    pub fn open_slots(&self) -> usize {
        self.blocked.iter().filter(|b| !**b).count()
    }

    /// True when every unblocked slot holds a tile.
    pub fn is_complete(&self) -> bool {
        self.slots
            .iter()
            .zip(&self.blocked)
            .all(|(s, b)| *b || s.is_some())
    }

    /// The distinct tiles in use, sorted.
    pub fn tiles_used(&self) -> Vec<TileKey> {
        let mut keys: Vec<TileKey> = self.slots.iter().flatten().copied().collect();
        keys.sort_unstable();
        keys.dedup();
        keys
    }

    /// Refuses slots outside the grid, blocked or already tiled.
    pub(super) fn check_slot(&self, x: u32, y: u32) -> Result<(), TilingError> {
        if x >= self.width || y >= self.height {
            return Err(TilingError::NoSuchSlot(x, y));
        }
        if self.is_blocked(x, y) {
            return Err(TilingError::SlotBlocked(x, y));
        }
        if self.tile(x, y).is_some() {
            return Err(TilingError::SlotOccupied(x, y));
        }
        Ok(())
    }

    /// The arc of horizontal edge `(col, row)` for `row < H` (no wrap-around).
    pub(super) fn h_arc(&self, col: u32, row: u32) -> ArcId {
        self.h_arcs[(row * self.width + col) as usize]
    }

    /// The arc of vertical edge `(col, row)` for `col < W` (no wrap-around).
    pub(super) fn v_arc(&self, col: u32, row: u32) -> ArcId {
        let per_row = grid_lines(self.border_x, self.width);
        self.v_arcs[(row * per_row + col) as usize]
    }

    /// Current bounds of a grid edge's flux (after placements and conditions).
    pub fn edge_bounds(&self, edge: Edge) -> Result<(i32, i32), TilingError> {
        let a = self.net.arc(self.edge_arc(edge)?);
        Ok((a.lo, a.hi))
    }

    /// The exact interval of flux values a grid edge can still take.
    pub fn edge_interval(&mut self, edge: Edge) -> Result<(i32, i32), TilingError> {
        let a = self.edge_arc(edge)?;
        Ok(self.net.range(a))
    }
}

/// Grid lines across `n` slots: `n + 1`, or `n` when the `border` glues the
/// two ends together (the last line is the first). The number of vertical
/// edges per row (with `n` the width), of horizontal edge rows (the height),
/// and of vertices along either axis.
pub(super) fn grid_lines(border: Border, n: u32) -> u32 {
    if border == Border::Periodic { n } else { n + 1 }
}
