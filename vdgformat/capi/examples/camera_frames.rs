//! The Rust side of `scripts/capi-check.sh`'s timing: replays the camera
//! frames of a `tests/c/smoke.c` script through the Rust API exactly as
//! `smoke GRAPH SCRIPT CORRUPT REPEAT` does through the C API (a fresh camera
//! per run, reset on the first frame) and prints the median time per frame.
//!
//! usage: cargo run --release -p vdgformat-capi --example camera_frames -- GRAPH.vdg SCRIPT REPEAT

use std::time::Instant;

use vdgformat::VdgFile;
use vdgformat::camera::{Camera, CameraParams, Target};

fn main() {
    if let Err(e) = run() {
        eprintln!("camera_frames: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [graph, script, repeat] = args.as_slice() else {
        return Err("usage: camera_frames GRAPH.vdg SCRIPT REPEAT".into());
    };
    let repeat: usize = repeat
        .parse()
        .ok()
        .filter(|&r| r > 0)
        .ok_or("REPEAT must be a positive integer")?;
    let file = VdgFile::open(graph).map_err(|e| format!("{graph}: {e}"))?;
    let g = file.graph();
    let text = std::fs::read_to_string(script).map_err(|e| format!("{script}: {e}"))?;
    let mut frames = Vec::new();
    for line in text.lines().filter(|l| l.starts_with("T ")) {
        let v: Vec<f32> = line[2..]
            .split(' ')
            .map(|h| u32::from_str_radix(h, 16).map(f32::from_bits))
            .collect::<Result<_, _>>()
            .map_err(|e| format!("{script}: {e}"))?;
        let [o0, o1, o2, a0, a1, a2, v0, v1, v2, dt] = v[..] else {
            return Err(format!("{script}: a T line needs 10 floats"));
        };
        frames.push((
            Target::from_angles([o0, o1, o2], [a0, a1, a2], [v0, v1, v2]),
            dt,
        ));
    }
    if frames.is_empty() {
        return Err(format!("{script}: no frames"));
    }
    let mut times: Vec<f64> = (0..repeat)
        .map(|_| {
            let mut cam = Camera::new(CameraParams::default()).expect("default parameters");
            let t0 = Instant::now();
            cam.reset(&g, &frames[0].0);
            for (t, dt) in &frames[1..] {
                std::hint::black_box(cam.update(&g, t, *dt));
            }
            t0.elapsed().as_secs_f64() / frames.len() as f64
        })
        .collect();
    times.sort_by(f64::total_cmp);
    eprintln!(
        "Rust camera: median {:.2} us/frame over {repeat} runs of {} frames",
        times[repeat / 2] * 1e6,
        frames.len()
    );
    Ok(())
}
