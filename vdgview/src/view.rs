//! `vdgview view`: the interactive window. It shows the software rasterizer's
//! framebuffer through `minifb` (X11, loaded with dlopen at run time), so it
//! needs no GPU, no OpenGL/Vulkan driver and no system libraries at build time;
//! under Xvfb it runs like on a desktop.

use crate::camera::Camera;
use crate::raster::Framebuffer;
use crate::render;
use crate::viewer::Viewer;
use anyhow::{Context, Result};
use glam::Vec3;
use minifb::{Key, KeyRepeat, MouseButton, MouseMode, Window, WindowOptions};
use std::cell::RefCell;
use std::rc::Rc;
use std::time::Instant;

/// One frame of `view --follow`: camera eye, look-at point, target origin.
pub type FollowPose = ([f32; 3], [f32; 3], [f32; 3]);

/// Window options beyond the map and graph.
#[derive(Debug, Clone, Default)]
pub struct ViewOptions {
    pub width: usize,
    pub height: usize,
    /// Console commands run before the first frame (`;`-separated).
    pub exec: Vec<String>,
    /// Close after this many frames (for scripted screenshots and timing).
    pub frames: Option<u64>,
    /// Close after this many seconds.
    pub seconds: Option<f64>,
    /// `--follow`: camera poses to play back, one per `follow_dt` seconds (eye,
    /// look-at point, target origin); the target is shown as the marked point.
    pub follow: Vec<FollowPose>,
    pub follow_dt: f64,
}

/// Units per second; Shift multiplies by 4.
const SPEED: f32 = 320.0;
/// Degrees per pixel of mouse drag.
const MOUSE_DEG: f32 = 0.25;
/// Degrees per second for the arrow keys.
const KEY_TURN: f32 = 90.0;

/// Typed characters for the console, filled by minifb's input callback.
struct Typed(Rc<RefCell<Vec<char>>>);

impl minifb::InputCallback for Typed {
    fn add_char(&mut self, c: u32) {
        if let Some(ch) = char::from_u32(c).filter(|c| !c.is_control()) {
            self.0.borrow_mut().push(ch);
        }
    }
}

/// What to do without a display, for the error of a window that cannot open.
const NO_WINDOW_HINT: &str = "Without a display (no DISPLAY, ssh, CI), run it under a virtual one: \
xvfb-run -a vdgview view ...; or write a picture with no window: vdgview view ... --screenshot OUT.png";

/// Puts the view at one pose of a followed route (the recorded camera, looking at its
/// target, the target marked), keeping the viewer's projection.
fn show_follow_pose(viewer: &mut Viewer, (eye, look, target): FollowPose) {
    let projection = viewer.camera.projection;
    viewer.camera = Camera {
        projection,
        ..Camera::look_at(eye.into(), look.into(), 74.0)
    };
    viewer.mark = Some(target.into());
}

/// `view --screenshot`: the first frame (after `exec`; with `follow`, the pose of
/// frame `frames`) drawn by the same code as the window's, written as a PNG, with no
/// window and no display.
pub fn screenshot(mut viewer: Viewer, opts: &ViewOptions, path: &std::path::Path) -> Result<()> {
    let mut fb = Framebuffer::new(opts.width, opts.height, &viewer.camera, [0, 0, 0]);
    for cmd in &opts.exec {
        viewer.execute(cmd);
    }
    if !opts.follow.is_empty() {
        let k = opts.frames.unwrap_or(0) as usize % opts.follow.len();
        show_follow_pose(&mut viewer, opts.follow[k]);
    }
    viewer.draw(&mut fb, None);
    let png = render::encode_png(&fb.color, fb.width, fb.height)?;
    render::write_atomic(path, &png).with_context(|| format!("cannot write {}", path.display()))?;
    toolbox::outln!("wrote {} ({}x{})", path.display(), fb.width, fb.height);
    Ok(())
}

