//! The camera's constraints (thesis 5.1: optimum μ and tolerance σ per
//! criterion) and the switches between the thesis' algorithm and ours.

/// Everything that shapes a camera's behaviour. Every cost is a variant of
/// `((x − μ)/σ)²`: there are no separate weights, a smaller σ makes a
/// criterion matter more (thesis 5.1). Units are Quake units and seconds.
///
/// [`CameraParams::default`] is our improved camera; [`CameraParams::thesis`]
/// the thesis' algorithm as printed (the switches under "beyond the thesis"
/// off), so the two can be measured side by side. With the feature
/// `camera-toml` (on by default) any subset of fields can be loaded from
/// TOML; missing fields keep their default:
///
/// ```
/// # #[cfg(feature = "camera-toml")] {
/// use vdgformat::camera::CameraParams;
/// let p = CameraParams::from_toml_str("distance_mu = 96.0\nangle_sigma_deg = 45.0")?;
/// assert_eq!(p.distance_mu, 96.0);
/// assert_eq!(p.inertia_sigma, CameraParams::default().inertia_sigma);
/// assert!(CameraParams::from_toml_str("distance_mu = -1.0").is_err());
/// # }
/// # Ok::<(), vdgformat::camera::CameraError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "camera-toml",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct CameraParams {
    /// d_μ: the ideal distance to the target. 80, closer than Half-Life's
    /// chase cam (`cl_chasedist` 112): a camera that may not pass through
    /// walls loses the player round every corner it trails far behind, and
    /// in the camera replay over many maps 80 kept the player in view more
    /// often than 112 did, at the same jerk.
    pub distance_mu: f32,
    /// d_σ: distance tolerance. 48 (about a player's width and a half) lets
    /// the camera come in to 32 or back off to 128 at cost 1.
    pub distance_sigma: f32,
    /// a_μ azimuth: the ideal direction from the target to the camera,
    /// relative to the target's heading, in degrees. 180 = behind.
    pub angle_mu_yaw_deg: f32,
    /// a_μ elevation above the horizon in degrees. 15° looks slightly down
    /// on the player, over low cover, without losing the horizon.
    pub angle_mu_pitch_deg: f32,
    /// a_σ in degrees, in (0, 180]. 60° lets the camera swing a third of the
    /// way round the player before the angle costs as much as the others.
    pub angle_sigma_deg: f32,
    /// How much of the target's pitch turns a_n (0 = heading's yaw only,
    /// 1 = the thesis' full `Angles(t) + a_μ`). Players look up and down far
    /// more than they move that way; following the full pitch sends the
    /// camera to the ceiling when they look down. Default 0.
    pub heading_pitch_weight: f32,
    /// i_σ: the allowed deviation from where inertia would carry the camera,
    /// as a fraction of its travel (the thesis' example value 0.5).
    pub inertia_sigma: f32,
    /// Floor on the camera speed in f_inertia's denominator (units/s), so a
    /// resting camera's inertia cost stays finite (the thesis divides by the
    /// camera's own travel, which is 0 at rest). 128 u/s, half a run: with
    /// 32 (a slow walk) the allowed deviation was 4 units, and a slow camera
    /// behind a player standing still was held on its course by inertia
    /// and drifted past the player.
    pub inertia_min_speed: f32,
    /// Time over which f_inertia compares positions (s). The thesis uses the
    /// frame time Δt, which makes the cost depend on the frame rate (four
    /// times larger at 60 Hz than at 30 Hz for the same motion); 0.25 s
    /// compares where the camera would be a quarter second ahead instead.
    /// 0 means "use Δt" (the thesis).
    pub inertia_horizon: f32,
    /// f_inertia rates where a step towards a candidate gets over the
    /// horizon (at the speed that sets its denominator), not the candidate
    /// itself. The thesis compares positions, so a slow camera in a narrow
    /// corridor rated a candidate a few dozen units back towards a player
    /// who had stopped as costly as a swerve and drifted away from him, out
    /// of sight round the corner (bsp2vdg's `tests/camera_maps.rs`, the L
    /// corridor reduced without the floor). In the camera replay it left
    /// visibility about as it was and shortened the longest occlusions
    /// (`CAMERA.md`). `false` = the thesis.
    pub inertia_step: bool,
    /// p_σ: "room for p_σ seconds at the current speed" (f_clear). 0.5 s.
    pub clearance_sigma: f32,
    /// v_σ: how long the target may stay hidden before invisibility
    /// dominates everything (f_novis). The thesis gives 1–2 s; 1.5 s.
    pub visibility_sigma: f32,
    /// Hidden this long (s), the camera cuts to the target. The thesis gives
    /// no value. 1.5 s = v_σ: one tolerance to find the target on its own
    /// first; in the camera replay it finds the target within that in
    /// most occlusions, and a spectator waiting longer has lost the
    /// player (a longer wait lost visibility, a shorter one multiplied the
    /// cuts for little gain; `CAMERA.md`).
    pub cut_after: f32,
    /// Hidden this long (s) while out of the camera's reach, the camera
    /// cuts. Out of reach: the graph's way from the camera to the target
    /// (VDistance, through no gap narrower than `field_min_clearance`) is
    /// longer than the camera covers in `cut_after` at `max_speed`, or there
    /// is none. The player climbed a staircase or a ladder shaft too narrow
    /// for the camera, dropped through a hatch or crawled into a vent: the
    /// camera could not get him back into view before `cut_after` by its
    /// own motion (a way of thousands of units round a whole level, or
    /// none: then every candidate was rated hidden and unreachable alike and
    /// the camera stood still), and only the target can end the occlusion.
    /// So the wait is short: 0.5 s lets a player who steps behind a pillar
    /// and out again pass without a cut (over all the shared maps' routes a
    /// shorter wait cut too often and a longer one saw less; the figures are
    /// in docs/measurements/2026-12-07-camera-reach.md). The thesis:
    /// `cut_after` (no such cut).
    pub cut_unreachable_after: f32,
    /// A target that moves farther than this in one update has teleported
    /// (respawn, portal, spectator switch): the camera cuts. 256 units is
    /// ten frames of running at 30 Hz.
    pub teleport_distance: f32,
    /// The camera's top speed (units/s). Just under twice a running
    /// player's 265 u/s: fast enough to catch up, below what a replay
    /// counts as a jump (twice the target's top speed).
    pub max_speed: f32,
    /// τ of the step rule's `frac = 1 − e^(−Δt/τ)` (s): how fast the speed
    /// follows the cost. The thesis leaves `frac` undefined; the exponential
    /// form makes it independent of the frame rate. 0.12 s: 0.2 s lagged
    /// round corners (less visibility in the camera replay, no less jerk).
    pub speed_tau: f32,
    /// Updates longer than this (s) are integrated as if they were this long
    /// (a hitch must not fling the camera). 0.1 s.
    pub max_dt: f32,
    /// Height added to the target's position for every criterion (the point
    /// the camera keeps in view and looks at). 0 = the origin the engine
    /// gives (in Half-Life the standing hull's centre, 36 above the floor).
    pub target_height: f32,
    /// ε of the thesis' early stop: a candidate cheaper than this is taken
    /// at once.
    pub early_stop: f32,

    // --- beyond the thesis (each off in `thesis()`) ---
    /// Clamp candidates and the step across as many face volumes as needed
    /// (up to this many hops) instead of inside the current face only. The
    /// thesis clamps to Volume(f_i), so a small face stalls a fast camera
    /// (the dips of its fig. 7.2); 0 = the thesis.
    pub max_substeps: u32,
    /// VDistance from one distance field per frame (O(1) per candidate)
    /// instead of one A* per candidate (the thesis). Same values.
    pub distance_field: bool,
    /// f_vis = (1 + VDistance/d_σ)² for a hidden target instead of the
    /// thesis' 1 + VDistance: unitless like the other costs, so a hidden
    /// target still dominates but the speed rule's √f_total stays sane.
    pub normalized_visibility: bool,
    /// τ of the smoothing of the point the camera heads for (s): the best
    /// candidate's position, carried along with the target's own motion
    /// and followed with this lag. The best candidate jumps between
    /// candidates on either side of the camera from one frame to the next
    /// (their costs are close); heading for each in turn, the smoothed
    /// velocity averaged opposite directions, and a camera that should
    /// have kept pace with a walking player slowed to a crawl beside him
    /// and fell behind at the next corner. The smoothed point keeps the
    /// side it was on until the new one has won for a while, and it moves
    /// with the target, so the camera keeps pace. Only while the camera
    /// saw the target at its last update: once it is hidden, the costs are
    /// no longer close (the visible candidates win by far) and the camera
    /// must commit to the best one; averaged with the hidden ones, the
    /// point lay between them and the camera stayed hidden for up to 1.3 s.
    /// 0 = the best candidate itself (the thesis).
    pub goal_tau: f32,
    /// τ of the smoothing of the camera's velocity (s): the best candidate
    /// changes from frame to frame and the camera turns towards each with
    /// this lag. 0.13, chosen with `accel_tau` 0.05 as the split of one lag
    /// of 0.18 (which alone kept the jerk far below a chase cam's; a shorter
    /// lag jerks markedly more) for a little visibility. 0 = none (the
    /// thesis jumps to the best candidate's direction every frame).
    pub direction_tau: f32,
    /// A move blocked by the volume's boundary slides along it (the rest
    /// of the step without its part into the wall) instead of stopping:
    /// a camera whose smoothed direction touches a wall keeps its speed,
    /// no kink. false = stop there (the thesis has no boundary handling
    /// beyond Trace).
    pub slide: bool,
    /// The most the camera slows down per second (units/s²). The thesis'
    /// step never passes the best candidate, so a fast camera whose best
    /// candidate is suddenly near (the ideal distance reached, another
    /// criterion winning) stopped dead in one frame: most of its jerk.
    /// It now brakes at this rate and may pass the point a little (the
    /// move is still clamped into the volume). The same rate bounds its
    /// speed towards the nearest wall and towards the wall straight ahead,
    /// so that it can always stop before either. Its speed towards the
    /// point it heads for, and towards d_μ from the target, is one it can
    /// stop from with this rate after its reaction time (`direction_tau` +
    /// `accel_tau`), so it settles onto them instead of braking hard at the
    /// last moment. Where those limits drop faster (the player stops short,
    /// the point jumps close), the camera still slows at this rate, and
    /// may come inside d_μ, as long as it can stop before `distance_min`.
    /// 0 = stop dead, and no braking before walls (the thesis).
    pub max_decel: f32,
    /// The most the camera's acceleration changes per second (units/s³,
    /// 0 = no bound, the thesis). The velocity follows its command through
    /// this bound, so the acceleration is continuous and the jerk (its rate
    /// of change) never exceeds this, however the best candidate, the
    /// brakes or the arrival change from one frame to the next (where the
    /// move is not stopped by the volume's boundary). A hard bound costs
    /// visibility: at 10 000 the camera trails the player. Needs
    /// `accel_tau` 0.
    pub max_jerk: f32,
    /// τ of the lag with which the camera's acceleration follows the one
    /// its command asks for (s; 0 = at once, the thesis). With one lag
    /// (the velocity's, `direction_tau`) the acceleration jumped whenever
    /// the best candidate, a brake or the arrival changed the command: the
    /// jerk of a camera braking as the player lands. A second lag makes the
    /// acceleration continuous; with 0.05 s and `direction_tau` 0.13, on the
    /// shared maps together the jerk fell by about a third without losing
    /// sight of the player (docs/measurements/2026-12-02e-camera-jerk.md).
    /// The acceleration aims at the command in one frame, so the velocity
    /// behaves as a spring of damping ratio ½·√(Δt/τ): it lags the command
    /// by about a frame whatever τ and overshoots a step in it. The camera's
    /// seen share rests on that overshoot: a critically damped follow lost
    /// sight of the player on several maps
    /// (docs/measurements/2026-12-07i-camera-cut-cost.md). Excludes `max_jerk`.
    pub accel_tau: f32,
    /// τ of the smoothing of the look-at point (s); 0 = look straight at the
    /// target every frame (the thesis).
    pub look_tau: f32,
    /// The camera keeps at least this clearance (units): the near plane's
    /// corner distance. A 4-unit near plane at 90° × 74° has its corners
    /// 6.4 units from the eye; closer to a wall, the wall's inside shows.
    /// 0 = the thesis (anywhere inside the volume).
    pub near_margin: f32,
    /// VDistance (the distance field) takes no way through vertices of
    /// less clearance (units): a way through a gap the camera cannot pass
    /// (a vent, a crack the graph found under a door) led it into a corner
    /// to wait there for the cut. Below `near_margin`, because a face's
    /// volume is the hull of its vertices' balls: the camera passes beside
    /// a thin vertex when its neighbours are wide. 0 = the thesis' Voronoi
    /// distance.
    pub field_min_clearance: f32,
    /// On a cut, place the camera towards the ideal position from the
    /// target (as far as the volume allows) instead of on the target.
    pub cut_to_ideal: bool,
    /// Reachable(P(c_i), f_i) exactly as the thesis defines it (a straight
    /// line through the region's volumes, certified by a cover per vertex)
    /// rather than the vertices reachable inside one face volume (a subset,
    /// a few clearance evaluations each). The exact set costs most of an
    /// update and buys little: every candidate is clamped into the volume.
    pub exact_reachable: bool,
    /// Fresh line-of-sight tests per update for the reachable vertices
    /// (where k_vis and k_neighb are sought). The others reuse their last
    /// answer: a vertex does not move and the target moves a few units a
    /// frame, so yesterday's answer is nearly always today's, and the
    /// candidates built from these vertices are tested fresh anyway. Bounds
    /// an update's worst case (a hidden target makes every vertex a failed
    /// test). 0 = test every vertex every update (the thesis).
    pub vertex_tests: u32,
    /// Face volumes the candidates' and vertices' sight-line tests of one
    /// update may cross together (each test at most 48). A typical test
    /// crosses a few; a camera trailing far behind a hidden target makes
    /// every test long and failing, and without a bound such frames cost
    /// many times the median. A test cut short counts as "hidden", which
    /// only makes that candidate look worse. The test of the pose itself
    /// (`target_visible`, the cut clock) has its own 48. What one hop
    /// costs is bounded too: a step that searches a face's neighbourhood
    /// evaluates at most 128 faces (where hundreds of face volumes overlap,
    /// in a big open room). The thesis: no bound (4294967295).
    pub sight_hops: u32,
    /// Tree-leaf searches those tests may make per update. A leaf search
    /// bridges the rare gap where no face sharing a vertex with the current
    /// one continues a sight line, at the price of a dozen hops; a hidden
    /// target makes every test fail into one. The pose's own test has an
    /// allowance of its own of the same size, and so have the candidates'
    /// clamps. 2 keeps the slowest updates on a large map within the
    /// camera's time budget, which 3 or 4 did not, at the price of a
    /// fraction of a point of visibility in the camera replay (`CAMERA.md`
    /// has the measurements); engines with time to spare can buy it back.
    /// The thesis: no bound (4294967295).
    pub leaf_searches: u32,
    /// While the target is hidden, one more candidate k_path: the point
    /// this far (units of path) along the shortest way through the graph
    /// to the target, following the update's distance field from the
    /// reachable vertex nearest the target. The thesis' candidates are all
    /// local: where the way on passes a vertex outside Reachable(c) (a
    /// door, a bend in a corridor), every candidate is farther from the
    /// target than the camera and it waits until the cut. Vertices whose
    /// clearance is below `near_margin` are not followed. 0 = off (the
    /// thesis).
    pub pursuit_length: f32,
    /// f_inertia's denominator is at least this fraction of the target's
    /// speed (measured from its last two positions). With only the camera's
    /// own speed there, a camera at rest rates every candidate more than a
    /// few units away as a violent start: behind a target walking off from
    /// a spawn it stayed put for a second, until f_dist outgrew that. A
    /// camera following a moving target is expected to move like it.
    /// 0 = the camera's own speed only (the thesis).
    pub inertia_target_speed: f32,
    /// The step rule commands at least this fraction of the target's speed.
    /// The thesis' rule `V ← (1−frac)·V + frac·(1+V)·√f_total` settles at
    /// √f/(1−√f) while f_total < 1: a camera at rest behind a target that
    /// walks off crawls at a few units per second until the costs pass 1,
    /// then accelerates exponentially. A camera that follows a moving
    /// target needs its speed; it still never passes its best candidate.
    /// 0 = the thesis.
    pub target_speed_floor: f32,
    /// While the camera sees the target (at its last update, and now
    /// where it stands and where the target is heading), it moves no faster
    /// than this many times the target's recent top speed (the fastest it
    /// moved, forgotten with a time constant of one second), and that speed
    /// is taken as at least `seen_speed_floor`. A camera that sees its
    /// player has no need to outrun him; held up at a narrow spot behind a
    /// crouching player (96 units/s) one caught up at 284 units/s. While
    /// the target is hidden the camera may still hurry. 0 = no bound (the
    /// thesis).
    pub seen_speed_factor: f32,
    /// The least target speed (units/s) [`Self::seen_speed_factor`] allows
    /// for: a player who stands still can still be walked round.
    pub seen_speed_floor: f32,
    /// d_μ is at most this many times the target's room (the graph's
    /// clearance at the target), never below `distance_min`: where the
    /// player has little room the camera follows closer. At the full d_μ a
    /// camera trailing a runner through a corridor lost him at every bend
    /// for as long as it took to cover the extra way round it (the
    /// corridors, ducts and furniture of real maps held most of the
    /// frames the replay's camera missed); in open ground, where the
    /// target's room exceeds d_μ / factor, nothing changes. 0 = off (the
    /// thesis).
    pub distance_room_factor: f32,
    /// The least d_μ that `distance_room_factor` brings the camera in to
    /// (units): a little more than the player's own width from his eye.
    pub distance_min: f32,
    /// Seconds of lag with which d_μ follows the target's room (see
    /// `distance_room_factor`). 0 = at once.
    pub distance_room_tau: f32,
    /// f_clear asks for no more room than the graph gives the target
    /// itself: "room for p_σ seconds at the current speed" (about 125
    /// units when following a running player) is more than a corridor,
    /// a doorway or even open ground at eye height (the floor is 64 units
    /// below a standing player's eye) ever has, so every position the
    /// player's way passes through was rated as cramped, the more the
    /// faster the camera chased: a chasing camera next to the doorway the
    /// player had gone through kept to the open room. Where the player
    /// has room, the camera still keeps its distance from walls. false =
    /// the thesis' need, whatever the target's room.
    pub clearance_within_target_room: bool,
    /// Seconds ahead the candidates must see the target: a candidate that
    /// sees where the target is but not where its motion takes it within
    /// this time (its velocity over the last update, stopped at the
    /// volume's boundary) is rated as hidden, with the way through the
    /// graph to that point. A camera that only sees the player now waits
    /// where the sight line grazes a wall until it is cut: high in a room,
    /// looking down through a doorway into a low corridor, it watched the
    /// player walk in and lost him under the lintel. The camera's own
    /// place is rated so too, so the step rule (whose speed grows with
    /// its cost) hurries from a place about to lose him. 0.25 s, the
    /// inertia horizon: the time over which the camera plans its motion.
    /// 0 = the thesis (the target where it is).
    pub sight_lead: f32,
}

