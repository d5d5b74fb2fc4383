//! `--routes spawns`: routes between the map's player spawns, found on the floor with
//! the player's own clip hulls (never from the graph under test).
//!
//! The floor is explored on a 16-unit grid the way the engine moves a player: step up
//! at most 18 units, move, drop to the ground (at most 36 below the step), walkable
//! ground only (normal z ≥ 0.7); where the standing hull (1) does not fit the crouched
//! hull (3) is tried, so routes crouch through low passages. A* finds the grid path,
//! [`string_pull`] straightens it, [`walk`] turns it into a player's motion.

use super::route::Route;
use super::walk::{WalkStats, Waypoint, string_pull, walk_parts};
use bsp::Bsp;
use bsp::oracle::Oracle;
use bsp::player::{above_floor, clip_hulls, hull_fits, settle};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use toolbox::SplitMix64;

/// Grid spacing of the floor search.
pub const CELL: f64 = 16.0;
/// Largest number of grid cells one search expands.
const MAX_EXPANSIONS: usize = 400_000;

/// Spawn classnames by team (Counter-Strike: CT and T; Half-Life: start and deathmatch).
const TEAM_A: [&str; 2] = ["info_player_start", "info_player_counterterrorist"];
const TEAM_B: [&str; 2] = ["info_player_deathmatch", "info_player_terrorist"];

/// A floor position on the grid.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cell {
    ix: i32,
    iy: i32,
    floor: f64,
    crouch: bool,
}

/// The floor search of one map: grid origin and the oracle.
pub struct Floor<'a> {
    oracle: &'a Oracle,
    x0: f64,
    y0: f64,
}

#[derive(PartialEq)]
struct Open(f64, usize);
impl Eq for Open {}
impl Ord for Open {
    fn cmp(&self, o: &Self) -> Ordering {
        o.0.total_cmp(&self.0).then(o.1.cmp(&self.1))
    }
}
impl PartialOrd for Open {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}

impl<'a> Floor<'a> {
    /// A search whose grid passes through `(x0, y0)`.
    pub fn new(oracle: &'a Oracle, x0: f64, y0: f64) -> Self {
        Floor { oracle, x0, y0 }
    }

    fn xy(&self, c: &Cell) -> (f64, f64) {
        (self.x0 + c.ix as f64 * CELL, self.y0 + c.iy as f64 * CELL)
    }

    fn key(c: &Cell) -> (i32, i32, i32) {
        (c.ix, c.iy, (c.floor / 4.0).round() as i32)
    }

    fn waypoint(&self, c: &Cell) -> Waypoint {
        let (x, y) = self.xy(c);
        Waypoint {
            x,
            y,
            floor: c.floor,
            crouch: c.crouch,
        }
    }

    /// The cell reached by moving one grid step `(dx, dy)` from `c`, as the engine
    /// would move the player (standing if possible, else crouched).
    fn step(&self, c: &Cell, dx: i32, dy: i32) -> Option<Cell> {
        let (x, y) = self.xy(c);
        let d = [dx as f64 * CELL, dy as f64 * CELL];
        for &hull in clip_hulls(self.oracle, false) {
            let half = above_floor(self.oracle, hull == 3);
            let o = [x, y, c.floor + half];
            if !hull_fits(self.oracle, hull, o) {
                continue;
            }
            let up = self.oracle.trace(hull, o, [x, y, o[2] + 18.0])?;
            let o1 = up.end;
            let fw = self
                .oracle
                .trace(hull, o1, [o1[0] + d[0], o1[1] + d[1], o1[2]])?;
            if fw.fraction < 1.0 || fw.start_solid {
                continue;
            }
            let o2 = fw.end;
            let dn = self
                .oracle
                .trace(hull, o2, [o2[0], o2[1], o2[2] - 18.0 - 36.0])?;
            if dn.start_solid || dn.fraction >= 1.0 || dn.normal[2] < 0.7 {
                continue;
            }
            return Some(Cell {
                ix: c.ix + dx,
                iy: c.iy + dy,
                floor: dn.end[2] - half,
                crouch: hull == 3,
            });
        }
        None
    }

