//! The walker: turns a path on the floor into a player's motion, as a person plays:
//! running at 250–265 units/s with Quake's acceleration and friction, stopping now
//! and then, turning round (180°) to run back a little, crouching for stretches
//! (96 units/s) and wherever the path is too low to stand. Every frame's origin is
//! settled on the floor with the player's clip hull, so the route is physically
//! possible in the map; where the floor drops by more than a step the player falls
//! under the game's gravity instead of landing below in one frame, and a route never
//! jumps: where the walker finds no floor for a stretch it would have to skip, the
//! route ends at the last place it reached. All choices come from a seeded
//! generator: the same path and seed give the same route.

use super::route::{Route, TargetState};
use bsp::oracle::Oracle;
use bsp::player::{above_floor, crouches, hull_fits, settle};
use toolbox::SplitMix64;

/// The walker's fixed step (the route is resampled at the replay's `--dt`).
pub const STEP: f64 = 1.0 / 120.0;
/// Crouched walking speed (the thesis' figure for GoldSrc).
pub const CROUCH_SPEED: f64 = 96.0;
/// `sv_accelerate` × wish speed: units/s² while speeding up.
const ACCEL: f64 = 2500.0;
/// Largest view turn rate of the player in degrees per second.
const TURN_RATE: f64 = 720.0;
/// `sv_gravity` of GoldSrc and Quake (units/s²): how a player falls off a ledge.
const GRAVITY: f64 = 800.0;
/// The highest step a player walks up or down without leaving the ground (`STEPSIZE`).
const STEP_HEIGHT: f64 = 18.0;
/// How fast a player climbs where the path rises by more than a step (GoldSrc's ladder
/// speed, units/s).
const CLIMB_SPEED: f64 = 200.0;
/// The longest move between two frames a route may make after a stretch without a
/// floor: more would be a jump no player makes; the route ends before it instead.
const LONGEST_CATCH_UP: f64 = 16.0;
/// How long the player stands at the end of the path after stopping there (seconds),
/// so the cameras are also judged on how they settle.
const STAND_AT_END: f64 = 0.5;

/// A point of a path on the floor (`floor` is the height of the ground under it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Waypoint {
    pub x: f64,
    pub y: f64,
    pub floor: f64,
    /// The path must be crouched here.
    pub crouch: bool,
}

impl Waypoint {
    /// From a player origin and its crouch state on `oracle`'s map.
    pub fn from_origin(oracle: &Oracle, o: [f64; 3], crouch: bool) -> Waypoint {
        Waypoint {
            x: o[0],
            y: o[1],
            floor: o[2] - above_floor(oracle, crouch),
            crouch,
        }
    }
}

/// What the player is doing besides running along the path.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Act {
    Run,
    Stop {
        until: f64,
    },
    Back {
        until: f64,
    },
    Crouch {
        until: f64,
    },
    /// Letting go of the keys to come to rest at the end of the path, as a player
    /// does: friction brings the run to a stop there (GoldSrc has no instant stop).
    /// A player who was crouching stays down.
    Arrive {
        crouch: bool,
    },
}

/// Shortens a grid path to straight runs: from each point, the farthest later point
/// (up to 24 ahead) that a straight walk reaches on the floor with unchanged crouch.
pub fn string_pull(oracle: &Oracle, path: &[Waypoint]) -> Vec<Waypoint> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < path.len() {
        out.push(path[i]);
        if i + 1 == path.len() {
            break;
        }
        let mut best = i + 1;
        for j in (i + 2..path.len().min(i + 25)).rev() {
            if straight_walkable(oracle, &path[i], &path[j]) {
                best = j;
                break;
            }
        }
        i = best;
    }
    out
}

/// A straight walk from `a` to `b`: settled every 8 units, no step above 18 units,
/// the same crouch state as the ends all along.
fn straight_walkable(oracle: &Oracle, a: &Waypoint, b: &Waypoint) -> bool {
    if a.crouch != b.crouch {
        return false;
    }
    let len = ((b.x - a.x).powi(2) + (b.y - a.y).powi(2)).sqrt();
    let n = (len / 8.0).ceil().max(1.0) as usize;
    let mut floor = a.floor;
    for k in 1..=n {
        let f = k as f64 / n as f64;
        let (x, y) = (a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
        match settle(oracle, x, y, floor, a.crouch) {
            Some((o, c)) if c == a.crouch => {
                let nf = o[2] - above_floor(oracle, c);
                if (nf - floor).abs() > 18.5 {
                    return false;
                }
                floor = nf;
            }
            _ => return false,
        }
    }
    (floor - b.floor).abs() < 4.0
}

/// The polyline with its cumulative lengths, for positions by arc length.
struct Polyline<'a> {
    points: &'a [Waypoint],
    cum: Vec<f64>,
}

