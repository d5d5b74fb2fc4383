//! `bsp2vdg [options] MAP.bsp ...` — the command line, in the manner of map compile
//! tools (ericw-tools, VHLT): single-dash options, a log beside the output, `MAP.err`
//! on failure, low priority by default, non-zero exit on failure, `--json` for CI, and
//! batch mode over many maps with a summary table that skips maps already up to date.
#![recursion_limit = "256"] // the --json report is one large json! literal

mod cli;

use anyhow::{Context, Result};
use bsp2vdg::log::{Log, Verbosity};
use bsp2vdg::options::{self, CompileOptions, SamplesFormat, Stage, defaults};
use bsp2vdg::pipeline;
use bsp2vdg::progress::{NoProgress, PercentLines, Progress};
use bsp2vdg::reduce::ReductionCost;
use bsp2vdg::sample::SampleOptions;
use clap::{CommandFactory, Parser, ValueEnum};
use cli::args::usage;
use cli::priority::{self, Priority};
use cli::report::{self, Outcome, TerminalBar};
use serde_json::json;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};

#[derive(Parser, Debug)]
#[command(
    name = "bsp2vdg",
    version = concat!(env!("CARGO_PKG_VERSION"), " (build ", env!("BSP2VDG_BUILD"), ")"),
    about = "Compile a BSP map into a Voronoi Distance Graph (.vdg)",
    allow_negative_numbers = true,
    after_help = "Every long option works with one dash too, as in the compile tools: -sd 16 -ms 100000 -rl 0.05 -rv 1000 -rc relative -md 16 -bb 256 -savesamples -subset -threads 2 -verbose -quiet -low -nolog -estimate -chart.\nExit status: 0 success, 1 a map failed (MAP.err beside the output says why), 2 bad command line."
)]
struct Cli {
    /// The map(s) to compile; several maps are compiled in parallel (batch mode).
    #[arg(required = true, value_name = "MAP.bsp")]
    maps: Vec<PathBuf>,
    /// Sample spacing m: every point of a wall lies within m units of a sample.
    #[arg(long = "sd", value_name = "M", default_value_t = defaults::SAMPLE_SPACING)]
    sample_spacing: f64,
    /// Cap on the number of samples; the spacing is raised until it holds.
    #[arg(long = "ms", value_name = "N", default_value_t = defaults::MAX_SAMPLES)]
    max_samples: usize,
    /// Reduction limit: 1.0 = no reduction, 0.0 = as far as possible.
    #[arg(long = "rl", value_name = "F", default_value_t = defaults::REDUCTION_LIMIT)]
    reduction_limit: f64,
    /// Reduction floor: never reduce below N vertices, whatever -rl says (small maps
    /// keep enough of their graph to see across their rooms); 0 = no floor.
    #[arg(long = "rv", value_name = "N", default_value_t = defaults::REDUCTION_FLOOR)]
    reduction_floor: usize,
    /// Reduction cost: `relative` removes first what loses the least volume for the
    /// vertex's size (volume / clearance²), keeping the volume near the walls that sight
    /// lines along them need; `volume` is the thesis' (the volume alone).
    #[arg(long = "rc", value_enum, value_name = "COST", default_value_t = ReductionCostArg::of(defaults::REDUCTION_COST))]
    reduction_cost: ReductionCostArg,
    /// Minimum clearance of the unreduced graph: Voronoi vertices with less are dropped
    /// before the reduction (thesis 4.1). The interpolation guard (down to 8 units, so
    /// doorways stay joined) and the reduction (condition A) then lower the clearances of
    /// the vertices they keep, so the written graph may hold smaller ones.
    #[arg(long = "md", value_name = "N", default_value_t = defaults::MIN_CLEARANCE)]
    min_clearance: f64,
    /// Smallest leaf box of the face tree in the .vdg.
    #[arg(long = "bb", value_name = "N", default_value_t = defaults::TREE_LEAF_SIZE)]
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
    /// Treat player and monster clip brushes as walls (Quake 2/3 PLAYERCLIP, GoldSrc
    /// clip; by default free space, as cameras pass through them).
    #[arg(long)]
    clip_solid: bool,
    /// Brush entity classnames whose models are walls too (comma separated), e.g. func_wall.
    #[arg(long, value_name = "CLASSES", value_delimiter = ',')]
    entities: Vec<String>,
    /// Run at low process priority (the default, as ericw-tools does).
    #[arg(long, visible_alias = "lowpriority")]
    low: bool,
    /// Run at high process priority (needs privileges on Unix; else normal priority).
    #[arg(long, conflicts_with = "low")]
    high: bool,
    /// Write no log file.
    #[arg(long, conflicts_with = "logfile")]
    nolog: bool,
    /// Append the log to FILE instead of OUT.log beside the output.
    #[arg(long, value_name = "FILE")]
    logfile: Option<PathBuf>,
    /// Show the estimated time left with the progress.
    #[arg(long, conflicts_with = "noestimate")]
    estimate: bool,
    /// Show progress without time estimates (the default).
    #[arg(long)]
    noestimate: bool,
    /// Print a chart of the stage times and the sizes after each map.
    #[arg(long)]
    chart: bool,
    /// Developer message level (VHLT); 1 or more shows the -verbose lines.
    #[arg(long, value_name = "N")]
    dev: Option<u32>,
    /// Rebuild maps whose output is up to date (batch mode skips them otherwise).
    #[arg(long)]
    force: bool,
    /// Record the map's name in the .vdg (=NAME records NAME). By default only its hash
    /// is recorded, so renaming or moving the map does not change the output's bytes.
    #[arg(long, value_name = "NAME", num_args = 0..=1, require_equals = true, default_missing_value = "")]
    source_name: Option<String>,
    /// CI: compile the maps and store their graphs and statistics in DIR as the baseline.
    #[arg(long, value_name = "DIR", conflicts_with_all = ["baseline", "output"])]
    update_baseline: Option<PathBuf>,
    /// CI: compile the maps again and compare with the baseline in DIR; exit 1 on a regression.
    #[arg(long, value_name = "DIR", conflicts_with = "output")]
    baseline: Option<PathBuf>,
    /// Tolerances of --baseline (TOML: counts, bytes, seconds, min_seconds, quality, [figures]).
    #[arg(long, value_name = "FILE")]
    tolerances: Option<PathBuf>,
    /// Measurement switch: skip the raise towards the walls after the reduction (the
    /// reduction's own raise back towards the unreduced graph runs instead, so the
    /// written volume lies inside the unreduced one). Recorded in the .vdg.
    #[arg(long)]
    no_wall_raise: bool,
    /// Measurement switch, never for graphs you ship: reduce without the coverage
    /// guards (the kept player places and deep points), to see whether they or the
    /// graph's shape stop the reduction above -rl. Recorded in the .vdg.
    #[arg(long)]
    no_coverage_guards: bool,
    /// Random points per quality figure measured for a baseline.
    #[arg(long, value_name = "N", default_value_t = 100_000)]
    check_samples: usize,
    /// Read a BSP29/BSP30 map as this game's whatever the map itself says (by default
    /// its clip hulls and entities decide: Half-Life's oldest maps are BSP29 too).
    #[arg(long, value_enum, value_name = "GAME")]
    game: Option<GameArg>,
    /// Scale of each map's time and memory budget (base + share per MB of map; a map
    /// over it fails with the reason and a batch goes on); 0 = no budget.
    #[arg(long, value_name = "F", default_value_t = 1.0)]
    budget: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum GameArg {
    Goldsrc,
    Quake,
}

#[derive(Clone, Copy, Debug, PartialEq, ValueEnum)]
enum StageArg {
    Samples,
    Delaunay,
    Voronoi,
    Reduce,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum ReductionCostArg {
    Volume,
    Relative,
}

impl ReductionCostArg {
    /// The command line's name of a cost.
    const fn of(cost: ReductionCost) -> Self {
        match cost {
            ReductionCost::Volume => ReductionCostArg::Volume,
            ReductionCost::Relative => ReductionCostArg::Relative,
        }
    }

