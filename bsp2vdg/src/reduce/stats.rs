//! What a reduction reports: why it stopped, what each operation did and where the
//! time went.

use super::ReductionCost;

/// Why the reduction stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StopReason {
    /// The vertex count reached the limit.
    #[default]
    LimitReached,
    /// The vertex count reached the floor ([`ReduceOptions::min_vertices`]),
    /// which lies above the limit.
    FloorReached,
    /// No remaining vertex can be removed without breaking a condition.
    NothingRemovable,
}

impl StopReason {
    /// Short name for `--json`.
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::LimitReached => "limit",
            StopReason::FloorReached => "floor",
            StopReason::NothingRemovable => "nothing_removable",
        }
    }
}

/// What the raise back towards the unreduced clearances did (see
/// [`ReduceOptions::raise`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RaisedBack {
    /// Vertices whose clearance was raised, and the sum of the raises (units).
    pub vertices: usize,
    pub total: f64,
    /// Seconds the raise took (part of the reduction's time).
    pub seconds: f64,
}

/// Counts of a reduction.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReduceStats {
    /// Vertices with at least one face, and faces, before.
    pub vertices_before: usize,
    pub faces_before: usize,
    /// The vertex count aimed at ([`ReduceOptions::target`]: `ceil(limit ·
    /// vertices_before)`, or the floor if higher).
    pub target: usize,
    /// The order the removals went in ([`ReduceOptions::cost`]).
    pub cost: ReductionCost,
    pub vertices_after: usize,
    pub faces_after: usize,
    /// Vertices removed by the main loop (vertices left without a face by a
    /// one-face removal are not counted here but are gone).
    pub removals: usize,
    /// Edge swaps (4.5), one-face removals (4.4), three faces replaced by a
    /// new face (4.6.2), by an existing face, two faces at a concave corner
    /// replaced (4.6.1).
    pub swaps: usize,
    pub one_face: usize,
    pub three_faces: usize,
    pub three_faces_existing: usize,
    pub two_faces_concave: usize,
    /// Seam vertices contracted out of their seam, and vertices collapsed
    /// into a neighbour along an edge (module `seam`).
    pub seam_contractions: usize,
    pub seam_collapses: usize,
    /// Border and seam-end vertices removed fan by fan (module `border`).
    pub fan_removals: usize,
    /// Vertices left when the thesis' cases alone stopped and the second
    /// phase with the seam operations began (`None`: the limit came first).
    pub seam_phase_at: Option<usize>,
    /// Seconds the second phase took (part of the reduction's time).
    pub seam_phase_seconds: f64,
    /// Deep points the second phase keeps (see `seam::DEEP_CLEARANCE`).
    pub seam_deep_points: usize,
    /// The model volume (cubic units) the removals lost.
    pub lost_volume: f64,
    /// The raise back towards the unreduced clearances after the reduction
    /// (the `raise` module), `None` when [`ReduceOptions::raise`] is off.
    pub raised_back: Option<RaisedBack>,
    /// Points kept inside the volume (see [`reduce_keeping`]).
    pub kept_points: usize,
    /// Batches of the main loop, removals costed in them (initial costs
    /// and the final sweep not counted), and costed removals put back into
    /// the queue because their cost had risen above the next one's.
    pub batches: usize,
    pub costed: usize,
    pub requeued: usize,
    /// Seconds spent on the initial costs, on costing batches (with the
    /// next batch picked at the same time) and on the rest of the main
    /// loop (committing, queue upkeep, final sweeps): where the time goes.
    pub seconds_initial: f64,
    pub seconds_batches: f64,
    pub seconds_rest: f64,
    /// Of those, the seconds spent picking the batches (on one thread, while
    /// the batch before is costed) and committing them (serial).
    pub seconds_picking: f64,
    pub seconds_commits: f64,
    /// Sweeps over every vertex before giving up (see `run`), the vertices
    /// they did not cost again because nothing around them had changed since
    /// a costing refused them, and their seconds (part of `seconds_rest`).
    pub sweeps: usize,
    pub sweep_skipped: usize,
    pub seconds_sweeps: f64,
    pub stop: StopReason,
    /// When the reduction stopped with [`StopReason::NothingRemovable`]: per
    /// refusal reason (see [`refusals`]), how many of the vertices left it
    /// refuses; empty otherwise.
    pub refusals: Vec<(&'static str, usize)>,
}

/// A progress report, about once a second.
#[derive(Debug, Clone, Copy)]
pub struct Tick {
    pub seconds: f64,
    pub vertices: usize,
    pub faces: usize,
    /// Cost of the last removal.
    pub cost: f64,
    /// Vertices left / vertices before.
    pub reduction: f64,
}
