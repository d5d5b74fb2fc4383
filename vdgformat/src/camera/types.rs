//! The camera's inputs and outputs (the target, the pose, the debug view)
//! and what it keeps between and within frames: the configuration c_i =
//! (position, motion, speed) and the frame's view of the target.

use super::{CandidateKind, Costs};
use crate::geom::V3;
use crate::read::Vdg;

/// What the camera follows, in world units (Quake: z up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// The point to keep in view: best the player's eye (in Half-Life the
    /// origin + view offset, 28 standing and 12 crouched), the point a
    /// spectator looks at and the chase cam pivots on. Given the origin,
    /// [`CameraParams::target_height`](super::CameraParams::target_height) adds a constant height instead.
    pub position: [f32; 3],
    /// Where the target looks / moves (need not be unit length; a zero
    /// vector keeps the previous heading).
    pub heading: [f32; 3],
    /// The target's velocity (units/s); informational for now.
    pub velocity: [f32; 3],
}

impl Target {
    /// A target from its parts.
    pub fn new(position: [f32; 3], heading: [f32; 3], velocity: [f32; 3]) -> Target {
        Target {
            position,
            heading,
            velocity,
        }
    }

    /// A target from Quake view angles `[pitch, yaw, roll]` in degrees
    /// (`pitch` positive looking down, as in `cl.viewangles`), the form an
    /// engine has at hand.
    ///
    /// ```
    /// let t = vdgformat::camera::Target::from_angles([0.0; 3], [0.0, 90.0, 0.0], [0.0; 3]);
    /// assert!(t.heading[0].abs() < 1e-6 && (t.heading[1] - 1.0).abs() < 1e-6);
    /// ```
    pub fn from_angles(position: [f32; 3], angles: [f32; 3], velocity: [f32; 3]) -> Target {
        let (pitch, yaw) = (
            f64::from(angles[0]).to_radians(),
            f64::from(angles[1]).to_radians(),
        );
        let heading = [
            (pitch.cos() * yaw.cos()) as f32,
            (pitch.cos() * yaw.sin()) as f32,
            (-pitch.sin()) as f32,
        ];
        Target {
            position,
            heading,
            velocity,
        }
    }

    pub(super) fn is_finite(&self) -> bool {
        self.position
            .iter()
            .chain(&self.heading)
            .chain(&self.velocity)
            .all(|c| c.is_finite())
    }
}

/// How the last update went.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Status {
    /// Normal tracking.
    #[default]
    Following,
    /// The target stands outside Volume(VDG) — the graph does not describe
    /// the free space there. The camera follows the nearest part of the
    /// volume towards it; visibility is judged to that point.
    TargetOutside,
    /// The input was unusable (NaN or infinite coordinates, negative or NaN
    /// `dt`): the previous pose is returned unchanged.
    Held,
    /// The graph has no faces: the eye is put on the target.
    NoGraph,
}

/// The camera's output for one frame. Angles follow Quake's `viewangles`
/// (degrees, z up, yaw counter-clockwise from +x, pitch positive looking
/// down), ready for `V_CalcRefdef`'s `vieworg`/`viewangles`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Pose {
    /// The camera position.
    pub eye: [f32; 3],
    /// The point the camera looks at.
    pub look_at: [f32; 3],
    /// Yaw in degrees, (−180, 180].
    pub yaw: f32,
    /// Pitch in degrees, positive looking down.
    pub pitch: f32,
    /// The face whose volume holds the eye (`None` without a graph).
    pub face: Option<u32>,
    /// The camera cut (jumped) this frame: reset, teleported target, the
    /// target hidden for longer than [`CameraParams::cut_after`](super::CameraParams::cut_after), or
    /// hidden and out of the camera's reach for longer than
    /// [`CameraParams::cut_unreachable_after`](super::CameraParams::cut_unreachable_after).
    pub cut: bool,
    /// The graph proves a clear line from the eye to the target (to the
    /// nearest volume point towards it when [`Status::TargetOutside`]).
    pub target_visible: bool,
    /// How the update went.
    pub status: Status,
}

impl Pose {
    /// `[pitch, yaw, roll]` in degrees, Quake's `viewangles` layout.
    pub fn angles(&self) -> [f32; 3] {
        [self.pitch, self.yaw, 0.0]
    }
}

/// One candidate of the last frame.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct CandidateDebug {
    pub kind: CandidateKind,
    /// Where the criterion wanted the camera.
    pub wanted: [f32; 3],
    /// After clamping into the free volume.
    pub pos: [f32; 3],
    /// Whether the target is visible from `pos`.
    pub visible: bool,
    pub costs: Costs,
}

/// What the last update looked at: its candidates with their costs, the
/// choice, and the step.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrameDebug {
    pub(super) candidates: [CandidateDebug; 8],
    pub(super) count: usize,
    /// Index of the chosen candidate in [`FrameDebug::candidates`].
    pub best: usize,
    /// The costs at the camera's position before the step.
    pub current: Costs,
    /// Number of vertices in Reachable(P(c_i), f_i).
    pub reachable: u32,
    /// The commanded speed (units/s) and the distance actually moved.
    pub speed: f32,
    pub moved: f32,
    /// Whether the volume's boundary changed the step: stopped or turned
    /// it, or pushed its end back out of the near-plane margin. The
    /// motion's smoothness bounds (`max_jerk`, the lags) hold for the moves
    /// it left alone.
    pub blocked: bool,
    /// Line-of-sight tests made (the dominant cost of an update).
    pub visibility_tests: u32,
    /// Vertices the distance field settled for this update's VDistances.
    pub field_settled: u32,
}

