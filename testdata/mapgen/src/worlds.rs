//! The standard test worlds, written to `testdata/maps/NAME.bsp` + `.json`.
//!
//! Coordinates are multiples of 16 (Quake-style); floors are at z = 0 unless
//! stated. Spawn origins are hull-1 centres: 37 units above the floor.

use crate::world::{Aabb, BrushEntity, Ramp, Rise, World};

const fn b(min: [f64; 3], max: [f64; 3]) -> Aabb {
    Aabb::new(min, max)
}

/// Every standard world, in a fixed order.
///
/// ```
/// let names: Vec<String> = mapgen::worlds::worlds().into_iter().map(|w| w.name).collect();
/// assert_eq!(names, ["box_room", "two_rooms", "pillars", "sky_room", "ramp", "complex", "l_corridor", "pillar_hall"]);
/// ```
pub fn worlds() -> Vec<World> {
    vec![
        box_room(),
        two_rooms(),
        pillars(),
        sky_room(),
        ramp(),
        complex(),
        l_corridor(),
        pillar_hall(),
    ]
}

/// Where the committed files of a standard map live
/// (`testdata/maps/NAME.bsp` and `NAME.json`).
///
/// ```
/// let bsp = mapgen::worlds::committed_map_path("box_room", "bsp");
/// assert!(bsp.ends_with("testdata/maps/box_room.bsp"));
/// ```
pub fn committed_map_path(name: &str, extension: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("crate lives in testdata/")
        .join("maps")
        .join(format!("{name}.{extension}"))
}

/// One closed box room, 512 × 384 × 256, spanning `[0,512]×[0,384]×[0,256]`.
/// Its clearance is the distance to the nearest of six planes, so its medial
/// structure is known in closed form.
pub fn box_room() -> World {
    let mut w = World::new("box_room", "one closed box room 512 x 384 x 256");
    w.free.push(b([0.0, 0.0, 0.0], [512.0, 384.0, 256.0]));
    w.spawns = vec![[128.0, 192.0, 37.0], [384.0, 192.0, 37.0]];
    w
}

/// A map that leaks: a closed room with a 64-wide hole in its east wall opening into
/// a large hall around it that stands for the void outside a leaking level. Returned
/// with the world bounds its compiler would write (the room and the hole's
/// corridor): the hall's free space lies outside them, as a leaking map's empty
/// outside does (write it with [`crate::bsp::write_with_world_bounds`]).
pub fn leaking_room() -> (World, Aabb) {
    let mut w = World::new(
        "leaking_room",
        "a 512 x 384 x 256 room whose east wall has a hole to the void around it",
    );
    w.free.push(b([0.0, 0.0, 0.0], [512.0, 384.0, 256.0]));
    w.free.push(b([496.0, 160.0, 0.0], [640.0, 224.0, 96.0]));
    // The void: a hall east of the room, beyond the bounds.
    w.free
        .push(b([640.0, -512.0, -256.0], [1664.0, 896.0, 512.0]));
    w.spawns = vec![[128.0, 192.0, 37.0]];
    (w, b([0.0, 0.0, 0.0], [640.0, 384.0, 256.0]))
}

/// Two rooms joined by a corridor; the corridor box overlaps both rooms, so
/// its cross-section (128 wide, 112 high) is the door opening in each wall.
pub fn two_rooms() -> World {
    let mut w = World::new(
        "two_rooms",
        "two 384x384x192 rooms joined by a 256-long corridor through door openings",
    );
    w.free.push(b([0.0, 0.0, 0.0], [384.0, 384.0, 192.0]));
    w.free.push(b([640.0, 0.0, 0.0], [1024.0, 384.0, 192.0]));
    w.free.push(b([368.0, 128.0, 0.0], [656.0, 256.0, 112.0]));
    w.spawns = vec![[192.0, 192.0, 37.0], [832.0, 192.0, 37.0]];
    w
}

/// A room with two floor-to-ceiling pillars, a free-standing short pillar and
/// a 16-unit step along the back wall.
pub fn pillars() -> World {
    let mut w = World::new(
        "pillars",
        "768x512x256 room with pillars and a 16-unit step along the back wall",
    );
    w.free.push(b([0.0, 0.0, 0.0], [768.0, 512.0, 256.0]));
    w.solids.push(b([192.0, 128.0, 0.0], [256.0, 192.0, 256.0]));
    w.solids.push(b([512.0, 288.0, 0.0], [576.0, 352.0, 256.0]));
    w.solids.push(b([384.0, 224.0, 0.0], [416.0, 288.0, 160.0]));
    w.solids.push(b([0.0, 400.0, 0.0], [768.0, 512.0, 16.0]));
    w.spawns = vec![
        [96.0, 96.0, 37.0],
        [672.0, 96.0, 37.0],
        [384.0, 448.0, 53.0],
    ];
    w
}

