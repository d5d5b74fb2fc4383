//! Bézier patches: the curved surfaces of Quake 3 (`cm_patch.c`, `tr_curve.c`).
//!
//! A patch is a grid of `width × height` control points (both odd), a row of
//! biquadratic pieces each 3 × 3 points. [`Grid::tessellate`] evaluates it on a grid
//! fine enough that no chord strays more than [`TOLERANCE`] units from the curve, the
//! same for every row so neighbouring pieces share their edges. The game collides
//! with patches as surfaces; for the tools they must also be volumes: a patch closed
//! around itself (a pipe, a column: first and last column of the grid coincide) is
//! filled solid, one convex piece per ring of the grid ([`Grid::tube_pieces`]); an
//! open patch becomes a slab [`SLAB`] units thick on each side of every triangle
//! ([`Grid::slabs`]), which blocks every segment that crosses the surface.

use toolbox::vec3::{cross, dot, norm, sub};

type P = [f64; 3];

/// Largest distance allowed between the curve and its drawn faces, in units.
pub const TOLERANCE: f64 = 1.0;
/// The same for the patch's volume (its brushes), coarser to keep the carved trees
/// small: the game's own patch collision allows 16 units (`cm_patch.c`).
pub const VOLUME_TOLERANCE: f64 = 4.0;
/// Half the thickness of the slab an open patch becomes.
pub const SLAB: f64 = 1.0;
/// Most segments a biquadratic piece gets along one direction.
const MAX_SEGMENTS: usize = 16;

/// A convex volume as planes `normal · x <= dist`.
pub type Planes = Vec<(P, f64)>;

/// A tessellated patch: `rows × cols` points and vertex normals, row major.
#[derive(Debug, Clone)]
pub struct Grid {
    pub rows: usize,
    pub cols: usize,
    pub points: Vec<P>,
    pub normals: Vec<P>,
}

fn lerp(a: P, b: P, t: f64) -> P {
    [0, 1, 2].map(|i| a[i] + t * (b[i] - a[i]))
}

fn unit(v: P) -> Option<P> {
    let l = norm(v);
    (l > 1e-9).then(|| v.map(|x| x / l))
}

/// The quadratic Bézier curve through control points `a`, `b`, `c` at `t`.
fn bezier(a: P, b: P, c: P, t: f64) -> P {
    lerp(lerp(a, b, t), lerp(b, c, t), t)
}

/// Segments each piece of a row of quadratic curves gets: `rows` are the control
/// rows, each `2 n + 1` points; piece `i` uses points `2i..=2i+2` of every row.
fn segments(rows: &[&[P]], tolerance: f64) -> Vec<usize> {
    let pieces = (rows[0].len() - 1) / 2;
    (0..pieces)
        .map(|i| {
            let err = rows
                .iter()
                .map(|r| {
                    let (a, b, c) = (r[2 * i], r[2 * i + 1], r[2 * i + 2]);
                    norm([0, 1, 2].map(|k| a[k] - 2.0 * b[k] + c[k])) / 4.0
                })
                .fold(0.0, f64::max);
            ((err / tolerance).sqrt().ceil() as usize).clamp(1, MAX_SEGMENTS)
        })
        .collect()
}

/// Evaluates one control row at the pieces' segment parameters.
fn eval_row(row: &[P], segs: &[usize]) -> Vec<P> {
    let mut out = vec![row[0]];
    for (i, &n) in segs.iter().enumerate() {
        let (a, b, c) = (row[2 * i], row[2 * i + 1], row[2 * i + 2]);
        out.extend((1..=n).map(|k| bezier(a, b, c, k as f64 / n as f64)));
    }
    out
}

impl Grid {
    /// Tessellates a patch of `width × height` control points (row major), both odd
    /// and at least 3 (the reader checks), to within `tolerance` units.
    pub fn tessellate(
        control: &[P],
        normals: &[P],
        width: usize,
        height: usize,
        tolerance: f64,
    ) -> Grid {
        debug_assert_eq!(control.len(), width * height);
        let rows: Vec<&[P]> = control.chunks(width).collect();
        let useg = segments(&rows, tolerance);
        let cols_of = |r: &[&[P]], segs: &[usize]| -> Vec<Vec<P>> {
            r.iter().map(|row| eval_row(row, segs)).collect()
        };
        // Along u for every control row, then along v for every resulting column.
        let across = cols_of(&rows, &useg);
        let nrows: Vec<&[P]> = normals.chunks(width).collect();
        let nacross = cols_of(&nrows, &useg);
        let cols = across[0].len();
        let columns: Vec<Vec<P>> = (0..cols)
            .map(|k| across.iter().map(|r| r[k]).collect())
            .collect();
        let colrefs: Vec<&[P]> = columns.iter().map(|c| c.as_slice()).collect();
        let vseg = segments(&colrefs, tolerance);
        let down: Vec<Vec<P>> = columns.iter().map(|c| eval_row(c, &vseg)).collect();
        let ndown: Vec<Vec<P>> = (0..cols)
            .map(|k| {
                let c: Vec<P> = nacross.iter().map(|r| r[k]).collect();
                eval_row(&c, &vseg)
            })
            .collect();
        let nr = down[0].len();
        let mut points = Vec::with_capacity(nr * cols);
        let mut norms = Vec::with_capacity(nr * cols);
        for r in 0..nr {
            for k in 0..cols {
                points.push(down[k][r]);
                norms.push(ndown[k][r]);
            }
        }
        Grid {
            rows: nr,
            cols,
            points,
            normals: norms,
        }
    }

