//! `replay` on the generated maps, whose geometry is known exactly (mapgen): the routes
//! stay on the floor and free for the player's hull, the chase cam and the spring arm
//! behave as specified at a wall, and the CLI writes every output with the JSON keys
//! the measuring scripts read.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use mapgen::world::Contents;
use std::path::{Path, PathBuf};
use std::process::Command;
use vdgview::replay::cameras::{ChaseCam, ReplayCamera, SpringArm};
use vdgview::replay::route::TargetState;
use vdgview::replay::spawns;
use vdgview::replay::walk::{Waypoint, walk, walk_parts};

fn map(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../testdata/maps")
        .join(format!("{name}.bsp"))
}

fn target(origin: [f32; 3], yaw: f32) -> TargetState {
    TargetState {
        t: 0.0,
        origin,
        angles: [0.0, yaw, 0.0],
        velocity: [0.0; 3],
        crouch: false,
        game: bsp::Game::GoldSrc,
    }
}

#[test]
fn spawn_routes_stay_on_the_floor_and_free_for_the_player_hull() {
    for world in mapgen::worlds::worlds() {
        if world.spawn_points().len() < 2 {
            continue;
        }
        let bsp = Bsp::open(map(&world.name)).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let (routes, stats, unreachable) = spawns::routes(&bsp, &oracle, 1, 2);
        assert!(!routes.is_empty(), "{}: no route", world.name);
        assert_eq!(unreachable, 0, "{}", world.name);
        for (r, s) in routes.iter().zip(&stats) {
            assert_eq!(s.stuck_steps, 0, "{} {}", world.name, r.name);
            assert!(r.duration() > 1.0, "{} {}", world.name, r.name);
            let mut top = 0.0f32;
            for t in r.resample(1.0 / 60.0) {
                let hull = if t.crouch { 3 } else { 1 };
                let o = t.origin.map(f64::from);
                // Exact geometry: the hull is free, and 2 units lower it is not (on the floor).
                assert_eq!(
                    world.hull_contents(hull, o),
                    Contents::Empty,
                    "{} {} t={:.2}: hull {hull} at {o:?} not free",
                    world.name,
                    r.name,
                    t.t
                );
                // On the floor, unless falling off a ledge.
                assert!(
                    t.velocity[2] < 0.0
                        || world.hull_contents(hull, [o[0], o[1], o[2] - 2.0]) != Contents::Empty,
                    "{} {} t={:.2}: floating at {o:?}",
                    world.name,
                    r.name,
                    t.t
                );
                top = top.max(t.speed());
            }
            assert!(
                top > 240.0 && top < 300.0,
                "{}: top speed {top}",
                world.name
            );
        }
    }
}

/// A spawn route ends as a player arriving does: letting go of the keys in time to
/// slide to rest at the path's end under the game's friction, then standing there for
/// half a second. The walker used to run into the end at full speed and stop dead in
/// one step (250 units/s lost in 1/120 s, which no GoldSrc player can do), the largest
/// jerk of every route for any camera that follows the player.
#[test]
fn a_spawn_route_slides_to_rest_at_its_end() {
    let step = 1.0 / 120.0;
    for world in mapgen::worlds::worlds() {
        if world.spawn_points().len() < 2 {
            continue;
        }
        let bsp = Bsp::open(map(&world.name)).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let (routes, stats, _) = spawns::routes(&bsp, &oracle, 1, 2);
        for (r, s) in routes.iter().zip(&stats) {
            if s.cut_short || s.climb_steps > 0 {
                continue;
            }
            let speed = |t: &TargetState| f64::from(t.velocity[0]).hypot(f64::from(t.velocity[1]));
            // The last 0.6 s before coming to rest: a stop from a run takes about
            // half a second under friction.
            let end = r.states.last().unwrap();
            let moving = r.states.len()
                - r.states
                    .iter()
                    .rev()
                    .take_while(|t| speed(t) < 1.0 && t.origin == end.origin)
                    .count();
            let rest = r.states.len() - moving;
            let from = moving.saturating_sub((0.6 / step) as usize);
            for w in r.states[from..=moving.min(r.states.len() - 1)].windows(2) {
                let (v0, v1) = (speed(&w[0]), speed(&w[1]));
                // Friction: 4 × max(v, 100) units/s², and a little for the corners the
                // settled feet cut.
                let most = 4.0 * v0.max(100.0) * step + 2.0;
                assert!(
                    v0 - v1 <= most,
                    "{} {}: {v0:.1} → {v1:.1} units/s at t={:.3}",
                    world.name,
                    r.name,
                    w[1].t
                );
            }
            assert!(
                rest as f64 * step >= 0.45,
                "{} {}: at rest for {rest} steps at the end",
                world.name,
                r.name
            );
        }
    }
}

