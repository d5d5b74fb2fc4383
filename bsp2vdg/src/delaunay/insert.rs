//! Bowyer–Watson insertion: collect the cavity (all cells in conflict with the new point) by
//! a breadth-first search from the located cell, delete it, and star its boundary from the
//! new point.
//!
//! Conflict tests are exact and perturbed (see [`super::predicates::in_conflict`]), so the
//! cavity is exactly the set of cells whose perturbed circumsphere contains the point; it is
//! connected and star-shaped from the point, hence every new cell is positively oriented.
//! An infinite cell is in conflict when the point is strictly outside its hull facet; when
//! the point is exactly in the facet's plane, the answer is taken from the finite cell behind
//! the facet, so both cells always agree (a hull facet joined to a coplanar point would
//! otherwise make a flat cell).
//!
//! The new cells are glued to each other through a small open-addressing hash table keyed by
//! the boundary edge they share; the table and all work lists are reused between insertions.

use super::INFINITE;
use super::build::{Builder, DEAD, IN_CAVITY, NBR_MASK, TESTED};
use super::locate::Location;
use super::predicates::{in_conflict, orient3d};

/// Largest number of cavity boundary vertices glued through the dense `m × m` table (up
/// to 36 KiB, cache resident); larger cavities use the hash table.
pub(super) const MATRIX_GLUE_MAX: usize = 96;

/// Slots of the vertex → local id table (power of two, at least twice the largest `m`).
const VTAB: usize = 256;

/// A boundary facet of the cavity: the new cell's vertices (the old cell with the opposite
/// vertex replaced by the new point at `pos`) and the packed outside neighbour.
#[derive(Clone, Copy)]
struct BoundaryFacet {
    verts: [u32; 4],
    pos: u32,
    outside: u32,
}

