//! Where the target stands this frame: its face (a local climb, a tree
//! leaf, a global search when it is outside the volume), the point
//! visibility is judged to, the ideal direction a_n and the frame's fixed
//! cost terms.

use super::motion::{advance_locally, lag_fraction};
use super::types::Ahead;
use super::{Camera, Scene, State, Target};
use crate::geom::V3;
use crate::read::Vdg;

/// Clearance a point needs to count as inside a face volume in the camera's
/// one-face visibility shortcut (the line-of-sight certificate's margin).
pub(super) const INSIDE: f64 = 1e-4;

/// How long (s) the camera remembers the target's top speed for
/// [`CameraParams::seen_speed_factor`](super::CameraParams::seen_speed_factor): the time constant with
/// which it is forgotten.
const SEEN_SPEED_MEMORY: f64 = 1.0;

/// This frame's [`Scene::recent_target_speed`]: the target's speed, or the
/// last update's (`last`) forgotten over `dt` with [`SEEN_SPEED_MEMORY`]
/// when that is higher.
fn recent_target_speed_after(target_speed: f64, last: Option<f64>, dt: f64) -> f64 {
    last.map_or(target_speed, |last| {
        target_speed.max(last * (-dt.max(0.0) / SEEN_SPEED_MEMORY).exp())
    })
}

impl Camera {
    /// The target's heading as a unit vector, with the pitch weighted by
    /// [`CameraParams::heading_pitch_weight`](super::CameraParams::heading_pitch_weight); a zero heading keeps the
    /// last one.
    pub(super) fn heading(&self, target: &Target) -> V3 {
        let h = V3::from_f32(target.heading);
        let horiz = horizontal(h);
        if h.norm() < 1e-9 {
            return self.state.map_or(V3(1.0, 0.0, 0.0), |s| s.heading);
        }
        let w = f64::from(self.params.heading_pitch_weight);
        let pitch = h.2.atan2(horiz) * w;
        let yaw = if horiz > 1e-9 {
            h.1.atan2(h.0)
        } else {
            self.state.map_or(0.0, |s| s.heading.1.atan2(s.heading.0))
        };
        direction(yaw, pitch)
    }

    /// Locates the target in the graph and derives the frame's fixed terms.
    pub(super) fn scene(
        &mut self,
        g: &Vdg<'_>,
        t: V3,
        heading: V3,
        hint: u32,
        state: Option<&State>,
        dt: f64,
    ) -> Scene {
        let (face, inside, searched) = self.locate(g, t, hint, state);
        let t_vis = if inside { t } else { anchor(g, face, t) };
        let p = &self.params;
        let yaw = heading.1.atan2(heading.0) + f64::from(p.angle_mu_yaw_deg).to_radians();
        let pitch =
            heading.2.atan2(horizontal(heading)) + f64::from(p.angle_mu_pitch_deg).to_radians();
        let a_n = direction(yaw, pitch);
        let (pos, vel, speed, hidden) = state.map_or((t, V3(0.0, 0.0, 0.0), 0.0, 0.0), |s| {
            (s.pos, s.vel, s.speed, s.hidden)
        });
        // The target's speed over the last update (a teleport cuts before
        // it counts; the cap keeps a hitch from freeing the camera).
        let target_speed = match state {
            Some(s) if dt > 0.0 => ((t - s.target_prev).norm() / dt).min(f64::from(p.max_speed)),
            _ => 0.0,
        };
        // f_inertia compares with where inertia carries the camera over the
        // horizon (the thesis: one frame); the denominator is that travel,
        // floored so a resting camera's cost stays finite.
        let horizon = if p.inertia_horizon > 0.0 {
            f64::from(p.inertia_horizon)
        } else {
            dt.max(1e-6)
        };
        let c_t = pos + vel * horizon;
        let inertia_reach = speed
            .max(f64::from(p.inertia_min_speed))
            .max(target_speed * f64::from(p.inertia_target_speed))
            * horizon;
        let inertia_scale = inertia_reach * f64::from(p.inertia_sigma);
        let v_sigma = f64::from(p.visibility_sigma);
        let novis = (v_sigma / (v_sigma + hidden)).powi(2);
        let in_face = self.faces.fc(g, face, t_vis);
        // The target's room is the graph's clearance at him, the largest of
        // the faces there: the face he keeps from frame to frame may hold
        // him only by a sliver (9 units of room in a hall of 48). One round
        // over that face and its neighbours: four rounds added about 5 µs
        // to an update's median (`camera_bench`), one adds about 2.
        let target_room = if in_face > INSIDE {
            g.climb_cached(&self.faces, face, t_vis, 1).1
        } else {
            in_face
        };
        let ahead = match state {
            Some(s) if inside && dt > 0.0 && target_speed > 0.0 => {
                self.ahead(g, face, t, t - s.target_prev, target_speed)
            }
            _ => None,
        };
        Scene {
            t,
            face,
            t_vis,
            inside,
            target_speed,
            brake_speed: self.brake_speed_after(target_speed, state.map(|s| s.brake_speed), dt),
            recent_target_speed: recent_target_speed_after(
                target_speed,
                state.map(|s| s.recent_target_speed),
                dt,
            ),
            a_n,
            dt,
            c_t,
            inertia_scale,
            pos,
            inertia_reach: if p.inertia_step {
                inertia_reach
            } else {
                f64::INFINITY
            },
            novis,
            searched,
            t_vis_in_face: in_face > INSIDE,
            target_room: target_room.max(0.0),
            d_mu: self.distance_mu_after(target_room.max(0.0), state, dt),
            out_of_reach: state.is_some_and(|s| s.unreachable),
            ahead,
        }
    }

