//! The compile pipeline: the stages of SPEC §3 run in order, each logged with its
//! time, up to the stage the user asked for.

use crate::delaunay::Triangulation;
use crate::log::{Log, secs};
use crate::progress::Progress;
use crate::reduce;
use crate::sample::{self, SampleOptions, Samples};
use crate::voronoi::{self, FreeSpace, Graph, VoronoiOptions, VoronoiStats};
use bsp::boundary;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use bsp::{Bsp, BspError};

/// A map's free space: the BSP oracle for points and segments, the tree's obstacle
/// boundary for exact wall distances.
struct MapSpace<'a> {
    oracle: &'a Oracle,
    walls: Walls,
    /// The world's bounds (mins, maxs).
    bounds: ([f64; 3], [f64; 3]),
    /// The map's game: how its players crouch (see `standing::Crouching`).
    game: bsp::Game,
}

impl FreeSpace for MapSpace<'_> {
    fn is_free(&self, p: [f64; 3]) -> bool {
        self.oracle.is_free(p)
    }
    fn segment_free(&self, a: [f64; 3], b: [f64; 3]) -> bool {
        self.oracle.segment_free(a, b)
    }
    fn wall_distance(&self, p: [f64; 3]) -> f64 {
        self.walls.distance(p)
    }
    fn wall_distance_within(&self, p: [f64; 3], radius: f64) -> Option<f64> {
        self.walls.distance_within(p, radius)
    }
    fn wall_distances_within(
        &self,
        points: &[[f64; 3]],
        radii: &[f64],
        out: &mut Vec<Option<f64>>,
    ) {
        self.walls.distances_within(points, radii, out)
    }
}

use std::fmt;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The pipeline's stages, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    Samples,
    Delaunay,
    Voronoi,
    Reduce,
}

impl Stage {
    pub fn name(self) -> &'static str {
        match self {
            Stage::Samples => "samples",
            Stage::Delaunay => "delaunay",
            Stage::Voronoi => "voronoi",
            Stage::Reduce => "reduce",
        }
    }
}

/// Format of the `-savesamples` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SamplesFormat {
    /// One `x y z` line per sample.
    #[default]
    Xyz,
    /// qhull's input format: `3`, the count, then `x y z` lines.
    Qhull,
}

/// The default `-rv`: small maps keep at least this many vertices. On the
/// shared maps below it (the allocblock tests, the qbsp and ericw examples)
/// Visible's false negatives fall with it (allocblock-lightmap-test 2.24 %
/// at 224 vertices, 1.20 % at 500, 1.03 % at 1000; the qbsp example 38 % at
/// 35 vertices, 15 % at its unreduced 648) for files of about 100 kB; a
/// Half-Life or Counter-Strike map reduces to 2 000-15 000 anyway.
pub const DEFAULT_REDUCTION_FLOOR: usize = 1000;

/// Everything that steers a compile.
#[derive(Debug, Clone)]
pub struct CompileOptions {
    pub sampling: SampleOptions,
    /// `-rl`: stop reducing at this fraction of the vertices.
    pub reduction_limit: f64,
    /// `-rv`: never reduce below this many vertices (see
    /// [`reduce::ReduceOptions::min_vertices`]).
    pub reduction_floor: usize,
    /// `-rc`: what a removal costs (see [`reduce::ReductionCost`]).
    pub reduction_cost: reduce::ReductionCost,
    /// `-md`: vertices with less clearance are removed before reduction.
    pub min_clearance: f64,
    /// `-bb`: the smallest leaf box of the face tree.
    pub tree_leaf_size: f64,
    pub liquids_are_solid: bool,
    /// Player and monster clip brushes are walls (`--clip-solid`).
    pub clip_is_solid: bool,
    /// Brush entity classnames whose models are walls too.
    pub entity_classes: Vec<String>,
    pub save_samples: bool,
    pub samples_format: SamplesFormat,
    pub stop_after: Stage,
    /// Where the `.vdg` goes; other outputs go beside it.
    pub output: PathBuf,
    /// The source name recorded in the `.vdg` (`--source-name`); by default none, so
    /// the output does not depend on the map file's name.
    pub source_name: Option<String>,
}

