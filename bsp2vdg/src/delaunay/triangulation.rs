//! The finished triangulation: read-only access to cells, neighbours, circumspheres and
//! the cycles of cells around Delaunay edges (the Voronoi faces).

use super::INFINITE;
use super::build::Cell;
use super::insert::other_two;

/// A Delaunay tetrahedralization of a point set, with an infinite vertex closing the convex
/// hull (so every cell has exactly four neighbours).
///
/// Cells `0..num_finite_cells()` are finite, the rest have [`INFINITE`] as one vertex.
/// Vertex ids are indices into the input slice. Every finite cell is positively oriented
/// (`robust::orient3d(v0, v1, v2, v3) > 0`, exactly), neighbour `i` of a cell lies opposite
/// its vertex `i`, and no input point lies strictly inside any finite cell's circumsphere.
///
/// ```
/// use bsp2vdg::delaunay::Triangulation;
/// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
/// let tri = Triangulation::new(&pts).unwrap();
/// // Five cospherical cube corners: two or three cells are equally Delaunay; the symbolic
/// // perturbation picks one, never a flat cell.
/// assert!(matches!(tri.num_finite_cells(), 2 | 3));
/// tri.validate().unwrap();
/// let c = tri.circumcenter(0);
/// assert!((c[0] - 0.5).abs() < 1e-12 && (tri.circumradius(0) - 0.75f64.sqrt()).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct Triangulation {
    points: Vec<[f64; 3]>,
    /// Vertex ids and packed neighbours `(cell << 2) | facet`: across facet `i` of cell `t`
    /// lies cell `n`, where the same facet is opposite `n`'s vertex `facet`. 32 bytes.
    cells: Vec<Cell>,
    num_finite: usize,
    duplicates: Vec<(u32, u32)>,
}

/// A Delaunay edge and the cells around it, in cyclic order: counter-clockwise when looking
/// from `b` towards `a` (i.e. positive rotation about the direction `a → b`, right-hand
/// rule). Consecutive cells share a facet, and so do the last and the first.
///
/// On degenerate input (wall samples) cospherical neighbouring cells have the same
/// circumcenter, so the Voronoi polygon built from a ring can repeat a vertex (zero-length
/// Voronoi edges); merge equal consecutive circumcenters when building faces.
#[derive(Clone, Copy, Debug)]
pub struct EdgeRing<'a> {
    /// Smaller vertex id.
    pub a: u32,
    /// Larger vertex id.
    pub b: u32,
    /// Cell ids around the edge. If `touches_infinity`, the two infinite cells come last,
    /// so the finite cells form a contiguous path.
    pub cells: &'a [u32],
    /// Whether the edge lies on the convex hull (its ring contains infinite cells; its
    /// Voronoi face is unbounded).
    pub touches_infinity: bool,
}

impl Triangulation {
    pub(super) fn from_parts(
        points: Vec<[f64; 3]>,
        cells: Vec<Cell>,
        num_finite: usize,
        duplicates: Vec<(u32, u32)>,
    ) -> Self {
        Triangulation {
            points,
            cells,
            num_finite,
            duplicates,
        }
    }

    /// The input points (including skipped duplicates), indexed by vertex id.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// Number of cells, finite and infinite.
    pub fn num_cells(&self) -> usize {
        self.cells.len()
    }

    /// Number of finite cells (tetrahedra); they are the cells `0..num_finite_cells()`.
    pub fn num_finite_cells(&self) -> usize {
        self.num_finite
    }

    /// Whether cell `t` is a finite tetrahedron (has no [`INFINITE`] vertex).
    #[inline]
    pub fn is_finite(&self, t: u32) -> bool {
        (t as usize) < self.num_finite
    }

