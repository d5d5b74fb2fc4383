//! `vdgview replay MAP.bsp MAP.vdg`: measure cameras against the map's ground truth.
//!
//! The thesis judged its camera by one replay and two plots (figs. 7.2, 7.3). Here every
//! camera follows every route of a map, the routes come from the map itself (player
//! spawns walked with the player's clip hulls, a Counter-Strike bot nav mesh, or a
//! recorded JSONL playtest) and never from the graph under test, and every frame is
//! measured against the BSP (solid, near plane, visibility) and for smoothness
//! (speed, jerk, jumps, stalls). [`route`] and [`walk`] make the target's motion,
//! [`spawns`], [`nav`] and [`jsonl`] the routes, [`cameras`] the cameras and the
//! baselines, [`metrics`] the measures, [`plots`] and [`frames`] the pictures.
//!
//! ```no_run
//! use vdgview::replay::{cameras::{ChaseCam, ReplayCamera}, route::{Route, TargetState}};
//! # let oracle: bsp::oracle::Oracle = unimplemented!();
//! let mut cam = ChaseCam::new(&oracle);
//! let t = TargetState { t: 0.0, origin: [0.0, 0.0, 36.0], angles: [0.0, 90.0, 0.0], velocity: [0.0; 3], crouch: false, game: bsp::Game::GoldSrc };
//! cam.reset(&t);
//! let frame = cam.update(&t, 1.0 / 60.0);
//! toolbox::outln!("camera at {:?} looking at {:?}", frame.eye, frame.look_at);
//! ```

pub mod cameras;
pub mod demo;
pub mod frames;
pub mod jsonl;
pub mod metrics;
pub mod nav;
pub mod plots;
pub mod route;
pub mod spawns;
pub mod vdgcam;
pub mod walk;

use anyhow::{Context, Result, bail};
use bsp::Bsp;
use bsp::oracle::Oracle;
use bsp::walls::Walls;
use cameras::{ChaseCam, Frame, ReplayCamera, SpringArm};
use metrics::{FrameMeasure, Summary};
use rayon::prelude::*;
use route::Route;
use std::path::{Path, PathBuf};
use std::time::Instant;
use vdgformat::Vdg;

/// Where the target's routes come from.
#[derive(Debug, Clone, PartialEq)]
pub enum RouteSource {
    /// Pairs of player spawns, walked on the floor (default).
    Spawns,
    /// Random area pairs of a Counter-Strike bot nav mesh.
    Nav(PathBuf),
    /// Recorded frames (`t`, `origin`, `angles` per line).
    Jsonl(PathBuf),
    /// A GoldSrc demo (`.dem`, the game's `record`): the recorded player.
    Demo(PathBuf),
}

impl RouteSource {
    /// Parses `spawns`, `nav:FILE.nav`, `demo:FILE.dem` or `FILE.jsonl`.
    pub fn parse(s: &str) -> Result<RouteSource> {
        if s == "spawns" {
            Ok(RouteSource::Spawns)
        } else if let Some(p) = s.strip_prefix("nav:") {
            Ok(RouteSource::Nav(PathBuf::from(p)))
        } else if let Some(p) = s.strip_prefix("demo:") {
            Ok(RouteSource::Demo(PathBuf::from(p)))
        } else if s.ends_with(".dem") {
            Ok(RouteSource::Demo(PathBuf::from(s)))
        } else if s.ends_with(".jsonl") || s.ends_with(".json") {
            Ok(RouteSource::Jsonl(PathBuf::from(s)))
        } else {
            bail!("--routes {s:?}: expected spawns, nav:FILE.nav, demo:FILE.dem or FILE.jsonl")
        }
    }

    pub fn label(&self) -> String {
        match self {
            RouteSource::Spawns => "spawns".into(),
            RouteSource::Nav(p) => format!("nav:{}", p.display()),
            RouteSource::Jsonl(p) => p.display().to_string(),
            RouteSource::Demo(p) => format!("demo:{}", p.display()),
        }
    }
}

/// Parses a frame time: `1/60`, `0.0166`.
pub fn parse_dt(s: &str) -> Result<f64> {
    let v = match s.split_once('/') {
        Some((a, b)) => {
            let (a, b): (f64, f64) = (a.trim().parse()?, b.trim().parse()?);
            a / b
        }
        None => s.trim().parse()?,
    };
    if !(v.is_finite() && v > 0.0 && v <= 0.25) {
        bail!("--dt {s}: expected a frame time in (0, 0.25] seconds, e.g. 1/60");
    }
    Ok(v)
}