impl CompileOptions {
    /// The command line's defaults (`-sd 24 -ms 250000 -rl 0.025 -rv 1000 -rc relative -md 20 -bb 256`),
    /// writing to `output`.
    pub fn new(output: PathBuf) -> CompileOptions {
        CompileOptions {
            sampling: SampleOptions::default(),
            reduction_limit: 0.025,
            reduction_floor: DEFAULT_REDUCTION_FLOOR,
            reduction_cost: reduce::ReductionCost::Relative,
            min_clearance: 20.0,
            tree_leaf_size: 256.0,
            liquids_are_solid: false,
            clip_is_solid: false,
            entity_classes: Vec::new(),
            save_samples: false,
            samples_format: SamplesFormat::Xyz,
            stop_after: Stage::Reduce,
            output,
            source_name: None,
        }
    }
}

/// What a compile measured, for the log summary and `--json`.
#[derive(Debug, Clone, Default)]
pub struct Stats {
    pub version: String,
    pub file_size: usize,
    pub bounds: ([f32; 3], [f32; 3]),
    pub faces: usize,
    pub sampled_faces: usize,
    pub sky_faces: usize,
    pub samples: usize,
    pub sample_spacing: f64,
    pub requested_spacing: f64,
    pub subfaces: usize,
    pub merged_samples: usize,
    /// Samples on walls the BSP tree has but no face shows.
    pub hidden_samples: usize,
    pub entity_models: usize,
    /// Seconds per stage, in order.
    pub seconds: Vec<(&'static str, f64)>,
    pub samples_file: Option<PathBuf>,
    /// Delaunay and Voronoi counts (thesis table 7.1), once those stages ran.
    pub tetrahedra: Option<usize>,
    pub duplicate_samples: usize,
    pub voronoi: Option<VoronoiStats>,
    /// The written graph: vertices, faces, bytes.
    pub vdg: Option<(usize, usize, usize)>,
    /// The reduction's counts, when it ran (`-rl` < 1).
    pub reduce: Option<crate::reduce::ReduceStats>,
    pub output: Option<PathBuf>,
}

/// Runs the reduction stage (thesis 4, 6.1.5) with its log lines.
fn reduce_graph(
    graph: &Graph,
    options: reduce::ReduceOptions,
    space: &MapSpace,
    log: &Log,
    progress: &dyn Progress,
) -> (Graph, (reduce::ReduceStats, f64)) {
    let t = Instant::now();
    // Where a standing player is, the camera's target is: the reduction keeps those
    // places inside the volume (a grid of floor points of clip hull 1), and the eyes
    // of the places where a player only fits crouching (vents, crawl spaces: c1a1b's
    // unreduced graph holds 91 % of them, the reduction kept 80 %).
    let mut keep = bsp::player::grid_origins(
        space.oracle,
        space.bounds.0,
        space.bounds.1,
        bsp::player::KEEP_SPACING,
    );
    let standing = keep.len();
    keep.extend(bsp::player::grid_crouch_eyes(
        space.oracle,
        space.game,
        space.bounds.0,
        space.bounds.1,
        bsp::player::KEEP_SPACING,
    ));
    let crouching = keep.len() - standing;
    let before = graph.vertices.len();
    let cost = options.cost.formula();
    log.info(if options.floor_sets_target(before) {
        format!(
            "Reducing to {} vertices (the floor -rv {}; -rl {} would leave {}), cost {cost}...",
            options.target(before),
            options.min_vertices,
            options.limit,
            (options.limit * before as f64).ceil() as usize
        )
    } else {
        format!(
            "Reducing to {} ({}) vertices, cost {cost}...",
            options.target(before),
            options.limit
        )
    });
    let (reduced, rs) = reduce::reduce_keeping(graph, &options, &keep, progress, &mut |k| {
        log.info(format!(
            "Time {:.0}, Nodes {}, Faces {}, Cost {:.1}, Reduction {:.3}",
            k.seconds, k.vertices, k.faces, k.cost, k.reduction
        ))
    });
    log.info(format!(
        "Kept {} of {} player places ({} standing, {} crouching; floors every {} units) inside the volume",
        rs.kept_points,
        keep.len(),
        standing,
        crouching,
        bsp::player::KEEP_SPACING
    ));
    if let Some(at) = rs.seam_phase_at {
        log.info(format!(
            "Seam phase from {} vertices: {} seam contractions, {} collapses, {} fan removals, {} deep points kept [{}]",
            at,
            rs.seam_contractions,
            rs.seam_collapses,
            rs.fan_removals,
            rs.seam_deep_points,
            secs(rs.seam_phase_seconds)
        ));
    }
    log.info(match rs.stop {
        reduce::StopReason::LimitReached => "Reduction limit reached.".to_string(),
        reduce::StopReason::FloorReached => "Reduction floor (-rv) reached.".to_string(),
        reduce::StopReason::NothingRemovable => {
            "Reduction stopped: nothing more can be removed.".to_string()
        }
    });
    log.info(format!(
        "Reduced nodes {} -> {}, faces {} -> {} ({} swaps) [{}]",
        rs.vertices_before,
        rs.vertices_after,
        rs.faces_before,
        rs.faces_after,
        rs.swaps,
        secs(t.elapsed().as_secs_f64())
    ));
    if let Some(r) = rs.raised_back {
        log.info(format!(
            "Raised {} vertices back towards their unreduced clearance (by {:.1} units on average) [{}]",
            r.vertices,
            r.total / r.vertices.max(1) as f64,
            secs(r.seconds)
        ));
    }
    log.detail(format!(
        "Reduction work: {} batches, {} removals costed in them, {} put back with a higher cost; \
         {} sweeps skipping {} unchanged refused vertices [{}]; \
         {} initial costs, {} batches ({} of it picking the next one on one thread), {} the rest ({} committing)",
        rs.batches,
        rs.costed,
        rs.requeued,
        rs.sweeps,
        rs.sweep_skipped,
        secs(rs.seconds_sweeps),
        secs(rs.seconds_initial),
        secs(rs.seconds_batches),
        secs(rs.seconds_picking),
        secs(rs.seconds_rest),
        secs(rs.seconds_commits)
    ));
    (reduced, (rs, t.elapsed().as_secs_f64()))
}

/// Why a compile failed.
#[derive(Debug)]
pub enum CompileError {
    Bsp {
        path: PathBuf,
        error: BspError,
    },
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    Delaunay(crate::delaunay::DelaunayError),
    /// Too few samples: the map has (almost) no walls around free space.
    NoFreeSpace(usize),
    Vdg {
        path: PathBuf,
        error: String,
    },
    NotBuilt(Stage),
    /// A BSP of an engine whose format this version does not read.
    OtherFormat {
        path: PathBuf,
        format: String,
    },
    /// No vertex (or no face) survived: nothing to write.
    EmptyGraph {
        min_clearance: f64,
    },
}

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CompileError::Bsp { path, error } => write!(f, "{}: {error}", path.display()),
            CompileError::Write { path, error } => {
                write!(f, "cannot write {}: {error}", path.display())
            }
            CompileError::Delaunay(e) => write!(f, "Delaunay stage: {e}"),
            CompileError::NoFreeSpace(n) => write!(
                f,
                "the map has no walls around free space to build a graph from ({n} samples; is it sealed, with no empty leaves?)"
            ),
            CompileError::Vdg { path, error } => {
                write!(f, "cannot write {}: {error}", path.display())
            }
            CompileError::OtherFormat { path, format } => write!(
                f,
                "{}: {format}, which bsp2vdg does not read (it reads GoldSrc BSP v30 and Quake BSP29, BSP2 and 2PSB maps)",
                path.display()
            ),
            CompileError::EmptyGraph { min_clearance } => write!(
                f,
                "the graph is empty: no free space with at least -md {min_clearance} units of clearance survived (is the map sealed, or -md too large?); nothing written"
            ),
            CompileError::NotBuilt(stage) => write!(
                f,
                "the {} stage is not built yet in this version",
                stage.name(),
            ),
        }
    }
}

