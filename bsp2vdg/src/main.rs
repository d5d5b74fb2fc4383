//! `bsp2vdg [options] MAP.bsp ...` — the command line, in the manner of map compile
//! tools: thesis-style single-dash options, a log beside the map, non-zero exit on
//! failure, `--json` for CI, and batch mode over many maps with a summary table.

use anyhow::{Context, Result, bail};
use bsp2vdg::log::{Log, Verbosity, secs};
use bsp2vdg::pipeline::{self, CompileOptions, SamplesFormat, Stage, Stats};
use bsp2vdg::progress::{NoProgress, PercentLines, Progress};
use bsp2vdg::sample::SampleOptions;
use clap::{Parser, ValueEnum};
use rayon::prelude::*;
use serde_json::json;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "bsp2vdg",
    version,
    about = "Compile a BSP map into a Voronoi Distance Graph (.vdg)",
    allow_negative_numbers = true,
    after_help = "Thesis-style single-dash spellings work too: -sd 16 -ms 100000 -rl 0.05 -md 20 -bb 256 -savesamples -subset -threads 2 -verbose -quiet"
)]
struct Cli {
    /// The map(s) to compile; several maps are compiled in parallel (batch mode).
    #[arg(required = true, value_name = "MAP.bsp")]
    maps: Vec<PathBuf>,
    /// Sample spacing m: every point of a wall lies within m units of a sample.
    #[arg(long = "sd", value_name = "M", default_value_t = 24.0)]
    sample_spacing: f64,
    /// Cap on the number of samples; the spacing is raised until it holds.
    #[arg(long = "ms", value_name = "N", default_value_t = 250_000)]
    max_samples: usize,
    /// Reduction limit: 1.0 = no reduction, 0.0 = as far as possible.
    #[arg(long = "rl", value_name = "F", default_value_t = 0.025)]
    reduction_limit: f64,
    /// Minimum clearance a Voronoi vertex must have to be kept.
    #[arg(long = "md", value_name = "N", default_value_t = 20.0)]
    min_clearance: f64,
    /// Smallest leaf box of the face tree in the .vdg.
    #[arg(long = "bb", value_name = "N", default_value_t = 256.0)]
    tree_leaf_size: f64,
    /// Save the samples as text beside the output (OUT.samples.txt).
    #[arg(long = "savesamples")]
    save_samples: bool,
    /// Format of the samples file.
    #[arg(long, value_enum, default_value_t = SamplesFormatArg::Xyz)]
    samples_format: SamplesFormatArg,
    /// Compile only the central eighth of the map, for quick test runs.
    #[arg(long)]
    subset: bool,
    /// Worker threads (0 = one per core).
    #[arg(long, value_name = "N", default_value_t = 0)]
    threads: usize,
    /// More detail in the log.
    #[arg(long, conflicts_with = "quiet")]
    verbose: bool,
    /// Only errors (and --json).
    #[arg(long)]
    quiet: bool,
    /// Output file (default: MAP.vdg beside the map); a directory in batch mode.
    #[arg(short, long, value_name = "PATH")]
    output: Option<PathBuf>,
    /// Stop after this stage.
    #[arg(long, value_enum, default_value_t = StageArg::Reduce)]
    stop_after: StageArg,
    /// Print one JSON object with the statistics on stdout (the log goes to stderr).
    #[arg(long)]
    json: bool,
    /// Treat water, slime and lava as walls (by default they are free space).
    #[arg(long)]
    liquids_solid: bool,
    /// Brush entity classnames whose models are walls too (comma separated), e.g. func_wall.
    #[arg(long, value_name = "CLASSES", value_delimiter = ',')]
    entities: Vec<String>,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum StageArg {
    Samples,
    Delaunay,
    Voronoi,
    Reduce,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SamplesFormatArg {
    Xyz,
    Qhull,
}

/// Options spelled with one dash, as the thesis and the compile tools do.
const SINGLE_DASH: [&str; 15] = [
    "sd",
    "ms",
    "rl",
    "md",
    "bb",
    "savesamples",
    "subset",
    "threads",
    "verbose",
    "quiet",
    "json",
    "output",
    "entities",
    "stop-after",
    "samples-format",
];

/// Rewrites `-sd` to `--sd` and so on; everything else is left alone.
fn normalise_args(args: impl Iterator<Item = String>) -> Vec<String> {
    args.enumerate()
        .map(|(i, a)| match a.strip_prefix('-') {
            Some(rest) if i > 0 && !rest.starts_with('-') && SINGLE_DASH.contains(&rest) => {
                format!("--{rest}")
            }
            _ => a,
        })
        .collect()
}

fn main() {
    let cli = Cli::parse_from(normalise_args(std::env::args()));
    match run(&cli) {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("bsp2vdg: error: {e:#}");
            std::process::exit(1);
        }
    }
}

fn check_options(cli: &Cli) -> Result<()> {
    if !(cli.sample_spacing.is_finite() && cli.sample_spacing > 0.0) {
        bail!(
            "-sd must be a positive number of units, got {}",
            cli.sample_spacing
        );
    }
    if cli.max_samples < 4 {
        bail!("-ms must allow at least 4 samples, got {}", cli.max_samples);
    }
    if !(0.0..=1.0).contains(&cli.reduction_limit) {
        bail!(
            "-rl must lie between 0.0 and 1.0, got {}",
            cli.reduction_limit
        );
    }
    if !(cli.min_clearance.is_finite() && cli.min_clearance >= 0.0) {
        bail!("-md must be zero or positive, got {}", cli.min_clearance);
    }
    if !(cli.tree_leaf_size.is_finite() && cli.tree_leaf_size > 0.0) {
        bail!(
            "-bb must be a positive number of units, got {}",
            cli.tree_leaf_size
        );
    }
    if cli.threads > 4096 {
        bail!(
            "-threads {} is more than this tool supports (4096)",
            cli.threads
        );
    }
    Ok(())
}

/// Returns whether every map compiled.
fn run(cli: &Cli) -> Result<bool> {
    check_options(cli)?;
    if cli.threads > 0 {
        rayon::ThreadPoolBuilder::new()
            .num_threads(cli.threads)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    let batch = cli.maps.len() > 1;
    if batch
        && let Some(o) = &cli.output
        && !o.is_dir()
    {
        bail!(
            "-o must name an existing directory when compiling several maps ({} is not one)",
            o.display()
        );
    }
    for map in &cli.maps {
        if !map.is_file() {
            bail!("{}: no such map file", map.display());
        }
    }
    let verbosity = if cli.quiet {
        Verbosity::Quiet
    } else if cli.verbose {
        Verbosity::Verbose
    } else {
        Verbosity::Normal
    };
    if verbosity != Verbosity::Quiet {
        let line = format!(
            "bsp2vdg {} ({} threads)",
            env!("CARGO_PKG_VERSION"),
            rayon::current_num_threads()
        );
        if cli.json {
            eprintln!("{line}")
        } else {
            println!("{line}")
        }
    }

    let compile_one = |map: &PathBuf| {
        let name = map
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let mut log = Log::new(verbosity, cli.json);
        if batch {
            log = log.with_prefix(&name);
        }
        let options = compile_options(cli, map);
        let progress: Box<dyn Progress> = if batch || verbosity == Verbosity::Quiet {
            Box::new(NoProgress)
        } else if std::io::stderr().is_terminal() {
            Box::new(TerminalBar::default())
        } else {
            Box::new(PercentLines::default())
        };
        let result = pipeline::compile(map, &options, &log, progress.as_ref());
        if let Err(e) = &result {
            // The console gets the error once, at the end; the log file keeps it too.
            log.record(format!("ERROR: {e}"));
            if batch {
                log.info(format!("ERROR: {e}"));
            }
        }
        save_log(&options.output, &log);
        (map.clone(), result)
    };
    let results: Vec<_> = if batch {
        cli.maps.par_iter().map(compile_one).collect()
    } else {
        cli.maps.iter().map(compile_one).collect()
    };

    let ok = results.iter().all(|(_, r)| r.is_ok());
    if batch && verbosity != Verbosity::Quiet {
        print_summary(&results, cli.json);
    }
    if cli.json {
        let objects: Vec<_> = results
            .iter()
            .map(|(m, r)| json_report(m, r, cli))
            .collect();
        let out = if batch {
            json!({ "maps": objects })
        } else {
            objects[0].clone()
        };
        println!("{out}");
    } else if !batch && let Some((_, Err(e))) = results.first() {
        eprintln!("bsp2vdg: error: {e}");
        return Ok(false);
    }
    Ok(ok)
}

fn compile_options(cli: &Cli, map: &Path) -> CompileOptions {
    let default_output = map.with_extension("vdg");
    let output = match &cli.output {
        Some(o) if cli.maps.len() > 1 => o.join(default_output.file_name().unwrap_or_default()),
        Some(o) => o.clone(),
        None => default_output,
    };
    CompileOptions {
        sampling: SampleOptions {
            spacing: cli.sample_spacing,
            max_samples: cli.max_samples,
            subset: cli.subset,
            ..SampleOptions::default()
        },
        reduction_limit: cli.reduction_limit,
        min_clearance: cli.min_clearance,
        tree_leaf_size: cli.tree_leaf_size,
        liquids_are_solid: cli.liquids_solid,
        entity_classes: cli.entities.clone(),
        save_samples: cli.save_samples,
        samples_format: match cli.samples_format {
            SamplesFormatArg::Xyz => SamplesFormat::Xyz,
            SamplesFormatArg::Qhull => SamplesFormat::Qhull,
        },
        stop_after: match cli.stop_after {
            StageArg::Samples => Stage::Samples,
            StageArg::Delaunay => Stage::Delaunay,
            StageArg::Voronoi => Stage::Voronoi,
            StageArg::Reduce => Stage::Reduce,
        },
        output,
    }
}

/// Appends the log beside the output (`MAP.log` for the default output `MAP.vdg`,
/// as map compile tools do). With `-o` elsewhere the map's folder stays untouched:
/// shared or read-only map folders are common in build farms. A log that cannot be
/// written never fails the compile.
fn save_log(output: &Path, log: &Log) {
    let header = format!(
        "bsp2vdg {} {}",
        env!("CARGO_PKG_VERSION"),
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    );
    let path = output.with_extension("log");
    if let Err(e) = log.append_to(&path, &header) {
        log.detail(format!(
            "could not write the log file {}: {e}",
            path.display()
        ));
    }
}

fn json_report(
    map: &Path,
    result: &Result<Stats, pipeline::CompileError>,
    cli: &Cli,
) -> serde_json::Value {
    match result {
        Err(e) => json!({ "map": map.display().to_string(), "ok": false, "error": e.to_string() }),
        Ok(s) => {
            let seconds: serde_json::Map<String, serde_json::Value> = s
                .seconds
                .iter()
                .map(|(k, v)| (k.to_string(), json!(v)))
                .collect();
            let mut out = json!({
                "map": map.display().to_string(),
                "ok": true,
                "version": s.version,
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
                "reduce_faces_before": s.reduce.as_ref().map(|r| r.faces_before),
                "reduce_lost_volume": s.reduce.as_ref().map(|r| r.lost_volume),
                "reduce_raise": s.reduce.as_ref().map(|r| [r.raised as f64, r.raised_by, r.raise_seconds]),
                "reduce_refusals": s.reduce.as_ref().map(|r| {
                    r.refusals
                        .iter()
                        .map(|(k, n)| (k.to_string(), json!(n)))
                        .collect::<serde_json::Map<String, serde_json::Value>>()
                }),
                "output": s.output.as_ref().map(|p| p.display().to_string()),
                "threads": rayon::current_num_threads(),
                "stop_after": format!("{:?}", cli.stop_after).to_lowercase(),
                "seconds": seconds,
            });
            out["reduce_kept_points"] = json!(s.reduce.as_ref().map(|r| r.kept_points));
            out
        }
    }
}

fn print_summary(results: &[(PathBuf, Result<Stats, pipeline::CompileError>)], to_stderr: bool) {
    let mut lines = vec![format!(
        "{:<32} {:>6} {:>8} {:>9} {:>8} {:>9}  status",
        "map", "faces", "sampled", "samples", "spacing", "time"
    )];
    for (map, r) in results {
        let name = map
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        lines.push(match r {
            Ok(s) => format!(
                "{:<32} {:>6} {:>8} {:>9} {:>8.2} {:>9}  ok",
                name,
                s.faces,
                s.sampled_faces,
                s.samples,
                s.sample_spacing,
                secs(s.seconds.last().map_or(0.0, |x| x.1))
            ),
            Err(e) => format!(
                "{name:<32} {:>6} {:>8} {:>9} {:>8} {:>9}  FAILED: {e}",
                "-", "-", "-", "-", "-"
            ),
        });
    }
    for l in lines {
        if to_stderr {
            eprintln!("{l}")
        } else {
            println!("{l}")
        }
    }
}

/// An indicatif bar on stderr, for interactive runs.
#[derive(Default)]
struct TerminalBar {
    bar: std::sync::Mutex<Option<indicatif::ProgressBar>>,
}

impl Progress for TerminalBar {
    fn start(&self, label: &str, total: u64) {
        let bar = indicatif::ProgressBar::new(total);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{msg:>12} [{bar:40}] {percent:>3}% {elapsed_precise}",
        ) {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_dash_options_are_normalised() {
        let args = [
            "bsp2vdg",
            "-sd",
            "16",
            "-savesamples",
            "-o",
            "x.vdg",
            "-5",
            "--json",
            "-subset",
        ];
        let out = normalise_args(args.iter().map(|s| s.to_string()));
        assert_eq!(
            out,
            [
                "bsp2vdg",
                "--sd",
                "16",
                "--savesamples",
                "-o",
                "x.vdg",
                "-5",
                "--json",
                "--subset"
            ]
        );
    }

    #[test]
    fn cli_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
