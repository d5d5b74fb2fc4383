//! Motion: the step rule's speed, the smoothed direction of travel, the
//! move across face volumes (sliding along the boundary where it is
//! blocked) and the smoothed look-at point.

use super::sight::{POSE_HINT, STEP_EVALS};
use super::{Camera, Pose, Scene, Slot, State};
use crate::geom::V3;
use crate::query::{Advance, CoverBudget, FaceCache};
use crate::read::Vdg;

/// Clearance the step may lose when the camera starts inside the
/// near-plane margin (more than the trace's own margin, so it can always
/// move, towards more room).
pub(super) const MARGIN_SLACK: f64 = 0.02;

/// The distance field is steered towards the camera: the questions of one
/// update come from within about this radius of it (its reachable vertices
/// and clamped candidates).
const FIELD_RADIUS: f32 = 48.0;

/// How close (units) the camera's clamps and steps go to the boundary of
/// the volume they are certified in.
pub(super) const CLAMP_TOL: f64 = 0.125;

impl Camera {
    /// How long the camera takes to answer a new speed limit: the lag of its
    /// velocity (`direction_tau`) and of its acceleration (`accel_tau`). The
    /// limits that bring it to its goal and to the distance it keeps from
    /// the target allow for it (see [`stopping_speed`]): with the bare
    /// `√(2 · max_decel · way)` the camera ran at its goal at speed, its
    /// velocity reached the limit a reaction time late, and it braked at up
    /// to three times `max_decel` in the last frames (a playtest's and the
    /// spawn routes' largest jerk at 1/30 s).
    fn reaction_time(&self) -> f64 {
        f64::from(self.params.direction_tau) + f64::from(self.params.accel_tau)
    }

    /// The margin the camera keeps from the volume's boundary at `pos`:
    /// the near-plane margin, or a little less than the current clearance
    /// when the camera is already closer (so it can still move out).
    pub(super) fn margin_at(&self, clearance: f64) -> f32 {
        let m = f64::from(self.params.near_margin);
        if clearance >= m + MARGIN_SLACK {
            m as f32
        } else {
            (clearance - MARGIN_SLACK).clamp(0.0, m) as f32
        }
    }

    /// One regular frame: candidates, choice, step, face update.
    pub(super) fn step(&mut self, g: &Vdg<'_>, scene: &Scene, mut s: State, heading: V3) -> Pose {
        let target_moved = scene.t - s.target_prev;
        remember_target(&mut s, scene, heading);
        if scene.dt <= 0.0 {
            // Re-aim only; the point the camera heads for moves on with
            // the target.
            s.goal = s.goal + target_moved;
            self.state = Some(s);
            let visible = self.sees_finally(g, s.face, s.pos, scene);
            if let Some(st) = self.state.as_mut() {
                st.visible = visible;
            }
            return self.finish(s.pos, s.face, s.look, false, visible, scene.inside);
        }
        if self.params.distance_field {
            self.steer_field(g, scene, &s);
        }
        let here_clear = self.faces.fc(g, s.face, s.pos);
        let margin = self.margin_at(here_clear);
        // The current position's visibility: last update's answer (the
        // target moved a few units since) in our variant, a trace in the
        // thesis'.
        let known = (self.params.max_substeps > 0).then_some(s.visible);
        let mut current = self.costs_at(
            g,
            scene,
            &s,
            s.pos,
            s.face,
            here_clear,
            known,
            Some(Slot::Line(POSE_HINT)),
        );
        // The place the camera stands is rated as its candidates are: one
        // that is about to lose the target costs as if hidden, so the step
        // rule (whose speed grows with this cost) hurries away from it.
        if current.vis == 0.0
            && let Some(ahead) = &scene.ahead
            && !self.sees_ahead(g, s.face, s.pos, ahead, POSE_HINT)
        {
            self.hidden_ahead(g, scene, s.face, s.pos, ahead, &mut current);
        }
        let (best_pos, best_cost) = self.choose(g, scene, &s, margin);
        s.goal = self.goal_after(scene.dt, s.goal, target_moved, best_pos, s.visible);
        let to_goal = s.goal - s.pos;
        let dist_goal = to_goal.norm();
        // Seen at the last update, and now where the camera stands and where
        // the target is heading.
        let seeing = s.visible && current.vis == 0.0;
        let top = self.top_speed(scene, seeing);
        let v = self.speed(scene, &s, f64::from(current.total), dist_goal, top);
        let dir = if dist_goal > 1e-9 {
            to_goal * (1.0 / dist_goal)
        } else {
            V3(0.0, 0.0, 0.0)
        };
        let (new_pos, new_face) = if self.params.max_substeps == 0 {
            // The thesis: one step inside Volume(f_i), then the best of f_i
            // and its neighbours.
            let p = s.pos + dir * (v * scene.dt).min(dist_goal);
            let p = V3::from_f32(p.to_f32());
            let (f, _) = g.climb(s.face, p, 1);
            s.vel = dir * v;
            (p, f)
        } else {
            self.move_smoothly(g, scene, &mut s, dir, dist_goal, v, top, margin, here_clear)
        };
        let moved = (new_pos - s.pos).norm();
        s.speed = v;
        // f_clear's Velocity(c): the thesis uses the commanded speed; ours
        // the speed actually moved, so a blocked camera whose command winds
        // up to top speed does not let f_clear outweigh everything.
        s.clear_speed = if self.params.max_substeps == 0 {
            v
        } else {
            moved / scene.dt
        };
        s.pos = new_pos;
        s.face = new_face;
        let visible = self.sees_finally(g, s.face, s.pos, scene);
        s.hidden = if visible { 0.0 } else { s.hidden + scene.dt };
        s.visible = visible;
        s.unreachable = !visible && self.unreachable(g, s.face, s.pos);
        s.look = self.look_at(scene, s.look);
        self.state = Some(s);
        self.debug.current = current;
        self.debug.field_settled = self.field.settled();
        self.debug.speed = v as f32;
        self.debug.moved = moved as f32;
        let _ = best_cost;
        self.finish(s.pos, s.face, s.look, false, visible, scene.inside)
    }

