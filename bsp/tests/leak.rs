//! A map that leaks is fenced by the world's bounds, and the leak is found: a free
//! path from the player start out of the bounds, through the hole.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use mapgen::bsp::{write_with_world_bounds, write_world};
use mapgen::worlds;

#[test]
fn a_leaking_map_is_fenced_and_the_hole_is_found() {
    let (world, bounds) = worlds::leaking_room();
    let bsp = Bsp::parse(&write_with_world_bounds(&world, bounds)).unwrap();
    assert!(bsp::leak::outside_is_free(&bsp));
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let (lo, hi) = oracle.fence().expect("fenced");
    assert_eq!((lo, hi), (bounds.min, bounds.max));
    // Inside the room: free; in the void past the bounds: solid for the oracle.
    assert!(oracle.is_free([256.0, 192.0, 64.0]));
    assert!(!oracle.is_free([1000.0, 192.0, 64.0]));
    assert!(!oracle.segment_free([256.0, 192.0, 64.0], [1000.0, 192.0, 64.0]));
    let leak = bsp::leak::find(&bsp).expect("a path out");
    assert_eq!(leak.entity, "info_player_start");
    assert_eq!(leak.from, [128.0, 192.0, 37.0]);
    // The path leaves the bounds through the hole (y 160..224, z 0..96, x past 512).
    assert!(leak.exit[0] > 500.0, "{:?}", leak.exit);
    let out = leak.path.last().unwrap();
    assert!(out[0] > bounds.max[0], "{out:?}");
    let through = leak
        .path
        .iter()
        .find(|p| p[0] > 520.0 && p[0] < 630.0)
        .unwrap();
    assert!(
        (150.0..=234.0).contains(&through[1]) && through[2] <= 100.0,
        "{through:?}"
    );
    let text = bsp::leak::pointfile(&leak.path);
    assert_eq!(text.lines().count(), leak.path.len());
    assert!(
        text.lines()
            .all(|l| l.split(' ').filter_map(|x| x.parse::<f64>().ok()).count() == 3)
    );
}

#[test]
fn sealed_maps_are_not_fenced() {
    for world in worlds::worlds() {
        let bsp = Bsp::parse(&write_world(&world)).unwrap();
        assert!(!bsp::leak::outside_is_free(&bsp), "{}", world.name);
        assert!(
            Oracle::new(&bsp, &OracleOptions::default())
                .fence()
                .is_none()
        );
        assert!(bsp::leak::find(&bsp).is_none());
    }
}
