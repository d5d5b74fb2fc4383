//! The world description — boxes of free space, solid boxes, ramps, sky and
//! water — and the exact answers tests compare a compiled map against.
//!
//! ## Contents rule
//! A point `p` is
//! 1. SOLID if it lies in the open interior of a solid box or of a ramp wedge;
//! 2. otherwise WATER if it lies in a (closed) free box and a (closed) water
//!    box, EMPTY if it lies in a free box only;
//! 3. otherwise SKY if it lies in a (closed) sky box;
//! 4. otherwise SOLID (everything outside is solid).
//!
//! Free space is EMPTY ∪ WATER; obstacles are SOLID ∪ SKY. On the boundary
//! between two contents the answer follows these open/closed conventions, but
//! a compiled BSP (with `f32` planes) may answer either way there: tests should
//! skip points with [`World::distance_to_boundary`] below `1e-3`.

use std::sync::OnceLock;

use serde::{Deserialize, Serialize};

use crate::geometry::{
    ConvexCell, Plane, V3, point_polygon_distance, polygon_area, segment_polygon_distance,
};

/// Point contents, with the GoldSrc values of [`Contents::bsp_value`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Contents {
    Empty,
    Solid,
    Water,
    Sky,
}

impl Contents {
    /// The value stored in BSP leaves and clipnodes (EMPTY −1, SOLID −2,
    /// WATER −3, SKY −6).
    pub fn bsp_value(self) -> i32 {
        match self {
            Contents::Empty => -1,
            Contents::Solid => -2,
            Contents::Water => -3,
            Contents::Sky => -6,
        }
    }
    /// Free space for the VDG: EMPTY and WATER.
    pub fn is_free(self) -> bool {
        matches!(self, Contents::Empty | Contents::Water)
    }
}

/// Half extents of the GoldSrc collision hulls: 0 point, 1 standing player
/// (±16, ±16, ±36), 2 large monster (±32), 3 crouching player (±16, ±16, ±18).
pub const HULL_HALF_EXTENTS: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [16.0, 16.0, 36.0],
    [32.0, 32.0, 32.0],
    [16.0, 16.0, 18.0],
];

/// Whose player boxes a map's clip hulls are built for: GoldSrc's (symmetric, the
/// standing player ±36 high) or Quake's (the player 24 below and 32 above its
/// origin, hull 2 24 below and 64 above). Half-Life's oldest maps are BSP29 files
/// with GoldSrc hulls, which is how a reader tells them from Quake's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HullSet {
    GoldSrc,
    Quake,
}

/// A hull's box around its origin: the centre offset and the half extents.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullShape {
    pub center: [f64; 3],
    pub half: [f64; 3],
}

impl HullSet {
    /// The box of hull `hull` (0..=3). Quake has no crouching hull; its hull 3 is
    /// written as its hull 1.
    pub fn shape(self, hull: usize) -> HullShape {
        match (self, hull) {
            (HullSet::GoldSrc, h) | (HullSet::Quake, h @ 0) => HullShape {
                center: [0.0; 3],
                half: HULL_HALF_EXTENTS[h],
            },
            (HullSet::Quake, 2) => HullShape {
                center: [0.0, 0.0, 20.0],
                half: [32.0, 32.0, 44.0],
            },
            (HullSet::Quake, _) => HullShape {
                center: [0.0, 0.0, 4.0],
                half: [16.0, 16.0, 28.0],
            },
        }
    }
}

/// An axis-aligned box `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    pub min: [f64; 3],
    pub max: [f64; 3],
}

