//! The cameras a replay compares, behind one small trait, and the two baselines
//! people use today, both against the BSP's exact walls:
//!
//! - [`ChaseCam`]: Half-Life's locked chase cam (`V_GetChaseOrigin` in the SDK's
//!   client): pivot at the target's origin + 28 z, 112 units back along the view
//!   direction, a point trace through hull 0, the camera at the hit point + 4 × the
//!   wall normal. It jumps in front of every obstacle (the thesis' fig. 7.3).
//! - [`SpringArm`]: Unreal's SpringArm / Cinemachine's third-person follow: an arm of
//!   112 units from the target's eye, swept as a sphere of radius 12 against the exact
//!   walls (sphere tracing on the true wall distance), retracting at once on a hit and
//!   returning exponentially (rate 10/s, Unreal's lag speed).

use super::route::{TargetState, forward};
use bsp::oracle::Oracle;
use bsp::walls::Walls;

/// What a camera shows in one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub eye: [f32; 3],
    pub look_at: [f32; 3],
    /// The camera declared a cut (a jump it means, not a glitch).
    pub cut: bool,
}

/// A camera under test: reset at a route's start, then updated once per frame.
pub trait ReplayCamera {
    fn name(&self) -> &str;
    fn reset(&mut self, target: &TargetState);
    fn update(&mut self, target: &TargetState, dt: f32) -> Frame;
    /// The distance from the target's eye the camera aims for (the replay's distance
    /// error is measured against it).
    fn ideal_distance(&self) -> f64 {
        CHASE_DISTANCE
    }
}

/// Half-Life's chase distance (`cl_chasedist`).
pub const CHASE_DISTANCE: f64 = 112.0;
/// Height of the chase cam's pivot above the target's origin.
pub const CHASE_PIVOT: f64 = 28.0;

fn add(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// Half-Life's locked chase cam.
pub struct ChaseCam<'a> {
    oracle: &'a Oracle,
}

impl<'a> ChaseCam<'a> {
    pub fn new(oracle: &'a Oracle) -> Self {
        ChaseCam { oracle }
    }

    /// `V_GetChaseOrigin`: the camera position for a target.
    pub fn place(&self, t: &TargetState) -> ([f64; 3], [f64; 3]) {
        let o = t.origin.map(f64::from);
        let pivot = [o[0], o[1], o[2] + CHASE_PIVOT];
        let f = forward(t.angles).map(f64::from);
        let end = add(pivot, f, -CHASE_DISTANCE);
        match self.oracle.trace(0, pivot, end) {
            Some(tr) => (add(tr.end, tr.normal, 4.0), pivot),
            None => (end, pivot),
        }
    }
}

impl ReplayCamera for ChaseCam<'_> {
    fn name(&self) -> &str {
        "chase"
    }
    fn reset(&mut self, _: &TargetState) {}
    fn update(&mut self, t: &TargetState, _: f32) -> Frame {
        let (eye, pivot) = self.place(t);
        Frame {
            eye: eye.map(|c| c as f32),
            look_at: pivot.map(|c| c as f32),
            cut: false,
        }
    }
}

/// A spring arm with a swept sphere, instant retract and exponential return.
pub struct SpringArm<'a> {
    walls: &'a Walls,
    pub arm: f64,
    pub radius: f64,
    /// Return rate per second (1 − e^(−rate·dt) of the gap closes per frame).
    pub rate: f64,
    length: f64,
}

impl<'a> SpringArm<'a> {
    pub fn new(walls: &'a Walls) -> Self {
        SpringArm {
            walls,
            arm: CHASE_DISTANCE,
            radius: 12.0,
            rate: 10.0,
            length: 0.0,
        }
    }

    /// How far a sphere of radius `radius` (less where the pivot itself is tighter)
    /// travels from `pivot` along unit `dir` before touching a wall, up to `max`.
    pub fn sweep(&self, pivot: [f64; 3], dir: [f64; 3], max: f64) -> f64 {
        let r = self.radius.min(self.walls.distance(pivot) - 0.25).max(0.0);
        let mut s = 0.0;
        for _ in 0..96 {
            let d = self.walls.distance(add(pivot, dir, s)) - r;
            if d < 0.05 {
                return s;
            }
            s += d;
            if s >= max {
                return max;
            }
        }
        s.min(max)
    }
}

impl ReplayCamera for SpringArm<'_> {
    fn name(&self) -> &str {
        "springarm"
    }
    fn reset(&mut self, t: &TargetState) {
        let pivot = t.eye().map(f64::from);
        let dir = forward(t.angles).map(|c| -c as f64);
        self.length = self.sweep(pivot, dir, self.arm);
    }
    fn update(&mut self, t: &TargetState, dt: f32) -> Frame {
        let pivot = t.eye().map(f64::from);
        let dir = forward(t.angles).map(|c| -c as f64);
        let free = self.sweep(pivot, dir, self.arm);
        if free < self.length {
            self.length = free;
        } else {
            self.length += (free - self.length) * (1.0 - (-self.rate * dt as f64).exp());
        }
        Frame {
            eye: add(pivot, dir, self.length).map(|c| c as f32),
            look_at: pivot.map(|c| c as f32),
            cut: false,
        }
    }
}