    /// This frame's [`Scene::brake_speed`]: the target's speed, or the last
    /// update's brake speed (`last`) falling towards it with the lag
    /// `accel_tau` when that is higher.
    fn brake_speed_after(&self, target_speed: f64, last: Option<f64>, dt: f64) -> f64 {
        let tau = self.params.accel_tau;
        match last {
            Some(last) if tau > 0.0 && last > target_speed => {
                last + (target_speed - last) * lag_fraction(dt.max(0.0), tau)
            }
            _ => target_speed,
        }
    }

    /// This frame's d_μ: the last update's, followed towards the one for
    /// the target's `room` with the lag `distance_room_tau` (the room jumps
    /// at every doorway and jump; the ideal place must not).
    fn distance_mu_after(&self, room: f64, state: Option<&State>, dt: f64) -> f64 {
        let wanted = self.distance_mu_at(room);
        let tau = self.params.distance_room_tau;
        match state {
            Some(s) if tau > 0.0 => s.d_mu + (wanted - s.d_mu) * lag_fraction(dt.max(0.0), tau),
            _ => wanted,
        }
    }

    /// d_μ where the target has `room`: `distance_mu`, or `room` times
    /// `distance_room_factor` where that is less (never below
    /// `distance_min`).
    pub(super) fn distance_mu_at(&self, room: f64) -> f64 {
        let p = &self.params;
        let mu = f64::from(p.distance_mu);
        if p.distance_room_factor > 0.0 {
            mu.min((room * f64::from(p.distance_room_factor)).max(f64::from(p.distance_min)))
        } else {
            mu
        }
    }

    /// Where the target gets within [`CameraParams::sight_lead`](super::CameraParams::sight_lead) going on
    /// at `speed` along `motion` (its last update's displacement), stopped
    /// at the volume's boundary; `None` when that is less than a unit away.
    fn ahead(&self, g: &Vdg<'_>, face: u32, t: V3, motion: V3, speed: f64) -> Option<Ahead> {
        let lead = f64::from(self.params.sight_lead) * speed;
        let len = motion.norm();
        if lead < 1.0 || len < 1e-9 {
            return None;
        }
        let goal = t + motion * (lead / len);
        let a = advance_locally(g, &self.faces, face, t, goal, 0.0, self.params.max_substeps);
        let point = V3::from_f32(a.point);
        let lead = (point - t).norm();
        (lead >= 1.0).then_some(Ahead {
            point,
            face: a.face,
            lead,
        })
    }

