//! The [`Camera`] and the course of one update: unusable input held, a
//! new graph noticed, the target located, then a cut or a regular step,
//! and the pose made from where the camera ended.

use super::scene::horizontal;
use super::sight::VertexHints;
use super::{
    CameraError, CameraParams, FrameDebug, GraphKey, Pose, Scratch, State, Status, Target, VisMemo,
};
use crate::geom::V3;
use crate::query::{CoverBudget, CoverHint, DistanceField, FaceCache, PathFinder};
use crate::read::Vdg;

/// An automatic camera following one target (thesis ch. 5). `Send`, owns
/// its scratch memory; the graph is passed to every call.
#[derive(Debug)]
pub struct Camera {
    pub(super) params: CameraParams,
    pub(super) graph: Option<GraphKey>,
    pub(super) state: Option<State>,
    pub(super) field: DistanceField,
    pub(super) finder: PathFinder,
    pub(super) scratch: Scratch,
    pub(super) debug: FrameDebug,
    pub(super) last: Pose,
    /// What the candidates' sight-line tests may still spend in this
    /// update.
    pub(super) sight_budget: CoverBudget,
    /// Tree-leaf searches the candidates' clamps may still make.
    pub(super) clamp_leaf_searches: u32,
    /// The way each candidate's sight line (by position in the frame's
    /// list, which follows the kinds) and the pose's took last frame.
    pub(super) hints: [CoverHint; 9],
    /// What the sight lines to the point ahead of the target (the
    /// candidates', then the pose's) may still spend in this update (an
    /// allowance of their own: they must not starve the tests to the
    /// target itself), and their ways.
    pub(super) ahead_budget: CoverBudget,
    pub(super) ahead_hints: [CoverHint; 9],
    /// The same for the sight lines of recently tested vertices.
    pub(super) vertex_hints: VertexHints,
    /// The way each candidate's clamp took last frame.
    pub(super) clamp_hints: [CoverHint; 8],
    /// What the camera keeps about the graph's faces (boxes, recent
    /// clearance functions), for cheaper sight lines and clamps.
    pub(super) faces: FaceCache,
}

/// Vertices the camera's distance field may settle per update.
const FIELD_BUDGET: u32 = 8192;

