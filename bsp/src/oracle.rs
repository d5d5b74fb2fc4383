//! The free-space oracle: point contents and "is this segment free?" queries answered
//! by the map's own BSP trees.
//!
//! This is both a pipeline stage (Voronoi faces are kept only where they lie in free
//! space) and the ground truth of every quality measurement, so it follows the engine:
//! a point with `normal · p - dist >= 0` goes to the front child, exactly as Quake's
//! `SV_HullPointContents` does. Trees are flattened into 32-byte nodes whose leaf
//! children are replaced by their contents value, so a query touches one array only.
//!
//! ```no_run
//! use bsp::{Bsp, oracle::{Oracle, OracleOptions}};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let oracle = Oracle::new(&bsp, &OracleOptions::default());
//! let free = oracle.is_free([0.0, 0.0, 64.0]);
//! let seen = oracle.segment_free([0.0, 0.0, 64.0], [512.0, 0.0, 64.0]);
//! # Ok::<(), bsp::BspError>(())
//! ```

use crate::{Bsp, contents};
use toolbox::vec3::sub;

mod brushes;
mod player_hull;
mod trace;

pub use brushes::BrushSet;
pub use trace::{DIST_EPSILON, Trace};

/// Which contents count as obstacles.
#[derive(Debug, Clone, Default)]
pub struct OracleOptions {
    /// Treat water, slime and lava as obstacles (by default they are free space).
    pub liquids_are_solid: bool,
    /// Treat player and monster clip as obstacles ([`contents::CLIP`]: GoldSrc's
    /// clip, Quake 2's and 3's `PLAYERCLIP`/`MONSTERCLIP` brushes). By default they
    /// are free space: they keep players off ledges and out of corners, but cameras
    /// and sight lines pass through them. The player's hulls always collide with
    /// them, as the games do.
    pub clip_is_solid: bool,
    /// Brush models (by index `*N`) whose solid volume also blocks, e.g. func_wall.
    pub solid_models: Vec<usize>,
}

impl OracleOptions {
    /// Whether a Quake contents value is an obstacle under these options: solid and
    /// sky always, liquids and clip when asked.
    ///
    /// ```
    /// use bsp::{contents, oracle::OracleOptions};
    /// let o = OracleOptions::default();
    /// assert!(o.blocks(contents::SOLID) && !o.blocks(contents::CLIP));
    /// let clip = OracleOptions { clip_is_solid: true, ..Default::default() };
    /// assert!(clip.blocks(contents::CLIP) && !clip.blocks(contents::WATER));
    /// ```
    pub fn blocks(&self, c: i32) -> bool {
        blocks(c, self.liquids_are_solid, self.clip_is_solid)
    }
}

fn blocks(c: i32, liquids: bool, clip: bool) -> bool {
    c == contents::SOLID
        || c == contents::SKY
        || (liquids && contents::is_liquid(c))
        || (clip && c == contents::CLIP)
}

/// A flattened BSP node. `children[i] >= 0` is a node index, `< 0` a contents value.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(32))]
struct HullNode {
    normal: [f32; 3],
    dist: f32,
    children: [i32; 2],
    /// 0, 1, 2 for an axial plane (the normal is that unit axis), 3 otherwise.
    axis: u32,
}

/// One collision tree: hull 0 (the visible geometry) or a clip hull.
#[derive(Debug, Clone)]
pub struct Hull {
    nodes: Vec<HullNode>,
    /// A node index, or a contents value when the hull is a single leaf.
    root: i32,
}

impl Hull {
    /// The hull-0 tree of model `model`.
    pub fn from_nodes(bsp: &Bsp, model: usize) -> Hull {
        let leaf_contents = |c: i32| {
            let c = bsp.leaves[(-(c + 1)) as usize].contents;
            // Contents >= 0 are not part of the Quake family; be conservative.
            if c >= 0 { contents::SOLID } else { c }
        };
        let map_child = |c: i32| if c >= 0 { c } else { leaf_contents(c) };
        let nodes = bsp
            .nodes
            .iter()
            .map(|n| hull_node(bsp, n.plane, n.children.map(map_child)))
            .collect();
        Hull {
            nodes,
            root: map_child(bsp.models[model].headnode[0]),
        }
    }

