//! The problem's boundary conditions (borders, blocked slots, fixed fluxes
//! and corners), the ASCII mask reader, the grid's size limits and the
//! errors of tiling problems and placements.

use std::fmt;

use crate::tileset::TileKey;

/// What happens at a pair of opposite outer borders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Border {
    /// Any flux the tile set offers may cross, corners are free.
    Free,
    /// Walls: zero flux and zero corner velocity.
    Zero,
    /// The two borders are glued together (a torus in that direction).
    Periodic,
}

/// A grid edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Edge {
    /// Vertical edge at `x` in row `y` (flux towards +x).
    Vertical {
        /// Column of the edge, `0..=W`.
        x: u32,
        /// Row, `0..H`.
        y: u32,
    },
    /// Horizontal edge at `y` in column `x` (flux towards +y).
    Horizontal {
        /// Column, `0..W`.
        x: u32,
        /// Row of the edge, `0..=H`.
        y: u32,
    },
}

/// Boundary conditions of a tiling problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Conditions {
    /// Left and right borders.
    pub border_x: Border,
    /// Bottom and top borders.
    pub border_y: Border,
    /// Blocked slots, row-major from the bottom row (`y * W + x`); empty for none.
    pub blocked: Vec<bool>,
    /// Edges with a fixed flux multiple.
    pub fluxes: Vec<(Edge, i32)>,
    /// Vertices `(x, y)` with a fixed corner velocity index.
    pub corners: Vec<((u32, u32), u16)>,
}

impl Conditions {
    /// Conditions with the given borders and nothing else.
    pub fn borders(border_x: Border, border_y: Border) -> Conditions {
        Conditions {
            border_x,
            border_y,
            blocked: Vec::new(),
            fluxes: Vec::new(),
            corners: Vec::new(),
        }
    }
}

/// Reads an ASCII mask: one line per row, top row first; `#`, `X` or `x`
/// mark blocked slots, `.` or space free ones. Returns the row-major blocked
/// flags (bottom row first) for a `width`×`height` grid.
pub fn parse_mask(text: &str, width: u32, height: u32) -> Result<Vec<bool>, TilingError> {
    let rows: Vec<&str> = text
        .lines()
        .map(|l| l.trim_end_matches('\r'))
        .filter(|l| !l.trim().is_empty())
        .collect();
    if rows.len() != height as usize {
        return Err(TilingError::BadMask(format!(
            "{} rows, grid has {height}",
            rows.len()
        )));
    }
    let mut blocked = vec![false; (width * height) as usize];
    for (r, line) in rows.iter().enumerate() {
        let chars: Vec<char> = line.trim().chars().collect();
        if chars.len() != width as usize {
            return Err(TilingError::BadMask(format!(
                "row {} has {} columns, grid has {width}",
                r + 1,
                chars.len()
            )));
        }
        let y = height as usize - 1 - r;
        for (x, ch) in chars.iter().enumerate() {
            blocked[y * width as usize + x] = match ch {
                '#' | 'X' | 'x' => true,
                '.' | ' ' => false,
                other => {
                    return Err(TilingError::BadMask(format!(
                        "unexpected character {other:?} in row {}",
                        r + 1
                    )));
                }
            };
        }
    }
    Ok(blocked)
}

/// Errors of tiling problems and placements.
#[derive(Clone, Debug, PartialEq)]
pub enum TilingError {
    /// Width or height zero or too large.
    BadGrid(u32, u32),
    /// The mask does not fit the grid.
    BadMask(String),
    /// An edge or vertex outside the grid.
    OutOfGrid(String),
    /// A fixed flux the tile set does not offer on that edge.
    FluxOutOfRange(Edge, i32),
    /// A corner index the tile set does not have.
    CornerOutOfRange(u16),
    /// Two conditions disagree.
    Conflict(String),
    /// Walls or blocked slots need a zero corner velocity option.
    NoZeroCorner,
    /// The conditions admit no complete tiling.
    Infeasible(String),
    /// The slot is blocked by the mask.
    SlotBlocked(u32, u32),
    /// The slot already holds a tile.
    SlotOccupied(u32, u32),
    /// The slot is outside the grid.
    NoSuchSlot(u32, u32),
    /// The tile would make the tiling impossible to complete.
    TileNotAllowed(u32, u32, TileKey),
}

impl fmt::Display for TilingError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TilingError::BadGrid(w, h) => write!(
                f,
                "grid {w}x{h} is empty or larger than {MAX_SIDE}x{MAX_SIDE} / {MAX_SLOTS} slots"
            ),
            TilingError::BadMask(why) => write!(f, "mask does not fit the grid: {why}"),
            TilingError::OutOfGrid(what) => write!(f, "{what} lies outside the grid"),
            TilingError::FluxOutOfRange(e, m) => {
                write!(f, "fixed flux {m} on {e:?} is not offered by the tile set")
            }
            TilingError::CornerOutOfRange(c) => {
                write!(f, "corner velocity index {c} is not in the tile set")
            }
            TilingError::Conflict(why) => write!(f, "conflicting conditions: {why}"),
            TilingError::NoZeroCorner => write!(
                f,
                "walls and blocked slots need the zero velocity among the corner options"
            ),
            TilingError::Infeasible(why) => {
                write!(f, "boundary conditions admit no complete tiling ({why})")
            }
            TilingError::SlotBlocked(x, y) => write!(f, "slot ({x}, {y}) is blocked"),
            TilingError::SlotOccupied(x, y) => write!(f, "slot ({x}, {y}) is already tiled"),
            TilingError::NoSuchSlot(x, y) => write!(f, "slot ({x}, {y}) is outside the grid"),
            TilingError::TileNotAllowed(x, y, k) => write!(
                f,
                "tile {k} at ({x}, {y}) would leave the tiling uncompletable"
            ),
        }
    }
}

impl std::error::Error for TilingError {}

/// Largest grid side.
pub const MAX_SIDE: u32 = 8192;
/// Largest number of slots.
pub const MAX_SLOTS: u64 = 1 << 24;
