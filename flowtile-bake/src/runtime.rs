//! Runtime queries on baked tilings: velocity at any point, flow coordinates
//! that map a tiling into world triangles (paper §5), and time-varying flows
//! blended from key tilings.
//!
//! Flow space: `(u, v)` in tile lengths, `0 ≤ u ≤ W`, `0 ≤ v ≤ H`.
//! Velocities are in tile lengths per unit time (the flux of `f_base` per
//! tile edge corresponds to a mean speed of `f_base`).

use crate::bake::BakedTiling;

impl BakedTiling {
    /// The stream value at global node-space point `(px, py)` (cell units)
    /// relative to the stream function of reference slot `(rx, ry)`.
    ///
    /// Each tile stores its stream function up to a constant; neighbouring
    /// tiles differ by the stream value at their shared corner, which is read
    /// from the stored corner nodes, so lookups stay local even on periodic
    /// grids (where no global stream function exists).
    fn stream_rel(&self, rx: i64, ry: i64, px: f64, py: f64) -> f64 {
        let n = self.set.n as f64;
        let (w, h) = (self.width as i64, self.height as i64);
        // Points on the reference tile's own edges use the reference tile:
        // robust to rounding, and the values agree with the neighbour anyway.
        let pick = |p: f64, r: i64| {
            let local = p - r as f64 * n;
            if (-1e-9..=n + 1e-9).contains(&local) {
                r
            } else {
                (p / n).floor() as i64
            }
        };
        let mut tx = pick(px, rx);
        let mut ty = pick(py, ry);
        // Clamp to the grid (or to the reference's neighbours); wrap if periodic.
        tx = tx.clamp(rx - 1, rx + 1);
        ty = ty.clamp(ry - 1, ry + 1);
        if !self.periodic_x {
            tx = tx.clamp(0, w - 1);
        }
        if !self.periodic_y {
            ty = ty.clamp(0, h - 1);
        }
        let (dx, dy) = (tx - rx, ty - ry);
        let lx = px - tx as f64 * n;
        let ly = py - ty as f64 * n;
        let (wx, wy) = (tx.rem_euclid(w) as u32, ty.rem_euclid(h) as u32);
        let (rwx, rwy) = (rx.rem_euclid(w) as u32, ry.rem_euclid(h) as u32);
        // Offset: horizontal step first, then vertical.
        let hx = (rx + dx).rem_euclid(w) as u32;
        let mut offset = self.step_offset(rwx, rwy, hx, rwy, dx, 0);
        offset += self.step_offset(hx, rwy, wx, wy, 0, dy);
        offset + self.local_stream(wx, wy, lx, ly)
    }

    /// Stream offset of slot `to` relative to adjacent slot `from`.
    fn step_offset(&self, fx: u32, fy: u32, tx: u32, ty: u32, dx: i64, dy: i64) -> f64 {
        let n = self.set.n;
        let corner =
            |x: u32, y: u32, i: usize, j: usize| self.tile_at(x, y).map_or(0.0, |t| t.s(i, j));
        match (dx, dy) {
            (1, 0) => corner(fx, fy, n, 0),
            (-1, 0) => -corner(tx, ty, n, 0),
            (0, 1) => corner(fx, fy, 0, n),
            (0, -1) => -corner(tx, ty, 0, n),
            _ => 0.0,
        }
    }

    /// Bilinear stream value inside slot `(x, y)` at local cell coordinates
    /// (extrapolating linearly past the tile's edge when clamped).
    fn local_stream(&self, x: u32, y: u32, lx: f64, ly: f64) -> f64 {
        let Some(t) = self.tile_at(x, y) else {
            return 0.0;
        };
        let n = t.n;
        let i = (lx.floor() as i64).clamp(0, n as i64 - 1) as usize;
        let j = (ly.floor() as i64).clamp(0, n as i64 - 1) as usize;
        let (fx, fy) = (lx - i as f64, ly - j as f64);
        let s00 = t.s(i, j);
        let s10 = t.s(i + 1, j);
        let s01 = t.s(i, j + 1);
        let s11 = t.s(i + 1, j + 1);
        s00 * (1.0 - fx) * (1.0 - fy)
            + s10 * fx * (1.0 - fy)
            + s01 * (1.0 - fx) * fy
            + s11 * fx * fy
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

    /// Velocity at flow-space point `(u, v)` (paper Eq. 3 on the bilinearly
    /// interpolated stream function). Zero in blocked slots and outside
    /// non-periodic grids.
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
        let n = self.set.n as f64;
        // Work in unwrapped coordinates relative to the slot found.
        let (uu, vv) = (
            if self.periodic_x {
                u.rem_euclid(self.width as f64)
            } else {
                u
            },
            if self.periodic_y {
                v.rem_euclid(self.height as f64)
            } else {
                v
            },
        );
        let (px, py) = (uu * n, vv * n);
        let (rx, ry) = (sx as i64, sy as i64);
        let s = |x: f64, y: f64| self.stream_rel(rx, ry, x, y);
        let vx = s(px, py - 0.5) - s(px, py + 0.5);
        let vy = s(px + 0.5, py) - s(px - 0.5, py);
        [vx * n, vy * n]
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

    #[test]
    fn velocity_matches_face_values_at_face_centres() {
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
            // Left face centre of cell (i, j): u exact; bottom face centre: v exact.
            let u = x as f64 + i as f64 / n;
            let v = y as f64 + (j as f64 + 0.5) / n;
            assert!((b.velocity(u, v)[0] - t.face_u(i, j)).abs() < 1e-9);
            let u = x as f64 + (i as f64 + 0.5) / n;
            let v = y as f64 + j as f64 / n;
            assert!((b.velocity(u, v)[1] - t.face_v(i, j)).abs() < 1e-9);
        }
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
        let n = 6.0;
        let total: f64 = (0..24)
            .map(|k| b.velocity(3.0, (k as f64 + 0.5) / n)[0] / n)
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
