//! The automatic camera of the thesis (ch. 5, 6.2): it follows a target
//! through the VDG, keeps it in view, never leaves Volume(VDG) (so never
//! enters a wall) and moves smoothly.
//!
//! Each update builds candidate positions near the optima of the criteria
//! (distance, angle, inertia, clearance, visibility, the best local vertex),
//! pulls them back into the free volume, recombines them once, picks the
//! cheapest and moves towards it at a speed that grows with the current cost
//! (thesis 5.2/5.3). `../shared/CAMERA.md` in the project restates the
//! algorithm and records our decisions where the thesis is silent; each
//! improvement beyond the thesis is a switch in [`CameraParams`], and
//! [`CameraParams::thesis`] turns them all off.
//!
//! The graph is borrowed per call, so one mapped file serves many cameras;
//! each camera owns its scratch memory and allocates nothing per frame once
//! warmed up on a graph (the thesis variant's A* excepted).
//!
//! ```
//! use vdgformat::camera::{Camera, CameraParams, Target};
//! # let mut b = vdgformat::VdgBuilder::new();
//! # let v: Vec<u32> = [[0.0, 0.0], [512.0, 0.0], [0.0, 512.0], [512.0, 512.0]]
//! #     .iter().map(|&[x, y]| b.add_vertex([x, y, 64.0], 64.0)).collect();
//! # b.add_face([v[0], v[1], v[2]]);
//! # b.add_face([v[1], v[3], v[2]]);
//! # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes()?)?;
//! let g = file.graph();
//! let mut camera = Camera::new(CameraParams::default())?;
//! let mut player = Target::new([100.0, 250.0, 60.0], [1.0, 0.0, 0.0], [200.0, 0.0, 0.0]);
//! camera.reset(&g, &player);
//! for _ in 0..120 {
//!     player.position[0] += 200.0 / 60.0;
//!     let pose = camera.update(&g, &player, 1.0 / 60.0);
//!     assert!(g.contains(pose.eye)); // never outside the free volume
//! }
//! let pose = camera.update(&g, &player, 1.0 / 60.0);
//! assert!(pose.target_visible && pose.eye[0] < player.position[0]); // behind the player
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod director;
mod params;

pub use director::{CameraId, Director, DirectorEvent};
pub use params::{CameraError, CameraParams};

use crate::geom::V3;
use crate::query::{CoverBudget, CoverHint, DistanceField, FaceCache, PathFinder};
use crate::read::Vdg;

/// What the camera follows, in world units (Quake: z up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Target {
    /// The point to keep in view: best the player's eye (in Half-Life the
    /// origin + view offset, 28 standing and 12 crouched), the point a
    /// spectator looks at and the chase cam pivots on. Given the origin,
    /// [`CameraParams::target_height`] adds a constant height instead.
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

    fn is_finite(&self) -> bool {
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
    /// The camera cut (jumped) this frame: reset, teleported target, or the
    /// target hidden for longer than [`CameraParams::cut_after`].
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

/// Which criterion a candidate stands for (thesis 5.2/5.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CandidateKind {
    /// The camera moved along target→camera to the ideal distance.
    #[default]
    Dist,
    /// The camera rotated about the target by a quarter of the way to a_n.
    Angle,
    /// Where inertia alone carries the camera.
    Inertia,
    /// The reachable vertex of least f_clear.
    Clear,
    /// The reachable vertex of least f_vis.
    Vis,
    /// The reachable vertex of least f_total.
    Neighb,
    /// Ours, while the target is hidden: a point further along the
    /// shortest way through the graph to the target (the distance field's
    /// descent from the reachable vertex nearest the target by VDistance).
    Path,
    /// The cost-weighted mean of the others.
    Comb,
}

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
    candidates: [CandidateDebug; 8],
    count: usize,
    /// Index of the chosen candidate in [`FrameDebug::candidates`].
    pub best: usize,
    /// The costs at the camera's position before the step.
    pub current: Costs,
    /// Number of vertices in Reachable(P(c_i), f_i).
    pub reachable: u32,
    /// The commanded speed (units/s) and the distance actually moved.
    pub speed: f32,
    pub moved: f32,
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
struct GraphKey {
    vertices: usize,
    faces: usize,
    data: usize,
    source_hash: u64,
}