    fn at(&self, r: usize, k: usize) -> P {
        self.points[r * self.cols + k]
    }

    /// The triangles of the grid, each turned to face along the patch's vertex
    /// normals (the side it is drawn on); degenerate ones left out. Indices into
    /// [`Grid::points`].
    pub fn triangles(&self) -> Vec<[usize; 3]> {
        let mut out = Vec::new();
        for r in 0..self.rows - 1 {
            for k in 0..self.cols - 1 {
                let i = |r: usize, k: usize| r * self.cols + k;
                for t in [
                    [i(r, k), i(r, k + 1), i(r + 1, k + 1)],
                    [i(r, k), i(r + 1, k + 1), i(r + 1, k)],
                ] {
                    let [a, b, c] = t.map(|j| self.points[j]);
                    let n = cross(sub(b, a), sub(c, a));
                    if norm(n) < 1e-6 {
                        continue;
                    }
                    let vn = t.iter().fold([0.0; 3], |s, &j| {
                        let v = self.normals[j];
                        [s[0] + v[0], s[1] + v[1], s[2] + v[2]]
                    });
                    out.push(if dot(n, vn) < 0.0 {
                        [t[0], t[2], t[1]]
                    } else {
                        t
                    });
                }
            }
        }
        out
    }

    /// Whether the grid closes on itself across its columns (first and last column
    /// the same points: a pipe or column).
    pub fn closed_across(&self) -> bool {
        self.cols >= 4
            && (0..self.rows).all(|r| {
                let d = sub(self.at(r, 0), self.at(r, self.cols - 1));
                norm(d) < 0.5
            })
    }

    /// The same grid with rows and columns swapped.
    pub fn transposed(&self) -> Grid {
        let mut points = Vec::with_capacity(self.points.len());
        let mut normals = Vec::with_capacity(self.points.len());
        for k in 0..self.cols {
            for r in 0..self.rows {
                points.push(self.at(r, k));
                normals.push(self.normals[r * self.cols + k]);
            }
        }
        Grid {
            rows: self.cols,
            cols: self.rows,
            points,
            normals,
        }
    }

    /// A closed grid's volume: between each pair of neighbouring rings, the convex
    /// piece bounded by the planes of the quads around and the two rings' planes.
    /// Each plane is moved out to the farthest point of the piece, so the piece
    /// always holds the rings it joins.
    pub fn tube_pieces(&self) -> Vec<Planes> {
        let n = self.cols - 1;
        let mut out = Vec::new();
        for r in 0..self.rows - 1 {
            let a: Vec<P> = (0..n).map(|k| self.at(r, k)).collect();
            let b: Vec<P> = (0..n).map(|k| self.at(r + 1, k)).collect();
            let all: Vec<P> = a.iter().chain(&b).copied().collect();
            let centre = mean(&all);
            let out_to_all = |n: P| (n, all.iter().map(|p| dot(n, *p)).fold(f64::MIN, f64::max));
            let mut planes = Vec::new();
            for k in 0..n {
                let (p0, p1, q1, q0) = (a[k], a[(k + 1) % n], b[(k + 1) % n], b[k]);
                let Some(mut nrm) = unit(cross(sub(q1, p0), sub(q0, p1))) else {
                    continue;
                };
                if dot(nrm, sub(mean(&[p0, p1, q1, q0]), centre)) < 0.0 {
                    nrm = nrm.map(|x| -x);
                }
                planes.push(out_to_all(nrm));
            }
            let (ca, cb) = (mean(&a), mean(&b));
            for (ring, c, other) in [(&a, ca, cb), (&b, cb, ca)] {
                let away = sub(c, other);
                let nrm = unit(newell(ring)).or_else(|| unit(away));
                let Some(mut nrm) = nrm else { continue };
                if dot(nrm, away) < 0.0 {
                    nrm = nrm.map(|x| -x);
                }
                planes.push(out_to_all(nrm));
            }
            if planes.len() >= 4 {
                out.push(planes);
            }
        }
        out
    }