impl Camera {
    /// A camera with validated parameters. It is placed on the first
    /// [`Camera::update`] (or [`Camera::reset`]).
    pub fn new(params: CameraParams) -> Result<Camera, CameraError> {
        params.validate()?;
        Ok(Camera {
            params,
            graph: None,
            state: None,
            field: DistanceField::new(),
            finder: PathFinder::new(),
            scratch: Scratch::default(),
            debug: FrameDebug::default(),
            last: Pose::default(),
            sight_budget: CoverBudget {
                hops: 0,
                leaf_searches: 0,
            },
            clamp_leaf_searches: 0,
            hints: [CoverHint::default(); 9],
            ahead_budget: CoverBudget {
                hops: 0,
                leaf_searches: 0,
            },
            ahead_hints: [CoverHint::default(); 9],
            vertex_hints: VertexHints::default(),
            clamp_hints: [CoverHint::default(); 8],
            faces: FaceCache::default(),
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// Replaces the parameters (validated); the camera keeps its place.
    pub fn set_params(&mut self, params: CameraParams) -> Result<(), CameraError> {
        params.validate()?;
        self.params = params;
        Ok(())
    }

    /// The candidates and costs of the last update.
    pub fn debug(&self) -> &FrameDebug {
        &self.debug
    }

    /// The pose of the last update.
    pub fn last_pose(&self) -> &Pose {
        &self.last
    }

    /// Starts a new scene: places the camera for `target` (a cut) and
    /// returns that pose. Also sizes the scratch memory for `g`, so
    /// following updates on the same graph allocate nothing.
    pub fn reset(&mut self, g: &Vdg<'_>, target: &Target) -> Pose {
        self.state = None;
        self.update(g, target, 0.0)
    }

    /// Advances the camera by `dt` seconds towards the best view of
    /// `target` and returns the new pose.
    ///
    /// Behaviour at the edges: NaN/infinite input or a negative `dt` holds
    /// the previous pose ([`Status::Held`]); `dt == 0` re-aims without
    /// moving; a `dt` longer than [`CameraParams::max_dt`] moves as if it
    /// were that long; a target outside the graph's volume (however far) is
    /// followed via the nearest volume point ([`Status::TargetOutside`]); a
    /// different graph than last time (a new map) resets the camera (a cut);
    /// an empty graph puts the eye on the target ([`Status::NoGraph`]).
    pub fn update(&mut self, g: &Vdg<'_>, target: &Target, dt: f32) -> Pose {
        if !target.is_finite() || !dt.is_finite() || dt < 0.0 {
            return self.hold();
        }
        if g.face_count() == 0 {
            return self.no_graph(target);
        }
        let key = GraphKey::of(g);
        if self.graph != Some(key) {
            self.prepare(g);
            self.graph = Some(key);
            self.state = None;
        }
        self.debug = FrameDebug::default();
        self.sight_budget = CoverBudget {
            hops: self.params.sight_hops,
            leaf_searches: self.params.leaf_searches,
        };
        self.clamp_leaf_searches = self.params.leaf_searches;
        self.ahead_budget = self.sight_budget;
        let dt = f64::from(dt.min(self.params.max_dt));
        let t = V3::from_f32(target.position) + V3(0.0, 0.0, f64::from(self.params.target_height));
        let heading = self.heading(target);
        let Some(state) = self.state else {
            let scene = self.scene(g, t, heading, g.faces.len() as u32, None, dt);
            return self.cut(g, &scene, heading);
        };
        let scene = self.scene(g, t, heading, state.target_face, Some(&state), dt);
        let teleported = (t - state.target_prev).norm() > f64::from(self.params.teleport_distance);
        let lost = state.hidden > f64::from(self.params.cut_after)
            || (state.unreachable && state.hidden > f64::from(self.params.cut_unreachable_after));
        if teleported || lost {
            return self.cut(g, &scene, heading);
        }
        self.step(g, &scene, state, heading)
    }

    /// Sizes the scratch memory for a graph (once per graph).
    fn prepare(&mut self, g: &Vdg<'_>) {
        let max_degree = (0..g.vertex_count() as u32)
            .map(|v| g.vertex_neighbours(v).len())
            .max()
            .unwrap_or(0);
        let cap = 3 * max_degree + 3;
        let s = &mut self.scratch;
        for v in [&mut s.base, &mut s.vd] {
            v.clear();
            v.reserve(cap);
        }
        s.reach.clear();
        s.reach.reserve(cap);
        s.order.clear();
        s.order.reserve(cap);
        s.vis.clear();
        s.vis.reserve(cap);
        // Hints name faces of the old graph.
        self.hints = [CoverHint::default(); 9];
        self.ahead_hints = [CoverHint::default(); 9];
        self.vertex_hints = VertexHints::default();
        self.clamp_hints = [CoverHint::default(); 8];
        // Sized whatever `vertex_tests` says now: `set_params` may turn the
        // memo on later without a new graph.
        s.memo.clear();
        s.memo.resize(g.vertex_count(), VisMemo::default());
        self.field.reserve(g);
        self.faces.rebuild(g);
        // A target the camera cannot reach (cut off by gaps narrower than
        // `field_min_clearance`) would have the field settle its whole
        // component every update to prove it; past this budget distances
        // are lower bounds, which is all a cost needs.
        self.field.set_budget(FIELD_BUDGET);
    }

    fn hold(&mut self) -> Pose {
        let mut p = self.last;
        p.cut = false;
        p.status = Status::Held;
        self.last = p;
        p
    }

    fn no_graph(&mut self, target: &Target) -> Pose {
        let t = target.position;
        let eye = [t[0], t[1], t[2] + self.params.target_height];
        self.state = None;
        self.graph = None;
        self.last = Pose {
            eye,
            look_at: eye,
            yaw: self.last.yaw,
            pitch: self.last.pitch,
            face: None,
            cut: true,
            target_visible: false,
            status: Status::NoGraph,
        };
        self.last
    }

    pub(super) fn finish(
        &mut self,
        eye: V3,
        face: u32,
        look: V3,
        cut: bool,
        visible: bool,
        inside: bool,
    ) -> Pose {
        let d = look - eye;
        let horiz = horizontal(d);
        let (yaw, pitch) = if d.norm() > 1e-6 {
            (
                d.1.atan2(d.0).to_degrees(),
                (-d.2).atan2(horiz).to_degrees(),
            )
        } else {
            (f64::from(self.last.yaw), f64::from(self.last.pitch))
        };
        self.last = Pose {
            eye: eye.to_f32(),
            look_at: look.to_f32(),
            yaw: yaw as f32,
            pitch: pitch as f32,
            face: Some(face),
            cut,
            target_visible: visible,
            status: if inside {
                Status::Following
            } else {
                Status::TargetOutside
            },
        };
        self.last
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Director;

    fn assert_send<T: Send>() {}

    #[test]
    fn camera_and_director_are_send() {
        assert_send::<Camera>();
        assert_send::<Director>();
    }
}