impl<'a> Polyline<'a> {
    fn new(points: &'a [Waypoint]) -> Self {
        let mut cum = vec![0.0];
        for w in points.windows(2) {
            let d = ((w[1].x - w[0].x).powi(2) + (w[1].y - w[0].y).powi(2)).sqrt();
            cum.push(cum.last().unwrap() + d);
        }
        Polyline { points, cum }
    }
    fn length(&self) -> f64 {
        *self.cum.last().unwrap()
    }
    /// The path from arc length `s`, starting at the floor position `at` found there.
    fn rest_from(&self, s: f64, at: ([f64; 3], bool), oracle: &Oracle) -> Vec<Waypoint> {
        let mut out = vec![Waypoint::from_origin(oracle, at.0, at.1)];
        out.extend(
            self.points
                .iter()
                .zip(&self.cum)
                .filter(|&(_, &c)| c > s)
                .map(|(w, _)| *w),
        );
        out
    }
    /// The lower of the floors at the two ends of the path's segment at arc length `s`:
    /// where the path itself goes down (off a ledge), no lower.
    fn segment_low(&self, s: f64) -> f64 {
        let i = self.segment(s);
        let j = (i + 1).min(self.points.len() - 1);
        self.points[i].floor.min(self.points[j].floor)
    }
    /// The index of the path's segment at arc length `s`.
    fn segment(&self, s: f64) -> usize {
        let s = s.clamp(0.0, self.length());
        match self.cum.binary_search_by(|c| c.total_cmp(&s)) {
            Ok(i) => i.min(self.points.len().saturating_sub(2)),
            Err(i) => (i.max(1) - 1).min(self.points.len().saturating_sub(2)),
        }
    }
    /// Position, floor, crouch flag and unit xy direction at arc length `s`.
    fn at(&self, s: f64) -> (f64, f64, f64, bool, [f64; 2]) {
        let s = s.clamp(0.0, self.length());
        let i = self.segment(s);
        let (a, b) = (
            self.points[i],
            self.points[(i + 1).min(self.points.len() - 1)],
        );
        let seg = self.cum.get(i + 1).map_or(0.0, |c| c - self.cum[i]);
        let f = if seg > 0.0 {
            ((s - self.cum[i]) / seg).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let dir = if seg > 0.0 {
            [(b.x - a.x) / seg, (b.y - a.y) / seg]
        } else {
            [1.0, 0.0]
        };
        (
            a.x + f * (b.x - a.x),
            a.y + f * (b.y - a.y),
            a.floor + f * (b.floor - a.floor),
            a.crouch || b.crouch,
            dir,
        )
    }
}

/// Statistics of one walk.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WalkStats {
    /// Steps where no floor position was found and the player stayed put.
    pub stuck_steps: usize,
    /// Whether the route ended early: after a stretch without a floor the next floor
    /// position lay farther than a player moves in a frame ([`LONGEST_CATCH_UP`]).
    /// [`walk_parts`] walks the rest as another part.
    pub cut_short: bool,
    /// Falls from a ledge (drops deeper than a step, taken under gravity).
    pub falls: usize,
    /// Steps spent climbing where the path rises by more than a step.
    pub climb_steps: usize,
    pub stops: usize,
    pub turns: usize,
    pub crouch_stretches: usize,
}

/// Walks `path` (at least two points) as a player; `seed` picks the speed and the
/// moments of stops, turns and crouching.
pub fn walk(oracle: &Oracle, name: &str, path: &[Waypoint], seed: u64) -> (Route, WalkStats) {
    let (route, stats, _) = walk_part(oracle, name, path, seed);
    (route, stats)
}