    /// Steers the update's distance field towards the camera: every
    /// VDistance of this update is asked near it.
    fn steer_field(&mut self, g: &Vdg<'_>, scene: &Scene, s: &State) {
        let near = s.pos.to_f32();
        let radius = FIELD_RADIUS;
        // Ways the camera cannot pass are no ways to the target.
        self.field
            .set_min_clearance(self.params.field_min_clearance);
        self.field
            .reset_towards(g, scene.face, scene.t.to_f32(), near, radius);
    }

    /// The point the camera heads for after an update of `dt` seconds:
    /// with `goal_tau`, while the camera `seeing` the target at its last
    /// update, last update's point `goal` moved on by the target's own
    /// motion (`target_moved`) and then drawn towards the best candidate
    /// with that lag; else the best candidate itself (see `goal_tau` for
    /// why not while hidden).
    pub(super) fn goal_after(
        &self,
        dt: f64,
        goal: V3,
        target_moved: V3,
        best_pos: V3,
        seeing: bool,
    ) -> V3 {
        if self.params.goal_tau > 0.0 && seeing {
            let carried = goal + target_moved;
            carried + (best_pos - carried) * lag_fraction(dt, self.params.goal_tau)
        } else {
            best_pos
        }
    }

    /// The step rule (thesis 5.3): the speed follows the command with
    /// `frac = 1 − e^(−Δt/τ)`, with `max_decel` at the speed from which the
    /// camera can stop at the point it heads for, `dist_goal` away, and
    /// capped at `top` (see [`Self::top_speed`]). `f_cur` is f_total where
    /// the camera is.
    fn speed(&self, scene: &Scene, s: &State, f_cur: f64, dist_goal: f64, top: f64) -> f64 {
        let frac = lag_fraction(scene.dt, self.params.speed_tau);
        // The thesis' command (1 + V)·√f_total has the fixed point
        // √f/(1 − √f) below f = 1: a resting camera hardly moves until the
        // costs pass 1. Ours commands at least the target's own speed.
        let command = ((1.0 + s.speed) * f_cur.sqrt())
            .max(scene.target_speed * f64::from(self.params.target_speed_floor));
        let v = ((1.0 - frac) * s.speed + frac * command).min(f64::from(self.params.max_speed));
        // Arrive rather than overshoot: no faster than the camera can brake
        // to a stop at the best candidate (plus the target's own speed, which
        // moves that point on). Without it the command winds up to top speed
        // (f_clear grows with the speed it rates) and a camera behind a
        // player standing still hunted back and forth across the ideal.
        let v = if self.params.max_decel > 0.0 {
            let a = f64::from(self.params.max_decel);
            let arrive = stopping_speed(a, dist_goal, self.reaction_time()) + scene.brake_speed;
            v.min(arrive.max(no_harder_than(a, s.speed, scene.dt)))
        } else {
            v
        };
        v.min(top)
    }

    /// The fastest the camera may move in this update: `max_speed`, and
    /// while it is `seeing` the target `seen_speed_factor` times his recent
    /// top speed (at least `seen_speed_floor`). Both the step rule's speed
    /// and the velocity the acceleration's lag lets through keep to it: the
    /// lag overshoots a step in its command a little, and a camera held to
    /// twice a crouching player's 96 units/s moved at 192.2.
    fn top_speed(&self, scene: &Scene, seeing: bool) -> f64 {
        let top = f64::from(self.params.max_speed);
        if seeing && self.params.seen_speed_factor > 0.0 {
            let allowed = scene
                .recent_target_speed
                .max(f64::from(self.params.seen_speed_floor));
            top.min(
                f64::from(self.params.seen_speed_factor) * allowed * (1.0 - SEEN_SPEED_ROUNDING),
            )
        } else {
            top
        }
    }

    /// The look-at point after this update: `look` drawn towards the
    /// target with the lag `look_tau`, or the target itself.
    fn look_at(&self, scene: &Scene, look: V3) -> V3 {
        if self.params.look_tau > 0.0 {
            let k = lag_fraction(scene.dt, self.params.look_tau);
            look + (scene.t - look) * k
        } else {
            scene.t
        }
    }

