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
