//! The feasibility model: the grid as a flow network (one node per slot,
//! the outside as a ring of ports, one arc per grid edge) built from the
//! boundary conditions, and the corner conditions beside it.

use super::grid::grid_lines;
use super::{Border, Conditions, Edge, MAX_SIDE, MAX_SLOTS, Tiling, TilingError};
use crate::flow::{ArcId, Network};
use crate::tileset::{FluxRange, TileSet};

/// Capacity of the arcs that join the outside ring: more than any border can carry.
const UNBOUNDED: i32 = 1 << 28;

impl Tiling {
    /// Sets up an empty tiling and checks that it can be completed: the
    /// grid and its mask, the flow network of the fluxes, the corner and
    /// flux conditions, then a feasible circulation (or the reason there is
    /// none).
    pub fn new(
        set: TileSet,
        width: u32,
        height: u32,
        cond: &Conditions,
    ) -> Result<Tiling, TilingError> {
        let blocked = blocked_flags(width, height, cond)?;
        let (net, v_arcs, h_arcs) = build_network(&set, width, height, cond, &blocked);
        let vertices = grid_lines(cond.border_x, width) * grid_lines(cond.border_y, height);
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
            corner_fixed: vec![None; vertices as usize],
            slots: vec![None; (width * height) as usize],
            base_bounds: Vec::new(),
            base_corners: Vec::new(),
            cycle: Vec::new(),
        };
        tiling.apply_corner_conditions(cond)?;
        tiling.apply_flux_conditions(cond)?;
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

    /// Narrows the arcs of the conditions' fixed fluxes to their values,
    /// refusing fluxes into blocked slots, two values for one edge and
    /// values the tile set does not offer.
    fn apply_flux_conditions(&mut self, cond: &Conditions) -> Result<(), TilingError> {
        let slots = self.slots.len();
        let mut fixed: Vec<Option<i32>> = vec![None; self.net.arc_count()];
        for &(edge, m) in &cond.fluxes {
            let arc = self.edge_arc(edge)?;
            let a = self.net.arc(arc);
            let touches_block = [a.tail, a.head]
                .iter()
                .any(|&n| (n as usize) < slots && self.blocked[n as usize]);
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
                Edge::Vertical { .. } => self.set.mx,
                Edge::Horizontal { .. } => self.set.my,
            };
            if !range.contains(m) {
                return Err(TilingError::FluxOutOfRange(edge, m));
            }
            // An explicit flux overrides a wall border: an inlet or outlet.
            fixed[arc] = Some(m);
            self.net_clamp(arc, m);
        }
        Ok(())
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
}

/// Checks the grid's size and returns the blocked flags of its slots (none
/// blocked when the conditions give no mask).
fn blocked_flags(width: u32, height: u32, cond: &Conditions) -> Result<Vec<bool>, TilingError> {
    if width == 0
        || height == 0
        || width > MAX_SIDE
        || height > MAX_SIDE
        || width as u64 * height as u64 > MAX_SLOTS
    {
        return Err(TilingError::BadGrid(width, height));
    }
    let slots = (width * height) as usize;
    if cond.blocked.is_empty() {
        Ok(vec![false; slots])
    } else if cond.blocked.len() == slots {
        Ok(cond.blocked.clone())
    } else {
        Err(TilingError::BadMask(format!(
            "{} flags for {slots} slots",
            cond.blocked.len()
        )))
    }
}

/// The flow network of a grid: one node per slot, then the ring of outside
/// ports; the ring's arcs, then one arc per grid edge with the tile set's
/// flux range as bounds (zero at walls and blocked slots). Returns it with
/// the arcs of the vertical edges (row by row, [`grid_lines`] per row) and
/// of the horizontal ones (edge row by edge row, `width` per row).
fn build_network(
    set: &TileSet,
    width: u32,
    height: u32,
    cond: &Conditions,
    blocked: &[bool],
) -> (Network, Vec<ArcId>, Vec<ArcId>) {
    let slots = (width * height) as usize;
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
    let bounds = |tail: u32, head: u32, border: Border, r: FluxRange| {
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
    let vx_count = grid_lines(cond.border_x, width);
    let hy_count = grid_lines(cond.border_y, height);
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
    (net, v_arcs, h_arcs)
}
