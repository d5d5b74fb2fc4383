//! The cost functions (thesis 5.1): f_dist, f_angle, f_inertia, f_clear,
//! f_vis with its weight f_novis, and f_total, which rates a position.

use super::{Camera, Scene, Slot, State};
use crate::geom::V3;
use crate::read::Vdg;

/// The cost terms of one position (thesis 5.1); `total` is
/// `(vis + novis · (dist + angle + inertia + clear)) / 5`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Costs {
    pub vis: f32,
    pub novis: f32,
    pub dist: f32,
    pub angle: f32,
    pub inertia: f32,
    pub clear: f32,
    pub total: f32,
}

/// The longest way VDistance tells apart (units): longer ones are as far
/// (a level is rarely more than a few thousand units across).
pub(super) const FAR_WAY: f64 = 16_384.0;

/// VDistance where there is no way: worse than any way, yet f_vis over it
/// (about 4.7·10⁵, an f32 step of 1/128 in f_total) leaves the other terms
/// their say among candidates that all lack a way.
pub(super) const NO_WAY: f64 = 2.0 * FAR_WAY;

impl Camera {
    /// All cost terms at `k` (in face `face` with clearance `clear`).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn costs_at(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &State,
        k: V3,
        face: u32,
        clear: f64,
        visible: Option<bool>,
        slot: Option<Slot>,
    ) -> Costs {
        let visible = match visible {
            Some(v) => v,
            None => k == scene.t_vis || self.sees(g, face, k, scene, slot),
        };
        let vis = if visible {
            0.0
        } else {
            let vd = self.vdistance(g, scene, face, k);
            self.vis_cost(vd)
        };
        let dist = self.dist_cost(scene, k);
        let angle = self.angle_cost(scene, k);
        let inertia = self.inertia_cost(scene, k);
        let clear = self.clear_cost(scene, s, clear);
        let total = (vis + scene.novis * (dist + angle + inertia + clear)) / 5.0;
        Costs {
            vis: vis as f32,
            novis: scene.novis as f32,
            dist: dist as f32,
            angle: angle as f32,
            inertia: inertia as f32,
            clear: clear as f32,
            total: total as f32,
        }
    }

    /// VDistance(k, t): from the frame's distance field, or (the thesis) an
    /// A* per call. A way longer than [`FAR_WAY`] counts as that long, and
    /// no way at all as [`NO_WAY`]: finite, and small enough that f_total
    /// (an f32) still tells the other terms apart. With 10⁶ for "no way"
    /// f_vis was 4·10⁸, the totals of all hidden candidates were equal to
    /// the bit, and the first of them (the camera's own place) won: the
    /// camera stood still behind a target it could not reach.
    ///
    /// While the target is out of reach ([`Scene::out_of_reach`]) the
    /// straight distance to it instead: the way then runs round a detour
    /// longer than the camera covers before the cut (a low passage the
    /// graph joins to the camera's side only far away, a floor between two
    /// levels), and following it ran the camera off at top speed from a
    /// target 50–100 units away, only for the cut to bring it back half a
    /// second later. Near the target it sees him again as soon as he comes
    /// out.
    pub(super) fn vdistance(&mut self, g: &Vdg<'_>, scene: &Scene, face: u32, k: V3) -> f64 {
        if scene.out_of_reach {
            return (k - scene.t).norm().min(FAR_WAY);
        }
        let d = if self.params.distance_field {
            f64::from(self.field.vdistance(g, face, k.to_f32()))
        } else {
            self.finder
                .path_between_faces(g, face, k.to_f32(), scene.face, scene.t.to_f32())
                .map_or(f64::INFINITY, |p| f64::from(p.length))
        };
        if d.is_finite() {
            d.min(FAR_WAY)
        } else {
            NO_WAY
        }
    }

    /// Whether the target is out of reach from `k` (in face `face`): the
    /// update's distance field proves the way through the graph longer than
    /// the camera covers in `cut_after` at its top speed, or that there is
    /// none (a field cut short by its budget gives lower bounds, which
    /// prove it too). Never without a field.
    pub(super) fn unreachable(&mut self, g: &Vdg<'_>, face: u32, k: V3) -> bool {
        let reach = f64::from(self.params.max_speed) * f64::from(self.params.cut_after);
        self.params.distance_field && f64::from(self.field.vdistance(g, face, k.to_f32())) > reach
    }

    pub(super) fn vis_cost(&self, vd: f64) -> f64 {
        if self.params.normalized_visibility {
            (1.0 + vd / f64::from(self.params.distance_sigma)).powi(2)
        } else {
            1.0 + vd
        }
    }

    pub(super) fn dist_cost(&self, scene: &Scene, k: V3) -> f64 {
        let p = &self.params;
        (((scene.t - k).norm() - scene.d_mu) / f64::from(p.distance_sigma)).powi(2)
    }

    pub(super) fn angle_cost(&self, scene: &Scene, k: V3) -> f64 {
        let tc = k - scene.t;
        let len = tc.norm();
        let angle = if len > 1e-6 {
            (tc.dot(scene.a_n) / len).clamp(-1.0, 1.0).acos()
        } else {
            std::f64::consts::FRAC_PI_2
        };
        (angle / f64::from(self.params.angle_sigma_deg).to_radians()).powi(2)
    }

    /// f_inertia. With `inertia_step` the candidate is first brought within
    /// the horizon's reach of the camera: a far candidate in the direction
    /// the camera is already going is a gentle step, not a violent turn (the
    /// thesis compares the candidate itself, so a camera slowed by a narrow
    /// corridor rated a candidate a few dozen units back towards a standing
    /// player as costly as a swerve, and drifted away from him).
    pub(super) fn inertia_cost(&self, scene: &Scene, k: V3) -> f64 {
        // Squared lengths: no square root for the candidates within reach
        // (all of them with `inertia_step` off, where the reach is infinite).
        let d = k - scene.pos;
        let len2 = d.norm2();
        let k = if len2 > scene.inertia_reach * scene.inertia_reach {
            scene.pos + d * (scene.inertia_reach / len2.sqrt())
        } else {
            k
        };
        ((k - scene.c_t).norm() / scene.inertia_scale).powi(2)
    }

    /// f_clear: the room the camera needs, p_σ seconds at its speed, over
    /// the room at the position; with [`CameraParams::clearance_within_target_room`](super::CameraParams::clearance_within_target_room)
    /// the need is at most the room the target itself has.
    pub(super) fn clear_cost(&self, scene: &Scene, s: &State, clearance: f64) -> f64 {
        let mut need = s.clear_speed * f64::from(self.params.clearance_sigma);
        if self.params.clearance_within_target_room {
            need = need.min(scene.target_room);
        }
        (need / clearance.max(1e-3)).powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraParams;

    /// f_total as the candidates compare it: an f32.
    fn total(cam: &Camera, vd: f64, rest: f64) -> f32 {
        ((cam.vis_cost(vd) + rest) / 5.0) as f32
    }

    #[test]
    fn candidates_without_a_way_are_still_told_apart_by_the_other_terms() {
        for params in [CameraParams::default(), CameraParams::thesis()] {
            let cam = Camera::new(params).unwrap();
            // Two hidden candidates, neither with a way to the target: a
            // tenth of f_dist apart.
            assert!(total(&cam, NO_WAY, 1.0) < total(&cam, NO_WAY, 1.1));
            assert!(total(&cam, FAR_WAY, 1.0) < total(&cam, FAR_WAY, 1.1));
            // No way at all is worse than the longest way, whatever the rest.
            assert!(total(&cam, FAR_WAY, 50.0) < total(&cam, NO_WAY, 0.0));
        }
    }
}