/// [`walk`] over the whole of `path` in parts: where the walker cannot follow the
/// path (no floor for a stretch, e.g. a jump across a gap or a ladder the nav mesh
/// links), the part ends and the next starts where the floor is found again, so no
/// route ever jumps and none loses the rest of its path. Parts after the first are
/// named `NAME#2`, `NAME#3`, ..., each with its own statistics.
pub fn walk_parts(
    oracle: &Oracle,
    name: &str,
    path: &[Waypoint],
    seed: u64,
) -> Vec<(Route, WalkStats)> {
    let mut out = Vec::new();
    let mut path = path.to_vec();
    // Each part starts where the previous one's floor was found again, farther along.
    for part in 1.. {
        let name = if part == 1 {
            name.to_string()
        } else {
            format!("{name}#{part}")
        };
        let (route, stats, rest) = walk_part(oracle, &name, &path, seed ^ (part as u64 - 1));
        if route.states.len() > 1 {
            out.push((route, stats));
        }
        match rest {
            Some(r) if r.len() >= 2 => path = r,
            _ => break,
        }
    }
    out
}

fn walk_part(
    oracle: &Oracle,
    name: &str,
    path: &[Waypoint],
    seed: u64,
) -> (Route, WalkStats, Option<Vec<Waypoint>>) {
    let mut rng = SplitMix64::new(seed);
    let line = Polyline::new(path);
    let run_speed = rng.range(250.0, 265.0);
    let mut stats = WalkStats::default();
    let (mut s, mut v) = (0.0f64, 0.0f64); // arc position and signed speed along the path
    let mut t = 0.0;
    let mut act = Act::Run;
    let mut next_event = rng.range(1.0, 3.0);
    let (x0, y0, f0, c0, d0) = line.at(0.0);
    let mut yaw = d0[1].atan2(d0[0]).to_degrees();
    let mut last =
        settle(oracle, x0, y0, f0, c0).unwrap_or(([x0, y0, f0 + above_floor(oracle, false)], c0));
    let mut states = Vec::new();
    let mut prev_feet = [
        last.0[0],
        last.0[1],
        last.0[2] - above_floor(oracle, last.1),
    ];
    let limit = (line.length() / CROUCH_SPEED * 4.0 + 60.0) / STEP;
    // Steps in a row without a floor, and the downward speed of a fall (0 on the ground).
    let mut stuck = 0usize;
    let mut fall_speed = 0.0f64;
    // Where the walk goes on after a stretch it could not follow (see `walk_parts`).
    let mut rest = None;
    let crouching = crouches(oracle);
    // When the player came to rest at the end of the path.
    let mut arrived: Option<f64> = None;
    for _ in 0..limit as usize {
        let (_, _, floor, must_crouch, dir) = line.at(s);
        // What the player wants now.
        match act {
            Act::Run if t >= next_event && line.length() - s > 200.0 && !must_crouch => {
                act = match rng.below(3) {
                    0 => {
                        stats.stops += 1;
                        Act::Stop {
                            until: t + rng.range(0.5, 1.2),
                        }
                    }
                    1 if s > 150.0 => {
                        stats.turns += 1;
                        Act::Back {
                            until: t + rng.range(0.8, 1.5),
                        }
                    }
                    // Players that do not crouch (Quake 1) stop instead.
                    _ if !crouching => {
                        stats.stops += 1;
                        Act::Stop {
                            until: t + rng.range(1.0, 2.0),
                        }
                    }
                    _ => {
                        stats.crouch_stretches += 1;
                        Act::Crouch {
                            until: t + rng.range(1.0, 2.0),
                        }
                    }
                };
            }
            Act::Stop { until } | Act::Back { until } | Act::Crouch { until } if t >= until => {
                act = Act::Run;
                next_event = t + rng.range(2.0, 5.0);
            }
            _ => {}
        }
        // Let go in time to slide to rest at the end (a step of slack: the step
        // after letting go still moves). A stop or a run back carries on: it ends
        // more than 200 units before the end, where the run resumes first.
        // Friction is at least 400 units/s², so the slide is at most v²/800
        // long: the exact way is only worked out near the end.
        let left = line.length() - s;
        if matches!(act, Act::Run | Act::Crouch { .. })
            && v > 0.0
            && left <= v * v / 800.0 + v * STEP
            && left <= stopping_way(v) + v * STEP
        {
            act = Act::Arrive {
                crouch: matches!(act, Act::Crouch { .. }),
            };
        }
        let crouch =
            must_crouch || matches!(act, Act::Crouch { .. } | Act::Arrive { crouch: true });
        let wish = match act {
            Act::Stop { .. } | Act::Arrive { .. } => 0.0,
            Act::Back { .. } => -run_speed,
            _ if crouch => CROUCH_SPEED,
            _ => run_speed,
        };
        v = approach_speed(v, wish, STEP);
        let s_before = s;
        s = (s + v * STEP).clamp(0.0, line.length());
        // The view turns towards the motion (or the wished motion while stopped).
        let facing = if wish < 0.0 || (wish == 0.0 && v < 0.0) {
            [-dir[0], -dir[1]]
        } else {
            dir
        };
        let want = facing[1].atan2(facing[0]).to_degrees();
        let d = (want - yaw + 540.0).rem_euclid(360.0) - 180.0;
        yaw += d.clamp(-TURN_RATE * STEP, TURN_RATE * STEP);
        yaw = yaw.rem_euclid(360.0);
        // Settle on the floor; a crouch that cannot stand up stays crouched.
        let (nx, ny, nfloor, _, _) = line.at(s);
        let hint = if (nfloor - floor).abs() < 18.0 {
            last.0[2] - above_floor(oracle, last.1)
        } else {
            nfloor
        };
        let low = line.segment_low(s);
        match ground(oracle, nx, ny, [hint, nfloor, low], crouch) {
            Some(p) => {
                let moved = (p.0[0] - last.0[0]).hypot(p.0[1] - last.0[1]);
                if stuck > 0 && moved > LONGEST_CATCH_UP {
                    stats.cut_short = true;
                    rest = Some(line.rest_from(s, p, oracle));
                    break;
                }
                stuck = 0;
                let feet = last.0[2] - above_floor(oracle, last.1);
                let rise = p.0[2] - above_floor(oracle, p.1) - feet;
                if rise > STEP_HEIGHT + 0.5 && fall_speed == 0.0 {
                    // Higher than a step: no walking up it. Running back over a
                    // ledge the player dropped from ends the run back; ahead on the
                    // path (a nav mesh's jump or ladder) the player climbs in place.
                    s = s_before;
                    if v < 0.0 {
                        v = 0.0;
                        act = Act::Run;
                        next_event = t + rng.range(2.0, 5.0);
                    } else if let Some(up) = climb(oracle, last, &mut stats) {
                        last = up;
                    } else {
                        // Something overhead: the player cannot get up here, so the
                        // route ends and the rest of the path is walked from above.
                        stats.cut_short = true;
                        rest = Some(line.rest_from(s_before, p, oracle));
                        break;
                    }
                } else if let Some(next) =
                    fall_towards(oracle, last, p, &mut fall_speed, &mut stats)
                {
                    last = next;
                } else {
                    // No free line down to the floor found: end the route there
                    // rather than land in one frame.
                    stats.cut_short = true;
                    rest = Some(line.rest_from(s, p, oracle));
                    break;
                }
            }
            None => {
                stats.stuck_steps += 1;
                stuck += 1;
            }
        }
        let o = last.0;
        // Velocity of the feet: ducking moves GoldSrc's hull centre by 18 units at
        // once (PM_Duck), which is not motion; Quake 2 and 3 keep the origin where it
        // is (the feet must be taken with the game's heights, or a duck is a spike).
        let feet = [o[0], o[1], o[2] - above_floor(oracle, last.1)];
        let vel = [0, 1, 2].map(|k| ((feet[k] - prev_feet[k]) / STEP) as f32);
        prev_feet = feet;
        states.push(TargetState {
            t,
            origin: o.map(|c| c as f32),
            angles: [0.0, yaw as f32, 0.0],
            velocity: vel,
            crouch: last.1,
            game: oracle.game(),
        });
        t += STEP;
        if s >= line.length() && v.abs() >= 1.0 && !matches!(act, Act::Arrive { .. }) {
            // Reached at speed all the same (a path shorter than the way to stop):
            // the end holds the player, who slows down standing there.
            act = Act::Arrive { crouch };
        }
        if matches!(act, Act::Arrive { .. }) && v.abs() < 1.0 {
            arrived.get_or_insert(t);
        }
        if arrived.is_some_and(|at| t >= at + STAND_AT_END) {
            break;
        }
    }
    if let Some(first) = states.first_mut() {
        first.velocity = [0.0; 3];
    }
    (
        Route {
            name: name.to_string(),
            states,
        },
        stats,
        rest,
    )
}