/// A standing waypoint of a path at `(x, y)` on the floor at height `floor`.
fn standing(x: f64, y: f64, floor: f64) -> Waypoint {
    Waypoint {
        x,
        y,
        floor,
        crouch: false,
    }
}

/// Walking off the ramp map's ledge (128 units above the floor) the player falls under
/// gravity, as in the game: no frame moves more than a step down, the fall lasts as long
/// as a 128-unit drop at 800 units/s² does (0.57 s), the hull stays free all the way,
/// and the route reaches its end on the floor below. The walker used to land in one
/// frame, a 128-unit jump that any camera must take as a cut.
#[test]
fn walking_off_a_ledge_is_a_fall_not_a_jump() {
    let world = mapgen::worlds::ramp();
    let bsp = Bsp::open(map("ramp")).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let path = [standing(640.0, 96.0, 128.0), standing(640.0, 420.0, 0.0)];
    let (route, stats) = walk(&oracle, "off the ledge", &path, 7);
    assert_eq!(stats.falls, 1, "{stats:?}");
    assert!(!stats.cut_short, "{stats:?}");
    let states = &route.states;
    let (mut top, mut bottom) = (None, None);
    for w in states.windows(2) {
        let dz = f64::from(w[1].origin[2] - w[0].origin[2]);
        assert!(
            dz > -18.5,
            "a drop of {dz} units in one frame at t={:.3}",
            w[1].t
        );
        let moved = f64::from(w[1].origin[0] - w[0].origin[0])
            .hypot(f64::from(w[1].origin[1] - w[0].origin[1]));
        assert!(moved < 4.0, "a jump of {moved} units at t={:.3}", w[1].t);
        if w[0].origin[2] > 150.0 && w[1].origin[2] <= 164.0 {
            top.get_or_insert(w[0].t);
        }
        if w[1].origin[2] < 37.5 && w[0].origin[2] >= 37.5 {
            bottom = Some(w[1].t);
        }
    }
    for t in states {
        let o = t.origin.map(f64::from);
        assert_eq!(
            world.hull_contents(1, o),
            Contents::Empty,
            "hull not free at {o:?}"
        );
    }
    let fall = bottom.expect("reached the floor") - top.expect("left the ledge");
    let free_fall = (2.0 * 128.0 / 800.0f64).sqrt();
    assert!(
        (fall - free_fall).abs() < 0.05,
        "fell for {fall:.3} s, free fall {free_fall:.3} s"
    );
    let end = states.last().unwrap().origin;
    assert!(
        (end[1] - 420.0).abs() < 2.0 && (end[2] - 36.0).abs() < 1.5,
        "ended at {end:?}"
    );
}

/// A path straight through a pillar (as a nav mesh's jump or ladder link leaves a
/// stretch the walker cannot follow): the walk is split where the floor is lost and
/// found again, into routes that never jump, and the second part reaches the path's
/// end. The walker used to hold still and then jump 100 units across the pillar.
#[test]
fn a_path_the_walker_cannot_follow_is_split_not_jumped() {
    let bsp = Bsp::open(map("pillars")).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let path = [standing(96.0, 160.0, 0.0), standing(400.0, 160.0, 0.0)];
    let parts = walk_parts(&oracle, "through", &path, 3);
    let names: Vec<&str> = parts.iter().map(|(r, _)| r.name.as_str()).collect();
    assert_eq!(names, ["through", "through#2"]);
    assert!(parts[0].1.cut_short && !parts[1].1.cut_short);
    for (r, _) in &parts {
        for w in r.states.windows(2) {
            let moved = f64::from(w[1].origin[0] - w[0].origin[0])
                .hypot(f64::from(w[1].origin[1] - w[0].origin[1]));
            assert!(
                moved < 4.0,
                "{}: a jump of {moved} units at t={:.3}",
                r.name,
                w[1].t
            );
        }
    }
    let first_end = parts[0].0.states.last().unwrap().origin;
    let second = &parts[1].0.states;
    assert!(
        first_end[0] < 192.0 - 15.0,
        "first part ends at {first_end:?}"
    );
    assert!(
        second[0].origin[0] > 256.0 + 15.0,
        "second part starts at {:?}",
        second[0].origin
    );
    assert!((second.last().unwrap().origin[0] - 400.0).abs() < 2.0);
}