/// The cameras `replay` knows.
pub const CAMERA_NAMES: [&str; 4] = ["vdg", "vdg-thesis", "chase", "springarm"];
/// The cameras compared when `--camera` is not given.
pub const DEFAULT_CAMERAS: &str = "vdg,vdg-thesis,chase,springarm";

/// Checks a `--camera` list before any work is done.
pub fn check_camera_names(names: &[String]) -> Result<()> {
    if names.is_empty() {
        bail!("--camera: no camera given");
    }
    for n in names {
        if !CAMERA_NAMES.contains(&n.as_str()) {
            bail!(
                "--camera {n:?}: unknown camera (known: {})",
                CAMERA_NAMES.join(", ")
            );
        }
    }
    Ok(())
}

/// The routes of a replay with how they were made.
#[derive(Debug, Clone, Default)]
pub struct RouteSet {
    pub source: String,
    pub routes: Vec<Route>,
    /// Endpoint pairs no path joined.
    pub unreachable: usize,
    /// Walker steps without a floor position (the player stayed put).
    pub stuck_steps: usize,
    /// Routes that end where the walker could not follow the path (the rest of the path
    /// is the next route, named `NAME#2`...; see `walk::walk_parts`).
    pub cut_short: usize,
    /// Falls from ledges taken under gravity.
    pub falls: usize,
}

/// The map a replay runs on, for the checks that a nav mesh or a demo was made on it.
#[derive(Debug, Clone, Copy)]
pub struct MapCheck<'a> {
    /// The BSP file.
    pub path: &'a Path,
    /// Accept a nav mesh or demo of another map (the routes then mean little).
    pub force: bool,
}

/// Refuses (or, with `force`, warns about) a route source made for another map.
fn check_source(result: std::result::Result<(), String>, force: bool) -> Result<()> {
    match result {
        Ok(()) => Ok(()),
        Err(e) if force => {
            toolbox::errln!("vdgview: warning: {e}");
            Ok(())
        }
        Err(e) => bail!("{e}"),
    }
}

/// Makes the routes of a map.
pub fn load_routes(
    bsp: &Bsp,
    oracle: &Oracle,
    source: &RouteSource,
    map: MapCheck<'_>,
    seed: u64,
    max_routes: usize,
) -> Result<RouteSet> {
    let (routes, stats, unreachable) = match source {
        RouteSource::Spawns => spawns::routes(bsp, oracle, seed, max_routes),
        RouteSource::Nav(p) => {
            let mesh = nav::NavMesh::open(p).map_err(anyhow::Error::msg)?;
            match nav::same_map(&mesh, p, map.path, oracle) {
                Ok(Some(warning)) => toolbox::errln!("vdgview: warning: {warning}"),
                Ok(None) => {}
                Err(e) => check_source(Err(e), map.force)?,
            }
            nav::routes(&mesh, oracle, seed, max_routes)
        }
        RouteSource::Demo(p) => {
            let d = demo::open(p).map_err(anyhow::Error::msg)?;
            check_source(demo::same_map(&d, p, map.path), map.force)?;
            if oracle.game() != bsp::Game::GoldSrc {
                bail!(
                    "{}: a GoldSrc demo cannot be replayed on a {:?} map ({})",
                    p.display(),
                    oracle.game(),
                    map.path.display()
                );
            }
            let stem = p
                .file_stem()
                .map_or("demo".into(), |s| s.to_string_lossy().into_owned());
            let routes = demo::routes(&d, &stem, oracle.game());
            if routes.is_empty() {
                bail!(
                    "{}: no playback segment with at least two player frames",
                    p.display()
                );
            }
            (routes, Vec::new(), 0)
        }
        RouteSource::Jsonl(p) => {
            let text =
                std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
            let stem = p
                .file_stem()
                .map_or("recording".into(), |s| s.to_string_lossy().into_owned());
            let routes = jsonl::parse(&text, &stem, oracle.game())
                .map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))?;
            (routes, Vec::new(), 0)
        }
    };
    if routes.is_empty() {
        bail!(
            "no route could be made from {} ({unreachable} endpoint pairs unreachable on the floor)",
            source.label()
        );
    }
    Ok(RouteSet {
        source: source.label(),
        routes,
        unreachable,
        stuck_steps: stats.iter().map(|s| s.stuck_steps).sum(),
        cut_short: stats.iter().filter(|s| s.cut_short).count(),
        falls: stats.iter().map(|s| s.falls).sum(),
    })
}