    /// Our step: the direction of motion follows `dir`, towards the point
    /// the camera heads for (`dist_goal` away), with a lag (frame-rate
    /// independent), the move may cross several faces, and a move the
    /// smoothed direction cannot make falls back to the straight line
    /// towards that point. The line is free by construction where the
    /// point is the best candidate (clamped from the camera's place): with
    /// `goal_tau` 0 or a hidden target. The smoothed point need not be
    /// reachable in a straight line; the move is clamped into the volume
    /// either way. (Turning towards the best candidate instead was measured
    /// and not kept: docs/measurements/2026-12-07f-camera-goal.md.)
    #[allow(clippy::too_many_arguments)]
    fn move_smoothly(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &mut State,
        dir: V3,
        dist_goal: f64,
        v: f64,
        top: f64,
        margin: f32,
        here_clear: f64,
    ) -> (V3, u32) {
        let hops = self.params.max_substeps;
        let desired = dir * v;
        let vel = if self.params.direction_tau > 0.0 {
            let k = lag_fraction(scene.dt, self.params.direction_tau);
            s.vel + (desired - s.vel) * k
        } else {
            desired
        };
        let accel_lag = self.params.accel_tau > 0.0;
        let vel = self.brake_at_walls(g, s, vel, here_clear, margin);
        let room = (here_clear - f64::from(margin)).max(0.0);
        let vel = self.brake_before_the_wall_ahead(g, s.pos, s.face, vel, scene.dt, margin, room);
        let vel = self.brake_before_the_target(scene, s, vel);
        let mut step = vel * scene.dt;
        let len = step.norm();
        let mut allowed = (v * scene.dt).min(dist_goal);
        if self.params.max_decel > 0.0 {
            // The best candidate may be reached (or may jump to the
            // camera's own position, another criterion winning) while the
            // camera is fast: it then brakes at `max_decel` and passes the
            // point a little instead of stopping dead in one frame.
            let coast = (s.vel.norm() - f64::from(self.params.max_decel) * scene.dt).max(0.0);
            allowed = allowed.max((coast * scene.dt).min(len));
        }
        if len > allowed && len > 0.0 {
            step = step * (allowed / len);
        }
        let mut len = len;
        if accel_lag || self.params.max_jerk > 0.0 {
            // The capped step is the velocity the camera is commanded; it
            // gets there through a continuous acceleration (and may then
            // pass the best candidate a little more).
            let commanded = step * (1.0 / scene.dt);
            let vel = if accel_lag {
                self.lag_acceleration(scene, s, commanded, top)
            } else {
                self.limit_jerk(scene, s, commanded)
            };
            step = vel * scene.dt;
            len = step.norm();
        }
        let from = s.pos.to_f32();
        let budget = CoverBudget {
            hops,
            leaf_searches: u32::MAX,
        };
        let a = g.advance_tol(
            s.face,
            from,
            (s.pos + step).to_f32(),
            margin,
            &mut budget.clone(),
            CLAMP_TOL,
            None,
            Some(&self.faces),
            STEP_EVALS,
        );
        let (mut p, mut f) = (V3::from_f32(a.point), a.face);
        self.debug.blocked = !a.reached;
        if !a.reached && self.params.slide {
            (p, f) = slide(g, &self.faces, p, f, s.pos + step, margin, hops);
        }
        if !a.reached {
            // The straight line at no more than the speed the camera had
            // plus what `max_decel` allows in a frame: at the full command
            // a camera that had slowed along a wall leapt off it (a speed
            // jump of a few hundred units per second in one frame).
            let straight = if self.params.max_jerk > 0.0 || accel_lag {
                // No faster than the step the jerk bound or the
                // acceleration's lag let through.
                allowed.min(len)
            } else if self.params.max_decel > 0.0 {
                allowed.min((s.vel.norm() + f64::from(self.params.max_decel) * scene.dt) * scene.dt)
            } else {
                allowed
            };
            // A slide that carried the camera at least half its step keeps
            // it: turning onto the straight line there reflected the
            // camera off the wall (a kink every time it grazed one).
            let slid = (p - s.pos).norm();
            let left = straight - slid;
            if left > 1e-6 && !(self.params.slide && slid >= 0.5 * len.min(straight)) {
                (p, f) = self.turn_towards_the_line(g, s, (p, f), step, dir, straight, margin);
            }
        }
        // GetClosestFace: the face of largest clearance near the new point.
        let (mut f, new_clear) = g.climb_cached(&self.faces, f, p, 4);
        // Inside the near-plane margin the camera may only gain room: the
        // relaxed margin lets a segment dip a little, never the end point
        // (or it would sink a little more every frame).
        let m = f64::from(self.params.near_margin);
        if new_clear < m && new_clear < here_clear {
            (p, f) = self.keep_room(g, s, p, f, new_clear, here_clear.min(m), margin, hops);
            self.debug.blocked = true;
        }
        s.vel = (p - s.pos) * (1.0 / scene.dt);
        (p, f)
    }