    fn start_cell(&self, origin: [f64; 3]) -> Option<Cell> {
        let ix = ((origin[0] - self.x0) / CELL).round() as i32;
        let iy = ((origin[1] - self.y0) / CELL).round() as i32;
        let (x, y) = (self.x0 + ix as f64 * CELL, self.y0 + iy as f64 * CELL);
        let (o, crouch) = settle(
            self.oracle,
            x,
            y,
            origin[2] - above_floor(self.oracle, false),
            false,
        )
        .or_else(|| drop_to_floor(self.oracle, [x, y, origin[2]]))?;
        Some(Cell {
            ix,
            iy,
            floor: o[2] - above_floor(self.oracle, crouch),
            crouch,
        })
    }

    /// A* over the floor grid from player origin `from` to player origin `to`.
    pub fn path(&self, from: [f64; 3], to: [f64; 3]) -> Option<Vec<Waypoint>> {
        let start = self.start_cell(from)?;
        let goal = self.start_cell(to)?;
        let h = |c: &Cell| {
            let (x, y) = self.xy(c);
            let g = self.xy(&goal);
            ((x - g.0).powi(2) + (y - g.1).powi(2) + (c.floor - goal.floor).powi(2)).sqrt()
        };
        let mut cells = vec![start];
        let mut parent = vec![usize::MAX];
        let mut cost = vec![0.0f64];
        let mut index = HashMap::from([(Self::key(&start), 0usize)]);
        let mut open = BinaryHeap::from([Open(h(&start), 0)]);
        let mut expanded = 0;
        while let Some(Open(_, i)) = open.pop() {
            let c = cells[i];
            if c.ix == goal.ix && c.iy == goal.iy && (c.floor - goal.floor).abs() < 20.0 {
                let mut out = Vec::new();
                let mut k = i;
                while k != usize::MAX {
                    out.push(self.waypoint(&cells[k]));
                    k = parent[k];
                }
                out.reverse();
                return Some(out);
            }
            expanded += 1;
            if expanded > MAX_EXPANSIONS {
                return None;
            }
            for (dx, dy) in NEIGHBOURS {
                let Some(n) = self.step(&c, dx, dy) else {
                    continue;
                };
                let len = if dx != 0 && dy != 0 {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                } * CELL;
                let g =
                    cost[i] + len * if n.crouch { 2.5 } else { 1.0 } + (n.floor - c.floor).abs();
                match index.get(&Self::key(&n)) {
                    Some(&j) if cost[j] <= g => {}
                    Some(&j) => {
                        cost[j] = g;
                        parent[j] = i;
                        open.push(Open(g + h(&n), j));
                    }
                    None => {
                        let j = cells.len();
                        cells.push(n);
                        parent.push(i);
                        cost.push(g);
                        index.insert(Self::key(&n), j);
                        open.push(Open(g + h(&n), j));
                    }
                }
            }
        }
        None
    }

    /// Floor cells reachable from `from` (breadth first, at most `limit`), as player origins.
    pub fn reachable(&self, from: [f64; 3], limit: usize) -> Vec<[f64; 3]> {
        let Some(start) = self.start_cell(from) else {
            return Vec::new();
        };
        let mut cells = vec![start];
        let mut seen = HashMap::from([(Self::key(&start), ())]);
        let mut i = 0;
        while i < cells.len() && cells.len() < limit {
            let c = cells[i];
            i += 1;
            for (dx, dy) in NEIGHBOURS {
                if let Some(n) = self.step(&c, dx, dy)
                    && seen.insert(Self::key(&n), ()).is_none()
                {
                    cells.push(n);
                }
            }
        }
        cells
            .iter()
            .filter(|c| !c.crouch)
            .map(|c| {
                let (x, y) = self.xy(c);
                [x, y, c.floor + above_floor(self.oracle, false)]
            })
            .collect()
    }
}