    /// Clip hull `hull` (1..=3) of model `model`, or `None` when the map has no clip
    /// nodes or the hull is unused (see [`crate::Model::clip_headnode`]).
    pub fn from_clipnodes(bsp: &Bsp, model: usize, hull: usize) -> Option<Hull> {
        let root = bsp.models[model].clip_headnode(hull, bsp.clipnodes.len())?;
        let nodes = bsp
            .clipnodes
            .iter()
            .map(|n| hull_node(bsp, n.plane, n.children))
            .collect();
        Some(Hull { nodes, root })
    }

    /// The contents value at `p`.
    #[inline]
    pub fn contents(&self, p: [f64; 3]) -> i32 {
        let mut n = self.root;
        while n >= 0 {
            // Validated on load: every child index is in range and the tree is acyclic.
            let node = &self.nodes[n as usize];
            n = node.children[(side_distance(node, p) < 0.0) as usize];
        }
        n
    }

    /// The contents at `p` below node (or contents value) `n`.
    #[inline]
    fn contents_from(&self, mut n: i32, p: [f64; 3]) -> i32 {
        while n >= 0 {
            let node = &self.nodes[n as usize];
            n = node.children[(side_distance(node, p) < 0.0) as usize];
        }
        n
    }

    /// Whether the closed segment `a`–`b` meets no contents for which `blocks` is true.
    pub fn segment_clear(&self, a: [f64; 3], b: [f64; 3], blocks: impl Fn(i32) -> bool) -> bool {
        let mut stack: Vec<(i32, [f64; 3], [f64; 3])> = Vec::with_capacity(64);
        stack.push((self.root, a, b));
        while let Some((n, p, q)) = stack.pop() {
            if n < 0 {
                if blocks(n) {
                    return false;
                }
                continue;
            }
            let node = &self.nodes[n as usize];
            let (dp, dq) = (side_distance(node, p), side_distance(node, q));
            let (sp, sq) = ((dp < 0.0) as usize, (dq < 0.0) as usize);
            if sp == sq {
                stack.push((node.children[sp], p, q));
            } else {
                // The crossing point belongs to both halves, so touching a wall counts.
                let t = dp / (dp - dq);
                let m = [
                    p[0] + t * (q[0] - p[0]),
                    p[1] + t * (q[1] - p[1]),
                    p[2] + t * (q[2] - p[2]),
                ];
                stack.push((node.children[sq], m, q));
                stack.push((node.children[sp], p, m));
            }
        }
        true
    }

    /// Visits the leaves the segment `a`–`b` passes through, in order from `a`:
    /// `visit(t0, t1, contents, exit_normal)` with `a + t (b - a)` for `t0 ≤ t ≤ t1` in the
    /// leaf, and the normal of the node plane by which the segment leaves it (`[0; 3]`
    /// for the last leaf). Finding floors (a free leaf followed by a solid one along a
    /// downward ray) and their slope needs exactly this.
    pub fn segment_leaves(
        &self,
        a: [f64; 3],
        b: [f64; 3],
        mut visit: impl FnMut(f64, f64, i32, [f32; 3]),
    ) {
        type Piece = (i32, [f64; 3], [f64; 3], f64, f64, [f32; 3]);
        let mut stack: Vec<Piece> = Vec::with_capacity(64);
        stack.push((self.root, a, b, 0.0, 1.0, [0.0; 3]));
        while let Some((n, p, q, tp, tq, nq)) = stack.pop() {
            if n < 0 {
                visit(tp, tq, n, nq);
                continue;
            }
            let node = &self.nodes[n as usize];
            let (dp, dq) = (side_distance(node, p), side_distance(node, q));
            let (sp, sq) = ((dp < 0.0) as usize, (dq < 0.0) as usize);
            if sp == sq {
                stack.push((node.children[sp], p, q, tp, tq, nq));
            } else {
                let t = dp / (dp - dq);
                let m = [0, 1, 2].map(|i| p[i] + t * (q[i] - p[i]));
                let tm = tp + t * (tq - tp);
                stack.push((node.children[sq], m, q, tm, tq, nq));
                stack.push((node.children[sp], p, m, tp, tm, node.normal));
            }
        }
    }
}

