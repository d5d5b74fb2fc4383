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
// `hilbert_key` takes the top level alone and the others two at a time.
const _: () = assert!(HILBERT_BITS % 2 == 1);

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
/// of Skilling's transpose algorithm ("Programming the Hilbert curve", 2004; the textbook
/// form is [`hilbert_key_reference`]), computed by a state machine ([`HILBERT_TABLE`]).
///
/// Why a table: the transpose algorithm works on all 21 levels at every step (about 770
/// instructions a key, 3 % of a triangulation's instructions); the state machine does one
/// lookup per two levels ([`HILBERT_TABLE2`]).
pub fn hilbert_key(x: u32, y: u32, z: u32) -> u64 {
    // Bit `3l + 2` is x's bit `l`, `3l + 1` y's, `3l` z's: level `l`'s octant at `3l`.
    let octants = (spread3(x) << 2) | (spread3(y) << 1) | spread3(z);
    // The top level (20) from the initial state, then the other 20 two at a time.
    let top = HILBERT_TABLE[((octants >> (3 * (HILBERT_BITS - 1))) & 7) as usize];
    let mut key = u64::from(top & 7);
    let mut row = usize::from(top >> 3) * 64;
    for pair in (0..(HILBERT_BITS - 1) / 2).rev() {
        let two = ((octants >> (6 * pair)) & 63) as usize;
        // `% len`: the table is padded to a power of two, so this spares the bounds check.
        let e = HILBERT_TABLE2[(row | two) % HILBERT_TABLE2.len()];
        key = (key << 6) | u64::from(e & 63);
        row = usize::from(e & !63);
    }
    key
}

/// States of [`hilbert_key`]'s machine: what Skilling's algorithm has done to the lower
/// bits when it reaches a level — a signed permutation of the axes (`X_i = x_{perm[i]} ⊕
/// flip_i` for the original coordinates' lower bits; 6 permutations × 8 sign masks) — and
/// the parity of the Gray-coded third coordinate's bits above (which its final "t" step
/// XORs into every lower bit): 96 states.
const HILBERT_STATES: usize = 6 * 8 * 2;

/// [`HILBERT_TABLE`] two levels at a time: `HILBERT_TABLE2[64 · state + (high octant << 3 |
/// low octant)]` is `next state << 6 | the two digits`, so `entry & !63` is the next
/// state's row. Padded to a power of two (the pad is never read).
const HILBERT_TABLE2: [u16; 8192] = {
    let mut table = [0u16; 8192];
    let mut state = 0;
    while state < HILBERT_STATES {
        let mut two = 0;
        while two < 64 {
            let first = HILBERT_TABLE[state * 8 + two / 8] as usize;
            let second = HILBERT_TABLE[(first >> 3) * 8 + two % 8] as usize;
            let digits = ((first & 7) << 3) | (second & 7);
            table[state * 64 + two] = (((second >> 3) << 6) | digits) as u16;
            two += 1;
        }
        state += 1;
    }
    table
};

/// Bit of `axis` (0: x, the high bit) in a level's `octant`.
const fn octant_bit(octant: usize, axis: usize) -> usize {
    (octant >> (2 - axis)) & 1
}

/// The axis permutations, by index.
const PERMS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [0, 2, 1],
    [1, 0, 2],
    [1, 2, 0],
    [2, 0, 1],
    [2, 1, 0],
];

