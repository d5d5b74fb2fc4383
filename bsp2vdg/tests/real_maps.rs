//! The foundation against real compiled maps (../shared/testmaps; skipped when absent):
//! every map reads, player spawns are free, samples sit on the boundary between free
//! space and obstacles, and every face point lies within m of a sample.

mod common;

use bsp::Bsp;
use bsp::boundary;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use bsp2vdg::sample::{self, SampleOptions, classify::FaceClass, grid::PointGrid};

const SPAWNS: [&str; 4] = [
    "info_player_start",
    "info_player_deathmatch",
    "info_player_terrorist",
    "info_player_counterterrorist",
];

#[test]
fn every_goldsrc_and_quake_map_reads() {
    let Some(maps) =
        common::shared_maps(&["goldsrc", "goldsrc/nonfree", "quake1", "quake1/nonfree"])
    else {
        return;
    };
    assert!(!maps.is_empty());
    for m in &maps {
        let bsp = Bsp::open(m).unwrap_or_else(|e| panic!("{}: {e}", m.display()));
        assert!(!bsp.faces.is_empty(), "{}", m.display());
    }
}

#[test]
fn foreign_bsp_versions_are_refused_clearly() {
    // Formats we know but do not read: the error names them.
    for (head, name) in [
        (
            &b"IBSP\x2f\0\0\0"[..],
            "Quake Live / Wolfenstein: ET BSP (IBSP 47)",
        ),
        (&b"VBSP\x14\0\0\0"[..], "Source BSP (VBSP)"),
        (&b"RBSP\x01\0\0\0"[..], "Raven BSP"),
    ] {
        let mut bytes = head.to_vec();
        bytes.resize(4096, 0);
        let err = Bsp::parse(&bytes).expect_err("not read").to_string();
        assert!(err.starts_with(name), "the error names the format: {err}");
    }
}

/// Spawns, sample sides and covering on a few maps of each family.
#[test]
fn oracle_and_samples_agree_with_the_maps() {
    let Some(maps) =
        common::shared_maps(&["goldsrc", "goldsrc/nonfree", "quake1", "quake1/nonfree"])
    else {
        return;
    };
    let chosen = maps.iter().filter(|m| {
        let n = m.to_string_lossy();
        !n.contains("nonfree")
            || n.contains("de_dust2")
            || n.contains("c1a0.bsp")
            || n.contains("quake_start")
    });
    for path in chosen {
        let bsp = Bsp::open(path).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        for e in bsp
            .entities
            .iter()
            .filter(|e| SPAWNS.contains(&e.classname()))
        {
            let o = e.origin().unwrap().map(f64::from);
            if outside_fence(&oracle, o) {
                // A leaking map's spawn in the void beyond its world bounds: the
                // oracle counts that as solid by design (nothing to guide there).
                continue;
            }
            assert!(
                oracle.is_free(o),
                "{}: spawn at {o:?} is not free",
                path.display()
            );
        }

        let mut faces = sample::collect_faces(&bsp, &[]);
        sample::cull_by_contents(&mut faces, |p| oracle.is_free(p));
        let s = sample::sample_faces(&faces, &SampleOptions::default());
        // Behind every sample (one unit through its face) lies an obstacle — except on
        // face edges, where the probe lands on the neighbouring face's plane.
        let mut inner = 0usize;
        let mut blocked = 0usize;
        for (p, &f) in s.points.iter().zip(&s.source_face) {
            let face = faces.iter().find(|x| x.index == f).unwrap();
            if edge_distance(&face.polygon, *p) <= 1.0 {
                continue;
            }
            let n = face.normal;
            inner += 1;
            blocked += !oracle.is_free([p[0] - n[0], p[1] - n[1], p[2] - n[2]]) as usize;
        }
        if inner > 0 {
            let share = blocked as f64 / inner as f64;
            assert!(
                share >= 0.995,
                "{}: only {share} of samples have an obstacle behind",
                path.display()
            );
        }

        // Covering: random points of sampled faces are within m (2m on sky) of a sample.
        let sampled: Vec<&sample::SampledFace> = faces
            .iter()
            .filter(|f| !matches!(f.class, FaceClass::Skip(_)))
            .collect();
        let grid = PointGrid::from_points(&s.points, s.spacing);
        for (p, fi) in sample::random_face_points(&sampled, 5_000, 7) {
            let limit = if sampled[fi].class == FaceClass::Sky {
                2.0
            } else {
                1.0
            } * s.spacing;
            assert!(
                grid.nearest_within(p, limit).is_some(),
                "{}: {p:?} is farther than {limit} from every sample",
                path.display()
            );
        }
    }
}