fn hull_node(bsp: &Bsp, plane: u32, children: [i32; 2]) -> HullNode {
    let p = &bsp.planes[plane as usize];
    hull_node_on(p.normal, p.dist, children)
}

fn hull_node_on(normal: [f32; 3], dist: f32, children: [i32; 2]) -> HullNode {
    let axis = (0..3)
        .find(|&i| normal[i] == 1.0 && normal.iter().filter(|&&c| c == 0.0).count() == 2)
        .unwrap_or(3) as u32;
    HullNode {
        normal,
        dist,
        children,
        axis,
    }
}

#[inline(always)]
fn side_distance(node: &HullNode, p: [f64; 3]) -> f64 {
    let dist = node.dist as f64;
    match node.axis {
        0 => p[0] - dist,
        1 => p[1] - dist,
        2 => p[2] - dist,
        _ => {
            let n = node.normal;
            n[0] as f64 * p[0] + n[1] as f64 * p[1] + n[2] as f64 * p[2] - dist
        }
    }
}

/// A brush model that blocks, with its placement.
#[derive(Debug, Clone)]
struct SolidModel {
    hull: Hull,
    origin: [f64; 3],
    mins: [f64; 3],
    maxs: [f64; 3],
}

/// Free-space queries against a map.
#[derive(Debug, Clone)]
pub struct Oracle {
    world: Hull,
    clip_hulls: [Option<Hull>; 3],
    /// The player's hulls of games that keep none (Quake 2, 3), built from the
    /// brushes on first use (seconds on large maps; most queries never need them)
    /// and shared by the oracle's clones.
    built_hulls: Option<std::sync::Arc<BuiltHulls>>,
    solid_models: Vec<SolidModel>,
    liquids_are_solid: bool,
    clip_is_solid: bool,
    /// The world's brushes where the map keeps them (Quake 2).
    brushes: Option<BrushSet>,
    game: crate::Game,
    /// The world model's bounds, where the map leaks (see [`Oracle::fence`]).
    fence: Option<([f64; 3], [f64; 3])>,
}

/// The player's hulls built from a map's brushes, once.
#[derive(Debug)]
struct BuiltHulls {
    source: Bsp,
    standing: std::sync::OnceLock<Option<Hull>>,
    crouched: std::sync::OnceLock<Option<Hull>>,
}

/// The player's two collision boxes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlayerHull {
    Standing,
    Crouched,
}

impl PlayerHull {
    /// The Quake 2 player's box for this stance (`pmove`'s mins and maxs).
    pub fn quake2_box(self) -> ([f64; 3], [f64; 3]) {
        let s = *Body::of(crate::Game::Quake2).stance(self);
        (s.mins, s.maxs)
    }

    /// The Quake 3 player's box for this stance (`bg_pmove.c`: 15 units to each
    /// side, 32 above the origin standing, 16 crouched, 24 below).
    pub fn quake3_box(self) -> ([f64; 3], [f64; 3]) {
        let s = *Body::of(crate::Game::Quake3).stance(self);
        (s.mins, s.maxs)
    }
}

/// A player in one stance: the collision box around the origin and the eye (the
/// view offset) above it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stance {
    pub mins: [f64; 3],
    pub maxs: [f64; 3],
    /// The eye's height above the origin (negative: below it).
    pub view: f64,
}

