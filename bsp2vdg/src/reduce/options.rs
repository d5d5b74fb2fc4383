//! What a reduction is asked for: how far ([`ReduceOptions`]) and in which order
//! ([`ReductionCost`]).

/// What to reduce to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReduceOptions {
    /// Stop when at most this fraction of the vertices is left (`-rl`).
    pub limit: f64,
    /// Never reduce below this many vertices (`-rv`), whatever `limit`
    /// says: a fraction made for maps of thousands of vertices leaves a
    /// small map a few dozen, whose volume misses a third of the room's
    /// sight lines (on small example maps Visible answered more than twice as
    /// often wrong as unreduced). 0 = no floor (the thesis).
    pub min_vertices: usize,
    /// Raise the clearances the operations lowered back towards the
    /// unreduced graph's afterwards, as far as condition A against the
    /// unreduced volume allows (the `raise` module). On by default: it is
    /// what a reduction without the map can do. The compiler turns it off
    /// and raises towards the walls instead (`voronoi::raise_to_walls`),
    /// which the map's walls certify and which reaches further: on the
    /// shared maps the volume holds as much or more without this raise, and
    /// the compile saves its time (about a tenth of a dense compile's).
    pub raise: bool,
    /// What a removal costs, i.e. which vertices go first (`-rc`).
    pub cost: ReductionCost,
    /// The coverage guards: the kept places and the seam phase's deep points stay
    /// inside the volume (on by default). Off is a measurement switch that shows
    /// whether the reduction stops above `-rl` because of them or because the
    /// vertices left have no operation that keeps conditions A–C; never for graphs
    /// you ship: without the guards the reduction shaves the volume off the floors.
    pub coverage_guards: bool,
}

/// The order of the reduction: what a vertex's removal costs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ReductionCost {
    /// The model volume the removal loses (4.4): the thesis.
    #[default]
    Volume,
    /// That volume divided by the removed vertex's clearance squared (at
    /// least 1). The same volume costs more when a small vertex near the
    /// walls loses it: the volume's skin there is what sight lines along
    /// the walls run through, and the thesis' cost took it first (its
    /// small volumes are cheap). On the shared maps Visible's false
    /// negatives inside the volume fell (on most maps, not all), the files
    /// shrank, and the camera's replay saw the target in more of the frames.
    Relative,
}

impl ReductionCost {
    /// The cost of removing a vertex of clearance `r` that loses `volume`.
    ///
    /// ```
    /// use bsp2vdg::reduce::ReductionCost;
    /// assert_eq!(ReductionCost::Volume.of(100.0, 5.0), 100.0);
    /// assert_eq!(ReductionCost::Relative.of(100.0, 5.0), 4.0);
    /// // A vertex on a wall is not free to remove.
    /// assert_eq!(ReductionCost::Relative.of(100.0, 0.0), 100.0);
    /// ```
    pub fn of(self, volume: f64, r: f64) -> f64 {
        match self {
            ReductionCost::Volume => volume,
            ReductionCost::Relative => volume / r.max(1.0).powi(2),
        }
    }

    /// The name `-rc` takes and the `.vdg` records.
    pub fn as_str(self) -> &'static str {
        match self {
            ReductionCost::Volume => "volume",
            ReductionCost::Relative => "relative",
        }
    }

    /// What [`Self::of`] computes, for the log.
    pub fn formula(self) -> &'static str {
        match self {
            ReductionCost::Volume => "volume",
            ReductionCost::Relative => "volume / clearance²",
        }
    }
}

impl ReduceOptions {
    /// Reduce to `limit` (see [`ReduceOptions::limit`]), raising afterwards,
    /// by the thesis' cost.
    pub fn new(limit: f64) -> ReduceOptions {
        ReduceOptions {
            limit,
            min_vertices: 0,
            raise: true,
            cost: ReductionCost::Volume,
            coverage_guards: true,
        }
    }

    /// The vertex count to reduce `live` vertices to: the fraction
    /// `limit` of them, but at least `min_vertices` (or all of them, if
    /// fewer).
    ///
    /// ```
    /// use bsp2vdg::reduce::ReduceOptions;
    /// let o = ReduceOptions { min_vertices: 1000, ..ReduceOptions::new(0.025) };
    /// assert_eq!(o.target(100_000), 2500);
    /// assert_eq!(o.target(8_000), 1000);
    /// assert_eq!(o.target(600), 600);
    /// ```
    pub fn target(&self, live: usize) -> usize {
        let fraction = (self.limit.clamp(0.0, 1.0) * live as f64).ceil() as usize;
        fraction.max(self.min_vertices.min(live))
    }

    /// Whether the floor, not the fraction, sets [`Self::target`].
    pub fn floor_sets_target(&self, live: usize) -> bool {
        self.target(live) > (self.limit.clamp(0.0, 1.0) * live as f64).ceil() as usize
    }
}

impl Default for ReduceOptions {
    fn default() -> Self {
        ReduceOptions::new(0.025)
    }
}
