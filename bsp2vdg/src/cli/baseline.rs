//! CI regression mode. `bsp2vdg --update-baseline DIR MAPS...` compiles each map and
//! stores its `.vdg` and statistics (counts, bytes, seconds and the quality figures of
//! [`vdgcheck`], the same code as `vdgview check`) in DIR; `bsp2vdg --baseline DIR
//! MAPS...` compiles again and compares. A byte-identical graph passes at once; else
//! counts, bytes, quality figures and time are compared within tolerances, a table (or
//! `--json`) shows each figure, and any figure beyond its tolerance is a regression.
//!
//! Quality figures are taken from the check's JSON by name, so figures the check gains
//! later are compared too: names with `coverage` must not fall, `leak` and names ending
//! in `_fp`, `_fn`, `_fn_inside` or `_fn_query` must not rise, by more than their tolerance.

use super::args::usage;
use anyhow::{Context, Result};
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::CompileOptions;
use bsp2vdg::pipeline;
use bsp2vdg::progress::NoProgress;
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use vdgcheck::{CheckOptions, check};

/// How far a figure may move before it is a regression. Defaults are documented in the
/// README; a TOML file (`--tolerances FILE`) overrides any of them:
///
/// ```toml
/// counts = 0.02        # vertices, faces: relative change either way
/// bytes = 0.02         # file size: relative change either way
/// seconds = 0.5        # compile time: relative slow-down
/// min_seconds = 1.0    # times below this (in the baseline) are not compared
/// quality = 0.01       # quality figures: absolute change in the bad direction
/// [figures]            # per quality figure, overriding `quality`
/// leak = 0.0
/// visible_fp = 0.0
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Tolerances {
    pub counts: f64,
    pub bytes: f64,
    pub seconds: f64,
    pub min_seconds: f64,
    pub quality: f64,
    pub figures: BTreeMap<String, f64>,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances {
            counts: 0.02,
            bytes: 0.02,
            seconds: 0.5,
            min_seconds: 1.0,
            quality: 0.01,
            figures: [("leak", 0.0), ("visible_fp", 0.0)]
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
        }
    }
}

impl Tolerances {
    /// The defaults, overridden by the TOML file when given.
    pub fn load(path: Option<&Path>) -> Result<Tolerances> {
        let Some(path) = path else {
            return Ok(Tolerances::default());
        };
        // A tolerances file that cannot be read is a configuration error (exit 2), not
        // a regression: CI must tell a typo from a worse graph.
        let text = match std::fs::read_to_string(path) {
            Ok(t) => t,
            Err(e) => usage!("cannot read the tolerances {}: {e}", path.display()),
        };
        let mut t: Tolerances = match toml::from_str(&text) {
            Ok(t) => t,
            Err(e) => usage!("{}: {}", path.display(), e.message().trim()),
        };
        // A figure not named in the file keeps its default.
        for (k, v) in Tolerances::default().figures {
            t.figures.entry(k).or_insert(v);
        }
        for (k, v) in [
            ("counts", t.counts),
            ("bytes", t.bytes),
            ("seconds", t.seconds),
            ("min_seconds", t.min_seconds),
            ("quality", t.quality),
        ]
        .into_iter()
        .chain(t.figures.iter().map(|(k, v)| (k.as_str(), *v)))
        {
            if !(v.is_finite() && v >= 0.0) {
                usage!(
                    "{}: tolerance {k} must be zero or positive, got {v}",
                    path.display()
                );
            }
        }
        Ok(t)
    }
}

/// Which way a quality figure should go, by its name; `None` for figures that are not
/// figures of quality (the sizes of the measurement: point, line and segment counts,
/// seconds). Every rate of error (`*_fp`, `*_fn*`, `leak`) and every count of errors
/// (`*false_positives`, `*false_negatives`, `leaked`) must not rise, whatever the
/// check it comes from (the camera's sight lines too); coverages must not fall.
fn better(name: &str) -> Option<Better> {
    let error = name == "leak"
        || name == "leaked"
        || name.ends_with("_fp")
        || name.contains("_fn")
        || name.contains("false_positives")
        || name.contains("false_negatives");
    if name.starts_with("seconds") {
        None
    } else if error {
        Some(Better::Lower)
    } else if name.contains("coverage") {
        Some(Better::Higher)
    } else {
        None
    }
}