impl std::error::Error for CompileError {}

/// Runs the pipeline on one map.
pub fn compile(
    map: &Path,
    options: &CompileOptions,
    log: &Log,
    progress: &dyn Progress,
) -> Result<Stats, CompileError> {
    let t_total = Instant::now();
    let mut stats = Stats::default();

    let t = Instant::now();
    let bsp = Bsp::open(map).map_err(|error| match other_format(map) {
        Some(format) => CompileError::OtherFormat {
            path: map.to_path_buf(),
            format,
        },
        None => CompileError::Bsp {
            path: map.to_path_buf(),
            error,
        },
    })?;
    let world = bsp.world();
    stats.version = bsp.version.name().to_string();
    stats.file_size = bsp.file_size;
    stats.bounds = (world.mins, world.maxs);
    log.info(format!(
        "Loading model: {} ({} kB), {}, {} models, {} entities",
        map.display(),
        bsp.file_size.div_ceil(1024),
        bsp.version.name(),
        bsp.models.len(),
        bsp.entities.len()
    ));
    if bsp.unused_bad_records > 0 {
        log.info(format!(
            "Ignored {} unused records with bad indices (the game never reads them)",
            bsp.unused_bad_records
        ));
    }
    log.info(format!(
        "Bounding Box ({:.1},{:.1},{:.1})-({:.1},{:.1},{:.1})",
        world.mins[0], world.mins[1], world.mins[2], world.maxs[0], world.maxs[1], world.maxs[2]
    ));
    stats.seconds.push(("load", t.elapsed().as_secs_f64()));

    let t = Instant::now();
    let mut sampling = options.sampling.clone();
    sampling.models = entity_models(&bsp, &options.entity_classes);
    stats.entity_models = sampling.models.len();
    if !sampling.models.is_empty() {
        log.info(format!(
            "Including {} brush entity models ({})",
            sampling.models.len(),
            options.entity_classes.join(", ")
        ));
    }
    let oracle_options = OracleOptions {
        liquids_are_solid: options.liquids_are_solid,
        clip_is_solid: options.clip_is_solid,
        solid_models: sampling.models.clone(),
    };
    let oracle = Oracle::new(&bsp, &oracle_options);
    let boundary = boundary::of_map(&bsp, &oracle_options);
    let mut faces = sample::collect_faces(&bsp, &sampling.models);
    sample::cull_by_contents(&mut faces, |p| oracle.is_free(p));
    faces.extend(sample::hidden_faces(&boundary));
    log.info(format!(
        "Sampling from {} faces and {} pieces of the BSP's obstacle boundary ...",
        faces.len() - boundary.len(),
        boundary.len()
    ));
    progress.start("Sampling", 1);
    let samples = sample::sample_faces(&faces, &sampling);
    progress.advance(1);
    progress.finish();
    log_samples(log, &samples);
    stats.faces = samples.faces;
    stats.sampled_faces = samples.sampled_faces;
    stats.sky_faces = samples.sky_faces;
    stats.samples = samples.points.len();
    stats.sample_spacing = samples.spacing;
    stats.requested_spacing = samples.requested_spacing;
    stats.subfaces = samples.subfaces;
    stats.merged_samples = samples.merged;
    stats.hidden_samples = samples.hidden_samples;
    stats.seconds.push(("sample", t.elapsed().as_secs_f64()));
    log.info(format!(
        "Sampled {} points from {} faces ({} subfaces) [{}]",
        samples.points.len(),
        samples.sampled_faces,
        samples.subfaces,
        secs(t.elapsed().as_secs_f64())
    ));

    if options.save_samples {
        let path = samples_path(&options.output);
        write_samples(&path, &samples.points, options.samples_format)?;
        log.info(format!(
            "Wrote {} samples to {}",
            samples.points.len(),
            path.display()
        ));
        stats.samples_file = Some(path);
    }

    let walls = Walls::from_boundary(&boundary);
    let world = bsp.world();
    let space = MapSpace {
        oracle: &oracle,
        walls,
        bounds: (world.mins.map(f64::from), world.maxs.map(f64::from)),
        game: bsp.version.game(),
    };
    let result = later_stages(map, options, &samples, &space, log, progress, &mut stats);
    stats
        .seconds
        .push(("total", t_total.elapsed().as_secs_f64()));
    result.map(|()| {
        log.info(format!("Total {}", secs(t_total.elapsed().as_secs_f64())));
        stats
    })
}

