//! Filling tiles (paper §3.3–3.4): a stream function on the `(n+1)²` cell
//! corners of a tile, built from the edge fluxes and corner velocities and
//! completed by an interpolating bicubic Bézier patch.
//!
//! Velocities are the discrete curl of the stream function on cell faces
//! (paper Eq. 3): the x-velocity on a vertical face is `S(below) − S(above)`,
//! the y-velocity on a horizontal face is `S(right) − S(left)`, both scaled by
//! `n` so they are in tile lengths per unit time. Every cell is therefore
//! exactly divergence-free, the flux across an edge is the difference of the
//! stream values at its end points, and the field along an edge depends only
//! on that edge's two corners — which is why neighbouring tiles agree.

use crate::tileset::{TileKey, TileSet};

/// One filled tile: its key and its stream function.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// The tile's indices.
    pub key: TileKey,
    /// Cells per side.
    pub n: usize,
    /// Stream function, row-major: node `(i, j)` at `j * (n + 1) + i`,
    /// `i` along x, `j` along y, `S(0, 0) = 0`.
    pub stream: Vec<f64>,
}

impl Tile {
    /// Stream value at node `(i, j)`.
    #[inline]
    pub fn s(&self, i: usize, j: usize) -> f64 {
        self.stream[j * (self.n + 1) + i]
    }

    /// X-velocity on the vertical face at `x = i`, between rows `j` and `j+1`.
    #[inline]
    pub fn face_u(&self, i: usize, j: usize) -> f64 {
        (self.s(i, j) - self.s(i, j + 1)) * self.n as f64
    }

    /// Y-velocity on the horizontal face at `y = j`, between columns `i` and `i+1`.
    #[inline]
    pub fn face_v(&self, i: usize, j: usize) -> f64 {
        (self.s(i + 1, j) - self.s(i, j)) * self.n as f64
    }

    /// Net outflow of cell `(i, j)` (zero up to rounding for every tile).
    pub fn cell_divergence(&self, i: usize, j: usize) -> f64 {
        (self.face_u(i + 1, j) - self.face_u(i, j)) + (self.face_v(i, j + 1) - self.face_v(i, j))
    }

    /// Mean over all cell faces of the face velocity running against the
    /// unit direction `d` (`max(0, −d·v)`), in tile lengths per unit time:
    /// zero when no face of the tile flows backwards.
    pub fn backflow(&self, d: [f64; 2]) -> f64 {
        let n = self.n;
        let mut sum = 0.0;
        for j in 0..n {
            for i in 0..=n {
                sum += (-d[0] * self.face_u(i, j)).max(0.0);
                sum += (-d[1] * self.face_v(j, i)).max(0.0);
            }
        }
        sum / (2 * n * (n + 1)) as f64
    }

    /// Total flux across the edges, in the order left, bottom, right, top,
    /// summed face by face (in units of flux, not multiples).
    pub fn edge_fluxes(&self) -> [f64; 4] {
        let n = self.n;
        let h = 1.0 / n as f64;
        let sum = |f: &dyn Fn(usize) -> f64| (0..n).map(f).sum::<f64>() * h;
        [
            sum(&|j| self.face_u(0, j)),
            sum(&|i| self.face_v(i, 0)),
            sum(&|j| self.face_u(n, j)),
            sum(&|i| self.face_v(i, n)),
        ]
    }
}

impl Tile {
    /// The tile under symmetry `g` of the square (codes as in
    /// [`TileSet::transform`]): the key transformed, and the stream function
    /// carried along. A quarter turn moves node `(i, j)` to `(n − j, i)`; a
    /// top-to-bottom mirror moves it to `(i, n − j)` and flips the sign
    /// (mirroring reverses orientation). Both keep `S(0, 0) = 0` by
    /// subtracting the value that lands there. `None` when the transformed
    /// key leaves the set.
    ///
    /// ```
    /// use flowtile_bake::{fill::fill_tile, tileset::TileSet};
    /// let set = TileSet::paper(3, 3, 5, 6).unwrap();
    /// let key = set.key_at(7).unwrap();
    /// let turned = fill_tile(&set, &key).transformed(&set, 1).unwrap();
    /// assert_eq!(turned.key, set.rotate(&key).unwrap());
    /// ```
    pub fn transformed(&self, set: &TileSet, g: u8) -> Option<Tile> {
        let key = set.transform(&self.key, g)?;
        let n = self.n;
        let mut stream = self.stream.clone();
        if g & 4 != 0 {
            let base = stream[n * (n + 1)];
            for j in 0..=n {
                for i in 0..=n {
                    stream[j * (n + 1) + i] = base - self.stream[(n - j) * (n + 1) + i];
                }
            }
        }
        for _ in 0..g & 3 {
            let before = stream.clone();
            let base = before[n * (n + 1)];
            for j in 0..=n {
                for i in 0..=n {
                    stream[i * (n + 1) + (n - j)] = before[j * (n + 1) + i] - base;
                }
            }
        }
        Some(Tile { key, n, stream })
    }
}

