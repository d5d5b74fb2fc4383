//! What the command line prints: the JSON report, the batch summary table, the
//! `-chart` of stage times, and the progress bar.

use bsp2vdg::log::secs;
use bsp2vdg::pipeline::{CompileError, Stats};
use bsp2vdg::progress::{CompileClock, Progress, format_left};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};
use toolbox::table::{self, Align};

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
                "missed_places": s.missed_places,
                "missed_pointfile": s.missed_pointfile.as_ref().map(|p| p.display().to_string()),
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

/// The batch summary table, one line per map; its columns as wide as their widest
/// cell (long map names, large counts).
pub fn summary_lines(results: &[(PathBuf, Outcome)]) -> Vec<String> {
    let cells = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let mut rows = vec![cells(&[
        "map", "faces", "sampled", "unusable", "samples", "spacing", "time", " status",
    ])];
    for (map, r) in results {
        let name = map
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let dashes = |status: String| {
            let mut row = vec![name.clone()];
            row.extend(std::iter::repeat_n("-".to_string(), 6));
            row.push(status);
            row
        };
        rows.push(match r {
            Outcome::Built(s) => vec![
                name.clone(),
                s.faces.to_string(),
                s.sampled_faces.to_string(),
                s.unusable_faces.to_string(),
                s.samples.to_string(),
                format!("{:.2}", s.sample_spacing),
                secs(s.seconds.last().map_or(0.0, |x| x.1)),
                format!(" ok{}", if s.leak.is_some() { " (leaks)" } else { "" }),
            ],
            Outcome::Current { .. } => dashes(" up to date (skipped; -force rebuilds)".into()),
            Outcome::Failed(e) => dashes(format!(" FAILED: {e}")),
        });
    }
    let mut aligns = vec![Align::Left];
    aligns.extend([Align::Right; 6]);
    let mut lines = table::lines(&rows, &aligns, 1);
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

/// `-chart`: the time of each stage as a bar, and the sizes the compile produced; the
/// columns as wide as the longest stage name and time.
pub fn chart_lines(s: &Stats) -> Vec<String> {
    let total = s
        .seconds
        .iter()
        .find(|(k, _)| *k == "total")
        .map_or(0.0, |x| x.1);
    let mut rows = Vec::new();
    for (stage, t) in s.seconds.iter().filter(|(k, _)| *k != "total") {
        let share = if total > 0.0 { t / total } else { 0.0 };
        rows.push(vec![
            stage.to_string(),
            secs(*t),
            format!("{:.1}%", 100.0 * share),
            format!("|{}", "#".repeat((40.0 * share).round() as usize)),
        ]);
    }
    rows.push(vec!["total".into(), secs(total), String::new()]);
    let mut lines = vec!["Stage chart (share of the total time):".to_string()];
    lines.extend(
        table::lines(&rows, &[Align::Left, Align::Right, Align::Right], 1)
            .into_iter()
            .map(|l| format!("  {l}")),
    );
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
/// as wide as the terminal (`-estimate` fits 80 columns). Every stage of the pipeline
/// shows its line, whether or not it reports progress of its own, with the seconds it has
/// run (a steady tick keeps them moving). With `-estimate` the line ends with the time
/// left of the whole compile ([`CompileClock`]: the work done weighed by the stages'
/// measured shares, smoothed). Log lines printed meanwhile go through
/// [`TerminalBar::printer`], which hides the bar while the line is printed above it.
#[derive(Default)]
pub struct TerminalBar {
    bar: Arc<Mutex<Option<indicatif::ProgressBar>>>,
    clock: Arc<Mutex<CompileClock>>,
    /// When the running stage began: its bars show the stage's seconds, also after the
    /// stage's own bar replaced its spinner.
    stage_began: Mutex<Option<std::time::Instant>>,
    /// Show the estimated time left (`-estimate`).
    estimate: bool,
}

/// How often the bar is redrawn when no work is reported (the elapsed seconds and the
/// estimate move on).
const TICK: std::time::Duration = std::time::Duration::from_millis(250);

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

    /// The bar's style: the stage, the bar and its percentage (a spinner for a stage that
    /// reports no progress), the stage's seconds and, with `-estimate`, the compile's
    /// time left.
    fn style(&self, counted: bool) -> Option<indicatif::ProgressStyle> {
        let work = if counted {
            "[{wide_bar}] {percent:>3}%"
        } else {
            "{spinner}"
        };
        let template = if self.estimate {
            format!("{{prefix:>10}} {work} {{elapsed:>4}} {{left}}")
        } else {
            format!("{{prefix:>10}} {work} {{elapsed:>4}}")
        };
        let clock = self.clock.clone();
        let left = move |_: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
            let left = clock.lock().ok().and_then(|mut c| c.seconds_left());
            let _ = w.write_str(&left_text(left));
        };
        indicatif::ProgressStyle::with_template(&template)
            .ok()
            .map(|s| s.with_key("left", left).progress_chars("=> "))
    }

    /// Replaces the shown bar by a new one. The previous one is cleared first: two bars
    /// drawing at once would each redraw the line over the other's.
    fn show(&self, label: &str, total: Option<u64>) {
        let Ok(mut shown) = self.bar.lock() else {
            return;
        };
        if let Some(old) = shown.take() {
            old.finish_and_clear();
        }
        let began = self
            .stage_began
            .lock()
            .ok()
            .and_then(|b| *b)
            .map_or(std::time::Duration::ZERO, |b| b.elapsed());
        let bar = indicatif::ProgressBar::new(total.unwrap_or(1).max(1)).with_elapsed(began);
        if let Some(style) = self.style(total.is_some()) {
            bar.set_style(style);
        }
        bar.set_prefix(label.to_string());
        bar.enable_steady_tick(TICK);
        *shown = Some(bar);
    }
}