    fn cost(self) -> ReductionCost {
        match self {
            ReductionCostArg::Volume => ReductionCost::Volume,
            ReductionCostArg::Relative => ReductionCost::Relative,
        }
    }
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum SamplesFormatArg {
    Xyz,
    Qhull,
}

/// Exit status of a command line that cannot be run (unknown option, bad syntax).
const EXIT_USAGE: i32 = 2;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (mut cli, ignored) = match parse(&args) {
        Ok(parsed) => parsed,
        Err(code) => std::process::exit(code),
    };
    if !ignored.is_empty() {
        note(
            &cli,
            &format!(
                "warning: ignoring {} (options of the map compile tools that do not apply to bsp2vdg)",
                ignored.join(" ")
            ),
        );
    }
    let verdict = cli::outputs::resolve_maps(&cli.maps).and_then(|maps| {
        cli.maps = maps;
        run(&cli)
    });
    // With --json stdout is the report: losing it (a full disk) fails the run; a
    // reader closing the pipe does not, and never stops the compile.
    if cli.json
        && let Some(lost) = toolbox::console::stdout_lost()
    {
        toolbox::errln!("bsp2vdg: error: {lost}");
        std::process::exit(1);
    }
    match verdict {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            toolbox::errln!("bsp2vdg: error: {e:#}");
            let usage = e.downcast_ref::<cli::args::UsageError>().is_some();
            std::process::exit(if usage { EXIT_USAGE } else { 1 });
        }
    }
}

/// Parses the command line; a usage error is printed as one line and gives the exit
/// status (help and version are printed in full and give 0). Also returns the map
/// compile tools' options it ignored.
fn parse(args: &[String]) -> Result<(Cli, Vec<String>), i32> {
    let longs = cli::args::long_options(&Cli::command());
    let normal = cli::args::normalise(args, &longs).map_err(|e| {
        toolbox::errln!("bsp2vdg: error: {}", e.0);
        EXIT_USAGE
    })?;
    let ignored = normal.ignored;
    let cli = Cli::try_parse_from(normal.args).map_err(|e| {
        use clap::error::ErrorKind;
        if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
            let _ = e.print();
            return 0;
        }
        // clap's message without its usage block, on one line.
        let text = e.to_string();
        let message: Vec<&str> = text
            .lines()
            .take_while(|l| !l.starts_with("Usage:"))
            .map(str::trim)
            .filter(|l| {
                !l.is_empty() && !l.starts_with("tip:") && !l.starts_with("For more information")
            })
            .collect();
        let message = message.join(" ");
        let message = message.strip_prefix("error: ").unwrap_or(&message);
        toolbox::errln!("bsp2vdg: error: {message}; bsp2vdg --help lists the options");
        EXIT_USAGE
    })?;
    Ok((cli, ignored))
}

