//! The stages of a compile as the driver calls them: each takes the [`Context`], runs
//! its part of the pipeline (the stage's own module does the work) and writes its log
//! lines and statistics.

use super::{CompileError, Context};
use crate::delaunay::Triangulation;
use crate::graph::Graph;
use crate::guard::{self, GuardMode};
use crate::log::{Log, secs};
use crate::raise;
use crate::reduce;
use crate::sample::{self, Samples};
use crate::space::MapSpace;
use crate::voronoi::{self, VoronoiOptions};
use crate::write;
use bsp::Bsp;
use bsp::boundary::{self, BoundaryPolygon};
use bsp::oracle::{Oracle, OracleOptions};
use std::path::Path;

/// Opens the map; a file of another engine is named as such. A map of an engine we
/// read that the reader refuses (truncated, corrupt) keeps the reader's own error,
/// which names the lump and the problem.
pub fn load_map(cx: &mut Context, map: &Path) -> Result<Bsp, CompileError> {
    let bsp = Bsp::open(map).map_err(|error| match other_engine(&error, map) {
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
    cx.stats.version = bsp.version.name().to_string();
    cx.stats.file_size = bsp.file_size;
    cx.stats.bounds = (world.mins, world.maxs);
    cx.log.info(format!(
        "Loading model: {} ({} kB), {}, {} models, {} entities",
        map.display(),
        bsp.file_size.div_ceil(1024),
        bsp.version.name(),
        bsp.models.len(),
        bsp.entities.len()
    ));
    if bsp.unused_bad_records > 0 {
        cx.log.info(format!(
            "Ignored {} unused records with bad indices (the game never reads them)",
            bsp.unused_bad_records
        ));
    }
    cx.log.info(format!(
        "Bounding Box ({:.1},{:.1},{:.1})-({:.1},{:.1},{:.1})",
        world.mins[0], world.mins[1], world.mins[2], world.maxs[0], world.maxs[1], world.maxs[2]
    ));
    Ok(bsp)
}

/// The engine of a file the reader refused because of its format, not its content.
fn other_engine(error: &bsp::BspError, map: &Path) -> Option<String> {
    match error {
        bsp::BspError::Unsupported { .. } | bsp::BspError::UnknownVersion { .. } => {
            super::other_format(map)
        }
        _ => None,
    }
}

/// The map's free space as the later stages ask about it, and the samples on its walls.
pub struct SampledMap {
    pub oracle: Oracle,
    pub boundary: Vec<BoundaryPolygon>,
    pub samples: Samples,
}

/// Builds the free-space oracle (with the chosen brush entities as walls) and samples
/// the walls: the faces that bound free space and the tree's walls no face shows.
pub fn sample_walls(cx: &mut Context, bsp: &Bsp) -> SampledMap {
    let options = cx.options;
    let mut sampling = options.sampling.clone();
    sampling.models = sample::entity_models(bsp, &options.entity_classes);
    cx.stats.entity_models = sampling.models.len();
    if !sampling.models.is_empty() {
        cx.log.info(format!(
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
    let oracle = Oracle::new(bsp, &oracle_options);
    let boundary = boundary::of_map(bsp, &oracle_options);
    let faces = sample::wall_faces(bsp, &sampling.models, &oracle, &boundary);
    cx.log.info(format!(
        "Sampling from {} faces and {} pieces of the BSP's obstacle boundary ...",
        faces.len() - boundary.len(),
        boundary.len()
    ));
    cx.progress.start("Sampling", 1);
    let samples = sample::sample_faces(&faces, &sampling);
    cx.progress.advance(1);
    cx.progress.finish();
    log_samples(cx.log, &samples);
    let stats = &mut cx.stats;
    stats.faces = samples.faces;
    stats.sampled_faces = samples.sampled_faces;
    stats.sky_faces = samples.sky_faces;
    stats.samples = samples.points.len();
    stats.sample_spacing = samples.spacing;
    stats.requested_spacing = samples.requested_spacing;
    stats.subfaces = samples.subfaces;
    stats.merged_samples = samples.merged;
    stats.hidden_samples = samples.hidden_samples;
    cx.log.info(format!(
        "Sampled {} points from {} faces ({} subfaces) [{}]",
        samples.points.len(),
        samples.sampled_faces,
        samples.subfaces,
        secs(cx.stage_seconds())
    ));
    SampledMap {
        oracle,
        boundary,
        samples,
    }
}

/// `-savesamples`: the samples as text beside the output.
pub fn save_samples(cx: &mut Context, samples: &Samples) -> Result<(), CompileError> {
    let path = crate::options::samples_path(&cx.options.output);
    write::write_samples(&path, &samples.points, cx.options.samples_format)?;
    cx.log.info(format!(
        "Wrote {} samples to {}",
        samples.points.len(),
        path.display()
    ));
    cx.stats.samples_file = Some(path);
    Ok(())
}

/// The 3D Delaunay tetrahedralization of the samples.
pub fn tetrahedralize(cx: &mut Context, samples: &Samples) -> Result<Triangulation, CompileError> {
    cx.log.info(format!(
        "Tetrahedralizing {} sample points ...",
        samples.points.len()
    ));
    let tri = Triangulation::new(&samples.points).map_err(CompileError::Delaunay)?;
    cx.stats.tetrahedra = Some(tri.num_finite_cells());
    cx.stats.duplicate_samples = tri.duplicates().len();
    cx.log.info(format!(
        "Delaunay: {} tetrahedra ({} with the hull) [{}]",
        tri.num_finite_cells(),
        tri.num_cells(),
        secs(cx.stage_seconds())
    ));
    Ok(tri)
}

/// The Voronoi graph in free space, each vertex with its exact wall distance.
pub fn extract_voronoi(
    cx: &mut Context,
    tri: Triangulation,
    samples: &Samples,
    space: &MapSpace,
) -> Graph {
    let log = cx.log;
    log.info("Building voronoi graph ...");
    cx.progress.start("Voronoi", 1);
    let voronoi_options = VoronoiOptions {
        spacing: samples.spacing,
        min_clearance: cx.options.min_clearance,
    };
    let (graph, vs) = voronoi::extract(&tri, space, &voronoi_options);
    cx.progress.advance(1);
    cx.progress.finish();
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
        vs.removed_low_clearance, samples.spacing, cx.options.min_clearance
    ));
    log.info(format!(
        "Nodes {}, Faces {} [{}]",
        vs.vertices,
        vs.faces,
        secs(cx.stage_seconds())
    ));
    cx.stats.voronoi = Some(vs);
    graph
}

/// The interpolation guard on the unreduced graph: the volume must not leave free
/// space between vertices, so each face's interpolation error is bounded against the
/// exact walls and its vertices lowered. It runs before the reduction, whose small
/// faces give tight bounds; the reduction keeps its volume inside this one
/// (condition A), so it stays free too.
pub fn guard_volume(cx: &mut Context, graph: Graph, space: &MapSpace) -> Graph {
    let (graph, guard) = guard::guard_interpolation(graph, space, cx.options.min_clearance);
    cx.log.info(format!(
        "Interpolation guard: lowered {} vertices by up to {:.3} units, removed {}; nodes {}, faces {} [{}]",
        guard.lowered,
        guard.max_lowering,
        guard.removed,
        graph.vertices.len(),
        graph.faces.len(),
        secs(cx.stage_seconds())
    ));
    graph
}

/// Reduces the graph by edge swaps and the seam phase (thesis ch. 4), keeping the
/// places where a player stands or crouches inside the volume.
pub fn reduce_graph(cx: &mut Context, graph: &Graph, space: &MapSpace) -> Graph {
    let (log, progress) = (cx.log, cx.progress);
    let options = reduce::ReduceOptions {
        limit: cx.options.reduction_limit,
        min_vertices: cx.options.reduction_floor,
        // The wall raise after the reduction replaces the reduction's own raise.
        raise: !cx.options.wall_raise,
        cost: cx.options.reduction_cost,
        coverage_guards: cx.options.coverage_guards,
    };
    // Where a standing player is, the camera's target is: the reduction keeps those
    // places inside the volume (a grid of floor points of clip hull 1), and the eyes
    // of the places where a player only fits crouching (vents, crawl spaces: the
    // unreduced graph holds most of them, and without this the reduction would drop
    // many).
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
        secs(cx.stage_seconds())
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
    cx.stats.reduce = Some(rs);
    reduced
}

/// The wall raise: the clearances rise towards the walls, then each face's own corner
/// radii, both certified against the walls (see [`crate::raise`]). Returns the
/// corner radii, one per face.
pub fn raise_to_walls(cx: &mut Context, graph: &mut Graph, space: &MapSpace) -> Vec<[f64; 3]> {
    let (raise, radii, cs) = raise::raise_to_walls_and_corners(graph, space);
    cx.log.info(format!(
        "Raised {} vertices towards their wall distance, certified against the walls (by {:.1} units on average), and {} corners of {} faces above their vertex's clearance, each face certified alone (by {:.1} units on average) [{}]",
        raise.raised,
        raise.mean_raise,
        cs.corners,
        cs.faces,
        cs.mean_raise,
        secs(cx.stage_seconds())
    ));
    radii
}

/// The check after the reduction and the raise: condition A keeps the reduced volume
/// inside the guarded one and the raise is certified, but every face is checked
/// anyway, and faces where it evidently failed are repaired.
pub fn check_volume(cx: &mut Context, graph: Graph, space: &MapSpace) -> Graph {
    let options = cx.options;
    let (graph, repair) = guard::guard_with(graph, space, options.min_clearance, GuardMode::Repair);
    // An unreduced graph reaches this check through the raise alone.
    let what = if options.reduction_limit < 1.0 {
        "Reduction check"
    } else {
        "Raise check"
    };
    cx.log.info(format!(
        "{what}: repaired {} vertices (lowered by up to {:.3} units), removed {}; nodes {}, faces {} [{}]",
        repair.lowered,
        repair.max_lowering,
        repair.removed,
        graph.vertices.len(),
        graph.faces.len(),
        secs(cx.stage_seconds())
    ));
    graph
}

/// The corner check: the repair keeps every face and only lowers clearances, so the
/// corners stay above them; a face whose volume it found reaching a wall falls back
/// to its vertices' clearances here.
pub fn check_corners(cx: &mut Context, graph: &Graph, radii: &mut [[f64; 3]], space: &MapSpace) {
    let failed = guard::check_corners(graph, radii, space);
    cx.log.info(format!(
        "Corner check: {failed} faces back to their vertices' clearances [{}]",
        secs(cx.stage_seconds())
    ));
}

/// Writes the `.vdg`.
pub fn write_graph(
    cx: &mut Context,
    map: &Path,
    graph: &Graph,
    corners: Option<&[[f64; 3]]>,
) -> Result<(), CompileError> {
    let options = cx.options;
    let bytes = write::write_vdg(map, options, graph, corners)?;
    cx.log.info(format!(
        "Writing {} ...Wrote file, size {} [{}]",
        options.output.display(),
        bytes,
        secs(cx.stage_seconds())
    ));
    cx.stats.vdg = Some((graph.vertices.len(), graph.faces.len(), bytes));
    cx.stats.output = Some(options.output.clone());
    Ok(())
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