impl Aabb {
    /// The box between two corners (`min < max` on every axis).
    pub const fn new(min: [f64; 3], max: [f64; 3]) -> Self {
        Aabb { min, max }
    }
    pub(crate) fn lo(&self) -> V3 {
        self.min.into()
    }
    pub(crate) fn hi(&self) -> V3 {
        self.max.into()
    }
    /// Closed containment.
    pub fn contains(&self, p: [f64; 3]) -> bool {
        (0..3).all(|i| self.min[i] <= p[i] && p[i] <= self.max[i])
    }
    /// Containment in the open interior.
    pub fn contains_open(&self, p: [f64; 3]) -> bool {
        (0..3).all(|i| self.min[i] < p[i] && p[i] < self.max[i])
    }
    /// The box grown by `h` on each side.
    pub fn expanded(&self, h: [f64; 3]) -> Aabb {
        Aabb {
            min: [self.min[0] - h[0], self.min[1] - h[1], self.min[2] - h[2]],
            max: [self.max[0] + h[0], self.max[1] + h[1], self.max[2] + h[2]],
        }
    }
    /// Smallest box holding both.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: (self.lo().min(o.lo())).into(),
            max: (self.hi().max(o.hi())).into(),
        }
    }
    /// Whether the open interiors intersect.
    fn overlaps_open(&self, o: &Aabb) -> bool {
        (0..3).all(|i| self.min[i] < o.max[i] && o.min[i] < self.max[i])
    }
    /// Distance from `p` to the box's surface (inside or outside).
    fn surface_distance(&self, p: [f64; 3]) -> f64 {
        if self.contains(p) {
            (0..3)
                .map(|i| (p[i] - self.min[i]).min(self.max[i] - p[i]))
                .fold(f64::INFINITY, f64::min)
        } else {
            let d: V3 = (self.lo() - V3::from(p))
                .max(V3::from(p) - self.hi())
                .max(V3::ZERO);
            d.length()
        }
    }
    /// The parameter interval `t` with `a + t d` in the box (closed or open).
    fn segment_interval(&self, a: V3, d: V3, open: bool) -> Option<(f64, f64)> {
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for i in 0..3 {
            let (lo, hi, ai, di) = (self.min[i], self.max[i], a.get(i), d.get(i));
            if di == 0.0 {
                let inside = if open {
                    lo < ai && ai < hi
                } else {
                    lo <= ai && ai <= hi
                };
                if !inside {
                    return None;
                }
            } else {
                let (u, v) = ((lo - ai) / di, (hi - ai) / di);
                t0 = t0.max(u.min(v));
                t1 = t1.min(u.max(v));
            }
        }
        let nonempty = if open { t0 < t1 } else { t0 <= t1 };
        nonempty.then_some((t0, t1))
    }
    /// `self` minus `o`, as boxes of positive volume.
    fn minus(&self, o: &Aabb) -> Vec<Aabb> {
        if !self.overlaps_open(o) {
            return vec![*self];
        }
        let mut rest = *self;
        let mut out = Vec::new();
        for i in 0..3 {
            if rest.min[i] < o.min[i] {
                let mut piece = rest;
                piece.max[i] = o.min[i];
                out.push(piece);
                rest.min[i] = o.min[i];
            }
            if rest.max[i] > o.max[i] {
                let mut piece = rest;
                piece.min[i] = o.max[i];
                out.push(piece);
                rest.max[i] = o.max[i];
            }
        }
        out
    }
}

/// Which way a floor ramp climbs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rise {
    PlusX,
    MinusX,
    PlusY,
    MinusY,
}

/// A solid wedge: the box `bounds` intersected with the half-space
/// `normal · p <= dist` (`normal` is a unit vector pointing into free space and
/// is not axial). Used for ramps and slanted walls.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ramp {
    pub bounds: Aabb,
    pub normal: [f64; 3],
    pub dist: f64,
}

impl Ramp {
    /// The wedge of `bounds` behind the plane through `point` with normal
    /// `normal` (any length; it points out of the solid).
    pub fn new(bounds: Aabb, normal: [f64; 3], point: [f64; 3]) -> Self {
        let p = Plane::through(normal.into(), point.into());
        Ramp {
            bounds,
            normal: p.normal.into(),
            dist: p.dist,
        }
    }

    /// A floor ramp filling `bounds` below the diagonal that climbs from
    /// `bounds.min.z` at one end to `bounds.max.z` at the other.
    ///
    /// ```
    /// use mapgen::world::{Aabb, Ramp, Rise};
    /// let r = Ramp::rising(Aabb::new([0.0, 0.0, 0.0], [256.0, 128.0, 128.0]), Rise::PlusX);
    /// assert!(r.contains_open([200.0, 64.0, 10.0]));
    /// assert!(!r.contains_open([20.0, 64.0, 100.0]));
    /// ```
    pub fn rising(bounds: Aabb, rise: Rise) -> Self {
        let [x0, y0, z0] = bounds.min;
        let [x1, y1, z1] = bounds.max;
        let h = z1 - z0;
        let (normal, point) = match rise {
            Rise::PlusX => ([-h, 0.0, x1 - x0], [x0, y0, z0]),
            Rise::MinusX => ([h, 0.0, x1 - x0], [x1, y0, z0]),
            Rise::PlusY => ([0.0, -h, y1 - y0], [x0, y0, z0]),
            Rise::MinusY => ([0.0, h, y1 - y0], [x0, y1, z0]),
        };
        Ramp::new(bounds, normal, point)
    }

    /// The slanted plane (normal out of the solid).
    pub fn plane(&self) -> Plane {
        Plane {
            normal: self.normal.into(),
            dist: self.dist,
        }
    }

    /// Containment in the open interior of the wedge.
    pub fn contains_open(&self, p: [f64; 3]) -> bool {
        self.bounds.contains_open(p) && self.plane().distance(p.into()) < 0.0
    }

    /// The wedge as a convex cell (None if the plane misses the box).
    pub(crate) fn cell(&self) -> Option<ConvexCell> {
        ConvexCell::from_halfspaces(self.bounds.lo(), self.bounds.hi(), &[self.plane()])
    }
}

/// A brush entity (its own BSP model `*N`, not part of the world's contents),
/// e.g. a `trigger_once` drawn with `aaatrigger`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BrushEntity {
    pub classname: String,
    pub bounds: Aabb,
    pub texture: String,
}

/// What a wall polygon is, by the obstacle behind it and its facing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SurfaceClass {
    /// Solid, facing mostly sideways.
    Wall,
    /// Solid, facing up (normal z > 0.7).
    Floor,
    /// Solid, facing down (normal z < −0.7).
    Ceiling,
    /// A SKY boundary.
    Sky,
}

