//! Render-time benchmark: median of repeated headless renders (load excluded)
//! of a map and its graph, per mode, plus one viewer-sized frame from inside.
//!
//! `VDGVIEW_BENCH_MAP=…bsp VDGVIEW_BENCH_VDG=…vdg cargo bench -p vdgview --bench render`
//! (default: testdata/maps/complex.bsp without a graph, walls only).

use glam::Vec3;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use vdgview::camera::Camera;
use vdgview::raster::Framebuffer;
use vdgview::render::{self, Mode, RenderRequest, Style, View};
use vdgview::scene::{self, Scene};

const RUNS: usize = 7;

fn median(mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..RUNS)
        .map(|_| {
            let s = Instant::now();
            f();
            s.elapsed()
        })
        .collect();
    t.sort_unstable();
    t[RUNS / 2]
}

fn main() -> anyhow::Result<()> {
    let map = std::env::var_os("VDGVIEW_BENCH_MAP").map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../testdata/maps/complex.bsp"),
        PathBuf::from,
    );
    let bsp = scene::open_map(&map)?;
    let file = std::env::var_os("VDGVIEW_BENCH_VDG")
        .map(|p| scene::open_graph(std::path::Path::new(&p)))
        .transpose()?;
    let graph = file.as_ref().map(|f| f.graph());
    let scene = Scene::new(&bsp, graph.as_ref(), vec![])?;
    println!(
        "{}: {} wall triangles, {} graph faces; median of {RUNS}",
        map.display(),
        scene.walls.len(),
        scene.graph.as_ref().map_or(0, |g| g.faces.len())
    );
    let modes: &[Mode] = if scene.graph.is_some() {
        &[Mode::Hidden, Mode::Wireframe, Mode::Clearance]
    } else {
        &[Mode::Hidden]
    };
    let mut base = None;
    for &mode in modes {
        for (name, view, ss) in [
            ("auto 1024x768 ss2", View::Auto, 2),
            ("top 1024x768 ss1", View::Top, 1),
        ] {
            let req = RenderRequest {
                width: 1024,
                height: 768,
                supersample: ss,
                view,
                style: Style {
                    mode,
                    samples: false,
                    ..Style::default()
                },
            };
            let t = median(|| {
                render::render(&scene, &req).unwrap();
            });
            let b = *base.get_or_insert(t);
            println!(
                "render {mode:?} {name}: {:.1} ms ({:.2}x mode 0 auto)",
                t.as_secs_f64() * 1e3,
                t.as_secs_f64() / b.as_secs_f64()
            );
        }
    }
    // A viewer frame (960x600, no supersampling) from the middle of the level.
    let eye = scene.bounds.center();
    let cam = Camera::look_at(eye, eye + Vec3::new(1.0, 0.3, -0.2), 75.0);
    let mut fb = Framebuffer::new(960, 600, &cam, [0, 0, 0]);
    for &mode in modes {
        let style = Style {
            mode,
            ..Style::default()
        };
        let t = median(|| {
            fb.reset(&cam, style.background);
            render::draw_scene(&mut fb, &scene, &style).unwrap();
        });
        println!(
            "viewer frame {mode:?} 960x600 from the centre: {:.1} ms",
            t.as_secs_f64() * 1e3
        );
    }
    Ok(())
}