impl Default for CameraParams {
    fn default() -> Self {
        CameraParams {
            distance_mu: 80.0,
            distance_sigma: 48.0,
            angle_mu_yaw_deg: 180.0,
            angle_mu_pitch_deg: 15.0,
            angle_sigma_deg: 60.0,
            heading_pitch_weight: 0.0,
            inertia_sigma: 0.5,
            inertia_min_speed: 128.0,
            inertia_horizon: 0.25,
            inertia_step: true,
            clearance_sigma: 0.5,
            visibility_sigma: 1.5,
            cut_after: 1.5,
            cut_unreachable_after: 0.5,
            teleport_distance: 256.0,
            max_speed: 500.0,
            speed_tau: 0.12,
            max_dt: 0.1,
            target_height: 0.0,
            early_stop: 1e-3,
            max_substeps: 16,
            distance_field: true,
            normalized_visibility: true,
            goal_tau: 0.08,
            direction_tau: 0.13,
            slide: true,
            max_decel: 1000.0,
            max_jerk: 0.0,
            accel_tau: 0.05,
            look_tau: 0.08,
            near_margin: 6.4,
            field_min_clearance: 3.2,
            cut_to_ideal: true,
            exact_reachable: false,
            vertex_tests: 8,
            sight_hops: 64,
            leaf_searches: 2,
            pursuit_length: 128.0,
            inertia_target_speed: 1.0,
            target_speed_floor: 1.0,
            seen_speed_factor: 2.0,
            seen_speed_floor: 96.0,
            distance_room_factor: 2.0,
            distance_min: 40.0,
            distance_room_tau: 0.5,
            clearance_within_target_room: true,
            sight_lead: 0.25,
        }
    }
}

