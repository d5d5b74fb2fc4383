//! What the command line prints: the JSON report, the batch summary table, the
//! `-chart` of stage times, and the progress bar.

use bsp2vdg::log::secs;
use bsp2vdg::pipeline::{CompileError, Stats};
use bsp2vdg::progress::Progress;
use serde_json::json;
use std::path::{Path, PathBuf};

/// What became of one map.
#[derive(Debug)]
pub enum Outcome {
    Built(Box<Stats>),
    /// The output is current (batch mode without `-force`): nothing was compiled.
    Current {
        output: PathBuf,
    },
    Failed(CompileError),
}

impl Outcome {
    pub fn ok(&self) -> bool {
        !matches!(self, Outcome::Failed(_))
    }
}

pub fn json_report(map: &Path, outcome: &Outcome, stop_after: &str) -> serde_json::Value {
    match outcome {
        Outcome::Failed(e) => {
            json!({ "map": map.display().to_string(), "ok": false, "error": e.to_string() })
        }
        Outcome::Current { output, .. } => json!({
            "map": map.display().to_string(),
            "ok": true,
            "up_to_date": true,
            "output": output.display().to_string(),
        }),
        Outcome::Built(s) => {
            let seconds: serde_json::Map<String, serde_json::Value> = s
                .seconds
                .iter()
                .map(|(k, v)| (k.to_string(), json!(v)))
                .collect();
            json!({
                "map": map.display().to_string(),
                "ok": true,
                "version": s.version,
                "game": s.game,
                "game_reason": s.game_reason,
                "unusable_faces": s.unusable_faces,
                "unusable_examples": s.unusable_examples,
                "leak": s.leak,
                "pointfile": s.pointfile.as_ref().map(|p| p.display().to_string()),
                "file_size": s.file_size,
                "bounds": [s.bounds.0, s.bounds.1],
                "faces": s.faces,
                "sampled_faces": s.sampled_faces,
                "sky_faces": s.sky_faces,
                "samples": s.samples,
                "sample_spacing": s.sample_spacing,
                "requested_spacing": s.requested_spacing,
                "subfaces": s.subfaces,
                "merged_samples": s.merged_samples,
                "hidden_samples": s.hidden_samples,
                "entity_models": s.entity_models,
                "samples_file": s.samples_file.as_ref().map(|p| p.display().to_string()),
                "tetrahedra": s.tetrahedra,
                "duplicate_samples": s.duplicate_samples,
                "voronoi_vertices": s.voronoi.as_ref().map(|v| v.voronoi_vertices),
                "inner_vertices": s.voronoi.as_ref().map(|v| v.inner_vertices),
                "voronoi_faces": s.voronoi.as_ref().map(|v| v.voronoi_faces),
                "inner_faces": s.voronoi.as_ref().map(|v| v.inner_faces),
                "triangulated_faces": s.voronoi.as_ref().map(|v| v.triangulated),
                "removed_low_clearance": s.voronoi.as_ref().map(|v| v.removed_low_clearance),
                "graph_vertices": s.voronoi.as_ref().map(|v| v.vertices),
                "graph_faces": s.voronoi.as_ref().map(|v| v.faces),
                "vertices": s.vdg.map(|v| v.0),
                "vdg_faces": s.vdg.map(|v| v.1),
                "bytes": s.vdg.map(|v| v.2),
                "reduced_vertices": s.reduce.as_ref().map(|r| r.vertices_after),
                "reduced_faces": s.reduce.as_ref().map(|r| r.faces_after),
                "reduce_stop_reason": s.reduce.as_ref().map(|r| r.stop.as_str()),
                "reduce_vertices_before": s.reduce.as_ref().map(|r| r.vertices_before),
                "reduce_target": s.reduce.as_ref().map(|r| r.target),
                "reduce_cost": s.reduce.as_ref().map(|r| r.cost.as_str()),
                "reduce_faces_before": s.reduce.as_ref().map(|r| r.faces_before),
                "reduce_lost_volume": s.reduce.as_ref().map(|r| r.lost_volume),
                "reduce_raise": s.reduce.as_ref().and_then(|r| r.raised_back).map(|r| [r.vertices as f64, r.total, r.seconds]),
                "reduce_kept_points": s.reduce.as_ref().map(|r| r.kept_points),
                "reduce_seam_phase_at": s.reduce.as_ref().and_then(|r| r.seam_phase_at),
                "reduce_seam_contractions": s.reduce.as_ref().map(|r| r.seam_contractions),
                "reduce_seam_collapses": s.reduce.as_ref().map(|r| r.seam_collapses),
                "reduce_fan_removals": s.reduce.as_ref().map(|r| r.fan_removals),
                "reduce_seam_deep_points": s.reduce.as_ref().map(|r| r.seam_deep_points),
                "reduce_refusals": s.reduce.as_ref().map(|r| {
                    r.refusals
                        .iter()
                        .map(|(k, n)| (k.to_string(), json!(n)))
                        .collect::<serde_json::Map<String, serde_json::Value>>()
                }),
                "output": s.output.as_ref().map(|p| p.display().to_string()),
                "threads": rayon::current_num_threads(),
                "stop_after": stop_after,
                "up_to_date": false,
                "seconds": seconds,
            })
        }
    }
}

