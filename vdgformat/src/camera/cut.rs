//! Cuts: the camera jumps instead of moving (the first frame, a
//! teleported target, a target hidden too long).

use super::motion::CLAMP_TOL;
use super::{Camera, Pose, Scene, State};
use crate::geom::V3;
use crate::query::CoverBudget;
use crate::read::Vdg;

impl Camera {
    /// A cut: puts the camera at the target (the thesis: c₀ = t) or, with
    /// [`CameraParams::cut_to_ideal`](super::CameraParams::cut_to_ideal), as far towards the ideal position as
    /// the volume allows along a few directions around a_n.
    pub(super) fn cut(&mut self, g: &Vdg<'_>, scene: &Scene, heading: V3) -> Pose {
        let start = scene.t_vis;
        let start_clear = g.fc(scene.face, start);
        let (mut pos, mut face) = (start, scene.face);
        if self.params.cut_to_ideal {
            let margin = self.margin_at(start_clear);
            let d_mu = f64::from(self.params.distance_mu);
            let mut best = f64::INFINITY;
            for dir in cut_directions(scene.a_n) {
                let goal = start + dir * d_mu;
                let a = g.advance_tol(
                    scene.face,
                    start.to_f32(),
                    goal.to_f32(),
                    margin,
                    &mut CoverBudget {
                        hops: 64,
                        leaf_searches: u32::MAX,
                    },
                    CLAMP_TOL,
                    None,
                    Some(&self.faces),
                );
                let p = V3::from_f32(a.point);
                let cost = self.dist_cost(scene, p) + self.angle_cost(scene, p);
                if cost < best {
                    best = cost;
                    (pos, face) = (p, a.face);
                }
            }
        }
        let look = scene.t;
        self.state = Some(State {
            pos,
            face,
            vel: V3(0.0, 0.0, 0.0),
            speed: 0.0,
            clear_speed: 0.0,
            look,
            hidden: 0.0,
            visible: false,
            target_face: scene.face,
            target_prev: scene.t,
            outside_search: None,
            heading,
        });
        let visible = pos == scene.t_vis || self.sees_finally(g, face, pos, scene);
        if let Some(s) = self.state.as_mut() {
            s.visible = visible;
        }
        self.finish(pos, face, look, true, visible, scene.inside)
    }
}

/// The directions a cut tries from the target: a_n, turned ±45° and ±90°
/// about the vertical, and straight up.
fn cut_directions(a_n: V3) -> [V3; 6] {
    let turn = |deg: f64| {
        let (s, c) = deg.to_radians().sin_cos();
        V3(a_n.0 * c - a_n.1 * s, a_n.0 * s + a_n.1 * c, a_n.2)
    };
    [
        a_n,
        turn(45.0),
        turn(-45.0),
        turn(90.0),
        turn(-90.0),
        V3(0.0, 0.0, 1.0),
    ]
}
