//! Particles moving through the placed tiles, a function of time only.

use super::EditorView;
use crate::editor::model::Editor;
use crate::rng::Rng;

/// Particles advected through the placed tiles, a function of time only
/// (fixed steps from a fixed seed), so a screenshot at time `t` is
/// reproducible.
pub(super) struct Particles {
    pub(super) pos: Vec<[f64; 2]>,
    age: Vec<f64>,
    rng: Rng,
    steps: u64,
}

/// Particle step in seconds.
const PARTICLE_DT: f64 = 1.0 / 30.0;
/// Particle lifetime in seconds.
const PARTICLE_LIFE: f64 = 4.0;

impl Particles {
    pub(super) fn new() -> Particles {
        Particles {
            pos: Vec::new(),
            age: Vec::new(),
            rng: Rng::new(1),
            steps: 0,
        }
    }
}

impl EditorView {
    /// Advances the particles to time `t` (re-running from zero when `t`
    /// lies before the current time).
    pub(super) fn advance_particles(&mut self, ed: &Editor, t: f64) {
        let target = (t / PARTICLE_DT).round() as u64;
        let (w, h) = ed.size();
        let want = ((w * h) as usize * 3).clamp(60, 2500);
        if target < self.particles.steps || self.particles.pos.len() != want {
            self.particles = Particles::new();
            for _ in 0..want {
                let p = [
                    self.particles.rng.unit() * w as f64,
                    self.particles.rng.unit() * h as f64,
                ];
                let age = self.particles.rng.unit() * PARTICLE_LIFE;
                self.particles.pos.push(p);
                self.particles.age.push(age);
            }
        }
        // At most 10 s of catching up per frame.
        let first = self.particles.steps.max(target.saturating_sub(300));
        for _ in first..target {
            for i in 0..self.particles.pos.len() {
                let p = self.particles.pos[i];
                let moved = self.velocity(ed, p).and_then(|v| {
                    let mid = [
                        p[0] + v[0] * PARTICLE_DT / 2.0,
                        p[1] + v[1] * PARTICLE_DT / 2.0,
                    ];
                    let v2 = self.velocity(ed, mid)?;
                    Some([p[0] + v2[0] * PARTICLE_DT, p[1] + v2[1] * PARTICLE_DT])
                });
                self.particles.age[i] += PARTICLE_DT;
                let rng = &mut self.particles.rng;
                let (rx, ry) = (rng.unit(), rng.unit());
                match moved {
                    Some(q) if self.particles.age[i] < PARTICLE_LIFE => self.particles.pos[i] = q,
                    _ => {
                        self.particles.pos[i] = [rx * w as f64, ry * h as f64];
                        self.particles.age[i] = 0.0;
                    }
                }
            }
        }
        self.particles.steps = target;
    }
}