impl Stance {
    /// How far the origin is above the floor the player stands on.
    pub fn origin_above_ground(&self) -> f64 {
        -self.mins[2]
    }

    /// The box's height.
    pub fn height(&self) -> f64 {
        self.maxs[2] - self.mins[2]
    }
}

/// A game's player, standing and crouched: the numbers every tool that puts a player
/// into a map needs (where the origin is above the floor, how tall the box is, where
/// the eye a camera follows is).
///
/// ```
/// use bsp::{Game, oracle::Body};
/// let hl = Body::of(Game::GoldSrc);
/// assert_eq!(hl.standing.origin_above_ground() + hl.standing.view, 64.0);
/// assert_eq!(Body::of(Game::Quake2).crouched.map(|c| c.view), Some(-2.0));
/// assert_eq!(Body::of(Game::Quake).crouched, None);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    pub standing: Stance,
    /// `None` for Quake 1, whose players do not crouch.
    pub crouched: Option<Stance>,
}

impl Body {
    /// The player of `game`: GoldSrc's clip hulls 1 (32 × 32 × 72) and 3 (32 × 32 × 36)
    /// centred on the origin with the views `VEC_VIEW` 28 and `VEC_DUCK_VIEW` 12;
    /// Quake's 32 × 32 × 56 box 24 units below and 32 above the origin, view 22;
    /// Quake 2's (`pmove.c`) 24 below and 32 above standing, 4 above crouched, views 22
    /// and −2; Quake 3's (`bg_pmove.c`) 15 units to each side, 24 below and 32 above
    /// standing, 16 above crouched, views 26 and 12.
    pub fn of(game: crate::Game) -> Body {
        let stance = |w: f64, below: f64, above: f64, view: f64| Stance {
            mins: [-w, -w, -below],
            maxs: [w, w, above],
            view,
        };
        match game {
            crate::Game::GoldSrc => Body {
                standing: stance(16.0, 36.0, 36.0, 28.0),
                crouched: Some(stance(16.0, 18.0, 18.0, 12.0)),
            },
            crate::Game::Quake => Body {
                standing: stance(16.0, 24.0, 32.0, 22.0),
                crouched: None,
            },
            crate::Game::Quake2 => Body {
                standing: stance(16.0, 24.0, 32.0, 22.0),
                crouched: Some(stance(16.0, 24.0, 4.0, -2.0)),
            },
            crate::Game::Quake3 => Body {
                standing: stance(15.0, 24.0, 32.0, 26.0),
                crouched: Some(stance(15.0, 24.0, 16.0, 12.0)),
            },
        }
    }

    /// The stance of `hull` (standing for a player that does not crouch).
    pub fn stance(&self, hull: PlayerHull) -> &Stance {
        match (hull, &self.crouched) {
            (PlayerHull::Crouched, Some(c)) => c,
            _ => &self.standing,
        }
    }
}

