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
//! The new cells are glued to each other the way CGAL does it, without any table: the new
//! cell on boundary facet `(c, i)` and its neighbour across the face `(q, x, y)` share the
//! boundary edge `(x, y)`; turning around that edge through the (still intact) cavity cells,
//! starting from `c`, reaches the other boundary facet containing the edge, whose new cell is
//! found through the outside cell's back link. The cavity's cells are therefore freed only
//! after gluing, and the new cells take the slots freed by the previous insertion (which was
//! next door in the Hilbert order, so still in cache). All work lists are reused between
//! insertions.

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

/// Work lists reused across insertions.
#[derive(Default)]
pub(super) struct Scratch {
    /// Cavity cells in the order found; doubles as the breadth-first search queue.
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFacet>,
    new_cells: Vec<u32>,
}

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
        self.find_cavity(q, start, &mut s);
        self.star_boundary(q, &mut s);
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
    /// is recorded as a boundary facet.
    #[inline(always)]
    fn find_cavity(&mut self, q: u32, start: u32, s: &mut Scratch) {
        s.cavity.clear();
        s.boundary.clear();
        self.cells[start as usize].n[0] |= IN_CAVITY;
        s.cavity.push(start);
        let mut head = 0;
        while let Some(&c) = s.cavity.get(head) {
            head += 1;
            let cn = self.cells[c as usize].n;
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
            }
        }
    }

    /// Create one new cell per boundary facet (the cavity cell with the facet's opposite
    /// vertex replaced by `q`), link it with the outside cell both ways, then glue the new
    /// cells to each other by turning around boundary edges inside the cavity.
    #[inline(always)]
    fn star_boundary(&mut self, q: u32, s: &mut Scratch) {
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

/// The two indices of `0..4` other than `i` and `k`.
#[inline]
pub(super) fn other_two(i: usize, k: usize) -> (usize, usize) {
    let mut r = [0usize; 2];
    let mut n = 0;
    for j in 0..4 {
        if j != i && j != k {
            r[n] = j;
            n += 1;
        }
    }
    (r[0], r[1])
}
