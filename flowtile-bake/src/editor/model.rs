//! The editing model: a spec (tile set, grid, mask, borders, fixed fluxes
//! and corners, preferences) plus a partial tiling, the edits a designer
//! makes, the palette of a slot, and undo/redo. No GUI here.
//!
//! Invariant: the [`Tiling`] held by an [`Editor`] is always completable.
//! Every edit is tried on a copy first (a placement with the selection
//! function's own exact test, any other edit by building the tiling of the
//! new spec and placing the tiles again); if the result admits no complete
//! tiling the edit is refused with the reason and nothing changes. Clearing a
//! tile can never break completability (fewer constraints), so it always
//! succeeds.
//!
//! Undo keeps whole documents (spec + tiles; about 24 bytes a slot), not
//! tilings: undoing rebuilds the tiling, which takes milliseconds.

use std::fmt;

use crate::bake::BakedTiling;
use crate::prefer::DirectionRegion;
use crate::rng::Rng;
use crate::spec::Problem;
use crate::tileset::{TileKey, TileSet};
use crate::tiling::{Border, Conditions, Edge, Selection, Tiling};

/// Most undo steps kept.
pub const UNDO_LIMIT: usize = 256;

/// Who put a tile in a slot: the designer (saved in the spec as a fixed
/// tile) or the random fill (reproduced from the seed, not saved).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin {
    /// Placed by hand (or loaded from the spec's `[[tile]]`).
    Designer,
    /// Placed by `fill`.
    Fill,
}

/// What the editor edits: the spec and the tiles in the slots.
#[derive(Clone, Debug)]
pub struct Document {
    /// The spec; its `tiles` are rewritten from the slots when saving.
    pub problem: Problem,
    /// Row-major slots (bottom row first).
    pub slots: Vec<Option<(TileKey, Origin)>>,
}

/// Why the editor refused an edit or a query.
#[derive(Clone, Debug, PartialEq)]
pub enum EditError {
    /// The spec's own constraints admit no complete tiling.
    NoTiling(String),
    /// The edit would leave no completion for the tile already at a slot.
    Conflict {
        /// What the edit was.
        edit: String,
        /// The slot whose tile no longer fits.
        slot: (u32, u32),
        /// Why.
        why: String,
    },
    /// The tile keeps no completion at that slot (greyed in the palette).
    NotAllowed {
        /// The slot.
        slot: (u32, u32),
        /// The tile.
        key: TileKey,
        /// Why the palette greys it.
        why: Why,
    },
    /// A slot, edge or vertex outside the grid, a blocked slot, a value the
    /// tile set does not have.
    Invalid(String),
    /// Nothing to undo or redo.
    NothingToUndo(&'static str),
    /// Reading or writing a file failed.
    Io(String),
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            EditError::NoTiling(why) => write!(f, "the spec admits no tiling: {why}"),
            EditError::Conflict { edit, slot, why } => write!(
                f,
                "{edit} would leave no completion for the tile at ({}, {}) ({why}); clear that tile first",
                slot.0, slot.1
            ),
            EditError::NotAllowed { slot, key, why } => {
                write!(f, "tile {key} at ({}, {}): {why}", slot.0, slot.1)
            }
            EditError::Invalid(why) => f.write_str(why),
            EditError::NothingToUndo(what) => write!(f, "nothing to {what}"),
            EditError::Io(why) => f.write_str(why),
        }
    }
}

impl std::error::Error for EditError {}

/// Which side of a slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// x = slot's left.
    Left,
    /// y = slot's bottom.
    Bottom,
    /// x = slot's right.
    Right,
    /// y = slot's top.
    Top,
}

impl Side {
    /// Left, bottom, right, top (the order of [`TileKey::fluxes`]).
    pub const ALL: [Side; 4] = [Side::Left, Side::Bottom, Side::Right, Side::Top];

    fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Bottom => "bottom",
            Side::Right => "right",
            Side::Top => "top",
        }
    }
}

/// What holds an edge's flux or a corner's velocity fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FixedBy {
    /// A tile placed in the neighbouring slot.
    Tile(u32, u32),
    /// A blocked neighbouring slot (no flux, zero velocity).
    Blocked(u32, u32),
    /// A wall border.
    Wall,
    /// A fixed flux or corner in the spec.
    Spec,
}

