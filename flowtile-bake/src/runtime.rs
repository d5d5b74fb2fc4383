//! Runtime queries on baked tilings: velocity at any point, flow coordinates
//! that map a tiling into world triangles (paper §5), and time-varying flows
//! blended from key tilings.
//!
//! The continuous field is the curl of a C¹ bicubic Hermite interpolant of
//! the tiles' stream values, so it is divergence-free at every point.
//!
//! Flow space: `(u, v)` in tile lengths, `0 ≤ u ≤ W`, `0 ≤ v ≤ H`.
//! Velocities are in tile lengths per unit time (the flux of `f_base` per
//! tile edge corresponds to a mean speed of `f_base`).

use crate::bake::BakedTiling;
use crate::fill::Tile;

impl BakedTiling {
    /// The tile at slot `(tx, ty)` given in unwrapped slot coordinates:
    /// wrapped on periodic axes, `None` outside the grid or when blocked.
    fn tile_unwrapped(&self, tx: i64, ty: i64) -> Option<&Tile> {
        let (w, h) = (self.width as i64, self.height as i64);
        let wrap = |t: i64, len: i64, periodic: bool| {
            if periodic {
                Some(t.rem_euclid(len))
            } else {
                (0..len).contains(&t).then_some(t)
            }
        };
        let x = wrap(tx, w, self.periodic_x)?;
        let y = wrap(ty, h, self.periodic_y)?;
        self.tile_at(x as u32, y as u32)
    }

    /// Stream difference `S(gx+1, gy) − S(gx, gy)` between two neighbouring
    /// global nodes (node space: `n` nodes per tile length). The segment lies
    /// in one tile column; on a horizontal seam both tiles hold it (and agree),
    /// so the lower-row tile is asked first, then the upper one. `None` when
    /// no open tile holds the segment (blocked or outside the grid).
    fn diff_x(&self, gx: i64, gy: i64) -> Option<f64> {
        let n = self.set.n as i64;
        let (tx, i) = (gx.div_euclid(n), gx.rem_euclid(n) as usize);
        let (ty, j) = (gy.div_euclid(n), gy.rem_euclid(n) as usize);
        let seam = j == 0;
        if seam && let Some(t) = self.tile_unwrapped(tx, ty - 1) {
            return Some(t.s(i + 1, t.n) - t.s(i, t.n));
        }
        self.tile_unwrapped(tx, ty)
            .map(|t| t.s(i + 1, j) - t.s(i, j))
    }

    /// Stream difference `S(gx, gy+1) − S(gx, gy)`, like [`Self::diff_x`].
    fn diff_y(&self, gx: i64, gy: i64) -> Option<f64> {
        let n = self.set.n as i64;
        let (tx, i) = (gx.div_euclid(n), gx.rem_euclid(n) as usize);
        let (ty, j) = (gy.div_euclid(n), gy.rem_euclid(n) as usize);
        if i == 0
            && let Some(t) = self.tile_unwrapped(tx - 1, ty)
        {
            return Some(t.s(t.n, j + 1) - t.s(t.n, j));
        }
        self.tile_unwrapped(tx, ty)
            .map(|t| t.s(i, j + 1) - t.s(i, j))
    }

    /// `∂S/∂x` at global node `(gx, gy)` in node units: the central
    /// difference of the stream function, one-sided at walls and open
    /// borders. A function of the node alone (not of the cell asking), which
    /// is what makes the Hermite interpolant C¹ across cells and seams.
    fn node_dx(&self, gx: i64, gy: i64) -> Option<f64> {
        centred(self.diff_x(gx - 1, gy), self.diff_x(gx, gy))
    }

    /// `∂S/∂y` at a global node, like [`Self::node_dx`].
    fn node_dy(&self, gx: i64, gy: i64) -> Option<f64> {
        centred(self.diff_y(gx, gy - 1), self.diff_y(gx, gy))
    }

    /// Hermite data (value, ∂x, ∂y, ∂xy) of the four nodes of cell `(i, j)`
    /// of slot `(sx, sy)`, in the order (0,0), (1,0), (0,1), (1,1).
    fn cell_hermite(&self, sx: u32, sy: u32, i: usize, j: usize) -> [[f64; 4]; 4] {
        let t = self.tile_at(sx, sy).expect("open slot");
        let n = t.n as i64;
        let (gx0, gy0) = (sx as i64 * n + i as i64, sy as i64 * n + j as i64);
        let mut out = [[0.0; 4]; 4];
        for (k, (a, b)) in [(0, 0), (1, 0), (0, 1), (1, 1)].into_iter().enumerate() {
            let (gx, gy) = (gx0 + a, gy0 + b);
            out[k] = [
                t.s(i + a as usize, j + b as usize),
                self.node_dx(gx, gy).unwrap_or(0.0),
                self.node_dy(gx, gy).unwrap_or(0.0),
                // Zero twist: any node-only choice keeps the patch C¹;
                // a finite-difference twist overshoots beside stagnation
                // corners and makes the flow turn back there.
                0.0,
            ];
        }
        out
    }

