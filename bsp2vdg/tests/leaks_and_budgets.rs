//! One bad map must not cost a batch the others: a map that leaks compiles to a graph
//! of its inside (fenced by the world's bounds) with a warning and a pointfile, and a
//! map over its budget fails with that reason while the others compile.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::CompileOptions;
use bsp2vdg::pipeline::{self, CompileError};
use bsp2vdg::progress::NoProgress;
use mapgen::bsp::write_with_world_bounds;
use mapgen::worlds;

fn tempdir() -> toolbox::ScratchDir {
    toolbox::ScratchDir::new("bsp2vdg-leaks").unwrap()
}

#[test]
fn a_leaking_map_compiles_its_inside_with_a_warning_and_a_pointfile() {
    let (world, bounds) = worlds::leaking_room();
    let bytes = write_with_world_bounds(&world, bounds);
    let dir = tempdir();
    let map = dir.join("leaking_room.bsp");
    std::fs::write(&map, &bytes).unwrap();
    let out = dir.join("leaking_room.vdg");
    let log = Log::new(Verbosity::Quiet, true);
    let stats = pipeline::compile(&map, &CompileOptions::new(out.clone()), &log, &NoProgress)
        .unwrap_or_else(|e| panic!("{e}"));
    let leak = stats.leak.as_deref().expect("the leak is reported");
    assert!(leak.contains("info_player_start at (128 192 37)"), "{leak}");
    let pts = stats.pointfile.clone().expect("a pointfile");
    assert_eq!(pts, dir.join("leaking_room.pts"));
    let text = std::fs::read_to_string(&pts).unwrap();
    let first: Vec<f64> = text
        .lines()
        .next()
        .unwrap()
        .split(' ')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(first, vec![128.0, 192.0, 37.0]);
    // Every vertex of the graph lies inside the bounds and in free space.
    let file = vdgformat::VdgFile::from_bytes(&std::fs::read(&out).unwrap()).unwrap();
    let bsp = Bsp::parse(&bytes).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let g = file.graph();
    assert!(!g.vertices().is_empty());
    for v in g.vertices() {
        let p = v.pos.map(f64::from);
        assert!(
            (0..3).all(|i| p[i] >= bounds.min[i] - 1e-3 && p[i] <= bounds.max[i] + 1e-3),
            "{p:?} outside the bounds"
        );
        assert!(oracle.is_free(p), "{p:?} not free");
        // A clearance no larger than the room's half height (the void is not free).
        assert!(v.clearance <= 130.0, "{p:?} clearance {}", v.clearance);
    }
}

#[test]
fn a_map_over_its_budget_fails_with_the_reason() {
    let dir = tempdir();
    let map = dir.join("box_room.bsp");
    std::fs::write(&map, mapgen::bsp::write_world(&worlds::box_room())).unwrap();
    let log = Log::new(Verbosity::Quiet, true);
    let mut options = CompileOptions::new(dir.join("box_room.vdg"));
    // A budget of microseconds: the first stage after loading is over it.
    options.budget = 1e-9;
    let err = pipeline::compile(&map, &options, &log, &NoProgress).unwrap_err();
    assert!(matches!(err, CompileError::OverBudget { .. }), "{err}");
    assert!(err.to_string().contains("over the map's budget"), "{err}");
    assert!(!dir.join("box_room.vdg").exists());
    // The same map with its normal budget compiles.
    options.budget = 1.0;
    pipeline::compile(&map, &options, &log, &NoProgress).unwrap();
}

/// The points of a pointfile (`x y z` per line), which must parse.
fn pointfile_points(path: &std::path::Path) -> Vec<[f64; 3]> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .map(|l| {
            let v: Vec<f64> = l.split(' ').map(|x| x.parse().unwrap()).collect();
            assert_eq!(v.len(), 3, "{l}");
            [v[0], v[1], v[2]]
        })
        .collect()
}

#[test]
fn a_map_without_a_graph_gets_a_pointfile_of_its_player_starts() {
    let dir = tempdir();
    let map = dir.join("box_room.bsp");
    let world = worlds::box_room();
    std::fs::write(&map, mapgen::bsp::write_world(&world)).unwrap();
    let out = dir.join("box_room.vdg");
    let mut options = CompileOptions::new(out.clone());
    // No free space has this much clearance: the graph is empty.
    options.min_clearance = 1000.0;
    let log = Log::new(Verbosity::Quiet, true);
    let err = pipeline::compile(&map, &options, &log, &NoProgress).unwrap_err();
    let pts = dir.join("box_room.pts");
    assert!(matches!(err, CompileError::EmptyGraph { .. }), "{err}");
    assert!(
        err.to_string()
            .contains(&format!("pointfile {}", pts.display())),
        "{err}"
    );
    assert!(!out.exists());
    let mut spawns: Vec<[f64; 3]> = world.spawn_points().to_vec();
    spawns.dedup();
    assert_eq!(pointfile_points(&pts), spawns);
}

