//! `check` on the generated maps: the compiler's graphs must not leak or see through
//! walls, and a graph that does must be caught.

use bsp::Bsp;
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::CompileOptions;
use bsp2vdg::pipeline;
use bsp2vdg::progress::NoProgress;
use std::path::{Path, PathBuf};
use vdgcheck::{CheckOptions, check};

fn generated_maps() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../testdata/maps");
    let mut maps: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        .collect();
    maps.sort();
    maps
}

fn compile(map: &Path, out: &Path) {
    let options = CompileOptions {
        reduction_limit: 1.0,
        ..CompileOptions::new(out.to_path_buf())
    };
    pipeline::compile(
        map,
        &options,
        &Log::new(Verbosity::Quiet, true),
        &NoProgress,
    )
    .unwrap();
}

fn tempdir() -> toolbox::ScratchDir {
    toolbox::ScratchDir::new("vdgview-check").unwrap()
}

#[test]
fn compiled_graphs_do_not_leak_or_see_through_walls() {
    let dir = tempdir();
    for map in generated_maps() {
        let out = dir.join(map.file_name().unwrap()).with_extension("vdg");
        compile(&map, &out);
        let bsp = Bsp::open(&map).unwrap();
        let file = vdgformat::VdgFile::open(&out).unwrap();
        let options = CheckOptions {
            samples: 20_000,
            ..Default::default()
        };
        let r = check(&bsp, &file.graph(), 0, &options);
        eprintln!("{}: {}", map.display(), r.to_json());
        assert_eq!(r.leaked, 0, "{}: leak", map.display());
        assert_eq!(
            r.false_positives,
            0,
            "{}: visible through a wall",
            map.display()
        );
        assert!(
            r.coverage() > 0.95,
            "{}: coverage {}",
            map.display(),
            r.coverage()
        );
        assert!(r.free_segments > 0 && r.visible > 0);
        // Every generated map has standing places, so camera sight lines to them.
        assert_eq!(
            r.camera_false_positives,
            0,
            "{}: a camera saw its target through a wall",
            map.display()
        );
        assert!(
            r.camera_lines > 1000 && r.camera_lines_inside > 0,
            "{}: {} camera lines",
            map.display(),
            r.camera_lines
        );
        // Where the camera looks from, Visible misses few of the lines it could see.
        assert!(
            r.visible_fn_camera().is_some_and(|f| f <= 0.02),
            "{}: camera sight lines missed {:?}",
            map.display(),
            r.visible_fn_camera()
        );
        // Same figures for the same seed.
        let mut again = check(&bsp, &file.graph(), 0, &options);
        (again.seconds, again.seconds_parts) = (r.seconds, r.seconds_parts);
        assert_eq!(again, r);
    }
}

#[test]
fn an_inflated_graph_is_caught_leaking() {
    let dir = tempdir();
    let map = generated_maps()
        .into_iter()
        .find(|m| m.ends_with("two_rooms.bsp"))
        .unwrap();
    let out = dir.join("two_rooms_honest.vdg");
    compile(&map, &out);
    let file = vdgformat::VdgFile::open(&out).unwrap();
    let g = file.graph();
    // Triple every clearance: the volume now reaches through the walls.
    let mut b = vdgformat::VdgBuilder::new();
    for v in g.vertices() {
        b.add_vertex(v.pos, v.clearance * 3.0);
    }
    for f in g.faces() {
        b.add_face(f);
    }
    let bytes = b.to_bytes().unwrap();
    let inflated = vdgformat::VdgFile::from_bytes(&bytes).unwrap();
    let bsp = Bsp::open(&map).unwrap();
    let r = check(
        &bsp,
        &inflated.graph(),
        bytes.len(),
        &CheckOptions {
            samples: 20_000,
            ..Default::default()
        },
    );
    assert!(r.leaked > 0 && !r.passed(), "{}", r.to_json());
    // A camera behind the wall between the rooms sees the player in the other one.
    assert!(r.camera_false_positives > 0, "{}", r.to_json());
}