/// Delaunay, Voronoi, (reduction) and writing, as far as `--stop-after` asks.
fn later_stages(
    map: &Path,
    options: &CompileOptions,
    samples: &Samples,
    space: &MapSpace,
    log: &Log,
    progress: &dyn Progress,
    stats: &mut Stats,
) -> Result<(), CompileError> {
    if options.stop_after == Stage::Samples {
        log.info("Stopped after sampling (--stop-after samples).");
        return Ok(());
    }
    if samples.points.len() < 4 {
        return Err(CompileError::NoFreeSpace(samples.points.len()));
    }
    let t = Instant::now();
    log.info(format!(
        "Tetrahedralizing {} sample points ...",
        samples.points.len()
    ));
    let tri = Triangulation::new(&samples.points).map_err(CompileError::Delaunay)?;
    stats.tetrahedra = Some(tri.num_finite_cells());
    stats.duplicate_samples = tri.duplicates().len();
    stats.seconds.push(("delaunay", t.elapsed().as_secs_f64()));
    log.info(format!(
        "Delaunay: {} tetrahedra ({} with the hull) [{}]",
        tri.num_finite_cells(),
        tri.num_cells(),
        secs(t.elapsed().as_secs_f64())
    ));
    if options.stop_after == Stage::Delaunay {
        log.info("Stopped after the Delaunay stage (--stop-after delaunay).");
        return Ok(());
    }

    let t = Instant::now();
    log.info("Building voronoi graph ...");
    progress.start("Voronoi", 1);
    let voronoi_options = VoronoiOptions {
        spacing: samples.spacing,
        min_clearance: options.min_clearance,
    };
    let (graph, vs) = voronoi::extract(&tri, space, &voronoi_options);
    progress.advance(1);
    progress.finish();
    drop(tri);
    log.info(format!(
        "Voronoi vertices {}, inner vertices {}.",
        vs.voronoi_vertices, vs.inner_vertices
    ));
    log.info(format!(
        "Voronoi faces {}, inner faces {}, triangulated {}",
        vs.voronoi_faces, vs.inner_faces, vs.triangulated
    ));
    log.info(format!(
        "Exact wall distance as clearance; removed {} vertices with C <= m = {:.2} or clearance below {}",
        vs.removed_low_clearance, samples.spacing, options.min_clearance
    ));
    log.info(format!(
        "Nodes {}, Faces {} [{}]",
        vs.vertices,
        vs.faces,
        secs(t.elapsed().as_secs_f64())
    ));
    stats.seconds.push(("voronoi", t.elapsed().as_secs_f64()));
    stats.voronoi = Some(vs);
    if options.stop_after == Stage::Voronoi {
        log.info("Stopped after the Voronoi stage (--stop-after voronoi).");
        return Ok(());
    }
    // The volume must not leave free space between vertices (thesis fig. 3.9): bound
    // each face's interpolation error against the exact walls and lower its vertices.
    // This runs on the unreduced graph, whose small faces give tight bounds; the
    // reduction keeps its volume inside this one (condition A), so it stays free too.
    let t = Instant::now();
    let (graph, guard) = voronoi::guard_interpolation(graph, space, options.min_clearance);
    log.info(format!(
        "Interpolation guard: lowered {} vertices by up to {:.3} units, removed {}; nodes {}, faces {} [{}]",
        guard.lowered,
        guard.max_lowering,
        guard.removed,
        graph.vertices.len(),
        graph.faces.len(),
        secs(t.elapsed().as_secs_f64())
    ));
    stats.seconds.push(("guard", t.elapsed().as_secs_f64()));

    // Condition A keeps the reduced volume inside the unreduced one, which misses a
    // skin along the walls where reduced faces cut across its sheets; the walls
    // themselves allow more (issue 14: sight lines pass there), so the reduced
    // clearances are raised towards the walls, not back towards the unreduced ones
    // (the reduction's own raise, `ReduceOptions::raise`): the walls reach further,
    // and one raise costs half the time of two. An unreduced graph (`-rl 1.0`) is
    // raised the same way: the guard lowered each of its vertices by its curvature
    // margin, and without the raise `-rl 1.0` wrote a graph whose Visible missed more
    // sight lines than the one `-rl 0.99` writes (c1a0: 2.89 against 1.97 %).
    // BSP2VDG_NO_WALL_RAISE=1 raises as the reduction alone would, so that tests
    // can check condition A (the reduced volume inside the unreduced one) on the
    // output.
    let wall_raise = std::env::var_os("BSP2VDG_NO_WALL_RAISE").is_none();
    let mut graph = if options.reduction_limit < 1.0 {
        let reduce_options = reduce::ReduceOptions {
            limit: options.reduction_limit,
            min_vertices: options.reduction_floor,
            raise: !wall_raise,
            cost: options.reduction_cost,
        };
        let (reduced, rs) = reduce_graph(&graph, reduce_options, space, log, progress);
        stats.seconds.push(("reduce", rs.1));
        stats.reduce = Some(rs.0);
        reduced
    } else {
        log.info("Reduction limit 1.0: the graph is written unreduced.");
        graph
    };
    // Then each face raises its own corners on the same certificate grids: a
    // vertex's clearance must hold in every face around it, a corner only in its
    // face (format version 3).
    let t = Instant::now();
    let mut corners = wall_raise.then(|| {
        let (raise, radii, cs) = voronoi::raise_to_walls_and_corners(&mut graph, space);
        log.info(format!(
            "Raised {} vertices towards their wall distance, certified against the walls (by {:.1} units on average), and {} corners of {} faces above their vertex's clearance, each face certified alone (by {:.1} units on average) [{}]",
            raise.raised,
            raise.mean_raise,
            cs.corners,
            cs.faces,
            cs.mean_raise,
            secs(t.elapsed().as_secs_f64())
        ));
        stats
            .seconds
            .push(("wall_raise", t.elapsed().as_secs_f64()));
        radii
    });
    // Condition A keeps the reduced volume inside the guarded one and the raise is
    // certified; check every face anyway and repair faces where it evidently failed.
    // A graph neither reduced nor raised is the guard's own output: nothing to check.
    let changed_since_guard = options.reduction_limit < 1.0 || wall_raise;
    let graph = if changed_since_guard {
        let t = Instant::now();
        let (graph, repair) = voronoi::guard_with(
            graph,
            space,
            options.min_clearance,
            voronoi::GuardMode::Repair,
        );
        // An unreduced graph reaches this check through the raise alone.
        let what = if options.reduction_limit < 1.0 {
            "Reduction check"
        } else {
            "Raise check"
        };
        log.info(format!(
            "{what}: repaired {} vertices (lowered by up to {:.3} units), removed {}; nodes {}, faces {} [{}]",
            repair.lowered,
            repair.max_lowering,
            repair.removed,
            graph.vertices.len(),
            graph.faces.len(),
            secs(t.elapsed().as_secs_f64())
        ));
        stats.seconds.push(("check", t.elapsed().as_secs_f64()));
        graph
    } else {
        graph
    };
    // The repair keeps every face and only lowers clearances, so the corners stay
    // above them; a face whose volume it found reaching a wall is the corner
    // check's to put back.
    if let Some(radii) = corners.as_mut() {
        let t = Instant::now();
        let failed = voronoi::check_corners(&graph, radii, space);
        log.info(format!(
            "Corner check: {failed} faces back to their vertices' clearances [{}]",
            secs(t.elapsed().as_secs_f64())
        ));
        stats
            .seconds
            .push(("corner_check", t.elapsed().as_secs_f64()));
    }

    if graph.vertices.is_empty() || graph.faces.is_empty() {
        return Err(CompileError::EmptyGraph {
            min_clearance: options.min_clearance,
        });
    }
    let t = Instant::now();
    let bytes = write_vdg(map, options, &graph, corners.as_deref())?;
    stats.seconds.push(("write", t.elapsed().as_secs_f64()));
    log.info(format!(
        "Writing {} ...Wrote file, size {} [{}]",
        options.output.display(),
        bytes,
        secs(t.elapsed().as_secs_f64())
    ));
    stats.vdg = Some((graph.vertices.len(), graph.faces.len(), bytes));
    stats.output = Some(options.output.clone());
    Ok(())
}

