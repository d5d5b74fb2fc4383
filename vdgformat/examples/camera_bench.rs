//! Drives one camera along a route through a graph and prints per-update
//! timing and allocation figures as one JSON object.
//!
//! ```text
//! cargo run --release -p vdgformat --example camera_bench -- FILE.vdg [--frames N] [--dt S] [--thesis] [--params CAM.toml] [--json]
//! ```
//!
//! The route is made from the graph alone (the runtime crate knows nothing
//! of maps): shortest paths between vertices picked by a fixed stride,
//! walked at 265 units/s with stops and 180° turns. The first second is
//! warm-up (scratch memory sized, caches filled); allocations are counted
//! after it.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use vdgformat::VdgFile;
use vdgformat::camera::{Camera, CameraParams, Target};

/// Counts every allocation and reallocation.
struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

struct Args {
    file: String,
    frames: usize,
    dt: f32,
    thesis: bool,
    params: Option<String>,
    json: bool,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args {
        file: String::new(),
        frames: 6000,
        dt: 1.0 / 60.0,
        thesis: false,
        params: None,
        json: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--frames" => {
                args.frames = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|&n: &usize| n > 0)
                    .ok_or("--frames needs a positive whole number")?
            }
            "--dt" => {
                args.dt = it
                    .next()
                    .and_then(|v| v.parse().ok())
                    .filter(|d: &f32| d.is_finite() && *d > 0.0)
                    .ok_or("--dt needs a positive number of seconds")?
            }
            "--thesis" => args.thesis = true,
            "--params" => args.params = Some(it.next().ok_or("--params needs a TOML file")?),
            "--json" => args.json = true,
            s if s.starts_with('-') => return Err(format!("unknown option {s}")),
            s => args.file = s.to_string(),
        }
    }
    if args.file.is_empty() {
        return Err(
            "usage: camera_bench FILE.vdg [--frames N] [--dt S] [--thesis] [--params CAM.toml] [--json]".into(),
        );
    }
    Ok(args)
}

