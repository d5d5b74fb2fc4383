//! The oracle and the sampler against exact geometry: the generated maps of
//! `testdata/maps` come with a manifest from which `mapgen` answers contents,
//! segment and clearance questions exactly.
//!
//! Sizes: `ORACLE_POINTS` (default 200 000) random points and `ORACLE_SEGMENTS`
//! (default 20 000) random segments per map; the acceptance run uses 10⁶ and 10⁵:
//! `ORACLE_POINTS=1000000 ORACLE_SEGMENTS=100000 cargo test --release -p bsp2vdg --test generated_maps -- --nocapture`

mod common;

use bsp::Bsp;
use bsp::boundary;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use bsp2vdg::sample::{self, SampleOptions, grid::PointGrid};
use mapgen::world::World;
use std::path::Path;
use toolbox::SplitMix64;
use toolbox::vec3::{dot, sub};

fn env_count(name: &str, default: usize) -> usize {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn load(map: &Path) -> (Bsp, World) {
    let bsp = Bsp::open(map).unwrap_or_else(|e| panic!("{}: {e}", map.display()));
    let json =
        std::fs::read_to_string(map.with_extension("json")).expect("manifest beside the map");
    (
        bsp,
        World::from_manifest_json(&json).expect("manifest parses"),
    )
}

fn random_point(rng: &mut SplitMix64, lo: [f64; 3], hi: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| rng.range(lo[i] - 32.0, hi[i] + 32.0))
}

#[test]
fn generated_maps_exist() {
    assert!(
        common::generated_maps().len() >= 6,
        "testdata/maps should hold the generated maps"
    );
}

#[test]
fn point_contents_match_exact_geometry() {
    let n = env_count("ORACLE_POINTS", 200_000);
    for map in common::generated_maps() {
        let (bsp, world) = load(&map);
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let b = world.bounds();
        let mut rng = SplitMix64::new(11);
        let (mut checked, mut clip_checked) = (0usize, 0usize);
        for _ in 0..n {
            let p = random_point(&mut rng, b.min, b.max);
            if world.distance_to_boundary(p) >= 1e-3 {
                checked += 1;
                let want = world.contents(p).bsp_value();
                assert_eq!(
                    oracle.contents(p),
                    want,
                    "{}: contents at {p:?}",
                    map.display()
                );
                assert_eq!(
                    oracle.is_free(p),
                    world.is_free(p),
                    "{}: free at {p:?}",
                    map.display()
                );
            }
            for hull in 1..=3 {
                if world.hull_distance_to_boundary(hull, p) >= 1e-3 {
                    clip_checked += 1;
                    let want = world.hull_contents(hull, p).bsp_value();
                    assert_eq!(
                        oracle.clip_contents(hull, p),
                        Some(want),
                        "{}: hull {hull} at {p:?}",
                        map.display()
                    );
                }
            }
        }
        eprintln!(
            "{}: {checked} of {n} points agree exactly (hull 0); {clip_checked} clip-hull checks agree",
            map.display()
        );
        assert!(checked > n * 9 / 10);
    }
}

#[test]
fn segment_tests_match_exact_geometry() {
    let n = env_count("ORACLE_SEGMENTS", 20_000);
    for map in common::generated_maps() {
        let (bsp, world) = load(&map);
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let fb = world.free_bounds();
        let mut rng = SplitMix64::new(12);
        let (mut checked, mut free) = (0usize, 0usize);
        for i in 0..n {
            // Half short segments from free points (most of them free), half anywhere.
            let a = random_point(&mut rng, fb.min, fb.max);
            let b = if i % 2 == 0 {
                [0, 1, 2].map(|k| a[k] + rng.range(-200.0, 200.0))
            } else {
                random_point(&mut rng, fb.min, fb.max)
            };
            if world.segment_margin(a, b) < 1e-3 {
                continue;
            }
            checked += 1;
            let want = world.segment_free(a, b);
            free += want as usize;
            assert_eq!(
                oracle.segment_free(a, b),
                want,
                "{}: segment {a:?} - {b:?}",
                map.display()
            );
        }
        eprintln!(
            "{}: {checked} of {n} segments agree exactly ({free} free)",
            map.display()
        );
        // Both answers must occur often enough to mean something (a thin
        // world like the L corridor has ~3 % free segments in its box).
        assert!(checked > n / 2 && free > checked / 50 && free < checked);
    }
}

