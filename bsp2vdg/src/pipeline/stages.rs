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
    let mut bsp = Bsp::open(map).map_err(|error| match other_engine(&error, map) {
        Some(format) => CompileError::OtherFormat {
            path: map.to_path_buf(),
            format,
        },
        None => CompileError::Bsp {
            path: map.to_path_buf(),
            error,
        },
    })?;
    if let Some(game) = cx.options.game {
        bsp.force_game(game).map_err(CompileError::Game)?;
    }
    let world = bsp.world();
    cx.stats.version = bsp.format_name().to_string();
    cx.stats.game = bsp.game.name().to_string();
    cx.stats.game_reason = bsp.game_reason.clone();
    cx.stats.file_size = bsp.file_size;
    cx.stats.bounds = (world.mins, world.maxs);
    cx.log.info(format!(
        "Loading model: {} ({} kB), {}, {} models, {} entities",
        map.display(),
        bsp.file_size.div_ceil(1024),
        bsp.format_name(),
        bsp.models.len(),
        bsp.entities.len()
    ));
    if bsp.unused_bad_records > 0 {
        cx.log.info(format!(
            "Ignored {} unused records with bad indices (the game never reads them)",
            bsp.unused_bad_records
        ));
    }
    cx.log
        .info(format!("Game: {} ({})", bsp.game.name(), bsp.game_reason));
    check_unusable_faces(cx, &bsp)?;
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