const NEIGHBOURS: [(i32, i32); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
];

/// The pairs of start and end origins for spawn routes: cross-team pairs first,
/// then same-team pairs, shuffled with `seed` and capped at `max`; where the map has
/// fewer than two spawns, random floor points reachable from the one spawn (or from a
/// random free floor point).
pub fn endpoints(bsp: &Bsp, oracle: &Oracle, seed: u64, max: usize) -> Vec<([f64; 3], [f64; 3])> {
    let spawns = |names: &[&str]| -> Vec<[f64; 3]> {
        bsp.entities
            .iter()
            .filter(|e| names.contains(&e.classname()))
            .filter_map(|e| e.origin())
            .map(|o| o.map(f64::from))
            .collect()
    };
    let (a, b) = (spawns(&TEAM_A), spawns(&TEAM_B));
    let mut rng = SplitMix64::new(seed);
    let all: Vec<[f64; 3]> = a.iter().chain(&b).copied().collect();
    let far = |p: &[f64; 3], q: &[f64; 3]| {
        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2) > 256.0f64.powi(2)
    };
    if all.len() >= 2 {
        let mut cross: Vec<_> = a
            .iter()
            .flat_map(|p| b.iter().map(move |q| (*p, *q)))
            .filter(|(p, q)| far(p, q))
            .collect();
        shuffle(&mut cross, &mut rng);
        let mut same: Vec<_> = (0..all.len())
            .flat_map(|i| (i + 1..all.len()).map(move |j| (i, j)))
            .map(|(i, j)| (all[i], all[j]))
            .filter(|(p, q)| far(p, q))
            .collect();
        shuffle(&mut same, &mut rng);
        // A spawn may carry several classnames (e.g. start and deathmatch at one
        // place): each unordered pair of places once.
        let mut seen = std::collections::HashSet::new();
        let key = |p: &[f64; 3]| p.map(|c| c.round() as i64);
        let mut pairs: Vec<_> = cross
            .into_iter()
            .chain(same)
            .filter(|(p, q)| {
                let (kp, kq) = (key(p), key(q));
                seen.insert(if kp <= kq { (kp, kq) } else { (kq, kp) })
            })
            .collect();
        pairs.truncate(max);
        if !pairs.is_empty() {
            return pairs;
        }
    }
    // Fewer than two usable spawns: random reachable floor points.
    let start = all
        .first()
        .copied()
        .or_else(|| random_floor_point(bsp, oracle, &mut rng));
    match start {
        Some(start) => floor_tour(oracle, start, &mut rng, max),
        None => Vec::new(),
    }
}

/// `max` legs between random floor points reachable on foot from `start`, each
/// more than 256 units long, the next leg starting where the last one ended.
fn floor_tour(
    oracle: &Oracle,
    start: [f64; 3],
    rng: &mut SplitMix64,
    max: usize,
) -> Vec<([f64; 3], [f64; 3])> {
    let far = |p: &[f64; 3], q: &[f64; 3]| {
        (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2) > 256.0f64.powi(2)
    };
    let floor = Floor::new(oracle, start[0], start[1]);
    let reach = floor.reachable(start, 60_000);
    let far_ones: Vec<_> = reach.iter().filter(|p| far(p, &start)).copied().collect();
    if far_ones.is_empty() {
        return Vec::new();
    }
    let mut pairs = Vec::new();
    let mut from = start;
    for _ in 0..max {
        let to = far_ones[rng.below(far_ones.len())];
        pairs.push((from, to));
        from = to;
    }
    pairs
}

fn shuffle<T>(v: &mut [T], rng: &mut SplitMix64) {
    for i in (1..v.len()).rev() {
        v.swap(i, rng.below(i + 1));
    }
}

