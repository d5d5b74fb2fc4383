//! Quake 2 maps (../shared/testmaps/quake2, IBSP 38 and Qbism's QBSP 38): they read,
//! their spawns are free for the player's box, and the oracle (the BSP tree's leaf
//! contents) agrees with the brushes the file keeps. Skipped when the maps are absent.

use bsp::oracle::{Oracle, OracleOptions, PlayerHull};
use bsp::quake2::contents as q2;
use bsp::{Bsp, Game, contents};
use std::path::PathBuf;
use toolbox::SplitMix64;

mod common;

fn quake2_maps() -> Option<Vec<PathBuf>> {
    common::shared_maps("quake2")
}

#[test]
fn every_quake2_map_reads_with_spawns_free() {
    let Some(maps) = quake2_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap_or_else(|e| panic!("{}: {e}", m.display()));
        assert_eq!(bsp.game, Game::Quake2, "{}", m.display());
        assert!(!bsp.faces.is_empty() && !bsp.brushes.is_empty());
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let spawns = bsp.spawns();
        assert!(!spawns.is_empty(), "{}: no spawns", m.display());
        for s in spawns {
            let p = s.map(f64::from);
            assert!(
                oracle.is_free(p),
                "{}: spawn {s:?} in an obstacle",
                m.display()
            );
            // The game lifts the player 9 units above the spawn entity.
            let lifted = [p[0], p[1], p[2] + 9.0];
            let c = oracle.player_contents(PlayerHull::Standing, lifted);
            assert!(
                c.is_some() && c != Some(contents::SOLID),
                "{}: player stuck at {s:?}",
                m.display()
            );
        }
    }
}

fn disagreements(bsp: &Bsp, n: usize, seed: u64) -> usize {
    common::disagreements(bsp, n, seed, q2::SOLID | q2::WINDOW)
}

#[test]
fn oracle_agrees_with_the_brushes() {
    let Some(maps) = quake2_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let bad = disagreements(&bsp, 20_000, 1);
        eprintln!("{}: {bad} of 20000 points disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// The full measurement: 10^6 points per map (`cargo test -p bsp --release --test
/// quake2 -- --ignored`).
#[test]
#[ignore]
fn oracle_agrees_with_the_brushes_on_a_million_points() {
    let Some(maps) = quake2_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let bad = disagreements(&bsp, 1_000_000, 2);
        eprintln!("{}: {bad} of 1000000 points disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

#[test]
fn corrupt_quake2_maps_fail_cleanly_naming_the_lump() {
    let Some(maps) = quake2_maps() else { return };
    let mut rng = SplitMix64::new(7);
    for m in &maps {
        let bytes = std::fs::read(m).unwrap();
        // Truncated: the error names a lump (or the header).
        for cut in [8, 100, bytes.len() / 2] {
            let msg = Bsp::parse(&bytes[..cut]).unwrap_err().to_string();
            assert!(
                msg.starts_with("lump ") || msg.starts_with("file is"),
                "{msg}"
            );
        }
        // Random bytes changed: never a panic; a parsed map answers queries.
        for _ in 0..40 {
            let mut b = bytes.clone();
            for _ in 0..1 + rng.below(8) {
                let at = if rng.below(2) == 0 {
                    rng.below(160)
                } else {
                    rng.below(b.len())
                };
                b[at] = rng.next_u64() as u8;
            }
            match Bsp::parse(&b) {
                Ok(bsp) => {
                    let oracle = Oracle::new(&bsp, &OracleOptions::default());
                    let (lo, hi) = bsp.bounds();
                    let mid = [0, 1, 2].map(|i| (lo[i] as f64 + hi[i] as f64) * 0.5);
                    let _ = oracle.is_free(mid);
                    let _ = oracle.player_contents(PlayerHull::Crouched, mid);
                    let _ = bsp::faces::polygons(&bsp, 0).count();
                }
                Err(e) => {
                    let msg = e.to_string();
                    assert!(!msg.is_empty() && !msg.contains('\n'), "{msg}");
                }
            }
        }
    }
}

/// The standing player's clip hull built from the brushes agrees with the game's box
/// test, on one small map (all maps: the ignored test below).
#[test]
fn player_hull_agrees_with_the_box_test() {
    let Some(maps) = quake2_maps() else { return };
    for m in maps
        .iter()
        .filter(|m| m.to_string_lossy().contains("qbsp-example-quake2"))
    {
        let bsp = Bsp::open(m).unwrap();
        let (bad, tested) = common::hull_disagreements(&bsp, 5_000, 3);
        eprintln!("{}: {bad} of {tested} free origins disagree", m.display());
        assert!(tested > 100, "{}: {tested} free origins", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// Every map, 10^5 origins (`cargo test -p bsp --release --test quake2 -- --ignored`).
#[test]
#[ignore]
fn player_hull_agrees_with_the_box_test_on_every_map() {
    let Some(maps) = quake2_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let (bad, tested) = common::hull_disagreements(&bsp, 100_000, 4);
        eprintln!("{}: {bad} of {tested} free origins disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}