impl FrameDebug {
    /// The candidates evaluated in the last update (empty after a cut or a
    /// held frame).
    pub fn candidates(&self) -> &[CandidateDebug] {
        &self.candidates[..self.count]
    }
}

/// Identifies a graph well enough to notice that a camera was handed a
/// different one (a new map): the face indices it holds would be
/// meaningless there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct GraphKey {
    vertices: usize,
    faces: usize,
    data: usize,
    source_hash: u64,
}

impl GraphKey {
    pub(super) fn of(g: &Vdg<'_>) -> GraphKey {
        GraphKey {
            vertices: g.vertex_count(),
            faces: g.face_count(),
            data: g.vertices.as_ptr() as usize,
            source_hash: g.source_hash(),
        }
    }
}

/// The camera's configuration c_i = (position, motion, speed) and what it
/// remembers between frames.
#[derive(Clone, Copy, Debug)]
pub(super) struct State {
    pub(super) pos: V3,
    pub(super) face: u32,
    /// Direction of motion times speed.
    pub(super) vel: V3,
    /// The acceleration the last update commanded (units/s²).
    pub(super) acc: V3,
    /// The step rule's speed V(c_i).
    pub(super) speed: f64,
    /// The speed f_clear rates positions by.
    pub(super) clear_speed: f64,
    pub(super) look: V3,
    /// Seconds the target has been invisible (Δn_vis).
    pub(super) hidden: f64,
    /// Whether the target was visible at the end of the last update.
    pub(super) visible: bool,
    /// Whether, at the end of the last update, the target was hidden and
    /// out of the camera's reach (see
    /// [`CameraParams::cut_unreachable_after`](super::CameraParams::cut_unreachable_after)).
    pub(super) unreachable: bool,
    pub(super) target_face: u32,
    pub(super) target_prev: V3,
    /// Where the last global face search for an outside target ran.
    pub(super) outside_search: Option<V3>,
    pub(super) heading: V3,
    /// d_μ of the last update (see [`Scene::d_mu`]).
    pub(super) d_mu: f64,
    /// The target speed the brakes allowed for in the last update (see
    /// [`Scene::brake_speed`]).
    pub(super) brake_speed: f64,
    /// The point the camera headed for in the last update (see
    /// [`CameraParams::goal_tau`](super::CameraParams::goal_tau)).
    pub(super) goal: V3,
    /// [`Scene::recent_target_speed`] of the last update.
    pub(super) recent_target_speed: f64,
}

/// The target as this frame sees it.
#[derive(Clone, Copy, Debug)]
pub(super) struct Scene {
    /// The followed point (position + height).
    pub(super) t: V3,
    pub(super) face: u32,
    /// Where visibility is judged: `t`, or the nearest volume point towards
    /// it when the target is outside.
    pub(super) t_vis: V3,
    pub(super) inside: bool,
    /// The target's speed over the last update (units/s, capped at the
    /// camera's top speed; 0 on the first frame).
    pub(super) target_speed: f64,
    /// The target's speed as the camera's brakes allow for it: it rises
    /// with `target_speed` at once and falls with the camera's own
    /// reaction lag (`accel_tau`). A landing player loses his falling
    /// speed in one frame; braking for that at once threw the camera's
    /// velocity command down by as much, the largest jerk on a playtest.
    pub(super) brake_speed: f64,
    /// The fastest the target moved lately (units/s): this update's speed,
    /// or the last update's recent top speed forgotten with a time constant
    /// of one second when that is higher (see
    /// [`CameraParams::seen_speed_factor`](super::CameraParams::seen_speed_factor)).
    pub(super) recent_target_speed: f64,
    /// The ideal direction from the target to the camera (unit).
    pub(super) a_n: V3,
    pub(super) dt: f64,
    /// Where inertia carries the camera over the inertia horizon, and that
    /// horizon's length.
    pub(super) c_t: V3,
    pub(super) inertia_scale: f64,
    /// Where the camera stands before the step, and how far it may travel
    /// over the horizon: with [`CameraParams::inertia_step`](super::CameraParams::inertia_step) f_inertia rates
    /// the point a step towards a candidate reaches, not the candidate.
    pub(super) pos: V3,
    pub(super) inertia_reach: f64,
    pub(super) novis: f64,
    /// The target's face came from a global search this frame.
    pub(super) searched: bool,
    /// `t_vis` lies in the volume of `face` (with the visibility margin).
    pub(super) t_vis_in_face: bool,
    /// The graph's clearance at `t_vis`: the room the target has.
    pub(super) target_room: f64,
    /// d_μ of this frame: `distance_mu`, or less where the target has
    /// little room (`distance_room_factor`), followed with the lag
    /// `distance_room_tau`.
    pub(super) d_mu: f64,
    /// At the end of the last update the target was hidden and the
    /// distance field proved it out of the camera's reach (see
    /// [`State::unreachable`]): hidden places are then rated by their
    /// straight distance to the target, not by the way (see
    /// `Camera::vdistance`).
    pub(super) out_of_reach: bool,

    /// Where the target's motion takes it within
    /// [`CameraParams::sight_lead`](super::CameraParams::sight_lead) (in the volume), when it moves.
    pub(super) ahead: Option<Ahead>,
}

/// The point the candidates must also see (see [`Scene::ahead`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Ahead {
    pub(super) point: V3,
    pub(super) face: u32,
    /// Its distance from `t_vis` (a straight free segment).
    pub(super) lead: f64,
}
