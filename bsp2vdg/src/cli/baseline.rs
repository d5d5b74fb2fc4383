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
use toolbox::table::{self, Align};
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
    // The sizes of the measurement (point counts) and its times are no quality.
    if name.starts_with("seconds") || name.ends_with("points") || name.ends_with("covered") {
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
        for line in stored_lines(&rows) {
            toolbox::outln!("{line}");
        }
    }
    Ok(ok)
}

/// The table of `--update-baseline`: a row per map stored (or failed), its columns as
/// wide as their widest cell.
fn stored_lines(rows: &[Value]) -> Vec<String> {
    let cells = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let mut table = vec![cells(&[
        "map",
        "vertices",
        "faces",
        "bytes",
        "seconds",
        "coverage",
        " baseline",
    ])];
    for r in rows {
        let map = r["map"].as_str().unwrap_or("").to_string();
        let s = &r["stats"];
        table.push(if r["ok"] == true {
            vec![
                map,
                s["vertices"].to_string(),
                s["faces"].to_string(),
                s["bytes"].to_string(),
                format!("{:.2}", s["seconds"].as_f64().unwrap_or(0.0)),
                format!("{:.4}", s["check"]["coverage"].as_f64().unwrap_or(f64::NAN)),
                " stored".into(),
            ]
        } else {
            vec![
                map,
                format!("FAILED: {}", r["error"].as_str().unwrap_or("")),
            ]
        });
    }
    let mut aligns = vec![Align::Left];
    aligns.extend([Align::Right; 5]);
    table::lines(&table, &aligns, 1)
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
    for line in compare_lines(reports) {
        toolbox::outln!("{line}");
    }
}

/// The table of `--baseline`: a row per compared figure (or per map whose graph is
/// identical, or that failed), option differences, and the count; its columns as wide
/// as their widest cell (long map and figure names, large numbers).
fn compare_lines(reports: &[Value]) -> Vec<String> {
    let cells = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let mut table = vec![cells(&[
        "map", "figure", "baseline", "current", "change", "tol", " verdict",
    ])];
    let mut regressions = 0;
    for r in reports {
        let map = r["map"].as_str().unwrap_or("");
        if let Some(e) = r["error"].as_str() {
            regressions += 1;
            table.push(vec![map.into(), format!("FAILED: {e}")]);
            continue;
        }
        if r["identical"] == true {
            table.push(cells(&[
                map,
                "(graph)",
                "identical",
                "identical",
                "",
                "",
                " ok",
            ]));
            continue;
        }
        for change in r["option_changes"].as_array().into_iter().flatten() {
            table.push(vec![
                map.into(),
                format!(
                    "options differ from the baseline's: {}",
                    change.as_str().unwrap_or("")
                ),
            ]);
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
                " ok"
            } else {
                regressions += 1;
                " REGRESSION"
            };
            table.push(vec![
                map.into(),
                f["name"].as_str().unwrap_or("").into(),
                short(b),
                short(c),
                change,
                short(f["tolerance"].as_f64().unwrap_or(f64::NAN)),
                verdict.into(),
            ]);
        }
    }
    let aligns = [
        Align::Left,
        Align::Left,
        Align::Right,
        Align::Right,
        Align::Right,
        Align::Right,
    ];
    let mut lines = table::lines(&table, &aligns, 1);
    lines.push(format!(
        "{} maps, {} regressions",
        reports.len(),
        regressions
    ));
    lines
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
    use toolbox::table::cell_spans;

    /// Both baseline tables with long map and figure names and large numbers: every
    /// column starts (text) or ends (figures) at one position in every row.
    #[test]
    fn the_baseline_tables_align() {
        let long = "a_map_whose_name_is_much_longer_than_twenty_eight_characters";
        let figure = |name: &str, b: f64, c: f64, kind: &str, ok: bool| {
            json!({"name": name, "baseline": b, "current": c, "tolerance": 0.05,
                "tolerance_kind": kind, "ok": ok})
        };
        let reports = vec![
            json!({"map": long, "option_changes": ["-sd: 24 -> 16"], "figures": [
                figure("bytes", 123_456_789_012_345.0, 123_456_789_999_999.0, "relative", true),
                figure("check.visible_fn_camera_with_a_long_name", 0.0123, 0.5, "absolute", false),
            ]}),
            json!({"map": "b", "figures": [figure("vertices", 1.0, 2.0, "relative", false)]}),
            json!({"map": "c", "identical": true}),
            json!({"map": "d", "error": "cannot read d.bsp"}),
        ];
        let lines = compare_lines(&reports);
        let rows: Vec<(usize, Vec<&str>)> = vec![
            (
                0,
                vec![
                    "map", "figure", "baseline", "current", "change", "tol", "verdict",
                ],
            ),
            (
                2,
                vec![
                    long,
                    "bytes",
                    "123456789012345",
                    "123456789999999",
                    "+0.0%",
                    "0.0500",
                    "ok",
                ],
            ),
            (
                3,
                vec![
                    long,
                    "check.visible_fn_camera_with_a_long_name",
                    "0.0123",
                    "0.5000",
                    "+0.4877",
                    "0.0500",
                    "REGRESSION",
                ],
            ),
            (
                4,
                vec!["b", "vertices", "1", "2", "+100.0%", "0.0500", "REGRESSION"],
            ),
            (5, vec!["c", "(graph)", "identical", "identical"]),
        ];
        let spans: Vec<_> = rows
            .iter()
            .map(|(i, c)| cell_spans(&lines[*i], c))
            .collect();
        for ((i, c), s) in rows.iter().zip(&spans) {
            assert_eq!(s.len(), c.len(), "{}", lines[*i]);
            assert_eq!(s[1].0, spans[0][1].0, "figure column: {lines:#?}");
            for k in 2..c.len().min(6) {
                assert_eq!(s[k].1, spans[0][k].1, "column {k}: {lines:#?}");
            }
            if c.len() == 7 {
                assert_eq!(s[6].0, spans[0][6].0, "verdict: {lines:#?}");
            }
        }
        assert!(lines[1].contains("options differ from the baseline's: -sd: 24 -> 16"));
        assert_eq!(lines[1].find("options"), Some(spans[0][1].0));
        assert!(lines[6].starts_with("d ") && lines[6].contains("FAILED: cannot read d.bsp"));

        let stored = stored_lines(&[
            json!({"map": long, "ok": true, "stats": {"vertices": 12_345_678, "faces": 3,
                "bytes": 9_876_543_210u64, "seconds": 12_345.678, "check": {"coverage": 0.9}}}),
            json!({"map": "b", "ok": true, "stats": {"vertices": 1, "faces": 22_222_222,
                "bytes": 5, "seconds": 0.5, "check": {"coverage": 1.0}}}),
        ]);
        let cells = [
            vec![
                "map", "vertices", "faces", "bytes", "seconds", "coverage", "baseline",
            ],
            vec![
                long,
                "12345678",
                "3",
                "9876543210",
                "12345.68",
                "0.9000",
                "stored",
            ],
            vec!["b", "1", "22222222", "5", "0.50", "1.0000", "stored"],
        ];
        let spans: Vec<_> = stored
            .iter()
            .zip(&cells)
            .map(|(l, c)| cell_spans(l, c))
            .collect();
        for s in &spans {
            for k in 1..6 {
                assert_eq!(s[k].1, spans[0][k].1, "column {k}: {stored:#?}");
            }
            assert_eq!(s[6].0, spans[0][6].0, "{stored:#?}");
        }
    }

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