    /// A step that ends with less room than `need` (the camera is inside
    /// the near-plane margin and may only gain room): its end point pushed
    /// back out along the boundary's inward normal until it has `need`, if
    /// the straight way there is free; else the camera stays where it was.
    /// A camera gliding along a wall at the margin ends about half its steps
    /// a hair below its start (the step's tolerance); stopping it dead there
    /// threw its speed from a few hundred units per second to zero in a
    /// frame.
    #[allow(clippy::too_many_arguments)]
    fn keep_room(
        &self,
        g: &Vdg<'_>,
        s: &State,
        p: V3,
        f: u32,
        clear: f64,
        need: f64,
        margin: f32,
        hops: u32,
    ) -> (V3, u32) {
        let stay = (s.pos, s.face);
        let (mut q, mut f, mut c) = (p, f, clear);
        for _ in 0..KEEP_ROOM_TRIES {
            let Some(n) = inward_normal(g, &self.faces, f, q) else {
                return stay;
            };
            q = V3::from_f32((q + n * (need - c + KEEP_ROOM_EXTRA)).to_f32());
            (f, c) = g.climb_cached(&self.faces, f, q, 4);
            if c >= need {
                break;
            }
        }
        if c < need {
            return stay;
        }
        let a = advance_locally(g, &self.faces, s.face, s.pos, q, margin, hops);
        if a.reached { (q, f) } else { stay }
    }
}

/// The directions between a blocked step's and the straight line's that
/// [`Camera::turn_towards_the_line`] tries, as the straight line's share.
const TURN_SHARES: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

impl Camera {
    /// A blocked step that did not slide far: the move of length `straight`
    /// whose direction turns least from the step's towards `dir` (the
    /// straight line to the point the camera heads for) and is
    /// free all the way; the straight line itself if none is, kept when it
    /// carries the camera further than `blocked`. Turning onto the straight
    /// line at once reversed a camera pressed into a corner within a frame
    /// (a velocity change of about 200 u/s, the largest jerk on a walker
    /// route at 1/30 s).
    #[allow(clippy::too_many_arguments)]
    fn turn_towards_the_line(
        &self,
        g: &Vdg<'_>,
        s: &State,
        blocked: (V3, u32),
        step: V3,
        dir: V3,
        straight: f64,
        margin: f32,
    ) -> (V3, u32) {
        let hops = self.params.max_substeps;
        let len = step.norm();
        let along = if len > 1e-9 { step * (1.0 / len) } else { dir };
        for share in TURN_SHARES {
            let mixed = along * (1.0 - share) + dir * share;
            let n = mixed.norm();
            if n < 1e-9 {
                continue;
            }
            let goal = s.pos + mixed * (straight / n);
            let b = g.advance_tol(
                s.face,
                s.pos.to_f32(),
                goal.to_f32(),
                margin,
                &mut CoverBudget {
                    hops,
                    leaf_searches: u32::MAX,
                },
                CLAMP_TOL,
                None,
                Some(&self.faces),
                STEP_EVALS,
            );
            let q = V3::from_f32(b.point);
            if b.reached || (share == 1.0 && (q - s.pos).norm() > (blocked.0 - s.pos).norm()) {
                return (q, b.face);
            }
        }
        blocked
    }
}

/// Pushes [`Camera::keep_room`] makes along the inward normal before it
/// gives up (the clearance's slope along it is about one).
const KEEP_ROOM_TRIES: usize = 3;

/// The share of the seen-speed cap ([`Camera::top_speed`]) kept back for
/// rounding: positions are f32, and a step of exactly the cap measured
/// between two rounded eye positions came out up to 0.01 units/s faster.
const SEEN_SPEED_ROUNDING: f64 = 1e-3;

/// How much more room than needed (units) a pushed-back end point aims for,
/// so that rounding to f32 does not leave it a hair short.
const KEEP_ROOM_EXTRA: f64 = 1e-3;

impl Camera {
    /// With `accel_tau`, the velocity `vel` the step wants, reached through
    /// the acceleration that would reach it in this update, followed with
    /// the lag `accel_tau` (kept in the state for the next update): the
    /// acceleration is continuous. Never faster than `top`, the update's
    /// top speed (a lagged acceleration carries on a little after its
    /// command stopped).
    fn lag_acceleration(&self, scene: &Scene, s: &mut State, vel: V3, top: f64) -> V3 {
        let k = lag_fraction(scene.dt, self.params.accel_tau);
        let wanted = (vel - s.vel) * (1.0 / scene.dt);
        s.acc = s.acc + (wanted - s.acc) * k;
        let vel = s.vel + s.acc * scene.dt;
        let speed = vel.norm();
        if speed > top {
            vel * (top / speed)
        } else {
            vel
        }
    }

    /// With `max_jerk`, the velocity `vel` the step wants, reached through
    /// an acceleration that differs from the last update's by at most
    /// `max_jerk · Δt` (and kept in the state for the next update). The
    /// acceleration asked for is the one that closes the gap to `vel` in
    /// this update, but no more than the camera can bring back to zero by
    /// the time the gap is closed (√(2 · max_jerk · gap), the arrival rule
    /// one derivative up): without it the velocity overshot its command
    /// and swung about it.
    fn limit_jerk(&self, scene: &Scene, s: &mut State, vel: V3) -> V3 {
        let j = f64::from(self.params.max_jerk);
        let dt = scene.dt;
        let gap = vel - s.vel;
        let g = gap.norm();
        let wanted = if g > 1e-12 {
            let reach = (2.0 * j * g).sqrt().min(g / dt);
            gap * (reach / g)
        } else {
            V3(0.0, 0.0, 0.0)
        };
        // The acceleration changes by at most max_jerk·Δt from the one the
        // last update commanded (not the one it moved with: a move stopped
        // by the boundary would hand on a huge one, and the camera swung).
        let change = wanted - s.acc;
        let most = j * dt;
        let c = change.norm();
        s.acc = if c > most {
            s.acc + change * (most / c)
        } else {
            wanted
        };
        s.vel + s.acc * dt
    }
}