/// Opens the window and runs until it is closed, Esc, `quit`, or `frames`.
pub fn run(mut viewer: Viewer, opts: &ViewOptions) -> Result<()> {
    let mut window = Window::new(
        "vdgview",
        opts.width,
        opts.height,
        WindowOptions {
            resize: false,
            ..WindowOptions::default()
        },
    )
    .map_err(|e| anyhow::anyhow!("cannot open a window: {e}. {}", NO_WINDOW_HINT))?;
    window.set_target_fps(60);
    let typed = Rc::new(RefCell::new(Vec::new()));
    window.set_input_callback(Box::new(Typed(typed.clone())));
    let mut fb = Framebuffer::new(opts.width, opts.height, &viewer.camera, [0, 0, 0]);
    for cmd in &opts.exec {
        viewer.execute(cmd);
    }
    let mut console: Option<String> = None;
    let mut last_mouse: Option<(f32, f32)> = None;
    let mut last = Instant::now();
    let mut frames = 0u64;
    let cpu_start = process_cpu_seconds();
    let wall_start = Instant::now();
    while window.is_open() && !viewer.quit {
        let now = Instant::now();
        let dt = (now - last).as_secs_f32().min(0.1);
        last = now;
        let chars: Vec<char> = typed.borrow_mut().drain(..).collect();
        match console.as_mut() {
            Some(line) => {
                if handle_console(&window, line, &chars, &mut viewer) {
                    console = None;
                }
            }
            None => {
                if handle_keys(&window, &mut viewer, dt) {
                    console = Some(String::new());
                }
                if window.is_key_pressed(Key::Escape, KeyRepeat::No) {
                    break;
                }
            }
        }
        // Mouse look while the left button is held.
        let mouse = window.get_mouse_pos(MouseMode::Pass);
        if window.get_mouse_down(MouseButton::Left) {
            if let (Some((x, y)), Some((lx, ly))) = (mouse, last_mouse) {
                viewer.turn(-(x - lx) * MOUSE_DEG, -(y - ly) * MOUSE_DEG);
            }
            last_mouse = mouse;
        } else {
            last_mouse = None;
        }
        if window.get_mouse_down(MouseButton::Right) && viewer.crosshair != viewer.mark {
            viewer.mark_crosshair();
        }

        if !opts.follow.is_empty() && opts.follow_dt > 0.0 {
            // Play the route in real time, looping.
            let k =
                (wall_start.elapsed().as_secs_f64() / opts.follow_dt) as usize % opts.follow.len();
            show_follow_pose(&mut viewer, opts.follow[k]);
        }
        let t = Instant::now();
        viewer.draw(&mut fb, console.as_deref());
        viewer.record_frame(t.elapsed());
        if let Some(path) = viewer.screenshot.take() {
            let shot = render::encode_png(&fb.color, fb.width, fb.height)
                .and_then(|png| render::write_atomic(std::path::Path::new(&path), &png));
            match shot {
                Ok(()) => viewer.say(format!("screenshot {path}")),
                Err(e) => viewer.say(format!("screenshot: {e:#}")),
            }
        }
        window
            .update_with_buffer(&fb.color, fb.width, fb.height)
            .context("cannot show the frame")?;
        frames += 1;
        if opts.frames.is_some_and(|n| frames >= n)
            || opts
                .seconds
                .is_some_and(|s| wall_start.elapsed().as_secs_f64() >= s)
        {
            break;
        }
    }
    if let Some(t) = viewer.median_frame() {
        let wall = wall_start.elapsed().as_secs_f64();
        let cpu = match (cpu_start, process_cpu_seconds()) {
            (Some(a), Some(b)) if frames > 0 => {
                format!(
                    ", process CPU {:.1} ms/frame",
                    (b - a) * 1e3 / frames as f64
                )
            }
            _ => String::new(),
        };
        toolbox::outln!(
            "vdgview: {frames} frames in {wall:.1} s ({}x{}): median draw {:.1} ms{cpu}",
            opts.width,
            opts.height,
            t.as_secs_f64() * 1e3,
        );
    }
    Ok(())
}

/// User + system CPU time of this process from `/proc/self/stat` (Linux), so
/// the frame cost can be told apart from waiting on a busy machine.
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are the
    // 14th and 15th fields overall, in clock ticks (100 per second on Linux).
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Edits the console line; true when it closes (Enter runs it, Esc drops it).
fn handle_console(window: &Window, line: &mut String, chars: &[char], viewer: &mut Viewer) -> bool {
    for &c in chars {
        line.push(c);
    }
    if window.is_key_pressed(Key::Backspace, KeyRepeat::Yes) {
        line.pop();
    }
    if window.is_key_pressed(Key::Enter, KeyRepeat::No) {
        let cmd = std::mem::take(line);
        viewer.say(format!("> {cmd}"));
        viewer.execute(&cmd);
        return true;
    }
    window.is_key_pressed(Key::Escape, KeyRepeat::No)
}

/// Flight keys and toggles; true when the console should open.
fn handle_keys(window: &Window, viewer: &mut Viewer, dt: f32) -> bool {
    let down = |k| window.is_key_down(k);
    let speed = SPEED
        * dt
        * if down(Key::LeftShift) || down(Key::RightShift) {
            4.0
        } else {
            1.0
        };
    let b = viewer.camera.basis();
    let mut d = Vec3::ZERO;
    for (key, dir) in [
        (Key::W, b.forward),
        (Key::S, -b.forward),
        (Key::D, b.right),
        (Key::A, -b.right),
        (Key::E, Vec3::Z),
        (Key::Q, -Vec3::Z),
    ] {
        if down(key) {
            d += dir;
        }
    }
    if d != Vec3::ZERO {
        viewer.move_by(d.normalize() * speed);
    }
    let turn = KEY_TURN * dt;
    for (key, dy, dp) in [
        (Key::Left, turn, 0.0),
        (Key::Right, -turn, 0.0),
        (Key::Up, 0.0, turn),
        (Key::Down, 0.0, -turn),
    ] {
        if down(key) {
            viewer.turn(dy, dp);
        }
    }
    let pressed = |k| window.is_key_pressed(k, KeyRepeat::No);
    for (key, cmd) in [
        (Key::Key0, "mode 0"),
        (Key::Key1, "mode 1"),
        (Key::Key2, "mode 2"),
        (Key::Key3, "mode 3"),
        (Key::C, "clearance"),
        (Key::M, "mark"),
        (Key::P, "path"),
        (Key::I, "stats"),
        (Key::H, "help"),
    ] {
        if pressed(key) {
            viewer.execute(cmd);
        }
    }
    if pressed(Key::K) {
        let on = !viewer.samples;
        viewer.execute(if on { "samples 1" } else { "samples 0" });
    }
    if pressed(Key::N) {
        let on = !viewer.noclip;
        viewer.execute(if on { "noclip 1" } else { "noclip 0" });
    }
    if pressed(Key::X) {
        viewer.mark = None;
        viewer.path = None;
    }
    if pressed(Key::F12) {
        let name = format!("vdgview-{}.png", std::process::id());
        viewer.screenshot = Some(name);
    }
    pressed(Key::Tab) || pressed(Key::Enter)
}