/// A courtyard open to the sky (a SKY box above it, larger than its
/// footprint) and a side room with a normal ceiling, joined by a door.
pub fn sky_room() -> World {
    let mut w = World::new(
        "sky_room",
        "512x512x384 courtyard under a sky ceiling, with a side room through a door",
    );
    w.free.push(b([0.0, 0.0, 0.0], [512.0, 512.0, 384.0]));
    w.sky.push(b([-64.0, -64.0, 384.0], [576.0, 576.0, 448.0]));
    w.free.push(b([576.0, 128.0, 0.0], [832.0, 384.0, 192.0]));
    w.free.push(b([496.0, 208.0, 0.0], [592.0, 304.0, 112.0]));
    w.spawns = vec![[256.0, 256.0, 37.0], [704.0, 256.0, 37.0]];
    w
}

/// A room with a ramp up to a ledge and one slanted (non-axial) wall cutting a
/// corner.
pub fn ramp() -> World {
    let mut w = World::new(
        "ramp",
        "768x512x320 room with a ramp (rise 128 over 256) to a ledge and a slanted corner wall",
    );
    w.free.push(b([0.0, 0.0, 0.0], [768.0, 512.0, 320.0]));
    w.ramps.push(Ramp::rising(
        b([256.0, 0.0, 0.0], [512.0, 192.0, 128.0]),
        Rise::PlusX,
    ));
    w.solids.push(b([512.0, 0.0, 0.0], [768.0, 192.0, 128.0]));
    // Corner at (0, 512) cut off by the vertical plane through (0, 384) and
    // (128, 512): solid where y - x > 384.
    w.ramps.push(Ramp::new(
        b([0.0, 384.0, 0.0], [128.0, 512.0, 320.0]),
        [1.0, -1.0, 0.0],
        [0.0, 384.0, 0.0],
    ));
    w.spawns = vec![
        [128.0, 96.0, 37.0],
        [640.0, 96.0, 165.0],
        [384.0, 384.0, 37.0],
    ];
    w
}

/// A mini level: five rooms in a loop of corridors, a pillar, a ramp to a
/// ledge, a sky courtyard, a water pool, a slanted wall, a `trigger_once`
/// (`aaatrigger`) and a `func_illusionary` fence (`{fence`) as brush
/// entities.
pub fn complex() -> World {
    let mut w = World::new(
        "complex",
        "mini level: 5 rooms, corridor loop, pillar, ramp, sky courtyard, water pool, slanted wall, trigger",
    );
    // Room A (start hall) with a pillar.
    w.free.push(b([0.0, 0.0, 0.0], [512.0, 512.0, 256.0]));
    w.solids.push(b([224.0, 224.0, 0.0], [288.0, 288.0, 256.0]));
    // Corridor A–B.
    w.free.push(b([496.0, 192.0, 0.0], [784.0, 320.0, 128.0]));
    // Room B with a ramp up to a ledge.
    w.free.push(b([768.0, 0.0, 0.0], [1280.0, 512.0, 320.0]));
    w.ramps.push(Ramp::rising(
        b([896.0, 352.0, 0.0], [1152.0, 512.0, 128.0]),
        Rise::PlusX,
    ));
    w.solids
        .push(b([1152.0, 352.0, 0.0], [1280.0, 512.0, 128.0]));
    // Corridor B–C.
    w.free.push(b([960.0, 496.0, 0.0], [1088.0, 784.0, 128.0]));
    // Room C: sky courtyard.
    w.free.push(b([768.0, 768.0, 0.0], [1280.0, 1280.0, 384.0]));
    w.sky
        .push(b([752.0, 752.0, 384.0], [1296.0, 1296.0, 448.0]));
    // Corridor C–D.
    w.free.push(b([496.0, 960.0, 0.0], [784.0, 1088.0, 128.0]));
    // Room D with a water pool (surface 16 below the floor).
    w.free.push(b([0.0, 768.0, 0.0], [512.0, 1280.0, 256.0]));
    w.free.push(b([128.0, 896.0, -128.0], [384.0, 1152.0, 0.0]));
    w.water
        .push(b([128.0, 896.0, -128.0], [384.0, 1152.0, -16.0]));
    // Corridor D–A closes the loop.
    w.free.push(b([192.0, 496.0, 0.0], [320.0, 784.0, 128.0]));
    // Room E off room D, with a slanted wall cutting its far corner.
    w.free.push(b([-320.0, 896.0, 0.0], [-64.0, 1152.0, 192.0]));
    w.free.push(b([-80.0, 960.0, 0.0], [16.0, 1056.0, 112.0]));
    w.ramps.push(Ramp::new(
        b([-320.0, 1024.0, 0.0], [-192.0, 1152.0, 192.0]),
        [1.0, -1.0, 0.0],
        [-320.0, 1024.0, 0.0],
    ));
    w.brush_entities.push(BrushEntity {
        classname: "trigger_once".into(),
        bounds: b([576.0, 192.0, 0.0], [608.0, 320.0, 128.0]),
        texture: "aaatrigger".into(),
    });
    w.brush_entities.push(BrushEntity {
        classname: "func_illusionary".into(),
        bounds: b([64.0, 64.0, 0.0], [128.0, 72.0, 96.0]),
        texture: "{fence".into(),
    });
    w.spawns = vec![
        [96.0, 96.0, 37.0],
        [1024.0, 128.0, 37.0],
        [1024.0, 1024.0, 37.0],
        [96.0, 1216.0, 37.0],
        [-192.0, 960.0, 37.0],
    ];
    w
}

