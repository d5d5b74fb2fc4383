//! Tilings: a W×H grid of tile slots, boundary conditions, and the selection
//! function that offers, for any empty slot of any partial tiling, exactly the
//! tiles that keep the tiling completable (paper §4).
//!
//! Fluxes and corners are independent: corner velocities only have to match
//! between the (up to four) slots meeting at a grid vertex, which is a local
//! check, while fluxes are coupled across the whole grid by conservation. The
//! flux constraints live in a [`Network`] (one node per slot plus the outside,
//! one arc per grid edge) that always holds a feasible circulation; see
//! [`crate::flow`].
//!
//! Grid conventions: slot `(x, y)` has `x` to the right and `y` up. Vertical
//! edge `(x, y)` (`0 ≤ x ≤ W`) lies between slots `(x-1, y)` and `(x, y)` and
//! carries flux towards +x; horizontal edge `(x, y)` (`0 ≤ y ≤ H`) lies
//! between `(x, y-1)` and `(x, y)` and carries flux towards +y. Vertex
//! `(x, y)` is the lower-left corner of slot `(x, y)`.

use std::fmt;

use crate::flow::{ArcId, Network};
use crate::prefer::{Preferences, Usage, normalise_log_weights};
use crate::rng::Rng;
use crate::tileset::{TileKey, TileSet};

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

/// Capacity of the arcs that join the outside ring: more than any border can carry.
const UNBOUNDED: i32 = 1 << 28;

/// Largest grid side.
pub const MAX_SIDE: u32 = 8192;
/// Largest number of slots.
pub const MAX_SLOTS: u64 = 1 << 24;

/// The tiles the selection function offers for one slot: every listed flux
/// tuple combined with every choice of the four corner lists.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Selection {
    /// Flux tuples `(left, bottom, right, top)` that keep the tiling completable.
    pub fluxes: Vec<[i32; 4]>,
    /// Allowed corner indices: bottom-left, bottom-right, top-right, top-left.
    pub corners: [Vec<u16>; 4],
    /// `Some(j)` when corner `k` is the same grid vertex as corner `j < k`
    /// (periodic grids one slot wide or high) and must repeat its choice.
    pub same_as: [Option<usize>; 4],
}

impl Selection {
    /// Number of tiles offered.
    pub fn len(&self) -> u64 {
        self.fluxes.len() as u64 * self.corner_choices()
    }

    fn corner_choices(&self) -> u64 {
        (0..4)
            .filter(|&k| self.same_as[k].is_none())
            .map(|k| self.corners[k].len() as u64)
            .product()
    }

    /// True when nothing fits (never happens for a completable tiling).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The `i`-th offered tile (`i < len()`).
    pub fn key(&self, i: u64) -> TileKey {
        let per_flux = self.corner_choices();
        let [left, bottom, right, top] = self.fluxes[(i / per_flux) as usize];
        let mut rest = i % per_flux;
        let mut corners = [0u16; 4];
        for k in (0..4).rev() {
            if self.same_as[k].is_none() {
                let len = self.corners[k].len() as u64;
                corners[k] = self.corners[k][(rest % len) as usize];
                rest /= len;
            }
        }
        for k in 0..4 {
            if let Some(j) = self.same_as[k] {
                corners[k] = corners[j];
            }
        }
        TileKey {
            left,
            bottom,
            right,
            top,
            corners,
        }
    }

    /// Every offered tile.
    pub fn keys(&self) -> impl Iterator<Item = TileKey> + '_ {
        (0..self.len()).map(|i| self.key(i))
    }
}

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
    set: TileSet,
    width: u32,
    height: u32,
    border_x: Border,
    border_y: Border,
    blocked: Vec<bool>,
    net: Network,
    v_arcs: Vec<ArcId>,
    h_arcs: Vec<ArcId>,
    corner_fixed: Vec<Option<u16>>,
    slots: Vec<Option<TileKey>>,
    /// Arc bounds and fixed corners from the conditions alone (before any
    /// tile), restored by [`Tiling::remove`].
    base_bounds: Vec<(i32, i32)>,
    base_corners: Vec<Option<u16>>,
    /// Scratch buffer of [`Tiling::ladder_move`]'s cycles.
    cycle: Vec<(u32, ArcId)>,
}

