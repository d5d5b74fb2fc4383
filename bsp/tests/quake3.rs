//! Quake 3 maps (../shared/testmaps/quake3, IBSP 46 from OpenArena): they read,
//! their spawns are free for the player's box, the carved tree agrees with the
//! brushes, patches block, and corrupt copies fail cleanly. Skipped when the maps are
//! absent.

use bsp::faces::FaceClass;
use bsp::oracle::{Oracle, OracleOptions, PlayerHull};
use bsp::quake3::contents as q3;
use bsp::{Bsp, Game, contents};
use std::path::PathBuf;
use toolbox::SplitMix64;

mod common;

fn quake3_maps() -> Option<Vec<PathBuf>> {
    common::shared_maps("quake3")
}

#[test]
fn every_quake3_map_reads_with_spawns_free() {
    let Some(maps) = quake3_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap_or_else(|e| panic!("{}: {e}", m.display()));
        assert_eq!(bsp.game, Game::Quake3, "{}", m.display());
        assert!(!bsp.brushes.is_empty());
        let walls = bsp::faces::polygons(&bsp, 0)
            .filter(|f| f.class == FaceClass::Wall)
            .count();
        assert!(walls > 100, "{}: {walls} wall faces", m.display());
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let spawns: Vec<_> = bsp
            .entities
            .iter()
            .filter(|e| e.classname() == "info_player_deathmatch")
            .filter_map(|e| e.origin())
            .collect();
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
    common::disagreements(bsp, n, seed, q3::SOLID)
}

#[test]
fn carved_tree_agrees_with_the_brushes() {
    let Some(maps) = quake3_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let bad = disagreements(&bsp, 20_000, 1);
        eprintln!("{}: {bad} of 20000 points disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// The full measurement: 10^6 points per map (`cargo test -p bsp --release --test
/// quake3 -- --ignored`).
#[test]
#[ignore]
fn carved_tree_agrees_with_the_brushes_on_a_million_points() {
    let Some(maps) = quake3_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let bad = disagreements(&bsp, 1_000_000, 2);
        eprintln!("{}: {bad} of 1000000 points disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// oa_ctf2's pipes are Bézier patches with no brush behind them: the tree holds them
/// filled, so a segment across a pipe is blocked and its axis is solid.
#[test]
fn patch_pipes_block() {
    let Some(maps) = quake3_maps() else { return };
    let Some(m) = maps
        .iter()
        .find(|m| m.to_string_lossy().contains("oa_ctf2"))
    else {
        return;
    };
    let bsp = Bsp::open(m).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    // A straight pipe along y at x = 3819, z = 310 (its control points 3805..3832,
    // 295..325).
    let axis = [3819.0, 700.0, 310.0];
    assert!(!oracle.is_free(axis));
    assert!(!oracle.segment_free([3790.0, 700.0, 310.0], [3850.0, 700.0, 310.0]));
}

#[test]
fn corrupt_quake3_maps_fail_cleanly_naming_the_lump() {
    let Some(maps) = quake3_maps() else { return };
    let mut rng = SplitMix64::new(11);
    for m in &maps {
        let bytes = std::fs::read(m).unwrap();
        for cut in [8, 100, bytes.len() / 2] {
            let msg = Bsp::parse(&bytes[..cut]).unwrap_err().to_string();
            assert!(
                msg.starts_with("lump ") || msg.starts_with("file is"),
                "{msg}"
            );
        }
        for _ in 0..25 {
            let mut b = bytes.clone();
            for _ in 0..1 + rng.below(8) {
                let at = if rng.below(2) == 0 {
                    rng.below(144)
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
                    // With the magic intact, the error names the lump.
                    let msg = e.to_string();
                    let same_format = b[..8] == bytes[..8];
                    assert!(!msg.is_empty() && !msg.contains('\n'), "{msg}");
                    assert!(!same_format || msg.starts_with("lump "), "{msg}");
                }
            }
        }
    }
}

/// The standing player's clip hull built from the brushes agrees with the game's box
/// test, on one small map (all maps: the ignored test below).
#[test]
fn player_hull_agrees_with_the_box_test() {
    let Some(maps) = quake3_maps() else { return };
    for m in maps
        .iter()
        .filter(|m| m.to_string_lossy().contains("oa_dm1"))
    {
        let bsp = Bsp::open(m).unwrap();
        let (bad, tested) = common::hull_disagreements(&bsp, 5_000, 3);
        eprintln!("{}: {bad} of {tested} free origins disagree", m.display());
        assert!(tested > 100, "{}: {tested} free origins", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// Every map, 10^5 origins (`cargo test -p bsp --release --test quake3 -- --ignored`).
#[test]
#[ignore]
fn player_hull_agrees_with_the_box_test_on_every_map() {
    let Some(maps) = quake3_maps() else { return };
    for m in &maps {
        let bsp = Bsp::open(m).unwrap();
        let (bad, tested) = common::hull_disagreements(&bsp, 100_000, 4);
        eprintln!("{}: {bad} of {tested} free origins disagree", m.display());
        assert_eq!(bad, 0, "{}", m.display());
    }
}

/// Player clip (`common/clip`, CONTENTS_PLAYERCLIP) is free space by default and an
/// obstacle with `clip_is_solid`, for points, segments and the walls; the player's
/// hull collides with it either way.
#[test]
fn player_clip_is_an_option() {
    let Some(maps) = quake3_maps() else { return };
    let Some(m) = maps.iter().find(|m| m.to_string_lossy().contains("oa_dm1")) else {
        return;
    };
    let bsp = Bsp::open(m).unwrap();
    let free = Oracle::new(&bsp, &OracleOptions::default());
    let clip_solid = OracleOptions {
        clip_is_solid: true,
        ..Default::default()
    };
    let solid = Oracle::new(&bsp, &clip_solid);
    let (lo, hi) = bsp.bounds();
    let mut rng = SplitMix64::new(5);
    let clip = (0..200_000)
        .map(|_| [0, 1, 2].map(|i| rng.range(lo[i] as f64, hi[i] as f64)))
        .find(|&p| free.contents(p) == contents::CLIP)
        .expect("oa_dm1 has player clip brushes");
    assert!(free.is_free(clip));
    assert!(!solid.is_free(clip));
    let above = [clip[0], clip[1], clip[2] + 512.0];
    assert!(!solid.segment_free(clip, above));
    assert_eq!(
        free.player_contents(PlayerHull::Standing, clip),
        Some(contents::SOLID)
    );
    let clip_walls = |o: &OracleOptions| {
        bsp::boundary::of_map(&bsp, o)
            .iter()
            .filter(|w| w.obstacle == contents::CLIP)
            .count()
    };
    assert!(clip_walls(&clip_solid) > 0);
    assert_eq!(clip_walls(&OracleOptions::default()), 0);
}
