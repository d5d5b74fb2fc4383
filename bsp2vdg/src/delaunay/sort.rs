//! Insertion order: a biased randomized insertion order (BRIO) whose rounds are each sorted
//! along a 3D Hilbert curve.
//!
//! Why BRIO: inserting in random order bounds the expected total cavity size (no adversarial
//! sequence of huge cavities, which regular grids of wall samples would otherwise produce
//! when swept in scan order), while sorting each round along a space-filling curve keeps
//! consecutive points close so the walking point location takes O(1) steps and the memory
//! touched stays in cache. Rounds grow geometrically (each is 3× the size of all previous
//! ones together, like CGAL's multiscale sort), so the first points form a coarse random
//! sample of the whole domain. The shuffle uses a fixed seed: the order is deterministic.
//! The keys are computed and the rounds sorted on all threads (rayon); the keys of distinct
//! indices make every sort key unique, so the order does not depend on the thread count.

use rayon::prelude::*;

use toolbox::SplitMix64;
/// Bits per axis of the Hilbert key (3 × 21 = 63 bits).
const HILBERT_BITS: u32 = 21;

/// Rounds smaller than this are merged into the first one.
const MIN_ROUND: usize = 64;

/// Spread the low 21 bits of `v` so that bit i moves to bit 3i.
fn spread3(v: u32) -> u64 {
    let mut x = (v as u64) & 0x1f_ffff;
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// Position of the grid cell `(x, y, z)` (each `< 2^HILBERT_BITS`) along the Hilbert curve
/// (Skilling's transpose algorithm, "Programming the Hilbert curve", 2004).
///
/// Written without data-dependent branches: on unsorted input every bit test of the
/// textbook form is a coin flip for the branch predictor, which cost more than the
/// arithmetic. Each conditional update is applied through an all-ones/all-zeros mask.
pub fn hilbert_key(x: u32, y: u32, z: u32) -> u64 {
    let mut a = [x, y, z];
    let m = 1u32 << (HILBERT_BITS - 1);
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            // if a[i] has bit q: invert the low bits of a[0]; else exchange them with a[i]'s.
            let set = ((a[i] & q) != 0) as u32;
            let mask = set.wrapping_neg();
            let t = (a[0] ^ a[i]) & p & !mask;
            a[0] ^= (p & mask) | t;
            a[i] ^= t;
        }
        q >>= 1;
    }
    a[1] ^= a[0];
    a[2] ^= a[1];
    let mut t = 0;
    q = m;
    while q > 1 {
        t ^= (q - 1) & (((a[2] & q) != 0) as u32).wrapping_neg();
        q >>= 1;
    }
    for v in &mut a {
        *v ^= t;
    }
    (spread3(a[0]) << 2) | (spread3(a[1]) << 1) | spread3(a[2])
}

/// The textbook (branching) form of [`hilbert_key`], kept as the test's reference.
#[cfg(test)]
fn hilbert_key_reference(x: u32, y: u32, z: u32) -> u64 {
    let mut a = [x, y, z];
    let m = 1u32 << (HILBERT_BITS - 1);
    let mut q = m;
    while q > 1 {
        let p = q - 1;
        for i in 0..3 {
            if a[i] & q != 0 {
                a[0] ^= p;
            } else {
                let t = (a[0] ^ a[i]) & p;
                a[0] ^= t;
                a[i] ^= t;
            }
        }
        q >>= 1;
    }
    a[1] ^= a[0];
    a[2] ^= a[1];
    let mut t = 0;
    q = m;
    while q > 1 {
        if a[2] & q != 0 {
            t ^= q - 1;
        }
        q >>= 1;
    }
    for v in &mut a {
        *v ^= t;
    }
    (spread3(a[0]) << 2) | (spread3(a[1]) << 1) | spread3(a[2])
}

/// Hilbert keys of all points on a common cubic grid over their bounding box.
pub(crate) fn hilbert_keys(points: &[[f64; 3]]) -> Vec<u64> {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
    let cells = ((1u32 << HILBERT_BITS) - 1) as f64;
    let scale = if extent > 0.0 { cells / extent } else { 0.0 };
    points
        .par_iter()
        .map(|p| {
            let q = |k: usize| (((p[k] - lo[k]) * scale) as u32).min(cells as u32);
            hilbert_key(q(0), q(1), q(2))
        })
        .collect()
}

/// The BRIO insertion order of `points`: indices, deterministic for a given input.
pub fn brio_order(points: &[[f64; 3]]) -> Vec<u32> {
    let n = points.len();
    let keys = hilbert_keys(points);
    let mut order: Vec<u32> = (0..n as u32).collect();
    let mut rng = SplitMix64::new(0x5EED_DE1A_0A11_u64);
    for i in (1..n).rev() {
        let j = rng.below(i + 1);
        order.swap(i, j);
    }
    let mut end = n;
    let mut scratch: Vec<(u64, u32)> = Vec::new();
    while end > 0 {
        let start = if end / 4 < MIN_ROUND { 0 } else { end / 4 };
        scratch.clear();
        scratch.extend(order[start..end].iter().map(|&i| (keys[i as usize], i)));
        scratch.par_sort_unstable();
        for (slot, &(_, i)) in order[start..end].iter_mut().zip(&scratch) {
            *slot = i;
        }
        end = start;
    }
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hilbert_keys_are_a_bijection_on_a_small_grid_with_adjacent_steps() {
        // On a 2^21 grid, consecutive keys of the 4×4×4 corner block are not guaranteed
        // contiguous, but the curve must be injective and consecutive cells adjacent.
        let mut cells: Vec<(u64, [u32; 3])> = Vec::new();
        let s = 1u32 << (HILBERT_BITS - 2);
        for x in 0..4 {
            for y in 0..4 {
                for z in 0..4 {
                    // Cells of a coarse 4×4×4 grid: the Hilbert curve visits each coarse
                    // block in one contiguous run, so block order is a 3D Hilbert curve.
                    cells.push((hilbert_key(x * s, y * s, z * s), [x, y, z]));
                }
            }
        }
        cells.sort_unstable();
        cells.dedup_by_key(|c| c.0);
        assert_eq!(cells.len(), 64);
        for w in cells.windows(2) {
            let d: u32 = (0..3).map(|k| w[0].1[k].abs_diff(w[1].1[k])).sum();
            assert_eq!(
                d, 1,
                "consecutive coarse blocks must be face-adjacent: {w:?}"
            );
        }
    }

    #[test]
    fn branch_free_hilbert_key_matches_the_textbook_form() {
        let mut rng = SplitMix64::new(11);
        let max = (1u32 << HILBERT_BITS) - 1;
        for i in 0..100_000 {
            let mut c = || (rng.next_u64() as u32) & max;
            let (x, y, z) = if i < 8 {
                // The corners.
                ((i & 1) * max, (i >> 1 & 1) * max, (i >> 2 & 1) * max)
            } else {
                (c(), c(), c())
            };
            assert_eq!(hilbert_key(x, y, z), hilbert_key_reference(x, y, z));
        }
    }

    #[test]
    fn brio_is_a_deterministic_permutation() {
        let mut rng = SplitMix64::new(7);
        let pts: Vec<[f64; 3]> = (0..5000)
            .map(|_| [0, 1, 2].map(|_| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64))
            .collect();
        let a = brio_order(&pts);
        let b = brio_order(&pts);
        assert_eq!(a, b);
        let mut s = a.clone();
        s.sort_unstable();
        assert!(s.iter().enumerate().all(|(i, &v)| v as usize == i));
    }
}
