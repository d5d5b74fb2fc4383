//! The compile driver: the stages in the order they run, each called on the
//! [`Context`] (options, log, progress, named timers), up to the stage the user asked
//! for. The stages' log lines and statistics live in [`stages`]; their work in the
//! stage modules (`sample`, `delaunay`, `voronoi`, `guard`, `reduce`, `raise`, `write`).
//!
//! The order matters where a later stage relies on an earlier one's guarantee: the
//! guard proves the unreduced volume free; the reduction keeps its volume inside that
//! one (condition A); the wall raise is certified against the walls itself; the check
//! after them repairs a face where a guarantee evidently failed; the corner check does
//! the same for the faces' own corner radii.

mod budget;
mod context;
mod error;
pub mod pointfiles;
pub mod stages;
mod stats;

pub use budget::Budget;
#[cfg(test)]
pub(crate) use budget::stopped_in;
pub use context::Context;
pub use error::{CompileError, Pointfile, other_format};
pub use stats::Stats;

use crate::log::{Log, secs};
use crate::options::{CompileOptions, Stage};
use crate::progress::Progress;
use crate::space::MapSpace;
use bsp::walls::Walls;
use std::path::Path;

/// Compiles one map as `options` say, within the map's budget ([`Budget`]).
pub fn compile(
    map: &Path,
    options: &CompileOptions,
    log: &Log,
    progress: &dyn Progress,
) -> Result<Stats, CompileError> {
    let size = std::fs::metadata(map).map(|m| m.len()).unwrap_or(0);
    let budgeted = budget::Budgeted {
        inner: progress,
        budget: Budget::for_map(size, options.budget),
        stage: Default::default(),
    };
    // A stage over its time unwinds to here (with no panic message): its work is
    // dropped on the way and the map fails with the stage named.
    let run = std::panic::AssertUnwindSafe(|| compile_within(map, options, log, &budgeted));
    match std::panic::catch_unwind(run) {
        Ok(result) => result,
        Err(payload) => match payload.downcast::<budget::OutOfTime>() {
            Ok(out) => {
                progress.finish();
                Err(CompileError::OverBudget {
                    stage: stage_name(&out.stage),
                    what: format!(
                        "{:.0} s for a map of {} kB",
                        out.seconds,
                        size.div_ceil(1024)
                    ),
                })
            }
            Err(other) => std::panic::resume_unwind(other),
        },
    }
}

/// Every stage's name, in the order a compile runs them (the names `--json`, the
/// budget and the progress display use).
pub const STAGE_NAMES: [&str; 10] = [
    "load",
    "sample",
    "delaunay",
    "voronoi",
    "guard",
    "reduce",
    "wall_raise",
    "check",
    "corner_check",
    "write",
];

/// The stage names the budget reports, as `&'static str`.
fn stage_name(stage: &str) -> &'static str {
    STAGE_NAMES
        .iter()
        .find(|n| stage.starts_with(*n))
        .copied()
        .unwrap_or("compile")
}

fn compile_within(
    map: &Path,
    options: &CompileOptions,
    log: &Log,
    progress: &budget::Budgeted,
) -> Result<Stats, CompileError> {
    let mut cx = Context::new(options, log, progress);
    cx.budget = progress.budget;
    let bsp = cx.stage("load", |cx| stages::load_map(cx, map))?;
    let sampled = cx.stage("sample", |cx| stages::sample_walls(cx, &bsp));
    if options.save_samples {
        stages::save_samples(&mut cx, &sampled.samples)?;
    }
    let world = bsp.world();
    let space = MapSpace {
        oracle: &sampled.oracle,
        walls: Walls::from_boundary(&sampled.boundary),
        bounds: (world.mins.map(f64::from), world.maxs.map(f64::from)),
        game: bsp.game,
    };
    build_graph(&mut cx, map, &sampled.samples, &space)
        .map_err(|e| with_failure_pointfile(e, &cx, &bsp))?;
    let total = cx.total_seconds();
    cx.stats.seconds.push(("total", total));
    log.info(format!("Total {}", secs(total)));
    Ok(cx.stats)
}

