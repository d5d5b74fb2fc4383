//! Libfuzzer-free fuzzing of the reader: ~10⁵ mutated and truncated files
//! (bit flips, truncations, header and section-table tweaks, index and float
//! overwrites — most of them re-sealed with a valid checksum so validation
//! gets past it) must each be rejected with an error or, if accepted,
//! survive every query. A panic fails the test. The cargo-fuzz target in
//! `vdgformat/fuzz` runs the same check under libFuzzer.

mod common;

use std::collections::BTreeMap;

use common::{Rng, flat, random_soup};
use vdgformat::__private::{exercise_queries, seal};
use vdgformat::VdgFile;

const ITERATIONS: usize = 100_000;

fn interesting_u64(rng: &mut Rng, len: u64) -> u64 {
    match rng.below(9) {
        0 => 0,
        1 => 1,
        2 => len,
        3 => len.wrapping_sub(16),
        4 => len + 16,
        5 => u64::MAX,
        6 => u64::from(u32::MAX),
        7 => rng.next_u64() % (len + 1),
        _ => rng.next_u64(),
    }
}

fn interesting_u32(rng: &mut Rng, here: u32) -> u32 {
    match rng.below(10) {
        0 => 0,
        1 => 1,
        2 => here.wrapping_add(1),
        3 => here.wrapping_sub(1),
        4 => u32::MAX,
        5 => f32::NAN.to_bits(),
        6 => f32::INFINITY.to_bits(),
        7 => (-1.0f32).to_bits(),
        8 => rng.next_u64() as u32 % 512,
        _ => rng.next_u64() as u32,
    }
}

fn mutate(base: &[u8], rng: &mut Rng) -> Vec<u8> {
    let mut b = base.to_vec();
    let len = b.len() as u64;
    let kind = rng.below(6);
    match kind {
        // Bit flips, checksum left stale or fixed.
        0 | 1 => {
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(b.len());
                b[i] ^= 1 << rng.below(8);
            }
        }
        // Truncation.
        2 => b.truncate(rng.below(b.len())),
        // Section table: one field of one entry.
        3 => {
            let count = u32::from_le_bytes(b[32..36].try_into().unwrap()) as usize;
            let entry = 64 + 32 * rng.below(count.max(1));
            match rng.below(5) {
                // Every known id (1–16) and a few unknown ones.
                0 => b[entry..entry + 4].copy_from_slice(&(rng.below(18) as u32).to_le_bytes()),
                1 => {
                    let v = interesting_u32(rng, 0);
                    b[entry + 4..entry + 8].copy_from_slice(&v.to_le_bytes())
                }
                f => {
                    let at = entry + 8 * f - 8;
                    let v = interesting_u64(rng, len);
                    b[at..at + 8].copy_from_slice(&v.to_le_bytes())
                }
            }
        }
        // A u32 anywhere in the sections: indices, offsets, floats.
        4 => {
            for _ in 0..1 + rng.below(3) {
                let at = 4 * ((416 + rng.below(b.len() - 416)) / 4);
                if at + 4 <= b.len() {
                    let here = u32::from_le_bytes(b[at..at + 4].try_into().unwrap());
                    b[at..at + 4].copy_from_slice(&interesting_u32(rng, here).to_le_bytes());
                }
            }
        }
        // Header fields.
        _ => {
            let at = 16 + 4 * rng.below(12);
            let v = interesting_u32(rng, 0);
            b[at..at + 4].copy_from_slice(&v.to_le_bytes());
        }
    }
    if kind != 0 && b.len() >= 16 && rng.below(4) != 0 {
        seal(&mut b);
    }
    b
}

/// The files the mutations start from (and the fuzz target's seed corpus):
/// a random soup with a deep tree, a flat grid, and the empty graph.
fn base_files(rng: &mut Rng) -> Vec<Vec<u8>> {
    vec![
        random_soup(60, 150, rng)
            .set_leaf_size(80.0)
            .to_bytes()
            .unwrap(),
        flat(4, 3, 32.0, 12.0)
            .set_leaf_size(16.0)
            .to_bytes()
            .unwrap(),
        vdgformat::VdgBuilder::new().to_bytes().unwrap(),
    ]
}

#[test]
fn mutated_files_never_panic() {
    let mut rng = Rng::new(2026);
    let bases = base_files(&mut rng);
    let mut accepted = 0usize;
    let mut errors: BTreeMap<String, usize> = BTreeMap::new();
    for i in 0..ITERATIONS {
        let base = &bases[i % bases.len()];
        let bytes = mutate(base, &mut rng);
        match VdgFile::from_bytes(&bytes) {
            Ok(file) => {
                accepted += 1;
                if accepted.is_multiple_of(4) || bytes.len() < 4000 {
                    exercise_queries(file.graph());
                }
            }
            Err(e) => {
                let name = format!("{e:?}");
                let variant = name.split([' ', '(', '{']).next().unwrap().to_owned();
                *errors.entry(variant).or_default() += 1;
            }
        }
    }
    eprintln!("accepted {accepted} of {ITERATIONS}; rejections by variant: {errors:?}");
    assert!(
        accepted > 100,
        "mutations too destructive to reach the queries"
    );
    assert!(
        errors.len() >= 15,
        "only {} error variants reached",
        errors.len()
    );
}

/// Writes the base files as a seed corpus for the cargo-fuzz target:
/// `VDG_SEED_DIR=fuzz/corpus/reader cargo test -p vdgformat --test fuzz_reader -- --ignored`
#[test]
#[ignore]
fn write_seed_corpus() {
    let Some(dir) = std::env::var_os("VDG_SEED_DIR") else {
        return;
    };
    let dir = std::path::PathBuf::from(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let seeds = base_files(&mut Rng::new(2026));
    for (i, s) in seeds.iter().enumerate() {
        std::fs::write(dir.join(format!("seed{i}.vdg")), s).unwrap();
    }
}