impl CameraParams {
    /// The thesis' camera (ch. 5) as printed: candidates clamped into the
    /// current face, one A* per VDistance, unnormalised f_vis, inertia over
    /// Δt, no smoothing, no near-plane margin, cuts onto the target. The
    /// constraints (μ, σ) are the same as the default's.
    pub fn thesis() -> CameraParams {
        CameraParams {
            heading_pitch_weight: 1.0,
            inertia_horizon: 0.0,
            inertia_step: false,
            max_substeps: 0,
            distance_field: false,
            normalized_visibility: false,
            goal_tau: 0.0,
            direction_tau: 0.0,
            slide: false,
            max_decel: 0.0,
            max_jerk: 0.0,
            accel_tau: 0.0,
            look_tau: 0.0,
            near_margin: 0.0,
            field_min_clearance: 0.0,
            cut_to_ideal: false,
            exact_reachable: true,
            vertex_tests: 0,
            sight_hops: u32::MAX,
            leaf_searches: u32::MAX,
            pursuit_length: 0.0,
            inertia_target_speed: 0.0,
            target_speed_floor: 0.0,
            seen_speed_factor: 0.0,
            seen_speed_floor: 0.0,
            distance_room_factor: 0.0,
            clearance_within_target_room: false,
            sight_lead: 0.0,
            cut_unreachable_after: CameraParams::default().cut_after,
            ..CameraParams::default()
        }
    }