/// The camera sight lines start at a camera's distance and elevation from standing
/// origins, in free space; whether the BSP lets each through is the exact answer of
/// the map's manifest; and the lines are the same for any thread count.
#[test]
fn camera_lines_are_where_a_camera_looks_from_and_exact() {
    use bsp::oracle::{Oracle, OracleOptions};
    use vdgcheck::{CAMERA_DISTANCE, CAMERA_ELEVATION_DEG, camera_lines, standing_places};
    for map in generated_maps() {
        let bsp = Bsp::open(&map).unwrap();
        let world = mapgen::world::World::from_manifest_json(
            &std::fs::read_to_string(map.with_extension("json")).unwrap(),
        )
        .unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let targets: Vec<[f64; 3]> = standing_places(&bsp, &oracle, 5_000, 3)
            .iter()
            .map(|s| s.origin)
            .collect();
        let lines = camera_lines(&targets, &oracle, 3);
        assert!(
            lines.len() > targets.len() * 9 / 10,
            "{}: {} lines for {} targets",
            map.display(),
            lines.len(),
            targets.len()
        );
        let (mut blocked, mut compared) = (0, 0);
        for &(camera, target, free) in &lines {
            let d: [f64; 3] = [0, 1, 2].map(|i| camera[i] - target[i]);
            let len = d.iter().map(|c| c * c).sum::<f64>().sqrt();
            let pitch = (d[2] / len).asin().to_degrees();
            assert!(
                (CAMERA_DISTANCE.0 - 0.01..=CAMERA_DISTANCE.1 + 0.01).contains(&len),
                "{len}"
            );
            assert!(
                (CAMERA_ELEVATION_DEG.0 - 0.01..=CAMERA_ELEVATION_DEG.1 + 0.01).contains(&pitch),
                "{pitch}"
            );
            assert!(world.is_free(camera), "{}: {camera:?}", map.display());
            // Lines grazing a wall within rounding are left out of the comparison.
            if world.segment_margin(camera, target).abs() < 1e-2 {
                continue;
            }
            compared += 1;
            blocked += !free as usize;
            assert_eq!(
                free,
                world.segment_free(camera, target),
                "{}: {camera:?} -> {target:?}",
                map.display()
            );
        }
        assert!(compared > lines.len() * 9 / 10, "{}", map.display());
        eprintln!(
            "{}: {} camera lines, {blocked} blocked",
            map.display(),
            lines.len()
        );
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| camera_lines(&targets, &oracle, 3));
        assert_eq!(one, lines, "{}", map.display());
    }
}

/// World brushes with `{` alpha textures are solid in the BSP: the graph must treat
/// them as walls (a name-only skip let the volume pass through the fence).
#[test]
fn alpha_textured_world_brushes_are_walls() {
    let map = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/testmaps/goldsrc/allocblock-in-bsp-texture-test.bsp");
    if !map.exists() {
        eprintln!("skipped: {} is absent", map.display());
        return;
    }
    let dir = tempdir();
    let out = dir.join("fence.vdg");
    compile(&map, &out);
    let bsp = Bsp::open(&map).unwrap();
    let file = vdgformat::VdgFile::open(&out).unwrap();
    let r = check(
        &bsp,
        &file.graph(),
        0,
        &CheckOptions {
            samples: 20_000,
            ..Default::default()
        },
    );
    assert!(r.leaked == 0 && r.false_positives == 0, "{}", r.to_json());
}

/// The exact player floors of column (x, y) of a generated world: heights where clip
/// hull 1 turns from free to solid going down, found by a scan and bisection of the
/// exact `hull_contents`.
fn exact_floors(world: &mapgen::world::World, x: f64, y: f64, top: f64, bottom: f64) -> Vec<f64> {
    let free = |z: f64| world.hull_contents(1, [x, y, z]) == mapgen::Contents::Empty;
    let mut floors = Vec::new();
    let step = 0.5;
    let mut z = top;
    while z - step > bottom {
        if free(z) && !free(z - step) {
            let (mut hi, mut lo) = (z, z - step);
            for _ in 0..40 {
                let m = 0.5 * (hi + lo);
                if free(m) { hi = m } else { lo = m }
            }
            floors.push(hi);
        }
        z -= step;
    }
    floors
}

