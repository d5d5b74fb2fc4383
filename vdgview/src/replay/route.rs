//! Target routes: what the followed player does, frame by frame.
//!
//! A route is a list of player states at increasing times (the origin is the player's
//! origin in the map's game — GoldSrc: the centre of its clip hull; Quake 1, 2 and 3:
//! 24 units above the floor, [`Body::of`] — angles are Quake view angles
//! `[pitch, yaw, roll]` in degrees). Routes are produced at their own rate (the
//! walker's fixed step, a recording's frames) and [`Route::resample`]d at the
//! replay's `--dt`, so 1/60 and 1/30 replays see the same motion.

use bsp::Game;
use bsp::oracle::{Body, Stance};
use bsp::player::player_hull;

/// One frame of the followed player.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetState {
    /// Seconds since the route began.
    pub t: f64,
    /// Centre of the player's hull.
    pub origin: [f32; 3],
    /// Quake view angles `[pitch, yaw, roll]` in degrees (pitch > 0 looks down).
    pub angles: [f32; 3],
    /// Units per second.
    pub velocity: [f32; 3],
    /// Crouched (clip hull 3) rather than standing (clip hull 1).
    pub crouch: bool,
    /// The map's game: the player's box and view ([`Body::of`]).
    pub game: Game,
}

impl TargetState {
    /// The player's box and view now (standing or crouched, in the map's game).
    pub fn stance(&self) -> Stance {
        *Body::of(self.game).stance(player_hull(self.crouch))
    }

    /// The player's eye (origin + the game's view offset: GoldSrc 28 standing, 12
    /// crouched; Quake 22; Quake 2 22 and −2; Quake 3 26 and 12).
    pub fn eye(&self) -> [f32; 3] {
        let h = self.stance().view as f32;
        [self.origin[0], self.origin[1], self.origin[2] + h]
    }

    /// Unit view direction from the angles (Quake's `AngleVectors` forward).
    pub fn heading(&self) -> [f32; 3] {
        forward(self.angles)
    }

    /// Horizontal speed in units per second.
    pub fn speed(&self) -> f32 {
        (self.velocity[0].powi(2) + self.velocity[1].powi(2) + self.velocity[2].powi(2)).sqrt()
    }

    /// The 8 corners (pulled 1 unit inwards) and the centre of the player's hull:
    /// the points whose visibility says how much of the player a camera shows.
    pub fn hull_points(&self) -> [[f64; 3]; 9] {
        let o = self.origin.map(f64::from);
        let s = self.stance();
        let lo = [0, 1, 2].map(|k| s.mins[k] + 1.0);
        let hi = [0, 1, 2].map(|k| s.maxs[k] - 1.0);
        let mut out = [o; 9];
        for (i, p) in out.iter_mut().take(8).enumerate() {
            *p = [0, 1, 2].map(|k| o[k] + if i >> k & 1 == 1 { hi[k] } else { lo[k] });
        }
        out
    }
}

/// Quake's `AngleVectors` forward vector of `[pitch, yaw, roll]` degrees.
pub fn forward(angles: [f32; 3]) -> [f32; 3] {
    let (p, y) = (angles[0].to_radians(), angles[1].to_radians());
    [p.cos() * y.cos(), p.cos() * y.sin(), -p.sin()]
}

/// A named sequence of player states.
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    pub name: String,
    pub states: Vec<TargetState>,
}

impl Route {
    /// Length in seconds.
    pub fn duration(&self) -> f64 {
        match (self.states.first(), self.states.last()) {
            (Some(a), Some(b)) => b.t - a.t,
            _ => 0.0,
        }
    }

    /// The route at a fixed step `dt` (linear between states, yaw the short way round),
    /// times starting at 0.
    pub fn resample(&self, dt: f64) -> Vec<TargetState> {
        let Some(first) = self.states.first() else {
            return Vec::new();
        };
        let t0 = first.t;
        let n = (self.duration() / dt).floor() as usize + 1;
        let mut out = Vec::with_capacity(n);
        let mut j = 0;
        for i in 0..n {
            let t = t0 + i as f64 * dt;
            while j + 2 < self.states.len() && self.states[j + 1].t <= t {
                j += 1;
            }
            let a = &self.states[j];
            let b = self.states.get(j + 1).unwrap_or(a);
            let f = if b.t > a.t {
                ((t - a.t) / (b.t - a.t)).clamp(0.0, 1.0) as f32
            } else {
                0.0
            };
            let mix = |x: f32, y: f32| x + f * (y - x);
            let angles = [0, 1, 2].map(|k| {
                let d = (b.angles[k] - a.angles[k] + 540.0).rem_euclid(360.0) - 180.0;
                a.angles[k] + f * d
            });
            out.push(TargetState {
                t: t - t0,
                origin: [0, 1, 2].map(|k| mix(a.origin[k], b.origin[k])),
                angles,
                velocity: [0, 1, 2].map(|k| mix(a.velocity[k], b.velocity[k])),
                crouch: if f < 0.5 { a.crouch } else { b.crouch },
                game: a.game,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(t: f64, x: f32, yaw: f32) -> TargetState {
        TargetState {
            t,
            origin: [x, 0.0, 36.0],
            angles: [0.0, yaw, 0.0],
            velocity: [100.0, 0.0, 0.0],
            crouch: false,
            game: Game::GoldSrc,
        }
    }

    #[test]
    fn resample_interpolates_and_turns_the_short_way() {
        let r = Route {
            name: "r".into(),
            states: vec![state(1.0, 0.0, 350.0), state(2.0, 100.0, 10.0)],
        };
        let s = r.resample(0.25);
        assert_eq!(s.len(), 5);
        assert_eq!(s[2].origin[0], 50.0);
        assert!((s[2].angles[1] - 360.0).abs() < 1e-3, "{}", s[2].angles[1]);
        assert_eq!(s[0].t, 0.0);
    }

    #[test]
    fn forward_follows_quake_angles() {
        let f = forward([0.0, 90.0, 0.0]);
        assert!(f[0].abs() < 1e-6 && (f[1] - 1.0).abs() < 1e-6);
        assert!(
            forward([45.0, 0.0, 0.0])[2] < 0.0,
            "positive pitch looks down"
        );
    }
}
