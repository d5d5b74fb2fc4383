//! BSP29 is Quake's format and Half-Life's oldest maps': the game is read from the
//! map itself. Generated maps with each game's clip hulls must be recognised by the
//! hulls alone, and by the entities where the map has no clip hulls.

use bsp::{Bsp, Game};
use mapgen::bsp::{write_v29, write_world};
use mapgen::world::HullSet;
use mapgen::worlds;

#[test]
fn v29_maps_with_half_life_hulls_are_goldsrc_maps() {
    for world in [worlds::box_room(), worlds::pillars(), worlds::complex()] {
        let bsp = Bsp::parse(&write_v29(&world, HullSet::GoldSrc)).unwrap();
        assert_eq!(
            bsp.game,
            Game::GoldSrc,
            "{}: {}",
            world.name,
            bsp.game_reason
        );
        assert_eq!(bsp.format_name(), "BSP29 (Half-Life)");
        let e = bsp::game::hull_evidence(&bsp);
        assert!(e.goldsrc >= 2 && e.quake == 0, "{}: {e:?}", world.name);
        assert!(
            bsp.game_reason.contains("Half-Life's player"),
            "{}",
            bsp.game_reason
        );
    }
}

#[test]
fn v29_maps_with_quake_hulls_are_quake_maps() {
    for world in [worlds::box_room(), worlds::pillars(), worlds::complex()] {
        let bsp = Bsp::parse(&write_v29(&world, HullSet::Quake)).unwrap();
        assert_eq!(bsp.game, Game::Quake, "{}: {}", world.name, bsp.game_reason);
        assert_eq!(bsp.format_name(), "BSP29 (Quake)");
        let e = bsp::game::hull_evidence(&bsp);
        assert!(e.quake >= 2 && e.goldsrc == 0, "{}: {e:?}", world.name);
    }
}

/// The game decides the player's body: Half-Life stands 36 above the floor, Quake 24.
#[test]
fn the_decided_game_gives_the_players_body() {
    let world = worlds::box_room();
    for (hulls, above) in [(HullSet::GoldSrc, 36.0), (HullSet::Quake, 24.0)] {
        let bsp = Bsp::parse(&write_v29(&world, hulls)).unwrap();
        assert_eq!(bsp::player::standing_origin_above_ground(bsp.game), above);
    }
}

/// Without clip hulls the entities are the witness; with neither, BSP29 is Quake's.
#[test]
fn without_clip_hulls_the_entities_decide() {
    let world = worlds::box_room();
    let mut bytes = write_v29(&world, HullSet::GoldSrc);
    // Every model's clip roots point past the clip nodes (no hulls to measure).
    let (models, len) = lump(&bytes, 14);
    let clipnodes = (lump(&bytes, 9).1 / 8) as i32;
    for m in 0..len / 64 {
        for h in 1..4 {
            let at = models + 64 * m + 36 + 4 * h;
            bytes[at..at + 4].copy_from_slice(&clipnodes.to_le_bytes());
        }
    }
    let bsp = Bsp::parse(&bytes).unwrap();
    assert_eq!(bsp.game, Game::Quake, "{}", bsp.game_reason);
    assert!(
        bsp.game_reason.contains("no clip hulls"),
        "{}",
        bsp.game_reason
    );
    // Half-Life's WAD and classes in the entity text.
    let (at, len) = lump(&bytes, 0);
    let text = String::from_utf8_lossy(&bytes[at..at + len]).replacen(
        "\"classname\" \"worldspawn\"",
        "\"classname\" \"worldspawn\"\n\"wad\" \"\\\\half-life\\\\valve\\\\halflife.wad\"",
        1,
    ) + "{\n\"classname\" \"ambient_generic\"\n\"origin\" \"10 10 10\"\n}\n";
    let bsp = Bsp::parse(&with_lump(&bytes, 0, text.as_bytes())).unwrap();
    assert_eq!(bsp.game, Game::GoldSrc, "{}", bsp.game_reason);
    assert!(
        bsp.game_reason.contains("halflife.wad"),
        "{}",
        bsp.game_reason
    );
}

#[test]
fn v30_is_goldsrc_and_forcing_works_within_the_family() {
    let mut bsp = Bsp::parse(&write_world(&worlds::box_room())).unwrap();
    assert_eq!(bsp.game, Game::GoldSrc);
    bsp.force_game(Game::Quake).unwrap();
    assert_eq!(bsp.game, Game::Quake);
    assert!(bsp.game_reason.starts_with("forced"), "{}", bsp.game_reason);
    assert!(bsp.force_game(Game::Quake3).is_err());
}

fn lump(bytes: &[u8], i: usize) -> (usize, usize) {
    let r = |k: usize| i32::from_le_bytes(bytes[k..k + 4].try_into().unwrap()) as usize;
    (r(4 + 8 * i), r(8 + 8 * i))
}

fn with_lump(bytes: &[u8], i: usize, data: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    while !out.len().is_multiple_of(4) {
        out.push(0);
    }
    let offset = out.len() as i32;
    out.extend_from_slice(data);
    out[4 + 8 * i..8 + 8 * i].copy_from_slice(&offset.to_le_bytes());
    out[8 + 8 * i..12 + 8 * i].copy_from_slice(&(data.len() as i32).to_le_bytes());
    out
}

/// Found by the fuzzer (scripts/fuzz.sh bsp, from the generated box_room): a BSP29 map
/// whose hull-1 plane lies at a height near f32's limit made the game decision subtract
/// past i64's range. It must read or fail with an error, never panic.
#[test]
fn a_hull_plane_at_a_hostile_height_does_not_panic_the_game_decision() {
    let bytes = include_bytes!("data/fuzz-hull-height-overflow.bsp");
    let _ = Bsp::parse(bytes);
}