impl fmt::Display for FixedBy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FixedBy::Tile(x, y) => write!(f, "the tile at ({x}, {y})"),
            FixedBy::Blocked(x, y) => write!(f, "the blocked slot ({x}, {y})"),
            FixedBy::Wall => f.write_str("the wall border"),
            FixedBy::Spec => f.write_str("the spec"),
        }
    }
}

/// Why the palette greys a tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Why {
    /// An edge of the slot already carries another flux.
    EdgeFixed {
        /// Which edge.
        side: Side,
        /// The flux it carries.
        value: i32,
        /// What fixes it.
        by: FixedBy,
    },
    /// A corner of the slot already has another velocity.
    CornerFixed {
        /// Corner index: bottom-left, bottom-right, top-right, top-left.
        corner: usize,
        /// The velocity index it has.
        value: u16,
        /// What fixes it.
        by: FixedBy,
    },
    /// Every edge fits locally, but no complete tiling would contain it.
    NoCompletion,
}

impl fmt::Display for Why {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const CORNERS: [&str; 4] = ["bottom-left", "bottom-right", "top-right", "top-left"];
        match self {
            Why::EdgeFixed { side, value, by } => write!(
                f,
                "the {} edge carries flux {value}, fixed by {by}",
                side.name()
            ),
            Why::CornerFixed { corner, value, by } => write!(
                f,
                "the {} corner has velocity {value}, fixed by {by}",
                CORNERS[*corner]
            ),
            Why::NoCompletion => f.write_str("would leave no completion"),
        }
    }
}

/// One flux tuple of the tile set in a palette.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FluxChoice {
    /// Left, bottom, right, top.
    pub fluxes: [i32; 4],
    /// `None` when allowed, else why greyed.
    pub why_not: Option<Why>,
}

/// One corner velocity option at one corner of a slot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerChoice {
    /// Index into the tile set's corner velocities.
    pub index: u16,
    /// `None` when allowed, else why greyed.
    pub why_not: Option<Why>,
}

/// The palette of a slot: every flux tuple and corner velocity of the tile
/// set, allowed or greyed with the reason. A tile is allowed exactly when
/// its flux tuple and its four corners are (the selection function's flux
/// and corner choices are independent).
#[derive(Clone, Debug)]
pub struct Palette {
    /// The slot.
    pub slot: (u32, u32),
    /// Every flux tuple of the tile set, in the set's order.
    pub fluxes: Vec<FluxChoice>,
    /// Per corner (bottom-left, bottom-right, top-right, top-left) every
    /// velocity option.
    pub corners: [Vec<CornerChoice>; 4],
    /// The selection function's answer.
    pub selection: Selection,
}

impl Palette {
    /// Number of allowed tiles.
    pub fn allowed_count(&self) -> u64 {
        self.selection.len()
    }

    /// Every allowed tile.
    pub fn allowed(&self) -> impl Iterator<Item = TileKey> + '_ {
        self.selection.keys()
    }

    /// `None` when `key` is allowed here, else why it is greyed.
    pub fn why_not(&self, key: &TileKey) -> Option<Why> {
        let f = key.fluxes();
        match self.fluxes.iter().find(|c| c.fluxes == f) {
            Some(c) if c.why_not.is_some() => return c.why_not,
            Some(_) => {}
            None => return Some(Why::NoCompletion),
        }
        for (k, list) in self.corners.iter().enumerate() {
            match list.iter().find(|c| c.index == key.corners[k]) {
                Some(c) if c.why_not.is_some() => return c.why_not,
                Some(_) => {}
                None => return Some(Why::NoCompletion),
            }
            if let Some(j) = self.selection.same_as[k]
                && key.corners[j] != key.corners[k]
            {
                return Some(Why::NoCompletion);
            }
        }
        None
    }

    /// Allowed flux tuples.
    pub fn allowed_fluxes(&self) -> impl Iterator<Item = [i32; 4]> + '_ {
        self.fluxes
            .iter()
            .filter(|c| c.why_not.is_none())
            .map(|c| c.fluxes)
    }
}

/// The editor: a document, its (always completable) tiling, undo and redo.
///
/// ```
/// use flowtile_bake::editor::model::Editor;
/// let mut ed = Editor::blank(4, 4).unwrap();
/// let palette = ed.palette(0, 0).unwrap();
/// let key = palette.allowed().next().unwrap();
/// ed.place(0, 0, key).unwrap();
/// ed.fill(None).unwrap();
/// assert!(ed.tiling().is_complete());
/// ed.undo().unwrap();
/// assert!(!ed.tiling().is_complete());
/// ```
#[derive(Clone, Debug)]
pub struct Editor {
    doc: Document,
    tiling: Tiling,
    undo: Vec<Document>,
    redo: Vec<Document>,
    modified: bool,
    revision: u64,
}