    /// Stream function and its gradient at local position `(fx, fy)` in
    /// `[0, 1]²` of cell `(i, j)` of slot `(sx, sy)`, from the bicubic
    /// Hermite patch of the cell (node units).
    fn stream_and_gradient(
        &self,
        sx: u32,
        sy: u32,
        i: usize,
        j: usize,
        fx: f64,
        fy: f64,
    ) -> [f64; 3] {
        let h = self.cell_hermite(sx, sy, i, j);
        let (hx, dhx) = (hermite(fx), hermite_d(fx));
        let (hy, dhy) = (hermite(fy), hermite_d(fy));
        let mut out = [0.0; 3];
        for (k, (a, b)) in [(0usize, 0usize), (1, 0), (0, 1), (1, 1)]
            .into_iter()
            .enumerate()
        {
            let [f, fxv, fyv, fxy] = h[k];
            // Value basis at index a, derivative basis at index a + 2.
            let term = |bx: &[f64; 4], by: &[f64; 4]| {
                f * bx[a] * by[b]
                    + fxv * bx[a + 2] * by[b]
                    + fyv * bx[a] * by[b + 2]
                    + fxy * bx[a + 2] * by[b + 2]
            };
            out[0] += term(&hx, &hy);
            out[1] += term(&dhx, &hy);
            out[2] += term(&hx, &dhy);
        }
        out
    }

    /// True when `(u, v)` lies in a blocked slot or outside a non-periodic grid.
    pub fn is_blocked_at(&self, u: f64, v: f64) -> bool {
        match self.slot_of(u, v) {
            Some((x, y)) => self.tile_at(x, y).is_none(),
            None => true,
        }
    }

    /// The slot containing `(u, v)` (wrapped on periodic axes), if any.
    pub fn slot_of(&self, u: f64, v: f64) -> Option<(u32, u32)> {
        if !u.is_finite() || !v.is_finite() {
            return None;
        }
        let (w, h) = (self.width as f64, self.height as f64);
        let wrap = |a: f64, len: f64, periodic: bool| {
            if periodic {
                Some(a.rem_euclid(len))
            } else if (0.0..=len).contains(&a) {
                Some(a.min(len - 1e-9))
            } else {
                None
            }
        };
        let uu = wrap(u, w, self.periodic_x)?;
        let vv = wrap(v, h, self.periodic_y)?;
        Some((
            (uu.floor() as u32).min(self.width - 1),
            (vv.floor() as u32).min(self.height - 1),
        ))
    }

    /// Velocity at flow-space point `(u, v)`: the analytic curl
    /// `(−∂S/∂y, ∂S/∂x)` of a C¹ interpolant of the tiles' node stream values
    /// (paper Eq. 3 taken to the continuum). Each cell is a bicubic Hermite
    /// patch whose node slopes are central differences on the global node
    /// grid, computed the same way from every cell that shares the node, so
    /// the interpolant is C¹ across cells and tile seams and the velocity is
    /// continuous. Because the velocity is an exact curl, the net flux
    /// through any closed curve is zero up to rounding (not only through grid
    /// cells), and the flux through every cell face equals the tile's
    /// discrete face flux (the patch interpolates the node values). At tile
    /// corners the velocity is exactly the corner velocity. Zero in blocked
    /// slots and outside non-periodic grids.
    ///
    /// ```
    /// use flowtile_bake::{bake::BakedTiling, rng::Rng, tileset::TileSet};
    /// use flowtile_bake::tiling::{Border, Conditions, Edge, Tiling};
    /// let set = TileSet::paper(3, 3, 1, 6).unwrap();
    /// let mut cond = Conditions::borders(Border::Free, Border::Zero);
    /// cond.fluxes.push((Edge::Vertical { x: 0, y: 0 }, 1));
    /// let mut t = Tiling::new(set, 3, 1, &cond).unwrap();
    /// t.random_fill(&mut Rng::new(1)).unwrap();
    /// let baked = BakedTiling::from_tiling(&t).unwrap();
    /// assert!(baked.velocity(1.5, 0.5)[0] > 0.0); // flowing right
    /// ```
    pub fn velocity(&self, u: f64, v: f64) -> [f64; 2] {
        let Some((sx, sy)) = self.slot_of(u, v) else {
            return [0.0, 0.0];
        };
        if self.tile_at(sx, sy).is_none() {
            return [0.0, 0.0];
        }
        let n = self.set.n;
        let local = |c: f64, len: u32, periodic: bool, slot: u32| {
            let c = if periodic {
                c.rem_euclid(len as f64)
            } else {
                c
            };
            ((c - slot as f64) * n as f64).clamp(0.0, n as f64)
        };
        let lx = local(u, self.width, self.periodic_x, sx);
        let ly = local(v, self.height, self.periodic_y, sy);
        let i = (lx.floor() as usize).min(n - 1);
        let j = (ly.floor() as usize).min(n - 1);
        let [_, sxd, syd] = self.stream_and_gradient(sx, sy, i, j, lx - i as f64, ly - j as f64);
        let scale = n as f64;
        [-syd * scale, sxd * scale]
    }