/// `HILBERT_TABLE[8 · state + octant]` (octant bits: x, y, z from high to low) is
/// `next state << 3 | key digit`. Built from one level of Skilling's algorithm:
///
/// * the level's bits are `X_i = x_{perm[i]} ⊕ flip_i`;
/// * "inverse undo": for `i = 0, 1, 2`, if `X_i` is set the lower bits of `X_0` are
///   inverted (`flip_0 ^= 1`), else the lower bits of `X_0` and `X_i` are exchanged (swap
///   `(perm[0], flip_0)` with `(perm[i], flip_i)`); the level's own bits are not changed;
/// * Gray code: `G_0 = X_0`, `G_1 = X_1 ⊕ G_0`, `G_2 = X_2 ⊕ G_1`, each XORed with the
///   parity of `G_2` over the levels above (the "t" step); the digit is `(G_0, G_1, G_2)`
///   and the next level's parity is the parity XOR this level's `G_2`.
///
/// The test `table_hilbert_key_matches_the_textbook_form` checks it against
/// [`hilbert_key_reference`].
const HILBERT_TABLE: [u16; 8 * HILBERT_STATES] = {
    let mut table = [0u16; 8 * HILBERT_STATES];
    let mut state = 0;
    while state < HILBERT_STATES {
        let (perm_index, flip, parity) = (state / 16, (state / 2) % 8, state % 2);
        let mut octant = 0;
        while octant < 8 {
            let mut perm = PERMS[perm_index];
            let mut flips = [flip & 1, (flip >> 1) & 1, (flip >> 2) & 1];
            let x = [
                octant_bit(octant, perm[0]) ^ flips[0],
                octant_bit(octant, perm[1]) ^ flips[1],
                octant_bit(octant, perm[2]) ^ flips[2],
            ];
            let mut i = 0;
            while i < 3 {
                if x[i] == 1 {
                    flips[0] ^= 1;
                } else {
                    (perm[0], perm[i]) = (perm[i], perm[0]);
                    (flips[0], flips[i]) = (flips[i], flips[0]);
                }
                i += 1;
            }
            let g0 = x[0];
            let g1 = x[1] ^ g0;
            let g2 = x[2] ^ g1;
            let digit = ((g0 ^ parity) << 2) | ((g1 ^ parity) << 1) | (g2 ^ parity);
            let mut next_perm = 0;
            while !(PERMS[next_perm][0] == perm[0]
                && PERMS[next_perm][1] == perm[1]
                && PERMS[next_perm][2] == perm[2])
            {
                next_perm += 1;
            }
            let next_flip = flips[0] | (flips[1] << 1) | (flips[2] << 2);
            let next = next_perm * 16 + next_flip * 2 + (parity ^ g2);
            table[state * 8 + octant] = ((next << 3) | digit) as u16;
            octant += 1;
        }
        state += 1;
    }
    table
};

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
    fn table_hilbert_key_matches_the_textbook_form() {
        let mut rng = SplitMix64::new(11);
        let max = (1u32 << HILBERT_BITS) - 1;
        for i in 0..1_000_000 {
            // Random cells of every size class: all bits, or only the low 1..21 bits.
            let bits = 1 + (i / 8) % HILBERT_BITS;
            let mut c =
                || (rng.next_u64() as u32) & max & if i % 2 == 0 { max } else { (1 << bits) - 1 };
            let (x, y, z) = if i < 8 {
                // The corners.
                ((i & 1) * max, (i >> 1 & 1) * max, (i >> 2 & 1) * max)
            } else {
                (c(), c(), c())
            };
            assert_eq!(hilbert_key(x, y, z), hilbert_key_reference(x, y, z));
        }
    }

    /// Every cell of a 32³ block, under random prefixes of the higher bits (so the block
    /// is entered in every state the curve reaches), against the textbook form.
    #[test]
    fn table_hilbert_key_matches_the_textbook_form_on_whole_blocks() {
        let mut rng = SplitMix64::new(13);
        let max = (1u32 << HILBERT_BITS) - 1;
        for _ in 0..40 {
            let mut high = || (rng.next_u64() as u32) & max & !31;
            let (hx, hy, hz) = (high(), high(), high());
            for x in 0..32 {
                for y in 0..32 {
                    for z in 0..32 {
                        let (x, y, z) = (hx | x, hy | y, hz | z);
                        assert_eq!(hilbert_key(x, y, z), hilbert_key_reference(x, y, z));
                    }
                }
            }
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