/// Builds the tiling of a document: the spec's empty tiling, then every
/// tile placed again. The first tile that no longer fits is named.
fn build(doc: &Document, edit: &str) -> Result<Tiling, EditError> {
    let p = &doc.problem;
    let mut t = Tiling::new(p.set.clone(), p.width, p.height, &p.conditions)
        .map_err(|e| EditError::NoTiling(e.to_string()))?;
    for y in 0..p.height {
        for x in 0..p.width {
            if let Some((key, _)) = doc.slots[(y * p.width + x) as usize] {
                t.place(x, y, key).map_err(|e| EditError::Conflict {
                    edit: edit.to_string(),
                    slot: (x, y),
                    why: e.to_string(),
                })?;
            }
        }
    }
    Ok(t)
}

impl Editor {
    /// Opens a spec; its fixed tiles become the designer's tiles. Refused
    /// (with the reason) when the spec admits no tiling.
    pub fn new(problem: Problem) -> Result<Editor, EditError> {
        let n = (problem.width * problem.height) as usize;
        let mut slots = vec![None; n];
        for &((x, y), key) in &problem.tiles {
            slots[(y * problem.width + x) as usize] = Some((key, Origin::Designer));
        }
        let doc = Document { problem, slots };
        let tiling = build(&doc, "opening the spec")?;
        Ok(Editor {
            doc,
            tiling,
            undo: Vec::new(),
            redo: Vec::new(),
            modified: false,
            revision: 0,
        })
    }

    /// A blank `width`×`height` spec: the paper's (5, 5, 5) tile set with
    /// 8 cells per tile side, free borders, seed 1.
    pub fn blank(width: u32, height: u32) -> Result<Editor, EditError> {
        let set = TileSet::paper(5, 5, 5, 8).map_err(|e| EditError::Invalid(e.to_string()))?;
        Editor::new(Problem::new(
            set,
            width,
            height,
            Conditions::borders(Border::Free, Border::Free),
        ))
    }

    /// Opens a baked tiling: its tile set, grid, blocked slots and
    /// periodicity become the spec (other borders free), every tile a
    /// designer's tile.
    pub fn from_baked(b: &BakedTiling) -> Result<Editor, EditError> {
        let border = |p: bool| if p { Border::Periodic } else { Border::Free };
        let mut conditions = Conditions::borders(border(b.periodic_x), border(b.periodic_y));
        conditions.blocked = b.grid.iter().map(|&g| g == crate::bake::BLOCKED).collect();
        let mut tiles = Vec::new();
        for y in 0..b.height {
            for x in 0..b.width {
                if let Some(t) = b.tile_at(x, y) {
                    tiles.push(((x, y), t.key));
                }
            }
        }
        Editor::new(Problem {
            tiles,
            ..Problem::new(b.set.clone(), b.width, b.height, conditions)
        })
    }

    /// The document.
    pub fn document(&self) -> &Document {
        &self.doc
    }

    /// The spec as edited (its `tiles` as last loaded; see [`Editor::spec`]).
    pub fn problem(&self) -> &Problem {
        &self.doc.problem
    }

    /// The current tiling (always completable).
    pub fn tiling(&self) -> &Tiling {
        &self.tiling
    }

    /// Grid width and height in slots.
    pub fn size(&self) -> (u32, u32) {
        (self.doc.problem.width, self.doc.problem.height)
    }

    /// The tile at a slot and who placed it.
    pub fn slot(&self, x: u32, y: u32) -> Option<(TileKey, Origin)> {
        let (w, h) = self.size();
        if x >= w || y >= h {
            return None;
        }
        self.doc.slots[(y * w + x) as usize]
    }

    /// True after an edit since opening or the last save.
    pub fn is_modified(&self) -> bool {
        self.modified
    }

    /// A number that changes with every change of the document (views
    /// cache what they draw by it).
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// Steps that can be undone and redone.
    pub fn history(&self) -> (usize, usize) {
        (self.undo.len(), self.redo.len())
    }