    /// Net outflow and total absolute flux through the boundary of the
    /// axis-aligned box `[u0, u1] × [v0, v1]` (flow space), integrated
    /// exactly: each side is cut at the cell lines and every piece, on which
    /// the normal velocity is a quadratic polynomial, is integrated by
    /// three-point Gauss–Legendre. For a divergence-free field the net
    /// outflow is zero up to rounding for any box.
    ///
    /// ```
    /// use flowtile_bake::{bake::BakedTiling, rng::Rng, tileset::TileSet};
    /// use flowtile_bake::tiling::{Border, Conditions, Tiling};
    /// let set = TileSet::paper(5, 5, 5, 6).unwrap();
    /// let mut t = Tiling::new(set, 4, 4, &Conditions::borders(Border::Periodic, Border::Periodic)).unwrap();
    /// t.random_fill(&mut Rng::new(3)).unwrap();
    /// let b = BakedTiling::from_tiling(&t).unwrap();
    /// let (net, total) = b.box_flux([1.03, 0.71], [1.37, 1.22]);
    /// assert!(net.abs() <= 1e-12 * total.max(1.0));
    /// ```
    pub fn box_flux(&self, lo: [f64; 2], hi: [f64; 2]) -> (f64, f64) {
        let n = self.set.n as f64;
        let mut net = 0.0;
        let mut total = 0.0;
        // (fixed coordinate, along x?, outward sign)
        let sides = [
            (lo[0], false, -1.0),
            (hi[0], false, 1.0),
            (lo[1], true, -1.0),
            (hi[1], true, 1.0),
        ];
        for (c, along_x, sign) in sides {
            let (a, b) = if along_x {
                (lo[0], hi[0])
            } else {
                (lo[1], hi[1])
            };
            let mut cuts = vec![a];
            let mut k = (a * n).floor() + 1.0;
            while k / n < b {
                cuts.push(k / n);
                k += 1.0;
            }
            cuts.push(b);
            for w in cuts.windows(2) {
                let (p, q) = (w[0], w[1]);
                let (mid, half) = (0.5 * (p + q), 0.5 * (q - p));
                let mut piece = 0.0;
                for (x, wt) in GAUSS3 {
                    let t = mid + half * x;
                    let vel = if along_x {
                        self.velocity(t, c)[1]
                    } else {
                        self.velocity(c, t)[0]
                    };
                    piece += wt * half * vel;
                }
                net += sign * piece;
                total += piece.abs();
            }
        }
        (net, total)
    }

    /// The largest |net outflow| of any cell of any used tile (exactly zero up
    /// to rounding for divergence-free tiles).
    pub fn max_cell_divergence(&self) -> f64 {
        let mut worst = 0.0f64;
        for t in &self.tiles {
            for j in 0..t.n {
                for i in 0..t.n {
                    worst = worst.max(t.cell_divergence(i, j).abs());
                }
            }
        }
        worst
    }

    /// The largest |stored edge flux − m·f_base| over all used tiles.
    pub fn max_flux_error(&self) -> f64 {
        let f = self.set.f_base;
        self.tiles
            .iter()
            .flat_map(|t| {
                let want = t.key.fluxes().map(|m| m as f64 * f);
                let got = t.edge_fluxes();
                (0..4).map(move |k| (got[k] - want[k]).abs())
            })
            .fold(0.0, f64::max)
    }