/// The floor position at `(x, y)`, looked for near each of `heights` in turn: the
/// walker's own height, the path's floor there, and the lower end of the path's
/// segment (where the path itself goes down a ledge, the floor a player walking off
/// it lands on). Never deeper: a floor far below the path (a pool beside it, a void
/// under the map) is not where the path goes.
fn ground(
    oracle: &Oracle,
    x: f64,
    y: f64,
    heights: [f64; 3],
    crouch: bool,
) -> Option<([f64; 3], bool)> {
    heights
        .iter()
        .find_map(|&h| settle(oracle, x, y, h, crouch))
}

/// The player's next position when the floor under it is at `landing`: on the floor
/// when it is within a step (or the fall reaches it this frame), else falling towards
/// it under [`GRAVITY`] (the fall's downward speed in `fall_speed`), over the landing
/// or, where the hull does not fit there, straight down where it is. `None` where it
/// fits at neither: no fall that does not pass through a wall.
fn fall_towards(
    oracle: &Oracle,
    last: ([f64; 3], bool),
    landing: ([f64; 3], bool),
    fall_speed: &mut f64,
    stats: &mut WalkStats,
) -> Option<([f64; 3], bool)> {
    let feet = last.0[2] - above_floor(oracle, last.1);
    let floor = landing.0[2] - above_floor(oracle, landing.1);
    if *fall_speed == 0.0 && floor >= feet - STEP_HEIGHT - 0.5 {
        return Some(landing);
    }
    let speed = *fall_speed + GRAVITY * STEP;
    let z = feet - speed * STEP;
    if z <= floor {
        *fall_speed = 0.0;
        return Some(landing);
    }
    let hull = if landing.1 { 3 } else { 1 };
    let over = |p: [f64; 3]| [p[0], p[1], z + above_floor(oracle, landing.1)];
    let origin = [over(landing.0), over(last.0)]
        .into_iter()
        .find(|&o| hull_fits(oracle, hull, o))?;
    if *fall_speed == 0.0 {
        stats.falls += 1;
    }
    *fall_speed = speed;
    Some((origin, landing.1))
}