impl Oracle {
    /// Builds the oracle for the world model (plus any solid brush models).
    pub fn new(bsp: &Bsp, options: &OracleOptions) -> Oracle {
        let solid_models = options
            .solid_models
            .iter()
            .filter(|&&m| m > 0 && m < bsp.models.len())
            .map(|&m| {
                let model = &bsp.models[m];
                let origin = bsp
                    .entity_of_model(m)
                    .and_then(|e| e.origin())
                    .unwrap_or([0.0; 3])
                    .map(f64::from);
                SolidModel {
                    hull: Hull::from_nodes(bsp, m),
                    origin,
                    mins: [0, 1, 2].map(|i| model.mins[i] as f64 + origin[i] - 1.0),
                    maxs: [0, 1, 2].map(|i| model.maxs[i] as f64 + origin[i] + 1.0),
                }
            })
            .collect();
        let clip_hulls = [1, 2, 3].map(|h| Hull::from_clipnodes(bsp, 0, h));
        let built_hulls = (clip_hulls.iter().all(Option::is_none)
            && matches!(bsp.game, crate::Game::Quake2 | crate::Game::Quake3))
        .then(|| {
            std::sync::Arc::new(BuiltHulls {
                source: bsp.clone(),
                standing: std::sync::OnceLock::new(),
                crouched: std::sync::OnceLock::new(),
            })
        });
        Oracle {
            built_hulls,
            world: Hull::from_nodes(bsp, 0),
            clip_hulls,
            solid_models,
            liquids_are_solid: options.liquids_are_solid,
            clip_is_solid: options.clip_is_solid,
            brushes: BrushSet::new(bsp, 0),
            game: bsp.game,
            fence: crate::leak::outside_is_free(bsp).then(|| {
                let w = bsp.world();
                (w.mins.map(f64::from), w.maxs.map(f64::from))
            }),
        }
    }

    /// Where free space ends in a map that leaks: the world model's bounds.
    ///
    /// A sealed map's compiler fills everything outside its walls with solid; a map
    /// that leaks (its free space reaches the void around the level, as many community
    /// maps compiled with warnings do) has an empty outside that stretches as far as
    /// the tree's planes do. No place a player can reach lies outside the world's
    /// bounds, so there everything beyond them counts as solid: the oracle's answers
    /// (contents, free points and segments, clip hulls) are those of the map's inside.
    /// `None` for a sealed map, whose answers are the tree's own.
    pub fn fence(&self) -> Option<([f64; 3], [f64; 3])> {
        self.fence
    }

    /// Whether `p` lies outside the fence of a leaking map.
    #[inline]
    fn fenced_out(&self, p: [f64; 3]) -> bool {
        self.fence
            .is_some_and(|(lo, hi)| (0..3).any(|i| p[i] < lo[i] || p[i] > hi[i]))
    }

    /// Whether a contents value is an obstacle under these options.
    #[inline]
    pub fn blocks(&self, c: i32) -> bool {
        blocks(c, self.liquids_are_solid, self.clip_is_solid)
    }

    /// The game of the map: how its players collide and crouch ([`Body::of`]).
    pub fn game(&self) -> crate::Game {
        self.game
    }

    /// The world's hull-0 contents at `p` (solid models not included).
    #[inline]
    pub fn contents(&self, p: [f64; 3]) -> i32 {
        if self.fenced_out(p) {
            return contents::SOLID;
        }
        self.world.contents(p)
    }

    /// Whether a player's box with its origin at `p` is stuck (`SOLID`) or, if not,
    /// the contents there, in the Quake convention; `None` when the map has no way to
    /// tell (no clip hulls, no brushes).
    ///
    /// The common query of every format: GoldSrc collides the player with clip hull 1
    /// (standing) or 3 (crouched), Quake with hull 1, Quake 2 and 3 with their brushes
    /// expanded by the player's box ([`PlayerHull::quake2_box`],
    /// [`PlayerHull::quake3_box`]; player clip blocks; Quake 3's patches are brushes
    /// too, see [`crate::quake3`]).
    ///
    /// ```no_run
    /// use bsp::oracle::{Oracle, PlayerHull};
    /// let bsp = bsp::Bsp::open("maps/q2dm1.bsp")?;
    /// let oracle = Oracle::new(&bsp, &Default::default());
    /// let stuck = oracle.player_contents(PlayerHull::Standing, [0.0, 0.0, 24.0])
    ///     == Some(bsp::contents::SOLID);
    /// # Ok::<(), bsp::BspError>(())
    /// ```
    pub fn player_contents(&self, hull: PlayerHull, p: [f64; 3]) -> Option<i32> {
        match self.game {
            crate::Game::Quake2 => {
                let (mins, maxs) = hull.quake2_box();
                let flags = self.brushes.as_ref()?.box_contents(p, mins, maxs);
                Some(if flags & crate::quake2::contents::MASK_PLAYERSOLID != 0 {
                    contents::SOLID
                } else {
                    crate::quake2::to_quake_contents(flags)
                })
            }
            crate::Game::Quake3 => {
                let (mins, maxs) = hull.quake3_box();
                let flags = self.brushes.as_ref()?.box_contents(p, mins, maxs);
                Some(if flags & crate::quake3::contents::MASK_PLAYERSOLID != 0 {
                    contents::SOLID
                } else {
                    crate::quake3::to_quake_contents(flags)
                })
            }
            crate::Game::GoldSrc if hull == PlayerHull::Crouched => self.clip_contents(3, p),
            crate::Game::GoldSrc | crate::Game::Quake => self.clip_contents(1, p),
        }
    }