    /// Empty (open, untiled) slots.
    pub fn empty_slots(&self) -> usize {
        let (w, h) = self.size();
        (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&(x, y)| !self.tiling.is_blocked(x, y) && self.tiling.tile(x, y).is_none())
            .count()
    }

    fn check_slot(&self, x: u32, y: u32) -> Result<(), EditError> {
        let (w, h) = self.size();
        if x >= w || y >= h {
            return Err(EditError::Invalid(format!(
                "slot ({x}, {y}) is outside the {w}x{h} grid"
            )));
        }
        Ok(())
    }

    /// Makes `doc` current if its tiling is completable, keeping the old
    /// one for undo; otherwise changes nothing and says why.
    fn commit(&mut self, doc: Document, edit: &str) -> Result<(), EditError> {
        let tiling = build(&doc, edit)?;
        self.push_undo();
        self.doc = doc;
        self.tiling = tiling;
        Ok(())
    }

    fn push_undo(&mut self) {
        self.undo.push(self.doc.clone());
        if self.undo.len() > UNDO_LIMIT {
            self.undo.remove(0);
        }
        self.redo.clear();
        self.modified = true;
        self.revision += 1;
    }

    /// Blocks (`blocked = true`) or opens the slots of the rectangle
    /// `x0..=x1` × `y0..=y1`; tiles in slots that become blocked are
    /// removed with them.
    pub fn set_blocked(
        &mut self,
        (x0, y0): (u32, u32),
        (x1, y1): (u32, u32),
        blocked: bool,
    ) -> Result<usize, EditError> {
        let (xa, xb) = (x0.min(x1), x0.max(x1));
        let (ya, yb) = (y0.min(y1), y0.max(y1));
        self.check_slot(xb, yb)?;
        let (w, h) = self.size();
        let mut doc = self.doc.clone();
        if doc.problem.conditions.blocked.is_empty() {
            doc.problem.conditions.blocked = vec![false; (w * h) as usize];
        }
        let mut changed = 0;
        for y in ya..=yb {
            for x in xa..=xb {
                let i = (y * w + x) as usize;
                if doc.problem.conditions.blocked[i] != blocked {
                    doc.problem.conditions.blocked[i] = blocked;
                    changed += 1;
                }
                if blocked {
                    doc.slots[i] = None;
                }
            }
        }
        if changed == 0 {
            return Ok(0);
        }
        let what = if blocked { "blocking" } else { "opening" };
        self.commit(doc, &format!("{what} ({xa}, {ya})..({xb}, {yb})"))?;
        Ok(changed)
    }

    /// Sets the left/right (`x`) or bottom/top (`y`) borders.
    pub fn set_border(&mut self, x_axis: bool, border: Border) -> Result<(), EditError> {
        let mut doc = self.doc.clone();
        let c = &mut doc.problem.conditions;
        let slot = if x_axis {
            &mut c.border_x
        } else {
            &mut c.border_y
        };
        if *slot == border {
            return Ok(());
        }
        *slot = border;
        // Fixed fluxes on the far border edge of a periodic direction are
        // the near edge's; keep one entry per edge.
        c.fluxes = dedup_fluxes(c.fluxes.clone(), doc.problem.width, doc.problem.height, c);
        self.commit(
            doc,
            &format!(
                "making the {} borders {border:?}",
                if x_axis { "x" } else { "y" }
            ),
        )
    }

    /// Fixes the flux of a grid edge to `m` (a multiple of the base flux,
    /// towards +x or +y), or frees it (`None`).
    pub fn set_flux(&mut self, edge: Edge, m: Option<i32>) -> Result<(), EditError> {
        let (w, h) = self.size();
        let ok = match edge {
            Edge::Vertical { x, y } => x <= w && y < h,
            Edge::Horizontal { x, y } => x < w && y <= h,
        };
        if !ok {
            return Err(EditError::Invalid(format!(
                "{edge:?} is outside the {w}x{h} grid"
            )));
        }
        let mut doc = self.doc.clone();
        let c = &mut doc.problem.conditions;
        let borders = Conditions::borders(c.border_x, c.border_y);
        let canon = canonical_edge(edge, w, h, &borders);
        c.fluxes
            .retain(|&(e, _)| canonical_edge(e, w, h, &borders) != canon);
        if let Some(m) = m {
            c.fluxes.push((edge, m));
        }
        let what = match m {
            Some(m) => format!("fixing {edge:?} to flux {m}"),
            None => format!("freeing {edge:?}"),
        };
        self.commit(doc, &what)
    }

