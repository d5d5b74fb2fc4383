//! Bowyer–Watson insertion: collect the cavity (all cells in conflict with the new point) by
//! a breadth-first search from the located cell, star its boundary from the new point, and
//! free the cavity's cells.
//!
//! Conflict tests are exact and perturbed (see [`super::predicates::in_conflict`]), so the
//! cavity is exactly the set of cells whose perturbed circumsphere contains the point; it is
//! connected and star-shaped from the point, hence every new cell is positively oriented.
//! An infinite cell is in conflict when the point is strictly outside its hull facet; when
//! the point is exactly in the facet's plane, the answer is taken from the finite cell behind
//! the facet, so both cells always agree (a hull facet joined to a coplanar point would
//! otherwise make a flat cell).
//!
//! The new cells are glued to each other through their boundary edges: the new cell on
//! boundary facet `(c, i)` and its neighbour across the face `(q, x, y)` share the boundary
//! edge `(x, y)`, which the two cells see in opposite directions (both are positively
//! oriented, on either side of the face). The boundary's vertices get small local numbers
//! (a byte per point, reset after each insertion), a first pass records every directed edge
//! in a small square table indexed by the two local numbers, and a second pass reads each
//! cell's neighbours from the reversed edges and writes the cell once, complete — the
//! scheme of HXT's Delaunay kernel (Marot, Pellerin & Remacle 2019). Its table accesses are
//! independent of each other, where turning around the edge through the cavity cells
//! (CGAL's way) is a chain of dependent loads; that walk remains the fallback for cavities
//! whose boundary has more vertices than the table has rows. The gluing does not depend on
//! the method, so neither do the cells. The new cells take the slots freed by the previous
//! insertion (which was next door in the Hilbert order, so still in cache). All work lists
//! are reused between insertions.

use super::INFINITE;
use super::build::{Builder, Cell, DEAD, IN_CAVITY, NBR_MASK, TESTED};
use super::locate::Location;
use super::predicates::{in_conflict, orient3d};

/// A not yet glued neighbour of a new cell (bit 31 set: never a packed neighbour).
const UNSET: u32 = u32::MAX;

/// A boundary facet of the cavity: facet `facet` of the cavity cell `cell`, and the packed
/// outside neighbour across it.
#[derive(Clone, Copy)]
struct BoundaryFacet {
    cell: u32,
    facet: u32,
    outside: u32,
}

/// Rows (and columns) of the edge table: boundary vertices beyond this many make the
/// insertion glue by turning around edges instead. Local number 0 means "none".
const EDGE_TABLE_SIDE: usize = 64;

/// Work lists reused across insertions. The default value holds no memory (the insertion
/// takes the builder's lists out with `std::mem::take` while it works on them).
#[derive(Default)]
pub(super) struct Scratch {
    /// Cavity cells in the order found; doubles as the breadth-first search queue.
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFacet>,
    new_cells: Vec<u32>,
    /// Local number (1..EDGE_TABLE_SIDE) of every boundary vertex of the current insertion,
    /// by vertex id, the infinite vertex's in the last slot; 0 for all other points.
    local: Vec<u8>,
    /// The vertices numbered in `local`, to reset them afterwards.
    numbered: Vec<u32>,
    /// Local numbers of each boundary facet's three vertices, byte `j` for the vertex at
    /// position `j` of the facet's cycle ([`AROUND`]). Packed in a `u32` built in a register: a `[u8; 4]` filled byte
    /// by byte and then read whole stalls on store-to-load forwarding.
    facet_locals: Vec<u32>,
    /// `edges[x * EDGE_TABLE_SIDE + y]`: the packed face `(cell << 2) | index` of the new
    /// cell that sees boundary edge `x → y` (local numbers). Stale entries are never read:
    /// every directed edge read was written by the same insertion.
    edges: Vec<u32>,
}

impl Scratch {
    /// Work lists for triangulating `num_points` points.
    pub(super) fn new(num_points: usize) -> Self {
        Scratch {
            local: vec![0; num_points + 1],
            edges: vec![0; EDGE_TABLE_SIDE * EDGE_TABLE_SIDE],
            ..Default::default()
        }
    }
}

/// For the new cell whose vertex `i` is the new point: its three faces other than the
/// boundary facet, as `(k, x, y)`: the face opposite vertex `k` contains the boundary edge
/// `(x, y)`, ordered so that `(i, k, x, y)` is an even permutation. The cell then sees the
/// edge as `x → y`, and its neighbour across that face (positively oriented too, on the
/// other side) sees it as `y → x`.
const FACES_AROUND: [[(usize, usize, usize); 3]; 4] = {
    let mut t = [[(0, 0, 0); 3]; 4];
    let mut i = 0;
    while i < 4 {
        let mut n = 0;
        let mut k = 0;
        while k < 4 {
            if i != k {
                let (x, y) = other_two(i, k);
                t[i][n] = if is_even([i, k, x, y]) {
                    (k, x, y)
                } else {
                    (k, y, x)
                };
                n += 1;
            }
            k += 1;
        }
        i += 1;
    }
    t
};