/// Fills the tile with key `key` of `set`.
///
/// ```
/// use flowtile_bake::{fill::fill_tile, tileset::{TileKey, TileSet}};
/// let set = TileSet::paper(3, 3, 1, 6).unwrap();
/// let key = TileKey { left: 1, bottom: 0, right: 0, top: 1, corners: [0; 4] };
/// let tile = fill_tile(&set, &key);
/// assert!((tile.edge_fluxes()[0] - 1.0).abs() < 1e-12);
/// ```
pub fn fill_tile(set: &TileSet, key: &TileKey) -> Tile {
    let n = set.n;
    let known = known_values(set, key);
    let control = solve_control_points(n, &known);
    let mut stream = vec![0.0; (n + 1) * (n + 1)];
    let basis: Vec<[f64; 4]> = (0..=n).map(|i| bernstein(i as f64 / n as f64)).collect();
    for j in 0..=n {
        for i in 0..=n {
            let mut s = 0.0;
            for (k, bk) in basis[i].iter().enumerate() {
                for (l, bl) in basis[j].iter().enumerate() {
                    s += bk * bl * control[k][l];
                }
            }
            stream[j * (n + 1) + i] = s;
        }
    }
    // The patch interpolates the known values; store them exactly so fluxes
    // and corner velocities carry no solver rounding.
    let nodes = known_nodes(n);
    for (a, &i) in nodes.iter().enumerate() {
        for (b, &j) in nodes.iter().enumerate() {
            stream[j * (n + 1) + i] = known[a][b];
        }
    }
    Tile {
        key: *key,
        n,
        stream,
    }
}

/// Node coordinates (per axis) of the 16 known values: each corner and its
/// neighbour towards the tile interior.
fn known_nodes(n: usize) -> [usize; 4] {
    [0, 1, n - 1, n]
}

/// The 16 stream values around the corners, indexed `[x node][y node]` over
/// [`known_nodes`]. Corner values come from the fluxes; around each corner the
/// stream function is the linear field of the corner velocity, so the corner
/// cell moves at exactly that velocity.
fn known_values(set: &TileSet, key: &TileKey) -> [[f64; 4]; 4] {
    let n = set.n as f64;
    let f = set.f_base;
    let corner_s = [
        0.0,
        key.bottom as f64 * f,
        -(key.left as f64) * f + key.top as f64 * f,
        -(key.left as f64) * f,
    ];
    // (x node, y node) of the corners bl, br, tr, tl and the inward step.
    let corners = [
        (0usize, 0usize, 1i32, 1i32),
        (3, 0, -1, 1),
        (3, 3, -1, -1),
        (0, 3, 1, -1),
    ];
    let mut v = [[0.0; 4]; 4];
    for (c, &(a, b, da, db)) in corners.iter().enumerate() {
        let [vx, vy] = set.corners[key.corners[c] as usize];
        let s0 = corner_s[c];
        for (sa, sb) in [(0i32, 0i32), (1, 0), (0, 1), (1, 1)] {
            let di = (sa * da) as f64;
            let dj = (sb * db) as f64;
            let xa = (a as i32 + sa * da) as usize;
            let yb = (b as i32 + sb * db) as usize;
            v[xa][yb] = s0 + (di * vy - dj * vx) / n;
        }
    }
    v
}

/// Cubic Bernstein basis at `t`.
fn bernstein(t: f64) -> [f64; 4] {
    let u = 1.0 - t;
    [u * u * u, 3.0 * t * u * u, 3.0 * t * t * u, t * t * t]
}

/// Solves `B P Bᵀ = V` for the 4×4 control net `P`, where `B[p][k]` is the
/// k-th Bernstein polynomial at the p-th known node. The tensor structure
/// splits the 16×16 system into two 4×4 solves.
fn solve_control_points(n: usize, known: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let nodes = known_nodes(n);
    let mut b = [[0.0; 4]; 4];
    for (p, &i) in nodes.iter().enumerate() {
        b[p] = bernstein(i as f64 / n as f64);
    }
    let binv = invert4(&b);
    // P = B⁻¹ V B⁻ᵀ
    let mut tmp = [[0.0; 4]; 4];
    for k in 0..4 {
        for q in 0..4 {
            tmp[k][q] = (0..4).map(|p| binv[k][p] * known[p][q]).sum();
        }
    }
    let mut p = [[0.0; 4]; 4];
    for k in 0..4 {
        for l in 0..4 {
            p[k][l] = (0..4).map(|q| tmp[k][q] * binv[l][q]).sum();
        }
    }
    p
}