/// The standing-place sampler against the generated maps' exact clip hull 1: every
/// place it draws is an exact floor, and in random columns it finds every exact floor
/// of walkable slope (and none steeper).
#[test]
fn standing_places_are_the_exact_player_floors() {
    use bsp::oracle::{Oracle, OracleOptions};
    use bsp::player::column_floors;
    use vdgcheck::standing_places;
    for map in generated_maps() {
        let world = mapgen::world::World::from_manifest_json(
            &std::fs::read_to_string(map.with_extension("json")).unwrap(),
        )
        .unwrap();
        let bsp = Bsp::open(&map).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let hull = oracle.clip_hull(1).unwrap();
        let places = standing_places(&bsp, &oracle, 2000, 7);
        assert_eq!(places.len(), 2000, "{}", map.display());
        for s in &places {
            let [x, y, z] = s.origin;
            let (above, below) = ([x, y, z + 0.01], [x, y, z - 0.01]);
            if world.hull_distance_to_boundary(1, above) < 0.005
                || world.hull_distance_to_boundary(1, below) < 0.005
            {
                continue;
            }
            assert_eq!(
                world.hull_contents(1, above),
                mapgen::Contents::Empty,
                "{s:?}"
            );
            assert_eq!(
                world.hull_contents(1, below),
                mapgen::Contents::Solid,
                "{s:?}"
            );
            let head = [x, y, z + 28.0];
            assert_eq!(s.head.is_some(), world.is_free(head), "{s:?}");
        }
        let b = world.bounds();
        let (top, bottom) = (b.max[2] + 1.0, b.min[2] - 1.0);
        let mut rng = toolbox::SplitMix64::new(11);
        let (mut compared, mut found) = (0, 0);
        for _ in 0..300 {
            let (x, y) = (rng.range(b.min[0], b.max[0]), rng.range(b.min[1], b.max[1]));
            let ours = column_floors(hull, &oracle, x, y, top, bottom);
            for f in exact_floors(&world, x, y, top, bottom) {
                // The exact slope from the neighbouring columns; skip edges and steps.
                let near = |dx: f64, dy: f64| {
                    exact_floors(&world, x + dx, y + dy, f + 2.0, f - 2.0)
                        .first()
                        .copied()
                };
                let (Some(e), Some(w), Some(n), Some(s)) = (
                    near(0.5, 0.0),
                    near(-0.5, 0.0),
                    near(0.0, 0.5),
                    near(0.0, -0.5),
                ) else {
                    continue;
                };
                let gradient = ((e - w).powi(2) + (n - s).powi(2)).sqrt();
                // Normal z >= 0.7 means gradient <= tan(acos 0.7) = 1.0202.
                let hit = ours.iter().any(|z| (z - f).abs() < 0.01);
                if gradient < 1.0 {
                    compared += 1;
                    found += hit as usize;
                    assert!(
                        hit,
                        "{}: floor {f} at ({x}, {y}) missed: {ours:?}",
                        map.display()
                    );
                } else if gradient > 1.05 {
                    assert!(
                        !hit,
                        "{}: steep floor {f} at ({x}, {y}) taken",
                        map.display()
                    );
                }
            }
            // No floor of ours that is not exact.
            for z in &ours {
                let ok = exact_floors(&world, x, y, z + 1.0, z - 1.0)
                    .iter()
                    .any(|f| (f - z).abs() < 0.01);
                assert!(
                    ok,
                    "{}: floor {z} at ({x}, {y}) is not exact",
                    map.display()
                );
            }
        }
        eprintln!(
            "{}: {found} of {compared} exact floors found",
            map.display()
        );
        assert!(
            compared > 30,
            "{}: only {compared} floors compared",
            map.display()
        );
    }
}

/// Walkable coverage of the unreduced graphs of the generated maps, and the figure is
/// the share of exact standing places inside the volume.
#[test]
fn walkable_coverage_of_generated_maps() {
    use bsp::oracle::{Oracle, OracleOptions};
    use vdgcheck::standing_places;
    let dir = tempdir();
    for map in generated_maps() {
        let out = dir
            .join(map.file_name().unwrap())
            .with_extension("walk.vdg");
        compile(&map, &out);
        let bsp = Bsp::open(&map).unwrap();
        let file = vdgformat::VdgFile::open(&out).unwrap();
        let options = CheckOptions {
            samples: 10_000,
            ..Default::default()
        };
        let r = check(&bsp, &file.graph(), 0, &options);
        eprintln!(
            "{}: walkable {:?} head {:?} of {}",
            map.display(),
            r.walkable_coverage(),
            r.walkable_coverage_head(),
            r.walkable_points
        );
        assert_eq!(r.walkable_points, 10_000);
        // The same figure from the places checked against the exact world.
        let world = mapgen::world::World::from_manifest_json(
            &std::fs::read_to_string(map.with_extension("json")).unwrap(),
        )
        .unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let places = standing_places(&bsp, &oracle, 10_000, options.seed);
        let g = file.graph();
        let exact_inside = places
            .iter()
            .filter(|s| {
                let [x, y, z] = s.origin;
                world.hull_contents(1, [x, y, z + 0.01]) == mapgen::Contents::Empty
                    && g.contains(s.origin.map(|c| c as f32))
            })
            .count();
        assert_eq!(exact_inside, r.walkable_covered, "{}", map.display());
        assert!(
            r.walkable_coverage().is_some_and(|w| w > 0.9),
            "{}: walkable coverage {:?}",
            map.display(),
            r.walkable_coverage()
        );
    }
}
