//! Cuts: the camera jumps instead of moving (the first frame, a
//! teleported target, a target hidden too long).

use super::motion::{CLAMP_TOL, MARGIN_SLACK};
use super::sight::STEP_EVALS;
use super::{Camera, Pose, Scene, State};
use crate::geom::V3;
use crate::query::CoverBudget;
use crate::read::Vdg;

impl Camera {
    /// A cut: puts the camera at the target (the thesis: c₀ = t) or, with
    /// [`CameraParams::cut_to_ideal`](super::CameraParams::cut_to_ideal), as far towards the ideal position as
    /// the volume allows along a few directions around a_n.
    pub(super) fn cut(&mut self, g: &Vdg<'_>, scene: &Scene, heading: V3) -> Pose {
        // A cut starts afresh: d_μ for the room where the target is now,
        // and the way to him measured again.
        let scene = &Scene {
            d_mu: self.distance_mu_at(scene.target_room),
            out_of_reach: false,
            ..*scene
        };
        let (start, start_face, start_clear) = if self.params.cut_to_ideal {
            self.roomy_start(g, scene)
        } else {
            (
                scene.t_vis,
                scene.face,
                self.faces.fc(g, scene.face, scene.t_vis),
            )
        };
        let (mut pos, mut face) = (start, start_face);
        if self.params.cut_to_ideal {
            let margin = self.margin_at(start_clear);
            let d_mu = scene.d_mu;
            let mut best = f64::INFINITY;
            for dir in cut_directions(scene.a_n) {
                let goal = start + dir * d_mu;
                let a = g.advance_tol(
                    start_face,
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
                    STEP_EVALS,
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
            acc: V3(0.0, 0.0, 0.0),
            speed: 0.0,
            clear_speed: 0.0,
            look,
            hidden: 0.0,
            visible: false,
            unreachable: false,
            target_face: scene.face,
            target_prev: scene.t,
            outside_search: None,
            heading,
            d_mu: scene.d_mu,
            brake_speed: scene.target_speed,
            goal: pos,
            recent_target_speed: scene.target_speed,
        });
        let visible = pos == scene.t_vis || self.sees_finally(g, face, pos, scene);
        if let Some(s) = self.state.as_mut() {
            s.visible = visible;
        }
        self.finish(pos, face, look, true, visible, scene.inside)
    }
}

/// Edges a cut's start climbs from the target's face towards more clearance.
const CLIMB_STEPS: usize = 64;

impl Camera {
    /// Where a cut starts: the target's eye (or the volume point nearest it) when the
    /// camera has room there — clearance at least the near-plane margin — else the
    /// graph vertex with that room nearest on the way up the clearance from the
    /// target's face (its vertex of most clearance, then each time the neighbour of
    /// most clearance), else the vertex with that room nearest the target anywhere.
    /// A cut then moves from the start with the full margin, and a step never ends
    /// below the margin from a place above it, so the camera is never placed closer to
    /// a wall than the margin (where the graph has such room at all): a cut from a
    /// target on a ladder or in a vent used to start inside the margin and keep the
    /// near plane in the wall until the camera had climbed out.
    /// Returns the start, its face and its clearance.
    fn roomy_start(&self, g: &Vdg<'_>, scene: &Scene) -> (V3, u32, f64) {
        let here = (
            scene.t_vis,
            scene.face,
            self.faces.fc(g, scene.face, scene.t_vis),
        );
        let need = f64::from(self.params.near_margin) + MARGIN_SLACK;
        if here.2 >= need || self.params.near_margin <= 0.0 {
            return here;
        }
        let room = |v: u32| f64::from(g.vertices[v as usize].clearance);
        let mut v = g.face(scene.face)[0];
        for u in g.face(scene.face) {
            if room(u) > room(v) || (room(u) == room(v) && u < v) {
                v = u;
            }
        }
        for _ in 0..CLIMB_STEPS {
            if room(v) >= need {
                break;
            }
            let mut next = v;
            for u in g.vertex_neighbours(v) {
                if room(u) > room(next) {
                    next = u;
                }
            }
            if next == v {
                break;
            }
            v = next;
        }
        if room(v) < need {
            // A local top of the clearance without room (a vent, a ladder shaft):
            // the roomy vertex nearest the target, over the whole graph (a cut is rare).
            let mut best: Option<(f64, u32)> = None;
            for u in 0..g.vertex_count() as u32 {
                if room(u) >= need {
                    let d = (g.pos(u) - scene.t).norm();
                    if best.is_none_or(|b| d < b.0) {
                        best = Some((d, u));
                    }
                }
            }
            match best {
                Some((_, u)) => v = u,
                None => return here,
            }
        }
        let p = g.pos(v);
        let mut best: Option<(u32, f64)> = None;
        for f in g.vertex_faces(v) {
            let c = self.faces.fc(g, f, p);
            if best.is_none_or(|b| c > b.1) {
                best = Some((f, c));
            }
        }
        match best {
            Some((f, c)) if c > here.2 => (p, f, c),
            _ => here,
        }
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
