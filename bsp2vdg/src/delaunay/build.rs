//! The incremental builder: the mutable tetrahedra store shared by point location
//! ([`super::locate`]) and cavity insertion ([`super::insert`]), the initial simplex, and the
//! final compaction into a [`Triangulation`].

use rayon::prelude::*;

use super::predicates::{collinear, orient_ids};
use super::sort::brio_order;
use super::triangulation::Triangulation;
use super::{DelaunayError, INFINITE};
use crate::progress::{Progress, Ticker};

/// Marks a tetrahedron slot that is on the free list.
pub(super) const DEAD: u32 = u32::MAX - 1;

/// Largest number of tetrahedron slots: 2 bits of a packed neighbour hold the facet index
/// and the top bit is a flag.
const MAX_TETS: usize = 1 << 29;

/// Flag bit in `Cell::n[0]`: the cell is in the cavity of the current insertion.
pub(super) const IN_CAVITY: u32 = 1 << 31;
/// Flag bit in `Cell::n[1]`: the cell was tested during this insertion and is not in conflict.
pub(super) const TESTED: u32 = 1 << 31;
/// Mask removing the flag bit from a packed neighbour.
pub(super) const NBR_MASK: u32 = !(1 << 31);

/// One tetrahedron while building: 4 vertex ids and 4 packed neighbours
/// (`tet << 2 | facet`, neighbour `i` opposite vertex `i`; bit 31 of `n[0]`/`n[1]` are the
/// insertion's visit flags). 32 bytes, aligned so a cell is one half cache line: the
/// cavity search reads a cell's flags, vertices and neighbours with one memory access.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub(super) struct Cell {
    pub v: [u32; 4],
    pub n: [u32; 4],
}

/// Builder state: 32 bytes per cell, plus small work lists reused by every insertion.
pub(super) struct Builder<'a> {
    pub pts: &'a [[f64; 3]],
    pub cells: Vec<Cell>,
    pub free: Vec<u32>,
    /// A live tetrahedron near the last inserted point: where the next walk starts.
    pub last: u32,
    /// State of the deterministic "stochastic" walk (xorshift32).
    pub walk_rng: u32,
    pub duplicates: Vec<(u32, u32)>,
    pub scratch: super::insert::Scratch,
    /// Set when a cell could not be allocated; the triangulation is then abandoned.
    pub overflow: bool,
}

impl<'a> Builder<'a> {
    /// Triangulate `input` (already checked to be finite).
    ///
    /// The points are copied in insertion order and get internal ids `0..n` in that order:
    /// consecutive insertions then touch neighbouring memory. Ids are mapped back to input
    /// indices when the result is assembled.
    pub fn run(
        input: &[[f64; 3]],
        progress: &dyn Progress,
    ) -> Result<Triangulation, DelaunayError> {
        if input.len() >= (MAX_TETS / 8) {
            return Err(DelaunayError::TooManyPoints { count: input.len() });
        }
        let order = brio_order(input);
        let sorted: Vec<[f64; 3]> = order.par_iter().map(|&i| input[i as usize]).collect();
        let simplex = {
            let ids: Vec<u32> = (0..sorted.len() as u32).collect();
            initial_simplex(&sorted, &ids)?
        };
        let Builder {
            cells, duplicates, ..
        } = Builder::triangulate(&sorted, simplex, progress)?;
        // Free what is no longer needed before the renumbering table and the result's copy
        // of the points are allocated: they do not add to the peak memory then.
        drop(sorted);
        let (cells, num_finite, duplicates) = finish(cells, duplicates, &order);
        drop(order);
        Ok(Triangulation::from_parts(
            input.to_vec(),
            cells,
            num_finite,
            duplicates,
        ))
    }

    fn triangulate(
        pts: &'a [[f64; 3]],
        simplex: [u32; 4],
        progress: &dyn Progress,
    ) -> Result<Self, DelaunayError> {
        // ~6.7 cells per point for uniform input, ~5.5 on wall samples.
        let cap = (pts.len().saturating_mul(27) / 4).min(MAX_TETS);
        let mut b = Builder {
            pts,
            cells: Vec::new(),
            free: Vec::new(),
            last: 0,
            walk_rng: 0x2545_F491,
            duplicates: Vec::new(),
            scratch: super::insert::Scratch::new(pts.len()),
            overflow: false,
        };
        // Reserve the estimate if the allocator can; otherwise grow on demand (and fail
        // with an error, never an abort, if even that is impossible).
        let _ = b.cells.try_reserve_exact(cap);
        b.create_simplex(simplex);
        let ticker = Ticker::start(progress, "Delaunay", pts.len() as u64, 4 * Ticker::BLOCK);
        let mut done = ticker.local();
        for q in 0..pts.len() as u32 {
            done.tick();
            if simplex.contains(&q) {
                continue;
            }
            b.insert_point(q);
            if b.overflow {
                return Err(DelaunayError::TooManyPoints { count: pts.len() });
            }
        }
        Ok(b)
    }

