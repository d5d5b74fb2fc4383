//! Maps that leak: free space that reaches the void around the level.
//!
//! A compiler fills the outside of a sealed map with solid. Where a wall has a hole,
//! the fill cannot tell inside from outside and leaves the outside empty: the game
//! still loads the map (ericw-tools and VHLT warn "LEAK" and go on), but the free
//! space then reaches as far as the tree's planes, millions of units out. The
//! [`crate::oracle::Oracle`] fences such a map with the world's bounds; this module
//! tells whether a map leaks ([`outside_is_free`]) and where ([`find`]): the shortest
//! free path from a player start (or any entity in free space) to the outside, the line
//! a compiler's pointfile draws, so the designer sees the hole in the editor.

use crate::Bsp;
use crate::contents;
use crate::oracle::Hull;

type P = [f64; 3];

/// How far outside the world's bounds the probes lie.
const PROBE_MARGIN: f64 = 16.0;

/// Whether the hull-0 tree is free (not solid, not sky) anywhere just outside the world
/// model's bounds: at the corners, edge midpoints and face centres of the bounds grown by
/// a margin. A sealed map is solid there; a leaking one is empty everywhere outside.
pub fn outside_is_free(bsp: &Bsp) -> bool {
    let Some(world) = bsp.models.first() else {
        return false;
    };
    if bsp.nodes.is_empty() {
        return false;
    }
    let hull = Hull::from_nodes(bsp, 0);
    let lo = world.mins.map(|v| v as f64 - PROBE_MARGIN);
    let hi = world.maxs.map(|v| v as f64 + PROBE_MARGIN);
    let mid = [0, 1, 2].map(|i| (lo[i] + hi[i]) * 0.5);
    let pick = |k: usize, i: usize| [lo[i], mid[i], hi[i]][k];
    (0..27)
        .filter(|&n| n != 13) // not the centre
        .map(|n| [pick(n % 3, 0), pick(n / 3 % 3, 1), pick(n / 9, 2)])
        .any(|p| is_open(hull.contents(p)))
}

/// Contents a leak path may run through: empty space and liquids.
fn is_open(c: i32) -> bool {
    c != contents::SOLID && c != contents::SKY
}

/// Where a map leaks: the path from `from` (an entity in free space) out of the world's
/// bounds, and the last point of the path still inside them.
#[derive(Debug, Clone, PartialEq)]
pub struct Leak {
    /// The entity the path starts at: its class name and origin.
    pub entity: String,
    pub from: P,
    /// Where the path leaves the world's bounds.
    pub exit: P,
    /// The path, from the entity to just outside the bounds (the pointfile's points).
    pub path: Vec<P>,
}

/// The shortest free path (on a grid, with every step a free segment of the tree)
/// from a player start, or the first entity in free space, to outside the world's
/// bounds; `None` when the map does not leak or no path is found within the grid's
/// resolution (a hole smaller than a grid step).
pub fn find(bsp: &Bsp) -> Option<Leak> {
    if !outside_is_free(bsp) {
        return None;
    }
    let hull = Hull::from_nodes(bsp, 0);
    let world = bsp.world();
    let (wlo, whi) = (world.mins.map(f64::from), world.maxs.map(f64::from));
    let start = bsp
        .entities
        .iter()
        .filter(|e| crate::is_spawn_class(e.classname()))
        .chain(bsp.entities.iter())
        .filter_map(|e| Some((e.classname().to_string(), e.origin()?.map(f64::from))))
        .find(|(_, o)| inside(*o, wlo, whi) && is_open(hull.contents(*o)))?;
    // A grid of at most ~2^21 cells per axis product over the bounds grown by two steps.
    let extent = (0..3).map(|i| whi[i] - wlo[i]).fold(0.0, f64::max);
    let step = (extent / 160.0).max(16.0);
    let lo = wlo.map(|v| v - 2.0 * step);
    let dims = [0, 1, 2].map(|i| ((whi[i] + 2.0 * step - lo[i]) / step).ceil() as usize + 1);
    let cell = |p: P| {
        [0, 1, 2].map(|i| (((p[i] - lo[i]) / step).round().max(0.0) as usize).min(dims[i] - 1))
    };
    let centre = |c: [usize; 3]| [0, 1, 2].map(|i| lo[i] + c[i] as f64 * step);
    let index = |c: [usize; 3]| (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    let total = dims.iter().product::<usize>();
    let mut parent = vec![u32::MAX; total];
    let first = cell(start.1);
    let mut queue = std::collections::VecDeque::new();
    parent[index(first)] = index(first) as u32;
    queue.push_back((first, start.1));
    let clear = |a: P, b: P| hull.segment_clear(a, b, |c| !is_open(c));
    while let Some((c, p)) = queue.pop_front() {
        if !inside(p, wlo, whi) {
            // Walk back to the start.
            let mut path = vec![p];
            let mut i = index(c);
            while parent[i] as usize != i {
                i = parent[i] as usize;
                let q = [i % dims[0], i / dims[0] % dims[1], i / (dims[0] * dims[1])];
                path.push(if i == index(first) {
                    start.1
                } else {
                    centre(q)
                });
            }
            path.reverse();
            let exit = path
                .iter()
                .rev()
                .find(|q| inside(**q, wlo, whi))
                .copied()
                .unwrap_or(start.1);
            return Some(Leak {
                entity: start.0,
                from: start.1,
                exit,
                path,
            });
        }
        for axis in 0..3 {
            for up in [false, true] {
                let mut n = c;
                if up {
                    if n[axis] + 1 >= dims[axis] {
                        continue;
                    }
                    n[axis] += 1;
                } else {
                    if n[axis] == 0 {
                        continue;
                    }
                    n[axis] -= 1;
                }
                let k = index(n);
                if parent[k] != u32::MAX {
                    continue;
                }
                let q = centre(n);
                if is_open(hull.contents(q)) && clear(p, q) {
                    parent[k] = index(c) as u32;
                    queue.push_back((n, q));
                }
            }
        }
    }
    None
}

fn inside(p: P, lo: P, hi: P) -> bool {
    (0..3).all(|i| p[i] >= lo[i] && p[i] <= hi[i])
}

/// The leak as a pointfile: one `x y z` line per point, the format Quake's and
/// Half-Life's compilers write as MAP.pts (Quake 2 and 3's as MAP.lin) and TrenchBroom
/// and J.A.C.K. load to draw the line to the hole.
pub fn pointfile(points: &[P]) -> String {
    points
        .iter()
        .map(|p| format!("{:.1} {:.1} {:.1}\n", p[0], p[1], p[2]))
        .collect()
}

/// The pointfile's extension for the map's game: `lin` for Quake 2 and 3, `pts` for
/// Quake and GoldSrc.
pub fn pointfile_extension(game: crate::Game) -> &'static str {
    match game {
        crate::Game::Quake2 | crate::Game::Quake3 => "lin",
        crate::Game::Quake | crate::Game::GoldSrc => "pts",
    }
}