    /// The largest disagreement of face velocities across any seam between
    /// two placed tiles (and against zero at blocked neighbours).
    pub fn max_seam_mismatch(&self) -> f64 {
        let (w, h) = (self.width, self.height);
        let mut worst = 0.0f64;
        for y in 0..h {
            for x in 0..w {
                let Some(a) = self.tile_at(x, y) else {
                    continue;
                };
                let n = a.n;
                if x + 1 < w || self.periodic_x {
                    let b = self.tile_at((x + 1) % w, y);
                    for j in 0..n {
                        let other = b.map_or(0.0, |b| b.face_u(0, j));
                        worst = worst.max((a.face_u(n, j) - other).abs());
                    }
                }
                if y + 1 < h || self.periodic_y {
                    let b = self.tile_at(x, (y + 1) % h);
                    for i in 0..n {
                        let other = b.map_or(0.0, |b| b.face_v(i, 0));
                        worst = worst.max((a.face_v(i, n) - other).abs());
                    }
                }
            }
        }
        worst
    }
}

/// Three-point Gauss–Legendre nodes and weights on [−1, 1].
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Node slope from the one-sided differences on either side: their harmonic
/// mean when they agree in sign, zero when they do not (Fritsch–Butland), so
/// the interpolant adds no overshoot where the node data is monotone — no
/// spurious backflow beside stagnation points — and stays exact where the
/// data is linear (both sides equal). One-sided at walls and borders.
fn centred(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(if a * b > 0.0 {
            2.0 * a * b / (a + b)
        } else {
            0.0
        }),
        (Some(a), None) | (None, Some(a)) => Some(a),
        (None, None) => None,
    }
}

/// Cubic Hermite basis at `t`: values for the end points 0, 1, then the
/// slope bases for 0, 1.
fn hermite(t: f64) -> [f64; 4] {
    let (t2, t3) = (t * t, t * t * t);
    [
        2.0 * t3 - 3.0 * t2 + 1.0,
        -2.0 * t3 + 3.0 * t2,
        t3 - 2.0 * t2 + t,
        t3 - t2,
    ]
}

/// Derivative of [`hermite`].
fn hermite_d(t: f64) -> [f64; 4] {
    let t2 = t * t;
    [
        6.0 * t2 - 6.0 * t,
        -6.0 * t2 + 6.0 * t,
        3.0 * t2 - 4.0 * t + 1.0,
        3.0 * t2 - 2.0 * t,
    ]
}

/// One world triangle with flow coordinates, with the Jacobians precomputed.
#[derive(Clone, Copy, Debug, PartialEq)]
struct MappedTriangle {
    w0: [f64; 2],
    q0: [f64; 2],
    /// Inverse of the world edge matrix `[w1−w0, w2−w0]`: world → (β, γ).
    world_inv: [[f64; 2]; 2],
    /// Flow edge matrix `[q1−q0, q2−q0]`: (β, γ) → flow.
    flow: [[f64; 2]; 2],
    /// `world · flow⁻¹`: flow velocity → world velocity.
    jacobian: [[f64; 2]; 2],
    min: [f64; 2],
    max: [f64; 2],
}

/// Errors building a flow-coordinate mapping or a key blend.
#[derive(Clone, Debug, PartialEq)]
pub enum MapError {
    /// Key tilings that cannot be blended.
    BadKeys(String),
    /// A triangle refers to a vertex that does not exist.
    BadIndex(usize),
    /// A triangle is degenerate in world or flow space.
    Degenerate(usize),
    /// Vertex arrays of different lengths or non-finite coordinates.
    BadVertices(String),
}

impl std::fmt::Display for MapError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MapError::BadIndex(t) => write!(f, "triangle {t} refers to a missing vertex"),
            MapError::Degenerate(t) => {
                write!(f, "triangle {t} has zero area in world or flow space")
            }
            MapError::BadVertices(why) => write!(f, "bad vertices: {why}"),
            MapError::BadKeys(why) => write!(f, "cannot blend key tilings: {why}"),
        }
    }
}

impl std::error::Error for MapError {}