/// Impossible values, refused as command-line errors (exit 2).
fn check_options(cli: &Cli) -> Result<()> {
    if !(cli.sample_spacing.is_finite() && cli.sample_spacing > 0.0) {
        usage!(
            "-sd must be a positive number of units, got {}",
            cli.sample_spacing
        );
    }
    if cli.max_samples < 4 {
        usage!("-ms must allow at least 4 samples, got {}", cli.max_samples);
    }
    if !(0.0..=1.0).contains(&cli.reduction_limit) {
        usage!(
            "-rl must lie between 0.0 and 1.0, got {}",
            cli.reduction_limit
        );
    }
    if !(cli.min_clearance.is_finite() && cli.min_clearance >= 0.0) {
        usage!("-md must be zero or positive, got {}", cli.min_clearance);
    }
    if !(cli.tree_leaf_size.is_finite() && cli.tree_leaf_size > 0.0) {
        usage!(
            "-bb must be a positive number of units, got {}",
            cli.tree_leaf_size
        );
    }
    if !(cli.budget.is_finite() && cli.budget >= 0.0) {
        usage!(
            "--budget must be zero or a positive scale, got {}",
            cli.budget
        );
    }
    if cli.threads > 4096 {
        usage!(
            "-threads {} is more than this tool supports (4096)",
            cli.threads
        );
    }
    if cli.maps.len() > 1 && cli.source_name.as_deref().is_some_and(|n| !n.is_empty()) {
        usage!(
            "--source-name=NAME names one map; give --source-name without a value to record each map's own name"
        );
    }
    Ok(())
}

/// A note on the console (stderr when stdout carries JSON), unless quiet.
fn note(cli: &Cli, line: &str) {
    if cli.quiet {
    } else if cli.json {
        toolbox::errln!("bsp2vdg: {line}");
    } else {
        toolbox::outln!("bsp2vdg: {line}");
    }
}

/// Lowers (or raises) the process priority before any worker thread starts.
fn set_priority(cli: &Cli) {
    let wanted = if cli.high {
        Priority::High
    } else {
        Priority::Low
    };
    if let Err(e) = priority::set(wanted) {
        let what = if cli.high { "-high" } else { "low priority" };
        note(
            cli,
            &format!(
                "warning: {what}: cannot set the process priority ({e}); running at the current priority"
            ),
        );
    }
}