fn edge_distance(poly: &[[f64; 3]], p: [f64; 3]) -> f64 {
    (0..poly.len())
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
            let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
            let l2 = ab.iter().map(|x| x * x).sum::<f64>();
            let t = if l2 > 0.0 {
                (ap.iter().zip(&ab).map(|(x, y)| x * y).sum::<f64>() / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (0..3)
                .map(|k| (a[k] + t * ab[k] - p[k]).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The obstacle boundary taken from the BSP tree: free space in front of it and an
/// obstacle behind (the oracle agrees), and every point of it within m of a sample,
/// also where the compiler left no face (solid blocks textured `NULL`).
#[test]
fn tree_boundary_bounds_free_space_and_is_sampled() {
    let Some(maps) =
        common::shared_maps(&["goldsrc", "goldsrc/nonfree", "quake1", "quake1/nonfree"])
    else {
        return;
    };
    for path in &maps {
        let bsp = Bsp::open(path).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let b = boundary::of_map(&bsp, &OracleOptions::default());
        let (mut inner, mut agree) = (0usize, 0usize);
        let mut rng = toolbox::SplitMix64::new(3);
        for poly in &b {
            for _ in 0..4 {
                let p = common::point_in_polygon(&poly.vertices, &mut rng);
                if edge_distance(&poly.vertices, p) <= 1.0 {
                    continue;
                }
                let n = poly.normal;
                // A tenth of a unit: some free leaves are thinner than half a unit.
                let front = [0, 1, 2].map(|i| p[i] + 0.1 * n[i]);
                let back = [0, 1, 2].map(|i| p[i] - 0.1 * n[i]);
                if outside_fence(&oracle, front) || outside_fence(&oracle, back) {
                    // On a leaking map's world bounds: beyond them is solid by design.
                    continue;
                }
                inner += 1;
                agree += (oracle.is_free(front) && !oracle.is_free(back)) as usize;
            }
        }
        if inner > 0 {
            let share = agree as f64 / inner as f64;
            assert!(
                share >= 0.995,
                "{}: only {share} of boundary points have free space in front and an obstacle behind",
                path.display()
            );
        }
        let n = path.to_string_lossy();
        if !(n.contains("de_cbble") || n.contains("de_dust2") || n.contains("c1a0.bsp")) {
            continue;
        }
        let s = sample::sample(&bsp, &SampleOptions::default());
        if n.contains("de_cbble") {
            assert!(
                s.hidden_samples > 1000,
                "{}: {} hidden samples",
                path.display(),
                s.hidden_samples
            );
        }
        let grid = PointGrid::from_points(&s.points, s.spacing);
        // Sky-textured faces are sampled at 2m even where the tree calls the leaf solid.
        let mut faces = sample::collect_faces(&bsp, &[]);
        faces.retain(|f| f.class == FaceClass::Sky);
        let sky = Walls::from_faces(&faces);
        for poly in &b {
            let p = common::point_in_polygon(&poly.vertices, &mut rng);
            let on_sky = sky.distance_within(p, 0.5).is_some();
            let limit = if on_sky || poly.obstacle == bsp::contents::SKY {
                2.0
            } else {
                1.0
            } * s.spacing;
            assert!(
                grid.nearest_within(p, limit).is_some(),
                "{}: boundary point {p:?} is farther than {limit} from every sample",
                path.display()
            );
        }
    }
}

/// Quake 2 and 3 players crouch in boxes of their own heights: the crouch-only places
/// found through the hulls built from the brushes agree with the player's boxes
/// against the brushes themselves, with the games' numbers written out here (`pmove.c`,
/// `bg_pmove.c`: the box reaches 24 units below the origin in both stances; the
/// crouched view is 2 units below the origin in Quake 2, 12 above it in Quake 3). Each
/// eye lies that high above the floor straight below it (the point hull's), and at the
/// origin there the crouched box is free just above and stuck 1 unit lower (its floor
/// right there) while the standing box is stuck — at every place. Quake 3's shared
/// maps have no such places; the Quake 2 ones do (the LibreQuake conversions' vents,
/// the example's low gaps).
#[test]
fn quake2_and_3_crouch_places_agree_with_the_player_boxes() {
    use bsp::oracle::PlayerHull;
    use bsp::{Game, contents::SOLID};
    let Some(maps) = common::shared_maps(&["quake2", "quake3"]) else {
        return;
    };
    let (mut places, mut disagree) = (0usize, Vec::new());
    for path in &maps {
        let bsp = Bsp::open(path).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let eye_above_ground = match bsp.game {
            Game::Quake2 => 24.0 - 2.0,
            Game::Quake3 => 24.0 + 12.0,
            g => panic!("{}: {g:?}", path.display()),
        };
        let eyes = vdgcheck::crouch_eyes(&bsp, &oracle, 20_000, 1);
        let stuck = |hull, p: [f64; 3]| oracle.player_contents(hull, p) == Some(SOLID);
        // The point hull's floor below `p` (within 64 units), to a hundredth.
        let floor = |p: [f64; 3]| {
            let (mut free, mut solid) = (p[2], p[2] - 64.0);
            if oracle.segment_free(p, [p[0], p[1], solid]) {
                return None;
            }
            while free - solid > 0.01 {
                let mid = 0.5 * (free + solid);
                if oracle.segment_free(p, [p[0], p[1], mid]) {
                    free = mid;
                } else {
                    solid = mid;
                }
            }
            Some(free)
        };
        for e in &eyes {
            let ok = floor(*e).is_some_and(|f| {
                let o = [e[0], e[1], f + 24.0];
                // A quarter of a unit above the floor: some gaps are barely taller
                // than the crouched box (28.5 units on the example maps' ledge).
                (e[2] - f - eye_above_ground).abs() <= 2.0
                    && !stuck(PlayerHull::Crouched, [o[0], o[1], o[2] + 0.25])
                    && stuck(PlayerHull::Crouched, [o[0], o[1], o[2] - 1.0])
                    && stuck(PlayerHull::Standing, [o[0], o[1], o[2] + 0.25])
            });
            if !ok {
                disagree.push((path.file_name().unwrap().to_owned(), *e));
            }
        }
        places += eyes.len();
    }
    assert!(
        maps.is_empty() || (places > 100 && disagree.is_empty()),
        "{} of {places} crouch places on the Quake 2 and 3 maps disagree with the player's boxes: {:?}",
        disagree.len(),
        &disagree[..disagree.len().min(10)]
    );
}

/// Whether `p` lies beyond the world bounds that fence a leaking map's free space.
fn outside_fence(oracle: &Oracle, p: [f64; 3]) -> bool {
    oracle
        .fence()
        .is_some_and(|(lo, hi)| (0..3).any(|i| p[i] < lo[i] || p[i] > hi[i]))
}