impl GraphKey {
    fn of(g: &Vdg<'_>) -> GraphKey {
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
struct State {
    pos: V3,
    face: u32,
    /// Direction of motion times speed.
    vel: V3,
    /// The step rule's speed V(c_i).
    speed: f64,
    /// The speed f_clear rates positions by.
    clear_speed: f64,
    look: V3,
    /// Seconds the target has been invisible (Δn_vis).
    hidden: f64,
    /// Whether the target was visible at the end of the last update.
    visible: bool,
    target_face: u32,
    target_prev: V3,
    /// Where the last global face search for an outside target ran.
    outside_search: Option<V3>,
    heading: V3,
}

/// The target as this frame sees it.
#[derive(Clone, Copy, Debug)]
struct Scene {
    /// The followed point (position + height).
    t: V3,
    face: u32,
    /// Where visibility is judged: `t`, or the nearest volume point towards
    /// it when the target is outside.
    t_vis: V3,
    inside: bool,
    /// The target's speed over the last update (units/s, capped at the
    /// camera's top speed; 0 on the first frame).
    target_speed: f64,
    /// The ideal direction from the target to the camera (unit).
    a_n: V3,
    dt: f64,
    /// Where inertia carries the camera over the inertia horizon, and that
    /// horizon's length.
    c_t: V3,
    inertia_scale: f64,
    /// Where the camera stands before the step, and how far it may travel
    /// over the horizon: with [`CameraParams::inertia_step`] f_inertia rates
    /// the point a step towards a candidate reaches, not the candidate.
    pos: V3,
    inertia_reach: f64,
    novis: f64,
    /// The target's face came from a global search this frame.
    searched: bool,
    /// `t_vis` lies in the volume of `face` (with the visibility margin).
    t_vis_in_face: bool,
}

/// Scratch for the reachable vertices of one frame (sized once per graph).
#[derive(Debug, Default)]
struct Scratch {
    reach: Vec<u32>,
    /// (sort key, index into `reach`).
    order: Vec<(f64, u32)>,
    /// Per reachable vertex: cost terms without visibility, VDistance, and
    /// visibility (-1 unknown, 0 no, 1 yes).
    base: Vec<f64>,
    vd: Vec<f64>,
    vis: Vec<i8>,
    /// Per graph vertex: the last line-of-sight answer to the target and
    /// where the target was then (see [`CameraParams::vertex_tests`]).
    memo: Vec<VisMemo>,
    /// Fresh vertex tests left in this update.
    fresh_left: u32,
}

/// A remembered Visible(P(v), t).
#[derive(Clone, Copy, Debug, Default)]
struct VisMemo {
    target: [f32; 3],
    visible: bool,
    known: bool,
}

/// A vertex's remembered answer is reused without a test while the target
/// stays this close (units) to where it was tested: about four frames of
/// running at 60 Hz, two at 30 Hz.
const MEMO_FRESH: f64 = 16.0;

/// Past this distance (units) from where it was tested, a remembered answer
/// says nothing (a teleport, a long gap): the vertex counts as unknown
/// when the update's fresh tests are spent.
const MEMO_STALE: f64 = 64.0;

/// An automatic camera following one target (thesis ch. 5). `Send`, owns
/// its scratch memory; the graph is passed to every call.
#[derive(Debug)]
pub struct Camera {
    params: CameraParams,
    graph: Option<GraphKey>,
    state: Option<State>,
    field: DistanceField,
    finder: PathFinder,
    scratch: Scratch,
    debug: FrameDebug,
    last: Pose,
    /// What the candidates' sight-line tests may still spend in this
    /// update.
    sight_budget: CoverBudget,
    /// Tree-leaf searches the candidates' clamps may still make.
    clamp_leaf_searches: u32,
    /// The way each candidate's sight line (by position in the frame's
    /// list, which follows the kinds) and the pose's took last frame.
    hints: [CoverHint; 9],
    /// The same for the sight lines of recently tested vertices.
    vertex_hints: VertexHints,
    /// The way each candidate's clamp took last frame.
    clamp_hints: [CoverHint; 8],
    /// What the camera keeps about the graph's faces (boxes, recent
    /// clearance functions), for cheaper sight lines and clamps.
    faces: FaceCache,
}

/// Which remembered sight line a test continues.
#[derive(Clone, Copy, Debug)]
enum Slot {
    /// A candidate's (by its index in the frame) or the pose's.
    Line(usize),
    /// A reachable vertex's.
    Vertex(u32),
}

/// Hints for the sight lines of the last few vertices tested (the
/// reachable set changes slowly), replaced oldest first.
#[derive(Clone, Debug)]
struct VertexHints {
    vertices: [u32; VERTEX_HINTS],
    hints: [CoverHint; VERTEX_HINTS],
    next: usize,
}

const VERTEX_HINTS: usize = 32;

impl Default for VertexHints {
    fn default() -> Self {
        VertexHints {
            vertices: [u32::MAX; VERTEX_HINTS],
            hints: [CoverHint::default(); VERTEX_HINTS],
            next: 0,
        }
    }
}

impl VertexHints {
    /// The hint of vertex `v`, a fresh one if it has none.
    fn get(&mut self, v: u32) -> &mut CoverHint {
        let i = match self.vertices.iter().position(|&u| u == v) {
            Some(i) => i,
            None => {
                let i = self.next;
                self.next = (i + 1) % VERTEX_HINTS;
                self.vertices[i] = v;
                self.hints[i] = CoverHint::default();
                i
            }
        };
        &mut self.hints[i]
    }
}

/// Clearance the step may lose when the camera starts inside the
/// near-plane margin (more than the trace's own margin, so it can always
/// move, towards more room).
const MARGIN_SLACK: f64 = 0.02;

/// Clearance a point needs to count as inside a face volume in the camera's
/// one-face visibility shortcut (the line-of-sight certificate's margin).
const INSIDE: f64 = 1e-4;

/// The distance field is steered towards the camera: the questions of one
/// update come from within about this radius of it (its reachable vertices
/// and clamped candidates).
const FIELD_RADIUS: f32 = 48.0;

/// How close (units) the camera's clamps and steps go to the boundary of
/// the volume they are certified in.
const CLAMP_TOL: f64 = 0.125;

/// A line of sight crossing more face volumes than this counts as blocked
/// (a camera's sight lines span a few faces; the bound caps the worst case
/// of an update).
const VISIBILITY_HOPS: u32 = 48;

/// The hint slot of the pose's own sight line (after the 7 candidates').
const POSE_HINT: usize = 8;

/// Vertices the camera's distance field may settle per update.
const FIELD_BUDGET: u32 = 8192;

/// Edges the pursuit candidate's descent may follow (bounds its cost).
const PURSUIT_STEPS: usize = 8;

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
        let dt = f64::from(dt.min(self.params.max_dt));
        let t = V3::from_f32(target.position) + V3(0.0, 0.0, f64::from(self.params.target_height));
        let heading = self.heading(target);
        let Some(state) = self.state else {
            let scene = self.scene(g, t, heading, g.faces.len() as u32, None, dt);
            return self.cut(g, &scene, heading);
        };
        let scene = self.scene(g, t, heading, state.target_face, Some(&state), dt);
        let teleported = (t - state.target_prev).norm() > f64::from(self.params.teleport_distance);
        let lost = state.hidden > f64::from(self.params.cut_after);
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

    /// The target's heading as a unit vector, with the pitch weighted by
    /// [`CameraParams::heading_pitch_weight`]; a zero heading keeps the
    /// last one.
    fn heading(&self, target: &Target) -> V3 {
        let h = V3::from_f32(target.heading);
        let horiz = (h.0 * h.0 + h.1 * h.1).sqrt();
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
        V3(
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            pitch.sin(),
        )
    }

    /// Locates the target in the graph and derives the frame's fixed terms.
    fn scene(
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
        let pitch = heading
            .2
            .atan2((heading.0 * heading.0 + heading.1 * heading.1).sqrt())
            + f64::from(p.angle_mu_pitch_deg).to_radians();
        let a_n = V3(
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            pitch.sin(),
        );
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
        Scene {
            t,
            face,
            t_vis,
            inside,
            target_speed,
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
            t_vis_in_face: g.fc(face, t_vis) > INSIDE,
        }
    }

    /// The target's face: a local climb from last frame's face; when that
    /// ends outside the volume, the tree leaf at the target; when the target
    /// is outside the volume, a global search — repeated only after the
    /// target moved 32 units, so a target far outside costs a tree search
    /// now and then, not every frame. Returns (face, inside, searched).
    fn locate(&self, g: &Vdg<'_>, t: V3, hint: u32, state: Option<&State>) -> (u32, bool, bool) {
        if (hint as usize) < g.faces.len() {
            // Our variant keeps last frame's face while it holds the target
            // (any face holding it serves as the field's entry and the
            // visibility anchor); the thesis climbs to ρ(t)'s face.
            if !self.params.exact_reachable && g.fc(hint, t) > INSIDE {
                return (hint, true, false);
            }
            let (f, c) = g.climb(hint, t, 32);
            if c > 0.0 {
                return (f, true, false);
            }
            let leaf = g
                .leaf_faces_at(t)
                .iter()
                .map(|f| (f, g.fc_above(f, t, 0.0)))
                .fold((f, c), |a, b| if b.1 > a.1 { b } else { a });
            if leaf.1 > 0.0 {
                return (leaf.0, true, false);
            }
            if let Some(s) = state.and_then(|s| s.outside_search)
                && (s - t).norm() < 32.0
            {
                return (f, false, false);
            }
        }
        match g.nearest_face_f64(t) {
            Some((f, c)) => (f, c > 0.0, true),
            None => (0, false, true),
        }
    }

    /// The margin the camera keeps from the volume's boundary at `pos`:
    /// the near-plane margin, or a little less than the current clearance
    /// when the camera is already closer (so it can still move out).
    fn margin_at(&self, clearance: f64) -> f32 {
        let m = f64::from(self.params.near_margin);
        if clearance >= m + MARGIN_SLACK {
            m as f32
        } else {
            (clearance - MARGIN_SLACK).clamp(0.0, m) as f32
        }
    }

    /// A cut: puts the camera at the target (the thesis: c₀ = t) or, with
    /// [`CameraParams::cut_to_ideal`], as far towards the ideal position as
    /// the volume allows along a few directions around a_n.
    fn cut(&mut self, g: &Vdg<'_>, scene: &Scene, heading: V3) -> Pose {
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

    /// One regular frame: candidates, choice, step, face update.
    fn step(&mut self, g: &Vdg<'_>, scene: &Scene, mut s: State, heading: V3) -> Pose {
        s.target_face = scene.face;
        s.target_prev = scene.t;
        s.heading = heading;
        if scene.searched {
            s.outside_search = Some(scene.t);
        } else if scene.inside {
            s.outside_search = None;
        }
        if scene.dt <= 0.0 {
            // Re-aim only.
            self.state = Some(s);
            let visible = self.sees_finally(g, s.face, s.pos, scene);
            if let Some(st) = self.state.as_mut() {
                st.visible = visible;
            }
            return self.finish(s.pos, s.face, s.look, false, visible, scene.inside);
        }
        if self.params.distance_field {
            // Every VDistance of this update is asked near the camera.
            let near = s.pos.to_f32();
            let radius = FIELD_RADIUS;
            // Ways the camera cannot pass are no ways to the target.
            self.field
                .set_min_clearance(self.params.field_min_clearance);
            self.field
                .reset_towards(g, scene.face, scene.t.to_f32(), near, radius);
        }
        let here_clear = g.fc(s.face, s.pos);
        let margin = self.margin_at(here_clear);
        // The current position's visibility: last update's answer (the
        // target moved a few units since) in our variant, a trace in the
        // thesis'.
        let known = (self.params.max_substeps > 0).then_some(s.visible);
        let current = self.costs_at(
            g,
            scene,
            &s,
            s.pos,
            s.face,
            here_clear,
            known,
            Some(Slot::Line(POSE_HINT)),
        );
        let (best_pos, best_cost) = self.choose(g, scene, &s, margin);

        // Step rule (thesis 5.3), frac = 1 − e^(−Δt/τ).
        let frac = 1.0 - (-scene.dt / f64::from(self.params.speed_tau)).exp();
        let f_cur = f64::from(current.total);
        // The thesis' command (1 + V)·√f_total has the fixed point
        // √f/(1 − √f) below f = 1: a resting camera hardly moves until the
        // costs pass 1. Ours commands at least the target's own speed.
        let command = ((1.0 + s.speed) * f_cur.sqrt())
            .max(scene.target_speed * f64::from(self.params.target_speed_floor));
        let v = ((1.0 - frac) * s.speed + frac * command).min(f64::from(self.params.max_speed));
        let to_best = best_pos - s.pos;
        let dist_best = to_best.norm();
        // Arrive rather than overshoot: no faster than the camera can brake
        // to a stop at the best candidate (plus the target's own speed, which
        // moves that point on). Without it the command winds up to top speed
        // (f_clear grows with the speed it rates) and a camera behind a
        // player standing still hunted back and forth across the ideal.
        let v = if self.params.max_decel > 0.0 {
            v.min((2.0 * f64::from(self.params.max_decel) * dist_best).sqrt() + scene.target_speed)
        } else {
            v
        };
        let dir = if dist_best > 1e-9 {
            to_best * (1.0 / dist_best)
        } else {
            V3(0.0, 0.0, 0.0)
        };
        let (new_pos, new_face) = if self.params.max_substeps == 0 {
            // The thesis: one step inside Volume(f_i), then the best of f_i
            // and its neighbours.
            let p = s.pos + dir * (v * scene.dt).min(dist_best);
            let p = V3::from_f32(p.to_f32());
            let (f, _) = g.climb(s.face, p, 1);
            s.vel = dir * v;
            (p, f)
        } else {
            self.move_smoothly(
                g, scene, &mut s, best_pos, dir, dist_best, v, margin, here_clear,
            )
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
        s.look = if self.params.look_tau > 0.0 {
            let k = 1.0 - (-scene.dt / f64::from(self.params.look_tau)).exp();
            s.look + (scene.t - s.look) * k
        } else {
            scene.t
        };
        self.state = Some(s);
        self.debug.current = current;
        self.debug.field_settled = self.field.settled();
        self.debug.speed = v as f32;
        self.debug.moved = moved as f32;
        let _ = best_cost;
        self.finish(s.pos, s.face, s.look, false, visible, scene.inside)
    }

    /// Our step: the direction of motion follows the best candidate with a
    /// lag (frame-rate independent), the move may cross several faces, and
    /// a move the smoothed direction cannot make falls back to the straight
    /// line to the best candidate, which is free by construction.
    #[allow(clippy::too_many_arguments)]
    fn move_smoothly(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &mut State,
        best_pos: V3,
        dir: V3,
        dist_best: f64,
        v: f64,
        margin: f32,
        here_clear: f64,
    ) -> (V3, u32) {
        let hops = self.params.max_substeps;
        let desired = dir * v;
        let vel = if self.params.direction_tau > 0.0 {
            let k = 1.0 - (-scene.dt / f64::from(self.params.direction_tau)).exp();
            s.vel + (desired - s.vel) * k
        } else {
            desired
        };
        let mut step = vel * scene.dt;
        let len = step.norm();
        let mut allowed = (v * scene.dt).min(dist_best);
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
        );
        let (mut p, mut f) = (V3::from_f32(a.point), a.face);
        if !a.reached && self.params.slide {
            (p, f) = slide(g, &self.faces, p, f, s.pos + step, margin, hops);
        }
        if !a.reached {
            let left = allowed - (p - s.pos).norm();
            if left > 1e-6 {
                let goal = s.pos + dir * allowed;
                let b = g.advance_tol(
                    s.face,
                    from,
                    goal.to_f32(),
                    margin,
                    &mut budget.clone(),
                    CLAMP_TOL,
                    None,
                    Some(&self.faces),
                );
                let q = V3::from_f32(b.point);
                if (q - s.pos).norm() > (p - s.pos).norm() {
                    (p, f) = (q, b.face);
                }
            }
            let _ = best_pos;
        }
        // GetClosestFace: the face of largest clearance near the new point.
        let (mut f, new_clear) = g.climb(f, p, 4);
        // Inside the near-plane margin the camera may only gain room: the
        // relaxed margin lets a segment dip a little, never the end point
        // (or it would sink a little more every frame).
        let m = f64::from(self.params.near_margin);
        if new_clear < m && new_clear < here_clear {
            (p, f) = (s.pos, s.face);
        }
        s.vel = (p - s.pos) * (1.0 / scene.dt);
        (p, f)
    }

    /// Builds, clamps, recombines and rates the candidates (thesis 5.2,
    /// 5.3); returns the best position and its cost.
    fn choose(&mut self, g: &Vdg<'_>, scene: &Scene, s: &State, margin: f32) -> (V3, f64) {
        let d_mu = f64::from(self.params.distance_mu);
        let early_stop = f64::from(self.params.early_stop);
        let tc = s.pos - scene.t;
        let r = tc.norm();
        let u = if r > 1e-6 { tc * (1.0 / r) } else { scene.a_n };
        let k_dist = scene.t + u * d_mu;
        let k_angle = scene.t + slerp(u, scene.a_n, 0.25) * r;
        let k_inertia = s.pos + s.vel * scene.dt;
        let (k_clear, k_vis, k_neighb, k_path, reachable) = self.local_candidates(g, scene, s);
        self.debug.reachable = reachable;
        let wanted = [
            (CandidateKind::Dist, Some(k_dist)),
            (CandidateKind::Angle, Some(k_angle)),
            (CandidateKind::Inertia, Some(k_inertia)),
            (CandidateKind::Clear, Some(k_clear)),
            (CandidateKind::Vis, Some(k_vis)),
            (CandidateKind::Neighb, Some(k_neighb)),
            (CandidateKind::Path, k_path),
        ];
        let mut n = 0;
        let mut best = (s.pos, f64::INFINITY, 0usize);
        let (mut wsum, mut wpos) = (0.0, V3(0.0, 0.0, 0.0));
        let mut stop = false;
        // Candidates often clamp to the same point (a blocked line, one
        // vertex best by two criteria): each point's sight line is tested
        // once.
        let mut tested = [(V3(0.0, 0.0, 0.0), false); 8];
        let mut n_tested = 0;
        let mut rate = |this: &mut Self, pos: V3, face: u32, clear: f64, slot: usize| {
            let known = tested[..n_tested].iter().find(|e| e.0 == pos).map(|e| e.1);
            let costs = this.costs_at(g, scene, s, pos, face, clear, known, Some(Slot::Line(slot)));
            if known.is_none() && n_tested < tested.len() {
                tested[n_tested] = (pos, costs.vis == 0.0);
                n_tested += 1;
            }
            costs
        };
        for (kind, k) in wanted {
            let Some(k) = k else { continue };
            let (pos, face, clear) = self.clamp(g, s, k, margin, n);
            let costs = rate(self, pos, face, clear, n);
            let total = f64::from(costs.total);
            self.record(n, kind, k, pos, costs);
            if total < best.1 {
                best = (pos, total, n);
            }
            n += 1;
            if total < early_stop {
                stop = true;
                break;
            }
            let w = 1.0 / total.max(1e-12);
            wsum += w;
            wpos = wpos + pos * w;
        }
        if !stop && wsum > 0.0 {
            let k = wpos * (1.0 / wsum);
            let (pos, face, clear) = self.clamp(g, s, k, margin, n);
            let costs = rate(self, pos, face, clear, n);
            self.record(n, CandidateKind::Comb, k, pos, costs);
            if f64::from(costs.total) < best.1 {
                best = (pos, f64::from(costs.total), n);
            }
            n += 1;
        }
        self.debug.count = n;
        self.debug.best = best.2;
        (best.0, best.1)
    }

    fn record(&mut self, i: usize, kind: CandidateKind, wanted: V3, pos: V3, costs: Costs) {
        self.debug.candidates[i] = CandidateDebug {
            kind,
            wanted: wanted.to_f32(),
            pos: pos.to_f32(),
            visible: costs.vis == 0.0,
            costs,
        };
    }

    /// Pulls a candidate back into the solution space: the thesis' Trace in
    /// Volume(f_i), or our advance across faces with the near-plane margin.
    /// Returns the point, a face holding it and its clearance there.
    /// `slot` is the candidate's place in the frame's list: its clamp
    /// follows the way the same candidate's took last frame.
    fn clamp(&mut self, g: &Vdg<'_>, s: &State, k: V3, margin: f32, slot: usize) -> (V3, u32, f64) {
        let (p, f) = if self.params.max_substeps == 0 {
            (
                V3::from_f32(g.trace(s.face, s.pos.to_f32(), k.to_f32())),
                s.face,
            )
        } else {
            // Candidates share the update's allowance of leaf searches
            // for their clamps (as their sight lines do).
            let mut budget = CoverBudget {
                hops: self.params.max_substeps,
                leaf_searches: self.clamp_leaf_searches,
            };
            let a = g.advance_tol(
                s.face,
                s.pos.to_f32(),
                k.to_f32(),
                margin,
                &mut budget,
                CLAMP_TOL,
                Some(&mut self.clamp_hints[slot]),
                Some(&self.faces),
            );
            self.clamp_leaf_searches = budget.leaf_searches;
            (V3::from_f32(a.point), a.face)
        };
        (p, f, g.fc(f, p))
    }

    /// k_clear, k_vis and k_neighb: the best vertices of
    /// Reachable(P(c_i), f_i) by f_clear, f_vis and f_total. Visibility is
    /// the expensive term, so it is tested lazily: k_vis is the first
    /// visible vertex in order of VDistance (all visible vertices cost 0;
    /// the nearest by VDistance breaks the tie), k_neighb a branch and bound
    /// over the cost without visibility (a lower bound).
    #[allow(clippy::type_complexity)]
    fn local_candidates(
        &mut self,
        g: &Vdg<'_>,
        scene: &Scene,
        s: &State,
    ) -> (V3, V3, V3, Option<V3>, u32) {
        let mut sc = std::mem::take(&mut self.scratch);
        sc.reach.clear();
        // The thesis' exact Reachable, or (ours) the vertices reachable
        // within one face volume: the candidates are clamped into the free
        // volume anyway, and the exact set costs most of an update.
        let exact = self.params.exact_reachable;
        g.for_each_local_vertex(s.pos.to_f32(), s.face, exact, |v| sc.reach.push(v));
        let n = sc.reach.len();
        if n == 0 {
            self.scratch = sc;
            return (s.pos, s.pos, s.pos, None, 0);
        }
        sc.base.clear();
        sc.vd.clear();
        sc.vis.clear();
        sc.fresh_left = self.params.vertex_tests;
        let (mut k_clear, mut best_clear) = (sc.reach[0], f64::INFINITY);
        for &v in &sc.reach {
            let pv = g.pos(v);
            let r = f64::from(g.vertices[v as usize].clearance);
            let clear = self.clear_cost(s, r);
            let base = self.dist_cost(scene, pv)
                + self.angle_cost(scene, pv)
                + self.inertia_cost(scene, pv)
                + clear;
            sc.base.push(base);
            sc.vd.push(f64::NAN);
            sc.vis.push(-1);
            if clear < best_clear {
                (k_clear, best_clear) = (v, clear);
            }
        }
        // k_vis: every visible vertex costs 0; the thesis leaves the tie
        // open, we take the one nearest the target (no VDistance needed).
        // Only when none is visible, the least VDistance.
        sc.order.clear();
        sc.order
            .extend((0..n).map(|i| ((g.pos(sc.reach[i]) - scene.t).norm(), i as u32)));
        sc.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut k_vis = None;
        for j in 0..n {
            let i = sc.order[j].1 as usize;
            if self.vertex_visible(g, scene, &mut sc, i) {
                k_vis = Some(sc.reach[i]);
                break;
            }
        }
        let nearest_by_vd = |this: &mut Self, sc: &mut Scratch| {
            let mut best = (f64::INFINITY, sc.reach[0]);
            for i in 0..n {
                let d = this.vertex_vd(g, scene, sc, i);
                if d < best.0 {
                    best = (d, sc.reach[i]);
                }
            }
            best.1
        };
        let k_vis = match k_vis {
            Some(v) => v,
            None => nearest_by_vd(self, &mut sc),
        };
        // k_path: only while the target is hidden (a visible target is
        // best served by the local candidates) and the field exists.
        let k_path = (self.params.pursuit_length > 0.0 && !s.visible && self.params.distance_field)
            .then(|| {
                let from = nearest_by_vd(self, &mut sc);
                self.descend(g, from)
            });
        // k_neighb: branch and bound on the cost without visibility, a
        // lower bound; VDistance only for hidden vertices.
        sc.order.clear();
        sc.order
            .extend((0..n).map(|i| (scene.novis * sc.base[i] / 5.0, i as u32)));
        sc.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let (mut k_neighb, mut best) = (sc.reach[sc.order[0].1 as usize], f64::INFINITY);
        for j in 0..n {
            let (lb, i) = (sc.order[j].0, sc.order[j].1 as usize);
            if lb >= best {
                break;
            }
            let vis = if self.vertex_visible(g, scene, &mut sc, i) {
                0.0
            } else {
                let d = self.vertex_vd(g, scene, &mut sc, i);
                self.vis_cost(d)
            };
            let total = vis / 5.0 + lb;
            if total < best {
                (k_neighb, best) = (sc.reach[i], total);
            }
        }
        self.scratch = sc;
        (
            g.pos(k_clear),
            g.pos(k_vis),
            g.pos(k_neighb),
            k_path,
            n as u32,
        )
    }

    /// The point [`CameraParams::pursuit_length`] along the distance
    /// field's descent from vertex `from` towards the target: each step to
    /// the settled neighbour through which the target is nearest, never to
    /// a vertex with less clearance than the near-plane margin (the camera
    /// could not pass it). Bounded by [`PURSUIT_STEPS`] edges.
    fn descend(&mut self, g: &Vdg<'_>, from: u32) -> V3 {
        let min_clear = self.params.near_margin + MARGIN_SLACK as f32;
        let mut v = from;
        let mut walked = 0.0f64;
        for _ in 0..PURSUIT_STEPS {
            let Some(dv) = self.field.settled_distance(v) else {
                break;
            };
            let pv = g.pos(v);
            let mut next: Option<(f32, u32, f64)> = None;
            for u in g.vertex_neighbours(v) {
                let Some(du) = self.field.settled_distance(u) else {
                    continue;
                };
                if du >= dv || g.vertices[u as usize].clearance < min_clear {
                    continue;
                }
                let edge = (g.pos(u) - pv).norm();
                let via = du + edge as f32;
                if next.is_none_or(|b| via < b.0 || (via == b.0 && u < b.1)) {
                    next = Some((via, u, edge));
                }
            }
            let Some((_, u, edge)) = next else { break };
            v = u;
            walked += edge;
            if walked >= f64::from(self.params.pursuit_length) {
                break;
            }
        }
        g.pos(v)
    }

    /// Visible(P(v), t) for the `i`-th reachable vertex: asked once per
    /// update, and with [`CameraParams::vertex_tests`] answered from the
    /// vertex's memo when the target has hardly moved since its last test
    /// or the update's fresh tests are spent (unknown counts as hidden).
    fn vertex_visible(&mut self, g: &Vdg<'_>, scene: &Scene, sc: &mut Scratch, i: usize) -> bool {
        if sc.vis[i] < 0 {
            let v = sc.reach[i];
            let ok = if self.params.vertex_tests == 0 {
                self.sees(
                    g,
                    g.vertex_faces(v).get(0),
                    g.pos(v),
                    scene,
                    Some(Slot::Vertex(v)),
                )
            } else {
                let memo = sc.memo[v as usize];
                let moved = (V3::from_f32(memo.target) - scene.t_vis).norm();
                if memo.known && moved < MEMO_FRESH {
                    memo.visible
                } else if sc.fresh_left > 0 {
                    sc.fresh_left -= 1;
                    let ok = self.sees(
                        g,
                        g.vertex_faces(v).get(0),
                        g.pos(v),
                        scene,
                        Some(Slot::Vertex(v)),
                    );
                    sc.memo[v as usize] = VisMemo {
                        target: scene.t_vis.to_f32(),
                        visible: ok,
                        known: true,
                    };
                    ok
                } else {
                    memo.known && moved < MEMO_STALE && memo.visible
                }
            };
            sc.vis[i] = i8::from(ok);
        }
        sc.vis[i] == 1
    }

    /// VDistance(P(v), t) for the `i`-th reachable vertex, computed once
    /// per update and only when asked.
    fn vertex_vd(&mut self, g: &Vdg<'_>, scene: &Scene, sc: &mut Scratch, i: usize) -> f64 {
        if sc.vd[i].is_nan() {
            let v = sc.reach[i];
            sc.vd[i] = self.vdistance(g, scene, g.vertex_faces(v).get(0), g.pos(v));
        }
        sc.vd[i]
    }

    /// All cost terms at `k` (in face `face` with clearance `clear`).
    #[allow(clippy::too_many_arguments)]
    fn costs_at(
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
        let clear = self.clear_cost(s, clear);
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
    /// A* per call. Unreachable: a large finite value, so costs stay
    /// comparable.
    fn vdistance(&mut self, g: &Vdg<'_>, scene: &Scene, face: u32, k: V3) -> f64 {
        let d = if self.params.distance_field {
            f64::from(self.field.vdistance(g, face, k.to_f32()))
        } else {
            self.finder
                .path_between_faces(g, face, k.to_f32(), scene.face, scene.t.to_f32())
                .map_or(f64::INFINITY, |p| f64::from(p.length))
        };
        if d.is_finite() { d } else { 1e6 }
    }

    /// Visible(k, t) from face `face` (counted in the debug view). When
    /// `k` lies in the volume of the target's face, which holds `t` too,
    /// the segment does (the volume is convex): one evaluation instead of a
    /// trace.
    ///
    /// The test's hops and tree-leaf searches come out of the update's
    /// allowance ([`CameraParams::sight_hops`], [`CameraParams::leaf_searches`]);
    /// the pose's own test, [`Camera::sees_finally`], has one of its own.
    ///
    /// `slot` names a sight line the camera tests again and again (a
    /// candidate kind, the pose, a reachable vertex): its [`CoverHint`]
    /// from the last time guides the test.
    fn sees(&mut self, g: &Vdg<'_>, face: u32, k: V3, scene: &Scene, slot: Option<Slot>) -> bool {
        if scene.t_vis_in_face && g.fc(scene.face, k) > INSIDE {
            return true;
        }
        self.debug.visibility_tests += 1;
        let hops = self.sight_budget.hops.min(VISIBILITY_HOPS);
        let mut budget = CoverBudget {
            hops,
            leaf_searches: self.sight_budget.leaf_searches,
        };
        let hint = match slot {
            Some(Slot::Line(i)) => Some(&mut self.hints[i]),
            Some(Slot::Vertex(v)) => Some(self.vertex_hints.get(v)),
            None => None,
        };
        let seen = g.visible_hinted_cached(
            face,
            k.to_f32(),
            scene.t_vis.to_f32(),
            &mut budget,
            hint,
            Some(&self.faces),
        );
        self.sight_budget.hops -= hops - budget.hops;
        self.sight_budget.leaf_searches = budget.leaf_searches;
        seen
    }

    /// [`Camera::sees`] for the pose the update returns: `target_visible`
    /// and the hidden-time clock (which makes cuts) rest on it, so it does
    /// not share the candidates' allowance.
    fn sees_finally(&mut self, g: &Vdg<'_>, face: u32, k: V3, scene: &Scene) -> bool {
        self.sight_budget = CoverBudget {
            hops: VISIBILITY_HOPS,
            leaf_searches: self.params.leaf_searches,
        };
        self.sees(g, face, k, scene, Some(Slot::Line(POSE_HINT)))
    }

    fn vis_cost(&self, vd: f64) -> f64 {
        if self.params.normalized_visibility {
            (1.0 + vd / f64::from(self.params.distance_sigma)).powi(2)
        } else {
            1.0 + vd
        }
    }

    fn dist_cost(&self, scene: &Scene, k: V3) -> f64 {
        let p = &self.params;
        (((scene.t - k).norm() - f64::from(p.distance_mu)) / f64::from(p.distance_sigma)).powi(2)
    }

    fn angle_cost(&self, scene: &Scene, k: V3) -> f64 {
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
    /// corridor rated a candidate 54 units back towards a standing player as
    /// costly as a swerve, and drifted away from him).
    fn inertia_cost(&self, scene: &Scene, k: V3) -> f64 {
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

    fn clear_cost(&self, s: &State, clearance: f64) -> f64 {
        (s.clear_speed * f64::from(self.params.clearance_sigma) / clearance.max(1e-3)).powi(2)
    }

    fn finish(
        &mut self,
        eye: V3,
        face: u32,
        look: V3,
        cut: bool,
        visible: bool,
        inside: bool,
    ) -> Pose {
        let d = look - eye;
        let horiz = (d.0 * d.0 + d.1 * d.1).sqrt();
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

/// A point inside the volume of `face` as close to `t` as a straight line
/// from the triangle's centroid allows: where visibility is judged for a
/// target standing outside the volume.
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
    let Some(n) = inward_normal(g, f, p) else {
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
    let b = g.advance_tol(
        f,
        p.to_f32(),
        (p + along).to_f32(),
        margin,
        &mut CoverBudget {
            hops,
            leaf_searches: 0,
        },
        CLAMP_TOL,
        None,
        Some(faces),
    );
    (V3::from_f32(b.point), b.face)
}

/// The direction in which face `f`'s clearance grows fastest at `p` (the
/// volume boundary's inward normal near the boundary), by central
/// differences; `None` where it is flat.
fn inward_normal(g: &Vdg<'_>, f: u32, p: V3) -> Option<V3> {
    const H: f64 = 0.25;
    let d = |e: V3| g.fc(f, p + e) - g.fc(f, p - e);
    let n = V3(d(V3(H, 0.0, 0.0)), d(V3(0.0, H, 0.0)), d(V3(0.0, 0.0, H)));
    let len = n.norm();
    (len > 1e-9).then(|| n * (1.0 / len))
}

fn anchor(g: &Vdg<'_>, face: u32, t: V3) -> V3 {
    let [a, b, c] = g.faces.get(face).map(|v| g.pos(v));
    let centroid = (a + b + c) * (1.0 / 3.0);
    V3::from_f32(g.trace(face, centroid.to_f32(), t.to_f32()))
}

/// Rotates unit vector `u` towards unit vector `w` by `frac` of the angle
/// between them (about the axis `u × w`; for opposite vectors about z, or
/// x when they are vertical).
fn slerp(u: V3, w: V3, frac: f64) -> V3 {
    let cos = u.dot(w).clamp(-1.0, 1.0);
    let angle = cos.acos();
    if angle < 1e-9 {
        return u;
    }
    let mut axis = u.cross(w);
    if axis.norm() < 1e-9 {
        axis = if u.2.abs() < 0.9 {
            V3(0.0, 0.0, 1.0)
        } else {
            V3(1.0, 0.0, 0.0)
        };
        axis = axis - u * axis.dot(u);
    }
    let axis = axis * (1.0 / axis.norm());
    let (sin_t, cos_t) = (angle * frac).sin_cos();
    // Rodrigues' rotation of u about the axis (u ⟂ axis).
    u * cos_t + axis.cross(u) * sin_t
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

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_send<T: Send>() {}

    #[test]
    fn camera_and_director_are_send() {
        assert_send::<Camera>();
        assert_send::<Director>();
    }

    #[test]
    fn slerp_turns_by_the_fraction() {
        let u = V3(1.0, 0.0, 0.0);
        let w = V3(0.0, 1.0, 0.0);
        let q = slerp(u, w, 0.5);
        assert!((q.0 - q.1).abs() < 1e-12 && (q.norm() - 1.0).abs() < 1e-12);
        let opposite = slerp(u, V3(-1.0, 0.0, 0.0), 0.25);
        assert!((opposite.norm() - 1.0).abs() < 1e-12);
        assert!((opposite.0 - (std::f64::consts::FRAC_PI_4).cos()).abs() < 1e-12);
    }

    #[test]
    fn thesis_params_turn_every_improvement_off() {
        let t = CameraParams::thesis();
        assert_eq!(t.max_substeps, 0);
        assert!(!t.distance_field && !t.normalized_visibility && !t.cut_to_ideal);
        assert_eq!(
            (t.direction_tau, t.look_tau, t.near_margin),
            (0.0, 0.0, 0.0)
        );
        assert_eq!(t.inertia_horizon, 0.0);
        assert_eq!(
            (t.vertex_tests, t.sight_hops, t.leaf_searches),
            (0, u32::MAX, u32::MAX)
        );
        t.validate().unwrap();
    }
}