    /// Fixes the velocity (an index into the tile set's corner options) at
    /// grid vertex `(x, y)`, or frees it (`None`).
    pub fn set_corner(&mut self, x: u32, y: u32, velocity: Option<u16>) -> Result<(), EditError> {
        let (w, h) = self.size();
        if x > w || y > h {
            return Err(EditError::Invalid(format!(
                "vertex ({x}, {y}) is outside the {w}x{h} grid"
            )));
        }
        let mut doc = self.doc.clone();
        let c = &mut doc.problem.conditions;
        let borders = Conditions::borders(c.border_x, c.border_y);
        let canon = canonical_vertex((x, y), w, h, &borders);
        c.corners
            .retain(|&(v, _)| canonical_vertex(v, w, h, &borders) != canon);
        if let Some(v) = velocity {
            c.corners.push(((x, y), v));
        }
        let what = match velocity {
            Some(v) => format!("fixing vertex ({x}, {y}) to velocity {v}"),
            None => format!("freeing vertex ({x}, {y})"),
        };
        self.commit(doc, &what)
    }

    /// Sets the weights of "favour straight" and "favour reuse".
    pub fn set_weights(
        &mut self,
        straight: Option<f64>,
        reuse: Option<f64>,
    ) -> Result<(), EditError> {
        let mut doc = self.doc.clone();
        let p = &mut doc.problem.preferences;
        if let Some(s) = straight {
            p.straight = s;
        }
        if let Some(r) = reuse {
            p.reuse = r;
        }
        p.validate().map_err(EditError::Invalid)?;
        self.commit(doc, "setting preferences")
    }

    /// Adds a main direction for a rectangle of slots.
    pub fn add_direction(&mut self, region: DirectionRegion) -> Result<(), EditError> {
        let (w, h) = self.size();
        if region.x.0.max(region.x.1) >= w || region.y.0.max(region.y.1) >= h {
            return Err(EditError::Invalid(format!(
                "direction region reaches outside the {w}x{h} grid"
            )));
        }
        let mut doc = self.doc.clone();
        let r = DirectionRegion {
            x: (region.x.0.min(region.x.1), region.x.0.max(region.x.1)),
            y: (region.y.0.min(region.y.1), region.y.0.max(region.y.1)),
            ..region
        };
        doc.problem.preferences.regions.push(r);
        doc.problem
            .preferences
            .validate()
            .map_err(EditError::Invalid)?;
        self.commit(doc, "adding a main direction")
    }

    /// Removes every main direction.
    pub fn clear_directions(&mut self) -> Result<(), EditError> {
        let mut doc = self.doc.clone();
        doc.problem.preferences.regions.clear();
        self.commit(doc, "clearing the main directions")
    }

    /// Sets the seed of the random fill.
    pub fn set_seed(&mut self, seed: u64) -> Result<(), EditError> {
        let mut doc = self.doc.clone();
        doc.problem.seed = seed;
        self.commit(doc, "setting the seed")
    }

    /// The palette of slot `(x, y)`: every flux tuple and corner option of
    /// the tile set, allowed (the selection function offers it) or greyed
    /// with the reason. For a slot that holds a tile, the palette of the
    /// slot with that tile cleared (what may replace it).
    pub fn palette(&self, x: u32, y: u32) -> Result<Palette, EditError> {
        self.check_slot(x, y)?;
        if self.tiling.is_blocked(x, y) {
            return Err(EditError::Invalid(format!("slot ({x}, {y}) is blocked")));
        }
        let mut tiling = self.tiling.clone();
        tiling.remove(x, y);
        self.palette_of(&mut tiling, x, y)
    }