    /// The world's brushes, where the map keeps them (Quake 2).
    pub fn brushes(&self) -> Option<&BrushSet> {
        self.brushes.as_ref()
    }

    /// Contents at `p` in clip hull 1..=3 of the world, if the map has clip hulls.
    pub fn clip_contents(&self, hull: usize, p: [f64; 3]) -> Option<i32> {
        let h = self.clip_hull(hull)?;
        Some(if self.fenced_out(p) {
            contents::SOLID
        } else {
            h.contents(p)
        })
    }

    /// Clip hull `hull` (1..=3) of the world, if the map has clip hulls. Quake 2 and
    /// 3 keep none: their hull 1 (standing player) and 3 (crouched) are built from
    /// the brushes ([`Hull::from_brushes`]) the first time they are asked for.
    pub fn clip_hull(&self, hull: usize) -> Option<&Hull> {
        match (&self.built_hulls, hull) {
            (Some(b), 1) => b
                .standing
                .get_or_init(|| Hull::from_brushes(&b.source, PlayerHull::Standing))
                .as_ref(),
            (Some(b), 3) => b
                .crouched
                .get_or_init(|| Hull::from_brushes(&b.source, PlayerHull::Crouched))
                .as_ref(),
            _ => self.clip_hulls.get(hull.wrapping_sub(1))?.as_ref(),
        }
    }

    /// Whether `p` is in free space.
    #[inline]
    pub fn is_free(&self, p: [f64; 3]) -> bool {
        !self.fenced_out(p)
            && !self.blocks(self.world.contents(p))
            && self.solid_models.iter().all(|m| {
                !inside_box(p, m.mins, m.maxs)
                    || m.hull.contents(sub(p, m.origin)) != contents::SOLID
            })
    }

    /// Whether the whole closed segment `a`–`b` lies in free space.
    pub fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        // The fence is a box: a segment is inside it when both ends are.
        !self.fenced_out(a)
            && !self.fenced_out(b)
            && self.world.segment_clear(a, b, |c| self.blocks(c))
            && self.solid_models.iter().all(|m| {
                !segment_meets_box(a, b, m.mins, m.maxs)
                    || m.hull
                        .segment_clear(sub(a, m.origin), sub(b, m.origin), |c| c == contents::SOLID)
            })
    }
}

fn inside_box(p: [f64; 3], mins: [f64; 3], maxs: [f64; 3]) -> bool {
    (0..3).all(|i| p[i] >= mins[i] && p[i] <= maxs[i])
}