/// Inverse of a 4×4 matrix by Gauss–Jordan with partial pivoting. The
/// Bernstein collocation matrix at 4 distinct nodes is always invertible.
fn invert4(m: &[[f64; 4]; 4]) -> [[f64; 4]; 4] {
    let mut a = *m;
    let mut inv = [[0.0; 4]; 4];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for col in 0..4 {
        let pivot = (col..4)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let d = a[col][col];
        for k in 0..4 {
            a[col][k] /= d;
            inv[col][k] /= d;
        }
        for r in 0..4 {
            if r != col {
                let f = a[r][col];
                for k in 0..4 {
                    a[r][k] -= f * a[col][k];
                    inv[r][k] -= f * inv[col][k];
                }
            }
        }
    }
    inv
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tileset::TileSet;

    fn sets() -> Vec<TileSet> {
        vec![
            TileSet::paper(3, 3, 5, 3).unwrap(),
            TileSet::paper(3, 5, 5, 4).unwrap(),
            TileSet::paper(5, 5, 9, 7).unwrap(),
        ]
    }

    /// Picks a spread of keys from a set without filling all of them.
    fn sample_keys(set: &TileSet) -> Vec<TileKey> {
        let step = (set.count() / 400).max(1);
        (0..set.count())
            .step_by(step as usize)
            .filter_map(|i| set.key_at(i))
            .collect()
    }

    #[test]
    fn every_cell_is_divergence_free() {
        let mut worst = 0.0f64;
        for set in sets() {
            for key in sample_keys(&set) {
                let t = fill_tile(&set, &key);
                for j in 0..set.n {
                    for i in 0..set.n {
                        worst = worst.max(t.cell_divergence(i, j).abs());
                    }
                }
            }
        }
        assert!(worst <= 1e-12, "max |div| = {worst}");
    }

    #[test]
    fn edge_flux_is_multiple_of_base() {
        for mut set in sets() {
            set.f_base = 0.37;
            for key in sample_keys(&set) {
                let t = fill_tile(&set, &key);
                let want = key.fluxes().map(|m| m as f64 * set.f_base);
                let got = t.edge_fluxes();
                for k in 0..4 {
                    assert!(
                        (got[k] - want[k]).abs() <= 1e-12,
                        "{key}: {got:?} vs {want:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn corner_cells_move_at_corner_velocity() {
        for set in sets() {
            let n = set.n;
            for key in sample_keys(&set) {
                let t = fill_tile(&set, &key);
                // (cell i, cell j) of the corner cells bl, br, tr, tl.
                let cells = [(0, 0), (n - 1, 0), (n - 1, n - 1), (0, n - 1)];
                for (c, &(i, j)) in cells.iter().enumerate() {
                    let [vx, vy] = set.corners[key.corners[c] as usize];
                    for u in [t.face_u(i, j), t.face_u(i + 1, j)] {
                        assert!((u - vx).abs() < 1e-12, "{key} corner {c}: u {u} vs {vx}");
                    }
                    for v in [t.face_v(i, j), t.face_v(i, j + 1)] {
                        assert!((v - vy).abs() < 1e-12, "{key} corner {c}: v {v} vs {vy}");
                    }
                }
            }
        }
    }

    #[test]
    fn tiles_sharing_an_edge_agree() {
        let set = TileSet::paper(3, 3, 5, 5).unwrap();
        let n = set.n;
        let keys = sample_keys(&set);
        let mut checked = 0;
        for a in &keys {
            for b in &keys {
                // b to the right of a: a.right == b.left, shared corners.
                if a.right == b.left && a.corners[1] == b.corners[0] && a.corners[2] == b.corners[3]
                {
                    let (ta, tb) = (fill_tile(&set, a), fill_tile(&set, b));
                    for j in 0..n {
                        assert!((ta.face_u(n, j) - tb.face_u(0, j)).abs() < 1e-12);
                    }
                    checked += 1;
                }
                // b above a: a.top == b.bottom.
                if a.top == b.bottom && a.corners[3] == b.corners[0] && a.corners[2] == b.corners[1]
                {
                    let (ta, tb) = (fill_tile(&set, a), fill_tile(&set, b));
                    for i in 0..n {
                        assert!((ta.face_v(i, n) - tb.face_v(i, 0)).abs() < 1e-12);
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 50, "only {checked} pairs checked");
    }

    #[test]
    fn patch_interpolates_known_values_before_overwrite() {
        let set = TileSet::paper(5, 5, 5, 9).unwrap();
        let key = set.key_at(set.count() / 3).unwrap();
        let known = known_values(&set, &key);
        let p = solve_control_points(set.n, &known);
        let nodes = known_nodes(set.n);
        for (a, &i) in nodes.iter().enumerate() {
            for (b, &j) in nodes.iter().enumerate() {
                let (bi, bj) = (bernstein(i as f64 / 9.0), bernstein(j as f64 / 9.0));
                let mut s = 0.0;
                for k in 0..4 {
                    for l in 0..4 {
                        s += bi[k] * bj[l] * p[k][l];
                    }
                }
                assert!((s - known[a][b]).abs() < 1e-12);
            }
        }
    }
}
