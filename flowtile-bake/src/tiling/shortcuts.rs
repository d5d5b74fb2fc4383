//! Shortcuts of the scan-line fill: short cycles (ladders along the filled
//! rows, columns across the periodic seam) that move flux where the
//! general search of the network would visit most of the grid.

use super::{Border, Edge, Tiling};
use crate::flow::ArcId;

/// Rows a ladder of [`Tiling::ladder_move`] may climb.
const LADDER_RUNGS: u32 = 64;
/// Columns a ladder may walk along the slot's row before it climbs.
const LADDER_SHIFTS: u32 = 32;

impl Tiling {
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
    /// the whole band (on large grids most of the fill's time).
    pub(super) fn ladder_move(&mut self, x: u32, y: u32, target: i32) {
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
    pub(super) fn seam_move(&mut self, x: u32, target: i32) {
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
    /// only after visiting a good part of the grid (on large grids most of
    /// a periodic fill's time); the straight column is such a path whenever
    /// its arcs have room, which on an empty column they have.
    pub(super) fn column_move(&mut self, x: u32, target: i32) {
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
}