/// On Quake 1 and 2 maps the player's box reaches 24 units below the origin and 32
/// above it (Quake 2 crouched: 4), not GoldSrc's 36 either way: the hull points a
/// replay measures visibility on (pulled 1 unit in) lie in free space just above the
/// floor, and the eye (22 above the origin; Quake 2 crouched 2 below it) is free.
/// With GoldSrc's box the bottom corners were 11 units inside the floor and the
/// chase cam "saw" only part of the hull. Skipped without ../shared/testmaps.
#[test]
fn quake_routes_measure_the_quake_players_box_and_eye() {
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/testmaps");
    if !shared.is_dir() {
        eprintln!("skipped: {} is absent", shared.display());
        return;
    }
    for name in ["quake1/lq_e0m1.bsp", "quake2/lq_e0m1-quake2.bsp"] {
        let bsp = Bsp::open(shared.join(name)).unwrap();
        let oracle = Oracle::new(&bsp, &OracleOptions::default());
        let (routes, _, _) = spawns::routes(&bsp, &oracle, 1, 2);
        assert!(!routes.is_empty(), "{name}: no route");
        let (mut points, mut free, mut eyes_free, mut frames) = (0usize, 0usize, 0usize, 0usize);
        for r in &routes {
            for t in r.resample(1.0 / 10.0) {
                frames += 1;
                let s = t.stance();
                assert_eq!(s.origin_above_ground(), 24.0, "{name}");
                let eye = t.eye();
                let want = if t.crouch { -2.0 } else { 22.0 };
                assert!(
                    (eye[2] - t.origin[2] - want).abs() < 1e-3,
                    "{name}: {eye:?} {t:?}"
                );
                eyes_free += usize::from(oracle.is_free(eye.map(f64::from)));
                for p in &t.hull_points()[..8] {
                    points += 1;
                    free += usize::from(oracle.is_free(*p));
                }
            }
        }
        // Corners may touch a wall the box grazes; the floor is 1 unit below them.
        assert!(
            free * 100 >= points * 97,
            "{name}: {free} of {points} hull points free"
        );
        assert!(
            eyes_free * 100 >= frames * 99,
            "{name}: {eyes_free} of {frames} eyes free"
        );
    }
}

#[test]
fn chase_cam_sits_four_units_off_the_wall_and_the_spring_arm_a_radius_off() {
    // box_room: free space 0..512 × 0..384 × 0..256; the player faces +x near x = 0.
    let bsp = Bsp::open(map("box_room")).unwrap();
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let walls = Walls::of_map(&bsp, &OracleOptions::default());
    let mut chase = ChaseCam::new(&oracle);
    // Far from walls: 112 back along the view, 28 above the origin.
    let f = chase.update(&target([256.0, 192.0, 37.0], 0.0), 1.0 / 60.0);
    assert!(
        (f.eye[0] - 144.0).abs() < 1e-3 && (f.eye[2] - 65.0).abs() < 1e-3,
        "{:?}",
        f.eye
    );
    // At the wall: the trace stops at x = 0 (+ DIST_EPSILON), the camera 4 units out.
    let f = chase.update(&target([64.0, 192.0, 37.0], 0.0), 1.0 / 60.0);
    assert!((f.eye[0] - 4.03125).abs() < 1e-3, "{:?}", f.eye);
    assert_eq!([f.eye[1], f.eye[2]], [192.0, 65.0]);
    assert!(
        walls.distance(f.eye.map(f64::from)) < 6.4,
        "the chase cam clips the near plane there"
    );
    // Facing a corner diagonally: the hit plane's normal is axial, so the camera is
    // pushed 4 units out along it.
    let f = chase.update(&target([40.0, 60.0, 37.0], 45.0), 1.0 / 60.0);
    assert!(
        f.eye[0] >= 4.0 - 1e-3 && f.eye[1] >= 4.0 - 1e-3,
        "{:?}",
        f.eye
    );

    let mut arm = SpringArm::new(&walls);
    let t = target([64.0, 192.0, 37.0], 0.0);
    arm.reset(&t);
    let f = arm.update(&t, 1.0 / 60.0);
    assert!(
        (f.eye[0] - 12.0).abs() < 0.2,
        "sphere radius off the wall: {:?}",
        f.eye
    );
    // Moving away from the wall, the arm returns exponentially, not at once.
    let far = target([256.0, 192.0, 37.0], 0.0);
    let f1 = arm.update(&far, 1.0 / 60.0);
    let len1 = 256.0 - f1.eye[0];
    assert!(
        len1 > 52.0 && len1 < 112.0,
        "retracted arm lags back: {len1}"
    );
    for _ in 0..120 {
        arm.update(&far, 1.0 / 60.0);
    }
    let f2 = arm.update(&far, 1.0 / 60.0);
    assert!((256.0 - f2.eye[0] - 112.0).abs() < 0.5, "{:?}", f2.eye);
}