/// The player's next position where the floor ahead is higher than a step: straight
/// up at [`CLIMB_SPEED`] where it stands (as on a ladder, or jumping up onto a box),
/// or `None` where the hull does not fit there (the player cannot get up).
fn climb(
    oracle: &Oracle,
    last: ([f64; 3], bool),
    stats: &mut WalkStats,
) -> Option<([f64; 3], bool)> {
    let up = [last.0[0], last.0[1], last.0[2] + CLIMB_SPEED * STEP];
    let hull = if last.1 { 3 } else { 1 };
    hull_fits(oracle, hull, up).then(|| {
        stats.climb_steps += 1;
        (up, last.1)
    })
}

/// How far a player running at `v` (≥ 0) along the path slides after letting go of
/// the keys, under the walker's friction at its step ([`approach_speed`] with no wish).
fn stopping_way(v: f64) -> f64 {
    let (mut v, mut way) = (v, 0.0);
    while v > 0.0 {
        v = approach_speed(v, 0.0, STEP);
        way += v * STEP;
    }
    way
}

/// Quake-like speed change over `dt`: accelerate towards the wished speed, friction
/// (4 × max(|v|, 100) units/s²) when the wish is to stop or turn round.
fn approach_speed(v: f64, wish: f64, dt: f64) -> f64 {
    let friction = 4.0 * v.abs().max(100.0) * dt;
    if wish == 0.0 {
        return if v.abs() <= friction {
            0.0
        } else {
            v - v.signum() * friction
        };
    }
    let cap = |nv: f64| {
        if wish > 0.0 {
            nv.min(wish)
        } else {
            nv.max(wish)
        }
    };
    if v * wish < 0.0 {
        // Turning round: friction and acceleration the other way.
        return cap(v + wish.signum() * (friction + ACCEL * dt));
    }
    if v.abs() < wish.abs() {
        cap(v + wish.signum() * ACCEL * dt)
    } else {
        // Slowing to a lower wish (crouching).
        wish.signum() * (v.abs() - friction).max(wish.abs())
    }
}

#[cfg(test)]
mod tests {
    use super::approach_speed;

    #[test]
    fn speed_rises_stops_and_reverses() {
        let mut v = 0.0;
        for _ in 0..60 {
            v = approach_speed(v, 250.0, 1.0 / 120.0);
        }
        assert_eq!(v, 250.0);
        let mut n = 0;
        while v > 0.0 {
            v = approach_speed(v, 0.0, 1.0 / 120.0);
            n += 1;
        }
        assert!(n > 10 && n < 200, "{n}");
        v = 250.0;
        for _ in 0..240 {
            v = approach_speed(v, -250.0, 1.0 / 120.0);
        }
        assert!((v + 250.0).abs() < 1e-9, "{v}");
    }
}