/// Writes the graph with its build parameters and the source map's name and hash.
/// `corners`: the faces' own corner radii, one per face, if raised
/// ([`voronoi::raise_to_walls_and_corners`]).
fn write_vdg(
    map: &Path,
    options: &CompileOptions,
    graph: &Graph,
    corners: Option<&[[f64; 3]]>,
) -> Result<usize, CompileError> {
    let vdg_err = |error: String| CompileError::Vdg {
        path: options.output.clone(),
        error,
    };
    let source =
        std::fs::read(map).map_err(|e| vdg_err(format!("cannot read the map again: {e}")))?;
    let mut b = vdgformat::VdgBuilder::new();
    for (p, &c) in graph.vertices.iter().zip(&graph.clearance) {
        b.add_vertex(p.map(|x| x as f32), c as f32);
    }
    match corners {
        // Rounded as the vertex clearances are, so a corner never falls below its vertex's.
        Some(radii) => {
            debug_assert_eq!(radii.len(), graph.faces.len());
            for (f, r) in graph.faces.iter().zip(radii) {
                b.add_face_with_radii(*f, r.map(|x| x as f32));
            }
        }
        None => {
            for f in &graph.faces {
                b.add_face(*f);
            }
        }
    }
    b.set_source_hash(vdgformat::xxh64(&source, 0))
        .set_leaf_size(options.tree_leaf_size as f32);
    for (key, value) in crate::uptodate::recorded_options(options) {
        b.set_metadata(&key, &value);
    }
    // What the source is, for `vdgview info` (from its bytes: no path recorded).
    if let Some(v) = bsp::BspVersion::identify(&source) {
        b.set_metadata("source.game", v.game().name());
        b.set_metadata("source.format", v.name());
    }
    let bytes = b.to_bytes().map_err(|e| vdg_err(e.to_string()))?;
    let len = bytes.len();
    write_atomic(&options.output, |w| w.write_all(&bytes))?;
    Ok(len)
}