/// A count of errors (not a rate): compared relatively.
fn is_error_count(name: &str) -> bool {
    name == "leaked" || name.contains("false_positives") || name.contains("false_negatives")
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Better {
    Higher,
    Lower,
}

/// What the run needs from the command line.
pub struct Run<'a> {
    pub dir: &'a Path,
    pub maps: &'a [PathBuf],
    /// The compile options for a map, writing to the given output.
    pub options: &'a dyn Fn(&Path, PathBuf) -> CompileOptions,
    pub check_samples: usize,
    pub liquids_are_solid: bool,
    pub tolerances: Tolerances,
    pub json: bool,
    pub verbosity: Verbosity,
}

/// Compiles one map into `out`.
fn compile(run: &Run, map: &Path, out: &Path) -> Result<(CompileOptions, pipeline::Stats)> {
    let options = (run.options)(map, out.to_path_buf());
    let log = Log::new(run.verbosity, true);
    let stats =
        pipeline::compile(map, &options, &log, &NoProgress).map_err(|e| anyhow::anyhow!("{e}"))?;
    Ok((options, stats))
}

/// One map's statistics as stored in `DIR/NAME.json`: the compile's counts and time and
/// the check's figures, measured with `samples` points from `seed`.
fn measure(
    run: &Run,
    map: &Path,
    (options, stats): &(CompileOptions, pipeline::Stats),
    samples: usize,
    seed: u64,
) -> Result<Value> {
    let (vertices, faces, bytes) = stats
        .vdg
        .context("the compile wrote no graph (--stop-after?)")?;
    let bsp = bsp::Bsp::open(map).map_err(|e| anyhow::anyhow!("{e}"))?;
    let file = vdgformat::VdgFile::open(&options.output).map_err(|e| anyhow::anyhow!("{e}"))?;
    let report = check(
        &bsp,
        &file.graph(),
        bytes,
        &CheckOptions {
            samples,
            seed,
            liquids_are_solid: run.liquids_are_solid,
            ..CheckOptions::default()
        },
    );
    let map_bytes = std::fs::read(map)?;
    Ok(json!({
        "map": map.file_name().map(|n| n.to_string_lossy().into_owned()),
        "map_hash": format!("{:016x}", vdgformat::xxh64(&map_bytes, 0)),
        "tool_version": env!("CARGO_PKG_VERSION"),
        "options": bsp2vdg::options::recorded_options(options)
            .into_iter()
            .collect::<BTreeMap<_, _>>(),
        "vertices": vertices,
        "faces": faces,
        "bytes": bytes,
        "seconds": total_seconds(stats),
        "check_samples": samples,
        "check_seed": seed,
        "check": report.to_json(),
    }))
}

fn total_seconds(stats: &pipeline::Stats) -> f64 {
    stats
        .seconds
        .iter()
        .find(|(k, _)| *k == "total")
        .map_or(0.0, |x| x.1)
}

