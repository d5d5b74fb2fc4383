//! Shared helpers of the unit tests: a tiny deterministic RNG and the
//! standard worlds compiled once.

use std::sync::OnceLock;

use crate::bsp::{Compiled, compile};
use crate::world::{Aabb, World};

/// The workspace's one generator (`toolbox::SplitMix64`) with the draws
/// these tests use.
pub struct Rng(toolbox::SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(toolbox::SplitMix64::new(seed))
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0.next_f64()
    }
    /// Uniform in the box grown by `margin`.
    pub fn point_in(&mut self, b: &Aabb, margin: f64) -> [f64; 3] {
        let mut p = [0.0; 3];
        for (i, c) in p.iter_mut().enumerate() {
            let (lo, hi) = (b.min[i] - margin, b.max[i] + margin);
            *c = lo + (hi - lo) * self.unit();
        }
        p
    }
    /// A uniformly random unit vector.
    pub fn direction(&mut self) -> [f64; 3] {
        loop {
            let v = [0, 1, 2].map(|_| 2.0 * self.unit() - 1.0);
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.1 && l <= 1.0 {
                return v.map(|c| c / l);
            }
        }
    }
}

/// The standard worlds with their compiled trees (built once per test run).
pub fn standard() -> &'static [(World, Compiled)] {
    static CELL: OnceLock<Vec<(World, Compiled)>> = OnceLock::new();
    CELL.get_or_init(|| {
        crate::worlds::worlds()
            .into_iter()
            .map(|w| {
                let c = compile(&w);
                (w, c)
            })
            .collect()
    })
}