impl Camera {
    /// With `max_decel`, the part of the velocity heading for the volume's
    /// boundary is no faster than the camera can brake from before it
    /// reaches the margin: √(2 · max_decel · (clearance − margin)), the
    /// clearance being the distance to the nearest boundary, so never more
    /// than the way left in any direction. A camera that ran into the
    /// boundary at speed stopped dead there or, turning onto its best
    /// candidate, bounced off it within a frame.
    fn brake_at_walls(&self, g: &Vdg<'_>, s: &State, vel: V3, here_clear: f64, margin: f32) -> V3 {
        let a = f64::from(self.params.max_decel);
        let room = (here_clear - f64::from(margin)).max(0.0);
        let speed2 = vel.norm2();
        // Far enough from every wall to stop from this speed: nothing to do.
        if a <= 0.0 || speed2 <= 2.0 * a * room {
            return vel;
        }
        let Some(n) = inward_normal(g, &self.faces, s.face, s.pos) else {
            return vel;
        };
        let towards = -vel.dot(n);
        let limit = (2.0 * a * room).sqrt();
        if towards > limit {
            vel + n * (towards - limit)
        } else {
            vel
        }
    }
}

impl Camera {
    /// With `max_decel`, the camera is no faster than it can stop from
    /// before the boundary straight ahead: √(2 · max_decel · way), the way
    /// being how far a move along the velocity goes before the margin
    /// stops it (looked for as far as the camera would need to stop, plus
    /// one frame). [`Self::brake_at_walls`] sees only the nearest wall,
    /// which is seldom the one ahead: a camera swinging round a player in
    /// a narrow room ran at 400 units/s into a wall a little further off,
    /// the move was cut short there and the camera lost 300 units/s in
    /// three frames (four times `max_decel`, the largest jerk of a spawn
    /// route at 1/30 s).
    ///
    /// The camera stands at `pos` in face `face` with `room` to the margin
    /// in every direction (its clearance less the margin); `dt` is the
    /// frame time. Where the way to look along fits in that room the wall
    /// ahead cannot be nearer, and no move is traced (most updates, away
    /// from walls).
    #[allow(clippy::too_many_arguments)]
    fn brake_before_the_wall_ahead(
        &self,
        g: &Vdg<'_>,
        pos: V3,
        face: u32,
        vel: V3,
        dt: f64,
        margin: f32,
        room: f64,
    ) -> V3 {
        let a = f64::from(self.params.max_decel);
        let speed = vel.norm();
        if a <= 0.0 || speed < 1e-6 {
            return vel;
        }
        let look = speed * speed / (2.0 * a) + speed * dt;
        if look <= room {
            return vel;
        }
        let ahead = pos + vel * (look / speed);
        let moved = g.advance_tol(
            face,
            pos.to_f32(),
            ahead.to_f32(),
            margin,
            &mut CoverBudget {
                hops: self.params.max_substeps,
                leaf_searches: 0,
            },
            CLAMP_TOL,
            None,
            Some(&self.faces),
            STEP_EVALS,
        );
        if moved.reached {
            return vel;
        }
        let way = (V3::from_f32(moved.point) - pos).norm();
        let limit = (2.0 * a * way).sqrt();
        if speed > limit {
            vel * (limit / speed)
        } else {
            vel
        }
    }
}

impl Camera {
    /// With `max_decel`, the camera closes in on the target no faster than
    /// it can brake from, after its reaction time, before it comes within
    /// d_μ of him (see [`stopping_speed`]), plus his own speed: nearer than
    /// d_μ f_dist wants it back, never on.
    /// A camera catching up at speed when the player stopped ran on up to
    /// him (or past him) and, at rest there, stayed too close: f_inertia
    /// rates every start from rest alike, so a distance error under 2 d_σ
    /// never made it back off.
    ///
    /// The limit falls by no more than `max_decel` per second (see
    /// [`no_harder_than`]) as long as the camera can still stop, after its
    /// reaction time, before it comes within `distance_min` of him (or d_μ
    /// where that is less): a player who stops with the game's friction
    /// stops about as hard as the camera may, and the camera, a reaction
    /// time behind, braked at up to 1.7 times `max_decel` to keep d_μ.
    /// It now uses part of the room inside d_μ to brake at its own rate.
    fn brake_before_the_target(&self, scene: &Scene, s: &State, vel: V3) -> V3 {
        let a = f64::from(self.params.max_decel);
        if a <= 0.0 {
            return vel;
        }
        let to_t = scene.t - s.pos;
        let r = to_t.norm();
        if r < 1e-6 {
            return vel;
        }
        let u = to_t * (1.0 / r);
        let closing = vel.dot(u);
        let lag = self.reaction_time();
        let limit_at = |near: f64| stopping_speed(a, (r - near).max(0.0), lag) + scene.brake_speed;
        let near = scene.d_mu;
        let hard = near.min(f64::from(self.params.distance_min));
        let gentle = no_harder_than(a, s.vel.dot(u), scene.dt).min(limit_at(hard));
        let limit = limit_at(near).max(gentle);
        if closing > limit {
            vel - u * (closing - limit)
        } else {
            vel
        }
    }
}

