//! `vdgview <command> ...`: one subcommand per module of the library.

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use vdgcheck::{CheckOptions, check};
use vdgview::render::{Mode, RenderRequest, Style, View};
use vdgview::{camera, info, query, render, scene};

#[derive(Parser, Debug)]
#[command(
    name = "vdgview",
    version,
    about = "Inspect, check, query and render Voronoi Distance Graphs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Measure a graph against its map's BSP: leak, coverage, walkable and crouch
    /// coverage, visibility errors on random and on camera sight lines.
    /// Exits non-zero when anything leaks or is seen through a wall.
    Check {
        #[arg(value_name = "MAP.bsp")]
        map: PathBuf,
        #[arg(value_name = "FILE.vdg")]
        vdg: PathBuf,
        /// Random points for leak, coverage and walkable coverage each, as many columns for
        /// crouch coverage (a tenth as many random segments, and camera sight lines to a
        /// tenth of the standing places).
        #[arg(long, default_value_t = 1_000_000)]
        samples: usize,
        /// Seed of the random points.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Treat water, slime and lava as walls.
        #[arg(long)]
        liquids_solid: bool,
        /// Treat player and monster clip brushes as walls (as `bsp2vdg --clip-solid`).
        #[arg(long)]
        clip_solid: bool,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Counts, bounds, clearance histogram, build options and source map (its game)
    /// of a .vdg; given a .bsp, the map's game, format, counts and bounds.
    Info {
        #[arg(value_name = "FILE.vdg|MAP.bsp")]
        graph: PathBuf,
    },
    /// Runtime queries: `clearance X Y Z`, `visible X1 Y1 Z1 X2 Y2 Z2`, `path X1 Y1 Z1 X2 Y2 Z2`.
    Query {
        #[arg(value_name = "FILE.vdg")]
        graph: PathBuf,
        /// clearance, visible or path.
        #[arg(value_name = "QUERY")]
        kind: String,
        /// The point(s): 3 numbers for clearance, 6 for visible and path.
        #[arg(value_name = "COORD", allow_negative_numbers = true, num_args = 0..)]
        coords: Vec<String>,
    },
    /// Interactive fly-through (software rendered; runs under Xvfb, no GPU).
    View(ViewArgs),
    /// Headless, deterministic PNG render of a graph inside its map (no GPU needed).
    Render(RenderArgs),
    /// Measure cameras (VDG camera, chase cam, spring arm) on routes made from the map,
    /// against the map's BSP: solid, near plane, visibility, jumps, jerk, cuts, time.
    Replay(ReplayArgs),
    /// The header of a GoldSrc demo (.dem): map, game, protocol, duration, frames.
    Demo {
        #[arg(value_name = "FILE.dem")]
        demo: PathBuf,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Chart of `replay --json` reports across maps (one panel per measure).
    ReplaySummary {
        /// Output PNG.
        #[arg(short, long, value_name = "OUT.png")]
        output: PathBuf,
        /// Title of the chart.
        #[arg(long, default_value = "camera measures per map")]
        title: String,
        /// `replay --json` outputs (the map label is the file stem).
        #[arg(value_name = "REPORT.json", required = true)]
        reports: Vec<PathBuf>,
    },
}

#[derive(clap::Args, Debug)]
struct ReplayArgs {
    #[arg(value_name = "MAP.bsp")]
    map: PathBuf,
    #[arg(value_name = "MAP.vdg")]
    vdg: PathBuf,
    /// Target routes: spawns (pairs of player spawns walked on the floor), nav:FILE.nav
    /// (a Counter-Strike bot nav mesh), demo:FILE.dem (a GoldSrc demo: the recorded
    /// player) or FILE.jsonl (recorded frames: t, origin, angles).
    #[arg(long, default_value = "spawns")]
    routes: String,
    /// Replay a graph, nav mesh or demo made for another map than MAP.bsp (refused
    /// otherwise: the figures would mean nothing).
    #[arg(long)]
    force: bool,
    /// Cameras to compare, comma-separated.
    #[arg(long, default_value = vdgview::replay::DEFAULT_CAMERAS)]
    camera: String,
    /// Camera parameters for the VDG camera (TOML).
    #[arg(long, value_name = "cam.toml")]
    params: Option<PathBuf>,
    /// Frame time in seconds: 1/60, 1/30, 0.02 ...
    #[arg(long, default_value = "1/60")]
    dt: String,
    /// Print one JSON object (per-camera summaries under cameras.<name>).
    #[arg(long)]
    json: bool,
    /// Write every frame's measures as CSV into this folder (one file per camera,
    /// plus outside.csv: the target positions outside Volume(VDG)).
    #[arg(long, value_name = "DIR")]
    csv: Option<PathBuf>,
    /// Write speed, occlusion and summary charts (PNG) into this folder.
    #[arg(long, value_name = "DIR")]
    plots: Option<PathBuf>,
    /// Write a contact sheet of frames seen from each camera into this folder.
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
    /// Seed of the route choices (pairs, speeds, stops, turns, crouching).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Most routes per map (spawn pairs are capped with the seed on big maps).
    #[arg(long, default_value_t = 8)]
    max_routes: usize,
    /// Also write the routes as JSONL (replayable with --routes FILE.jsonl).
    #[arg(long, value_name = "FILE.jsonl")]
    save_routes: Option<PathBuf>,
    /// Treat water, slime and lava as walls.
    #[arg(long)]
    liquids_solid: bool,
}

#[derive(clap::Args, Debug)]
struct RenderArgs {
    #[arg(value_name = "MAP.bsp")]
    map: PathBuf,
    /// The graph (leave out to draw the map alone).
    #[arg(value_name = "FILE.vdg")]
    graph: Option<PathBuf>,
    /// Output PNG.
    #[arg(short, long, value_name = "OUT.png")]
    output: PathBuf,
    /// 1 wireframe, 2 reduction cost, 3 faces coloured by clearance (blue large, red small), 0 map only.
    #[arg(long, default_value_t = 3)]
    mode: u32,
    /// Sample points to draw as black dots (a `bsp2vdg -savesamples` file).
    #[arg(long, value_name = "FILE")]
    samples: Option<PathBuf>,
    /// Camera as X,Y,Z:TX,TY,TZ[:FOV] (position, target, vertical fov in degrees); default: framed automatically.
    #[arg(long, value_name = "POS:TARGET:FOV", conflicts_with = "top")]
    camera: Option<String>,
    /// Top-down orthographic overview.
    #[arg(long)]
    top: bool,
    /// Image size WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768")]
    size: String,
    /// Supersampling factor (1 = off) for smoother edges.
    #[arg(long, default_value_t = 2)]
    supersample: usize,
}

#[derive(clap::Args, Debug)]
struct ViewArgs {
    #[arg(value_name = "MAP.bsp")]
    map: PathBuf,
    #[arg(value_name = "FILE.vdg")]
    graph: Option<PathBuf>,
    /// Sample points to draw as black dots (a `bsp2vdg -savesamples` file).
    #[arg(long, value_name = "FILE")]
    samples: Option<PathBuf>,
    /// Window size WIDTHxHEIGHT.
    #[arg(long, default_value = "960x600")]
    size: String,
    /// Console commands to run before the first frame, `;`-separated
    /// (e.g. "gopos 0 0 64; setang 90 -10; mode 1").
    #[arg(long, value_name = "COMMANDS")]
    exec: Option<String>,
    /// Close after this many frames and print the median frame time.
    #[arg(long)]
    frames: Option<u64>,
    /// Close after this many seconds and print the median frame time.
    #[arg(long)]
    seconds: Option<f64>,
    /// Play a route with the VDG camera: spawns (the first spawn route), nav:FILE.nav or
    /// FILE.jsonl (the first route in it). Needs the graph.
    #[arg(long, value_name = "ROUTE")]
    follow: Option<String>,
    /// Camera for --follow: vdg, vdg-thesis, chase or springarm.
    #[arg(long, default_value = "vdg")]
    follow_camera: String,
    /// Write the view as a PNG and exit, without a window or a display (after
    /// --exec; with --follow, the pose of frame --frames, default the first).
    #[arg(long, value_name = "OUT.png")]
    screenshot: Option<PathBuf>,
}

fn main() {
    let cli = Cli::parse();
    let verdict = run(cli);
    // A reader closing the pipe (`vdgview info G | head -1`) is no failure; a report
    // lost on a full disk is.
    if let Some(lost) = toolbox::console::stdout_lost() {
        toolbox::errln!("vdgview: error: {lost}");
        std::process::exit(1);
    }
    match verdict {
        Ok(true) => {}
        // A negative verdict (e.g. a failed check) after its report was printed.
        Ok(false) => std::process::exit(1),
        Err(e) => {
            toolbox::errln!("vdgview: error: {e:#}");
            std::process::exit(1);
        }
    }
}

/// Returns the command's verdict: false when a check failed.
fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::Check {
            map,
            vdg,
            samples,
            seed,
            liquids_solid,
            clip_solid,
            json,
        } => run_check(&map, &vdg, samples, seed, (liquids_solid, clip_solid), json),
        Command::Info { graph } => {
            let mut head = [0u8; 8];
            let is_map = std::fs::File::open(&graph)
                .and_then(|mut f| std::io::Read::read(&mut f, &mut head))
                .is_ok_and(|n| bsp::BspVersion::identify(&head[..n]).is_some());
            if is_map {
                toolbox::out!("{}", info::map_summary(&scene::open_map(&graph)?));
            } else {
                let file = scene::open_graph(&graph)?;
                toolbox::out!("{}", info::summary(&file.graph()));
            }
            Ok(true)
        }
        Command::Query {
            graph,
            kind,
            coords,
        } => {
            let q = query::Query::parse(&kind, &coords)?;
            let file = scene::open_graph(&graph)?;
            toolbox::out!("{}", q.run(&file.graph()));
            Ok(true)
        }
        Command::Render(args) => run_render(args).map(|()| true),
        Command::View(args) => run_view(args).map(|()| true),
        Command::Replay(args) => run_replay(args).map(|()| true),
        Command::Demo { demo, json } => {
            use vdgview::replay::demo as dem;
            let d = dem::open(&demo).map_err(anyhow::Error::msg)?;
            if json {
                toolbox::outln!("{}", dem::summary_json(&d));
            } else {
                toolbox::out!("{}", dem::summary(&d, &demo));
            }
            Ok(true)
        }
        Command::ReplaySummary {
            output,
            title,
            reports,
        } => run_replay_summary(&output, &title, &reports).map(|()| true),
    }
}