/// The `-estimate` text at the end of the bar (at most 17 characters below 100 hours).
pub fn left_text(seconds: Option<f64>) -> String {
    match seconds {
        Some(s) => format!("~{} left", format_left(s)),
        None => "estimating".to_string(),
    }
}

/// What a stage's line is called.
pub fn stage_label(stage: &str) -> &str {
    match stage {
        "load" => "Loading",
        "sample" => "Sampling",
        "delaunay" => "Delaunay",
        "voronoi" => "Voronoi",
        "guard" => "Guard",
        "reduce" => "Reduce",
        "wall_raise" => "Raise",
        "check" => "Check",
        "corner_check" => "Corners",
        "write" => "Writing",
        other => other,
    }
}

impl Progress for TerminalBar {
    fn stage(&self, name: &str) {
        if let Ok(mut c) = self.clock.lock() {
            c.stage(name);
        }
        if let Ok(mut b) = self.stage_began.lock() {
            *b = Some(std::time::Instant::now());
        }
        self.show(stage_label(name), None);
    }

    fn start(&self, label: &str, total: u64) {
        // The clock's lock is released before the bar draws (its style reads the clock).
        if let Ok(mut c) = self.clock.lock() {
            c.start(total);
        }
        self.show(label, Some(total).filter(|&t| t > 1));
    }

    fn advance(&self, n: u64) {
        if let Ok(mut c) = self.clock.lock() {
            c.advance(n);
        }
        if let Ok(b) = self.bar.lock()
            && let Some(bar) = b.as_ref()
        {
            bar.inc(n);
        }
    }

