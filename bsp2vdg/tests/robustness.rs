//! Bad input never panics: truncated, bit-flipped and hand-corrupted maps give an error
//! that names the lump, or parse into a map on which every query stays in bounds.

mod common;

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp2vdg::sample::{self, SampleOptions};
use toolbox::SplitMix64;

fn seed_maps() -> Vec<Vec<u8>> {
    let mut paths = common::generated_maps();
    if let Some(shared) = common::shared_maps(&["goldsrc", "quake1"]) {
        paths.extend(
            shared
                .into_iter()
                .filter(|p| std::fs::metadata(p).is_ok_and(|m| m.len() < 400_000)),
        );
    }
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

/// Parses and, when that succeeds, runs every query that indexes into the map.
fn exercise(bytes: &[u8]) -> Result<(), String> {
    let bsp = Bsp::parse(bytes).map_err(|e| e.to_string())?;
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let w = bsp.world();
    let mid = [0, 1, 2].map(|i| (w.mins[i] as f64 + w.maxs[i] as f64) * 0.5);
    oracle.is_free(mid);
    oracle.segment_free(mid, [mid[0] + 300.0, mid[1] - 100.0, mid[2] + 20.0]);
    for h in 1..=3 {
        oracle.clip_contents(h, mid);
    }
    let options = SampleOptions {
        spacing: 64.0,
        max_samples: 5_000,
        ..Default::default()
    };
    sample::sample(&bsp, &options);
    Ok(())
}

#[test]
fn truncated_maps_name_the_lump() {
    let maps = seed_maps();
    if maps.is_empty() {
        eprintln!("skipped: no maps (testdata/maps and ../shared/testmaps absent)");
        return;
    }
    for bytes in &maps {
        assert!(exercise(bytes).is_ok());
        let mut rng = SplitMix64::new(1);
        for _ in 0..40 {
            // Cut inside the 15 standard lumps: data after them (BSPX extensions) is
            // not needed, and a map cut there is still whole for us.
            let cut = rng.below(standard_lumps_end(bytes));
            let msg = exercise(&bytes[..cut]).expect_err("a truncated map must not parse");
            assert!(
                msg.contains("lump ") || msg.contains("shorter than a BSP header"),
                "unclear message: {msg}"
            );
        }
    }
}

fn standard_lumps_end(bytes: &[u8]) -> usize {
    (0..15)
        .map(|i| {
            let at = 4 + 8 * i;
            let word = |k: usize| i32::from_le_bytes(bytes[k..k + 4].try_into().unwrap());
            (word(at) + word(at + 4)) as usize
        })
        .max()
        .unwrap()
}

#[test]
fn mutated_maps_never_panic() {
    let maps = seed_maps();
    if maps.is_empty() {
        eprintln!("skipped: no maps (testdata/maps and ../shared/testmaps absent)");
        return;
    }
    let mut rng = SplitMix64::new(2);
    let (mut ok, mut err) = (0, 0);
    for bytes in &maps {
        for round in 0..150 {
            let mut m = bytes.clone();
            // Flips anywhere, and flips concentrated on the header and directory.
            let span = if round % 2 == 0 {
                m.len()
            } else {
                124.min(m.len())
            };
            for _ in 0..1 + rng.below(8) {
                let i = rng.below(span);
                m[i] ^= 1 << rng.below(8);
            }
            match exercise(&m) {
                Ok(()) => ok += 1,
                Err(_) => err += 1,
            }
        }
    }
    // Both outcomes must occur, or the mutations test nothing.
    assert!(ok > 0 && err > 0, "ok {ok}, err {err}");
}

#[test]
fn foreign_and_empty_files_are_refused() {
    assert!(
        Bsp::parse(b"")
            .unwrap_err()
            .to_string()
            .contains("shorter than a BSP header")
    );
    let mut v = vec![0u8; 200];
    v[..4].copy_from_slice(b"IBSP");
    assert!(Bsp::parse(&v).unwrap_err().to_string().contains("\"IBSP\""));
    v[..4].copy_from_slice(&31i32.to_le_bytes());
    assert!(
        Bsp::parse(&v)
            .unwrap_err()
            .to_string()
            .contains("version 31")
    );
}