fn log_samples(log: &Log, s: &Samples) {
    if s.spacing > s.requested_spacing {
        log.warn(format!(
            "more than the sample cap at spacing {:.1}: spacing raised to {:.2}",
            s.requested_spacing, s.spacing
        ));
    }
    if s.hidden_samples > 0 {
        log.info(format!(
            "{} samples on walls the BSP tree has but no face shows (faces the compiler dropped)",
            s.hidden_samples
        ));
    }
    let k = &s.skipped;
    if k.total() > 0 {
        log.info(format!(
            "Skipped {} faces: {} trigger, {} clip, {} helper, {} transparent, {} liquid; {} not facing free space, {} with free space behind; {} outside subset",
            k.total(), k.trigger, k.clip, k.helper, k.transparent, k.liquid, k.not_facing_free, k.free_behind, k.outside_subset
        ));
    }
    log.detail(format!(
        "Sky faces {} (sampled at twice the spacing); {} points merged within {:.3} units",
        s.sky_faces, s.merged, s.merge_tolerance
    ));
}

/// Names the engine of a BSP file the reader refused, from its magic and version, so the
/// user learns "a Quake 3 map" rather than a number.
pub fn other_format(map: &Path) -> Option<String> {
    use std::io::Read;
    let mut head = [0u8; 8];
    std::fs::File::open(map).ok()?.read_exact(&mut head).ok()?;
    let version = i32::from_le_bytes([head[4], head[5], head[6], head[7]]);
    let engine = match (&head[..4], version) {
        (b"IBSP", 38) => "a Quake 2 map",
        (b"IBSP", 46) => "a Quake 3 map",
        (b"IBSP", 47) => "a Quake Live map",
        (b"IBSP", _) => "an id Tech 2/3 map",
        (b"VBSP", _) => "a Source engine map",
        (b"RBSP", _) => "a Raven map (Jedi Knight, Soldier of Fortune 2)",
        (b"FBSP", _) => "a QFusion map (Warsow)",
        (b"QBSP", _) => "a Qfusion/Quake 2 extended map",
        (b"EF2!", _) => "a Star Trek: Elite Force 2 map",
        (b"FAKK", _) => "a Heavy Metal: F.A.K.K. 2 map",
        (b"2PSB", _) | (b"BSP2", _) => return None,
        _ => return None,
    };
    Some(format!(
        "{engine} ({} version {version})",
        String::from_utf8_lossy(&head[..4])
    ))
}