/// The floor below `p` (a spawn's origin may float or sit a little in the ground):
/// the standing, else the crouched hull, lifted by up to 36 units if it does not fit,
/// dropped until it lands on walkable ground.
fn drop_to_floor(oracle: &Oracle, p: [f64; 3]) -> Option<([f64; 3], bool)> {
    for hull in [1usize, 3] {
        for lift in [0.0, 18.0, 36.0] {
            let q = [p[0], p[1], p[2] + lift];
            if !hull_fits(oracle, hull, q) {
                continue;
            }
            let t = oracle.trace(hull, q, [q[0], q[1], q[2] - 4096.0])?;
            if !t.start_solid && t.fraction < 1.0 && t.normal[2] >= 0.7 {
                return Some((t.end, hull == 3));
            }
            break;
        }
    }
    None
}

/// A random origin where a standing player fits on the floor inside the world's bounds.
fn random_floor_point(bsp: &Bsp, oracle: &Oracle, rng: &mut SplitMix64) -> Option<[f64; 3]> {
    let m = bsp.world();
    for _ in 0..20_000 {
        let p = [0, 1, 2].map(|i| rng.range(m.mins[i] as f64, m.maxs[i] as f64));
        if !hull_fits(oracle, 1, p) {
            continue;
        }
        let t = oracle.trace(1, p, [p[0], p[1], p[2] - 4096.0])?;
        if !t.start_solid && t.fraction < 1.0 && t.normal[2] >= 0.7 {
            return Some(t.end);
        }
    }
    None
}

/// Spawn routes of a map: the planned, straightened and walked paths, with the
/// number of endpoint pairs no floor path joined.
pub fn routes(
    bsp: &Bsp,
    oracle: &Oracle,
    seed: u64,
    max: usize,
) -> (Vec<Route>, Vec<WalkStats>, usize) {
    let pairs = endpoints(bsp, oracle, seed, max);
    let (mut routes, mut stats, unreachable) = walk_pairs(oracle, &pairs, seed, 0);
    if routes.is_empty()
        && let Some(&(start, _)) = pairs.first()
    {
        // No floor path joins any pair of spawns (they sit in areas a player
        // joins by ladder, lift or door, as on some single-player maps): tour the floor
        // reachable from the first spawn instead, so every map gets measured.
        let mut rng = SplitMix64::new(seed ^ 0x7f4a_7c15);
        let tour = floor_tour(oracle, start, &mut rng, max);
        let (r, s, _) = walk_pairs(oracle, &tour, seed, pairs.len());
        (routes, stats) = (r, s);
    }
    (routes, stats, unreachable)
}

/// Plans, straightens and walks the route of each pair (numbered from `first`);
/// returns the routes, their walking statistics and the number of pairs no floor
/// path joined.
fn walk_pairs(
    oracle: &Oracle,
    pairs: &[([f64; 3], [f64; 3])],
    seed: u64,
    first: usize,
) -> (Vec<Route>, Vec<WalkStats>, usize) {
    let mut routes = Vec::new();
    let mut stats = Vec::new();
    let mut unreachable = 0;
    for (k, &(from, to)) in pairs.iter().enumerate() {
        let k = k + first;
        let floor = Floor::new(oracle, from[0], from[1]);
        let Some(path) = floor.path(from, to) else {
            unreachable += 1;
            continue;
        };
        if path.len() < 2 {
            unreachable += 1;
            continue;
        }
        let path = string_pull(oracle, &path);
        let name = format!(
            "spawn{k}:{:.0},{:.0},{:.0}->{:.0},{:.0},{:.0}",
            from[0], from[1], from[2], to[0], to[1], to[2]
        );
        for (r, s) in walk_parts(
            oracle,
            &name,
            &path,
            seed ^ (k as u64 + 1).wrapping_mul(0x9e37),
        ) {
            routes.push(r);
            stats.push(s);
        }
    }
    (routes, stats, unreachable)
}