/// Builds the named cameras.
pub fn make_cameras<'a>(
    names: &[String],
    oracle: &'a Oracle,
    walls: &'a Walls,
    graph: Vdg<'a>,
    params: Option<&str>,
) -> Result<Vec<Box<dyn ReplayCamera + 'a>>> {
    let mut out: Vec<Box<dyn ReplayCamera + 'a>> = Vec::new();
    for n in names {
        match n.as_str() {
            "chase" => out.push(Box::new(ChaseCam::new(oracle))),
            "springarm" => out.push(Box::new(SpringArm::new(walls))),
            "vdg" | "vdg-thesis" => out.push(Box::new(
                vdgcam::VdgCamera::new(n, graph, params).map_err(anyhow::Error::msg)?,
            )),
            other => bail!(
                "--camera {other:?}: unknown camera (known: {})",
                CAMERA_NAMES.join(", ")
            ),
        }
    }
    if out.is_empty() {
        bail!("--camera: no camera given");
    }
    Ok(out)
}

/// A run of frames whose target stood outside Volume(VDG).
#[derive(Debug, Clone, PartialEq)]
pub struct OutsideRun {
    pub route: String,
    pub t0: f64,
    pub t1: f64,
    /// The target's origin at the run's first frame.
    pub origin: [f32; 3],
}

/// One camera's results.
#[derive(Debug, Clone)]
pub struct CameraRun {
    pub name: String,
    /// Per route, per frame.
    pub routes: Vec<Vec<FrameMeasure>>,
    pub summary: Summary,
}

/// Everything a replay measured.
#[derive(Debug, Clone)]
pub struct Report {
    pub dt: f64,
    pub routes: RouteSet,
    pub cameras: Vec<CameraRun>,
    pub outside: Vec<OutsideRun>,
    pub outside_frames: usize,
    pub frames_per_camera: usize,
}