/// Work lists reused across insertions.
#[derive(Default)]
pub(super) struct Scratch {
    stack: Vec<u32>,
    cavity: Vec<u32>,
    boundary: Vec<BoundaryFacet>,
    new_cells: Vec<u32>,
    /// Edge hash table: key `(min << 32) | max`, value packed `(cell << 2) | facet`.
    keys: Vec<u64>,
    /// Dense directed-edge table of [`Builder::glue_by_edge_matrix`].
    edge_tab: Vec<u32>,
    /// Vertex id → local id hash table (keys, values, epoch stamps).
    vtab_key: Vec<u32>,
    vtab_val: Vec<u8>,
    vtab_stamp: Vec<u32>,
    vtab_epoch: u32,
    /// Local ids of each boundary facet's vertices (0 at the new point's position).
    local_ids: Vec<[u8; 4]>,
    vals: Vec<u32>,
    slot_epoch: Vec<u32>,
    table_epoch: u32,
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
        s.stack.clear();
        s.cavity.clear();
        s.boundary.clear();
        self.cells[start as usize].n[0] |= IN_CAVITY;
        s.stack.push(start);
        while let Some(c) = s.stack.pop() {
            s.cavity.push(c);
            for i in 0..4 {
                let packed = self.cells[c as usize].n[i] & NBR_MASK;
                let n = packed >> 2;
                let nn = self.cells[n as usize].n;
                if nn[0] & IN_CAVITY != 0 {
                    continue;
                }
                if nn[1] & TESTED == 0 {
                    if self.cell_in_conflict(n, q) {
                        self.cells[n as usize].n[0] |= IN_CAVITY;
                        s.stack.push(n);
                        // Its neighbours are tested next: start loading them now.
                        for &p in &nn {
                            self.prefetch_cell((p & NBR_MASK) >> 2);
                        }
                        continue;
                    }
                    self.cells[n as usize].n[1] |= TESTED;
                }
                let mut verts = self.cells[c as usize].v;
                verts[i] = q;
                s.boundary.push(BoundaryFacet {
                    verts,
                    pos: i as u32,
                    outside: packed,
                });
            }
        }
        // Recycle the cavity's slots (last freed is reused first: good locality).
        for &c in &s.cavity {
            self.cells[c as usize].v = [DEAD; 4];
            self.free.push(c);
        }
        s.new_cells.clear();
        for b in &s.boundary {
            let t = self.alloc();
            self.cells[t as usize].v = b.verts;
            let i = b.pos as usize;
            self.cells[t as usize].n[i] = b.outside;
            let (o, j) = (b.outside >> 2, b.outside & 3);
            let on = &mut self.cells[o as usize].n;
            on[j as usize] = (t << 2) | b.pos;
            on[1] &= NBR_MASK; // clear TESTED
            s.new_cells.push(t);
        }
        if !self.glue_by_edge_matrix(&mut s) {
            self.glue_new_cells(&mut s);
        }
        self.last = s.new_cells[0];
        self.scratch = s;
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
    #[inline]
    fn cell_in_conflict(&self, t: u32, q: u32) -> bool {
        let v = self.cells[t as usize].v;
        match v.iter().position(|&x| x == INFINITE) {
            None => in_conflict(self.pts, v, q),
            Some(k) => {
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
    }

    /// Connect the new cells to each other through a dense table indexed by the local ids of
    /// the two endpoints of each boundary edge. Orienting each edge by the cell's
    /// orientation, the two new cells sharing the facet `(q, x, y)` see it as `x → y` and
    /// `y → x`: one pass writes every directed edge, a second reads its reverse — no
    /// searching, no clearing. Returns `false` (nothing done) for cavities with too many
    /// boundary vertices, which then use the hash table.
    fn glue_by_edge_matrix(&mut self, s: &mut Scratch) -> bool {
        // Local ids come from a 256-slot hash table that stays in L1 (a per-point array
        // would miss the cache for every old vertex of the cavity). Local id 0 is ∞.
        let max = self.matrix_glue_max.min(VTAB / 2);
        if s.vtab_key.len() < VTAB {
            s.vtab_key = vec![0; VTAB];
            s.vtab_val = vec![0; VTAB];
            s.vtab_stamp = vec![0; VTAB];
        }
        s.vtab_epoch = s.vtab_epoch.wrapping_add(1);
        if s.vtab_epoch == 0 {
            s.vtab_stamp.iter_mut().for_each(|e| *e = 0);
            s.vtab_epoch = 1;
        }
        let ep = s.vtab_epoch;
        let mut m = 1usize;
        s.local_ids.clear();
        for b in &s.boundary {
            let mut ids = [0u8; 4];
            for (k, &v) in b.verts.iter().enumerate() {
                if k as u32 == b.pos || v == INFINITE {
                    continue;
                }
                let mut h = (v.wrapping_mul(0x9E37_79B1) >> 24) as usize;
                loop {
                    if s.vtab_stamp[h] != ep {
                        if m > max {
                            return false;
                        }
                        s.vtab_stamp[h] = ep;
                        s.vtab_key[h] = v;
                        s.vtab_val[h] = m as u8;
                        ids[k] = m as u8;
                        m += 1;
                        break;
                    }
                    if s.vtab_key[h] == v {
                        ids[k] = s.vtab_val[h];
                        break;
                    }
                    h = (h + 1) & (VTAB - 1);
                }
            }
            s.local_ids.push(ids);
        }
        if s.edge_tab.len() < m * m {
            s.edge_tab.resize(m * m, 0);
        }
        for ((&t, b), ids) in s.new_cells.iter().zip(&s.boundary).zip(&s.local_ids) {
            let p = b.pos as usize;
            for (k, &(x, y)) in EVEN_REST[p].iter().enumerate() {
                if k != p {
                    let (lx, ly) = (ids[x as usize] as usize, ids[y as usize] as usize);
                    s.edge_tab[lx * m + ly] = (t << 2) | k as u32;
                }
            }
        }
        for ((&t, b), ids) in s.new_cells.iter().zip(&s.boundary).zip(&s.local_ids) {
            let p = b.pos as usize;
            for (k, &(x, y)) in EVEN_REST[p].iter().enumerate() {
                if k != p {
                    let (lx, ly) = (ids[x as usize] as usize, ids[y as usize] as usize);
                    self.cells[t as usize].n[k] = s.edge_tab[ly * m + lx];
                }
            }
        }
        true
    }

    /// Connect the new cells to each other: the facet of a new cell opposite its vertex `k`
    /// contains the new point and one boundary edge, shared by exactly two new cells.
    #[inline(never)]
    fn glue_new_cells(&mut self, s: &mut Scratch) {
        let need = (s.new_cells.len() * 4).next_power_of_two().max(64);
        if s.keys.len() < need {
            s.keys = vec![0; need];
            s.vals = vec![0; need];
            s.slot_epoch = vec![0; need];
            s.table_epoch = 0;
        }
        s.table_epoch = s.table_epoch.wrapping_add(1);
        if s.table_epoch == 0 {
            s.slot_epoch.iter_mut().for_each(|e| *e = 0);
            s.table_epoch = 1;
        }
        let mask = need - 1;
        let shift = 64 - need.trailing_zeros();
        for (&t, b) in s.new_cells.iter().zip(&s.boundary) {
            let p = b.pos as usize;
            for k in 0..4 {
                if k == p {
                    continue;
                }
                let (a, c) = other_two(p, k);
                let (x, y) = (b.verts[a], b.verts[c]);
                let key = ((x.min(y) as u64) << 32) | x.max(y) as u64;
                let mut h = (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> shift) as usize;
                loop {
                    if s.slot_epoch[h] != s.table_epoch {
                        s.slot_epoch[h] = s.table_epoch;
                        s.keys[h] = key;
                        s.vals[h] = (t << 2) | k as u32;
                        break;
                    }
                    if s.keys[h] == key {
                        let other = s.vals[h];
                        self.cells[t as usize].n[k] = other;
                        self.cells[(other >> 2) as usize].n[(other & 3) as usize] =
                            (t << 2) | k as u32;
                        // Each edge is met exactly twice: the slot stays as a tombstone
                        // with a key no third lookup will ask for.
                        break;
                    }
                    h = (h + 1) & mask;
                }
            }
        }
    }
}

/// `EVEN_REST[p][k]` = the two indices `(x, y)` other than `p` and `k` such that
/// `(p, k, x, y)` is an even permutation (meaningless for `k == p`).
const EVEN_REST: [[(u8, u8); 4]; 4] = {
    let mut t = [[(0u8, 0u8); 4]; 4];
    let mut p = 0;
    while p < 4 {
        let mut k = 0;
        while k < 4 {
            if k != p {
                let mut r = [0u8; 2];
                let mut n = 0;
                let mut j = 0;
                while j < 4 {
                    if j != p && j != k {
                        r[n] = j as u8;
                        n += 1;
                    }
                    j += 1;
                }
                // Parity of (p, k, r0, r1): count inversions.
                let perm = [p as u8, k as u8, r[0], r[1]];
                let mut inv = 0;
                let mut a = 0;
                while a < 4 {
                    let mut b = a + 1;
                    while b < 4 {
                        if perm[a] > perm[b] {
                            inv += 1;
                        }
                        b += 1;
                    }
                    a += 1;
                }
                t[p][k] = if inv % 2 == 0 {
                    (r[0], r[1])
                } else {
                    (r[1], r[0])
                };
            }
            k += 1;
        }
        p += 1;
    }
    t
};

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