impl SurfaceClass {
    /// Classifies a boundary by the obstacle contents and the facing normal.
    pub fn of(obstacle: Contents, facing: [f64; 3]) -> Self {
        if obstacle == Contents::Sky {
            SurfaceClass::Sky
        } else if facing[2] > 0.7 {
            SurfaceClass::Floor
        } else if facing[2] < -0.7 {
            SurfaceClass::Ceiling
        } else {
            SurfaceClass::Wall
        }
    }
    /// The texture name the BSP writer gives this class.
    pub fn texture(self) -> &'static str {
        match self {
            SurfaceClass::Wall => "wall",
            SurfaceClass::Floor => "floor",
            SurfaceClass::Ceiling => "ceiling",
            SurfaceClass::Sky => "sky",
        }
    }
}

/// A convex piece of the exact boundary of free space.
#[derive(Clone, Debug, PartialEq)]
pub struct WallPolygon {
    /// Vertices, counter-clockwise seen from free space.
    pub vertices: Vec<[f64; 3]>,
    /// Unit normal pointing into free space.
    pub normal: [f64; 3],
    pub class: SurfaceClass,
}

impl WallPolygon {
    /// Area of the polygon.
    pub fn area(&self) -> f64 {
        let v: Vec<V3> = self.vertices.iter().map(|&p| p.into()).collect();
        polygon_area(&v)
    }
}

/// A problem with a world description.
#[derive(Clone, Debug, PartialEq)]
pub enum WorldError {
    /// A box with `min >= max` on some axis.
    EmptyBox(String),
    /// A coordinate outside ±4000 (GoldSrc maps must fit in ±4096).
    OutOfRange(String),
    /// A ramp whose plane is axial or misses its box.
    BadRamp(usize),
    /// A spawn point not in free space for a standing player.
    BadSpawn(usize),
}

impl std::fmt::Display for WorldError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            WorldError::EmptyBox(w) => write!(f, "empty box: {w}"),
            WorldError::OutOfRange(w) => write!(f, "coordinate out of range ±4000: {w}"),
            WorldError::BadRamp(i) => write!(f, "ramp {i}: plane is axial or misses its box"),
            WorldError::BadSpawn(i) => {
                write!(f, "spawn point {i} is not free for a standing player")
            }
        }
    }
}

impl std::error::Error for WorldError {}

/// A world: union of free boxes, minus solid boxes and ramps, with sky and
/// water boxes (see the module docs for the exact contents rule).
///
/// ```
/// use mapgen::world::{Aabb, Contents, World};
/// let mut w = World::new("demo", "one box room");
/// w.free.push(Aabb::new([0.0, 0.0, 0.0], [512.0, 384.0, 256.0]));
/// assert_eq!(w.contents([10.0, 10.0, 10.0]), Contents::Empty);
/// assert_eq!(w.contents([-10.0, 10.0, 10.0]), Contents::Solid);
/// assert!((w.clearance([10.0, 20.0, 30.0]) - 10.0).abs() < 1e-12);
/// assert!(w.segment_free([10.0, 10.0, 10.0], [500.0, 370.0, 250.0]));
/// ```
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct World {
    pub name: String,
    pub description: String,
    /// Boxes of free space (rooms, corridors, door openings).
    pub free: Vec<Aabb>,
    /// Solid boxes cut out of free space (pillars, steps).
    pub solids: Vec<Aabb>,
    /// Solid wedges (ramps, slanted walls).
    pub ramps: Vec<Ramp>,
    /// SKY boxes; they only matter outside the free boxes.
    pub sky: Vec<Aabb>,
    /// WATER boxes; they only matter inside the free boxes.
    pub water: Vec<Aabb>,
    /// Player origins (hull 1 centres) for `info_player_*` entities.
    pub spawns: Vec<[f64; 3]>,
    /// Brush entities (separate BSP models, not part of the contents).
    pub brush_entities: Vec<BrushEntity>,
    #[serde(skip)]
    walls: OnceLock<Vec<WallPolygon>>,
    #[serde(skip)]
    ramp_cells: OnceLock<Vec<ConvexCell>>,
    #[serde(skip)]
    grown_ramps: OnceLock<Vec<Vec<ConvexCell>>>,
}

impl World {
    /// An empty (all solid) world.
    pub fn new(name: &str, description: &str) -> Self {
        World {
            name: name.to_string(),
            description: description.to_string(),
            ..Default::default()
        }
    }

    /// Point contents (see the module docs for the rule).
    ///
    /// ```
    /// # use mapgen::world::{Aabb, Contents, World};
    /// let mut w = World::new("d", "");
    /// w.free.push(Aabb::new([0.0; 3], [64.0; 3]));
    /// w.sky.push(Aabb::new([0.0, 0.0, 64.0], [64.0, 64.0, 80.0]));
    /// assert_eq!(w.contents([32.0, 32.0, 70.0]), Contents::Sky);
    /// ```
    pub fn contents(&self, p: [f64; 3]) -> Contents {
        if self.solids.iter().any(|b| b.contains_open(p))
            || self.ramps.iter().any(|r| r.contains_open(p))
        {
            Contents::Solid
        } else if self.free.iter().any(|b| b.contains(p)) {
            if self.water.iter().any(|b| b.contains(p)) {
                Contents::Water
            } else {
                Contents::Empty
            }
        } else if self.sky.iter().any(|b| b.contains(p)) {
            Contents::Sky
        } else {
            Contents::Solid
        }
    }

