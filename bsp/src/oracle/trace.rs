//! Engine-style traces: where a moving point (hull 0) or player box (clip hulls 1–3)
//! first meets an obstacle, with the hit fraction and the wall's plane normal.
//!
//! This follows Quake's `SV_RecursiveHullCheck` (GoldSrc's `PM_RecursiveHullCheck`):
//! the segment is split at node planes, the crossing point is kept `DIST_EPSILON`
//! on the near side, and the end position never lies inside a wall. Cameras that
//! copy the engine (Half-Life's chase cam, `V_GetChaseOrigin`) and players walking
//! on the floor with their clip hull need exactly this answer, which a yes/no
//! segment test cannot give. Solid brush models are not traced (world only).
//!
//! ```no_run
//! use bsp::{Bsp, oracle::{Oracle, OracleOptions}};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let oracle = Oracle::new(&bsp, &OracleOptions::default());
//! let t = oracle.trace(0, [0.0, 0.0, 64.0], [512.0, 0.0, 64.0]).unwrap();
//! if t.fraction < 1.0 {
//!     println!("wall at {:?}, normal {:?}", t.end, t.normal);
//! }
//! # Ok::<(), bsp::BspError>(())
//! ```

use super::{Hull, Oracle, side_distance};

/// Distance kept from a wall plane by a trace's end position (the engine's value).
pub const DIST_EPSILON: f64 = 0.03125;

/// The result of [`Oracle::trace`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Trace {
    /// Share of the segment travelled before the first obstacle (1.0: none met).
    pub fraction: f64,
    /// Where the trace stopped (never inside an obstacle unless `start_solid`).
    pub end: [f64; 3],
    /// Normal of the plane that was hit, pointing into free space; zero when nothing was hit.
    pub normal: [f64; 3],
    /// The start point is inside an obstacle.
    pub start_solid: bool,
    /// The whole segment is inside obstacles.
    pub all_solid: bool,
}

impl Oracle {
    /// Traces the segment `a`→`b` through hull `hull` (0: a point against the visible
    /// walls; 1–3: the clip hulls of a standing player, a large monster, a crouched
    /// player, whose origins it moves). `None` when the map has no such clip hull.
    pub fn trace(&self, hull: usize, a: [f64; 3], b: [f64; 3]) -> Option<Trace> {
        let h = match hull {
            0 => &self.world,
            1..=3 => self.clip_hull(hull)?,
            _ => return None,
        };
        let mut t = Trace {
            fraction: 1.0,
            end: b,
            normal: [0.0; 3],
            start_solid: false,
            all_solid: true,
        };
        let blocks = |c: i32| self.blocks(c);
        recursive(h, &blocks, h.root, 0.0, 1.0, a, b, &mut t);
        if t.all_solid {
            t.start_solid = true;
        }
        if t.fraction == 1.0 {
            t.end = b;
        }
        if t.all_solid {
            t.fraction = 0.0;
            t.end = a;
        }
        Some(t)
    }
}

fn lerp(a: [f64; 3], b: [f64; 3], f: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] + f * (b[i] - a[i]))
}

/// Returns false once an impact has been recorded (the caller stops there).
#[allow(clippy::too_many_arguments)]
fn recursive(
    h: &Hull,
    blocks: &dyn Fn(i32) -> bool,
    num: i32,
    p1f: f64,
    p2f: f64,
    p1: [f64; 3],
    p2: [f64; 3],
    t: &mut Trace,
) -> bool {
    if num < 0 {
        if blocks(num) {
            t.start_solid = true;
        } else {
            t.all_solid = false;
        }
        return true;
    }
    let node = &h.nodes[num as usize];
    let (t1, t2) = (side_distance(node, p1), side_distance(node, p2));
    if t1 >= 0.0 && t2 >= 0.0 {
        return recursive(h, blocks, node.children[0], p1f, p2f, p1, p2, t);
    }
    if t1 < 0.0 && t2 < 0.0 {
        return recursive(h, blocks, node.children[1], p1f, p2f, p1, p2, t);
    }
    // The crossing point, DIST_EPSILON on the near side.
    let mut frac = if t1 < 0.0 {
        (t1 + DIST_EPSILON) / (t1 - t2)
    } else {
        (t1 - DIST_EPSILON) / (t1 - t2)
    }
    .clamp(0.0, 1.0);
    let mut midf = p1f + (p2f - p1f) * frac;
    let mut mid = lerp(p1, p2, frac);
    let side = (t1 < 0.0) as usize;
    if !recursive(h, blocks, node.children[side], p1f, midf, p1, mid, t) {
        return false;
    }
    if !blocks(h.contents_from(node.children[side ^ 1], mid)) {
        return recursive(h, blocks, node.children[side ^ 1], midf, p2f, mid, p2, t);
    }
    if t.all_solid {
        return false; // never got out of the obstacle
    }
    // The far side is an obstacle: this is the impact.
    let n = node.normal.map(f64::from);
    t.normal = if side == 0 { n } else { n.map(|c| -c) };
    while blocks(h.contents(mid)) {
        // Numerical corner cases: back off until the point is free (as the engine does).
        frac -= 0.1;
        if frac < 0.0 {
            t.fraction = midf;
            t.end = mid;
            return false;
        }
        midf = p1f + (p2f - p1f) * frac;
        mid = lerp(p1, p2, frac);
    }
    t.fraction = midf;
    t.end = mid;
    false
}

#[cfg(test)]
mod tests {
    use super::super::{HullNode, OracleOptions};
    use super::*;
    use crate::contents;

    /// x < 0 solid, x >= 0 empty.
    fn oracle() -> Oracle {
        let world = Hull {
            nodes: vec![HullNode {
                normal: [1.0, 0.0, 0.0],
                dist: 0.0,
                children: [contents::EMPTY, contents::SOLID],
                axis: 0,
            }],
            root: 0,
        };
        Oracle {
            world,
            clip_hulls: [None, None, None],
            built_hulls: None,
            solid_models: Vec::new(),
            liquids_are_solid: OracleOptions::default().liquids_are_solid,
            clip_is_solid: false,
            brushes: None,
            game: crate::Game::GoldSrc,
            fence: None,
        }
    }

    #[test]
    fn trace_stops_before_the_wall_with_its_normal() {
        let o = oracle();
        let t = o.trace(0, [10.0, 0.0, 0.0], [-10.0, 0.0, 0.0]).unwrap();
        assert!((t.fraction - (10.0 - DIST_EPSILON) / 20.0).abs() < 1e-9);
        assert!((t.end[0] - DIST_EPSILON).abs() < 1e-9);
        assert_eq!(t.normal, [1.0, 0.0, 0.0]);
        assert!(!t.start_solid);
        let free = o.trace(0, [10.0, 0.0, 0.0], [20.0, 5.0, 0.0]).unwrap();
        assert_eq!(free.fraction, 1.0);
        assert_eq!(free.end, [20.0, 5.0, 0.0]);
        let inside = o.trace(0, [-10.0, 0.0, 0.0], [-20.0, 0.0, 0.0]).unwrap();
        assert!(inside.all_solid && inside.start_solid && inside.fraction == 0.0);
        assert!(o.trace(1, [0.0; 3], [1.0; 3]).is_none());
    }
}