    #[inline]
    pub fn alloc(&mut self) -> u32 {
        if let Some(t) = self.free.pop() {
            t
        } else {
            if self.cells.len() == self.cells.capacity() {
                // Grow by a quarter, not double: the estimate is usually close.
                let more = self.cells.len() / 4 + 1024;
                if self.cells.len() >= MAX_TETS || self.cells.try_reserve_exact(more).is_err() {
                    // Out of cell ids or memory: the caller abandons the build.
                    self.overflow = true;
                    return 0;
                }
            }
            self.cells.push(Cell {
                v: [DEAD; 4],
                n: [0; 4],
            });
            (self.cells.len() - 1) as u32
        }
    }

    /// The first tetrahedron (positively oriented) and its four infinite neighbours.
    fn create_simplex(&mut self, mut s: [u32; 4]) {
        if orient_ids(self.pts, s) < 0.0 {
            s.swap(0, 1);
        }
        let f = self.alloc();
        self.cells[f as usize].v = s;
        for i in 0..4 {
            // Infinite cell on facet i: vertex i replaced by ∞, then two finite vertices
            // swapped, so that "∞ replaced by q is positive" means q is outside facet i.
            let t = self.alloc();
            let mut v = s;
            v[i] = INFINITE;
            let (a, b) = match i {
                0 => (1, 2),
                1 => (0, 2),
                _ => (0, 1),
            };
            v.swap(a, b);
            self.cells[t as usize].v = v;
            self.cells[f as usize].n[i] = (t << 2) | i as u32;
            self.cells[t as usize].n[i] = (f << 2) | i as u32;
        }
        // Infinite cells are glued along facets that contain ∞.
        for t in 1..5u32 {
            for k in 0..4 {
                if self.cells[t as usize].v[k] == INFINITE {
                    continue;
                }
                let missing = self.cells[t as usize].v[k];
                let facet: Vec<u32> = self.cells[t as usize]
                    .v
                    .iter()
                    .copied()
                    .filter(|&v| v != missing)
                    .collect();
                let (other, j) = (1..5u32)
                    .filter(|&u| u != t)
                    .find_map(|u| {
                        let vu = self.cells[u as usize].v;
                        if facet.iter().all(|x| vu.contains(x)) {
                            let j = vu.iter().position(|x| !facet.contains(x)).unwrap();
                            Some((u, j))
                        } else {
                            None
                        }
                    })
                    .expect("the four infinite cells of a simplex are pairwise adjacent");
                self.cells[t as usize].n[k] = (other << 2) | j as u32;
            }
        }
        self.last = f;
    }
}

/// Drop free slots and renumber in place: finite cells first, then infinite ones, each in
/// slot order (deterministic); map vertex ids back to input indices. Returns the cells, the
/// number of finite ones and the duplicates (as input indices). In place, so the peak
/// memory is the cell array plus a 4-byte remap per slot and a copy of the infinite cells.
fn finish(
    mut cells: Vec<Cell>,
    duplicates: Vec<(u32, u32)>,
    order: &[u32],
) -> (Vec<Cell>, usize, Vec<(u32, u32)>) {
    let to_input = |v: u32| if v == INFINITE { v } else { order[v as usize] };
    let live = |c: &Cell| c.v[0] != DEAD;
    let mut remap = vec![u32::MAX; cells.len()];
    let mut next = 0u32;
    for (t, c) in cells.iter().enumerate() {
        if live(c) && !c.v.contains(&INFINITE) {
            remap[t] = next;
            next += 1;
        }
    }
    let num_finite = next as usize;
    let num_infinite = cells
        .iter()
        .filter(|c| live(c) && c.v.contains(&INFINITE))
        .count();
    let mut infinite = Vec::with_capacity(num_infinite);
    for (t, c) in cells.iter().enumerate() {
        if live(c) && c.v.contains(&INFINITE) {
            remap[t] = next;
            next += 1;
            infinite.push(*c);
        }
    }
    // Finite cells move down (remap[t] <= t), so a forward pass never overwrites a
    // cell before it is moved.
    for t in 0..cells.len() {
        let r = remap[t] as usize;
        if r < num_finite {
            cells[r] = cells[t];
        }
    }
    cells.truncate(num_finite);
    cells.extend_from_slice(&infinite);
    drop(infinite);
    // No shrink_to_fit: with 32-byte alignment the system allocator's realloc copies,
    // doubling the peak memory for a few unused slots.
    // Each cell is rewritten from itself and the two read-only maps: in parallel.
    cells.par_iter_mut().for_each(|c| {
        debug_assert!(c.n[0] & IN_CAVITY == 0 && c.n[1] & TESTED == 0);
        for k in 0..4 {
            c.v[k] = to_input(c.v[k]);
            let p = c.n[k];
            c.n[k] = (remap[(p >> 2) as usize] << 2) | (p & 3);
        }
    });
    drop(remap);
    let mut duplicates: Vec<(u32, u32)> = duplicates
        .into_iter()
        .map(|(d, v)| (to_input(d), to_input(v)))
        .collect();
    duplicates.sort_unstable();
    (cells, num_finite, duplicates)
}