    /// Parses TOML (any subset of the fields) and validates the result.
    #[cfg(feature = "camera-toml")]
    pub fn from_toml_str(s: &str) -> Result<CameraParams, CameraError> {
        let p: CameraParams =
            toml::from_str(s).map_err(|e| CameraError::Params(one_line(&e.to_string())))?;
        p.validate()?;
        Ok(p)
    }

    /// Checks every field for a usable value (finite, in range).
    pub fn validate(&self) -> Result<(), CameraError> {
        let positive = [
            ("distance_mu", self.distance_mu),
            ("distance_sigma", self.distance_sigma),
            ("angle_sigma_deg", self.angle_sigma_deg),
            ("inertia_sigma", self.inertia_sigma),
            ("inertia_min_speed", self.inertia_min_speed),
            ("clearance_sigma", self.clearance_sigma),
            ("visibility_sigma", self.visibility_sigma),
            ("teleport_distance", self.teleport_distance),
            ("max_speed", self.max_speed),
            ("speed_tau", self.speed_tau),
            ("max_dt", self.max_dt),
        ];
        require(&positive, "a positive number", |v| v.is_finite() && v > 0.0)?;
        let non_negative = [
            ("inertia_horizon", self.inertia_horizon),
            ("cut_after", self.cut_after),
            ("cut_unreachable_after", self.cut_unreachable_after),
            ("early_stop", self.early_stop),
            ("goal_tau", self.goal_tau),
            ("direction_tau", self.direction_tau),
            ("max_decel", self.max_decel),
            ("max_jerk", self.max_jerk),
            ("accel_tau", self.accel_tau),
            ("look_tau", self.look_tau),
            ("near_margin", self.near_margin),
            ("field_min_clearance", self.field_min_clearance),
            ("pursuit_length", self.pursuit_length),
            ("inertia_target_speed", self.inertia_target_speed),
            ("target_speed_floor", self.target_speed_floor),
            ("seen_speed_factor", self.seen_speed_factor),
            ("seen_speed_floor", self.seen_speed_floor),
            ("distance_room_factor", self.distance_room_factor),
            ("distance_min", self.distance_min),
            ("distance_room_tau", self.distance_room_tau),
            ("sight_lead", self.sight_lead),
        ];
        require(&non_negative, "zero or positive", |v| {
            v.is_finite() && v >= 0.0
        })?;
        let finite = [
            ("angle_mu_yaw_deg", self.angle_mu_yaw_deg),
            ("angle_mu_pitch_deg", self.angle_mu_pitch_deg),
            ("target_height", self.target_height),
        ];
        require(&finite, "a finite number", f32::is_finite)?;
        if self.accel_tau > 0.0 && self.max_jerk > 0.0 {
            return Err(CameraError::Params(format!(
                "accel_tau ({}) and max_jerk ({}) exclude each other: set one to 0",
                self.accel_tau, self.max_jerk
            )));
        }
        if self.angle_sigma_deg > 180.0 {
            return Err(CameraError::Params(format!(
                "angle_sigma_deg must be in (0, 180], got {}",
                self.angle_sigma_deg
            )));
        }
        if !(0.0..=1.0).contains(&self.heading_pitch_weight) {
            return Err(CameraError::Params(format!(
                "heading_pitch_weight must be in [0, 1], got {}",
                self.heading_pitch_weight
            )));
        }
        if self.max_substeps > 4096 {
            return Err(CameraError::Params(format!(
                "max_substeps must be at most 4096, got {}",
                self.max_substeps
            )));
        }
        Ok(())
    }
}