/// What the configuration keeps of this frame's target: its face and
/// position (next frame's hint and teleport test), the heading, and where
/// the last global search for an outside target ran.
fn remember_target(s: &mut State, scene: &Scene, heading: V3) {
    s.target_face = scene.face;
    s.target_prev = scene.t;
    s.heading = heading;
    s.d_mu = scene.d_mu;
    s.brake_speed = scene.brake_speed;
    s.recent_target_speed = scene.recent_target_speed;
    if scene.searched {
        s.outside_search = Some(scene.t);
    } else if scene.inside {
        s.outside_search = None;
    }
}

/// The highest speed from which braking at `a` (units/s²), begun `lag`
/// seconds late, stops within `way` units: `a·(√(lag² + 2·way/a) − lag)`,
/// the familiar `√(2·a·way)` when `lag` is 0. Near the end of the way it
/// falls in proportion to the way left (`way/lag`), so whatever follows
/// this bound settles with the time constant `lag` and its deceleration
/// fades to zero, where the bare square root asks for the full rate up to
/// the last unit and drops it there.
pub(super) fn stopping_speed(a: f64, way: f64, lag: f64) -> f64 {
    if lag <= 0.0 {
        return (2.0 * a * way).sqrt();
    }
    a * ((lag * lag + 2.0 * way / a).sqrt() - lag)
}

/// The least a speed of `v` (units/s) may fall to in an update of `dt`
/// seconds braking at `a` (units/s²): the floor under the camera's arrival
/// and closing limits, so that a limit that drops faster (the target
/// stopping short, the point it heads for jumping close) brakes the camera
/// at `max_decel`, its stated rate, rather than at whatever the limit's
/// drop asks for.
pub(super) fn no_harder_than(a: f64, v: f64, dt: f64) -> f64 {
    v - a * dt
}

/// How far a quantity smoothed with time constant `tau` (s) moves towards
/// its goal in `dt` seconds: `1 − e^(−Δt/τ)`, the same motion at any
/// frame rate.
pub(super) fn lag_fraction(dt: f64, tau: f32) -> f64 {
    1.0 - (-dt / f64::from(tau)).exp()
}

/// A blocked move's rest along the boundary: from `p` (where the move to
/// `goal` stopped at the margin), the part of the remaining way that does
/// not point out of the volume, as far as it goes. A camera grazing a wall
/// keeps its speed along it instead of stopping dead (a kink in its path
/// every time its smoothed direction touches the boundary).
#[allow(clippy::too_many_arguments)]
fn slide(
    g: &Vdg<'_>,
    faces: &FaceCache,
    p: V3,
    f: u32,
    goal: V3,
    margin: f32,
    hops: u32,
) -> (V3, u32) {
    let rest = goal - p;
    let Some(n) = inward_normal(g, faces, f, p) else {
        return (p, f);
    };
    let into = rest.dot(n);
    if into >= 0.0 {
        return (p, f);
    }
    let along = rest - n * into;
    if along.norm() < 1e-3 {
        return (p, f);
    }
    let b = advance_locally(g, faces, f, p, p + along, margin, hops);
    (V3::from_f32(b.point), b.face)
}

/// The way from `from` (in face `face`) towards `to` inside the volume
/// with `margin`, to within [`CLAMP_TOL`], crossing at most `hops` face
/// volumes and never searching the tree's leaves: the short moves beside
/// the step itself (a slide, a pushed-back end point, the target's way
/// ahead), which may stop early rather than cost a search.
pub(super) fn advance_locally(
    g: &Vdg<'_>,
    faces: &FaceCache,
    face: u32,
    from: V3,
    to: V3,
    margin: f32,
    hops: u32,
) -> Advance {
    g.advance_tol(
        face,
        from.to_f32(),
        to.to_f32(),
        margin,
        &mut CoverBudget {
            hops,
            leaf_searches: 0,
        },
        CLAMP_TOL,
        None,
        Some(faces),
        STEP_EVALS,
    )
}

/// The direction in which face `f`'s clearance grows fastest at `p` (the
/// volume boundary's inward normal near the boundary), by central
/// differences; `None` where it is flat.
fn inward_normal(g: &Vdg<'_>, faces: &FaceCache, f: u32, p: V3) -> Option<V3> {
    const H: f64 = 0.25;
    let d = |e: V3| faces.fc(g, f, p + e) - faces.fc(g, f, p - e);
    let n = V3(d(V3(H, 0.0, 0.0)), d(V3(0.0, H, 0.0)), d(V3(0.0, 0.0, H)));
    let len = n.norm();
    (len > 1e-9).then(|| n * (1.0 / len))
}

#[cfg(test)]
mod tests {
    use super::super::{Camera, CameraParams, Target};
    use crate::geom::V3;