    /// The target's face: a local climb from last frame's face; when that
    /// ends outside the volume, the tree leaf at the target; when the target
    /// is outside the volume, a global search — repeated only after the
    /// target moved 32 units, so a target far outside costs a tree search
    /// now and then, not every frame. Returns (face, inside, searched).
    pub(super) fn locate(
        &self,
        g: &Vdg<'_>,
        t: V3,
        hint: u32,
        state: Option<&State>,
    ) -> (u32, bool, bool) {
        if (hint as usize) < g.faces.len() {
            // Our variant keeps last frame's face while it holds the target
            // (any face holding it serves as the field's entry and the
            // visibility anchor); the thesis climbs to ρ(t)'s face.
            if !self.params.exact_reachable && self.faces.fc(g, hint, t) > INSIDE {
                return (hint, true, false);
            }
            let (f, c) = g.climb_cached(&self.faces, hint, t, 32);
            if c > 0.0 {
                return (f, true, false);
            }
            if let Some((leaf_face, _)) = g.leaf_face_holding(&self.faces, t) {
                return (leaf_face, true, false);
            }
            if let Some(s) = state.and_then(|s| s.outside_search)
                && (s - t).norm() < 32.0
            {
                return (f, false, false);
            }
            // The leaf was looked at just above.
            return searched(g.nearest_face_by_tree(t));
        }
        searched(g.nearest_face_cached(&self.faces, t))
    }
}

/// [`Camera::locate`]'s answer after a global search: the face found, whether
/// it holds the target, and that a search was made.
fn searched(hit: Option<(u32, f64)>) -> (u32, bool, bool) {
    match hit {
        Some((f, c)) => (f, c > 0.0, true),
        None => (0, false, true),
    }
}

/// A point inside the volume of `face` as close to `t` as a straight line
/// from the triangle's centroid allows: where visibility is judged for a
/// target standing outside the volume.
fn anchor(g: &Vdg<'_>, face: u32, t: V3) -> V3 {
    let [a, b, c] = g.faces.get(face).map(|v| g.pos(v));
    let centroid = (a + b + c) * (1.0 / 3.0);
    V3::from_f32(g.trace(face, centroid.to_f32(), t.to_f32()))
}

/// The unit vector of azimuth `yaw` and elevation `pitch` (radians, z up).
fn direction(yaw: f64, pitch: f64) -> V3 {
    V3(
        pitch.cos() * yaw.cos(),
        pitch.cos() * yaw.sin(),
        pitch.sin(),
    )
}

/// The length of `v`'s horizontal part (x, y).
pub(super) fn horizontal(v: V3) -> f64 {
    (v.0 * v.0 + v.1 * v.1).sqrt()
}

#[cfg(test)]
mod tests {
    use super::super::{Camera, CameraParams};

    #[test]
    fn the_brakes_take_a_speed_up_at_once_and_a_slow_down_with_the_cameras_lag() {
        let cam = Camera::new(CameraParams::default()).unwrap();
        let dt = 1.0 / 60.0;
        // Faster than last frame, or the first frame: the target's speed.
        assert_eq!(cam.brake_speed_after(300.0, Some(100.0), dt), 300.0);
        assert_eq!(cam.brake_speed_after(300.0, None, dt), 300.0);
        // A landing (300 → 140 u/s in a frame): a fraction 1 − e^(−Δt/τ)
        // of the way down per frame, all of it after a few τ.
        let k = 1.0 - (-dt / 0.05f64).exp();
        let once = cam.brake_speed_after(140.0, Some(300.0), dt);
        assert!((once - (300.0 - 160.0 * k)).abs() < 1e-4, "{once}");
        let mut b = 300.0;
        for _ in 0..60 {
            b = cam.brake_speed_after(140.0, Some(b), dt);
        }
        assert!((b - 140.0).abs() < 1e-3, "{b}");
        // The thesis' camera has no such lag.
        let thesis = Camera::new(CameraParams::thesis()).unwrap();
        assert_eq!(thesis.brake_speed_after(140.0, Some(300.0), dt), 140.0);
    }
}
