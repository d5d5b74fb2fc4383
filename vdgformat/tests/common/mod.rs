//! Synthetic VDGs whose volume is known analytically, and a seeded PRNG.
#![allow(dead_code)]

use vdgformat::{VdgBuilder, VdgFile};

/// The workspace's one generator (SplitMix64), with the draws the tests use.
pub struct Rng(toolbox::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(toolbox::SplitMix64::new(seed))
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        self.0.next_f64()
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        self.0.range(lo, hi)
    }
    pub fn below(&mut self, n: usize) -> usize {
        self.0.below(n)
    }
    pub fn point(&mut self, lo: [f64; 3], hi: [f64; 3]) -> [f32; 3] {
        [
            self.range(lo[0], hi[0]) as f32,
            self.range(lo[1], hi[1]) as f32,
            self.range(lo[2], hi[2]) as f32,
        ]
    }
}

/// A grid of `nx × ny` cells of size `cell` in the plane z = `height(x, y)`,
/// two triangles per cell, vertex clearance `clear(x, y)`. Cells for which
/// `keep(i, j)` is false are left out (e.g. an L shape).
pub fn grid(
    nx: usize,
    ny: usize,
    cell: f32,
    height: impl Fn(f32, f32) -> f32,
    clear: impl Fn(f32, f32) -> f32,
    keep: impl Fn(usize, usize) -> bool,
) -> VdgBuilder {
    let mut b = VdgBuilder::new();
    let mut ids = vec![u32::MAX; (nx + 1) * (ny + 1)];
    let mut id = |b: &mut VdgBuilder, i: usize, j: usize| {
        let k = j * (nx + 1) + i;
        if ids[k] == u32::MAX {
            let (x, y) = (i as f32 * cell, j as f32 * cell);
            ids[k] = b.add_vertex([x, y, height(x, y)], clear(x, y));
        }
        ids[k]
    };
    for j in 0..ny {
        for i in 0..nx {
            if !keep(i, j) {
                continue;
            }
            let a = id(&mut b, i, j);
            let c = id(&mut b, i + 1, j);
            let d = id(&mut b, i, j + 1);
            let e = id(&mut b, i + 1, j + 1);
            b.add_face([a, c, d]);
            b.add_face([c, e, d]);
        }
    }
    b
}

/// A flat grid with constant clearance.
pub fn flat(nx: usize, ny: usize, cell: f32, r: f32) -> VdgBuilder {
    grid(nx, ny, cell, |_, _| 0.0, |_, _| r, |_, _| true)
}

/// Random faces over random vertices: each face takes a random vertex and
/// two of the next few vertices along a random walk, so faces are local and
/// the graph is (mostly) connected.
pub fn random_soup(nv: usize, nf: usize, rng: &mut Rng) -> VdgBuilder {
    let mut b = VdgBuilder::new();
    let mut p = [0.0f64; 3];
    for _ in 0..nv {
        for c in &mut p {
            *c += rng.range(-40.0, 40.0);
        }
        b.add_vertex(
            [p[0] as f32, p[1] as f32, p[2] as f32],
            rng.range(2.0, 60.0) as f32,
        );
    }
    for _ in 0..nf {
        let a = rng.below(nv - 4);
        let x = a + 1 + rng.below(3);
        let y = x + 1 + rng.below(nv - x - 1).min(2);
        b.add_face([a as u32, x as u32, y as u32]);
    }
    b
}

pub fn open(b: &VdgBuilder) -> VdgFile {
    VdgFile::from_bytes(&b.to_bytes().expect("valid graph")).expect("valid file")
}

/// Distance from `p` to the axis-aligned rectangle [x0,x1]×[y0,y1] in z = 0.
pub fn rect_distance(p: [f32; 3], x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let (x, y, z) = (f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
    let dx = (x0 - x).max(0.0).max(x - x1);
    let dy = (y0 - y).max(0.0).max(y - y1);
    (dx * dx + dy * dy + z * z).sqrt()
}
