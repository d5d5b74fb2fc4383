//! Which game a map is made for, where the format does not say.
//!
//! BSP version 29 is Quake's format, and Half-Life's oldest maps use it too: the file
//! layout is the same, the game is not. The game decides the player's body (Half-Life
//! stands 72 units tall with its origin 36 above the floor, Quake 56 with its origin 24
//! above), so a map read as the wrong game puts every standing place at the wrong
//! height. The map itself tells, most robustly through its clip hulls: the compiler
//! grew the world by the game's player box to build hull 1, so wherever hull 0 has a
//! floor or ceiling at height `z`, hull 1 has one at `z + 36` / `z - 36` in Half-Life
//! (box ±36) and at `z + 24` / `z - 32` in Quake (box -24..+32). Those offsets are
//! counted over the heights of the world's horizontal planes. The entities are the
//! second witness (Half-Life's WAD files and entity classes, or Quake's), used when the
//! hulls are missing or do not decide.

use crate::map::{Bsp, BspVersion, Game};
use std::collections::BTreeSet;

/// Floor and ceiling offsets from hull 0 to hull 1 of Half-Life's standing player.
const GOLDSRC_OFFSETS: [f32; 2] = [36.0, -36.0];
/// The same for Quake's player (mins z -24, maxs z +32).
const QUAKE_OFFSETS: [f32; 2] = [24.0, -32.0];

/// Entity classes only Half-Life's games use.
const GOLDSRC_CLASSES: &[&str] = &[
    "ambient_generic",
    "func_healthcharger",
    "func_recharge",
    "light_environment",
    "light_spot",
    "env_sprite",
    "env_sound",
    "env_shake",
    "env_beam",
    "env_laser",
    "env_message",
    "scripted_sequence",
    "multi_manager",
    "info_node",
    "func_breakable",
    "func_pushable",
    "func_tank",
    "func_water",
    "func_wall_toggle",
    "trigger_auto",
    "trigger_changetarget",
    "game_text",
    "monster_scientist",
    "monster_barney",
    "monster_headcrab",
    "monster_houndeye",
    "monster_bullchicken",
    "monster_alien_grunt",
    "monster_human_grunt",
    "cycler_sprite",
    "func_ladder",
    "info_player_terrorist",
    "info_player_counterterrorist",
];

/// Entity classes only Quake uses.
const QUAKE_CLASSES: &[&str] = &[
    "info_intermission",
    "item_shells",
    "item_spikes",
    "item_rockets",
    "item_cells",
    "item_armor1",
    "item_armor2",
    "item_armorInv",
    "weapon_supershotgun",
    "weapon_nailgun",
    "weapon_supernailgun",
    "weapon_grenadelauncher",
    "weapon_rocketlauncher",
    "weapon_lightning",
    "monster_army",
    "monster_dog",
    "monster_ogre",
    "monster_knight",
    "monster_hell_knight",
    "monster_shambler",
    "monster_demon1",
    "monster_wizard",
    "monster_enforcer",
    "monster_fish",
    "func_episodegate",
    "func_bossgate",
    "misc_explobox",
    "light_flame_large_yellow",
    "light_flame_small_yellow",
    "light_torch_small_walltorch",
    "light_fluoro",
];

/// WAD files that come with Half-Life and its mods (a Quake map names `gfx/base.wad`
/// or its own).
const GOLDSRC_WADS: &[&str] = &[
    "halflife.wad",
    "liquids.wad",
    "xeno.wad",
    "decals.wad",
    "cstrike.wad",
    "gearbox.wad",
    "spraypaint.wad",
    "zhlt.wad",
];

/// What the clip hulls say: at how many of the world's horizontal hull-1 planes
/// hull 0 has a plane at Half-Life's offset, and at how many at Quake's.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct HullEvidence {
    pub heights: usize,
    pub goldsrc: usize,
    pub quake: usize,
}

/// The game `bsp` is made for and why, in one line.
pub fn decide(bsp: &Bsp) -> (Game, String) {
    let game = bsp.version.game();
    if bsp.version != BspVersion::Bsp29 {
        return (
            game,
            format!("{}: no other game uses the format", bsp.version.name()),
        );
    }
    let hulls = hull_evidence(bsp);
    let (gold, quake) = entity_evidence(bsp);
    let entities = describe_entities(&gold, &quake);
    let hull_text = format!(
        "hull 1 is offset as Half-Life's player at {} and as Quake's at {} of {} heights",
        hulls.goldsrc, hulls.quake, hulls.heights
    );
    // The hulls decide when one game's offsets clearly dominate.
    let decided = |a: usize, b: usize| a >= 2 && a >= 4 * b;
    if decided(hulls.goldsrc, hulls.quake) {
        return (Game::GoldSrc, format!("{hull_text}; {entities}"));
    }
    if decided(hulls.quake, hulls.goldsrc) {
        return (Game::Quake, format!("{hull_text}; {entities}"));
    }
    let why = if hulls.heights == 0 {
        "no clip hulls to measure".to_string()
    } else {
        format!("the hulls do not decide ({hull_text})")
    };
    if gold.len() > quake.len() {
        (Game::GoldSrc, format!("{why}; {entities}"))
    } else if !quake.is_empty() && quake.len() > gold.len() {
        (Game::Quake, format!("{why}; {entities}"))
    } else {
        (
            Game::Quake,
            format!("{why}; {entities}; BSP29 is Quake's format"),
        )
    }
}