    /// The palette of an empty slot of `tiling` (a copy: the selection
    /// function moves flux around while it searches).
    fn palette_of(&self, tiling: &mut Tiling, x: u32, y: u32) -> Result<Palette, EditError> {
        let selection = tiling
            .select(x, y)
            .map_err(|e| EditError::Invalid(e.to_string()))?;
        let edges = slot_edges(x, y);
        let bounds: Vec<(i32, i32)> = edges
            .iter()
            .map(|&e| tiling.edge_bounds(e).expect("slot edges lie in the grid"))
            .collect();
        let fluxes = tiling
            .set()
            .flux_tuples()
            .iter()
            .map(|&f| {
                let why_not = if selection.fluxes.contains(&f) {
                    None
                } else {
                    Some(
                        (0..4)
                            .find(|&k| f[k] < bounds[k].0 || f[k] > bounds[k].1)
                            .map(|k| Why::EdgeFixed {
                                side: Side::ALL[k],
                                value: bounds[k].0,
                                by: self.edge_fixed_by(tiling, x, y, k),
                            })
                            .unwrap_or(Why::NoCompletion),
                    )
                };
                FluxChoice { fluxes: f, why_not }
            })
            .collect();
        let count = tiling.set().corners.len() as u16;
        let corners = std::array::from_fn(|k| {
            let allowed = &selection.corners[k];
            (0..count)
                .map(|index| CornerChoice {
                    index,
                    why_not: (!allowed.contains(&index)).then(|| Why::CornerFixed {
                        corner: k,
                        value: allowed.first().copied().unwrap_or(0),
                        by: self.corner_fixed_by(tiling, x, y, k),
                    }),
                })
                .collect()
        });
        Ok(Palette {
            slot: (x, y),
            fluxes,
            corners,
            selection,
        })
    }

    /// What fixes side `k` of slot `(x, y)`.
    fn edge_fixed_by(&self, t: &Tiling, x: u32, y: u32, k: usize) -> FixedBy {
        let (dx, dy) = [(-1, 0), (0, -1), (1, 0), (0, 1)][k];
        match self.neighbour(x, y, dx, dy) {
            Some((nx, ny)) if t.is_blocked(nx, ny) => FixedBy::Blocked(nx, ny),
            Some((nx, ny)) if t.tile(nx, ny).is_some() => FixedBy::Tile(nx, ny),
            None => {
                let c = &self.doc.problem.conditions;
                let (w, h) = self.size();
                let edge = slot_edges(x, y)[k];
                let canon = canonical_edge(edge, w, h, c);
                let border = if k.is_multiple_of(2) {
                    c.border_x
                } else {
                    c.border_y
                };
                if c.fluxes
                    .iter()
                    .any(|&(e, _)| canonical_edge(e, w, h, c) == canon)
                {
                    FixedBy::Spec
                } else if border == Border::Zero {
                    FixedBy::Wall
                } else {
                    FixedBy::Spec
                }
            }
            Some(_) => FixedBy::Spec,
        }
    }

    /// What fixes corner `k` of slot `(x, y)`: a tile or blocked slot
    /// sharing the vertex, a spec corner, or a wall border.
    fn corner_fixed_by(&self, t: &Tiling, x: u32, y: u32, k: usize) -> FixedBy {
        let (vx, vy) = [(x, y), (x + 1, y), (x + 1, y + 1), (x, y + 1)][k];
        for (dx, dy) in [(-1, -1), (0, -1), (-1, 0), (0, 0)] {
            if let Some((sx, sy)) = self.neighbour(vx, vy, dx, dy)
                && (sx, sy) != (x, y)
            {
                if t.tile(sx, sy).is_some() {
                    return FixedBy::Tile(sx, sy);
                }
                if t.is_blocked(sx, sy) {
                    return FixedBy::Blocked(sx, sy);
                }
            }
        }
        let c = &self.doc.problem.conditions;
        let (w, h) = self.size();
        let canon = canonical_vertex((vx, vy), w, h, c);
        if c.corners
            .iter()
            .any(|&(v, _)| canonical_vertex(v, w, h, c) == canon)
        {
            FixedBy::Spec
        } else {
            FixedBy::Wall
        }
    }

    /// The slot at `(x + dx, y + dy)`, wrapping around periodic borders.
    fn neighbour(&self, x: u32, y: u32, dx: i64, dy: i64) -> Option<(u32, u32)> {
        let (w, h) = self.size();
        let c = &self.doc.problem.conditions;
        let wrap = |v: i64, n: u32, b: Border| {
            if b == Border::Periodic {
                Some(v.rem_euclid(n as i64) as u32)
            } else {
                (0..n as i64).contains(&v).then_some(v as u32)
            }
        };
        Some((
            wrap(x as i64 + dx, w, c.border_x)?,
            wrap(y as i64 + dy, h, c.border_y)?,
        ))
    }