#[test]
fn standing_places_the_graph_misses_are_written_as_a_pointfile() {
    // two_rooms: a 128-wide, 112-high corridor between two rooms. With -md 60 no
    // Voronoi vertex of the corridor keeps its clearance, so the graph misses its floor.
    let dir = tempdir();
    let map = dir.join("two_rooms.bsp");
    let bytes = mapgen::bsp::write_world(&worlds::two_rooms());
    std::fs::write(&map, &bytes).unwrap();
    let out = dir.join("two_rooms.vdg");
    let missed_pts = dir.join("two_rooms.missed.pts");
    let log = Log::new(Verbosity::Quiet, true);
    let mut options = CompileOptions::new(out.clone());
    options.min_clearance = 60.0;
    let stats =
        pipeline::compile(&map, &options, &log, &NoProgress).unwrap_or_else(|e| panic!("{e}"));
    let missed = stats.missed_places.expect("the coverage was checked");
    assert_eq!(
        stats.missed_pointfile.as_deref(),
        Some(missed_pts.as_path())
    );
    let points = pointfile_points(&missed_pts);
    assert_eq!(points.len(), missed);
    let bsp = Bsp::parse(&bytes).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let file = vdgformat::VdgFile::from_bytes(&std::fs::read(&out).unwrap()).unwrap();
    let g = file.graph();
    let in_corridor = |p: [f64; 3]| p[0] > 368.0 && p[0] < 656.0 && p[1] > 128.0 && p[1] < 256.0;
    for p in &points {
        // Each is a standing place (to the pointfile's tenth of a unit) (the player hull fits on a floor) outside the volume.
        assert!(
            bsp::player::on_floor(&oracle, *p, false),
            "{p:?} is no standing place"
        );
        assert!(
            !g.contains(p.map(|x| x as f32)),
            "{p:?} is inside the volume"
        );
    }
    // The largest cluster, first in the file, is the corridor's floor, and most of the
    // missed places are there.
    let corridor = points.iter().filter(|p| in_corridor(**p)).count();
    assert!(in_corridor(points[0]), "{:?}", points[0]);
    assert!(
        corridor * 2 > missed,
        "{corridor} of {missed} in the corridor"
    );
    // Every standing place of the corridor is missed (none of its vertices survived).
    let standing = bsp::player::grid_origins(
        &oracle,
        [0.0, 0.0, 0.0],
        [1024.0, 384.0, 192.0],
        bsp::player::KEEP_SPACING,
    );
    let corridor_places = standing
        .iter()
        .filter(|p| in_corridor(**p) && p[0] > 400.0 && p[0] < 620.0);
    for p in corridor_places {
        let listed = points
            .iter()
            .any(|q| (0..3).all(|i| (q[i] - p[i]).abs() <= 0.06));
        assert!(listed, "{p:?} in the corridor is not in the pointfile");
    }

    // At the default -md the graph covers every standing place: no pointfile, and the
    // earlier one is removed.
    let stats = pipeline::compile(&map, &CompileOptions::new(out.clone()), &log, &NoProgress)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stats.missed_places, Some(0));
    assert!(stats.missed_pointfile.is_none());
    assert!(!missed_pts.exists());
}

#[test]
fn a_batch_fails_the_map_over_its_budget_and_compiles_the_one_under_it() {
    let dir = tempdir();
    let small = dir.join("box_room.bsp");
    let large = dir.join("open_field.bsp");
    std::fs::write(&small, mapgen::bsp::write_world(&worlds::box_room())).unwrap();
    std::fs::write(&large, mapgen::bsp::write_world(&worlds::open_field())).unwrap();
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    // At -sd 8 the field has a few hundred thousand wall samples in a file of a few
    // kilobytes: its Delaunay stage would need more memory than a twentieth of a
    // normal budget allows (about 0.2 GB). The box room's ~13 000 need a tenth of that,
    // and its ~30 s are many times what it takes.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_bsp2vdg"))
        .args(["--budget", "0.05", "-sd", "8", "-nolog", "-o"])
        .arg(&out)
        .arg(&large)
        .arg(&small)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert_eq!(o.status.code(), Some(1), "{stdout}");
    // The summary table's row of a map.
    let line = |name: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no line for {name} in\n{stdout}"))
            .to_string()
    };
    let failed = line("open_field.bsp");
    assert!(
        failed.contains("FAILED") && failed.contains("delaunay stage went over the map's budget"),
        "{stdout}"
    );
    assert!(line("box_room.bsp").ends_with(" ok"), "{stdout}");
    assert!(out.join("box_room.vdg").exists());
    assert!(!out.join("open_field.vdg").exists());
}
