//! The incremental builder: the mutable tetrahedra store shared by point location
//! ([`super::locate`]) and cavity insertion ([`super::insert`]), the initial simplex, and the
//! final compaction into a [`Triangulation`].

use super::predicates::{collinear, orient_ids};
use super::sort::brio_order;
use super::triangulation::Triangulation;
use super::{DelaunayError, INFINITE};

/// Marks a tetrahedron slot that is on the free list.
pub(super) const DEAD: u32 = u32::MAX - 1;

/// Largest number of tetrahedron slots: 2 bits of a packed neighbour hold the facet index.
const MAX_TETS: usize = 1 << 30;

/// Builder state. Per tetrahedron: 16 bytes of vertices, 16 bytes of packed neighbours
/// (`tet << 2 | facet`, neighbour `i` opposite vertex `i`) and a 4-byte visit stamp.
pub(super) struct Builder<'a> {
    pub pts: &'a [[f64; 3]],
    pub verts: Vec<[u32; 4]>,
    pub nbrs: Vec<[u32; 4]>,
    /// `2·epoch` = in the cavity of the current insertion, `2·epoch + 1` = tested, not in it.
    pub stamp: Vec<u32>,
    pub epoch: u32,
    pub free: Vec<u32>,
    /// A live tetrahedron near the last inserted point: where the next walk starts.
    pub last: u32,
    /// State of the deterministic "stochastic" walk (xorshift32).
    pub walk_rng: u32,
    pub duplicates: Vec<(u32, u32)>,
    pub scratch: super::insert::Scratch,
    /// Per point: local index in the current cavity boundary, and the epoch it was set in.
    pub vlocal: Vec<u32>,
    pub vstamp: Vec<u32>,
}

impl<'a> Builder<'a> {
    /// Triangulate `input` (already checked to be finite).
    ///
    /// The points are copied in insertion order and get internal ids `0..n` in that order:
    /// consecutive insertions then touch neighbouring memory. Ids are mapped back to input
    /// indices when the result is assembled.
    pub fn run(input: &[[f64; 3]]) -> Result<Triangulation, DelaunayError> {
        if input.len() >= (MAX_TETS / 8) {
            return Err(DelaunayError::TooManyPoints { count: input.len() });
        }
        let order = brio_order(input);
        let sorted: Vec<[f64; 3]> = order.iter().map(|&i| input[i as usize]).collect();
        let ids: Vec<u32> = (0..sorted.len() as u32).collect();
        let simplex = initial_simplex(&sorted, &ids)?;
        let b = Builder::triangulate(&sorted, simplex)?;
        Ok(b.finish(input, &order))
    }

    fn triangulate(pts: &'a [[f64; 3]], simplex: [u32; 4]) -> Result<Self, DelaunayError> {
        // Rough capacity: ~6.5 tetrahedra per point for uniform input, fewer on surfaces.
        let cap = pts.len().saturating_mul(7).min(MAX_TETS);
        let mut b = Builder {
            pts,
            verts: Vec::with_capacity(cap),
            nbrs: Vec::with_capacity(cap),
            stamp: Vec::with_capacity(cap),
            epoch: 0,
            free: Vec::new(),
            last: 0,
            walk_rng: 0x2545_F491,
            duplicates: Vec::new(),
            scratch: Default::default(),
            vlocal: vec![0; pts.len()],
            vstamp: vec![0; pts.len()],
        };
        b.create_simplex(simplex);
        for q in 0..pts.len() as u32 {
            if simplex.contains(&q) {
                continue;
            }
            if b.verts.len() >= MAX_TETS - 64 {
                return Err(DelaunayError::TooManyPoints { count: pts.len() });
            }
            b.insert_point(q);
        }
        Ok(b)
    }

    #[inline]
    pub fn alloc(&mut self) -> u32 {
        if let Some(t) = self.free.pop() {
            t
        } else {
            self.verts.push([DEAD; 4]);
            self.nbrs.push([0; 4]);
            self.stamp.push(0);
            (self.verts.len() - 1) as u32
        }
    }

    /// The first tetrahedron (positively oriented) and its four infinite neighbours.
    fn create_simplex(&mut self, mut s: [u32; 4]) {
        if orient_ids(self.pts, s) < 0.0 {
            s.swap(0, 1);
        }
        let f = self.alloc();
        self.verts[f as usize] = s;
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
            self.verts[t as usize] = v;
            self.nbrs[f as usize][i] = (t << 2) | i as u32;
            self.nbrs[t as usize][i] = (f << 2) | i as u32;
        }
        // Infinite cells are glued along facets that contain ∞.
        for t in 1..5u32 {
            for k in 0..4 {
                if self.verts[t as usize][k] == INFINITE {
                    continue;
                }
                let missing = self.verts[t as usize][k];
                let facet: Vec<u32> = self.verts[t as usize]
                    .iter()
                    .copied()
                    .filter(|&v| v != missing)
                    .collect();
                let (other, j) = (1..5u32)
                    .filter(|&u| u != t)
                    .find_map(|u| {
                        let vu = self.verts[u as usize];
                        if facet.iter().all(|x| vu.contains(x)) {
                            let j = vu.iter().position(|x| !facet.contains(x)).unwrap();
                            Some((u, j))
                        } else {
                            None
                        }
                    })
                    .expect("the four infinite cells of a simplex are pairwise adjacent");
                self.nbrs[t as usize][k] = (other << 2) | j as u32;
            }
        }
        self.last = f;
    }

    /// Drop free slots and renumber: finite tetrahedra first, then infinite ones, each in
    /// slot order (deterministic); map vertex ids back to input indices.
    fn finish(self, input: &[[f64; 3]], order: &[u32]) -> Triangulation {
        let Builder {
            verts,
            nbrs,
            stamp,
            duplicates,
            vlocal,
            vstamp,
            ..
        } = self;
        drop((stamp, vlocal, vstamp));
        let to_input = |v: u32| if v == INFINITE { v } else { order[v as usize] };
        let mut remap = vec![u32::MAX; verts.len()];
        let mut next = 0u32;
        for (t, v) in verts.iter().enumerate() {
            if v[0] != DEAD && !v.contains(&INFINITE) {
                remap[t] = next;
                next += 1;
            }
        }
        let num_finite = next as usize;
        for (t, v) in verts.iter().enumerate() {
            if v[0] != DEAD && v.contains(&INFINITE) {
                remap[t] = next;
                next += 1;
            }
        }
        let total = next as usize;
        let mut new_verts = vec![[0u32; 4]; total];
        for (t, v) in verts.iter().enumerate() {
            if remap[t] != u32::MAX {
                new_verts[remap[t] as usize] = v.map(to_input);
            }
        }
        drop(verts);
        let mut new_nbrs = vec![[0u32; 4]; total];
        for (t, n) in nbrs.iter().enumerate() {
            if remap[t] != u32::MAX {
                new_nbrs[remap[t] as usize] = n.map(|p| (remap[(p >> 2) as usize] << 2) | (p & 3));
            }
        }
        drop(nbrs);
        let mut duplicates: Vec<(u32, u32)> = duplicates
            .into_iter()
            .map(|(d, v)| (to_input(d), to_input(v)))
            .collect();
        duplicates.sort_unstable();
        Triangulation::from_parts(input.to_vec(), new_verts, new_nbrs, num_finite, duplicates)
    }
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
