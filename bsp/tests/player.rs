//! The three ways the tools place a player agree with each other on every generated
//! map: the compiler's and the check's standing places (`column_floors`, every floor
//! of a column), the camera replay's `settle` (a player dropped onto the floor near a
//! known height) and the flow-tile region's `ground_below` (the feet under a column).
//! They answer different questions, so they are three functions, but on the same
//! floor they must name the same height; before they shared one module each tool had
//! its own copy with its own constants.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::player::{
    column_floors, ground_below, on_floor, settle, standing_origin_above_ground, top_floor,
};

/// Traces stop a little short of a plane (the engines' DIST_EPSILON is 1/32).
const TOLERANCE: f64 = 0.1;

#[test]
fn standing_places_settle_and_ground_agree_on_every_generated_map() {
    let mut worlds = mapgen::worlds::worlds();
    worlds.extend(mapgen::worlds::extra_worlds());
    let mut checked = 0;
    for world in &worlds {
        let bytes = mapgen::bsp::write_world(world);
        let bsp = Bsp::parse(&bytes).expect("generated map parses");
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let Some(hull) = oracle.clip_hull(1) else {
            continue;
        };
        let half = standing_origin_above_ground(bsp.game);
        assert_eq!(
            half, 36.0,
            "{}: a GoldSrc player stands 36 units up",
            world.name
        );
        let w = bsp.world();
        let (lo, hi) = (w.mins.map(f64::from), w.maxs.map(f64::from));
        let step = 24.0;
        let mut y = lo[1] + step / 2.0;
        while y < hi[1] {
            let mut x = lo[0] + step / 2.0;
            while x < hi[0] {
                let floors = column_floors(hull, &oracle, x, y, hi[2] + 1.0, lo[2] - 1.0);
                for (k, &z) in floors.iter().enumerate() {
                    let at = format!("{} ({x}, {y}) floor {k} at {z}", world.name);
                    // The replay's walker lands on the same floor...
                    let (o, crouched) = settle(&oracle, x, y, z - half, false)
                        .unwrap_or_else(|| panic!("{at}: settle finds no floor"));
                    assert!(!crouched, "{at}: a standing place settles crouched");
                    assert!((o[2] - z).abs() < TOLERANCE, "{at}: settle lands at {o:?}");
                    assert!(
                        on_floor(&oracle, o, false),
                        "{at}: settled origin {o:?} not on the floor"
                    );
                    // ...and the region's ground test finds its feet there.
                    let feet = ground_below(hull, x, y, z + 1.0, z - 100.0, half)
                        .unwrap_or_else(|| panic!("{at}: ground_below finds no floor"));
                    assert!((feet + half - z).abs() < TOLERANCE, "{at}: feet at {feet}");
                    checked += 1;
                }
                // The highest floor the region sees is the highest standing place.
                if let (Some(&z), Some(feet)) =
                    (floors.first(), top_floor(hull, x, y, lo[2], hi[2], half))
                {
                    assert!(
                        (feet + half - z).abs() < TOLERANCE,
                        "{} ({x}, {y}): top floor {feet}, standing place {z}",
                        world.name
                    );
                }
                x += step;
            }
            y += step;
        }
    }
    assert!(checked > 1000, "only {checked} places checked");
}