/// Returns whether every map compiled (or was up to date).
fn run(cli: &Cli) -> Result<bool> {
    check_options(cli)?;
    set_priority(cli);
    if cli.threads > 0 {
        rayon::ThreadPoolBuilder::new()
            .num_threads(cli.threads)
            .build_global()
            .context("cannot start the worker threads")?;
    }
    let batch = cli.maps.len() > 1 && cli.update_baseline.is_none() && cli.baseline.is_none();
    if batch
        && let Some(o) = &cli.output
        && !o.is_dir()
    {
        usage!(
            "-o must name an existing directory when compiling several maps ({} is not one)",
            o.display()
        );
    }
    if let Some(dir) = cli.update_baseline.as_ref().or(cli.baseline.as_ref()) {
        return run_baseline(cli, dir);
    }
    check_outputs(cli)?;
    let verbosity = if cli.quiet {
        Verbosity::Quiet
    } else if cli.verbose || cli.dev.is_some_and(|n| n > 0) {
        Verbosity::Verbose
    } else {
        Verbosity::Normal
    };
    let console = |line: &str| {
        if verbosity == Verbosity::Quiet {
        } else if cli.json {
            toolbox::errln!("{line}")
        } else {
            toolbox::outln!("{line}")
        }
    };
    console(&format!(
        "bsp2vdg {} (build {}, {} threads)",
        env!("CARGO_PKG_VERSION"),
        options::BUILD,
        rayon::current_num_threads()
    ));
    if let Some(n) = cli.dev.filter(|&n| n > 0) {
        note(
            cli,
            &format!("note: -dev {n}: developer messages are the -verbose lines"),
        );
    }

    let results: Vec<(PathBuf, Outcome)> = if batch {
        // One map per thread at a time: a batch holds only the maps it is compiling.
        cli::batch::in_slots(&cli.maps, rayon::current_num_threads(), |m| {
            (m.clone(), build_one(cli, m, verbosity))
        })
        .context("cannot start the batch's threads")?
    } else {
        cli.maps
            .iter()
            .map(|m| (m.clone(), build_one(cli, m, verbosity)))
            .collect()
    };

    let ok = results.iter().all(|(_, r)| r.ok());
    if batch {
        // The summary table is the batch's result: -quiet keeps it (with --json,
        // which carries the same figures on stdout, it goes to stderr unless quiet).
        for line in report::summary_lines(&results) {
            if !cli.json {
                toolbox::outln!("{line}");
            } else if !cli.quiet {
                toolbox::errln!("{line}");
            }
        }
    }
    for (map, r) in &results {
        // Errors are shown even with -quiet (once, at the end).
        if let Outcome::Failed(e) = r
            && !cli.json
        {
            let msg = e.to_string();
            if batch && !msg.starts_with(&map.display().to_string()) {
                toolbox::errln!("bsp2vdg: error: {}: {msg}", map.display());
            } else {
                toolbox::errln!("bsp2vdg: error: {e}");
            }
        }
    }
    if cli.json {
        let stop_after = format!("{:?}", cli.stop_after).to_lowercase();
        let objects: Vec<_> = results
            .iter()
            .map(|(m, r)| report::json_report(m, r, &stop_after))
            .collect();
        let out = if batch {
            json!({ "maps": objects })
        } else {
            objects[0].clone()
        };
        toolbox::outln!("{out}");
    }
    Ok(ok)
}

/// `--update-baseline DIR` / `--baseline DIR` (see [`cli::baseline`]).
fn run_baseline(cli: &Cli, dir: &Path) -> Result<bool> {
    if cli.stop_after != StageArg::Reduce {
        usage!("--stop-after writes no graph to compare; a baseline needs the whole pipeline");
    }
    if cli.check_samples == 0 {
        usage!("--check-samples must be at least 1");
    }
    let options = |map: &Path, output: PathBuf| CompileOptions {
        output,
        ..compile_options(cli, map)
    };
    let run = cli::baseline::Run {
        dir,
        maps: &cli.maps,
        options: &options,
        check_samples: cli.check_samples,
        liquids_are_solid: cli.liquids_solid,
        tolerances: cli::baseline::Tolerances::load(cli.tolerances.as_deref())?,
        json: cli.json,
        verbosity: if cli.verbose {
            Verbosity::Verbose
        } else {
            Verbosity::Quiet
        },
    };
    if cli.update_baseline.is_some() {
        cli::baseline::update(&run)
    } else {
        cli::baseline::compare_all(&run)
    }
}