    /// A corridor along x from 0 to 400 (vertices of clearance 30 every 40
    /// units on two rows 40 apart): its volume ends at x = 430.
    fn corridor() -> crate::VdgFile {
        let mut b = crate::VdgBuilder::new();
        let row = |b: &mut crate::VdgBuilder, y: f32| -> Vec<u32> {
            (0..=10)
                .map(|i| b.add_vertex([i as f32 * 40.0, y, 0.0], 30.0))
                .collect()
        };
        let (low, high) = (row(&mut b, 0.0), row(&mut b, 40.0));
        for i in 0..10 {
            b.add_face([low[i], low[i + 1], high[i]]);
            b.add_face([low[i + 1], high[i + 1], high[i]]);
        }
        crate::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap()
    }

    #[test]
    fn the_stopping_speed_stops_within_the_way_after_the_reaction_time() {
        let a = 1000.0;
        for way in [0.0, 0.5, 10.0, 80.0, 1000.0] {
            // No lag: the familiar square root.
            assert_eq!(super::stopping_speed(a, way, 0.0), (2.0 * a * way).sqrt());
            for lag in [0.05, 0.18, 0.5] {
                let v = super::stopping_speed(a, way, lag);
                // Coasting `lag` seconds, then braking at `a`, covers the way.
                let covered = v * lag + v * v / (2.0 * a);
                assert!(
                    (covered - way).abs() <= 1e-9 * way.max(1.0),
                    "{way} {lag}: {covered}"
                );
                assert!(v <= (2.0 * a * way).sqrt());
                // Near the end, the speed falls in proportion to the way left.
                if way <= 0.5 {
                    assert!((v - way / lag).abs() <= 0.2 * way / lag, "{way} {lag}: {v}");
                }
            }
        }
    }

    #[test]
    fn the_acceleration_lag_never_lets_the_camera_pass_its_top_speed() {
        let file = corridor();
        let g = file.graph();
        let mut cam = Camera::new(CameraParams::default()).unwrap();
        cam.reset(
            &g,
            &Target::new([20.0, 20.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]),
        );
        let start = cam.state.unwrap();
        let scene = cam.scene(
            &g,
            V3(20.0, 20.0, 0.0),
            V3(1.0, 0.0, 0.0),
            0,
            Some(&start),
            1.0 / 60.0,
        );
        // Already at 190 units/s and accelerating hard, commanded 192: the
        // lag alone would carry it past a top speed of 192, not of 500.
        let lagged = |top: f64| {
            let mut s = start;
            s.vel = V3(190.0, 0.0, 0.0);
            s.acc = V3(2000.0, 0.0, 0.0);
            cam.lag_acceleration(&scene, &mut s, V3(192.0, 0.0, 0.0), top)
        };
        let vel = lagged(192.0);
        assert!(vel.norm() <= 192.0, "{vel:?}");
        let free = lagged(500.0);
        assert!(
            free.norm() > 192.0,
            "the lag does not overshoot here: {free:?}"
        );
    }

    /// A camera 200 units behind a target standing on the corridor's axis
    /// (d_μ 80, the hard distance `distance_min` 40),
    /// moving at him with `closing` units/s: the closing speed the target
    /// brake lets through, and the stopping speeds (no target speed) before
    /// d_μ and before the hard distance.
    fn closing_after_the_target_brake(closing: f64) -> (f64, f64, f64) {
        let file = corridor();
        let g = file.graph();
        // d_μ as set, not brought in by the corridor's narrow room.
        let params = CameraParams {
            distance_room_factor: 0.0,
            ..CameraParams::default()
        };
        let mut cam = Camera::new(params.clone()).unwrap();
        cam.reset(
            &g,
            &Target::new([300.0, 20.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]),
        );
        let mut s = cam.state.unwrap();
        s.pos = V3(100.0, 20.0, 0.0);
        s.vel = V3(closing, 0.0, 0.0);
        let dt = 1.0 / 30.0;
        let scene = cam.scene(&g, V3(300.0, 20.0, 0.0), V3(1.0, 0.0, 0.0), 0, Some(&s), dt);
        assert_eq!(scene.brake_speed, 0.0, "the target stands still");
        let braked = cam.brake_before_the_target(&scene, &s, s.vel);
        let (a, lag) = (f64::from(params.max_decel), cam.reaction_time());
        let law = |near: f64| super::stopping_speed(a, 200.0 - near, lag);
        let hard = scene.d_mu.min(f64::from(params.distance_min));
        (braked.0, law(scene.d_mu), law(hard))
    }

    #[test]
    fn the_target_brake_slows_the_camera_at_max_decel_until_the_hard_distance() {
        let a = f64::from(CameraParams::default().max_decel);
        let dt = 1.0 / 30.0;
        // The target stands; the camera closes in, 200 units off. Slower
        // than it can stop from before d_μ: not braked.
        let (_, law_mu, law_hard) = closing_after_the_target_brake(0.0);
        assert!(law_mu + a * dt < law_hard, "{law_mu} {law_hard}");
        let (braked, ..) = closing_after_the_target_brake(law_mu - 1.0);
        assert_eq!(braked, law_mu - 1.0);
        // Faster: it loses one frame of max_decel, not all it would take to
        // stop before d_μ, as long as it can stop before the hard distance.
        let fast = law_mu + 10.0;
        let (braked, ..) = closing_after_the_target_brake(fast);
        assert!(
            (braked - (fast - a * dt).max(law_mu)).abs() < 1e-9,
            "{braked}"
        );
        let faster = law_mu + 0.5 * (law_hard - law_mu) + a * dt;
        let (braked, ..) = closing_after_the_target_brake(faster);
        assert!((braked - (faster - a * dt)).abs() < 1e-9, "{braked}");
        assert!(braked > law_mu, "braked to d_μ's limit at once: {braked}");
        // Too fast to stop before the hard distance at that rate: the hard
        // distance's limit.
        let (braked, ..) = closing_after_the_target_brake(law_hard + a * dt + 20.0);
        assert!((braked - law_hard).abs() < 1e-9, "{braked} {law_hard}");
    }