fn stem(map: &Path) -> String {
    map.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// The maps' names must be distinct: each is stored as `DIR/NAME.vdg` and `.json`.
fn check_names(maps: &[PathBuf]) -> Result<()> {
    let mut seen = std::collections::HashSet::new();
    for m in maps {
        if !seen.insert(stem(m)) {
            usage!(
                "two maps are named {} (a baseline stores each map by name)",
                stem(m)
            );
        }
    }
    Ok(())
}

/// `--update-baseline DIR`: stores each map's graph and statistics. Returns whether
/// every map compiled.
pub fn update(run: &Run) -> Result<bool> {
    check_names(run.maps)?;
    std::fs::create_dir_all(run.dir)
        .with_context(|| format!("cannot create the baseline folder {}", run.dir.display()))?;
    let mut ok = true;
    let mut rows = Vec::new();
    for map in run.maps {
        let name = stem(map);
        let out = run.dir.join(format!("{name}.vdg"));
        let measured = compile(run, map, &out)
            .and_then(|built| measure(run, map, &built, run.check_samples, 1));
        match measured {
            Ok(stats) => {
                let text = serde_json::to_string_pretty(&stats)? + "\n";
                toolbox::write_bytes_atomic(&run.dir.join(format!("{name}.json")), text.as_bytes())
                    .with_context(|| format!("cannot write the baseline of {name}"))?;
                rows.push(json!({ "map": name, "ok": true, "stats": stats }));
            }
            Err(e) => {
                ok = false;
                rows.push(json!({ "map": name, "ok": false, "error": format!("{e:#}") }));
            }
        }
    }
    if run.json {
        toolbox::outln!(
            "{}",
            json!({ "baseline": run.dir.display().to_string(), "maps": rows })
        );
    } else {
        toolbox::outln!(
            "{:<28} {:>9} {:>9} {:>10} {:>8} {:>9}  baseline",
            "map",
            "vertices",
            "faces",
            "bytes",
            "seconds",
            "coverage"
        );
        for r in &rows {
            let s = &r["stats"];
            if r["ok"] == true {
                toolbox::outln!(
                    "{:<28} {:>9} {:>9} {:>10} {:>8.2} {:>9.4}  stored",
                    r["map"].as_str().unwrap_or(""),
                    s["vertices"],
                    s["faces"],
                    s["bytes"],
                    s["seconds"].as_f64().unwrap_or(0.0),
                    s["check"]["coverage"].as_f64().unwrap_or(f64::NAN),
                );
            } else {
                toolbox::outln!(
                    "{:<28} FAILED: {}",
                    r["map"].as_str().unwrap_or(""),
                    r["error"].as_str().unwrap_or("")
                );
            }
        }
    }
    Ok(ok)
}

/// One compared figure.
#[derive(Debug, Clone)]
struct Figure {
    name: String,
    baseline: f64,
    current: f64,
    tolerance: f64,
    /// How the tolerance is read.
    kind: &'static str,
    ok: bool,
}

fn relative(name: &str, b: f64, c: f64, tol: f64) -> Figure {
    let change = if b == 0.0 {
        c.abs()
    } else {
        (c - b).abs() / b.abs()
    };
    Figure {
        name: name.into(),
        baseline: b,
        current: c,
        tolerance: tol,
        kind: "relative",
        ok: change <= tol + 1e-12,
    }
}

/// The figures of a rebuild compared with the baseline's.
fn compare(base: &Value, cur: &Value, t: &Tolerances) -> Vec<Figure> {
    let num = |v: &Value, k: &str| v[k].as_f64().unwrap_or(f64::NAN);
    let mut figs = vec![
        relative(
            "vertices",
            num(base, "vertices"),
            num(cur, "vertices"),
            t.counts,
        ),
        relative("faces", num(base, "faces"), num(cur, "faces"), t.counts),
    ];
    // A smaller file is no regression: only growth beyond the tolerance is.
    let (bb, cb) = (num(base, "bytes"), num(cur, "bytes"));
    figs.push(Figure {
        name: "bytes".into(),
        baseline: bb,
        current: cb,
        tolerance: t.bytes,
        kind: "larger",
        ok: cb <= bb * (1.0 + t.bytes) + 1e-9,
    });
    let (bs, cs) = (num(base, "seconds"), num(cur, "seconds"));
    figs.push(Figure {
        name: "seconds".into(),
        baseline: bs,
        current: cs,
        tolerance: t.seconds,
        kind: "slower",
        ok: bs < t.min_seconds || cs <= bs * (1.0 + t.seconds),
    });
    if let (Some(bq), Some(cq)) = (base["check"].as_object(), cur["check"].as_object()) {
        if let (Some(b), Some(c)) = (bq.get("passed").and_then(Value::as_bool), cq.get("passed")) {
            let c = c.as_bool().unwrap_or(false);
            figs.push(Figure {
                name: "passed".into(),
                baseline: f64::from(u8::from(b)),
                current: f64::from(u8::from(c)),
                tolerance: 0.0,
                kind: "must stay passed",
                ok: c || !b,
            });
        }
        for (name, bv) in bq {
            let (Some(dir), Some(b)) = (better(name), bv.as_f64()) else {
                continue;
            };
            let c = cq.get(name).and_then(Value::as_f64).unwrap_or(f64::NAN);
            if is_error_count(name) {
                // A count scales with the measurement: it must not grow by more than
                // the counts' relative tolerance (from none, not at all).
                let tol = t.figures.get(name).copied().unwrap_or(t.counts);
                figs.push(Figure {
                    name: name.clone(),
                    baseline: b,
                    current: c,
                    tolerance: tol,
                    kind: "larger",
                    ok: c <= b * (1.0 + tol) + 1e-9,
                });
                continue;
            }
            let tol = t.figures.get(name).copied().unwrap_or(t.quality);
            let worse = match dir {
                Better::Higher => b - c,
                Better::Lower => c - b,
            };
            figs.push(Figure {
                name: name.clone(),
                baseline: b,
                current: c,
                tolerance: tol,
                kind: match dir {
                    Better::Higher => "absolute, must not fall",
                    Better::Lower => "absolute, must not rise",
                },
                ok: worse <= tol + 1e-12,
            });
        }
    }
    figs
}

/// `--baseline DIR`: rebuilds and compares. Returns whether nothing regressed.
pub fn compare_all(run: &Run) -> Result<bool> {
    check_names(run.maps)?;
    if !run.dir.is_dir() {
        usage!(
            "the baseline folder {} does not exist (make it with --update-baseline {})",
            run.dir.display(),
            run.dir.display()
        );
    }
    let scratch = std::env::temp_dir().join(format!("bsp2vdg-baseline-{}", std::process::id()));
    std::fs::create_dir_all(&scratch)
        .with_context(|| format!("cannot create {}", scratch.display()))?;
    let result = compare_in(run, &scratch);
    let _ = std::fs::remove_dir_all(&scratch);
    result
}

fn compare_in(run: &Run, scratch: &Path) -> Result<bool> {
    let mut all_ok = true;
    let mut reports = Vec::new();
    for map in run.maps {
        let name = stem(map);
        let base_json = run.dir.join(format!("{name}.json"));
        let base_vdg = run.dir.join(format!("{name}.vdg"));
        let base: Value = match std::fs::read_to_string(&base_json)
            .map_err(anyhow::Error::from)
            .and_then(|t| Ok(serde_json::from_str(&t)?))
        {
            Ok(b) => b,
            Err(e) => {
                all_ok = false;
                reports.push(json!({ "map": name, "ok": false,
                    "error": format!("no baseline {} ({e}); run --update-baseline first", base_json.display()) }));
                continue;
            }
        };
        let out = scratch.join(format!("{name}.vdg"));
        let built = match compile(run, map, &out) {
            Ok(b) => b,
            Err(e) => {
                all_ok = false;
                reports.push(json!({ "map": name, "ok": false, "error": format!("{e:#}") }));
                continue;
            }
        };
        let identical = match (std::fs::read(&base_vdg), std::fs::read(&out)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        };
        if identical {
            reports.push(
                json!({ "map": name, "ok": true, "identical": true, "figures": [],
                "seconds": total_seconds(&built.1) }),
            );
            continue;
        }
        // The graph differs: measure it as the baseline was measured (same samples, seed).
        let samples = base["check_samples"]
            .as_u64()
            .unwrap_or(run.check_samples as u64) as usize;
        let seed = base["check_seed"].as_u64().unwrap_or(1);
        let cur = match measure(run, map, &built, samples, seed) {
            Ok(c) => c,
            Err(e) => {
                all_ok = false;
                reports.push(json!({ "map": name, "ok": false, "error": format!("{e:#}") }));
                continue;
            }
        };
        let figs = compare(&base, &cur, &run.tolerances);
        let ok = figs.iter().all(|f| f.ok);
        all_ok &= ok;
        reports.push(json!({
            "map": name,
            "ok": ok,
            "identical": false,
            "options_changed": !option_changes(&base, &cur).is_empty(),
            "option_changes": option_changes(&base, &cur),
            "figures": figs.iter().map(|f| json!({
                "name": f.name, "baseline": f.baseline, "current": f.current,
                "tolerance": f.tolerance, "tolerance_kind": f.kind, "ok": f.ok,
            })).collect::<Vec<_>>(),
        }));
    }
    if run.json {
        toolbox::outln!(
            "{}",
            json!({ "baseline": run.dir.display().to_string(), "regressed": !all_ok, "maps": reports })
        );
    } else {
        print_table(&reports);
    }
    Ok(all_ok)
}

/// The graph-shaping options that differ between the baseline and this run, as
/// `key: baseline -> current` (the tool's own identity is not an option).
fn option_changes(base: &Value, cur: &Value) -> Vec<String> {
    let (Some(b), Some(c)) = (base["options"].as_object(), cur["options"].as_object()) else {
        return Vec::new();
    };
    let mut keys: Vec<&String> = b.keys().chain(c.keys()).collect();
    keys.sort();
    keys.dedup();
    let show = |v: Option<&Value>| v.and_then(Value::as_str).unwrap_or("unset").to_string();
    keys.into_iter()
        .filter(|k| !k.starts_with("tool."))
        .filter(|k| b.get(*k) != c.get(*k))
        .map(|k| format!("{k}: {} -> {}", show(b.get(k)), show(c.get(k))))
        .collect()
}

fn print_table(reports: &[Value]) {
    // Columns as wide as their longest entry, so long map names keep them aligned.
    let map_w = reports
        .iter()
        .map(|r| r["map"].as_str().unwrap_or("").chars().count())
        .chain([3])
        .max()
        .unwrap_or(3);
    let fig_w = reports
        .iter()
        .flat_map(|r| r["figures"].as_array().into_iter().flatten())
        .map(|f| f["name"].as_str().unwrap_or("").chars().count())
        .chain([9])
        .max()
        .unwrap_or(9);
    toolbox::outln!(
        "{:<map_w$} {:<fig_w$} {:>14} {:>14} {:>9} {:>8}  verdict",
        "map",
        "figure",
        "baseline",
        "current",
        "change",
        "tol"
    );
    let mut regressions = 0;
    for r in reports {
        let map = r["map"].as_str().unwrap_or("");
        if let Some(e) = r["error"].as_str() {
            regressions += 1;
            toolbox::outln!("{map:<map_w$} FAILED: {e}");
            continue;
        }
        if r["identical"] == true {
            toolbox::outln!(
                "{map:<map_w$} {:<fig_w$} {:>14} {:>14} {:>9} {:>8}  ok",
                "(graph)",
                "identical",
                "identical",
                "",
                ""
            );
            continue;
        }
        for change in r["option_changes"].as_array().into_iter().flatten() {
            toolbox::outln!(
                "{map:<map_w$} options differ from the baseline's: {}",
                change.as_str().unwrap_or("")
            );
        }
        for f in r["figures"].as_array().into_iter().flatten() {
            let (b, c) = (
                f["baseline"].as_f64().unwrap_or(f64::NAN),
                f["current"].as_f64().unwrap_or(f64::NAN),
            );
            let relative = ["relative", "slower", "larger"];
            let change = if relative.iter().any(|k| f["tolerance_kind"] == *k) {
                if b != 0.0 {
                    format!("{:+.1}%", 100.0 * (c - b) / b)
                } else {
                    "-".into()
                }
            } else {
                format!("{:+.4}", c - b)
            };
            let verdict = if f["ok"] == true {
                "ok"
            } else {
                regressions += 1;
                "REGRESSION"
            };
            toolbox::outln!(
                "{map:<map_w$} {:<fig_w$} {:>14} {:>14} {change:>9} {:>8}  {verdict}",
                f["name"].as_str().unwrap_or(""),
                short(b),
                short(c),
                short(f["tolerance"].as_f64().unwrap_or(f64::NAN)),
            );
        }
    }
    toolbox::outln!("{} maps, {} regressions", reports.len(), regressions);
}

fn short(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.4}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_by_name_and_direction() {
        let base = json!({"vertices": 100, "faces": 200, "bytes": 1000, "seconds": 2.0,
            "check": {"coverage": 0.9, "leak": 0.0, "visible_fn": 0.1, "walkable_coverage": 0.8, "covered": 9,
                "coverage_points": 100, "seconds_coverage": 1.0}});
        let same = compare(&base, &base, &Tolerances::default());
        assert!(same.iter().all(|f| f.ok));
        // Counts and times of the check are not rates: not compared.
        for name in ["covered", "coverage_points", "seconds_coverage"] {
            assert!(!same.iter().any(|f| f.name == name), "{name}");
        }
        let cur = json!({"vertices": 103, "faces": 200, "bytes": 1000, "seconds": 3.5,
            "check": {"coverage": 0.95, "leak": 0.001, "visible_fn": 0.105, "walkable_coverage": 0.7, "covered": 9,
                "coverage_points": 50, "seconds_coverage": 9.0}});
        let f = compare(&base, &cur, &Tolerances::default());
        let bad: Vec<&str> = f
            .iter()
            .filter(|f| !f.ok)
            .map(|f| f.name.as_str())
            .collect();
        assert_eq!(bad, ["vertices", "seconds", "leak", "walkable_coverage"]);
    }

    #[test]
    fn camera_figures_are_compared_and_a_smaller_file_is_no_regression() {
        let base = json!({"vertices": 100, "faces": 200, "bytes": 1000, "seconds": 2.0,
            "options": {"sd": "24", "tool.build": "a"},
            "check": {"visible_fn_camera": 0.01, "camera_false_positives": 0, "camera_lines": 50,
                "passed": true}});
        let cur = json!({"vertices": 100, "faces": 200, "bytes": 600, "seconds": 2.0,
            "options": {"sd": "16", "tool.build": "b"},
            "check": {"visible_fn_camera": 0.05, "camera_false_positives": 3, "camera_lines": 50,
                "passed": false}});
        let f = compare(&base, &cur, &Tolerances::default());
        let bad: Vec<&str> = f
            .iter()
            .filter(|f| !f.ok)
            .map(|f| f.name.as_str())
            .collect();
        assert_eq!(
            bad,
            ["passed", "camera_false_positives", "visible_fn_camera"]
        );
        assert!(f.iter().any(|f| f.name == "bytes" && f.ok));
        assert_eq!(option_changes(&base, &cur), ["sd: 24 -> 16"]);
    }

    #[test]
    fn tolerances_from_toml() {
        let dir = std::env::temp_dir().join(format!("bsp2vdg-tol-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.toml");
        std::fs::write(&p, "counts = 0.1\n[figures]\ncoverage = 0.2\n").unwrap();
        let t = Tolerances::load(Some(&p)).unwrap();
        assert_eq!(t.counts, 0.1);
        assert_eq!(t.bytes, 0.02);
        assert_eq!(t.figures["coverage"], 0.2);
        assert_eq!(t.figures["leak"], 0.0);
        std::fs::write(&p, "cuonts = 0.1\n").unwrap();
        let typo = Tolerances::load(Some(&p)).unwrap_err();
        assert!(
            typo.downcast_ref::<super::super::args::UsageError>()
                .is_some()
        );
        std::fs::write(&p, "counts = -1\n").unwrap();
        assert!(
            Tolerances::load(Some(&p))
                .unwrap_err()
                .to_string()
                .contains("counts")
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