    /// An open grid's volume: a slab [`SLAB`] units to each side of every triangle.
    pub fn slabs(&self) -> Vec<Planes> {
        self.triangles()
            .into_iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|j| self.points[j]);
                let n = unit(cross(sub(b, a), sub(c, a)))?;
                let mut planes = vec![(n, dot(n, a) + SLAB), (n.map(|x| -x), -dot(n, a) + SLAB)];
                for (p, q, o) in [(a, b, c), (b, c, a), (c, a, b)] {
                    let mut e = unit(cross(sub(q, p), n))?;
                    if dot(e, sub(o, p)) > 0.0 {
                        e = e.map(|x| -x);
                    }
                    planes.push((e, dot(e, p)));
                }
                Some(planes)
            })
            .collect()
    }
}

fn mean(p: &[P]) -> P {
    let s = p
        .iter()
        .fold([0.0; 3], |s, v| [s[0] + v[0], s[1] + v[1], s[2] + v[2]]);
    s.map(|x| x / p.len().max(1) as f64)
}

/// Newell's normal of a closed polygon (its area vector, twice the area long).
fn newell(p: &[P]) -> P {
    let mut n = [0.0; 3];
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertical pipe of radius 16 from z = 0 to z = 64 as Quake 3 patches store
    /// one: 9 control points around (four quarter circles), 3 up.
    fn pipe() -> (Vec<P>, Vec<P>) {
        let ring = [
            [16.0, 0.0],
            [16.0, 16.0],
            [0.0, 16.0],
            [-16.0, 16.0],
            [-16.0, 0.0],
            [-16.0, -16.0],
            [0.0, -16.0],
            [16.0, -16.0],
            [16.0, 0.0],
        ];
        let mut pts = Vec::new();
        let mut nrm = Vec::new();
        for z in [0.0, 32.0, 64.0] {
            for [x, y] in ring {
                pts.push([x, y, z]);
                nrm.push([x / 16.0, y / 16.0, 0.0]);
            }
        }
        (pts, nrm)
    }

    #[test]
    fn tessellation_follows_the_curve_within_tolerance() {
        let (pts, nrm) = pipe();
        let g = Grid::tessellate(&pts, &nrm, 9, 3, TOLERANCE);
        assert!(g.cols > 9 && g.rows == 2, "{} x {}", g.rows, g.cols);
        for p in &g.points {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            // Quadratic Bézier quarter "circles" bulge out a little from radius 16.
            assert!((15.99..=17.0).contains(&r), "{p:?} at radius {r}");
        }
        assert!(g.closed_across());
        // Triangles face outwards, along the vertex normals.
        for t in g.triangles() {
            let [a, b, c] = t.map(|j| g.points[j]);
            let n = cross(sub(b, a), sub(c, a));
            let m = mean(&[a, b, c]);
            assert!(n[0] * m[0] + n[1] * m[1] > 0.0);
        }
    }

    #[test]
    fn a_closed_pipe_is_filled_and_an_open_patch_is_a_slab() {
        let (pts, nrm) = pipe();
        let g = Grid::tessellate(&pts, &nrm, 9, 3, TOLERANCE);
        let pieces = g.tube_pieces();
        assert_eq!(pieces.len(), g.rows - 1);
        let inside = |planes: &Planes, p: P| planes.iter().all(|(n, d)| dot(*n, p) <= *d);
        assert!(pieces.iter().any(|pl| inside(pl, [0.0, 0.0, 32.0])));
        assert!(pieces.iter().any(|pl| inside(pl, [10.0, 0.0, 5.0])));
        assert!(!pieces.iter().any(|pl| inside(pl, [17.0, 0.0, 32.0])));
        assert!(!pieces.iter().any(|pl| inside(pl, [0.0, 0.0, 65.0])));
        // Half of the pipe (an arch) is open: slabs around its surface only.
        let half: Vec<P> = pts.chunks(9).flat_map(|r| r[..5].to_vec()).collect();
        let hn: Vec<P> = nrm.chunks(9).flat_map(|r| r[..5].to_vec()).collect();
        let g = Grid::tessellate(&half, &hn, 5, 3, TOLERANCE);
        assert!(!g.closed_across());
        let slabs = g.slabs();
        assert!(!slabs.iter().any(|pl| inside(pl, [0.0, 8.0, 32.0])));
        assert!(slabs.iter().any(|pl| inside(pl, [0.0, 15.5, 32.0])));
    }
}