/// [`FACES_AROUND`] as a cycle: `AROUND[i] = [k0, k1, k2]`, the new cell's vertices other
/// than `i`, ordered so that its face opposite `k0` sees the boundary edge `k1 → k2`, the
/// face opposite `k1` sees `k2 → k0` and the face opposite `k2` sees `k0 → k1` (the three
/// directed edges go round the boundary facet, all cells being positively oriented). With
/// a facet's local numbers packed in this order, the edge table's indices are taken out at
/// fixed positions (constant shifts), not at positions read from a table.
const AROUND: [[usize; 3]; 4] = {
    let mut t = [[0; 3]; 4];
    let mut i = 0;
    while i < 4 {
        let (k0, k1, k2) = FACES_AROUND[i][0];
        t[i] = [k0, k1, k2];
        // The other two faces must see the other two edges of the cycle.
        let mut n = 1;
        while n < 3 {
            let (k, x, y) = FACES_AROUND[i][n];
            assert!((k == k1 && x == k2 && y == k0) || (k == k2 && x == k0 && y == k1));
            n += 1;
        }
        i += 1;
    }
    t
};

impl Builder<'_> {
    #[inline(never)]
    pub(super) fn insert_point(&mut self, q: u32) {
        let start = match self.locate(q) {
            Location::Duplicate(v) => {
                self.duplicates.push((q, v));
                return;
            }
            Location::Cell(t) => t,
        };
        let mut s = std::mem::take(&mut self.scratch);
        if self.find_cavity(q, start, &mut s) {
            self.star_boundary_by_table(q, &mut s);
        } else {
            self.star_boundary_by_turning(q, &mut s);
        }
        // Recycle the cavity's slots (the next insertion reuses them first: it is next door).
        for &c in &s.cavity {
            self.cells[c as usize].v = [DEAD; 4];
            self.cells[c as usize].n[0] &= NBR_MASK;
            self.free.push(c);
        }
        self.last = s.new_cells[0];
        self.scratch = s;
    }

    /// Breadth-first search of the cells in conflict with `q` from `start` (in conflict).
    /// Cavity cells get the `IN_CAVITY` flag, cells tested and found not in conflict the
    /// `TESTED` flag (so each is tested once); every cavity facet towards a non-cavity cell
    /// is recorded as a boundary facet, and its vertices get their local numbers right away
    /// ([`Self::number_facet`]): the cavity cell's vertices are at hand here, where a
    /// separate pass would read every boundary facet's cell again. Returns whether all
    /// boundary vertices were numbered (false: too many for the edge table; all numbers
    /// are then reset and the gluing turns around edges instead).
    #[inline(always)]
    fn find_cavity(&mut self, q: u32, start: u32, s: &mut Scratch) -> bool {
        s.cavity.clear();
        s.boundary.clear();
        s.facet_locals.clear();
        let mut next = Some(1u8);
        self.cells[start as usize].n[0] |= IN_CAVITY;
        s.cavity.push(start);
        let mut head = 0;
        while let Some(&c) = s.cavity.get(head) {
            head += 1;
            let Cell { v: cv, n: cn } = self.cells[c as usize];
            for (i, &p) in cn.iter().enumerate() {
                let packed = p & NBR_MASK;
                let n = packed >> 2;
                let nn = self.cells[n as usize].n;
                if nn[0] & IN_CAVITY != 0 {
                    continue;
                }
                if nn[1] & TESTED == 0 {
                    if self.cell_in_conflict(n, q) {
                        self.cells[n as usize].n[0] |= IN_CAVITY;
                        s.cavity.push(n);
                        // Its neighbours are tested next: start loading them now.
                        for &p in &nn {
                            self.prefetch_cell((p & NBR_MASK) >> 2);
                        }
                        continue;
                    }
                    self.cells[n as usize].n[1] |= TESTED;
                }
                s.boundary.push(BoundaryFacet {
                    cell: c,
                    facet: i as u32,
                    outside: packed,
                });
                if let Some(first_free) = next {
                    next = Self::number_facet(cv, i, first_free, s);
                }
            }
        }
        next.is_some()
    }

    /// Give the vertices of boundary facet `i` of a cavity cell with vertices `v` local
    /// numbers (those not numbered yet get `next`, `next + 1`, ... below `EDGE_TABLE_SIDE`)
    /// and record the facet's packed local numbers. Returns the next free number, or `None`
    /// (with all numbers reset) when the edge table has no row left.
    #[inline(always)]
    fn number_facet(v: [u32; 4], i: usize, mut next: u8, s: &mut Scratch) -> Option<u8> {
        // The infinite vertex is numbered in the slot after the last point's.
        let infinite_slot = s.local.len() - 1;
        let mut locals = 0u32;
        for (j, &k) in AROUND[i].iter().enumerate() {
            let slot = &mut s.local[(v[k] as usize).min(infinite_slot)];
            if *slot == 0 {
                if next as usize == EDGE_TABLE_SIDE {
                    Self::reset_local_numbers(s);
                    return None;
                }
                *slot = next;
                next += 1;
                s.numbered.push(v[k]);
            }
            locals |= u32::from(*slot) << (8 * j);
        }
        s.facet_locals.push(locals);
        Some(next)
    }

    /// Set the local numbers of this insertion's boundary vertices back to 0.
    #[inline(always)]
    fn reset_local_numbers(s: &mut Scratch) {
        let infinite_slot = s.local.len() - 1;
        for &v in &s.numbered {
            s.local[(v as usize).min(infinite_slot)] = 0;
        }
        s.numbered.clear();
    }

    /// Create one new cell per boundary facet (the cavity cell with the facet's opposite
    /// vertex replaced by `q`), link it with the outside cell both ways, and glue the new
    /// cells to each other through the edge table (see the module documentation): allocate
    /// the new cells while recording which face of which new cell sees each directed
    /// boundary edge, then write every new cell once with all its neighbours.
    #[inline(always)]
    fn star_boundary_by_table(&mut self, q: u32, s: &mut Scratch) {
        const W: usize = EDGE_TABLE_SIDE;
        s.new_cells.clear();
        // A slice of known length: the indices below are less than `W * W` by construction
        // (two local numbers below `W`), so they need no bounds checks.
        let edges = &mut s.edges[..W * W];
        // Index of the directed edge from the vertex at cycle position `a` of a facet (see
        // [`AROUND`]) to the one at position `b`, from the facet's packed local numbers.
        let at = |l: u32, a: usize, b: usize| {
            let local = |j: usize| ((l >> (8 * j)) as usize) % W;
            local(a) * W + local(b)
        };
        for (b, &l) in s.boundary.iter().zip(&s.facet_locals) {
            let t = self.alloc();
            s.new_cells.push(t);
            let ks = AROUND[b.facet as usize];
            for j in 0..3 {
                edges[at(l, (j + 1) % 3, (j + 2) % 3)] = (t << 2) | ks[j] as u32;
            }
        }
        for ((b, &t), &l) in s.boundary.iter().zip(&s.new_cells).zip(&s.facet_locals) {
            let i = b.facet as usize;
            let v = self.cells[b.cell as usize].v;
            // Written field by field: building the cell in a local array and then copying
            // it stalls on store-to-load forwarding (narrow stores, one wide load).
            let new = &mut self.cells[t as usize];
            new.v = v;
            new.v[i] = q;
            new.n[i] = b.outside;
            let ks = AROUND[i];
            for j in 0..3 {
                new.n[ks[j] % 4] = edges[at(l, (j + 2) % 3, (j + 1) % 3)];
            }
            let (o, j) = (b.outside >> 2, b.outside & 3);
            let on = &mut self.cells[o as usize].n;
            on[j as usize] = (t << 2) | b.facet;
            on[1] &= NBR_MASK; // clear TESTED
        }
        Self::reset_local_numbers(s);
    }

    /// [`Self::star_boundary_by_table`] by turning around boundary edges inside the cavity
    /// (CGAL's way): the fallback for boundaries with more vertices than the edge table has
    /// rows.
    #[inline(never)]
    fn star_boundary_by_turning(&mut self, q: u32, s: &mut Scratch) {
        s.new_cells.clear();
        for b in &s.boundary {
            let t = self.alloc();
            let i = b.facet as usize;
            let mut v = self.cells[b.cell as usize].v;
            v[i] = q;
            let mut n = [UNSET; 4];
            n[i] = b.outside;
            self.cells[t as usize] = Cell { v, n };
            let (o, j) = (b.outside >> 2, b.outside & 3);
            let on = &mut self.cells[o as usize].n;
            on[j as usize] = (t << 2) | b.facet;
            on[1] &= NBR_MASK; // clear TESTED
            s.new_cells.push(t);
        }
        for (b, &t) in s.boundary.iter().zip(&s.new_cells) {
            let i = b.facet as usize;
            for k in 0..4 {
                if k != i && self.cells[t as usize].n[k] == UNSET {
                    let (t2, g) = self.across_boundary_edge(b.cell, k, i);
                    self.cells[t as usize].n[k] = (t2 << 2) | g;
                    self.cells[t2 as usize].n[g as usize] = (t << 2) | k as u32;
                }
            }
        }
    }

    /// The new cell across the face `(q, x, y)` of the new cell built on boundary facet `i`
    /// of cavity cell `c`, where `x, y` are `c`'s vertices other than `i` and `k`; returns it
    /// with the index of that face in it.
    ///
    /// Facet `k` of `c` contains `x`, `y` and `c.v[i]`. Cross it; in each cavity cell
    /// entered through a facet `(x, y, z)`, leave through the other facet containing `x, y`
    /// (opposite `z`), until the facet crossed leads out of the cavity: that is the other
    /// boundary facet on edge `(x, y)`, and its new cell is what the outside cell now links
    /// to. Every cell visited was in this cavity, so all of it is in cache.
    #[inline(always)]
    fn across_boundary_edge(&self, c: u32, k: usize, i: usize) -> (u32, u32) {
        // Invariant: facet `f` of `cur` contains x, y and cur.v[g].
        let (mut cur, mut f, mut g) = (c, k, i as u32);
        loop {
            let packed = self.cells[cur as usize].n[f] & NBR_MASK;
            let next = packed >> 2;
            let next_cell = &self.cells[next as usize];
            if next_cell.n[0] & IN_CAVITY == 0 {
                // Boundary facet (cur, f): its new cell is cur with v[f] = q, linked from the
                // outside cell; the face (q, x, y) lies opposite index g in it.
                let t2 = next_cell.n[(packed & 3) as usize] >> 2;
                return (t2, g);
            }
            let z = self.cells[cur as usize].v[g as usize];
            g = packed & 3;
            f = index_of(next_cell.v, z);
            cur = next;
        }
    }

    #[inline(always)]
    fn prefetch_cell(&self, t: u32) {
        #[cfg(target_arch = "x86_64")]
        {
            let p = self.cells.as_ptr().wrapping_add(t as usize) as *const i8;
            // SAFETY: prefetching is a hint; it never faults, even on an invalid address.
            unsafe { std::arch::x86_64::_mm_prefetch(p, std::arch::x86_64::_MM_HINT_T0) };
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = t;
    }

    /// Conflict test of any cell (finite or infinite) with point `q`.
    #[inline(always)]
    fn cell_in_conflict(&self, t: u32, q: u32) -> bool {
        let v = self.cells[t as usize].v;
        if v[0].max(v[1]).max(v[2].max(v[3])) != INFINITE {
            return in_conflict(self.pts, v, q);
        }
        self.infinite_cell_in_conflict(t, v, q)
    }

    /// [`Self::cell_in_conflict`] for a cell with the infinite vertex.
    #[inline(never)]
    fn infinite_cell_in_conflict(&self, t: u32, v: [u32; 4], q: u32) -> bool {
        let k = index_of(v, INFINITE);
        let mut w = v;
        w[k] = q;
        let p = |i: u32| &self.pts[i as usize];
        let o = orient3d(p(w[0]), p(w[1]), p(w[2]), p(w[3]));
        if o != 0.0 {
            o > 0.0
        } else {
            let f = self.cells[t as usize].n[k] >> 2;
            in_conflict(self.pts, self.cells[f as usize].v, q)
        }
    }
}

/// Index of vertex `x` in `v` (which contains it).
#[inline(always)]
fn index_of(v: [u32; 4], x: u32) -> usize {
    // Branch-free: exactly one lane matches.
    let m = (v[1] == x) as usize | (((v[2] == x) as usize) << 1) | (((v[3] == x) as usize) * 3);
    debug_assert!(v[m] == x, "vertex {x} not in {v:?}");
    m
}

/// Whether the permutation `p` of `0..4` is even (an even number of inversions).
const fn is_even(p: [usize; 4]) -> bool {
    let mut inversions = 0;
    let mut a = 0;
    while a < 4 {
        let mut b = a + 1;
        while b < 4 {
            if p[a] > p[b] {
                inversions += 1;
            }
            b += 1;
        }
        a += 1;
    }
    inversions % 2 == 0
}

/// The two indices of `0..4` other than `i` and `k`, in increasing order.
#[inline]
pub(super) const fn other_two(i: usize, k: usize) -> (usize, usize) {
    let mut r = [0usize; 2];
    let mut n = 0;
    let mut j = 0;
    while j < 4 {
        if j != i && j != k {
            r[n] = j;
            n += 1;
        }
        j += 1;
    }
    (r[0], r[1])
}
