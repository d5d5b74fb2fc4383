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

mod context;
mod error;
pub mod stages;
mod stats;

pub use context::Context;
pub use error::{CompileError, other_format};
pub use stats::Stats;

use crate::log::{Log, secs};
use crate::options::{CompileOptions, Stage};
use crate::progress::Progress;
use crate::space::MapSpace;
use bsp::walls::Walls;
use std::path::Path;

/// Compiles one map as `options` say.
pub fn compile(
    map: &Path,
    options: &CompileOptions,
    log: &Log,
    progress: &dyn Progress,
) -> Result<Stats, CompileError> {
    let mut cx = Context::new(options, log, progress);
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
        game: bsp.version.game(),
    };
    build_graph(&mut cx, map, &sampled.samples, &space)?;
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
        return Err(CompileError::NoFreeSpace(samples.points.len()));
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
    let mut graph = if reduced {
        cx.stage("reduce", |cx| stages::reduce_graph(cx, &graph, space))
    } else {
        cx.log
            .info("Reduction limit 1.0: the graph is written unreduced.");
        graph
    };
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
        });
    }
    cx.stage("write", |cx| {
        stages::write_graph(cx, map, &graph, corners.as_deref())
    })
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