/// The first of `fields` (name, value) whose value is not `ok`, as the
/// error "NAME must be WHAT, got VALUE".
fn require(
    fields: &[(&str, f32)],
    what: &str,
    ok: impl Fn(f32) -> bool,
) -> Result<(), CameraError> {
    match fields.iter().find(|&&(_, v)| !ok(v)) {
        Some((name, v)) => Err(CameraError::Params(format!(
            "{name} must be {what}, got {v}"
        ))),
        None => Ok(()),
    }
}

#[cfg(feature = "camera-toml")]
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Why a camera could not be made.
#[derive(Debug, Clone, PartialEq)]
pub enum CameraError {
    /// Invalid parameters (a field out of range, bad TOML).
    Params(String),
}

impl std::fmt::Display for CameraError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CameraError::Params(m) => write!(f, "invalid camera parameters: {m}"),
        }
    }
}

impl std::error::Error for CameraError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_params_turn_every_improvement_off() {
        let t = CameraParams::thesis();
        assert_eq!(t.max_substeps, 0);
        assert!(!t.distance_field && !t.normalized_visibility && !t.cut_to_ideal);
        assert_eq!(
            (t.goal_tau, t.direction_tau, t.look_tau, t.near_margin),
            (0.0, 0.0, 0.0, 0.0)
        );
        assert_eq!(t.inertia_horizon, 0.0);
        assert_eq!((t.target_speed_floor, t.distance_room_factor), (0.0, 0.0));
        assert_eq!(
            (t.vertex_tests, t.sight_hops, t.leaf_searches),
            (0, u32::MAX, u32::MAX)
        );
        t.validate().unwrap();
    }
}