    /// Places `key` at `(x, y)` (replacing a tile already there) if a
    /// complete tiling still exists; otherwise says why the palette greys it.
    pub fn place(&mut self, x: u32, y: u32, key: TileKey) -> Result<(), EditError> {
        self.check_slot(x, y)?;
        if self.tiling.is_blocked(x, y) {
            return Err(EditError::Invalid(format!("slot ({x}, {y}) is blocked")));
        }
        if self.tiling.set().index_of(&key).is_none() {
            return Err(EditError::Invalid(format!(
                "{key} is not in the tile set (fluxes must conserve mass and lie in the ranges, corners exist)"
            )));
        }
        let i = (y * self.size().0 + x) as usize;
        // Tiling::place is atomic (a refused tile changes nothing), so an
        // empty slot is tried in place; a tiled one on the tiling without it.
        let replaced = self.tiling.tile(x, y).map(|_| {
            let mut t = self.tiling.clone();
            t.remove(x, y);
            t
        });
        let mut trial = replaced.clone();
        let result = match trial.as_mut() {
            Some(t) => t.place(x, y, key),
            None => self.tiling.place(x, y, key),
        };
        if result.is_err() {
            let mut base = replaced.unwrap_or_else(|| self.tiling.clone());
            let why = self
                .palette_of(&mut base, x, y)?
                .why_not(&key)
                .unwrap_or(Why::NoCompletion);
            return Err(EditError::NotAllowed {
                slot: (x, y),
                key,
                why,
            });
        }
        self.push_undo();
        self.doc.slots[i] = Some((key, Origin::Designer));
        if let Some(t) = trial {
            self.tiling = t;
        }
        Ok(())
    }

    /// Clears the tiles of the rectangle `x0..=x1` × `y0..=y1` (always
    /// possible: fewer tiles never break completability; the tiling frees
    /// the slots' edges and corners in place). Returns how many.
    pub fn clear(
        &mut self,
        (x0, y0): (u32, u32),
        (x1, y1): (u32, u32),
    ) -> Result<usize, EditError> {
        let (xa, xb) = (x0.min(x1), x0.max(x1));
        let (ya, yb) = (y0.min(y1), y0.max(y1));
        self.check_slot(xb, yb)?;
        let w = self.size().0;
        let n = (ya..=yb)
            .flat_map(|y| (xa..=xb).map(move |x| (x, y)))
            .filter(|&(x, y)| self.doc.slots[(y * w + x) as usize].is_some())
            .count();
        if n > 0 {
            self.push_undo();
            for y in ya..=yb {
                for x in xa..=xb {
                    self.doc.slots[(y * w + x) as usize] = None;
                    self.tiling.remove(x, y);
                }
            }
        }
        Ok(n)
    }

    /// Clears every tile the fill placed, keeping the designer's.
    pub fn clear_filled(&mut self) -> Result<usize, EditError> {
        let filled: Vec<usize> = (0..self.doc.slots.len())
            .filter(|&i| matches!(self.doc.slots[i], Some((_, Origin::Fill))))
            .collect();
        if !filled.is_empty() {
            self.push_undo();
            let w = self.size().0;
            for &i in &filled {
                self.doc.slots[i] = None;
                self.tiling.remove(i as u32 % w, i as u32 / w);
            }
        }
        Ok(filled.len())
    }