/// Slab test: does the segment touch the box?
fn segment_meets_box(a: [f64; 3], b: [f64; 3], mins: [f64; 3], maxs: [f64; 3]) -> bool {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        let d = b[i] - a[i];
        if d == 0.0 {
            if a[i] < mins[i] || a[i] > maxs[i] {
                return false;
            }
            continue;
        }
        let (mut u, mut v) = ((mins[i] - a[i]) / d, (maxs[i] - a[i]) / d);
        if u > v {
            std::mem::swap(&mut u, &mut v);
        }
        t0 = t0.max(u);
        t1 = t1.min(v);
        if t0 > t1 {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_box_slab_test() {
        let (lo, hi) = ([0.0; 3], [1.0; 3]);
        assert!(segment_meets_box([-1.0, 0.5, 0.5], [2.0, 0.5, 0.5], lo, hi));
        assert!(!segment_meets_box(
            [-1.0, 2.0, 0.5],
            [2.0, 2.0, 0.5],
            lo,
            hi
        ));
        assert!(segment_meets_box([0.5; 3], [0.5; 3], lo, hi));
        assert!(!segment_meets_box(
            [-1.0, -1.0, 0.5],
            [-0.1, 3.0, 0.5],
            lo,
            hi
        ));
    }

    /// A hand-made hull: x >= 0 is empty, x < 0 solid; inside that, z >= 10 is sky.
    fn half_space_hull() -> Hull {
        Hull {
            nodes: vec![
                HullNode {
                    normal: [1.0, 0.0, 0.0],
                    dist: 0.0,
                    children: [1, contents::SOLID],
                    axis: 0,
                },
                HullNode {
                    normal: [0.0, 0.0, 1.0],
                    dist: 10.0,
                    children: [contents::SKY, contents::EMPTY],
                    axis: 2,
                },
            ],
            root: 0,
        }
    }

    #[test]
    fn point_contents_follows_front_on_plane_rule() {
        let h = half_space_hull();
        assert_eq!(h.contents([1.0, 0.0, 0.0]), contents::EMPTY);
        assert_eq!(h.contents([0.0, 0.0, 0.0]), contents::EMPTY);
        assert_eq!(h.contents([-0.001, 0.0, 0.0]), contents::SOLID);
        assert_eq!(h.contents([5.0, 0.0, 10.0]), contents::SKY);
    }

    #[test]
    fn segment_test_splits_at_planes() {
        let h = half_space_hull();
        let blocks = |c: i32| c == contents::SOLID || c == contents::SKY;
        assert!(h.segment_clear([1.0, 0.0, 1.0], [9.0, 5.0, 9.0], blocks));
        assert!(!h.segment_clear([1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], blocks));
        assert!(!h.segment_clear([1.0, 0.0, 1.0], [1.0, 0.0, 11.0], blocks));
        // Diagonal through the empty corner region only.
        assert!(h.segment_clear([0.5, 0.0, 9.5], [9.5, 0.0, 0.5], blocks));
    }

    #[test]
    fn segment_leaves_come_in_order_with_their_exit_planes() {
        let h = half_space_hull();
        let mut seen = Vec::new();
        h.segment_leaves([6.0, 0.0, 14.0], [-2.0, 0.0, 6.0], |t0, t1, c, n| {
            seen.push((t0, t1, c, n))
        });
        // Sky above z = 10 (t < 0.5), empty down to x = 0 (t = 0.75), then solid.
        let expected = [
            (0.0, 0.5, contents::SKY, [0.0, 0.0, 1.0]),
            (0.5, 0.75, contents::EMPTY, [1.0, 0.0, 0.0]),
            (0.75, 1.0, contents::SOLID, [0.0; 3]),
        ];
        assert_eq!(seen.len(), 3, "{seen:?}");
        for (s, e) in seen.iter().zip(expected) {
            assert!(
                (s.0 - e.0).abs() < 1e-12 && (s.1 - e.1).abs() < 1e-12,
                "{seen:?}"
            );
            assert_eq!((s.2, s.3), (e.2, e.3));
        }
        let mut down = Vec::new();
        h.segment_leaves([3.0, 0.0, 20.0], [3.0, 0.0, 0.0], |t0, t1, c, _| {
            down.push((t0, t1, c))
        });
        assert_eq!(
            down,
            vec![(0.0, 0.5, contents::SKY), (0.5, 1.0, contents::EMPTY)]
        );
    }
}