/// Samples lie on the exact walls only (no trigger, fence or water faces), and every
/// point of every exact wall lies within m of a sample.
#[test]
fn samples_cover_the_exact_walls_and_nothing_else() {
    for map in common::generated_maps() {
        let (bsp, world) = load(&map);
        let s = sample::sample(&bsp, &SampleOptions::default());
        for &p in &s.points {
            let d = world
                .wall_polygons()
                .iter()
                .map(|w| point_polygon_distance(p, &w.vertices, w.normal))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d < 1e-2,
                "{}: sample {p:?} is {d} from every wall",
                map.display()
            );
        }
        let grid = PointGrid::from_points(&s.points, s.spacing);
        let mut rng = SplitMix64::new(13);
        let walls = world.wall_polygons();
        let areas: Vec<f64> = walls.iter().map(|w| w.area()).collect();
        let total: f64 = areas.iter().sum();
        for _ in 0..20_000 {
            // Area-weighted wall, then a uniform point of it.
            let mut x = rng.next_f64() * total;
            let w = walls
                .iter()
                .zip(&areas)
                .find(|(_, a)| {
                    x -= **a;
                    x <= 0.0
                })
                .map_or(&walls[0], |(w, _)| w);
            let p = common::point_in_polygon(&w.vertices, &mut rng);
            let sky = w.class.texture() == "sky";
            let limit = if sky { 2.0 } else { 1.0 } * s.spacing;
            assert!(
                grid.nearest_within(p, limit).is_some(),
                "{}: wall point {p:?} is farther than {limit} from every sample",
                map.display()
            );
        }
    }
}

/// The obstacle boundary found in the BSP tree is exactly the manifest's walls: the
/// same area, every boundary point on a wall and every wall point on the boundary, and
/// wall distances from it equal the exact clearance.
#[test]
fn tree_boundary_is_exactly_the_walls() {
    for map in common::generated_maps() {
        let (bsp, world) = load(&map);
        let boundary = boundary::of_map(&bsp, &OracleOptions::default());
        let walls = world.wall_polygons();
        let exact_area: f64 = walls.iter().map(|w| w.area()).sum();
        let area: f64 = boundary.iter().map(|b| b.area()).sum();
        assert!(
            (area - exact_area).abs() <= 1e-6 * exact_area,
            "{}: boundary area {area} vs walls {exact_area}",
            map.display()
        );
        let mut rng = SplitMix64::new(29);
        for b in &boundary {
            for _ in 0..20 {
                let p = common::point_in_polygon(&b.vertices, &mut rng);
                let d = walls
                    .iter()
                    .map(|w| point_polygon_distance(p, &w.vertices, w.normal))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    d < 1e-3,
                    "{}: boundary point {p:?} is {d} off the walls",
                    map.display()
                );
                // The normal points into free space.
                let q = [0, 1, 2].map(|i| p[i] + 0.5 * b.normal[i]);
                if world.distance_to_boundary(q) > 1e-3 {
                    assert!(
                        world.is_free(q),
                        "{}: {q:?} in front of {p:?} is not free",
                        map.display()
                    );
                }
            }
        }
        let tree_walls = Walls::from_boundary(&boundary);
        for w in walls {
            for _ in 0..20 {
                let p = common::point_in_polygon(&w.vertices, &mut rng);
                assert!(
                    tree_walls.distance_within(p, 1e-3).is_some(),
                    "{}: wall point {p:?} is not on the boundary",
                    map.display()
                );
            }
        }
        let b = world.free_bounds();
        let (mut checked, mut k) = (0, 0);
        while checked < 2000 && k < 200_000 {
            k += 1;
            let p = random_point(&mut rng, b.min, b.max);
            if !world.is_free(p) {
                continue;
            }
            checked += 1;
            let (want, got) = (world.clearance(p), tree_walls.distance(p));
            assert!(
                (want - got).abs() < 1e-3,
                "{}: clearance at {p:?}: exact {want}, from the tree {got}",
                map.display()
            );
        }
        assert!(checked == 2000, "{}: too few free points", map.display());
    }
}

/// Distance from `p` to a convex planar polygon.
fn point_polygon_distance(p: [f64; 3], v: &[[f64; 3]], n: [f64; 3]) -> f64 {
    let h = dot(sub(p, v[0]), n);
    let q = [p[0] - h * n[0], p[1] - h * n[1], p[2] - h * n[2]];
    let inside = (0..v.len()).all(|i| {
        let e = sub(v[(i + 1) % v.len()], v[i]);
        let c = [
            e[1] * n[2] - e[2] * n[1],
            e[2] * n[0] - e[0] * n[2],
            e[0] * n[1] - e[1] * n[0],
        ];
        // Either winding: q on the same side of every edge.
        dot(sub(q, v[i]), c) <= 1e-9
    }) || (0..v.len()).all(|i| {
        let e = sub(v[(i + 1) % v.len()], v[i]);
        let c = [
            e[1] * n[2] - e[2] * n[1],
            e[2] * n[0] - e[0] * n[2],
            e[0] * n[1] - e[1] * n[0],
        ];
        dot(sub(q, v[i]), c) >= -1e-9
    });
    if inside {
        return h.abs();
    }
    (0..v.len())
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % v.len()]);
            let ab = sub(b, a);
            let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
            let d = sub(p, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]);
            dot(d, d).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}