/// The brush models used by entities of the given classnames, in model order.
pub fn entity_models(bsp: &Bsp, classes: &[String]) -> Vec<usize> {
    let mut models: Vec<usize> = bsp
        .entities
        .iter()
        .filter(|e| {
            classes
                .iter()
                .any(|c| c.eq_ignore_ascii_case(e.classname()))
        })
        .filter_map(|e| e.model_index())
        .filter(|&m| m > 0 && m < bsp.models.len())
        .collect();
    models.sort_unstable();
    models.dedup();
    models
}

/// `out/map.vdg` → `out/map.samples.txt`.
pub fn samples_path(output: &Path) -> PathBuf {
    output.with_extension("samples.txt")
}

/// Writes the samples through a temporary file, so no half-written file is left behind.
pub fn write_samples(
    path: &Path,
    points: &[[f64; 3]],
    format: SamplesFormat,
) -> Result<(), CompileError> {
    write_atomic(path, |w| {
        if format == SamplesFormat::Qhull {
            writeln!(w, "3\n{}", points.len())?;
        }
        for p in points {
            writeln!(w, "{} {} {}", p[0], p[1], p[2])?;
        }
        Ok(())
    })
}

/// Writes a file via a synced temporary sibling and a rename ([`toolbox::write_atomic`]).
pub fn write_atomic(
    path: &Path,
    body: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> Result<(), CompileError> {
    toolbox::write_atomic(path, body).map_err(|error| CompileError::Write {
        path: path.to_path_buf(),
        error,
    })
}