fn run_check(
    map: &std::path::Path,
    vdg: &std::path::Path,
    samples: usize,
    seed: u64,
    (liquids_solid, clip_solid): (bool, bool),
    json: bool,
) -> Result<bool> {
    if samples == 0 {
        bail!("--samples must be at least 1");
    }
    let bsp = scene::open_map(map)?;
    let file = scene::open_graph(vdg)?;
    // Figures of a graph against another map mean nothing: refuse.
    scene::same_map(map, vdg, &file.graph())?;
    let bytes = std::fs::metadata(vdg)
        .map(|m| m.len() as usize)
        .unwrap_or(0);
    let options = CheckOptions {
        samples,
        seed,
        liquids_are_solid: liquids_solid,
        clip_is_solid: clip_solid,
        ..Default::default()
    };
    let r = check(&bsp, &file.graph(), bytes, &options);
    if json {
        toolbox::outln!("{}", r.to_json());
    } else {
        toolbox::outln!("check {} against {}", vdg.display(), map.display());
        toolbox::outln!(
            "  graph      {} vertices, {} faces, {} bytes",
            r.vertices,
            r.faces,
            r.bytes
        );
        toolbox::outln!(
            "  leak       {:.6}  ({} of {} volume points in walls)",
            r.leak(),
            r.leaked,
            r.leak_points
        );
        toolbox::outln!(
            "  coverage   {:.4}  ({} of {} free points with clearance >= {} inside)",
            r.coverage(),
            r.covered,
            r.coverage_points,
            options.coverage_clearance
        );
        toolbox::outln!(
            "  visible    fp {:.6} ({} of {} blocked), fn {:.4} ({} of {} free; {:.4} with both ends inside, {:.4} staying inside)",
            r.visible_fp(),
            r.false_positives,
            r.segments - r.free_segments,
            r.visible_fn(),
            r.false_negatives,
            r.free_segments,
            r.visible_fn_inside(),
            r.visible_fn_query()
        );
        let share = |x: Option<f64>| x.map_or("n/a".to_string(), |x| format!("{x:.4}"));
        toolbox::outln!(
            "  walkable   {}  ({} of {} standing player origins inside), head {} ({} of {})",
            share(r.walkable_coverage()),
            r.walkable_covered,
            r.walkable_points,
            share(r.walkable_coverage_head()),
            r.walkable_head_covered,
            r.walkable_head_points
        );
        toolbox::outln!(
            "  crouching  {}  ({} of {} eyes of places where a player only fits crouching inside)",
            share(r.crouch_coverage()),
            r.crouch_covered,
            r.crouch_points
        );
        toolbox::outln!(
            "  camera     fn {} ({} of {} free sight lines from a camera's distance to a standing origin, both ends inside), fp {} of {}",
            share(r.visible_fn_camera()),
            r.camera_false_negatives,
            r.camera_lines_inside,
            r.camera_false_positives,
            r.camera_lines
        );
        toolbox::outln!(
            "  {} in {:.1} s (leak {:.1} s, coverage {:.1} s, visible {:.1} s, walkable {:.1} s)",
            if r.passed() { "PASSED" } else { "FAILED" },
            r.seconds,
            r.seconds_parts[0],
            r.seconds_parts[1],
            r.seconds_parts[2],
            r.seconds_parts[3]
        );
    }
    Ok(r.passed())
}