    #[test]
    fn the_arrival_slows_the_step_rule_by_at_most_max_decel() {
        let file = corridor();
        let g = file.graph();
        let params = CameraParams::default();
        let a = f64::from(params.max_decel);
        let mut cam = Camera::new(params).unwrap();
        cam.reset(
            &g,
            &Target::new([300.0, 20.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]),
        );
        let mut s = cam.state.unwrap();
        s.speed = 300.0;
        let dt = 1.0 / 30.0;
        let scene = cam.scene(&g, V3(300.0, 20.0, 0.0), V3(1.0, 0.0, 0.0), 0, Some(&s), dt);
        assert_eq!(scene.brake_speed, 0.0, "the target stands still");
        // The point it heads for is suddenly at hand (another candidate
        // won): the camera brakes at max_decel instead of stopping dead.
        let v = cam.speed(&scene, &s, 1.0, 0.0, 500.0);
        assert!((v - (300.0 - a * dt)).abs() < 1e-9, "{v}");
        // Far from it, the arrival does not bind.
        let far = cam.speed(&scene, &s, 1.0, 1000.0, 500.0);
        assert!(far > 300.0 - a * dt + 1.0, "{far}");
    }

    #[test]
    fn the_camera_can_always_stop_before_the_wall_ahead() {
        let file = corridor();
        let g = file.graph();
        let params = CameraParams::default();
        let (a, margin) = (f64::from(params.max_decel), params.near_margin);
        let mut cam = Camera::new(params).unwrap();
        cam.reset(
            &g,
            &Target::new([20.0, 20.0, 0.0], [1.0, 0.0, 0.0], [0.0; 3]),
        );
        let vel = V3(400.0, 0.0, 0.0);
        for x in [100.0f32, 300.0, 350.0, 380.0] {
            let p = [x, 20.0, 0.0];
            let face = g.nearest_face(p).unwrap().face;
            let braked = cam.brake_before_the_wall_ahead(
                &g,
                V3::from_f32(p),
                face,
                vel,
                1.0 / 30.0,
                margin,
                0.0,
            );
            // The way left: to the end of the volume (the hull of the last
            // two vertices' balls, 30 units beyond x = 400) less the margin.
            let way = 430.0 - f64::from(margin) - f64::from(x);
            let limit = (2.0 * a * way).sqrt();
            let speed = braked.norm();
            assert!(braked.1.abs() < 1e-9 && braked.2.abs() < 1e-9, "{braked:?}");
            if limit >= 400.0 {
                assert_eq!(
                    speed, 400.0,
                    "x = {x}: braked to {speed} with {way} units left"
                );
            } else {
                // Within the step's tolerance of the exact way.
                assert!(
                    speed <= limit * 1.01 && speed >= limit * 0.95,
                    "x = {x}: {speed} with {way} units left (at most {limit})"
                );
            }
        }
    }

    /// The best candidate alternates between two points on either side of
    /// a target walking along x at 250 u/s (their costs are close): the
    /// camera heading for each in turn would turn round every frame. The
    /// point it heads for keeps to the middle and moves with the target;
    /// without `goal_tau` it is the alternating candidate itself.
    #[test]
    fn the_point_the_camera_heads_for_keeps_its_side_and_moves_with_the_target() {
        let dt = 1.0 / 60.0;
        let step = V3(250.0 * dt, 0.0, 0.0);
        let side = V3(0.0, 40.0, 0.0);
        for (params, smoothed) in [
            (CameraParams::default(), true),
            (CameraParams::thesis(), false),
        ] {
            let cam = Camera::new(params).unwrap();
            let mut target = V3(0.0, 0.0, 0.0);
            let mut goal = target + V3(-80.0, 0.0, 0.0);
            for frame in 1..=120 {
                target = target + step;
                let behind = target + V3(-80.0, 0.0, 0.0);
                let best = if frame % 2 == 0 {
                    behind + side
                } else {
                    behind - side
                };
                let before = goal;
                goal = cam.goal_after(dt, goal, step, best, true);
                // Once the target is hidden, the best candidate itself.
                assert_eq!(cam.goal_after(dt, goal, step, best, false), best);
                if frame < 30 {
                    continue;
                }
                let sideways = goal.1.abs();
                let advance = goal.0 - before.0;
                if smoothed {
                    assert!(
                        sideways < 0.3 * side.1,
                        "frame {frame}: {sideways} off the middle"
                    );
                    assert!(
                        (advance - step.0).abs() < 0.01 * step.0,
                        "frame {frame}: advanced {advance}"
                    );
                } else {
                    assert_eq!(goal, best);
                }
            }
        }
    }
}