/// Four affinely independent points, the earliest possible in insertion order (the first
/// BRIO round is a random sample, so they span the domain well). Points skipped on the way
/// are inserted normally later (duplicates among them are then detected by the walk).
fn initial_simplex(pts: &[[f64; 3]], order: &[u32]) -> Result<[u32; 4], DelaunayError> {
    let p = |i: u32| &pts[i as usize];
    let too_few = || DelaunayError::Degenerate { count: pts.len() };
    let &a = order.first().ok_or_else(too_few)?;
    let b = *order.iter().find(|&&i| p(i) != p(a)).ok_or_else(too_few)?;
    let c = *order
        .iter()
        .find(|&&i| !collinear(p(a), p(b), p(i)))
        .ok_or_else(too_few)?;
    let d = *order
        .iter()
        .find(|&&i| orient_ids(pts, [a, b, c, i]) != 0.0)
        .ok_or_else(too_few)?;
    Ok([a, b, c, d])
}

#[cfg(test)]
mod tests {
    use super::Builder;

    /// The parallel parts (sort keys, round sorts, the final renumbering) must not make the
    /// result depend on the number of threads.
    #[test]
    fn same_triangulation_on_one_and_two_threads() {
        let mut rng = toolbox::SplitMix64::new(3);
        let pts: Vec<[f64; 3]> = (0..30_000)
            .map(|i| {
                let mut c = || (rng.next_u64() % 64) as f64 * 0.5;
                // Half on a grid (ties), half random.
                if i % 2 == 0 {
                    [c(), c(), c()]
                } else {
                    [0, 1, 2].map(|_| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64 * 32.0)
                }
            })
            .collect();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| Builder::run(&pts, &crate::progress::NoProgress).unwrap())
        };
        let (one, two) = (run(1), run(2));
        assert!(one.cells().eq(two.cells()));
        assert_eq!(one.num_finite_cells(), two.num_finite_cells());
        assert_eq!(one.duplicates(), two.duplicates());
        for t in 0..one.num_cells() as u32 {
            assert_eq!(one.neighbors(t), two.neighbors(t));
        }
    }

    /// A point at the centre of nearly cospherical points is joined to all of them; inserted
    /// late, its cavity is most of the triangulation, glued by turning around hundreds of
    /// boundary edges. `validate` checks the cells against the *input* coordinates, so it
    /// also checks that vertex ids were mapped back from the builder's sorted copy.
    #[test]
    fn huge_cavity_is_glued_validly_and_ids_are_input_indices() {
        let mut pts = Vec::new();
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        for i in 0..400 {
            // Fibonacci sphere, rounded to a grid: nearly (not exactly) cospherical.
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 400.0;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f64;
            pts.push([
                (r * a.cos() * 1e3).round(),
                (r * a.sin() * 1e3).round(),
                (z * 1e3).round(),
            ]);
        }
        pts.push([0.0, 0.0, 0.0]);
        let tri = Builder::run(&pts, &crate::progress::NoProgress).unwrap();
        tri.validate().unwrap();
        // Every point is a hull vertex or the centre: the centre has cells to all of them.
        let centre = pts.len() as u32 - 1;
        let mut touching = std::collections::BTreeSet::new();
        for c in tri.cells() {
            if c.contains(&centre) {
                touching.extend(c.iter().copied().filter(|&v| v != centre));
            }
        }
        assert_eq!(touching.len(), pts.len() - tri.duplicates().len() - 1);
    }
}