    /// Whether `p` is free (EMPTY or WATER).
    pub fn is_free(&self, p: [f64; 3]) -> bool {
        self.contents(p).is_free()
    }

    /// Contents of clip hull `hull` (0–3, see [`HULL_HALF_EXTENTS`]) at `p`:
    /// EMPTY if the hull box centred at `p` lies in free space, else SOLID.
    /// Water counts as empty and sky as solid, as in GoldSrc clip hulls.
    ///
    /// ```
    /// # use mapgen::world::{Aabb, Contents, World};
    /// let mut w = World::new("d", "");
    /// w.free.push(Aabb::new([0.0; 3], [512.0, 512.0, 256.0]));
    /// assert_eq!(w.hull_contents(1, [100.0, 100.0, 37.0]), Contents::Empty);
    /// assert_eq!(w.hull_contents(1, [100.0, 100.0, 35.0]), Contents::Solid);
    /// ```
    pub fn hull_contents(&self, hull: usize, p: [f64; 3]) -> Contents {
        self.shaped_contents(HullSet::GoldSrc.shape(hull), p)
    }

    /// Contents of a hull of box `shape` at `p` (see [`World::hull_contents`]).
    pub fn shaped_contents(&self, shape: HullShape, p: [f64; 3]) -> Contents {
        let c = [0, 1, 2].map(|i| p[i] + shape.center[i]);
        let q = Aabb::new(c, c).expanded(shape.half);
        let hits_solid = self.solids.iter().any(|s| q.overlaps_open(s))
            || self.ramps.iter().any(|r| {
                if !q.overlaps_open(&r.bounds) {
                    return false;
                }
                let lo = q.lo().max(r.bounds.lo());
                let hi = q.hi().min(r.bounds.hi());
                let n = V3::from(r.normal);
                let lowest: f64 = (0..3)
                    .map(|i| n.get(i) * if n.get(i) > 0.0 { lo.get(i) } else { hi.get(i) })
                    .sum();
                lowest < r.dist
            });
        if hits_solid || !self.box_in_free_boxes(q) {
            Contents::Solid
        } else {
            Contents::Empty
        }
    }

    /// Whether the closed box `q` is covered by the union of the free boxes.
    fn box_in_free_boxes(&self, q: Aabb) -> bool {
        let mut rest = vec![q];
        for f in &self.free {
            rest = rest.iter().flat_map(|r| r.minus(f)).collect();
            if rest.is_empty() {
                return true;
            }
        }
        // Zero-volume leftovers cannot occur: pieces always have volume.
        rest.is_empty()
    }