fn run_render(args: RenderArgs) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    let mode = Mode::from_number(args.mode)
        .with_context(|| format!("--mode {}: expected 0, 1, 2 or 3", args.mode))?;
    if !(1..=4).contains(&args.supersample) {
        anyhow::bail!("--supersample {}: expected 1..4", args.supersample);
    }
    let view = match (&args.camera, args.top) {
        (Some(c), _) => View::Camera(camera::parse_camera(c).map_err(anyhow::Error::msg)?),
        (None, true) => View::Top,
        (None, false) => View::Auto,
    };
    let bsp = scene::open_map(&args.map)?;
    let file = args.graph.as_deref().map(scene::open_graph).transpose()?;
    if let (Some(f), Some(path)) = (&file, &args.graph)
        && let Err(e) = scene::same_map(&args.map, path, &f.graph())
    {
        // A picture of a graph in another map can still be wanted (a moved map): warn.
        toolbox::errln!("vdgview: warning: {e}");
    }
    if mode == Mode::ReductionCost && file.is_some() {
        anyhow::bail!(render::NO_REDUCTION_COST);
    }
    let samples = args
        .samples
        .as_deref()
        .map(scene::read_samples)
        .transpose()?
        .unwrap_or_default();
    let graph = file.as_ref().map(|f| f.graph());
    let scene = scene::Scene::new(&bsp, graph.as_ref(), samples)?;
    let req = RenderRequest {
        width,
        height,
        supersample: args.supersample,
        view,
        style: Style {
            mode,
            samples: true,
            ..Style::default()
        },
    };
    let start = std::time::Instant::now();
    let pixels = render::render(&scene, &req)?;
    let png = render::encode_png(&pixels, width, height)?;
    render::write_atomic(&args.output, &png)?;
    toolbox::errln!(
        "vdgview: wrote {} ({width}x{height}, {} wall triangles, {} graph faces, rendered in {:.0} ms)",
        args.output.display(),
        scene.walls.len(),
        scene.graph.as_ref().map_or(0, |g| g.faces.len()),
        start.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

fn run_view(args: ViewArgs) -> Result<()> {
    let (width, height) = parse_size(&args.size)?;
    let bsp = scene::open_map(&args.map)?;
    let file = args.graph.as_deref().map(scene::open_graph).transpose()?;
    if let (Some(f), Some(path)) = (&file, &args.graph)
        && let Err(e) = scene::same_map(&args.map, path, &f.graph())
    {
        // A picture of a graph in another map can still be wanted (a moved map): warn.
        toolbox::errln!("vdgview: warning: {e}");
    }
    let samples = args
        .samples
        .as_deref()
        .map(scene::read_samples)
        .transpose()?
        .unwrap_or_default();
    let scene = {
        let graph = file.as_ref().map(|f| f.graph());
        scene::Scene::new(&bsp, graph.as_ref(), samples)?
    };
    let spawn = bsp
        .entities
        .iter()
        .filter(|e| e.classname().starts_with("info_player"))
        .find_map(|e| e.origin())
        .map(glam::Vec3::from);
    let follow = match &args.follow {
        Some(route) => follow_poses(&bsp, &args.map, file.as_ref(), route, &args.follow_camera)?,
        None => Vec::new(),
    };
    let viewer = vdgview::viewer::Viewer::new(scene, file, spawn);
    let exec = args
        .exec
        .as_deref()
        .map(|s| {
            s.split(';')
                .map(|c| c.trim().to_string())
                .filter(|c| !c.is_empty())
                .collect()
        })
        .unwrap_or_default();
    let options = options_of(&args, width, height, exec, follow);
    match &args.screenshot {
        Some(path) => vdgview::view::screenshot(viewer, &options, path),
        None => vdgview::view::run(viewer, &options),
    }
}

fn options_of(
    args: &ViewArgs,
    width: usize,
    height: usize,
    exec: Vec<String>,
    follow: Vec<vdgview::view::FollowPose>,
) -> vdgview::view::ViewOptions {
    vdgview::view::ViewOptions {
        width,
        height,
        exec,
        frames: args.frames,
        seconds: args.seconds,
        follow,
        follow_dt: FOLLOW_DT,
    }
}

fn run_replay(args: ReplayArgs) -> Result<()> {
    use vdgview::replay;
    let dt = replay::parse_dt(&args.dt)?;
    let source = replay::RouteSource::parse(&args.routes)?;
    if args.max_routes == 0 {
        bail!("--max-routes must be at least 1");
    }
    let names: Vec<String> = args
        .camera
        .split(',')
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .collect();
    let params = args
        .params
        .as_deref()
        .map(|p| std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display())))
        .transpose()?;
    replay::check_camera_names(&names)?;
    let start = std::time::Instant::now();
    let bsp = scene::open_map(&args.map)?;
    let file = scene::open_graph(&args.vdg)?;
    let graph = file.graph();
    // Figures of a graph against another map mean nothing: refuse unless asked.
    if let Err(e) = scene::same_map(&args.map, &args.vdg, &graph) {
        if !args.force {
            bail!("{e} (or --force)");
        }
        toolbox::errln!("vdgview: warning: {e}");
    }
    let options = bsp::oracle::OracleOptions {
        liquids_are_solid: args.liquids_solid,
        ..Default::default()
    };
    let oracle = bsp::oracle::Oracle::new(&bsp, &options);
    if oracle.clip_contents(1, [0.0; 3]).is_none() {
        bail!(
            "{}: the map has no clip hulls (needed to walk the player)",
            args.map.display()
        );
    }
    let walls = bsp::walls::Walls::of_map(&bsp, &options);
    let mut cameras = replay::make_cameras(&names, &oracle, &walls, graph, params.as_deref())?;
    toolbox::errln!("replay: making routes ({}) ...", source.label());
    let map_check = replay::MapCheck {
        path: &args.map,
        force: args.force,
    };
    let routes = replay::load_routes(
        &bsp,
        &oracle,
        &source,
        map_check,
        args.seed,
        args.max_routes,
    )?;
    toolbox::errln!(
        "replay: {} routes, {:.1} s of play ({} pairs unreachable); {} cameras at dt {:.4} s",
        routes.routes.len(),
        routes.routes.iter().map(|r| r.duration()).sum::<f64>(),
        routes.unreachable,
        cameras.len(),
        dt
    );
    if let Some(p) = &args.save_routes {
        vdgview::render::write_atomic(p, replay::jsonl::write(&routes.routes).as_bytes())?;
    }
    let mut progress = |cam: &str, k: usize, n: usize| {
        toolbox::err!("\rreplay: {cam:<12} route {k}/{n}   ");
        if k == n {
            toolbox::errln!();
        }
    };
    let report = replay::replay(
        &oracle,
        &walls,
        &graph,
        routes,
        &mut cameras,
        dt,
        &mut progress,
    );
    if let Some(dir) = &args.csv {
        report.write_csv(dir)?;
    }
    let map_name = args
        .map
        .file_stem()
        .map_or("map".into(), |s| s.to_string_lossy().into_owned());
    if let Some(dir) = &args.plots {
        replay::plots::write_all(&report, &map_name, dir)?;
    }
    if let Some(dir) = &args.frames {
        let scene = scene::Scene::new(&bsp, Some(&graph), Vec::new())?;
        replay::frames::contact_sheet(&report, &scene, dir, 6)?;
    }
    if args.json {
        toolbox::outln!("{}", report.to_json(&args.map, &args.vdg));
    } else {
        toolbox::out!("{}", report.table());
    }
    toolbox::errln!("replay: done in {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

/// Frame time of `view --follow`'s precomputed poses.
const FOLLOW_DT: f64 = 1.0 / 60.0;

/// The poses of one camera along the first route of `route` (eye, look-at, target).
fn follow_poses(
    bsp: &bsp::Bsp,
    map: &std::path::Path,
    file: Option<&vdgformat::VdgFile>,
    route: &str,
    camera: &str,
) -> Result<Vec<vdgview::view::FollowPose>> {
    use vdgview::replay;
    let Some(file) = file else {
        bail!("--follow needs the graph (vdgview view MAP.bsp MAP.vdg --follow ROUTE)");
    };
    replay::check_camera_names(&[camera.to_string()])?;
    let source = replay::RouteSource::parse(route)?;
    let options = ::bsp::oracle::OracleOptions::default();
    let oracle = ::bsp::oracle::Oracle::new(bsp, &options);
    let walls = ::bsp::walls::Walls::of_map(bsp, &options);
    let graph = file.graph();
    // A fly-through along another map's routes can still be wanted: warn only.
    let check = replay::MapCheck {
        path: map,
        force: true,
    };
    let routes = replay::load_routes(bsp, &oracle, &source, check, 1, 1)?;
    let mut cams = replay::make_cameras(&[camera.to_string()], &oracle, &walls, graph, None)?;
    let states = routes.routes[0].resample(FOLLOW_DT);
    let cam = &mut cams[0];
    cam.reset(&states[0]);
    Ok(states
        .iter()
        .map(|s| {
            let f = cam.update(s, FOLLOW_DT as f32);
            (f.eye, f.look_at, s.origin)
        })
        .collect())
}

fn run_replay_summary(output: &std::path::Path, title: &str, reports: &[PathBuf]) -> Result<()> {
    let mut rows = Vec::new();
    for p in reports {
        let text =
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).with_context(|| format!("{}: not JSON", p.display()))?;
        let Some(cams) = v.get("cameras").and_then(|c| c.as_object()) else {
            bail!(
                "{}: no \"cameras\" object (not a replay --json report)",
                p.display()
            );
        };
        let stem = p
            .file_stem()
            .map_or("?".into(), |s| s.to_string_lossy().into_owned());
        // Short labels: camera-report's names without the source prefixes and the dt.
        let mut label = stem.as_str();
        for prefix in ["bspview-", "cstrike-", "halflife_", "allocblock-"] {
            label = label.strip_prefix(prefix).unwrap_or(label);
        }
        let label = label.split("-dt").next().unwrap_or(label).to_string();
        rows.push((
            label,
            cams.iter().map(|(k, v)| (k.clone(), v.clone())).collect(),
        ));
    }
    vdgview::replay::plots::summary_chart(&rows, title, output)
}

/// Parses `WIDTHxHEIGHT`.
fn parse_size(s: &str) -> Result<(usize, usize)> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .with_context(|| format!("--size {s:?}: expected WIDTHxHEIGHT, e.g. 1024x768"))?;
    let parse = |t: &str| {
        t.trim()
            .parse::<usize>()
            .ok()
            .filter(|&v| (16..=8192).contains(&v))
    };
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => anyhow::bail!("--size {s:?}: width and height must be 16..8192"),
    }
}