    /// All cells' vertex ids, in cell id order; infinite cells contain [`INFINITE`].
    pub fn cells(&self) -> impl ExactSizeIterator<Item = [u32; 4]> + '_ {
        self.cells.iter().map(|c| c.v)
    }

    /// Vertex ids of cell `t`.
    #[inline]
    pub fn cell(&self, t: u32) -> [u32; 4] {
        self.cells[t as usize].v
    }

    /// The neighbour of cell `t` across the facet opposite its vertex `i`, and the index of
    /// that facet in the neighbour.
    #[inline]
    pub fn neighbor(&self, t: u32, i: usize) -> (u32, usize) {
        let p = self.cells[t as usize].n[i];
        (p >> 2, (p & 3) as usize)
    }

    /// The four neighbours of cell `t` (neighbour `i` opposite vertex `i`).
    #[inline]
    pub fn neighbors(&self, t: u32) -> [u32; 4] {
        self.cells[t as usize].n.map(|p| p >> 2)
    }

    /// Input points skipped because an earlier-inserted point has the same coordinates:
    /// `(skipped id, kept id)`, sorted.
    pub fn duplicates(&self) -> &[(u32, u32)] {
        &self.duplicates
    }

    /// Number of vertices of the triangulation (distinct input points).
    pub fn num_vertices(&self) -> usize {
        self.points.len() - self.duplicates.len()
    }

    /// Circumcenter of the finite cell `t`.
    ///
    /// Computed relative to the cell's first vertex (small differences, little
    /// cancellation) with the denominator from the adaptive-exact `orient3d`, which is never
    /// zero for a cell of this triangulation, so the result is always finite.
    pub fn circumcenter(&self, t: u32) -> [f64; 3] {
        debug_assert!(self.is_finite(t), "circumcenter of an infinite cell");
        let [p0, p1, p2, p3] = self.cells[t as usize].v.map(|v| self.points[v as usize]);
        let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let cross = |a: [f64; 3], b: [f64; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let (a, b, c) = (sub(p1, p0), sub(p2, p0), sub(p3, p0));
        // det[a; b; c] = -orient3d(p0, p1, p2, p3) in Shewchuk's convention. `robust`
        // returns a close approximation of the determinant's value (our predicate only
        // promises its sign), and it is never zero for a cell of this triangulation.
        let c3 = |p: [f64; 3]| robust::Coord3D {
            x: p[0],
            y: p[1],
            z: p[2],
        };
        let det = -robust::orient3d(c3(p0), c3(p1), c3(p2), c3(p3));
        let (bc, ca, ab) = (cross(b, c), cross(c, a), cross(a, b));
        let (la, lb, lc) = (dot(a, a), dot(b, b), dot(c, c));
        let s = 0.5 / det;
        [0, 1, 2].map(|k| p0[k] + (la * bc[k] + lb * ca[k] + lc * ab[k]) * s)
    }

    /// Circumradius of the finite cell `t` (distance from the circumcenter to its first vertex).
    pub fn circumradius(&self, t: u32) -> f64 {
        let c = self.circumcenter(t);
        let p = self.points[self.cells[t as usize].v[0] as usize];
        ((c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2)).sqrt()
    }

    /// Circumcenter and circumradius of every finite cell, indexed by cell id.
    pub fn circumspheres(&self) -> Vec<([f64; 3], f64)> {
        (0..self.num_finite as u32)
            .map(|t| {
                let c = self.circumcenter(t);
                let p = self.points[self.cells[t as usize].v[0] as usize];
                let r =
                    ((c[0] - p[0]).powi(2) + (c[1] - p[1]).powi(2) + (c[2] - p[2]).powi(2)).sqrt();
                (c, r)
            })
            .collect()
    }

    /// Call `f` once for every Delaunay edge between two input points, with the cycle of cells
    /// around it (see [`EdgeRing`]). Edges come in a deterministic order (by the smallest id
    /// of a cell around them); each ring starts at its smallest finite cell id... unless it
    /// touches infinity, then it starts right after the infinite cells.
    ///
    /// ```
    /// use bsp2vdg::delaunay::Triangulation;
    /// let pts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    /// let tri = Triangulation::new(&pts).unwrap();
    /// let mut edges = 0;
    /// tri.for_each_edge_ring(|ring| {
    ///     edges += 1;
    ///     assert!(ring.touches_infinity && ring.cells.len() == 3);
    /// });
    /// assert_eq!(edges, 6);
    /// ```
    pub fn for_each_edge_ring<F: FnMut(EdgeRing<'_>)>(&self, mut f: F) {
        // One bit per (cell, local edge): set once the edge's ring has been reported.
        let mut done = vec![0u8; self.cells.len()];
        let mut ring: Vec<u32> = Vec::new();
        for t in 0..self.cells.len() as u32 {
            let v = self.cells[t as usize].v;
            for (e, &(i, j)) in LOCAL_EDGES.iter().enumerate() {
                if done[t as usize] & (1 << e) != 0 || v[i] == INFINITE || v[j] == INFINITE {
                    continue;
                }
                let (a, b) = if v[i] < v[j] {
                    (v[i], v[j])
                } else {
                    (v[j], v[i])
                };
                let touches_infinity = self.edge_ring(t, a, b, &mut ring, &mut done);
                f(EdgeRing {
                    a,
                    b,
                    cells: &ring,
                    touches_infinity,
                });
            }
        }
    }

    /// Fill `ring` with the cells around edge `(a, b)` of cell `t`; mark them done.
    fn edge_ring(&self, t: u32, a: u32, b: u32, ring: &mut Vec<u32>, done: &mut [u8]) -> bool {
        ring.clear();
        let v = self.cells[t as usize].v;
        let ia = local(v, a);
        let ib = local(v, b);
        let (mut k, l) = other_two(ia, ib);
        // Start by leaving through the facet opposite v[k] with (a, b, v[k], v[l]) negatively
        // oriented (an odd permutation of the positive cell): moving from v[k] towards v[l]
        // is then a positive rotation about a → b.
        if is_even_permutation([ia, ib, k, l]) {
            k = l;
        }
        let mut cur = t;
        let mut exit_vertex = v[k];
        let mut infinite = false;
        loop {
            let cv = self.cells[cur as usize].v;
            ring.push(cur);
            infinite |= cv.contains(&INFINITE);
            let (la, lb) = (local(cv, a), local(cv, b));
            done[cur as usize] |= 1 << edge_bit(la, lb);
            let ke = local(cv, exit_vertex);
            // The crossed facet is (a, b, third); the next cell is left through the facet
            // opposite `third`, which keeps turning in the same direction.
            let (x, y) = other_two(la, lb);
            exit_vertex = if x == ke { cv[y] } else { cv[x] };
            let n = self.cells[cur as usize].n[ke] >> 2;
            if n == t {
                break;
            }
            cur = n;
        }
        if infinite {
            // Rotate so that the ring starts right after its infinite cells.
            let last_inf = ring
                .iter()
                .rposition(|&c| !self.is_finite(c))
                .expect("infinite ring has infinite cells");
            let first_inf = ring.iter().position(|&c| !self.is_finite(c)).unwrap();
            let split = if first_inf == 0 && last_inf == ring.len() - 1 {
                // Wrapped: infinite cells at both ends.
                ring.iter().position(|&c| self.is_finite(c)).unwrap_or(0)
            } else {
                last_inf + 1
            };
            let len = ring.len();
            ring.rotate_left(split % len);
        }
        infinite
    }
}