/// The batch summary table, one line per map.
pub fn summary_lines(results: &[(PathBuf, Outcome)]) -> Vec<String> {
    let mut lines = vec![format!(
        "{:<32} {:>6} {:>8} {:>8} {:>9} {:>8} {:>9}  status",
        "map", "faces", "sampled", "unusable", "samples", "spacing", "time"
    )];
    for (map, r) in results {
        let name = map
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let dash = "-";
        lines.push(match r {
            Outcome::Built(s) => format!(
                "{:<32} {:>6} {:>8} {:>8} {:>9} {:>8.2} {:>9}  ok{}",
                name,
                s.faces,
                s.sampled_faces,
                s.unusable_faces,
                s.samples,
                s.sample_spacing,
                secs(s.seconds.last().map_or(0.0, |x| x.1)),
                if s.leak.is_some() { " (leaks)" } else { "" }
            ),
            Outcome::Current { .. } => format!(
                "{name:<32} {dash:>6} {dash:>8} {dash:>8} {dash:>9} {dash:>8} {dash:>9}  up to date (skipped; -force rebuilds)"
            ),
            Outcome::Failed(e) => format!(
                "{name:<32} {dash:>6} {dash:>8} {dash:>8} {dash:>9} {dash:>8} {dash:>9}  FAILED: {e}"
            ),
        });
    }
    let built = results
        .iter()
        .filter(|(_, r)| matches!(r, Outcome::Built(_)))
        .count();
    let current = results
        .iter()
        .filter(|(_, r)| matches!(r, Outcome::Current { .. }))
        .count();
    lines.push(format!(
        "{} maps: {built} compiled, {current} up to date, {} failed",
        results.len(),
        results.len() - built - current
    ));
    lines
}

/// `-chart`: the time of each stage as a bar, and the sizes the compile produced.
pub fn chart_lines(s: &Stats) -> Vec<String> {
    let total = s
        .seconds
        .iter()
        .find(|(k, _)| *k == "total")
        .map_or(0.0, |x| x.1);
    let mut lines = vec!["Stage chart (share of the total time):".to_string()];
    for (stage, t) in s.seconds.iter().filter(|(k, _)| *k != "total") {
        let share = if total > 0.0 { t / total } else { 0.0 };
        lines.push(format!(
            "  {stage:<9} {:>9} {:>5.1}% |{}",
            secs(*t),
            100.0 * share,
            "#".repeat((40.0 * share).round() as usize)
        ));
    }
    lines.push(format!("  {:<9} {:>9}", "total", secs(total)));
    let mut sizes = format!(
        "  samples {}, tetrahedra {}",
        s.samples,
        s.tetrahedra.map_or("-".into(), |t| t.to_string())
    );
    if let Some((v, f, b)) = s.vdg {
        sizes.push_str(&format!(", graph {v} vertices, {f} faces, {b} bytes"));
    }
    lines.push(sizes);
    lines
}

/// An indicatif bar on stderr, for interactive runs: one self-updating line per stage,
/// as wide as the terminal (`-estimate` fits 80 columns). Log lines printed meanwhile go
/// through [`TerminalBar::printer`], above the bar.
#[derive(Default)]
pub struct TerminalBar {
    bar: std::sync::Arc<std::sync::Mutex<Option<indicatif::ProgressBar>>>,
    /// Show the estimated time left (`-estimate`).
    estimate: bool,
}

impl TerminalBar {
    pub fn new(estimate: bool) -> TerminalBar {
        TerminalBar {
            estimate,
            ..TerminalBar::default()
        }
    }

    /// Prints a console line with the bar hidden meanwhile, so it never breaks the bar.
    pub fn printer(&self, to_stderr: bool) -> Box<dyn Fn(&str) + Send + Sync> {
        let bar = self.bar.clone();
        Box::new(move |line: &str| {
            let print = || {
                if to_stderr {
                    toolbox::errln!("{line}");
                } else {
                    toolbox::outln!("{line}");
                }
            };
            let active = bar.lock().ok().and_then(|b| b.clone());
            match active {
                Some(b) => b.suspend(print),
                None => print(),
            }
        })
    }
}

impl Progress for TerminalBar {
    fn start(&self, label: &str, total: u64) {
        let bar = indicatif::ProgressBar::new(total);
        let template = if self.estimate {
            "{msg:>10} [{wide_bar}] {percent:>3}% {elapsed} (~{eta} left)"
        } else {
            "{msg:>10} [{wide_bar}] {percent:>3}% {elapsed}"
        };
        if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(label.to_string());
        if let Ok(mut b) = self.bar.lock() {
            *b = Some(bar);
        }
    }

    fn advance(&self, n: u64) {
        if let Ok(b) = self.bar.lock()
            && let Some(bar) = b.as_ref()
        {
            bar.inc(n);
        }
    }

    fn finish(&self) {
        if let Ok(mut b) = self.bar.lock()
            && let Some(bar) = b.take()
        {
            bar.finish_and_clear();
        }
    }
}