/// Counts, over the distinct heights of the world's horizontal hull-1 planes, those
/// hull 0 explains with Half-Life's and with Quake's player box.
pub fn hull_evidence(bsp: &Bsp) -> HullEvidence {
    let world = bsp.world();
    let hull0: BTreeSet<i64> = tree_heights(bsp, world.headnode[0], false);
    let Some(root1) = world.clip_headnode(1, bsp.clipnodes.len()) else {
        return HullEvidence::default();
    };
    let hull1 = tree_heights(bsp, root1, true);
    let explained = |h: i64, offsets: [f32; 2]| {
        // A hostile plane's height saturates `key`: no floor is that far below it.
        offsets
            .iter()
            .any(|&o| h.checked_sub(key(o)).is_some_and(|f| hull0.contains(&f)))
    };
    let mut e = HullEvidence {
        heights: hull1.len(),
        ..Default::default()
    };
    for &h in &hull1 {
        let (g, q) = (explained(h, GOLDSRC_OFFSETS), explained(h, QUAKE_OFFSETS));
        e.goldsrc += (g && !q) as usize;
        e.quake += (q && !g) as usize;
    }
    e
}

/// Heights are compared to 1/8 unit (the planes are stored as f32).
fn key(z: f32) -> i64 {
    (z as f64 * 8.0).round() as i64
}

/// The heights of the horizontal planes of the tree from `root` (clip nodes when
/// `clip`, else hull-0 nodes); the walk is bounded by the node count.
fn tree_heights(bsp: &Bsp, root: i32, clip: bool) -> BTreeSet<i64> {
    let count = if clip {
        bsp.clipnodes.len()
    } else {
        bsp.nodes.len()
    };
    let mut seen = vec![false; count];
    let mut stack = vec![root];
    let mut heights = BTreeSet::new();
    while let Some(n) = stack.pop() {
        let Ok(i) = usize::try_from(n) else { continue };
        if i >= count || seen[i] {
            continue;
        }
        seen[i] = true;
        let (plane, children) = if clip {
            let c = &bsp.clipnodes[i];
            (c.plane, c.children)
        } else {
            let c = &bsp.nodes[i];
            (c.plane, c.children)
        };
        if let Some(p) = bsp.planes.get(plane as usize) {
            let [x, y, z] = p.normal;
            if x == 0.0 && y == 0.0 && z.abs() == 1.0 {
                heights.insert(key(p.dist * z));
            }
        }
        stack.extend(children);
    }
    heights
}

/// The Half-Life and the Quake witnesses among the entities: WAD names and classes.
fn entity_evidence(bsp: &Bsp) -> (BTreeSet<String>, BTreeSet<String>) {
    let mut gold = BTreeSet::new();
    let mut quake = BTreeSet::new();
    if let Some(world) = bsp.entities.iter().find(|e| e.classname() == "worldspawn")
        && let Some(wads) = world.get("wad")
    {
        for w in wads.split(';') {
            let name = w
                .rsplit(['/', '\\'])
                .next()
                .unwrap_or("")
                .to_ascii_lowercase();
            if GOLDSRC_WADS.contains(&name.as_str()) {
                gold.insert(name);
            }
        }
    }
    for e in &bsp.entities {
        let c = e.classname();
        if GOLDSRC_CLASSES.contains(&c) {
            gold.insert(c.to_string());
        } else if QUAKE_CLASSES.contains(&c) {
            quake.insert(c.to_string());
        }
    }
    (gold, quake)
}

fn describe_entities(gold: &BTreeSet<String>, quake: &BTreeSet<String>) -> String {
    let list = |s: &BTreeSet<String>| {
        let mut v: Vec<&str> = s.iter().map(String::as_str).take(4).collect();
        if s.len() > 4 {
            v.push("...");
        }
        v.join(", ")
    };
    match (gold.is_empty(), quake.is_empty()) {
        (true, true) => "no entity names either game".into(),
        (false, true) => format!("entities name Half-Life ({})", list(gold)),
        (true, false) => format!("entities name Quake ({})", list(quake)),
        (false, false) => format!(
            "entities name both: Half-Life ({}) and Quake ({})",
            list(gold),
            list(quake)
        ),
    }
}