impl Tiling {
    /// Sets up an empty tiling and checks that it can be completed.
    pub fn new(
        set: TileSet,
        width: u32,
        height: u32,
        cond: &Conditions,
    ) -> Result<Tiling, TilingError> {
        if width == 0
            || height == 0
            || width > MAX_SIDE
            || height > MAX_SIDE
            || width as u64 * height as u64 > MAX_SLOTS
        {
            return Err(TilingError::BadGrid(width, height));
        }
        let slots = (width * height) as usize;
        let blocked = if cond.blocked.is_empty() {
            vec![false; slots]
        } else if cond.blocked.len() == slots {
            cond.blocked.clone()
        } else {
            return Err(TilingError::BadMask(format!(
                "{} flags for {slots} slots",
                cond.blocked.len()
            )));
        };
        // The outside is one node in the flow problem. Storing it as a ring of
        // "ports", one per border edge, joined by unbounded arcs is equivalent
        // but keeps every search local: a path that leaves through the border
        // walks along the ring instead of fanning out to every border slot.
        let (w, h) = (width as i64, height as i64);
        let ring = 2 * (width + height) as usize;
        let port = |x: i64, y: i64| -> u32 {
            let k = if y < 0 {
                x
            } else if x >= w {
                w + y
            } else if y >= h {
                w + h + (w - 1 - x)
            } else {
                2 * w + h + (h - 1 - y)
            };
            (slots as i64 + k) as u32
        };
        let mut net = Network::new(slots + ring);
        let slot_node = |x: i64, y: i64| -> u32 {
            let xw = if cond.border_x == Border::Periodic {
                x.rem_euclid(w)
            } else {
                x
            };
            let yw = if cond.border_y == Border::Periodic {
                y.rem_euclid(h)
            } else {
                y
            };
            if xw < 0 || yw < 0 || xw >= w || yw >= h {
                port(xw, yw)
            } else {
                (yw * w + xw) as u32
            }
        };
        let outside = |node: u32| node as usize >= slots;
        let is_blocked = |node: u32| !outside(node) && blocked[node as usize];
        let (mx, my) = (set.mx, set.my);
        let bounds = |tail: u32, head: u32, border: Border, r: crate::tileset::FluxRange| {
            let at_border = outside(tail) || outside(head);
            if is_blocked(tail) || is_blocked(head) || (at_border && border == Border::Zero) {
                (0, 0)
            } else {
                (r.min, r.max)
            }
        };
        for k in 0..ring {
            let a = (slots + k) as u32;
            let b = (slots + (k + 1) % ring) as u32;
            net.add_arc(a, b, -UNBOUNDED, UNBOUNDED);
        }
        // Vertical edges: with periodic x the edge at x = W is the one at x = 0;
        // likewise horizontal edges with periodic y.
        let vx_count = if cond.border_x == Border::Periodic {
            width
        } else {
            width + 1
        };
        let hy_count = if cond.border_y == Border::Periodic {
            height
        } else {
            height + 1
        };
        // Arcs are numbered slot by slot (left then bottom edge), so the arcs
        // a search reads around a slot share cache lines: the searches of
        // the fill are bound by memory reads, not arithmetic.
        let mut v_arcs = vec![0; (vx_count * height) as usize];
        let mut h_arcs = vec![0; (hy_count * width) as usize];
        for y in 0..height.max(hy_count) {
            for x in 0..vx_count.max(width) {
                let (xi, yi) = (x as i64, y as i64);
                if y < height && x < vx_count {
                    let (tail, head) = (slot_node(xi - 1, yi), slot_node(xi, yi));
                    let (lo, hi) = bounds(tail, head, cond.border_x, mx);
                    v_arcs[(y * vx_count + x) as usize] = net.add_arc(tail, head, lo, hi);
                }
                if y < hy_count && x < width {
                    let (tail, head) = (slot_node(xi, yi - 1), slot_node(xi, yi));
                    let (lo, hi) = bounds(tail, head, cond.border_y, my);
                    h_arcs[(y * width + x) as usize] = net.add_arc(tail, head, lo, hi);
                }
            }
        }
        let vw = if cond.border_x == Border::Periodic {
            width
        } else {
            width + 1
        };
        let vh = if cond.border_y == Border::Periodic {
            height
        } else {
            height + 1
        };
        let mut tiling = Tiling {
            set,
            width,
            height,
            border_x: cond.border_x,
            border_y: cond.border_y,
            blocked,
            net,
            v_arcs,
            h_arcs,
            corner_fixed: vec![None; (vw * vh) as usize],
            slots: vec![None; slots],
            base_bounds: Vec::new(),
            base_corners: Vec::new(),
            cycle: Vec::new(),
        };
        tiling.apply_corner_conditions(cond)?;
        let mut fixed: Vec<Option<i32>> = vec![None; tiling.net.arc_count()];
        for &(edge, m) in &cond.fluxes {
            let arc = tiling.edge_arc(edge)?;
            let a = tiling.net.arc(arc);
            let touches_block = [a.tail, a.head]
                .iter()
                .any(|&n| (n as usize) < slots && tiling.blocked[n as usize]);
            if touches_block && m != 0 {
                return Err(TilingError::Conflict(format!(
                    "{edge:?} borders a blocked slot and cannot carry flux {m}"
                )));
            }
            if let Some(old) = fixed[arc]
                && old != m
            {
                return Err(TilingError::Conflict(format!(
                    "{edge:?} fixed to both {old} and {m}"
                )));
            }
            let range = match edge {
                Edge::Vertical { .. } => mx,
                Edge::Horizontal { .. } => my,
            };
            if !range.contains(m) {
                return Err(TilingError::FluxOutOfRange(edge, m));
            }
            // An explicit flux overrides a wall border: an inlet or outlet.
            fixed[arc] = Some(m);
            tiling.net_clamp(arc, m);
        }
        tiling
            .net
            .make_feasible()
            .map_err(|e| TilingError::Infeasible(tiling.describe_node(e.node)))?;
        tiling.base_bounds = (0..tiling.net.arc_count())
            .map(|a| {
                let a = tiling.net.arc(a);
                (a.lo, a.hi)
            })
            .collect();
        tiling.base_corners = tiling.corner_fixed.clone();
        Ok(tiling)
    }

    /// Narrows an arc of the not yet solved network to one value.
    fn net_clamp(&mut self, arc: ArcId, m: i32) {
        self.net.set_bounds(arc, m, m);
    }

    fn describe_node(&self, node: u32) -> String {
        if node as usize >= self.slots.len() {
            "flux through the outer border cannot balance".to_string()
        } else {
            let (x, y) = (node % self.width, node / self.width);
            format!("flux cannot balance at slot ({x}, {y})")
        }
    }

    fn apply_corner_conditions(&mut self, cond: &Conditions) -> Result<(), TilingError> {
        let c = self.set.corners.len() as u16;
        let zero = self.set.zero_corner();
        let mut need_zero = Vec::new();
        for y in 0..self.height {
            for x in 0..self.width {
                if self.blocked[(y * self.width + x) as usize] {
                    need_zero.extend([(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)]);
                }
            }
        }
        if self.border_x == Border::Zero {
            for y in 0..=self.height {
                need_zero.extend([(0, y), (self.width, y)]);
            }
        }
        if self.border_y == Border::Zero {
            for x in 0..=self.width {
                need_zero.extend([(x, 0), (x, self.height)]);
            }
        }
        if !need_zero.is_empty() {
            let z = zero.ok_or(TilingError::NoZeroCorner)?;
            for (x, y) in need_zero {
                let v = self.vertex(x, y);
                self.corner_fixed[v] = Some(z);
            }
        }
        for &((x, y), idx) in &cond.corners {
            if idx >= c {
                return Err(TilingError::CornerOutOfRange(idx));
            }
            if x > self.width || y > self.height {
                return Err(TilingError::OutOfGrid(format!("vertex ({x}, {y})")));
            }
            let v = self.vertex(x, y);
            match self.corner_fixed[v] {
                Some(old) if old != idx => {
                    return Err(TilingError::Conflict(format!(
                        "vertex ({x}, {y}) fixed to corner {old} and {idx}"
                    )));
                }
                _ => self.corner_fixed[v] = Some(idx),
            }
        }
        Ok(())
    }