    /// Fills every empty slot at random with the spec's preferences (seed
    /// `seed`, or the spec's), exactly as `flowtile-bake tile` does after
    /// placing the designer's tiles. Returns the number of tiles placed.
    pub fn fill(&mut self, seed: Option<u64>) -> Result<usize, EditError> {
        let p = &self.doc.problem;
        let mut tiling = self.tiling.clone();
        if p.fill_forced {
            tiling
                .fill_forced()
                .map_err(|e| EditError::NoTiling(e.to_string()))?;
        }
        tiling
            .random_fill_preferring(&mut Rng::new(seed.unwrap_or(p.seed)), &p.preferences)
            .map_err(|e| EditError::NoTiling(e.to_string()))?;
        let (w, h) = self.size();
        let mut placed = 0;
        let mut slots = self.doc.slots.clone();
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                if slots[i].is_none()
                    && let Some(k) = tiling.tile(x, y)
                {
                    slots[i] = Some((k, Origin::Fill));
                    placed += 1;
                }
            }
        }
        if placed > 0 {
            self.push_undo();
            self.doc.slots = slots;
            self.tiling = tiling;
        }
        Ok(placed)
    }

    /// Makes every edit since the undo history had `mark` steps one step
    /// (a painted stroke undoes as a whole).
    pub fn squash_undo(&mut self, mark: usize) {
        if self.undo.len() > mark + 1 {
            self.undo.truncate(mark + 1);
        }
    }

    /// Undoes the last edit.
    pub fn undo(&mut self) -> Result<(), EditError> {
        let doc = self.undo.pop().ok_or(EditError::NothingToUndo("undo"))?;
        let tiling = build(&doc, "undo").expect("every kept state was completable");
        self.redo.push(std::mem::replace(&mut self.doc, doc));
        self.tiling = tiling;
        self.modified = true;
        self.revision += 1;
        Ok(())
    }

    /// Redoes the last undone edit.
    pub fn redo(&mut self) -> Result<(), EditError> {
        let doc = self.redo.pop().ok_or(EditError::NothingToUndo("redo"))?;
        let tiling = build(&doc, "redo").expect("every kept state was completable");
        self.undo.push(std::mem::replace(&mut self.doc, doc));
        self.tiling = tiling;
        self.modified = true;
        self.revision += 1;
        Ok(())
    }

    /// The spec to save: the edited problem with the designer's tiles as
    /// fixed tiles (filled ones are reproduced by `tile` from the seed).
    pub fn spec(&self) -> Problem {
        let mut p = self.doc.problem.clone();
        let w = p.width;
        p.tiles = self
            .doc
            .slots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match s {
                Some((k, Origin::Designer)) => Some(((i as u32 % w, i as u32 / w), *k)),
                _ => None,
            })
            .collect();
        p
    }

    /// Writes the spec (TOML) atomically.
    pub fn save(&mut self, path: &std::path::Path) -> Result<(), EditError> {
        crate::bake::write_atomic(path, self.spec().to_toml().as_bytes())
            .map_err(|e| EditError::Io(e.to_string()))?;
        self.modified = false;
        Ok(())
    }

    /// The baked tiling (complete tilings only).
    pub fn baked(&self) -> Result<BakedTiling, EditError> {
        if !self.tiling.is_complete() {
            return Err(EditError::Invalid(format!(
                "{} slots are still empty; fill them before baking",
                self.empty_slots()
            )));
        }
        BakedTiling::from_tiling(&self.tiling).map_err(|e| EditError::Invalid(e.to_string()))
    }

    /// Bakes the tiling and writes the `.ftb` atomically.
    pub fn bake(&self, path: &std::path::Path) -> Result<usize, EditError> {
        let bytes = self.baked()?.to_bytes();
        crate::bake::write_atomic(path, &bytes).map_err(|e| EditError::Io(e.to_string()))?;
        Ok(bytes.len())
    }
}

/// The edges of slot `(x, y)`: left, bottom, right, top.
pub fn slot_edges(x: u32, y: u32) -> [Edge; 4] {
    [
        Edge::Vertical { x, y },
        Edge::Horizontal { x, y },
        Edge::Vertical { x: x + 1, y },
        Edge::Horizontal { x, y: y + 1 },
    ]
}

/// The edge with periodic wrap-around applied (x = W is x = 0 when periodic).
fn canonical_edge(e: Edge, w: u32, h: u32, c: &Conditions) -> Edge {
    match e {
        Edge::Vertical { x, y } if c.border_x == Border::Periodic => Edge::Vertical { x: x % w, y },
        Edge::Horizontal { x, y } if c.border_y == Border::Periodic => {
            Edge::Horizontal { x, y: y % h }
        }
        e => e,
    }
}

fn canonical_vertex((x, y): (u32, u32), w: u32, h: u32, c: &Conditions) -> (u32, u32) {
    let x = if c.border_x == Border::Periodic {
        x % w
    } else {
        x
    };
    let y = if c.border_y == Border::Periodic {
        y % h
    } else {
        y
    };
    (x, y)
}

/// One entry per edge (the last wins), after wrap-around.
fn dedup_fluxes(fluxes: Vec<(Edge, i32)>, w: u32, h: u32, c: &Conditions) -> Vec<(Edge, i32)> {
    let mut out: Vec<(Edge, i32)> = Vec::with_capacity(fluxes.len());
    for (e, m) in fluxes {
        let canon = canonical_edge(e, w, h, c);
        out.retain(|&(o, _)| canonical_edge(o, w, h, c) != canon);
        out.push((e, m));
    }
    out
}

#[cfg(test)]
mod tests;