/// Runs every camera over every route at step `dt` and measures each frame.
/// `progress` is told (camera, route index, route count) as work finishes.
pub fn replay(
    oracle: &Oracle,
    walls: &Walls,
    graph: &Vdg<'_>,
    routes: RouteSet,
    cameras: &mut [Box<dyn ReplayCamera + '_>],
    dt: f64,
    progress: &mut dyn FnMut(&str, usize, usize),
) -> Report {
    let sampled: Vec<Vec<route::TargetState>> =
        routes.routes.iter().map(|r| r.resample(dt)).collect();
    let outside: Vec<Vec<bool>> = sampled
        .iter()
        .map(|s| s.iter().map(|t| !graph.contains(t.origin)).collect())
        .collect();
    let mut runs = Vec::new();
    for (r, (states, out)) in routes.routes.iter().zip(sampled.iter().zip(&outside)) {
        let mut start: Option<usize> = None;
        for i in 0..=out.len() {
            let o = out.get(i).copied().unwrap_or(false);
            match (o, start) {
                (true, None) => start = Some(i),
                (false, Some(s)) => {
                    runs.push(OutsideRun {
                        route: r.name.clone(),
                        t0: states[s].t,
                        t1: states[i - 1].t,
                        origin: states[s].origin,
                    });
                    start = None;
                }
                _ => {}
            }
        }
    }
    let mut results = Vec::new();
    for cam in cameras.iter_mut() {
        let name = cam.name().to_string();
        let d_mu = cam.ideal_distance();
        let mut played: Vec<(Vec<Frame>, Vec<f32>)> = Vec::new();
        for (k, states) in sampled.iter().enumerate() {
            let mut frames = Vec::with_capacity(states.len());
            let mut micros = Vec::with_capacity(states.len());
            if let Some(first) = states.first() {
                cam.reset(first);
            }
            for s in states {
                let t0 = Instant::now();
                let f = cam.update(s, dt as f32);
                micros.push(t0.elapsed().as_secs_f32() * 1e6);
                frames.push(f);
            }
            played.push((frames, micros));
            progress(&name, k + 1, sampled.len());
        }
        let measured: Vec<Vec<FrameMeasure>> = played
            .par_iter()
            .zip(sampled.par_iter().zip(outside.par_iter()))
            .map(|((frames, micros), (states, out))| {
                metrics::measure(oracle, walls, graph, states, frames, micros, out, dt, d_mu)
            })
            .collect();
        let summary = metrics::summarise(&measured, dt);
        results.push(CameraRun {
            name,
            routes: measured,
            summary,
        });
    }
    let outside_frames = outside.iter().flatten().filter(|&&o| o).count();
    let frames_per_camera = sampled.iter().map(Vec::len).sum();
    Report {
        dt,
        routes,
        cameras: results,
        outside: runs,
        outside_frames,
        frames_per_camera,
    }
}

impl Report {
    /// The `--json` object.
    pub fn to_json(&self, map: &Path, vdg: &Path) -> serde_json::Value {
        let cams: serde_json::Map<String, serde_json::Value> = self
            .cameras
            .iter()
            .map(|c| (c.name.clone(), c.summary.to_json()))
            .collect();
        let frames = self.frames_per_camera.max(1);
        serde_json::json!({
            "map": map.display().to_string(),
            "vdg": vdg.display().to_string(),
            "dt": self.dt,
            "routes": {
                "source": self.routes.source,
                "count": self.routes.routes.len(),
                "unreachable": self.routes.unreachable,
                "stuck_steps": self.routes.stuck_steps,
                "cut_short": self.routes.cut_short,
                "falls": self.routes.falls,
                "frames": self.frames_per_camera,
                "seconds": self.frames_per_camera as f64 * self.dt,
                "names": self.routes.routes.iter().map(|r| r.name.clone()).collect::<Vec<_>>(),
            },
            "target_outside_fraction": self.outside_frames as f64 / frames as f64,
            "target_outside_frames": self.outside_frames,
            "target_outside": self.outside.iter().map(|o| serde_json::json!({
                "route": o.route, "t0": o.t0, "t1": o.t1, "origin": o.origin,
            })).collect::<Vec<_>>(),
            "cameras": cams,
        })
    }

    /// The human-readable table.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{} routes ({}), {} frames per camera at dt {:.4} s ({:.1} s); target outside Volume(VDG) in {:.2} % of frames ({} runs)\n",
            self.routes.routes.len(),
            self.routes.source,
            self.frames_per_camera,
            self.dt,
            self.frames_per_camera as f64 * self.dt,
            100.0 * self.outside_frames as f64 / self.frames_per_camera.max(1) as f64,
            self.outside.len()
        );
        s += &format!(
            "{:<12} {:>7} {:>6} {:>6} {:>8} {:>8} {:>8} {:>7} {:>6} {:>6} {:>10} {:>8} {:>8} {:>9}\n",
            "camera",
            "frames",
            "solid",
            "near",
            "visible",
            "hull vis",
            "false oc",
            "occl s",
            "jumps",
            "stalls",
            "rms jerk",
            "|d-dmu|",
            "cuts/min",
            "median us"
        );
        for c in &self.cameras {
            let m = &c.summary;
            s += &format!(
                "{:<12} {:>7} {:>6} {:>6} {:>7.2}% {:>7.2}% {:>7.2}% {:>7.2} {:>6} {:>6} {:>10.0} {:>8.1} {:>8.2} {:>9.1}\n",
                c.name,
                m.frames,
                m.solid_frames,
                m.nearplane_frames,
                100.0 * m.visible_fraction,
                100.0 * m.hull_visible_mean,
                100.0 * m.graph_false_occlusion,
                m.longest_occlusion_s,
                m.jumps,
                m.stalls,
                m.rms_jerk,
                m.mean_abs_dist_error,
                m.cuts_per_min,
                m.median_us
            );
        }
        s
    }

    /// Writes `DIR/<camera>.csv` (every frame) and `DIR/outside.csv` (every frame whose
    /// target is outside the volume).
    pub fn write_csv(&self, dir: &Path) -> Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        for c in &self.cameras {
            let mut text = String::from(metrics::CSV_HEADER);
            text.push('\n');
            for (r, ms) in self.routes.routes.iter().zip(&c.routes) {
                for m in ms {
                    text += &metrics::csv_row(&r.name, m);
                    text.push('\n');
                }
            }
            crate::render::write_atomic(&dir.join(format!("{}.csv", c.name)), text.as_bytes())?;
        }
        if let Some(c) = self.cameras.first() {
            let mut text = String::from("route,t,x,y,z\n");
            for (r, ms) in self.routes.routes.iter().zip(&c.routes) {
                for m in ms.iter().filter(|m| m.target_outside) {
                    text += &format!(
                        "{},{:.4},{:.2},{:.2},{:.2}\n",
                        r.name.replace(',', ";"),
                        m.t,
                        m.target[0],
                        m.target[1],
                        m.target[2]
                    );
                }
            }
            crate::render::write_atomic(&dir.join("outside.csv"), text.as_bytes())?;
        }
        Ok(())
    }
}