/// Local vertex pairs; the bit index of an edge is its index here.
const LOCAL_EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];

#[inline]
fn edge_bit(i: usize, j: usize) -> usize {
    let (i, j) = if i < j { (i, j) } else { (j, i) };
    match (i, j) {
        (0, 1) => 0,
        (0, 2) => 1,
        (0, 3) => 2,
        (1, 2) => 3,
        (1, 3) => 4,
        _ => 5,
    }
}

#[inline]
fn local(v: [u32; 4], x: u32) -> usize {
    v.iter().position(|&y| y == x).expect("vertex of the cell")
}

fn is_even_permutation(p: [usize; 4]) -> bool {
    let mut inversions = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            if p[i] > p[j] {
                inversions += 1;
            }
        }
    }
    inversions % 2 == 0
}

impl Triangulation {
    /// Triangulate `points`. Vertex ids in the result are indices into `points`; points
    /// equal to an earlier-inserted one are skipped and listed in [`Self::duplicates`].
    ///
    /// Errors: a non-finite coordinate, fewer than four affinely independent points, or
    /// more cells than 29-bit cell ids (or the available memory) allow.
    ///
    /// ```
    /// use bsp2vdg::delaunay::{DelaunayError, Triangulation};
    /// let flat = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    /// assert!(matches!(Triangulation::new(&flat), Err(DelaunayError::Degenerate { .. })));
    /// ```
    pub fn new(points: &[[f64; 3]]) -> Result<Triangulation, super::DelaunayError> {
        Triangulation::new_reporting(points, &crate::progress::NoProgress)
    }

    /// [`Triangulation::new`], reporting the insertions to `progress` (a block of
    /// points at a time) as the stage "Delaunay".
    pub fn new_reporting(
        points: &[[f64; 3]],
        progress: &dyn crate::progress::Progress,
    ) -> Result<Triangulation, super::DelaunayError> {
        if let Some(index) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(super::DelaunayError::NonFinite { index });
        }
        super::build::Builder::run(points, progress)
    }
}

#[cfg(test)]
impl Triangulation {
    pub(super) fn corrupt_swap_vertices(&mut self, t: usize) {
        self.cells[t].v.swap(0, 1);
    }
    pub(super) fn corrupt_neighbor(&mut self, t: usize) {
        self.cells[t].n[0] = self.cells[t].n[1];
    }
    pub(super) fn corrupt_point(&mut self, v: usize, p: [f64; 3]) {
        self.points[v] = p;
    }
}