/// A polyline through the graph: shortest paths between vertices picked by
/// a fixed stride, long enough for `length` units.
fn route(g: &vdgformat::Vdg<'_>, length: f64) -> Vec<[f32; 3]> {
    let n = g.vertex_count() as u64;
    let mut pts: Vec<[f32; 3]> = Vec::new();
    let mut total = 0.0f64;
    let mut v = 0u64;
    let mut tries = 0;
    while total < length && tries < 10_000 {
        tries += 1;
        let w = (v * 7919 + 104_729 + tries) % n;
        if let Some(p) = g.vertex_path(v as u32, w as u32) {
            for &u in &p.vertices {
                let q = g.vertices()[u as usize].pos;
                if let Some(&last) = pts.last() {
                    total += dist(last, q);
                }
                pts.push(q);
            }
            v = w;
        }
    }
    pts
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f64 {
    (0..3)
        .map(|i| f64::from(a[i] - b[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The target at time `t` on the route: walks at 265 u/s, stands still for
/// a second every 10 s and turns round for half a second every 7 s.
fn target_at(route: &[[f32; 3]], t: f64) -> Target {
    let stop = t % 10.0 > 9.0;
    let walked = 265.0 * (t - (t / 10.0).floor() * 1.0 - if stop { t % 10.0 - 9.0 } else { 0.0 });
    let (mut left, mut i) = (walked.max(0.0), 0);
    while i + 1 < route.len() {
        let d = dist(route[i], route[i + 1]);
        if left <= d {
            break;
        }
        left -= d;
        i += 1;
    }
    let a = route[i];
    let b = route[(i + 1).min(route.len() - 1)];
    let d = dist(a, b).max(1e-9);
    let f = (left / d).min(1.0) as f32;
    let pos = [0, 1, 2].map(|k| a[k] + (b[k] - a[k]) * f);
    let mut heading = [0, 1, 2].map(|k| (b[k] - a[k]) / d as f32);
    if t % 7.0 > 6.5 {
        heading = heading.map(|c| -c);
    }
    let speed = if stop { 0.0 } else { 265.0 };
    Target::new(pos, heading, heading.map(|c| c * speed))
}

/// One camera update, never inlined, followed by a call of the empty
/// [`update_done`]: a profiler can cut the run at both, e.g.
/// `valgrind --tool=callgrind --dump-before='*timed_update*'
/// --dump-before='*update_done*'` writes one profile per update (those
/// dumped before `update_done`) and one per stretch of the bench's own work.
#[inline(never)]
fn timed_update(
    camera: &mut Camera,
    g: &vdgformat::Vdg<'_>,
    t: &Target,
    dt: f32,
) -> vdgformat::camera::Pose {
    camera.update(g, t, dt)
}

/// Marks the end of an update for a profiler (see [`timed_update`]).
#[inline(never)]
fn update_done() {
    std::hint::black_box(());
}

/// Camera parameters from a TOML file.
#[cfg(feature = "camera-toml")]
fn params_from_file(path: &str) -> Result<CameraParams, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    CameraParams::from_toml_str(&text).map_err(|e| format!("{path}: {e}"))
}

#[cfg(not(feature = "camera-toml"))]
fn params_from_file(path: &str) -> Result<CameraParams, String> {
    Err(format!(
        "{path}: --params needs vdgformat's feature camera-toml"
    ))
}

fn main() {
    if let Err(e) = run() {
        eprintln!("camera_bench: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let file = VdgFile::open(&args.file).map_err(|e| format!("{}: {e}", args.file))?;
    let g = file.graph();
    if g.face_count() == 0 {
        return Err(format!("{}: the graph has no faces", args.file));
    }
    let params = match (&args.params, args.thesis) {
        (Some(_), true) => return Err("--params and --thesis exclude each other".into()),
        (Some(path), false) => params_from_file(path)?,
        (None, true) => CameraParams::thesis(),
        (None, false) => CameraParams::default(),
    };
    let seconds = args.frames as f64 * f64::from(args.dt);
    let route = route(&g, 265.0 * seconds + 1000.0);
    if route.len() < 2 {
        return Err("could not build a route through the graph".into());
    }
    let mut camera = Camera::new(params).map_err(|e| e.to_string())?;
    let warmup = ((1.0 / args.dt).ceil() as usize).min(args.frames / 2);
    let mut times = Vec::with_capacity(args.frames);
    let (mut visible, mut cuts, mut outside) = (0usize, 0usize, 0usize);
    let (mut vis_tests, mut reach, mut settled) = (0u64, 0u64, 0u64);
    camera.reset(&g, &target_at(&route, 0.0));
    let mut allocs_before = 0;
    // FNV-1a over every pose's bits: equal hashes say two builds moved the
    // camera identically (a check that an optimisation changed no answer).
    let mut pose_hash = 0xcbf2_9ce4_8422_2325u64;
    for i in 0..args.frames {
        if i == warmup {
            allocs_before = ALLOCATIONS.load(Ordering::Relaxed);
        }
        let t = target_at(&route, (i + 1) as f64 * f64::from(args.dt));
        let start = Instant::now();
        let pose = timed_update(&mut camera, &g, &t, args.dt);
        update_done();
        for x in pose
            .eye
            .iter()
            .chain(&pose.look_at)
            .chain(&[pose.yaw, pose.pitch])
        {
            for b in x.to_bits().to_le_bytes() {
                pose_hash = (pose_hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
        }
        let us = start.elapsed().as_secs_f64() * 1e6;
        // CAMERA_BENCH_TRACE=US prints every update slower than US µs.
        if std::env::var("CAMERA_BENCH_TRACE")
            .ok()
            .and_then(|v| v.parse::<f64>().ok())
            .is_some_and(|limit| us > limit)
        {
            let d = camera.debug();
            let far = d
                .candidates()
                .iter()
                .map(|c| dist(c.pos, t.position))
                .fold(0.0, f64::max);
            eprintln!(
                "frame {i}: {us:.0} µs, {} tests, {} reachable, farthest candidate {far:.0}, eye {:?} target {:?} visible {}",
                d.visibility_tests, d.reachable, pose.eye, t.position, pose.target_visible
            );
        }
        if i >= warmup {
            times.push(us);
            visible += usize::from(pose.target_visible);
            cuts += usize::from(pose.cut);
            outside += usize::from(pose.status == vdgformat::camera::Status::TargetOutside);
            vis_tests += u64::from(camera.debug().visibility_tests);
            reach += u64::from(camera.debug().reachable);
            settled += u64::from(camera.debug().field_settled);
        }
    }
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - allocs_before;
    let measured = times.len();
    times.sort_by(f64::total_cmp);
    let q = |f: f64| times[((measured as f64 - 1.0) * f).round() as usize];
    let mean = times.iter().sum::<f64>() / measured as f64;
    let variant = match (&args.params, args.thesis) {
        (Some(_), _) => "params",
        (None, true) => "thesis",
        (None, false) => "improved",
    };
    if args.json {
        println!(
            "{{\"file\":{:?},\"variant\":\"{variant}\",\"vertices\":{},\"faces\":{},\"frames\":{measured},\"warmup_frames\":{warmup},\"dt\":{},\"median_us\":{:.3},\"p99_us\":{:.3},\"max_us\":{:.3},\"mean_us\":{:.3},\"allocations_after_warmup\":{allocations},\"visible_fraction\":{:.4},\"cuts\":{cuts},\"target_outside_frames\":{outside},\"visibility_tests_per_update\":{:.2},\"reachable_per_update\":{:.2},\"pose_hash\":\"{pose_hash:016x}\"}}",
            args.file,
            g.vertex_count(),
            g.face_count(),
            args.dt,
            q(0.5),
            q(0.99),
            times[measured - 1],
            mean,
            visible as f64 / measured as f64,
            vis_tests as f64 / measured as f64,
            reach as f64 / measured as f64
        );
    } else {
        println!(
            "{variant} camera on {} ({} vertices, {} faces): {measured} frames after {warmup} warm-up",
            args.file,
            g.vertex_count(),
            g.face_count()
        );
        println!(
            "  per update: median {:.2} µs, p99 {:.2} µs, max {:.2} µs, mean {:.2} µs",
            q(0.5),
            q(0.99),
            times[measured - 1],
            mean
        );
        println!(
            "  allocations after warm-up: {allocations}; target visible {:.1} % of frames; {cuts} cuts; target outside the volume {outside} frames",
            100.0 * visible as f64 / measured as f64
        );
        println!(
            "  per update: {:.1} visibility tests, {:.1} reachable vertices, {:.1} vertices settled by the distance field",
            vis_tests as f64 / measured as f64,
            reach as f64 / measured as f64,
            settled as f64 / measured as f64
        );
        println!("  pose hash {pose_hash:016x}");
    }
    Ok(())
}