fn tmpdir(tag: &str) -> toolbox::ScratchDir {
    toolbox::ScratchDir::new(&format!("vdgview-replay-{tag}")).unwrap()
}

#[test]
fn cli_writes_json_csv_plots_and_frames() {
    let dir = tmpdir("cli");
    let vdg = dir.join("two_rooms.vdg");
    let options = bsp2vdg::options::CompileOptions::new(vdg.clone());
    bsp2vdg::pipeline::compile(
        &map("two_rooms"),
        &options,
        &bsp2vdg::log::Log::new(bsp2vdg::log::Verbosity::Quiet, true),
        &bsp2vdg::progress::NoProgress,
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vdgview"))
        .arg("replay")
        .arg(map("two_rooms"))
        .arg(&vdg)
        .args([
            "--camera",
            "vdg,vdg-thesis,chase,springarm",
            "--max-routes",
            "1",
            "--dt",
            "1/30",
            "--json",
        ])
        .arg("--csv")
        .arg(dir.join("csv"))
        .arg("--plots")
        .arg(dir.join("plots"))
        .arg("--frames")
        .arg(dir.join("frames"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for cam in ["vdg", "vdg-thesis", "chase", "springarm"] {
        let c = &v["cameras"][cam];
        for key in [
            "frames",
            "solid_frames",
            "nearplane_frames",
            "visible_fraction",
            "jumps",
            "rms_jerk",
            "cuts_per_min",
            "median_us",
            "target_outside_fraction",
        ] {
            assert!(
                c.get(key).is_some_and(|x| x.is_number()),
                "{cam}.{key} missing: {c}"
            );
        }
        assert!(c["frames"].as_u64().unwrap() > 30);
        if cam != "vdg-thesis" {
            assert_eq!(c["solid_frames"], 0, "{cam} in solid in a plain room");
        }
    }
    assert!(v["target_outside_fraction"].is_number());
    for f in [
        "csv/chase.csv",
        "csv/springarm.csv",
        "csv/outside.csv",
        "plots/speed.png",
        "plots/occlusion.png",
        "plots/summary.png",
        "frames/contact-sheet.png",
    ] {
        let len = std::fs::metadata(dir.join(f)).map(|m| m.len()).unwrap_or(0);
        // The outside list holds only its header when every target lies inside the
        // volume (the reduction keeps standing places inside it).
        let empty_ok = f == "csv/outside.csv" && v["target_outside_fraction"] == 0.0;
        assert!(len > 100 || (empty_ok && len > 0), "{f}: {len} bytes");
    }
    let csv = std::fs::read_to_string(dir.join("csv/chase.csv")).unwrap();
    assert_eq!(
        csv.lines().count() as u64,
        v["cameras"]["chase"]["frames"].as_u64().unwrap() + 1
    );

    // Bad options are one-line errors.
    for args in [
        vec!["--camera", "nope"],
        vec!["--dt", "0"],
        vec!["--routes", "weird"],
        vec!["--routes", "nav:/nonexistent.nav"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_vdgview"))
            .arg("replay")
            .arg(map("two_rooms"))
            .arg(&vdg)
            .args(&args)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(
            err.trim().lines().filter(|l| l.contains("error")).count(),
            1,
            "{args:?}: {err}"
        );
    }
    // view --follow needs the graph; a bad route is a one-line error before any window opens.
    for args in [vec!["--follow", "spawns"], vec!["--follow", "weird"]] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_vdgview"));
        cmd.arg("view").arg(map("two_rooms"));
        if args[1] == "weird" {
            cmd.arg(&vdg);
        }
        let out = cmd.args(&args).env_remove("DISPLAY").output().unwrap();
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--follow") || err.contains("--routes"),
            "{err}"
        );
    }
}
