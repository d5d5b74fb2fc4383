//! The camera (vdgformat::camera) on compiled generated maps, judged by the
//! maps' exact geometry (crate `mapgen`), never by the graph: a player walks
//! a scripted route on the floor (origin 37 above it) through an L corridor,
//! a door between two rooms and a pillar hall; the camera must stay in free
//! space at least the near-plane margin from every wall, keep the player in
//! view (exact line of sight) nearly always, declare a cut when the player
//! teleports, and give bit-identical poses run after run.

mod common;

use std::path::PathBuf;

use mapgen::world::World;
use vdgformat::VdgFile;
use vdgformat::camera::{Camera, CameraParams, Pose, Target};

/// Compiles a generated map at the default options into a fresh folder and
/// returns the graph's bytes with the map's exact description.
fn compiled(name: &str) -> (VdgFile, World) {
    compiled_with(name, &[])
}

/// [`compiled`] with extra options.
fn compiled_with(name: &str, args: &[&str]) -> (VdgFile, World) {
    let maps = common::repo_root().join("testdata/maps");
    let dir = toolbox::ScratchDir::new(&format!("bsp2vdg-camera-{name}")).unwrap();
    let map: PathBuf = dir.join(format!("{name}.bsp"));
    std::fs::copy(maps.join(format!("{name}.bsp")), &map).unwrap();
    let file = common::compile(&map, &dir.join(format!("{name}.vdg")), args);
    let json = std::fs::read_to_string(maps.join(format!("{name}.json"))).unwrap();
    (file, World::from_manifest_json(&json).unwrap())
}

/// A player walking through `waypoints` (x, y; origin at z = 37) at 250 u/s,
/// pausing half a second at each inner waypoint and turning round there for
/// a moment, as players look back.
struct Walk {
    points: Vec<[f64; 2]>,
}

impl Walk {
    const SPEED: f64 = 250.0;
    const PAUSE: f64 = 0.5;

    fn duration(&self) -> f64 {
        let legs: f64 = self.points.windows(2).map(|w| dist(w[0], w[1])).sum();
        legs / Self::SPEED + Self::PAUSE * (self.points.len() - 2) as f64
    }