/// An L-shaped corridor, 128 wide and 160 high, two legs of 640: the corner
/// hides one leg from the other, the camera's classic test.
pub fn l_corridor() -> World {
    let mut w = World::new(
        "l_corridor",
        "L-shaped corridor 128 wide, 160 high, legs 640 long along +x and +y",
    );
    w.free.push(b([0.0, 0.0, 0.0], [640.0, 128.0, 160.0]));
    w.free.push(b([0.0, 0.0, 0.0], [128.0, 640.0, 160.0]));
    w.spawns = vec![[576.0, 64.0, 37.0], [64.0, 576.0, 37.0]];
    w
}

/// A hall of 1024 × 768 × 256 with six floor-to-ceiling pillars (64 × 64) in
/// two rows: sight lines around pillars come and go as a player walks.
pub fn pillar_hall() -> World {
    let mut w = World::new(
        "pillar_hall",
        "1024x768x256 hall with six 64x64 floor-to-ceiling pillars in two rows",
    );
    w.free.push(b([0.0, 0.0, 0.0], [1024.0, 768.0, 256.0]));
    for x in [224.0, 480.0, 736.0] {
        for y in [224.0, 480.0] {
            w.solids.push(b([x, y, 0.0], [x + 64.0, y + 64.0, 256.0]));
        }
    }
    w.spawns = vec![[96.0, 96.0, 37.0], [928.0, 672.0, 37.0]];
    w
}

/// Worlds made on request, not among the standard maps (too large to compile in
/// every test run): `mapgen --out DIR --only NAME` writes them too.
pub fn extra_worlds() -> Vec<World> {
    vec![open_field(), crawl_duct()]
}

/// Two 256 × 256 × 160 rooms joined by a duct 256 units long, 64 wide and 48 high
/// (`[256,512]×[96,160]×[0,48]`): a player stands in the rooms and only crouches in
/// the duct (GoldSrc's duck hull is 36 units tall, the standing hull 72). Where the
/// camera's target crawls, so crouch coverage has something to measure.
pub fn crawl_duct() -> World {
    let mut w = World::new(
        "crawl_duct",
        "two 256x256x160 rooms joined by a 256-long, 64-wide, 48-high crawl duct",
    );
    w.free.push(b([0.0, 0.0, 0.0], [256.0, 256.0, 160.0]));
    w.free.push(b([512.0, 0.0, 0.0], [768.0, 256.0, 160.0]));
    w.free.push(b([240.0, 96.0, 0.0], [528.0, 160.0, 48.0]));
    w.spawns = vec![[128.0, 128.0, 37.0], [640.0, 128.0, 37.0]];
    w
}

/// A large open map like an outdoor level: a 3072 × 3072 field under a sky 768
/// units up, with a few scattered buildings. Clearances reach hundreds of units,
/// so face volumes span several BBox-tree cells: the map that shows the tree's
/// size (its bytes per face).
pub fn open_field() -> World {
    let mut w = World::new(
        "open_field",
        "3072x3072x768 field under a sky with six scattered buildings",
    );
    w.free.push(b([0.0, 0.0, 0.0], [3072.0, 3072.0, 768.0]));
    w.sky
        .push(b([-64.0, -64.0, 768.0], [3136.0, 3136.0, 832.0]));
    for (x, y, sx, sy, h) in [
        (384.0, 512.0, 256.0, 384.0, 256.0),
        (1280.0, 320.0, 512.0, 192.0, 384.0),
        (2304.0, 640.0, 320.0, 320.0, 192.0),
        (640.0, 1792.0, 192.0, 512.0, 320.0),
        (1536.0, 1536.0, 384.0, 384.0, 512.0),
        (2432.0, 2304.0, 448.0, 256.0, 256.0),
    ] {
        w.solids.push(b([x, y, 0.0], [x + sx, y + sy, h]));
    }
    w.spawns = vec![[128.0, 128.0, 37.0], [2944.0, 2944.0, 37.0]];
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_worlds_are_valid() {
        for w in worlds().into_iter().chain(extra_worlds()) {
            assert_eq!(w.validate(), Ok(()), "{}", w.name);
        }
    }
}