    fn finish(&self) {
        let bar = self.bar.lock().ok().and_then(|mut b| b.take());
        if let Some(bar) = bar {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use toolbox::table::cell_spans;

    /// The chart's stage names (the longest, corner_check, is 12 characters), times of
    /// hours and the bars: each column at one position in every row.
    #[test]
    fn the_chart_columns_align() {
        let stats = Stats {
            seconds: vec![
                ("load", 0.03),
                ("reduce", 12_345.6),
                ("corner_check", 1.5),
                ("wall_raise", 0.0),
                ("total", 12_400.0),
            ],
            samples: 1_234_567,
            ..Stats::default()
        };
        let lines = chart_lines(&stats);
        let rows = &lines[1..lines.len() - 1];
        let spans: Vec<Vec<(usize, usize)>> = rows
            .iter()
            .zip(&stats.seconds)
            .map(|(l, (stage, t))| {
                let share = if *stage == "total" {
                    String::new()
                } else {
                    format!("{:.1}%", 100.0 * t / 12_400.0)
                };
                cell_spans(l, &[stage, &secs(*t), &share, "|"])
            })
            .collect();
        for (l, s) in rows.iter().zip(&spans) {
            assert_eq!(s[0].0, spans[0][0].0, "stage column: {l}");
            assert_eq!(s[1].1, spans[0][1].1, "time column: {l}\n{lines:#?}");
        }
        for (l, s) in rows.iter().zip(&spans).take(rows.len() - 1) {
            assert_eq!(s[2].1, spans[0][2].1, "share column: {l}\n{lines:#?}");
            assert_eq!(s[3].0, spans[0][3].0, "bar: {l}\n{lines:#?}");
        }
    }

    /// The batch summary with a long map name and large counts: every column ends (the
    /// name starts) at one position in every row, failures and skips too.
    #[test]
    fn the_summary_columns_align() {
        let big = Stats {
            faces: 1_234_567,
            sampled_faces: 1_000_000,
            unusable_faces: 12,
            samples: 98_765_432,
            sample_spacing: 24.0,
            seconds: vec![("total", 12_345.0)],
            ..Stats::default()
        };
        let small = Stats {
            faces: 6,
            samples: 40,
            sample_spacing: 1.5,
            seconds: vec![("total", 0.2)],
            ..Stats::default()
        };
        let results = vec![
            (
                PathBuf::from("maps/a_map_with_a_name_longer_than_thirty_two_characters.bsp"),
                Outcome::Built(Box::new(big)),
            ),
            (PathBuf::from("b.bsp"), Outcome::Built(Box::new(small))),
            (
                PathBuf::from("c.bsp"),
                Outcome::Current {
                    output: PathBuf::from("c.vdg"),
                },
            ),
            (
                PathBuf::from("d.bsp"),
                Outcome::Failed(CompileError::Game("x".into())),
            ),
        ];
        let lines = summary_lines(&results);
        let cells: [Vec<&str>; 5] = [
            vec![
                "map", "faces", "sampled", "unusable", "samples", "spacing", "time", "status",
            ],
            vec![
                "a_map_with_a_name_longer_than_thirty_two_characters.bsp",
                "1234567",
                "1000000",
                "12",
                "98765432",
                "24.00",
                "12345.0 s",
                "ok",
            ],
            vec!["b.bsp", "6", "0", "0", "40", "1.50", "0.20 s", "ok"],
            vec!["c.bsp", "-", "-", "-", "-", "-", "-", "up to date"],
            vec!["d.bsp", "-", "-", "-", "-", "-", "-", "FAILED"],
        ];
        let spans: Vec<_> = lines
            .iter()
            .zip(&cells)
            .map(|(l, c)| cell_spans(l, c))
            .collect();
        for (l, s) in lines.iter().zip(&spans) {
            assert_eq!(s.len(), 8, "{l}");
            assert_eq!(s[0].0, 0, "{l}");
            for k in 1..7 {
                assert_eq!(s[k].1, spans[0][k].1, "column {k}: {l}\n{lines:#?}");
            }
            assert_eq!(s[7].0, spans[0][7].0, "status: {l}\n{lines:#?}");
        }
    }

    /// The widest [`left_text`] below 100 hours.
    const LEFT_WIDTH: usize = "~99 h 59 min left".len();

    /// The bar's line at 80 columns: the fixed parts of the `-estimate` template and the
    /// longest estimate leave the bar at least 20 columns (indicatif shortens the bar,
    /// never the text, so a longer text would wrap).
    #[test]
    fn the_estimate_line_fits_80_columns() {
        for s in [0.0, 59.4, 3599.0, 359_999.0] {
            assert!(
                left_text(Some(s)).len() <= LEFT_WIDTH,
                "{}",
                left_text(Some(s))
            );
        }
        assert!(left_text(None).len() <= LEFT_WIDTH);
        // "{prefix:>10} [{wide_bar}] {percent:>3}% {elapsed:>4} {left}"
        let longest_label = bsp2vdg::pipeline::STAGE_NAMES
            .iter()
            .map(|s| stage_label(s).len())
            .max()
            .unwrap();
        assert!(longest_label <= 10);
        let fixed = 10 + " [".len() + "] ".len() + "100%".len() + " 59m 59s".len() + 1;
        assert!(80 - fixed - LEFT_WIDTH >= 20, "{fixed} + {LEFT_WIDTH}");
    }
}