/// Faces the engine could not draw are not sampled (the tree still gives their
/// walls); the log names the first few. Where they are more than half of the world's
/// faces, the map is not what its file claims and the compile stops.
fn check_unusable_faces(cx: &mut Context, bsp: &Bsp) -> Result<(), CompileError> {
    if bsp.unusable_faces.is_empty() {
        return Ok(());
    }
    let examples = bsp::first_unusable_faces(bsp, 3);
    cx.stats.unusable_faces = bsp.unusable_faces.len();
    cx.stats.unusable_examples = examples.clone();
    let (bad, world_faces) = bsp.unusable_world_faces();
    if 2 * bad > world_faces {
        return Err(CompileError::UnusableFaces {
            unusable: bad,
            world_faces,
            examples,
        });
    }
    cx.log.warn(format!(
        "{} unusable faces not sampled (their plane, texture or edges do not resolve; the game never draws them): {examples}",
        bsp.unusable_faces.len()
    ));
    Ok(())
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
    let mut boundary = boundary::of_map(bsp, &oracle_options);
    if let Some(fence) = oracle.fence() {
        report_leak(cx, bsp);
        fence_boundary(&mut boundary, fence, bsp, sampling.spacing);
    }
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

/// A leaking map: the warning names where (the path from a player start out of the
/// world's bounds), and the path is written as a pointfile beside the output for the
/// editor.
fn report_leak(cx: &mut Context, bsp: &Bsp) {
    let fmt = |p: [f64; 3]| format!("({:.0} {:.0} {:.0})", p[0], p[1], p[2]);
    let leak = bsp::leak::find(bsp);
    let text = match &leak {
        Some(l) => format!(
            "the map leaks: free space from {} at {} reaches outside the world's bounds past {}",
            l.entity,
            fmt(l.from),
            fmt(l.exit)
        ),
        None => "the map leaks: free space reaches outside the world's bounds (no entity in free space has a path out at the search's resolution)".to_string(),
    };
    let mut line = format!("{text}; compiling the inside of the bounds");
    if let Some(l) = &leak {
        let path = cx
            .options
            .output
            .with_extension(bsp::leak::pointfile_extension(bsp.game));
        match toolbox::write_bytes_atomic(&path, bsp::leak::pointfile(&l.path).as_bytes()) {
            Ok(()) => {
                line.push_str(&format!("; pointfile {}", path.display()));
                cx.stats.pointfile = Some(path);
            }
            Err(e) => line.push_str(&format!(
                "; cannot write the pointfile {}: {e}",
                path.display()
            )),
        }
    }
    cx.log.warn(line.clone());
    cx.stats.leak = Some(text);
}

/// The walls of a leaking map's inside: the tree's boundary pieces outside the world's
/// bounds go (they bound the void), and where free space crosses the bounds the
/// bounds themselves become wall, in squares of twice the sample spacing.
fn fence_boundary(
    boundary: &mut Vec<BoundaryPolygon>,
    (lo, hi): ([f64; 3], [f64; 3]),
    bsp: &Bsp,
    spacing: f64,
) {
    let inside = |p: [f64; 3]| (0..3).all(|i| p[i] >= lo[i] - 0.5 && p[i] <= hi[i] + 0.5);
    boundary.retain(|b| {
        let n = b.vertices.len().max(1) as f64;
        let c = b.vertices.iter().fold([0.0; 3], |a, v| {
            [a[0] + v[0] / n, a[1] + v[1] / n, a[2] + v[2] / n]
        });
        inside(c)
    });
    let raw = bsp::oracle::Hull::from_nodes(bsp, 0);
    let open = |p: [f64; 3]| {
        let c = raw.contents(p);
        c != bsp::contents::SOLID && c != bsp::contents::SKY
    };
    let cell = (2.0 * spacing).max(8.0);
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let nu = ((hi[u] - lo[u]) / cell).ceil().max(1.0) as usize;
        let nv = ((hi[v] - lo[v]) / cell).ceil().max(1.0) as usize;
        for (side, plane, inward) in [(0, lo[axis], 1.0), (1, hi[axis], -1.0)] {
            let _ = side;
            for i in 0..nu {
                for j in 0..nv {
                    let (u0, u1) = (
                        lo[u] + i as f64 * cell,
                        (lo[u] + (i + 1) as f64 * cell).min(hi[u]),
                    );
                    let (v0, v1) = (
                        lo[v] + j as f64 * cell,
                        (lo[v] + (j + 1) as f64 * cell).min(hi[v]),
                    );
                    let at = |a: f64, b: f64, off: f64| {
                        let mut p = [0.0; 3];
                        p[axis] = plane + off;
                        p[u] = a;
                        p[v] = b;
                        p
                    };
                    let (cu, cv) = ((u0 + u1) * 0.5, (v0 + v1) * 0.5);
                    // Free space crosses the bounds here: free just inside and outside.
                    if !(open(at(cu, cv, inward)) && open(at(cu, cv, -inward))) {
                        continue;
                    }
                    let mut vertices = vec![
                        at(u0, v0, 0.0),
                        at(u1, v0, 0.0),
                        at(u1, v1, 0.0),
                        at(u0, v1, 0.0),
                    ];
                    let mut normal = [0.0; 3];
                    normal[axis] = inward;
                    // Wound counter-clockwise seen from the free side.
                    let e1 = [0, 1, 2].map(|k| vertices[1][k] - vertices[0][k]);
                    let e2 = [0, 1, 2].map(|k| vertices[2][k] - vertices[0][k]);
                    let cross = toolbox::vec3::cross(e1, e2);
                    if toolbox::vec3::dot(cross, normal) < 0.0 {
                        vertices.reverse();
                    }
                    boundary.push(BoundaryPolygon {
                        vertices,
                        normal,
                        obstacle: bsp::contents::SOLID,
                    });
                }
            }
        }
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
    let tri = Triangulation::new_reporting(&samples.points, cx.progress)
        .map_err(CompileError::Delaunay)?;
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
    let voronoi_options = VoronoiOptions {
        spacing: samples.spacing,
        min_clearance: cx.options.min_clearance,
    };
    let (graph, vs) = voronoi::extract_reporting(&tri, space, &voronoi_options, cx.progress);
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
        "Exact wall distance as clearance; removed {} vertices with C <= m = {:.2} and clearance below m/2, or clearance below {}",
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
    let (graph, guard) = guard::guard_with(
        graph,
        space,
        guard::KEEP_CLEARANCE.min(cx.options.min_clearance),
        GuardMode::Bound,
        cx.progress,
    );
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
    cx.standing = Some(keep[..standing].to_vec());
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
    let (raise, radii, cs) = raise::raise_to_walls_and_corners(graph, space, cx.progress);
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
    let (graph, repair) = guard::guard_with(
        graph,
        space,
        options.min_clearance,
        GuardMode::Repair,
        cx.progress,
    );
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
    let failed = guard::check_corners(graph, radii, space, cx.progress);
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
    let bytes = write::write_vdg(
        map,
        options,
        graph,
        corners,
        (&cx.stats.game, &cx.stats.version),
    )?;
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

/// The standing places the written graph misses (outside its volume; see
/// [`super::pointfiles`]): a warning naming the count and a pointfile through them,
/// `OUT.missed.pts` (`.lin`), for the editor. A stale one from an earlier compile is
/// removed when nothing is missed.
pub fn report_missed_places(cx: &mut Context, space: &MapSpace) {
    use rayon::prelude::*;
    let Some(output) = cx.stats.output.clone() else {
        return;
    };
    let standing = cx.standing.take().unwrap_or_else(|| {
        bsp::player::grid_origins(
            space.oracle,
            space.bounds.0,
            space.bounds.1,
            bsp::player::KEEP_SPACING,
        )
    });
    let path = super::pointfiles::missed_path(&output, space.game);
    let bytes = match std::fs::read(&output) {
        Ok(b) => b,
        Err(e) => {
            cx.log.warn(format!(
                "cannot read back {} to check its standing places: {e}",
                output.display()
            ));
            return;
        }
    };
    let file = match vdgformat::VdgFile::from_bytes(&bytes) {
        Ok(f) => f,
        Err(e) => {
            cx.log.warn(format!(
                "cannot open {} to check its standing places: {e}",
                output.display()
            ));
            return;
        }
    };
    let graph = file.graph();
    let missed: Vec<[f64; 3]> = standing
        .par_iter()
        .filter(|p| !graph.contains(p.map(|x| x as f32)))
        .copied()
        .collect();
    cx.stats.missed_places = Some(missed.len());
    if missed.is_empty() {
        let _ = std::fs::remove_file(&path);
        cx.log.detail(format!(
            "Every one of the {} standing places lies inside the graph's volume",
            standing.len()
        ));
        return;
    }
    let groups = super::pointfiles::clusters(&missed, 1.5 * bsp::player::KEEP_SPACING);
    let c = super::pointfiles::centre_member(&groups[0]);
    let mut line = format!(
        "{} of {} standing places lie outside the graph's volume (the camera has no graph there), in {} {}; the largest, {} places, around ({:.0} {:.0} {:.0})",
        missed.len(),
        standing.len(),
        groups.len(),
        if groups.len() == 1 {
            "cluster"
        } else {
            "clusters"
        },
        groups[0].len(),
        c[0],
        c[1],
        c[2]
    );
    match super::pointfiles::write(&path, &super::pointfiles::path_through(&groups)) {
        Ok(()) => {
            line.push_str(&format!("; pointfile {}", path.display()));
            cx.stats.missed_pointfile = Some(path);
        }
        Err(e) => line.push_str(&format!(
            "; cannot write the pointfile {}: {e}",
            path.display()
        )),
    }
    cx.log.warn(line);
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