    /// Whether the whole closed segment `a`–`b` lies in free space (exact
    /// interval clipping against every box and wedge).
    ///
    /// ```
    /// # use mapgen::world::{Aabb, World};
    /// let mut w = World::new("d", "");
    /// w.free.push(Aabb::new([0.0; 3], [512.0, 512.0, 256.0]));
    /// w.solids.push(Aabb::new([200.0, 200.0, 0.0], [300.0, 300.0, 256.0]));
    /// assert!(!w.segment_free([100.0, 250.0, 50.0], [400.0, 250.0, 50.0]));
    /// assert!(w.segment_free([100.0, 100.0, 50.0], [400.0, 100.0, 50.0]));
    /// ```
    pub fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        match self.free_intervals(a, b).as_slice() {
            [(t0, t1)] => *t0 <= 0.0 && *t1 >= 1.0,
            _ => false,
        }
    }

    /// The parameters `t` in `[0, 1]` where `a + t (b − a)` is free, as
    /// sorted disjoint closed intervals (clipped to `[0, 1]`).
    fn free_intervals(&self, a: [f64; 3], b: [f64; 3]) -> Vec<(f64, f64)> {
        let (a, d) = (V3::from(a), V3::from(b) - V3::from(a));
        let mut cover: Vec<(f64, f64)> = self
            .free
            .iter()
            .filter_map(|f| f.segment_interval(a, d, false))
            .filter(|&(t0, t1)| t0 <= 1.0 && t1 >= 0.0)
            .collect();
        cover.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut free: Vec<(f64, f64)> = Vec::new();
        for (t0, t1) in cover {
            match free.last_mut() {
                Some(last) if t0 <= last.1 => last.1 = last.1.max(t1),
                _ => free.push((t0, t1)),
            }
        }
        let obstacles = self
            .solids
            .iter()
            .map(|s| s.segment_interval(a, d, true))
            .chain(self.ramps.iter().map(|r| {
                r.bounds.segment_interval(a, d, true).and_then(|(t0, t1)| {
                    let n = V3::from(r.normal);
                    let (g0, gd) = (n.dot(a) - r.dist, n.dot(d));
                    let (mut t0, mut t1) = (t0, t1);
                    if gd == 0.0 {
                        if g0 >= 0.0 {
                            return None;
                        }
                    } else if gd > 0.0 {
                        t1 = t1.min(-g0 / gd);
                    } else {
                        t0 = t0.max(-g0 / gd);
                    }
                    (t0 < t1).then_some((t0, t1))
                })
            }));
        for (o0, o1) in obstacles.flatten() {
            free = free
                .into_iter()
                .flat_map(|(s, e)| {
                    let below = (s <= e.min(o0)).then_some((s, e.min(o0)));
                    let above = (s.max(o1) <= e).then_some((s.max(o1), e));
                    below.into_iter().chain(above)
                })
                .collect();
        }
        free.into_iter()
            .map(|(s, e)| (s.max(0.0), e.min(1.0)))
            .filter(|(s, e)| s <= e)
            .collect()
    }

    /// How far the answer of [`segment_free`](Self::segment_free) is from
    /// flipping: for a free segment its exact distance to the nearest wall
    /// polygon; for a blocked one the depth (distance to free space) of the
    /// deepest midpoint of its blocked stretches. Any segment within this
    /// distance of `a`–`b` gets the same answer, so tests comparing against a
    /// BSP trace should skip segments where it is below `1e-3`.
    ///
    /// ```
    /// let w = mapgen::worlds::box_room();
    /// // 10 units above the floor, far from the other walls.
    /// let m = w.segment_margin([100.0, 150.0, 10.0], [300.0, 150.0, 10.0]);
    /// assert!((m - 10.0).abs() < 1e-9);
    /// // Through the wall at x = 512, up to 20 units deep.
    /// assert!(w.segment_margin([400.0, 150.0, 100.0], [550.0, 150.0, 100.0]) > 1.0);
    /// ```
    pub fn segment_margin(&self, a: [f64; 3], b: [f64; 3]) -> f64 {
        let (va, vb) = (V3::from(a), V3::from(b));
        let free = self.free_intervals(a, b);
        if matches!(free.as_slice(), [(t0, t1)] if *t0 <= 0.0 && *t1 >= 1.0) {
            return self
                .wall_polygons()
                .iter()
                .map(|w| {
                    let v: Vec<V3> = w.vertices.iter().map(|&x| x.into()).collect();
                    segment_polygon_distance(va, vb, &v, w.normal.into())
                })
                .fold(f64::INFINITY, f64::min);
        }
        let mut gaps = Vec::new();
        let mut from = 0.0;
        for &(s, e) in &free {
            if s > from {
                gaps.push((from, s));
            }
            from = e;
        }
        if from < 1.0 {
            gaps.push((from, 1.0));
        }
        gaps.iter()
            .map(|&(s, e)| self.wall_distance(va + (vb - va) * (0.5 * (s + e))))
            .fold(0.0, f64::max)
    }

    /// The exact Euclidean distance from `p` to the nearest obstacle (SOLID
    /// or SKY), i.e. to the nearest [`wall polygon`](Self::wall_polygons);
    /// 0 if `p` is not free.
    ///
    /// ```
    /// let w = mapgen::worlds::box_room(); // [0,512]x[0,384]x[0,256]
    /// assert!((w.clearance([256.0, 100.0, 128.0]) - 100.0).abs() < 1e-9);
    /// ```
    pub fn clearance(&self, p: [f64; 3]) -> f64 {
        if !self.is_free(p) {
            return 0.0;
        }
        self.wall_distance(p.into())
    }

    /// Distance from any point to the nearest wall polygon.
    fn wall_distance(&self, q: V3) -> f64 {
        let mut best = f64::INFINITY;
        for w in self.wall_polygons() {
            let lo = w
                .vertices
                .iter()
                .fold(V3::from(w.vertices[0]), |m, &v| m.min(v.into()));
            let hi = w
                .vertices
                .iter()
                .fold(V3::from(w.vertices[0]), |m, &v| m.max(v.into()));
            let gap = (lo - q).max(q - hi).max(V3::ZERO).length();
            if gap >= best {
                continue;
            }
            let verts: Vec<V3> = w.vertices.iter().map(|&v| v.into()).collect();
            best = best.min(point_polygon_distance(q, &verts, w.normal.into()));
        }
        best
    }

    /// Distance from `p` to the nearest surface of any primitive (box or
    /// wedge): a lower bound of the distance to any change of contents. Tests
    /// should skip points where it is below `1e-3`.
    ///
    /// ```
    /// let w = mapgen::worlds::box_room();
    /// assert!((w.distance_to_boundary([0.5, 100.0, 100.0]) - 0.5).abs() < 1e-12);
    /// assert!((w.distance_to_boundary([-2.0, 100.0, 100.0]) - 2.0).abs() < 1e-12);
    /// ```
    pub fn distance_to_boundary(&self, p: [f64; 3]) -> f64 {
        let boxes = self
            .free
            .iter()
            .chain(&self.solids)
            .chain(&self.sky)
            .chain(&self.water)
            .map(|b| b.surface_distance(p));
        let cells = self.ramp_cells.get_or_init(|| {
            self.ramps
                .iter()
                .map(|r| r.cell().expect("validated ramp"))
                .collect()
        });
        let wedges = cells.iter().flat_map(|c| {
            c.faces
                .iter()
                .map(|f| point_polygon_distance(p.into(), &f.polygon, f.plane.normal))
        });
        boxes.chain(wedges).fold(f64::INFINITY, f64::min)
    }

    /// A lower bound of the distance from `p` to a change of
    /// [`hull_contents`](Self::hull_contents) for `hull`: the hull box's faces
    /// are farther than this from every box face coordinate, and `p` from
    /// every face of the ramps grown by the hull. Tests comparing clip hulls
    /// should skip points where it is below `1e-3`.
    ///
    /// ```
    /// let w = mapgen::worlds::box_room();
    /// // The standing hull's bottom is 1 unit above the floor.
    /// assert!((w.hull_distance_to_boundary(1, [200.0, 200.0, 37.0]) - 1.0).abs() < 1e-12);
    /// ```
    pub fn hull_distance_to_boundary(&self, hull: usize, p: [f64; 3]) -> f64 {
        let h = HULL_HALF_EXTENTS[hull];
        let mut best = f64::INFINITY;
        for b in self.free.iter().chain(&self.solids) {
            for i in 0..3 {
                for c in [b.min[i], b.max[i]] {
                    best = best
                        .min((p[i] + h[i] - c).abs())
                        .min((p[i] - h[i] - c).abs());
                }
            }
        }
        let grown = self.grown_ramps.get_or_init(|| {
            let big = V3::new(8192.0, 8192.0, 8192.0);
            HULL_HALF_EXTENTS
                .iter()
                .map(|&h| {
                    self.ramps
                        .iter()
                        .filter_map(|r| crate::tree::expand_cell(&r.cell()?, h.into(), -big, big))
                        .collect()
                })
                .collect()
        });
        for c in &grown[hull] {
            for f in &c.faces {
                best = best.min(point_polygon_distance(p.into(), &f.polygon, f.plane.normal));
            }
        }
        best
    }

    /// The exact boundary of free space as convex polygons facing into it
    /// (computed once from the world's BSP tree, then cached).
    ///
    /// ```
    /// use mapgen::SurfaceClass;
    /// let w = mapgen::worlds::sky_room();
    /// let sky: f64 = w.wall_polygons().iter()
    ///     .filter(|p| p.class == SurfaceClass::Sky)
    ///     .map(|p| p.area())
    ///     .sum();
    /// assert!((sky - 512.0 * 512.0).abs() < 1e-6); // the courtyard's open ceiling
    /// ```
    pub fn wall_polygons(&self) -> &[WallPolygon] {
        self.walls.get_or_init(|| crate::tree::wall_polygons(self))
    }

    /// The player spawn origins.
    ///
    /// ```
    /// let w = mapgen::worlds::complex();
    /// assert!(w.spawn_points().iter().all(|&p| w.hull_contents(1, p) == mapgen::Contents::Empty));
    /// ```
    pub fn spawn_points(&self) -> &[[f64; 3]] {
        &self.spawns
    }

    /// Bounding box of every primitive (free, solid, ramp, sky, water).
    pub fn bounds(&self) -> Aabb {
        self.free
            .iter()
            .chain(&self.solids)
            .chain(&self.sky)
            .chain(&self.water)
            .chain(self.ramps.iter().map(|r| &r.bounds))
            .fold(None, |acc: Option<Aabb>, b| {
                Some(acc.map_or(*b, |a| a.union(b)))
            })
            .unwrap_or(Aabb::new([0.0; 3], [0.0; 3]))
    }

    /// Bounding box of the free boxes.
    pub fn free_bounds(&self) -> Aabb {
        self.free
            .iter()
            .fold(None, |acc: Option<Aabb>, b| {
                Some(acc.map_or(*b, |a| a.union(b)))
            })
            .unwrap_or(Aabb::new([0.0; 3], [0.0; 3]))
    }

    /// Checks the description: non-empty boxes, coordinates within ±4000,
    /// slanted ramp planes that cut their box, spawns free for hull 1.
    pub fn validate(&self) -> Result<(), WorldError> {
        let named = |kind: &str, i: usize| format!("{kind} {i}");
        let groups = [
            ("free", &self.free),
            ("solid", &self.solids),
            ("sky", &self.sky),
            ("water", &self.water),
        ];
        let ramp_boxes: Vec<Aabb> = self.ramps.iter().map(|r| r.bounds).collect();
        let brush_boxes: Vec<Aabb> = self.brush_entities.iter().map(|b| b.bounds).collect();
        for (kind, list) in groups
            .into_iter()
            .chain([("ramp", &ramp_boxes), ("brush", &brush_boxes)])
        {
            for (i, b) in list.iter().enumerate() {
                if (0..3).any(|k| b.min[k] >= b.max[k]) {
                    return Err(WorldError::EmptyBox(named(kind, i)));
                }
                if (0..3).any(|k| b.min[k] < -4000.0 || b.max[k] > 4000.0) {
                    return Err(WorldError::OutOfRange(named(kind, i)));
                }
            }
        }
        for (i, r) in self.ramps.iter().enumerate() {
            let cut = r.cell().is_some_and(|c| {
                let full = ConvexCell::from_box(r.bounds.lo(), r.bounds.hi());
                c.faces.len() != full.faces.len() || c.bounds() != full.bounds()
            });
            if r.plane().axial().is_some() || !cut {
                return Err(WorldError::BadRamp(i));
            }
        }
        for (i, &s) in self.spawns.iter().enumerate() {
            if self.hull_contents(1, s) != Contents::Empty {
                return Err(WorldError::BadSpawn(i));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn room() -> World {
        let mut w = World::new("t", "");
        w.free.push(Aabb::new([0.0; 3], [512.0, 384.0, 256.0]));
        w
    }

    #[test]
    fn hull_box_fits_across_overlapping_boxes() {
        // A door box between two boxes: a hull straddling room and door fits.
        let mut w = World::new("t", "");
        w.free
            .push(Aabb::new([0.0, 0.0, 0.0], [512.0, 512.0, 256.0]));
        w.free
            .push(Aabb::new([500.0, 200.0, 0.0], [540.0, 300.0, 128.0]));
        w.free
            .push(Aabb::new([528.0, 0.0, 0.0], [800.0, 512.0, 256.0]));
        assert_eq!(w.hull_contents(1, [510.0, 250.0, 40.0]), Contents::Empty);
        assert_eq!(w.hull_contents(1, [510.0, 190.0, 40.0]), Contents::Solid);
        assert_eq!(w.hull_contents(1, [520.0, 250.0, 100.0]), Contents::Solid);
    }

    #[test]
    fn clearance_in_a_box_is_distance_to_nearest_wall() {
        let w = room();
        for p in [
            [10.0f64, 200.0, 100.0],
            [256.0, 192.0, 128.0],
            [500.0, 5.0, 250.0],
        ] {
            let exact = (0..3)
                .map(|i| p[i].min([512.0, 384.0, 256.0][i] - p[i]))
                .fold(f64::INFINITY, f64::min);
            assert!((w.clearance(p) - exact).abs() < 1e-9, "{p:?}");
        }
        assert_eq!(w.clearance([-5.0, 1.0, 1.0]), 0.0);
    }

    #[test]
    fn segment_along_a_door_is_free_and_through_a_wall_is_not() {
        let mut w = room();
        w.free
            .push(Aabb::new([512.0, 100.0, 0.0], [800.0, 200.0, 128.0]));
        assert!(w.segment_free([100.0, 150.0, 50.0], [700.0, 150.0, 50.0]));
        assert!(w.segment_free([100.0, 250.0, 50.0], [700.0, 150.0, 50.0]));
        assert!(!w.segment_free([100.0, 380.0, 50.0], [700.0, 150.0, 50.0]));
        assert!(!w.segment_free([300.0, 150.0, 250.0], [700.0, 150.0, 50.0]));
        assert!(w.segment_free([1.0, 2.0, 3.0], [1.0, 2.0, 3.0]));
    }

    #[test]
    fn ramp_blocks_segments_below_its_slope() {
        let mut w = room();
        w.ramps.push(Ramp::rising(
            Aabb::new([128.0, 0.0, 0.0], [384.0, 128.0, 128.0]),
            Rise::PlusX,
        ));
        assert!(w.validate().is_ok());
        assert_eq!(w.contents([380.0, 64.0, 100.0]), Contents::Solid);
        assert_eq!(w.contents([140.0, 64.0, 100.0]), Contents::Empty);
        assert!(!w.segment_free([100.0, 64.0, 60.0], [450.0, 64.0, 60.0]));
        assert!(w.segment_free([100.0, 64.0, 140.0], [450.0, 64.0, 140.0]));
    }

    /// Points on a polygon spaced at most `step` apart along a triangle grid.
    fn polygon_samples(poly: &WallPolygon, step: f64) -> Vec<V3> {
        let v: Vec<V3> = poly.vertices.iter().map(|&p| p.into()).collect();
        let mut out = Vec::new();
        for i in 1..v.len() - 1 {
            let (a, b, c) = (v[0], v[i], v[i + 1]);
            let longest = (b - a).length().max((c - a).length()).max((c - b).length());
            let n = (longest / step).ceil().max(1.0) as usize;
            for s in 0..=n {
                for t in 0..=(n - s) {
                    let (s, t) = (s as f64 / n as f64, t as f64 / n as f64);
                    out.push(a + (b - a) * s + (c - a) * t);
                }
            }
        }
        out
    }

    #[test]
    fn clearance_matches_brute_force_over_wall_samples() {
        use crate::testutil::{Rng, standard};
        let step = 4.0;
        for (w, _) in standard() {
            let samples: Vec<V3> = w
                .wall_polygons()
                .iter()
                .flat_map(|p| polygon_samples(p, step))
                .collect();
            let mut rng = Rng::new(4);
            let mut tested = 0;
            while tested < 8 {
                let p = rng.point_in(&w.free_bounds(), 0.0);
                if !w.is_free(p) || w.distance_to_boundary(p) < 1e-3 {
                    continue;
                }
                tested += 1;
                let q = V3::from(p);
                let brute = samples
                    .iter()
                    .map(|&s| (s - q).length())
                    .fold(f64::MAX, f64::min);
                let c = w.clearance(p);
                // Samples lie on the polygons (brute >= exact) and cover them
                // within one grid step (brute <= exact + step).
                assert!(
                    c <= brute + 1e-9 && brute <= c + step,
                    "{} {p:?}: {c} vs {brute}",
                    w.name
                );
            }
        }
    }

    #[test]
    fn clearance_ball_is_free_and_touches_an_obstacle() {
        use crate::testutil::{Rng, standard};
        for (w, _) in standard() {
            let mut rng = Rng::new(5);
            let mut tested = 0;
            while tested < 40 {
                let p = rng.point_in(&w.free_bounds(), 0.0);
                if !w.is_free(p) || w.distance_to_boundary(p) < 1e-3 {
                    continue;
                }
                tested += 1;
                let c = w.clearance(p);
                assert!(c > 0.0 && c.is_finite());
                for _ in 0..200 {
                    let d = V3::from(rng.direction());
                    let q = (V3::from(p) + d * (0.999 * c)).into();
                    assert!(w.segment_free(p, q), "{} {p:?} r={c}", w.name);
                }
                // Some point just beyond the clearance is an obstacle: the
                // nearest wall polygon's nearest point, pushed through it.
                let near = w
                    .wall_polygons()
                    .iter()
                    .map(|wp| {
                        let v: Vec<V3> = wp.vertices.iter().map(|&x| x.into()).collect();
                        (point_polygon_distance(p.into(), &v, wp.normal.into()), wp)
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .unwrap();
                assert!((near.0 - c).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn segment_free_matches_dense_sampling() {
        use crate::testutil::{Rng, standard};
        for (w, _) in standard() {
            let mut rng = Rng::new(6);
            let (mut free, mut blocked, mut grazing) = (0, 0, 0);
            for _ in 0..1500 {
                let a = rng.point_in(&w.free_bounds(), 0.0);
                let b = if rng.unit() < 0.5 {
                    // Short segments from a free point: mostly free.
                    let d = rng.direction();
                    let len = 300.0 * rng.unit();
                    [a[0] + d[0] * len, a[1] + d[1] * len, a[2] + d[2] * len]
                } else {
                    rng.point_in(&w.free_bounds(), 0.0)
                };
                let (va, vb) = (V3::from(a), V3::from(b));
                let n = ((vb - va).length() / 0.25).ceil() as usize + 1;
                let mut any_blocked = false;
                let mut clear_blocked = false;
                for i in 0..=n {
                    let q: [f64; 3] = (va + (vb - va) * (i as f64 / n as f64)).into();
                    if !w.is_free(q) {
                        any_blocked = true;
                        clear_blocked |= w.distance_to_boundary(q) > 1e-3;
                    }
                }
                if w.segment_free(a, b) {
                    free += 1;
                    assert!(
                        !clear_blocked,
                        "{}: {a:?}-{b:?} free but crosses solid",
                        w.name
                    );
                } else {
                    blocked += 1;
                    grazing += usize::from(!any_blocked);
                }
            }
            assert!(
                free > 100 && blocked > 100,
                "{}: {free} free, {blocked} blocked",
                w.name
            );
            // Blocked segments the samples miss must be rare grazing cases.
            assert!(
                grazing * 200 <= blocked,
                "{}: {grazing} of {blocked} unseen",
                w.name
            );
        }
    }

    fn offset(p: [f64; 3], d: [f64; 3], r: f64) -> [f64; 3] {
        [p[0] + d[0] * r, p[1] + d[1] * r, p[2] + d[2] * r]
    }

    #[test]
    fn boundary_distances_are_sound() {
        use crate::testutil::{Rng, standard};
        for (w, _) in standard() {
            let mut rng = Rng::new(8);
            for _ in 0..3000 {
                let p = rng.point_in(&w.bounds(), 16.0);
                let m = w.distance_to_boundary(p).min(2.0);
                for _ in 0..4 {
                    let q = offset(p, rng.direction(), 0.99 * m * rng.unit());
                    assert_eq!(w.contents(q), w.contents(p), "{} {p:?} m={m}", w.name);
                }
                for hull in 1..=3 {
                    let m = w.hull_distance_to_boundary(hull, p).min(2.0);
                    for _ in 0..4 {
                        let q = offset(p, rng.direction(), 0.99 * m * rng.unit());
                        assert_eq!(
                            w.hull_contents(hull, q),
                            w.hull_contents(hull, p),
                            "{}",
                            w.name
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn segment_margin_is_exact_for_free_and_sound_for_blocked_segments() {
        use crate::testutil::{Rng, standard};
        for (w, _) in standard() {
            let mut rng = Rng::new(9);
            for _ in 0..300 {
                let a = rng.point_in(&w.free_bounds(), 0.0);
                let b = offset(a, rng.direction(), 200.0 * rng.unit());
                let m = w.segment_margin(a, b);
                let free = w.segment_free(a, b);
                if free {
                    let (va, vb) = (V3::from(a), V3::from(b));
                    let n = ((vb - va).length() / 0.5).ceil() as usize + 1;
                    let sampled = (0..=n)
                        .map(|i| w.clearance((va + (vb - va) * (i as f64 / n as f64)).into()))
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        m <= sampled + 1e-9 && sampled <= m + 0.5,
                        "{}: {m} vs {sampled}",
                        w.name
                    );
                }
                let r = m.min(4.0) * 0.99;
                for _ in 0..4 {
                    let a2 = offset(a, rng.direction(), r * rng.unit());
                    let b2 = offset(b, rng.direction(), r * rng.unit());
                    assert_eq!(w.segment_free(a2, b2), free, "{} {a:?} {b:?} m={m}", w.name);
                }
            }
        }
    }
}