/// One map: clean up after killed runs, skip it when current (batch mode), compile it,
/// write the log and `MAP.err` (removed again on success).
fn build_one(cli: &Cli, map: &Path, verbosity: Verbosity) -> Outcome {
    let batch = cli.maps.len() > 1;
    let name = map
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut log = Log::new(verbosity, cli.json);
    if batch {
        log = log.with_prefix(&name);
    }
    let options = compile_options(cli, map);
    open_log_file(cli, &options.output, &mut log, &name);
    for path in [
        options.output.clone(),
        options::samples_path(&options.output),
    ] {
        for stale in toolbox::clean_stale_temps(&path) {
            log.info(format!(
                "Removed {}, left behind by a run that was killed",
                stale.display()
            ));
        }
    }
    let outcome = if batch
        && !cli.force
        && let Some(hash) = map_hash(map)
    {
        match bsp2vdg::uptodate::check(hash, &options) {
            Ok(()) => {
                log.info(format!(
                    "{} is up to date (same map bytes, options and bsp2vdg build {}); skipped, -force rebuilds",
                    options.output.display(),
                    options::BUILD
                ));
                Some(Outcome::Current {
                    output: options.output.clone(),
                })
            }
            Err(why) => {
                log.detail(format!("Compiling: {why}"));
                None
            }
        }
    } else {
        None
    };
    let outcome = outcome.unwrap_or_else(|| compile_logged(cli, map, &options, &log, batch));
    write_err_file(&options.output, &outcome);
    outcome
}

/// Runs the pipeline with the progress display this run asks for.
fn compile_logged(
    cli: &Cli,
    map: &Path,
    options: &CompileOptions,
    log: &Log,
    batch: bool,
) -> Outcome {
    let progress: Box<dyn Progress> = if batch || cli.quiet {
        Box::new(NoProgress)
    } else if std::io::stderr().is_terminal() {
        let bar = TerminalBar::new(cli.estimate);
        log.set_console(bar.printer(cli.json));
        Box::new(bar)
    } else if cli.estimate {
        Box::new(PercentLines::with_estimate())
    } else {
        Box::new(PercentLines::default())
    };
    match pipeline::compile(map, options, log, progress.as_ref()) {
        Ok(stats) => {
            if cli.chart {
                for line in report::chart_lines(&stats) {
                    log.info(line);
                }
            }
            Outcome::Built(Box::new(stats))
        }
        Err(e) => {
            // The console gets the error once, at the end; the log file keeps it too.
            log.record(format!("ERROR: {e}"));
            if batch {
                log.info(format!("ERROR: {e}"));
            }
            Outcome::Failed(e)
        }
    }
}

/// XXH64 of the map's bytes, as the .vdg records it.
fn map_hash(map: &Path) -> Option<u64> {
    std::fs::read(map).ok().map(|b| vdgformat::xxh64(&b, 0))
}

/// `OUT.err` beside the output on failure, removed on success (VHLT's convention: a
/// compile chain stops at the first `.err`).
fn write_err_file(output: &Path, outcome: &Outcome) {
    let path = output.with_extension("err");
    match outcome {
        Outcome::Failed(e) => {
            let text = format!("{}\nERROR: {e}\n", command_line());
            let _ = toolbox::write_bytes_atomic(&path, text.as_bytes());
        }
        _ => {
            let _ = std::fs::remove_file(&path);
        }
    }
}

fn command_line() -> String {
    format!(
        "bsp2vdg {} (build {}) {}",
        env!("CARGO_PKG_VERSION"),
        options::BUILD,
        std::env::args().skip(1).collect::<Vec<_>>().join(" ")
    )
}

/// Every output place of every map, checked before the first compile starts.
fn check_outputs(cli: &Cli) -> Result<()> {
    let planned: Vec<cli::outputs::Planned<'_>> = cli
        .maps
        .iter()
        .map(|map| {
            let output = compile_options(cli, map).output;
            let mut companions = vec![output.with_extension("err")];
            if !cli.nolog {
                companions.push(log_path(cli, &output));
            }
            if cli.save_samples {
                companions.push(options::samples_path(&output));
            }
            cli::outputs::Planned {
                map,
                output,
                companions,
            }
        })
        .collect();
    cli::outputs::check(&planned)
}