    /// Index of vertex `(x, y)` with periodic wrap-around.
    fn vertex(&self, x: u32, y: u32) -> usize {
        let vw = if self.border_x == Border::Periodic {
            self.width
        } else {
            self.width + 1
        };
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
    fn edge_arc(&self, edge: Edge) -> Result<ArcId, TilingError> {
        match edge {
            Edge::Vertical { x, y } => {
                if x > self.width || y >= self.height {
                    return Err(TilingError::OutOfGrid(format!("{edge:?}")));
                }
                // Periodic in x: W arcs per row, the one at x = W is x = 0.
                let per_row = if self.border_x == Border::Periodic {
                    self.width
                } else {
                    self.width + 1
                };
                Ok(self.v_arcs[(y * per_row + x % per_row) as usize])
            }
            Edge::Horizontal { x, y } => {
                if x >= self.width || y > self.height {
                    return Err(TilingError::OutOfGrid(format!("{edge:?}")));
                }
                let rows = if self.border_y == Border::Periodic {
                    self.height
                } else {
                    self.height + 1
                };
                Ok(self.h_arcs[((y % rows) * self.width + x) as usize])
            }
        }
    }

    /// Arcs of slot `(x, y)` (inside the grid): left, bottom, right, top.
    /// Indexed directly, wrapping only the far edges of periodic grids: the
    /// fill asks for them at every slot.
    fn slot_arcs(&self, x: u32, y: u32) -> [ArcId; 4] {
        debug_assert!(x < self.width && y < self.height);
        let w = self.width;
        let per_row = if self.border_x == Border::Periodic {
            w
        } else {
            w + 1
        };
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
    fn slot_vertices(&self, x: u32, y: u32) -> [usize; 4] {
        debug_assert!(x < self.width && y < self.height);
        let (px, py) = (
            self.border_x == Border::Periodic,
            self.border_y == Border::Periodic,
        );
        let vw = if px { self.width } else { self.width + 1 };
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

    fn check_slot(&self, x: u32, y: u32) -> Result<(), TilingError> {
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

    /// The selection function: every tile that fits slot `(x, y)` and keeps
    /// the tiling completable.
    ///
    /// Each free edge's exact flux interval comes from max-flow on the
    /// residual graph. With at most two free edges (scan-line order) every
    /// value in the interval is feasible, since conservation leaves one degree
    /// of freedom; with more, each candidate tuple is tested by fixing it
    /// tentatively and rolling back (the paper's second step, needed only
    /// then).
    pub fn select(&mut self, x: u32, y: u32) -> Result<Selection, TilingError> {
        self.check_slot(x, y)?;
        let arcs = self.slot_arcs(x, y);
        let mut ranges = [(0i32, 0i32); 4];
        let mut free_arcs: Vec<ArcId> = Vec::with_capacity(4);
        for (k, &a) in arcs.iter().enumerate() {
            let arc = self.net.arc(a);
            if arc.lo == arc.hi {
                ranges[k] = (arc.lo, arc.hi);
            } else {
                if !free_arcs.contains(&a) {
                    free_arcs.push(a);
                }
                ranges[k] = (arc.lo, arc.hi); // refined below
            }
        }
        for &a in &free_arcs {
            let r = self.net.range(a);
            for k in 0..4 {
                if arcs[k] == a {
                    ranges[k] = r;
                }
            }
        }
        let mut fluxes = Vec::new();
        let test_each = free_arcs.len() >= 3;
        for l in ranges[0].0..=ranges[0].1 {
            for b in ranges[1].0..=ranges[1].1 {
                for r in ranges[2].0..=ranges[2].1 {
                    let t = l + b - r;
                    if t < ranges[3].0 || t > ranges[3].1 {
                        continue;
                    }
                    let values = [l, b, r, t];
                    if !self.same_arc_consistent(&arcs, &values) {
                        continue;
                    }
                    if test_each && !self.tuple_feasible(&arcs, &values) {
                        continue;
                    }
                    fluxes.push(values);
                }
            }
        }
        let c = self.set.corners.len() as u16;
        let verts = self.slot_vertices(x, y);
        let corners = verts.map(|v| match self.corner_fixed[v] {
            Some(i) => vec![i],
            None => (0..c).collect(),
        });
        let same_as = std::array::from_fn(|k| (0..k).find(|&j| verts[j] == verts[k]));
        Ok(Selection {
            fluxes,
            corners,
            same_as,
        })
    }

    /// With periodic borders of width or height 1 a slot's opposite edges are
    /// the same arc and must carry the same value.
    fn same_arc_consistent(&self, arcs: &[ArcId; 4], values: &[i32; 4]) -> bool {
        (0..4).all(|i| (0..4).all(|j| arcs[i] != arcs[j] || values[i] == values[j]))
    }

    fn tuple_feasible(&mut self, arcs: &[ArcId; 4], values: &[i32; 4]) -> bool {
        let mark = self.net.checkpoint();
        let ok = arcs.iter().zip(values).all(|(&a, &v)| self.net.fix(a, v));
        self.net.rollback(mark);
        ok
    }

    /// Places `key` at `(x, y)` if it keeps the tiling completable.
    pub fn place(&mut self, x: u32, y: u32, key: TileKey) -> Result<(), TilingError> {
        self.check_slot(x, y)?;
        if self.set.index_of(&key).is_none() {
            return Err(TilingError::TileNotAllowed(x, y, key));
        }
        let verts = self.slot_vertices(x, y);
        for (k, &v) in verts.iter().enumerate() {
            if let Some(c) = self.corner_fixed[v]
                && c != key.corners[k]
            {
                return Err(TilingError::TileNotAllowed(x, y, key));
            }
        }
        // Same vertex twice (periodic 1-wide grids) must get the same corner.
        for i in 0..4 {
            for j in 0..4 {
                if verts[i] == verts[j] && key.corners[i] != key.corners[j] {
                    return Err(TilingError::TileNotAllowed(x, y, key));
                }
            }
        }
        let arcs = self.slot_arcs(x, y);
        let values = key.fluxes();
        let mark = self.net.checkpoint();
        let ok = arcs.iter().zip(&values).all(|(&a, &v)| self.net.fix(a, v));
        if !ok {
            self.net.rollback(mark);
            return Err(TilingError::TileNotAllowed(x, y, key));
        }
        self.net.commit();
        for (k, &v) in verts.iter().enumerate() {
            self.corner_fixed[v] = Some(key.corners[k]);
        }
        self.slots[(y * self.width + x) as usize] = Some(key);
        Ok(())
    }

    /// Removes the tile at `(x, y)` and returns it (`None` for an empty or
    /// blocked slot). Fewer tiles never break completability: the current
    /// circulation stays feasible, and only the slot's edges and corners
    /// that no other tile holds go back to the conditions' bounds.
    ///
    /// ```
    /// use flowtile_bake::{tileset::TileSet, tiling::{Tiling, Conditions, Border}, rng::Rng};
    /// let set = TileSet::paper(3, 3, 1, 4).unwrap();
    /// let mut t = Tiling::new(set, 3, 3, &Conditions::borders(Border::Free, Border::Free)).unwrap();
    /// t.random_fill(&mut Rng::new(1)).unwrap();
    /// let k = t.remove(1, 1).unwrap();
    /// assert!(t.select(1, 1).unwrap().keys().any(|o| o == k));
    /// ```
    pub fn remove(&mut self, x: u32, y: u32) -> Option<TileKey> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let me = (y * self.width + x) as usize;
        let key = self.slots[me].take()?;
        for arc in self.slot_arcs(x, y) {
            let a = self.net.arc(arc);
            let other = if a.tail as usize == me {
                a.head
            } else {
                a.tail
            } as usize;
            let held = other < self.slots.len() && self.slots[other].is_some();
            if !held {
                let (lo, hi) = self.base_bounds[arc];
                self.net.set_bounds(arc, lo, hi);
            }
        }
        let (w, h) = (self.width as i64, self.height as i64);
        let (px, py) = (
            self.border_x == Border::Periodic,
            self.border_y == Border::Periodic,
        );
        for (vx, vy) in [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)] {
            let held = [(-1i64, -1i64), (0, -1), (-1, 0), (0, 0)]
                .iter()
                .any(|&(dx, dy)| {
                    let (mut sx, mut sy) = (vx as i64 + dx, vy as i64 + dy);
                    if px {
                        sx = sx.rem_euclid(w);
                    }
                    if py {
                        sy = sy.rem_euclid(h);
                    }
                    (0..w).contains(&sx)
                        && (0..h).contains(&sy)
                        && self.slots[(sy * w + sx) as usize].is_some()
                });
            if !held {
                let v = self.vertex(vx, vy);
                self.corner_fixed[v] = self.base_corners[v];
            }
        }
        Some(key)
    }

    /// Fills every slot that has exactly one option, repeatedly, until none
    /// is left (the paper's automatic filling of forced positions). Returns
    /// the number of tiles placed.
    pub fn fill_forced(&mut self) -> Result<usize, TilingError> {
        let mut placed = 0;
        loop {
            let mut changed = false;
            for y in 0..self.height {
                for x in 0..self.width {
                    if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                        continue;
                    }
                    let sel = self.select(x, y)?;
                    if sel.len() == 1 {
                        self.place(x, y, sel.key(0))?;
                        placed += 1;
                        changed = true;
                    }
                }
            }
            if !changed {
                return Ok(placed);
            }
        }
    }

    /// Fills every empty slot in scan-line order (bottom row first) with a
    /// tile chosen uniformly from the selection.
    pub fn random_fill(&mut self, rng: &mut Rng) -> Result<(), TilingError> {
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                    continue;
                }
                self.place_random(x, y, rng)?;
            }
        }
        Ok(())
    }

    /// Fills every empty slot in scan-line order like [`Tiling::random_fill`],
    /// drawing each tile with the weights of `prefs` among the tiles the
    /// selection function allows (so the fill always completes). Uniform
    /// preferences give exactly [`Tiling::random_fill`].
    ///
    /// ```
    /// use flowtile_bake::{tileset::TileSet, rng::Rng};
    /// use flowtile_bake::prefer::{DirectionRegion, Preferences};
    /// use flowtile_bake::tiling::{Border, Conditions, Tiling};
    /// let set = TileSet::paper(5, 3, 1, 4).unwrap();
    /// let mut t = Tiling::new(set, 12, 4, &Conditions::borders(Border::Periodic, Border::Zero)).unwrap();
    /// let p = Preferences {
    ///     regions: vec![DirectionRegion { x: (0, 11), y: (0, 3), direction: [1.0, 0.0], strength: 3.0 }],
    ///     ..Default::default()
    /// };
    /// t.random_fill_preferring(&mut Rng::new(1), &p).unwrap();
    /// assert!(t.is_complete());
    /// ```
    pub fn random_fill_preferring(
        &mut self,
        rng: &mut Rng,
        prefs: &Preferences,
    ) -> Result<(), TilingError> {
        if prefs.is_uniform() {
            return self.random_fill(rng);
        }
        let mut chooser = Chooser {
            dirs: prefs.slot_directions(self.width, self.height),
            prefs: prefs.clone(),
            usage: Usage::default(),
            backflow: Default::default(),
        };
        for key in self.slots.iter().flatten() {
            chooser.usage.add(*key);
        }
        for y in 0..self.height {
            for x in 0..self.width {
                if self.is_blocked(x, y) || self.tile(x, y).is_some() {
                    continue;
                }
                let key = self.place_chosen(x, y, rng, Some(&mut chooser))?;
                chooser.usage.add(key);
            }
        }
        Ok(())
    }

    /// Places a tile drawn uniformly from the selection of `(x, y)`.
    ///
    /// When at most two of the slot's edges are free (always so in scan-line
    /// order) the feasible values of the first free edge form an interval
    /// `F` and the second follows by conservation. Rather than computing `F`
    /// exactly (two full max-flow queries, then moving the flux back to the
    /// chosen value) we draw from a candidate interval `C ⊇ F` given by the
    /// edges' own bounds and try to move the flux there; a failed move proves
    /// where `F` ends, so `C` shrinks to it and we draw again. Conditioned on
    /// acceptance the draw is uniform over `F`, and the expected work is one
    /// short move instead of three long ones.
    pub fn place_random(&mut self, x: u32, y: u32, rng: &mut Rng) -> Result<TileKey, TilingError> {
        self.place_chosen(x, y, rng, None)
    }

    /// [`Tiling::place_random`] with optional preference weights.
    fn place_chosen(
        &mut self,
        x: u32,
        y: u32,
        rng: &mut Rng,
        mut chooser: Option<&mut Chooser>,
    ) -> Result<TileKey, TilingError> {
        self.check_slot(x, y)?;
        let slot = (y * self.width + x) as usize;
        let fixed = self.slot_vertices(x, y).map(|v| self.corner_fixed[v]);
        let arcs = self.slot_arcs(x, y);
        let distinct = (0..4).all(|i| (0..i).all(|j| arcs[i] != arcs[j]));
        // The slot's free edges, in side order (no allocation: this runs for
        // every slot of the fill).
        let mut free = [0usize; 4];
        let mut free_count = 0;
        for (k, &a) in arcs.iter().enumerate() {
            let a = self.net.arc(a);
            if a.lo < a.hi {
                free[free_count] = k;
                free_count += 1;
            }
        }
        let free = &free[..free_count];
        if !distinct {
            let sel = self.select(x, y)?;
            if sel.is_empty() {
                return Err(TilingError::Infeasible(format!(
                    "no tile fits slot ({x}, {y})"
                )));
            }
            let key = match chooser.as_deref_mut() {
                None => sel.key(rng.below(sel.len())),
                Some(c) => {
                    let keys: Vec<TileKey> = sel.keys().collect();
                    let mut logs: Vec<f64> = keys
                        .iter()
                        .map(|k| c.key_log_weight(slot, k, &self.set))
                        .collect();
                    normalise_log_weights(&mut logs);
                    keys[rng.weighted(&logs)]
                }
            };
            self.place(x, y, key)?;
            return Ok(key);
        }
        if free.len() > 2 {
            return self.place_random_tuple(x, y, arcs, rng, chooser);
        }
        // Conservation l + b - r - t = 0 with signs per side.
        const SIGN: [i32; 4] = [1, 1, -1, -1];
        let mut values = arcs.map(|a| self.net.arc(a).x);
        if free.len() == 2 {
            let (k, f) = (free[0], free[1]);
            let (ek, ef) = (self.net.arc(arcs[k]), self.net.arc(arcs[f]));
            let rest: i32 = (0..4)
                .filter(|&i| i != k && i != f)
                .map(|i| SIGN[i] * values[i])
                .sum();
            // value of side f given value v of side k
            let partner = |v: i32| -(rest + SIGN[k] * v) * SIGN[f];
            let mut lo = ek.lo;
            let mut hi = ek.hi;
            while lo <= hi && !(ef.lo..=ef.hi).contains(&partner(lo)) {
                lo += 1;
            }
            while hi >= lo && !(ef.lo..=ef.hi).contains(&partner(hi)) {
                hi -= 1;
            }
            let e = arcs[k];
            let tuple = |v: i32| {
                let mut t = values;
                t[k] = v;
                t[f] = partner(v);
                t
            };
            // Log-weights of every candidate value (only with preferences).
            let logs: Vec<f64> = match chooser.as_deref_mut() {
                Some(c) => (lo..=hi)
                    .map(|v| c.flux_log_weight(slot, tuple(v), fixed, &self.set))
                    .collect(),
                None => Vec::new(),
            };
            let first = lo;
            loop {
                if lo > hi {
                    return Err(TilingError::Infeasible(format!(
                        "no tile fits slot ({x}, {y})"
                    )));
                }
                let v = if logs.is_empty() {
                    lo + rng.below((hi - lo + 1) as u64) as i32
                } else {
                    let mut w = logs[(lo - first) as usize..=(hi - first) as usize].to_vec();
                    normalise_log_weights(&mut w);
                    lo + rng.weighted(&w) as i32
                };
                let cur = self.net.arc(e).x;
                if k == 2 && f == 3 && v != cur {
                    self.ladder_move(x, y, v);
                } else if k == 1 && y == 0 && self.border_y == Border::Periodic && v != cur {
                    self.seam_move(x, v);
                }
                let cur = self.net.arc(e).x;
                if v > cur {
                    let reached = self.net.raise(e, v);
                    if reached < v {
                        hi = reached;
                        continue;
                    }
                } else if v < cur {
                    let reached = self.net.lower(e, v);
                    if reached > v {
                        lo = reached;
                        continue;
                    }
                }
                values[k] = v;
                values[f] = partner(v);
                break;
            }
        }
        for (&a, &v) in arcs.iter().zip(&values) {
            if !self.net.fix(a, v) {
                return Err(TilingError::Infeasible(format!(
                    "internal: flux {v} became infeasible at ({x}, {y})"
                )));
            }
        }
        Ok(self.commit_slot(x, y, values, rng, chooser))
    }

    /// Moves the flux of slot `(x, y)`'s right edge towards `target` along
    /// "ladders", as far as they reach (the general search in
    /// [`Network::raise`] does the rest).
    ///
    /// In scan-line order the only free edges of the slot are its right and
    /// top edges, so every cycle through the right edge returns through the
    /// top one: along this row to some column `c ≥ x + 1`, up column `c`,
    /// back along some row above, down this column. Above the filled rows
    /// the unfilled rows carry the running sum of the fluxes that leave the
    /// filled part, and the nearest rows fill up to their bounds; the
    /// shortest cycle then climbs a few rows, and when the next slot's top
    /// edge is full it first walks a column or two along this row. Testing
    /// these cycles column by column and rung by rung finds one with a few
    /// arc reads, where the breadth-first search of the network would visit
    /// the whole band (most of the fill's time at 256×256).
    fn ladder_move(&mut self, x: u32, y: u32, target: i32) {
        let w = self.width;
        let next = if x + 1 < w {
            x + 1
        } else if self.border_x == Border::Periodic {
            0
        } else {
            return;
        };
        // Walking along the row only makes sense without wrap-around.
        let last_col = if next == 0 {
            0
        } else {
            (x + LADDER_SHIFTS).min(w - 1)
        };
        let e = self.slot_arcs(x, y)[2];
        // The cycle buffer lives in the tiling (no zeroing or allocation per call).
        let mut cycle = std::mem::take(&mut self.cycle);
        for _ in 0..4 {
            let cur = self.net.arc(e).x;
            if cur == target {
                break;
            }
            let up = target > cur;
            let Some((c, top)) = self.find_ladder(x, y, next, last_col, up) else {
                break;
            };
            self.ladder_cycle(x, y, next, c, top, up, e, &mut cycle);
            if self.net.push_cycle(&cycle, (target - cur).abs()) == 0 {
                break;
            }
        }
        self.cycle = cycle;
    }

    /// The arc of horizontal edge `(col, row)` for `row < H` (no wrap-around).
    fn h_arc(&self, col: u32, row: u32) -> ArcId {
        self.h_arcs[(row * self.width + col) as usize]
    }

    /// The arc of vertical edge `(col, row)` for `col < W` (no wrap-around).
    fn v_arc(&self, col: u32, row: u32) -> ArcId {
        let per_row = if self.border_x == Border::Periodic {
            self.width
        } else {
            self.width + 1
        };
        self.v_arcs[(row * per_row + col) as usize]
    }

    /// The first ladder of [`Tiling::ladder_move`] with room in every step:
    /// its column `c` (from `next` to `last_col`) and its top row. Raising
    /// (`up`) walks right along row `y`, up column `c`, left along the top
    /// row and down column `x`; lowering walks the same cycle backwards.
    ///
    /// Every arc of a ladder points right or up (tail in the left or lower
    /// slot, also across the periodic seam in x), so the room of a step
    /// follows from the arc alone: `hi - x` along it, `x - lo` against it.
    fn find_ladder(
        &self,
        x: u32,
        y: u32,
        next: u32,
        last_col: u32,
        up: bool,
    ) -> Option<(u32, u32)> {
        let net = &self.net;
        // Room along the arc's direction in the cycle when raising (`fwd`:
        // rightwards or upwards) and against it; swapped for lowering.
        let fwd = |arc: ArcId| {
            let a = net.arc(arc);
            if up { a.hi - a.x } else { a.x - a.lo }
        };
        let bwd = |arc: ArcId| {
            let a = net.arc(arc);
            if up { a.x - a.lo } else { a.hi - a.x }
        };
        let top_row = y + LADDER_RUNGS.min(self.height - 1 - y);
        // The descent down column x is climbed lazily: rows up to `here_top`
        // are known to have room, none above once `here_done`.
        if top_row == y || bwd(self.h_arc(x, y + 1)) <= 0 {
            return None;
        }
        let mut here_top = y + 1;
        let mut here_done = false;
        for c in next..=last_col {
            // Along row y from (c - 1, y) to (c, y).
            if c > next && fwd(self.v_arc(c, y)) <= 0 {
                return None;
            }
            for row in y + 1..=top_row {
                if row > here_top {
                    if here_done || bwd(self.h_arc(x, row)) <= 0 {
                        here_done = true;
                        break;
                    }
                    here_top = row;
                }
                if fwd(self.h_arc(c, row)) <= 0 {
                    break;
                }
                // Back along `row` from column c to column x.
                let open = if next == 0 {
                    bwd(self.v_arc(0, row)) > 0
                } else {
                    (x + 1..=c).all(|col| bwd(self.v_arc(col, row)) > 0)
                };
                if open {
                    return Some((c, row));
                }
            }
        }
        None
    }

    /// Writes the ladder `(c, top)` of [`Tiling::find_ladder`] as a cycle of
    /// (node the step leaves, arc) pairs into `out`.
    #[allow(clippy::too_many_arguments)]
    fn ladder_cycle(
        &self,
        x: u32,
        y: u32,
        next: u32,
        c: u32,
        top: u32,
        up: bool,
        e: ArcId,
        out: &mut Vec<(u32, ArcId)>,
    ) {
        let w = self.width;
        let node = |col: u32, row: u32| row * w + col;
        // The cycle when raising, as (from, to, arc); reversed for lowering.
        out.clear();
        let mut step = |from: u32, to: u32, arc: ArcId| {
            out.push(if up { (from, arc) } else { (to, arc) });
        };
        step(node(x, y), node(next, y), e);
        for col in next + 1..=c {
            step(node(col - 1, y), node(col, y), self.v_arc(col, y));
        }
        for row in y + 1..=top {
            step(node(c, row - 1), node(c, row), self.h_arc(c, row));
        }
        if next == 0 {
            step(node(0, top), node(x, top), self.v_arc(0, top));
        } else {
            for col in (x + 1..=c).rev() {
                step(node(col, top), node(col - 1, top), self.v_arc(col, top));
            }
        }
        for row in (y + 1..=top).rev() {
            step(node(x, row), node(x, row - 1), self.h_arc(x, row));
        }
        if !up {
            out.reverse();
        }
    }

    /// Moves the flux across the seam below slot `(x, 0)` of a grid periodic
    /// in y towards `target`: by short searches while they find a way, then
    /// straight along the column ([`Tiling::column_move`]) — the column
    /// carries the flow round the torus, so it is used only when nothing
    /// near will do, lest every column fill up with winding flow.
    fn seam_move(&mut self, x: u32, target: i32) {
        let seam = self.slot_arcs(x, 0)[1];
        if self.net.move_bounded(seam, target, 256) {
            self.column_move(x, target);
        }
    }

    /// Moves the flux across the seam of a grid periodic in y, below slot
    /// `(x, 0)`, towards `target` along column `x` itself (as far as it
    /// reaches; the general search does the rest).
    ///
    /// While the first row is filled, the flux its slots send across the
    /// seam adds up to the flow that winds around the torus; closing it
    /// takes a path through every row. The general search finds that path
    /// only after visiting a good part of the grid (most of a periodic
    /// fill's time at 256×256); the straight column is such a path whenever
    /// its arcs have room, which on an empty column they have.
    fn column_move(&mut self, x: u32, target: i32) {
        let w = self.width;
        let seam = self.slot_arcs(x, 0)[1];
        for _ in 0..4 {
            let cur = self.net.arc(seam).x;
            if cur == target {
                return;
            }
            let up = target > cur;
            // The nearest column that keeps room after the unit (so winding
            // flow spreads instead of filling columns), else any that fits.
            let mut fallback = None;
            let mut chosen = None;
            for c in x..w.min(x + 8) {
                let cycle = self.seam_cycle(x, c, up);
                let room = cycle
                    .iter()
                    .map(|&(from, a)| self.net.room_from(from, a))
                    .min()
                    .unwrap_or(0);
                if room >= 2 {
                    chosen = Some(cycle);
                    break;
                }
                if room >= 1 && fallback.is_none() {
                    fallback = Some(cycle);
                }
            }
            let Some(cycle) = chosen.or(fallback) else {
                return;
            };
            if self.net.push_cycle(&cycle, 1) == 0 {
                return;
            }
        }
    }

    /// The cycle of [`Tiling::column_move`] that carries flux across the seam
    /// below `(x, 0)` and round the torus up (or down) column `c ≥ x`,
    /// reached along the first and last rows.
    fn seam_cycle(&self, x: u32, c: u32, up: bool) -> Vec<(u32, ArcId)> {
        let (w, h) = (self.width, self.height);
        let seam = self.slot_arcs(x, 0)[1];
        let v = |xx: u32, y: u32| self.edge_arc(Edge::Vertical { x: xx, y }).expect("inside");
        let hz = |xx: u32, y: u32| {
            self.edge_arc(Edge::Horizontal { x: xx, y })
                .expect("inside")
        };
        let mut out = Vec::with_capacity((h + 2 * (c - x) + 1) as usize);
        if up {
            out.push(((h - 1) * w + x, seam));
            out.extend((x..c).map(|cc| (cc, v(cc + 1, 0))));
            out.extend((1..h).map(|y| ((y - 1) * w + c, hz(c, y))));
            out.extend(
                (x..c)
                    .rev()
                    .map(|cc| ((h - 1) * w + cc + 1, v(cc + 1, h - 1))),
            );
        } else {
            out.push((x, seam));
            out.extend((x..c).map(|cc| ((h - 1) * w + cc, v(cc + 1, h - 1))));
            out.extend((1..h).rev().map(|y| (y * w + c, hz(c, y))));
            out.extend((x..c).rev().map(|cc| (cc + 1, v(cc + 1, 0))));
        }
        out
    }

    /// Rejection sampling over whole flux tuples for slots with three or four
    /// free edges (the first row and column of a free-bordered grid): draw a
    /// tuple allowed by the edges' own bounds, keep it if fixing it stays
    /// feasible, otherwise drop it and draw again. Uniform over the
    /// selection, and usually one feasibility test instead of one per tuple.
    fn place_random_tuple(
        &mut self,
        x: u32,
        y: u32,
        arcs: [ArcId; 4],
        rng: &mut Rng,
        mut chooser: Option<&mut Chooser>,
    ) -> Result<TileKey, TilingError> {
        let slot = (y * self.width + x) as usize;
        let fixed = self.slot_vertices(x, y).map(|v| self.corner_fixed[v]);
        let b = arcs.map(|a| {
            let a = self.net.arc(a);
            (a.lo, a.hi)
        });
        let mut candidates = Vec::new();
        for l in b[0].0..=b[0].1 {
            for bo in b[1].0..=b[1].1 {
                for r in b[2].0..=b[2].1 {
                    let t = l + bo - r;
                    if (b[3].0..=b[3].1).contains(&t) {
                        candidates.push([l, bo, r, t]);
                    }
                }
            }
        }
        let mut logs: Vec<f64> = match chooser.as_deref_mut() {
            Some(c) => candidates
                .iter()
                .map(|&t| c.flux_log_weight(slot, t, fixed, &self.set))
                .collect(),
            None => Vec::new(),
        };
        while !candidates.is_empty() {
            let i = if logs.is_empty() {
                rng.below(candidates.len() as u64) as usize
            } else {
                let mut w = logs.clone();
                normalise_log_weights(&mut w);
                rng.weighted(&w)
            };
            let values = candidates[i];
            let mark = self.net.checkpoint();
            // The row's first slot of a periodic grid: its left edge is the
            // right edge of the row's last slot, across the seam.
            if x == 0 && self.border_x == Border::Periodic && self.width > 1 {
                self.ladder_move(self.width - 1, y, values[0]);
            }
            // The first row of a grid periodic in y: its bottom edge is the
            // top edge of the last row, across the seam.
            if y == 0 && self.border_y == Border::Periodic && self.height > 1 {
                self.seam_move(x, values[1]);
            }
            self.ladder_move(x, y, values[2]);
            // Fixing the left and bottom edges may route flux through the
            // right edge (the short way round); a ladder puts it back before
            // the right edge is fixed, which otherwise takes a long search.
            // Whether the tuple fits does not depend on the order.
            let fits = self.net.fix(arcs[0], values[0]) && self.net.fix(arcs[1], values[1]) && {
                self.ladder_move(x, y, values[2]);
                self.net.fix(arcs[2], values[2]) && self.net.fix(arcs[3], values[3])
            };
            if fits {
                self.net.commit();
                return Ok(self.commit_slot(x, y, values, rng, chooser));
            }
            self.net.rollback(mark);
            candidates.swap_remove(i);
            if !logs.is_empty() {
                logs.swap_remove(i);
            }
        }
        Err(TilingError::Infeasible(format!(
            "no tile fits slot ({x}, {y})"
        )))
    }

    /// Records a slot whose fluxes are already fixed in the network, drawing
    /// its free corners uniformly.
    /// With preferences, a placed tile with these fluxes and fitting corners
    /// is copied with probability `reuse / (1 + reuse)`; otherwise free
    /// corners are drawn with the main direction's weights.
    fn commit_slot(
        &mut self,
        x: u32,
        y: u32,
        values: [i32; 4],
        rng: &mut Rng,
        chooser: Option<&mut Chooser>,
    ) -> TileKey {
        let c = self.set.corners.len() as u64;
        let verts = self.slot_vertices(x, y);
        let fixed = verts.map(|v| self.corner_fixed[v]);
        let corners = match chooser {
            None => fixed.map(|f| f.unwrap_or_else(|| rng.below(c) as u16)),
            Some(ch) => ch.corners((y * self.width + x) as usize, values, fixed, &self.set, rng),
        };
        let [left, bottom, right, top] = values;
        let key = TileKey {
            left,
            bottom,
            right,
            top,
            corners,
        };
        for (k, &v) in verts.iter().enumerate() {
            self.corner_fixed[v] = Some(key.corners[k]);
        }
        self.slots[(y * self.width + x) as usize] = Some(key);
        key
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

/// Preference state of one preferring fill.
struct Chooser {
    /// Scaled main direction per slot.
    dirs: Vec<[f64; 2]>,
    prefs: Preferences,
    usage: Usage,
    /// Backflow of filled tiles per (key, unit direction bits).
    backflow: std::collections::HashMap<(TileKey, [u64; 2]), f64>,
}

impl Chooser {
    /// Log-weight of a flux tuple in `slot`: the preferences' flux terms,
    /// the reuse bonus, and with a main direction the backflow of the best
    /// tile these fluxes allow with the slot's fixed corners (a one-tile
    /// lookahead: fluxes whose every tile turns flow back are avoided).
    fn flux_log_weight(
        &mut self,
        slot: usize,
        f: [i32; 4],
        fixed: [Option<u16>; 4],
        set: &TileSet,
    ) -> f64 {
        let mut w = self.prefs.flux_log_weight(self.dirs[slot], f);
        if self.prefs.reuse > 0.0 && self.usage.has_tuple(f) {
            // Twice the bonus when a placed tile fits the fixed corners too.
            let fits = !self.usage.compatible(f, fixed).is_empty();
            w += self.prefs.reuse.ln_1p() * if fits { 2.0 } else { 1.0 };
        }
        let d = self.dirs[slot];
        let free = fixed.iter().filter(|c| c.is_none()).count() as u32;
        let c = set.corners.len();
        if d != [0.0, 0.0] && c.pow(free) <= MAX_SCORED_CORNERS {
            let best = (0..c.pow(free))
                .map(|combo| {
                    let key = key_with(f, fixed, combo, c);
                    self.tile_backflow(&key, d, set)
                })
                .fold(f64::INFINITY, f64::min);
            w -= BACKFLOW_WEIGHT * d[0].hypot(d[1]) * best / set.f_base.abs().max(1e-300);
        }
        w
    }

    /// Log-weight of a whole key (fluxes, corners, reuse, backflow).
    fn key_log_weight(&mut self, slot: usize, k: &TileKey, set: &TileSet) -> f64 {
        let mut w = self.prefs.flux_log_weight(self.dirs[slot], k.fluxes());
        if self.prefs.reuse > 0.0 && self.usage.has_tuple(k.fluxes()) {
            w += self.prefs.reuse.ln_1p();
        }
        for &c in &k.corners {
            w += self.corner_log_weight(slot, c, set);
        }
        let d = self.dirs[slot];
        if d != [0.0, 0.0] {
            let back = self.tile_backflow(k, d, set);
            w -= BACKFLOW_WEIGHT * d[0].hypot(d[1]) * back / set.f_base.abs().max(1e-300);
        }
        w
    }

    /// Backflow of the filled tile `key` against direction `d` (cached).
    fn tile_backflow(&mut self, key: &TileKey, d: [f64; 2], set: &TileSet) -> f64 {
        let len = d[0].hypot(d[1]);
        let unit = [d[0] / len, d[1] / len];
        *self
            .backflow
            .entry((*key, unit.map(f64::to_bits)))
            .or_insert_with(|| crate::fill::fill_tile(set, key).backflow(unit))
    }

    /// Log-weight of a corner velocity option in `slot`.
    fn corner_log_weight(&self, slot: usize, c: u16, set: &TileSet) -> f64 {
        let d = self.dirs[slot];
        let vmax = set
            .corners
            .iter()
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        if vmax == 0.0 {
            return 0.0;
        }
        let v = set.corners[c as usize];
        let along = d[0] * v[0] + d[1] * v[1];
        let cross = (d[0] * v[1] - d[1] * v[0]).abs();
        (along.min(0.0) - cross) / vmax
    }

    /// Corner indices for a slot whose fluxes are chosen.
    fn corners(
        &mut self,
        slot: usize,
        f: [i32; 4],
        fixed: [Option<u16>; 4],
        set: &TileSet,
        rng: &mut Rng,
    ) -> [u16; 4] {
        let r = self.prefs.reuse;
        if r > 0.0 && rng.unit() < r / (1.0 + r) {
            let reusable = self.usage.compatible(f, fixed);
            if !reusable.is_empty() {
                let w: Vec<f64> = reusable.iter().map(|&(_, n)| n as f64).collect();
                return reusable[rng.weighted(&w)].0.corners;
            }
        }
        let d = self.dirs[slot];
        let free = fixed.iter().filter(|c| c.is_none()).count() as u32;
        let c = set.corners.len();
        if d == [0.0, 0.0] || c.pow(free) > MAX_SCORED_CORNERS {
            let mut logs: Vec<f64> = (0..c as u16)
                .map(|i| self.corner_log_weight(slot, i, set))
                .collect();
            normalise_log_weights(&mut logs);
            return fixed.map(|fc| fc.unwrap_or_else(|| rng.weighted(&logs) as u16));
        }
        // With a main direction, score every choice of the free corners by
        // the backflow of the filled tile itself (cached per key), so the
        // corners that make flow turn back inside the tile are avoided.
        let strength = d[0].hypot(d[1]);
        let mut keys = Vec::new();
        let mut logs = Vec::new();
        for combo in 0..c.pow(free) {
            let key = key_with(f, fixed, combo, c);
            let corner_w: f64 = key
                .corners
                .iter()
                .zip(&fixed)
                .filter(|(_, f)| f.is_none())
                .map(|(&k, _)| self.corner_log_weight(slot, k, set))
                .sum();
            let back = self.tile_backflow(&key, d, set);
            let reused = if r > 0.0 && self.usage.contains(&key) {
                r.ln_1p()
            } else {
                0.0
            };
            keys.push(key.corners);
            logs.push(
                corner_w + reused
                    - BACKFLOW_WEIGHT * strength * back / set.f_base.abs().max(1e-300),
            );
        }
        normalise_log_weights(&mut logs);
        keys[rng.weighted(&logs)]
    }
}

/// The key with fluxes `f`, the fixed corners, and the free corners taken
/// from the digits of `combo` in base `c`.
fn key_with(f: [i32; 4], fixed: [Option<u16>; 4], combo: usize, c: usize) -> TileKey {
    let mut rest = combo;
    let corners = fixed.map(|fc| {
        fc.unwrap_or_else(|| {
            let v = (rest % c) as u16;
            rest /= c;
            v
        })
    });
    let [left, bottom, right, top] = f;
    TileKey {
        left,
        bottom,
        right,
        top,
        corners,
    }
}

/// Rows a ladder of [`Tiling::ladder_move`] may climb.
const LADDER_RUNGS: u32 = 64;
/// Columns a ladder may walk along the slot's row before it climbs.
const LADDER_SHIFTS: u32 = 32;

/// Most corner combinations scored by their tile's backflow per slot.
const MAX_SCORED_CORNERS: usize = 4096;
/// Log-weight per unit of mean backflow speed (in units of `f_base`), times
/// the direction's strength.
const BACKFLOW_WEIGHT: f64 = 8.0;

#[cfg(test)]
mod tests;