    fn at(&self, t: f64) -> Target {
        let mut left = t;
        for (i, w) in self.points.windows(2).enumerate() {
            let leg = dist(w[0], w[1]) / Self::SPEED;
            let dir = [
                (w[1][0] - w[0][0]) / dist(w[0], w[1]),
                (w[1][1] - w[0][1]) / dist(w[0], w[1]),
            ];
            if left <= leg {
                let p = [
                    w[0][0] + dir[0] * left * Self::SPEED,
                    w[0][1] + dir[1] * left * Self::SPEED,
                ];
                let v = [dir[0] * Self::SPEED, dir[1] * Self::SPEED, 0.0];
                return target(p, [dir[0], dir[1]], v);
            }
            left -= leg;
            let last = i + 2 == self.points.len();
            if !last && left <= Self::PAUSE {
                // Standing; looking back during the second half of the pause.
                let look = if left > Self::PAUSE / 2.0 {
                    [-dir[0], -dir[1]]
                } else {
                    dir
                };
                return target(w[1], look, [0.0; 3]);
            }
            if !last {
                left -= Self::PAUSE;
            }
        }
        let n = self.points.len();
        let (a, b) = (self.points[n - 2], self.points[n - 1]);
        target(
            b,
            [(b[0] - a[0]) / dist(a, b), (b[1] - a[1]) / dist(a, b)],
            [0.0; 3],
        )
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

fn target(p: [f64; 2], heading: [f64; 2], v: [f64; 3]) -> Target {
    Target::new(
        [p[0] as f32, p[1] as f32, 37.0],
        [heading[0] as f32, heading[1] as f32, 0.0],
        v.map(|c| c as f32),
    )
}

fn f64p(p: [f32; 3]) -> [f64; 3] {
    p.map(f64::from)
}

struct Run {
    poses: Vec<Pose>,
    targets: Vec<Target>,
    /// Per pose, whether the volume's boundary changed its step.
    blocked: Vec<bool>,
}

fn run(g: &vdgformat::Vdg<'_>, walk: &Walk, params: CameraParams, dt: f32) -> Run {
    let mut cam = Camera::new(params).unwrap();
    let frames = (walk.duration() / f64::from(dt)).ceil() as usize;
    cam.reset(g, &walk.at(0.0));
    let mut run = Run {
        poses: Vec::with_capacity(frames),
        targets: Vec::with_capacity(frames),
        blocked: Vec::with_capacity(frames),
    };
    for i in 1..=frames {
        let t = walk.at(i as f64 * f64::from(dt));
        run.poses.push(cam.update(g, &t, dt));
        run.targets.push(t);
        run.blocked.push(cam.debug().blocked);
    }
    run
}

/// Free space, margin and exact visibility along a route at 60 and 30 Hz,
/// on the default graph and on the graph reduced without the floor (`-rv 0`):
/// the generated maps are small, so the floor keeps 1000 vertices of them,
/// and the coarse faces a real map's reduction leaves in its corridors are
/// what `-rv 0` gives here (35 vertices in the L corridor).
fn check_route(name: &str, walk: Walk, min_visible: f64) {
    for args in [&[][..], &["-rv", "0"][..]] {
        let (file, world) = compiled_with(name, args);
        let name = format!("{name} {}", args.join(" "));
        check_route_on(&file, &world, name.trim_end(), &walk, min_visible);
    }
}

fn check_route_on(file: &VdgFile, world: &World, name: &str, walk: &Walk, min_visible: f64) {
    let g = file.graph();
    for dt in [1.0 / 60.0, 1.0 / 30.0f32] {
        let r = run(&g, walk, CameraParams::default(), dt);
        let (mut seen, mut hidden_run, mut longest) = (0usize, 0usize, 0usize);
        for (i, (p, t)) in r.poses.iter().zip(&r.targets).enumerate() {
            let eye = f64p(p.eye);
            assert!(
                world.is_free(eye),
                "{name} dt {dt} frame {i}: eye {eye:?} in solid"
            );
            let c = world.clearance(eye);
            assert!(
                c >= 6.3,
                "{name} dt {dt} frame {i}: eye {eye:?} only {c:.2} from a wall (near plane 6.4)"
            );
            assert!(
                g.contains(p.eye),
                "{name} dt {dt} frame {i}: eye left Volume(VDG)"
            );
            assert!(!p.cut, "{name} dt {dt} frame {i}: cut without a teleport");
            if world.segment_free(eye, f64p(t.position)) {
                seen += 1;
                hidden_run = 0;
            } else {
                hidden_run += 1;
                longest = longest.max(hidden_run);
            }
        }
        let fraction = seen as f64 / r.poses.len() as f64;
        eprintln!(
            "{name} dt {dt:.4}: {} frames, target visible {:.1} %, longest occlusion {:.2} s",
            r.poses.len(),
            100.0 * fraction,
            longest as f32 * dt
        );
        assert!(
            fraction >= min_visible,
            "{name} dt {dt}: target visible in only {:.1} % of frames",
            100.0 * fraction
        );
        assert!(
            longest as f32 * dt <= 1.0,
            "{name} dt {dt}: target hidden {:.2} s in a row",
            longest as f32 * dt
        );
    }
}

/// The `-rv 0` graph here is what made the camera's `inertia_step`: without
/// it the camera, slowed to the clearance cap as the player stops at the
/// corner, drifted away along the first leg and lost him.
#[test]
fn follows_round_the_corner_of_an_l_corridor() {
    let walk = Walk {
        points: vec![[576.0, 64.0], [64.0, 64.0], [64.0, 576.0]],
    };
    check_route("l_corridor", walk, 0.97);
}

#[test]
fn follows_through_a_door_between_two_rooms() {
    let walk = Walk {
        points: vec![
            [96.0, 192.0],
            [300.0, 192.0],
            [720.0, 192.0],
            [900.0, 300.0],
        ],
    };
    check_route("two_rooms", walk, 0.97);
}

#[test]
fn follows_between_the_pillars_of_a_hall() {
    let walk = Walk {
        points: vec![
            [96.0, 96.0],
            [928.0, 96.0],
            [928.0, 384.0],
            [96.0, 384.0],
            [96.0, 672.0],
            [928.0, 672.0],
        ],
    };
    check_route("pillar_hall", walk, 0.97);
}

#[test]
fn a_teleport_is_a_declared_cut_and_poses_repeat_bit_for_bit() {
    let (file, world) = compiled("two_rooms");
    let g = file.graph();
    let walk = Walk {
        points: vec![[96.0, 192.0], [300.0, 192.0]],
    };
    let a = run(&g, &walk, CameraParams::default(), 1.0 / 60.0);
    let b = run(&g, &walk, CameraParams::default(), 1.0 / 60.0);
    assert_eq!(a.poses, b.poses);
    let bits = |r: &Run| -> Vec<u32> {
        r.poses
            .iter()
            .flat_map(|p| p.eye.into_iter().chain([p.yaw, p.pitch]).map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));

    let mut cam = Camera::new(CameraParams::default()).unwrap();
    cam.reset(&g, &walk.at(0.0));
    for i in 1..60 {
        assert!(
            !cam.update(&g, &walk.at(f64::from(i) / 60.0), 1.0 / 60.0)
                .cut
        );
    }
    // Respawn in the other room.
    let there = target([832.0, 192.0], [-1.0, 0.0], [0.0; 3]);
    let p = cam.update(&g, &there, 1.0 / 60.0);
    assert!(p.cut, "the teleport was not declared");
    let eye = f64p(p.eye);
    assert!(world.is_free(eye) && world.segment_free(eye, f64p(there.position)));
    assert!(
        eye[0] > 640.0,
        "the camera stayed in the first room: {eye:?}"
    );
}

/// The eye's jerk per frame (third differences of its positions, units/s³).
fn jerks(r: &Run, dt: f32) -> Vec<f64> {
    let dt = f64::from(dt);
    let eyes: Vec<[f64; 3]> = r.poses.iter().map(|p| f64p(p.eye)).collect();
    eyes.windows(4)
        .map(|w| {
            let d: Vec<f64> = (0..3)
                .map(|k| w[3][k] - 3.0 * w[2][k] + 3.0 * w[1][k] - w[0][k])
                .collect();
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / (dt * dt * dt)
        })
        .collect()
}

/// With `max_jerk` the acceleration changes by at most that much per
/// second wherever the move is not stopped by the boundary: in the pillar
/// hall (open floor, the camera rarely touches the volume's boundary on
/// this route) the eye's jerk stays under the bound in every frame whose
/// moves the boundary left alone, where the default camera's exceeds it
/// in a fifth of them; the camera still never leaves free space or enters
/// the near-plane margin.
#[test]
fn max_jerk_bounds_the_eyes_jerk() {
    let (file, world) = compiled("pillar_hall");
    let g = file.graph();
    let walk = Walk {
        points: vec![[96.0, 96.0], [928.0, 96.0], [928.0, 384.0], [96.0, 384.0]],
    };
    const J: f32 = 10_000.0;
    for dt in [1.0 / 60.0, 1.0 / 30.0f32] {
        let bounded = CameraParams {
            max_jerk: J,
            accel_tau: 0.0,
            ..CameraParams::default()
        };
        // The frames (windows of four poses) whose moves the boundary left alone.
        let over = |r: &Run| {
            let j: Vec<f64> = jerks(r, dt)
                .into_iter()
                .enumerate()
                .filter(|&(i, _)| !r.blocked[i..i + 4].iter().any(|&b| b))
                .map(|(_, x)| x)
                .collect();
            let n = j.iter().filter(|&&x| x > f64::from(J) * 1.01).count();
            (
                n as f64 / j.len() as f64,
                j.iter().cloned().fold(0.0, f64::max),
            )
        };
        let r = run(&g, &walk, bounded, dt);
        // The bound must be tested on nearly the whole route.
        let blocked = r.blocked.iter().filter(|&&b| b).count();
        assert!(
            blocked * 20 < r.blocked.len(),
            "dt {dt}: the boundary changed {blocked} of {} steps",
            r.blocked.len()
        );
        for (i, p) in r.poses.iter().enumerate() {
            let eye = f64p(p.eye);
            assert!(
                world.is_free(eye),
                "dt {dt} frame {i}: eye {eye:?} in solid"
            );
            assert!(
                world.clearance(eye) >= 6.3,
                "dt {dt} frame {i}: eye {eye:?} inside the near-plane margin"
            );
        }
        let (bounded_over, bounded_max) = over(&r);
        let (free_over, free_max) = over(&run(&g, &walk, CameraParams::default(), dt));
        eprintln!(
            "dt {dt:.4}: frames over {J} u/s³: bounded {:.1} % (max {bounded_max:.0}), default {:.1} % (max {free_max:.0})",
            100.0 * bounded_over,
            100.0 * free_over
        );
        assert!(
            bounded_max <= f64::from(J) * 1.01,
            "dt {dt}: jerk {bounded_max:.0} u/s³ over the bound {J} ({:.1} % of frames)",
            100.0 * bounded_over
        );
        assert!(
            free_over > bounded_over,
            "dt {dt}: the default camera is no jerkier than the bounded one"
        );
    }
}