fn compile_options(cli: &Cli, map: &Path) -> CompileOptions {
    let output = cli::outputs::output_for(map, cli.output.as_deref());
    CompileOptions {
        sampling: SampleOptions {
            spacing: cli.sample_spacing,
            max_samples: cli.max_samples,
            subset: cli.subset,
            ..SampleOptions::default()
        },
        reduction_limit: cli.reduction_limit,
        reduction_floor: cli.reduction_floor,
        reduction_cost: cli.reduction_cost.cost(),
        min_clearance: cli.min_clearance,
        tree_leaf_size: cli.tree_leaf_size,
        liquids_are_solid: cli.liquids_solid,
        clip_is_solid: cli.clip_solid,
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
        source_name: match &cli.source_name {
            Some(n) if n.is_empty() => Some(
                map.file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
            ),
            other => other.clone(),
        },
        wall_raise: !cli.no_wall_raise,
        coverage_guards: !cli.no_coverage_guards,
        game: cli.game.map(|g| match g {
            GameArg::Goldsrc => bsp::Game::GoldSrc,
            GameArg::Quake => bsp::Game::Quake,
        }),
        budget: cli.budget,
    }
}

/// The log beside the output (`MAP.log` for the default output `MAP.vdg`, as map
/// compile tools do), or `-logfile FILE`. With `-o` elsewhere the map's folder stays
/// untouched: shared or read-only map folders are common in build farms.
fn log_path(cli: &Cli, output: &Path) -> PathBuf {
    cli.logfile
        .clone()
        .unwrap_or_else(|| output.with_extension("log"))
}

/// Appends the log to its file as it goes (see [`log_path`]), so a killed compile
/// leaves what it logged. A log that cannot be written never fails the compile.
fn open_log_file(cli: &Cli, output: &Path, log: &mut Log, name: &str) {
    if cli.nolog {
        return;
    }
    let path = log_path(cli, output);
    // One -logfile for a whole batch: each line says which map it is about.
    let prefix = if cli.logfile.is_some() && cli.maps.len() > 1 {
        format!("[{name}] ")
    } else {
        String::new()
    };
    if let Err(e) = log.attach_file(&path, &command_line(), &prefix) {
        log.warn(format!(
            "could not write the log file {}: {e}",
            path.display()
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(args: &[&str]) -> Result<Cli, i32> {
        let v: Vec<String> = args.iter().map(|s| s.to_string()).collect();
        parse(&v).map(|(cli, _)| cli)
    }

    #[test]
    fn compile_tool_spellings_parse() {
        let cli = parsed(&[
            "bsp2vdg",
            "-sd",
            "16",
            "-savesamples",
            "-lowpriority",
            "-logfile",
            "x.log",
            "-estimate",
            "-chart",
            "-dev",
            "2",
            "-force",
            "--source-name",
            "m.bsp",
            "-o",
            "x.vdg",
        ])
        .unwrap();
        assert_eq!(cli.sample_spacing, 16.0);
        assert!(cli.save_samples && cli.low && cli.estimate && cli.chart && cli.force);
        assert_eq!(cli.logfile.as_deref(), Some(Path::new("x.log")));
        assert_eq!(cli.dev, Some(2));
        // --source-name takes a value only with '=': the next word is still a map.
        assert_eq!(cli.source_name.as_deref(), Some(""));
        assert_eq!(cli.maps, [PathBuf::from("m.bsp")]);
        let cli = parsed(&["bsp2vdg", "--source-name=a.bsp", "-low", "m.bsp"]).unwrap();
        assert_eq!(cli.source_name.as_deref(), Some("a.bsp"));
    }

    #[test]
    fn usage_errors_exit_2() {
        assert_eq!(parsed(&["bsp2vdg", "-savesample", "m.bsp"]).err(), Some(2));
        assert_eq!(
            parsed(&["bsp2vdg", "-low", "-high", "m.bsp"]).err(),
            Some(2)
        );
        assert_eq!(parsed(&["bsp2vdg"]).err(), Some(2));
    }

    #[test]
    fn cli_definition_is_consistent() {
        use clap::CommandFactory;
        Cli::command().debug_assert();
    }
}