/// From the samples to the written graph, as far as `--stop-after` asks.
fn build_graph(
    cx: &mut Context,
    map: &Path,
    samples: &crate::sample::Samples,
    space: &MapSpace,
) -> Result<(), CompileError> {
    let options = cx.options;
    if stopped_after(cx, Stage::Samples) {
        return Ok(());
    }
    if samples.points.len() < 4 {
        return Err(CompileError::NoFreeSpace {
            samples: samples.points.len(),
            pointfile: None,
        });
    }
    if let Some(b) = cx.budget {
        // About 6.5 tetrahedra per point, each with its vertices, neighbours and
        // circumsphere (~100 bytes), and the Voronoi graph built from them.
        let n = samples.points.len() as f64;
        b.check_memory(
            "delaunay",
            n * 6.5 * 200.0,
            &format!("{} samples", samples.points.len()),
        )?;
    }
    let tri = cx.stage("delaunay", |cx| stages::tetrahedralize(cx, samples))?;
    if stopped_after(cx, Stage::Delaunay) {
        return Ok(());
    }
    let graph = cx.stage("voronoi", |cx| {
        stages::extract_voronoi(cx, tri, samples, space)
    });
    if stopped_after(cx, Stage::Voronoi) {
        return Ok(());
    }
    let graph = cx.stage("guard", |cx| stages::guard_volume(cx, graph, space));
    let reduced = options.reduction_limit < 1.0;
    if let Some(b) = cx.budget {
        // The reduction's mesh, queue and volume bookkeeping: a few hundred bytes per
        // vertex and face of its input.
        let (v, f) = (graph.vertices.len() as f64, graph.faces.len() as f64);
        b.check_memory(
            "reduce",
            v * 600.0 + f * 300.0,
            &format!(
                "a graph of {} vertices and {} faces",
                graph.vertices.len(),
                graph.faces.len()
            ),
        )?;
    }
    let mut graph = if reduced {
        cx.stage("reduce", |cx| stages::reduce_graph(cx, &graph, space))
    } else {
        cx.log
            .info("Reduction limit 1.0: the graph is written unreduced.");
        graph
    };
    if let (Some(b), true) = (cx.budget, options.wall_raise) {
        // The raise's certificate grids, one per face, grow with the faces' lengths.
        b.check_memory(
            "wall_raise",
            crate::raise::grid_bytes(&graph),
            &format!("the certificate grids of {} faces", graph.faces.len()),
        )?;
    }
    // An unreduced graph is raised too: the guard lowered each of its vertices by its
    // curvature margin, which the raise gives back where the walls allow.
    let mut corners = options.wall_raise.then(|| {
        cx.stage("wall_raise", |cx| {
            stages::raise_to_walls(cx, &mut graph, space)
        })
    });
    // A graph neither reduced nor raised is the guard's own output: nothing to check.
    let graph = if reduced || options.wall_raise {
        cx.stage("check", |cx| stages::check_volume(cx, graph, space))
    } else {
        graph
    };
    if let Some(radii) = corners.as_mut() {
        cx.stage("corner_check", |cx| {
            stages::check_corners(cx, &graph, radii, space)
        });
    }
    if graph.vertices.is_empty() || graph.faces.is_empty() {
        return Err(CompileError::EmptyGraph {
            min_clearance: options.min_clearance,
            pointfile: None,
        });
    }
    cx.stage("write", |cx| {
        stages::write_graph(cx, map, &graph, corners.as_deref())?;
        stages::report_missed_places(cx, space);
        Ok(())
    })
}

/// A compile that found no graph writes a pointfile of where free space was looked for
/// ([`pointfiles`]), named in its error; a leaking map's pointfile (the same name) is
/// kept and named instead.
fn with_failure_pointfile(e: CompileError, cx: &Context, bsp: &bsp::Bsp) -> CompileError {
    let pointfile = || {
        if let Some(path) = &cx.stats.pointfile {
            return Pointfile {
                path: path.clone(),
                shows: "where the map leaks",
                error: None,
            };
        }
        let path = pointfiles::failure_path(&cx.options.output, bsp.game);
        let (points, shows) = pointfiles::where_free_space_was_looked_for(bsp);
        let error = pointfiles::write(&path, &points)
            .err()
            .map(|e| e.to_string());
        Pointfile { path, shows, error }
    };
    match e {
        CompileError::NoFreeSpace { samples, .. } => CompileError::NoFreeSpace {
            samples,
            pointfile: Some(pointfile()),
        },
        CompileError::EmptyGraph { min_clearance, .. } => CompileError::EmptyGraph {
            min_clearance,
            pointfile: Some(pointfile()),
        },
        other => other,
    }
}

/// Whether the compile stops after `stage` (`--stop-after`), saying so in the log.
fn stopped_after(cx: &Context, stage: Stage) -> bool {
    if cx.options.stop_after != stage {
        return false;
    }
    cx.log.info(match stage {
        Stage::Samples => "Stopped after sampling (--stop-after samples).",
        Stage::Delaunay => "Stopped after the Delaunay stage (--stop-after delaunay).",
        Stage::Voronoi => "Stopped after the Voronoi stage (--stop-after voronoi).",
        Stage::Reduce => "",
    });
    true
}