fn inv2(m: [[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    if det.abs() < 1e-300 || !det.is_finite() {
        return None;
    }
    Some([
        [m[1][1] / det, -m[0][1] / det],
        [-m[1][0] / det, m[0][0] / det],
    ])
}

fn mul2(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    let mut c = [[0.0; 2]; 2];
    for i in 0..2 {
        for j in 0..2 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
        }
    }
    c
}

fn apply(m: [[f64; 2]; 2], v: [f64; 2]) -> [f64; 2] {
    [
        m[0][0] * v[0] + m[0][1] * v[1],
        m[1][0] * v[0] + m[1][1] * v[1],
    ]
}

/// Flow coordinates (paper §5): world triangles, each vertex carrying a
/// `(u, v)` point of the tiling, like texture coordinates. World velocity is
/// the flow velocity pushed through the barycentric Jacobians,
/// `ẋ = (∂x/∂(β,γ)) · (∂(β,γ)/∂(u,v)) · u̇`, one constant 2×2 matrix per triangle.
///
/// ```
/// use flowtile_bake::runtime::FlowMap;
/// // A square world twice the size of a 1×1 flow region, as two triangles.
/// let world = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
/// let flow = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
/// let map = FlowMap::new(&world, &flow, &[[0, 1, 2], [0, 2, 3]]).unwrap();
/// let (tri, uv) = map.locate([1.5, 0.5]).unwrap();
/// assert!((uv[0] - 0.75).abs() < 1e-12);
/// assert_eq!(map.world_velocity(tri, [1.0, 0.0]), [2.0, 0.0]);
/// ```
#[derive(Clone, Debug)]
pub struct FlowMap {
    tris: Vec<MappedTriangle>,
    /// Uniform bucket grid over the world bounding box for point location.
    origin: [f64; 2],
    cell: f64,
    cols: usize,
    rows: usize,
    buckets: Vec<Vec<u32>>,
}

impl FlowMap {
    /// Builds the mapping from world positions, flow coordinates and triangles.
    pub fn new(
        world: &[[f64; 2]],
        flow: &[[f64; 2]],
        triangles: &[[u32; 3]],
    ) -> Result<FlowMap, MapError> {
        if world.len() != flow.len() {
            return Err(MapError::BadVertices(format!(
                "{} world and {} flow vertices",
                world.len(),
                flow.len()
            )));
        }
        if world.iter().chain(flow).flatten().any(|c| !c.is_finite()) {
            return Err(MapError::BadVertices("non-finite coordinate".into()));
        }
        let mut tris = Vec::with_capacity(triangles.len());
        for (t, idx) in triangles.iter().enumerate() {
            let get =
                |i: u32, a: &[[f64; 2]]| a.get(i as usize).copied().ok_or(MapError::BadIndex(t));
            let [w0, w1, w2] = [
                get(idx[0], world)?,
                get(idx[1], world)?,
                get(idx[2], world)?,
            ];
            let [q0, q1, q2] = [get(idx[0], flow)?, get(idx[1], flow)?, get(idx[2], flow)?];
            let wm = [
                [w1[0] - w0[0], w2[0] - w0[0]],
                [w1[1] - w0[1], w2[1] - w0[1]],
            ];
            let qm = [
                [q1[0] - q0[0], q2[0] - q0[0]],
                [q1[1] - q0[1], q2[1] - q0[1]],
            ];
            let world_inv = inv2(wm).ok_or(MapError::Degenerate(t))?;
            let flow_inv = inv2(qm).ok_or(MapError::Degenerate(t))?;
            let min = [w0[0].min(w1[0]).min(w2[0]), w0[1].min(w1[1]).min(w2[1])];
            let max = [w0[0].max(w1[0]).max(w2[0]), w0[1].max(w1[1]).max(w2[1])];
            tris.push(MappedTriangle {
                w0,
                q0,
                world_inv,
                flow: qm,
                jacobian: mul2(wm, flow_inv),
                min,
                max,
            });
        }
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for t in &tris {
            for k in 0..2 {
                lo[k] = lo[k].min(t.min[k]);
                hi[k] = hi[k].max(t.max[k]);
            }
        }
        let side = ((tris.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-12);
        let cell = extent / side as f64;
        let (cols, rows) = if tris.is_empty() {
            (1, 1)
        } else {
            (
                (((hi[0] - lo[0]) / cell).floor() as usize + 1).min(1025),
                (((hi[1] - lo[1]) / cell).floor() as usize + 1).min(1025),
            )
        };
        let mut buckets = vec![Vec::new(); cols * rows];
        for (i, t) in tris.iter().enumerate() {
            let c0 = (((t.min[0] - lo[0]) / cell).floor() as usize).min(cols - 1);
            let c1 = (((t.max[0] - lo[0]) / cell).floor() as usize).min(cols - 1);
            let r0 = (((t.min[1] - lo[1]) / cell).floor() as usize).min(rows - 1);
            let r1 = (((t.max[1] - lo[1]) / cell).floor() as usize).min(rows - 1);
            for r in r0..=r1 {
                for c in c0..=c1 {
                    buckets[r * cols + c].push(i as u32);
                }
            }
        }
        Ok(FlowMap {
            tris,
            origin: lo,
            cell,
            cols,
            rows,
            buckets,
        })
    }

    /// The triangle containing world point `p` and the point's flow coordinates.
    pub fn locate(&self, p: [f64; 2]) -> Option<(usize, [f64; 2])> {
        let c = ((p[0] - self.origin[0]) / self.cell).floor();
        let r = ((p[1] - self.origin[1]) / self.cell).floor();
        if !(c >= 0.0 && r >= 0.0) || c as usize >= self.cols || r as usize >= self.rows {
            return None;
        }
        for &i in &self.buckets[r as usize * self.cols + c as usize] {
            let t = &self.tris[i as usize];
            let bg = apply(t.world_inv, [p[0] - t.w0[0], p[1] - t.w0[1]]);
            let eps = 1e-12;
            if bg[0] >= -eps && bg[1] >= -eps && bg[0] + bg[1] <= 1.0 + eps {
                let d = apply(t.flow, bg);
                return Some((i as usize, [t.q0[0] + d[0], t.q0[1] + d[1]]));
            }
        }
        None
    }

    /// Converts a flow-space velocity inside triangle `tri` to world space.
    pub fn world_velocity(&self, tri: usize, flow_velocity: [f64; 2]) -> [f64; 2] {
        apply(self.tris[tri].jacobian, flow_velocity)
    }

    /// World velocity of `field` at world point `p` (zero outside the mesh).
    pub fn velocity(&self, field: &BakedTiling, p: [f64; 2]) -> [f64; 2] {
        match self.locate(p) {
            Some((tri, uv)) => self.world_velocity(tri, field.velocity(uv[0], uv[1])),
            None => [0.0, 0.0],
        }
    }
}

/// A time-varying flow: key tilings blended linearly in time, looping. A
/// linear blend of divergence-free fields is divergence-free.
#[derive(Clone, Debug)]
pub struct KeyBlend {
    keys: Vec<BakedTiling>,
    period: f64,
}

impl KeyBlend {
    /// Keys spaced `period` apart in time; all must share grid size,
    /// resolution and periodicity.
    pub fn new(keys: Vec<BakedTiling>, period: f64) -> Result<KeyBlend, MapError> {
        let first = keys
            .first()
            .ok_or_else(|| MapError::BadKeys("no key tilings".into()))?;
        if !(period > 0.0 && period.is_finite()) {
            return Err(MapError::BadKeys(format!(
                "key period {period} must be positive"
            )));
        }
        for (i, k) in keys.iter().enumerate() {
            if (k.width, k.height, k.set.n, k.periodic_x, k.periodic_y)
                != (
                    first.width,
                    first.height,
                    first.set.n,
                    first.periodic_x,
                    first.periodic_y,
                )
            {
                return Err(MapError::BadKeys(format!(
                    "key {i} differs in grid size, resolution or borders"
                )));
            }
        }
        Ok(KeyBlend { keys, period })
    }

    /// Key tiling `i` (wrapping around the sequence).
    pub fn key(&self, i: usize) -> &BakedTiling {
        &self.keys[i % self.keys.len()]
    }

    /// Number of keys.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Always false: a blend has at least one key.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Time between keys.
    pub fn period(&self) -> f64 {
        self.period
    }

    /// The two keys and the blend weight of the second at time `t`.
    fn frame(&self, t: f64) -> (usize, usize, f64) {
        let n = self.keys.len();
        let s = (t / self.period).rem_euclid(n as f64);
        let a = (s.floor() as usize).min(n - 1);
        (a, (a + 1) % n, s - a as f64)
    }

    /// Velocity at `(u, v)` and time `t`.
    pub fn velocity(&self, u: f64, v: f64, t: f64) -> [f64; 2] {
        let (a, b, w) = self.frame(t);
        let va = self.keys[a].velocity(u, v);
        let vb = self.keys[b].velocity(u, v);
        [va[0] * (1.0 - w) + vb[0] * w, va[1] * (1.0 - w) + vb[1] * w]
    }

    /// Net outflow of the cell-sized square at node-space cell `(i, j)` of
    /// slot `(x, y)` at time `t`, from blended face velocities.
    pub fn cell_divergence(&self, x: u32, y: u32, i: usize, j: usize, t: f64) -> f64 {
        let (a, b, w) = self.frame(t);
        let div = |k: &BakedTiling| {
            k.tile_at(x, y)
                .map_or(0.0, |tile| tile.cell_divergence(i, j))
        };
        div(&self.keys[a]) * (1.0 - w) + div(&self.keys[b]) * w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use crate::tileset::TileSet;
    use crate::tiling::{Border, Conditions, Edge, Tiling, parse_mask};

    fn baked(seed: u64, bx: Border, by: Border) -> BakedTiling {
        let set = TileSet::paper(5, 5, 5, 6).unwrap();
        let mut t = Tiling::new(set, 8, 6, &Conditions::borders(bx, by)).unwrap();
        t.random_fill(&mut Rng::new(seed)).unwrap();
        BakedTiling::from_tiling(&t).unwrap()
    }

    #[test]
    fn figures_of_merit() {
        for (bx, by) in [
            (Border::Free, Border::Zero),
            (Border::Periodic, Border::Periodic),
        ] {
            let b = baked(3, bx, by);
            assert!(b.max_cell_divergence() <= 1e-12);
            assert!(b.max_flux_error() <= 1e-12);
            assert!(b.max_seam_mismatch() <= 1e-12);
        }
    }

    /// Mean normal velocity over a cell face, by Gauss–Legendre.
    fn face_mean(b: &BakedTiling, c: f64, from: f64, along_x: bool) -> f64 {
        let h = 0.5 / b.set.n as f64;
        GAUSS3
            .iter()
            .map(|&(x, w)| {
                let t = from + h + h * x;
                0.5 * w
                    * if along_x {
                        b.velocity(t, c)[1]
                    } else {
                        b.velocity(c, t)[0]
                    }
            })
            .sum()
    }

    #[test]
    fn face_fluxes_equal_the_tiles_discrete_fluxes() {
        let b = baked(4, Border::Periodic, Border::Free);
        let n = b.set.n as f64;
        let mut rng = Rng::new(2);
        for _ in 0..500 {
            let (x, y) = (rng.below(8) as u32, rng.below(6) as u32);
            let (i, j) = (
                rng.below(b.set.n as u64) as usize,
                rng.below(b.set.n as u64) as usize,
            );
            let t = b.tile_at(x, y).unwrap();
            let u = x as f64 + i as f64 / n;
            let v = y as f64 + j as f64 / n;
            assert!((face_mean(&b, u, v, false) - t.face_u(i, j)).abs() < 1e-9);
            assert!((face_mean(&b, v, u, true) - t.face_v(i, j)).abs() < 1e-9);
        }
    }

    #[test]
    fn corner_velocities_are_exact_at_vertices() {
        let b = baked(6, Border::Periodic, Border::Periodic);
        for y in 0..6u32 {
            for x in 0..8u32 {
                let t = b.tile_at(x, y).unwrap();
                let want = b.set.corners[t.key.corners[0] as usize];
                let got = b.velocity(x as f64, y as f64);
                assert!(
                    (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
                    "vertex ({x}, {y}): {got:?} vs {want:?}"
                );
            }
        }
    }

    /// Zero net flux through random small boxes anywhere
    /// (inside cells, across cell lines, tile seams, walls and wraps).
    #[test]
    fn random_boxes_have_zero_net_flux() {
        let set = TileSet::paper(5, 5, 5, 6).unwrap();
        let mut cond = Conditions::borders(Border::Periodic, Border::Zero);
        cond.blocked = parse_mask(
            "........\n..##....\n..##..#.\n........\n.#......\n........",
            8,
            6,
        )
        .unwrap();
        let mut t = Tiling::new(set, 8, 6, &cond).unwrap();
        t.random_fill(&mut Rng::new(12)).unwrap();
        let b = BakedTiling::from_tiling(&t).unwrap();
        let mut rng = Rng::new(77);
        let mut worst = 0.0f64;
        let mut tested = 0;
        for k in 0..4000 {
            // Sizes from a fraction of a cell to two tiles.
            let size = [0.01, 0.1, 0.5, 2.0][k % 4];
            let lo = [rng.unit() * 9.0 - 0.5, rng.unit() * 6.0];
            let hi = [
                lo[0] + size * (0.2 + rng.unit()),
                lo[1] + size * (0.2 + rng.unit()),
            ];
            let (net, total) = b.box_flux(lo, hi);
            if total > 1e-9 * size {
                worst = worst.max(net.abs() / total);
                tested += 1;
            }
        }
        assert!(tested > 3000, "{tested}");
        toolbox::errln!("random boxes: {tested} tested, max |net| / boundary flux = {worst:e}");
        assert!(worst <= 1e-9, "max |net| / boundary flux = {worst:e}");
    }

    #[test]
    fn velocity_is_continuous_across_seams_and_wraps() {
        let b = baked(5, Border::Periodic, Border::Periodic);
        let mut rng = Rng::new(8);
        for _ in 0..300 {
            let u = rng.below(9) as f64;
            let v = rng.unit() * 6.0;
            let l = b.velocity(u - 1e-9, v);
            let r = b.velocity(u + 1e-9, v);
            assert!(
                (l[0] - r[0]).abs() < 1e-6 && (l[1] - r[1]).abs() < 1e-6,
                "u {u} v {v}: {l:?} {r:?}"
            );
            let w = b.velocity(u + 8.0, v - 6.0);
            assert!((w[0] - r[0]).abs() < 1e-6);
            // Horizontal cell lines and seams too (C¹ interpolant).
            let (u, v) = (rng.unit() * 8.0, rng.below(37) as f64 / 6.0);
            let d = b.velocity(u, v - 1e-9);
            let a = b.velocity(u, v + 1e-9);
            assert!(
                (d[0] - a[0]).abs() < 1e-6 && (d[1] - a[1]).abs() < 1e-6,
                "u {u} v {v}: {d:?} {a:?}"
            );
        }
    }

    #[test]
    fn flux_through_a_line_matches_edge_multiples() {
        // Integrate the x-velocity along the vertical line u = 3 by the
        // midpoint rule on faces: equals the sum of the fixed fluxes.
        let set = TileSet::paper(5, 3, 1, 6).unwrap();
        let mut cond = Conditions::borders(Border::Free, Border::Zero);
        for y in 0..4 {
            cond.fluxes
                .push((Edge::Vertical { x: 0, y }, 1 + (y as i32 % 2)));
        }
        let mut t = Tiling::new(set, 6, 4, &cond).unwrap();
        t.random_fill(&mut Rng::new(1)).unwrap();
        let b = BakedTiling::from_tiling(&t).unwrap();
        let total: f64 = (0..24)
            .map(|k| face_mean(&b, 3.0, k as f64 / 6.0, false) / 6.0)
            .sum();
        assert!((total - 6.0).abs() < 1e-9, "{total}");
    }

    #[test]
    fn blocked_slots_are_still() {
        let set = TileSet::paper(3, 3, 5, 5).unwrap();
        let mut cond = Conditions::borders(Border::Free, Border::Free);
        cond.blocked = parse_mask("....\n.#..\n....", 4, 3).unwrap();
        let mut t = Tiling::new(set, 4, 3, &cond).unwrap();
        t.random_fill(&mut Rng::new(6)).unwrap();
        let b = BakedTiling::from_tiling(&t).unwrap();
        assert_eq!(b.velocity(1.5, 1.5), [0.0, 0.0]);
        assert!(b.is_blocked_at(1.5, 1.5));
        // No flow into the block: x-velocity on its left wall is zero.
        for k in 0..10 {
            let v = b.velocity(1.0 - 1e-12, 1.0 + (k as f64 + 0.5) / 10.0);
            assert!(v[0].abs() < 1e-9, "{v:?}");
        }
        assert!(b.max_seam_mismatch() <= 1e-12);
    }

    #[test]
    fn flow_map_jacobians() {
        // A sheared, scaled triangle mesh.
        let world = [[0.0, 0.0], [4.0, 1.0], [5.0, 3.0], [1.0, 2.0]];
        let flow = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]];
        let map = FlowMap::new(&world, &flow, &[[0, 1, 2], [0, 2, 3]]).unwrap();
        // World displacement of a small flow step equals Jacobian · step.
        let p = [2.5, 1.5];
        let (tri, uv) = map.locate(p).unwrap();
        let step = [1e-3, 2e-3];
        let dw = map.world_velocity(tri, step);
        let (_, uv2) = map.locate([p[0] + dw[0], p[1] + dw[1]]).unwrap();
        assert!(
            (uv2[0] - uv[0] - step[0]).abs() < 1e-12 && (uv2[1] - uv[1] - step[1]).abs() < 1e-12
        );
        assert!(map.locate([10.0, 10.0]).is_none());
        assert!(FlowMap::new(&world, &flow, &[[0, 1, 7]]).is_err());
        assert!(FlowMap::new(&world, &flow, &[[0, 0, 1]]).is_err());
    }

    #[test]
    fn blended_keys_stay_divergence_free() {
        let keys: Vec<BakedTiling> = (0..3)
            .map(|s| baked(10 + s, Border::Periodic, Border::Periodic))
            .collect();
        let blend = KeyBlend::new(keys.clone(), 2.0).unwrap();
        let mut rng = Rng::new(3);
        for _ in 0..200 {
            let t = rng.unit() * 12.0;
            let (x, y) = (rng.below(8) as u32, rng.below(6) as u32);
            let (i, j) = (rng.below(6) as usize, rng.below(6) as usize);
            assert!(blend.cell_divergence(x, y, i, j, t).abs() <= 1e-12);
        }
        // At key times the blend equals the key.
        let v = blend.velocity(2.3, 1.7, 4.0);
        assert_eq!(v, keys[2].velocity(2.3, 1.7));
        assert!(KeyBlend::new(vec![], 1.0).is_err());
    }
}
