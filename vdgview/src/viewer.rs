//! The fly-through's state and console, independent of any window: the eye,
//! render mode, noclip, the marked point with its line of sight and path, and
//! the thesis' console commands (`gopos`, `noclip`, `stats`, `reduce`, …).
//! `view.rs` feeds it keys and mouse motion and shows [`Viewer::draw`]'s
//! framebuffer; tests drive it directly.

use crate::camera::{Camera, Projection};
use crate::hud;
use crate::raster::Framebuffer;
use crate::render::{self, Mode, Style};
use crate::scene::Scene;
use glam::Vec3;
use std::fmt::Write;
use std::time::Duration;
use vdgformat::VdgFile;

/// Messages kept on screen.
const MESSAGE_LINES: usize = 6;
/// Frame times kept for the median.
const FRAME_WINDOW: usize = 120;

/// Console help, also printed by `help`.
pub const HELP: &str = "keys: W/A/S/D move, E/Q up/down, Shift fast, mouse drag or arrows look, \
1/2/3 render mode (0 map only), K samples, N noclip, C clearance at crosshair, \
M mark crosshair point (right click too), P path to mark, X clear mark, Tab/Enter console, F12 screenshot, Esc quit; \
console: gopos X Y Z | setang YAW PITCH | noclip 0/1 | mode 0-3 | samples 0/1 | stats | \
clearance | mark [X Y Z] | path | reduce N | screenshot FILE | help | quit";

/// The viewer's state.
pub struct Viewer {
    pub scene: Scene,
    pub graph: Option<VdgFile>,
    pub camera: Camera,
    pub mode: Mode,
    pub samples: bool,
    /// With noclip off the eye stays inside Volume(VDG) (thesis 6.3).
    pub noclip: bool,
    /// The face the eye was last tracked in (hint for `track`).
    hint: u32,
    pub mark: Option<Vec3>,
    /// The last path to the mark: its points from the eye to the mark.
    pub path: Option<Vec<Vec3>>,
    /// What the crosshair was on in the last frame.
    pub crosshair: Option<Vec3>,
    pub messages: Vec<String>,
    frame_times: Vec<Duration>,
    pub quit: bool,
    /// Files the viewer was asked to write (`screenshot FILE`), done by the window.
    pub screenshot: Option<String>,
}

impl Viewer {
    /// Starts at the map's first `info_player_start`/spawn point when there is
    /// one, else at the graph vertex of largest clearance, else the map centre.
    pub fn new(scene: Scene, graph: Option<VdgFile>, spawn: Option<Vec3>) -> Viewer {
        let start = spawn
            .or_else(|| {
                let g = scene.graph.as_ref()?;
                let best = (0..g.clearances.len())
                    .max_by(|&a, &b| g.clearances[a].total_cmp(&g.clearances[b]).then(b.cmp(&a)))?;
                Some(g.positions[best])
            })
            .unwrap_or_else(|| scene.bounds.center());
        let camera = Camera {
            pos: start,
            yaw: 0.0,
            pitch: 0.0,
            projection: Projection::Perspective { fov_deg: 75.0 },
        };
        let mode = if scene.graph.is_some() {
            Mode::Clearance
        } else {
            Mode::Hidden
        };
        let noclip = graph.is_none();
        let mut v = Viewer {
            scene,
            graph,
            camera,
            mode,
            samples: true,
            noclip,
            hint: 0,
            mark: None,
            path: None,
            crosshair: None,
            messages: Vec::new(),
            frame_times: Vec::new(),
            quit: false,
            screenshot: None,
        };
        // On screen only: printing it before the window exists would be noise
        // when the window cannot open.
        v.messages
            .push("vdgview: press Tab for the console, type help for commands".into());
        v
    }

    /// Adds a line to the on-screen messages and prints it.
    pub fn say(&mut self, line: impl Into<String>) {
        let line = line.into();
        toolbox::outln!("{line}");
        self.messages.push(line);
        if self.messages.len() > MESSAGE_LINES {
            self.messages.remove(0);
        }
    }

    /// Whether `p` is a position the eye may take.
    fn allowed(&mut self, p: Vec3) -> bool {
        if self.noclip {
            return true;
        }
        let Some(file) = &self.graph else {
            return true;
        };
        let g = file.graph();
        match g.track(self.hint, p.to_array()) {
            Some(hit) if hit.clearance > 0.0 => {
                self.hint = hit.face;
                true
            }
            _ => false,
        }
    }

    fn eye_inside(&self) -> bool {
        self.graph
            .as_ref()
            .is_some_and(|f| f.graph().contains(self.camera.pos.to_array()))
    }

    /// Moves the eye by `delta`; with noclip off, a move that would leave
    /// Volume(VDG) slides along it axis by axis, or is refused. An eye that is
    /// outside the volume (e.g. at the start) moves freely until it enters.
    pub fn move_by(&mut self, delta: Vec3) {
        let target = self.camera.pos + delta;
        if self.noclip || !self.eye_inside() || self.allowed(target) {
            self.camera.pos = target;
            return;
        }
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let step = self.camera.pos + axis * delta.dot(axis);
            if self.allowed(step) {
                self.camera.pos = step;
            }
        }
    }

    /// Turns the view by degrees.
    pub fn turn(&mut self, dyaw: f32, dpitch: f32) {
        self.camera.yaw = (self.camera.yaw + dyaw).rem_euclid(360.0);
        self.camera.pitch = (self.camera.pitch + dpitch).clamp(-89.0, 89.0);
    }

    /// Records a frame's duration for the statistics.
    pub fn record_frame(&mut self, d: Duration) {
        if self.frame_times.len() == FRAME_WINDOW {
            self.frame_times.remove(0);
        }
        self.frame_times.push(d);
    }

    /// Median of the recent frame times.
    pub fn median_frame(&self) -> Option<Duration> {
        let mut t = self.frame_times.clone();
        t.sort_unstable();
        t.get(t.len() / 2).copied()
    }

    /// Runs one console command line.
    pub fn execute(&mut self, line: &str) {
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((&cmd, args)) = words.split_first() else {
            return;
        };
        let nums: Option<Vec<f32>> = args
            .iter()
            .map(|a| a.parse::<f32>().ok().filter(|x| x.is_finite()))
            .collect();
        match (cmd, nums.as_deref()) {
            ("gopos", Some(&[x, y, z])) => self.gopos(Vec3::new(x, y, z)),
            ("setang", Some(&[yaw, pitch])) => {
                self.camera.yaw = yaw.rem_euclid(360.0);
                self.camera.pitch = pitch.clamp(-89.0, 89.0);
            }
            ("noclip", Some(&[n])) if n == 0.0 || n == 1.0 => self.set_noclip(n == 1.0),
            ("mode", Some(&[n])) => {
                match Mode::from_number(n as u32).filter(|_| n.fract() == 0.0) {
                    Some(m) => self.set_mode(m),
                    None => self.say("mode: expected 0, 1, 2 or 3"),
                }
            }
            ("samples", Some(&[n])) if n == 0.0 || n == 1.0 => {
                self.samples = n == 1.0;
                self.say(format!(
                    "samples {}",
                    if self.samples { "on" } else { "off" }
                ));
            }
            ("stats", _) => self.stats(),
            ("clearance", _) => self.report_clearance(),
            ("mark", Some(&[])) => self.mark_crosshair(),
            ("mark", Some(&[x, y, z])) => self.set_mark(Vec3::new(x, y, z)),
            ("path", _) => self.compute_path(),
            ("reduce", Some(&[n])) if n >= 1.0 && n.fract() == 0.0 => self.reduce_by(n as usize),
            ("reduce", _) => {
                self.say("reduce: expected a number of vertices to remove, e.g. reduce 1000")
            }
            ("screenshot", _) if args.len() == 1 => self.screenshot = Some(args[0].to_string()),
            ("help", _) => {
                for chunk in HELP.split("; ") {
                    self.say(chunk.to_string());
                }
            }
            ("quit" | "exit", _) => self.quit = true,
            _ => self.say(format!(
                "unknown or malformed command: {line:?} (type help)"
            )),
        }
    }

    fn gopos(&mut self, p: Vec3) {
        if !self.noclip
            && self.graph.is_some()
            && !self.graph.as_ref().unwrap().graph().contains(p.to_array())
        {
            self.say(format!(
                "gopos: ({:.0} {:.0} {:.0}) is outside Volume(VDG); use noclip 1 first",
                p.x, p.y, p.z
            ));
            return;
        }
        self.camera.pos = p;
        self.say(format!("at ({:.0} {:.0} {:.0})", p.x, p.y, p.z));
    }

    fn set_noclip(&mut self, on: bool) {
        self.noclip = on;
        if on {
            self.say("noclip 1: free flight");
        } else if self.graph.is_none() {
            self.say("noclip 0: no graph loaded, flight stays free");
        } else if self.eye_inside() {
            self.say("noclip 0: the eye stays inside Volume(VDG)");
        } else {
            self.say("noclip 0: the eye is outside Volume(VDG) and moves freely until it enters");
        }
    }

    /// Switches the render mode, refusing what the graph cannot show.
    pub fn set_mode(&mut self, m: Mode) {
        if m != Mode::Hidden && self.scene.graph.is_none() {
            self.say("no graph loaded: only mode 0 (map) is available");
            return;
        }
        if m == Mode::ReductionCost {
            self.say(render::NO_REDUCTION_COST);
            return;
        }
        self.mode = m;
        self.say(format!("mode {}", mode_name(m)));
    }

    /// The thesis' `stats`: graph size, position, clearance, frame time.
    /// Removes `n` more vertices by the compiler's reduction (thesis ch. 4), as the
    /// thesis' VDGView does with an unreduced graph, and shows the result.
    pub fn reduce_by(&mut self, n: usize) {
        let Some(file) = &self.graph else {
            self.say("reduce: no graph loaded");
            return;
        };
        let g = file.graph();
        let graph = bsp2vdg::graph::Graph::from_vdg(&g);
        let before = graph.vertices.len();
        if before == 0 {
            self.say("reduce: the graph is empty");
            return;
        }
        let limit = before.saturating_sub(n) as f64 / before as f64;
        let options = bsp2vdg::reduce::ReduceOptions::new(limit);
        let (reduced, stats) =
            bsp2vdg::reduce::reduce(&graph, &options, &bsp2vdg::progress::NoProgress);
        let file = match reduced
            .to_builder(None)
            .to_bytes()
            .map_err(|e| e.to_string())
            .and_then(|bytes| VdgFile::from_bytes(&bytes).map_err(|e| e.to_string()))
        {
            Ok(f) => f,
            Err(e) => {
                self.say(format!("reduce: {e}"));
                return;
            }
        };
        self.scene.graph = Some(crate::scene::GraphMesh::from_vdg(&file.graph()));
        self.graph = Some(file);
        self.hint = 0;
        self.say(format!(
            "reduce: nodes {} -> {}, faces {} -> {} ({:?})",
            before,
            reduced.vertices.len(),
            graph.faces.len(),
            reduced.faces.len(),
            stats.stop
        ));
    }

    pub fn stats(&mut self) {
        let mut s = String::new();
        if let Some(g) = &self.scene.graph {
            let _ = write!(
                s,
                "graph {} vertices, {} faces; ",
                g.positions.len(),
                g.faces.len()
            );
        }
        let p = self.camera.pos;
        let _ = write!(s, "eye ({:.0} {:.0} {:.0})", p.x, p.y, p.z);
        if let Some(f) = &self.graph {
            let _ = write!(s, " clearance {:.1}", f.graph().clearance(p.to_array()));
        }
        if let Some(t) = self.median_frame() {
            let _ = write!(
                s,
                "; frame median {:.1} ms over {}",
                t.as_secs_f64() * 1e3,
                self.frame_times.len()
            );
        }
        self.say(s);
    }

    /// Reports the clearance of the point under the crosshair.
    pub fn report_clearance(&mut self) {
        let Some(p) = self.crosshair else {
            self.say("crosshair: nothing under it");
            return;
        };
        let line = match &self.graph {
            Some(f) => {
                let g = f.graph();
                let c = g.clearance(p.to_array());
                format!(
                    "crosshair ({:.0} {:.0} {:.0}): clearance {:.1} ({})",
                    p.x,
                    p.y,
                    p.z,
                    c,
                    if c > 0.0 {
                        "inside Volume(VDG)"
                    } else {
                        "outside Volume(VDG)"
                    }
                )
            }
            None => format!(
                "crosshair ({:.0} {:.0} {:.0}): no graph loaded",
                p.x, p.y, p.z
            ),
        };
        self.say(line);
    }

    /// Marks the point under the crosshair.
    pub fn mark_crosshair(&mut self) {
        match self.crosshair {
            Some(p) => self.set_mark(p),
            None => self.say("mark: nothing under the crosshair"),
        }
    }

    /// Marks `p` and computes the path to it.
    pub fn set_mark(&mut self, p: Vec3) {
        self.mark = Some(p);
        self.say(format!("marked ({:.0} {:.0} {:.0})", p.x, p.y, p.z));
        self.compute_path();
    }

    /// Recomputes the path from the eye to the mark (A* over the graph).
    pub fn compute_path(&mut self) {
        let (Some(m), Some(f)) = (self.mark, &self.graph) else {
            self.say("path: needs a mark and a graph");
            return;
        };
        let g = f.graph();
        let eye = self.camera.pos;
        let visible = g.visible(eye.to_array(), m.to_array());
        match g.path(eye.to_array(), m.to_array()) {
            Some(path) => {
                let mut pts = vec![eye];
                pts.extend(
                    path.vertices
                        .iter()
                        .map(|&v| Vec3::from(g.vertices()[v as usize].pos)),
                );
                pts.push(m);
                let line = format!(
                    "path: Voronoi distance {:.0}, {} vertices; straight {:.0}; line of sight {}",
                    path.length,
                    path.vertices.len(),
                    (m - eye).length(),
                    if visible { "free" } else { "blocked" }
                );
                self.path = Some(pts);
                self.say(line);
            }
            None => {
                self.path = None;
                self.say("path: none (eye and mark are in unconnected parts of the graph)");
            }
        }
    }

    /// Draws the scene, the mark with its line of sight and path, and the HUD.
    pub fn draw(&mut self, fb: &mut Framebuffer, console: Option<&str>) {
        let style = Style {
            mode: self.mode,
            samples: self.samples,
            ..Style::default()
        };
        fb.reset(&self.camera, style.background);
        if let Err(e) = render::draw_scene(fb, &self.scene, &style) {
            self.say(e.to_string());
            self.mode = Mode::Hidden;
        }
        let (cx, cy) = (fb.width / 2, fb.height / 2);
        self.crosshair = fb.unproject(cx, cy);
        self.draw_mark(fb);
        for d in -6i64..=6 {
            if d.abs() > 1 {
                fb.put(cx as i64 + d, cy as i64, [255, 255, 255]);
                fb.put(cx as i64, cy as i64 + d, [255, 255, 255]);
            }
        }
        self.draw_hud(fb, console);
    }

    fn draw_mark(&self, fb: &mut Framebuffer) {
        let Some(m) = self.mark else { return };
        if let Some(f) = &self.graph {
            let eye = self.camera.pos;
            // The sight line starts a little in front of the eye so it shows.
            let from = eye + self.camera.forward() * 4.0 + Vec3::new(0.0, 0.0, -8.0);
            let free = f.graph().visible(eye.to_array(), m.to_array());
            let c = if free { [40, 230, 60] } else { [230, 40, 40] };
            fb.line(from, m, c, 1, 1e9);
        }
        if let Some(path) = &self.path {
            for w in path.windows(2) {
                fb.line(w[0], w[1], [255, 255, 0], 2, 1e9);
            }
        }
        fb.dot(m, [255, 0, 255], 7, 1e9);
    }

    fn draw_hud(&self, fb: &mut Framebuffer, console: Option<&str>) {
        let p = self.camera.pos;
        let mut status = format!(
            "({:.0} {:.0} {:.0}) yaw {:.0} pitch {:.0} | mode {} | noclip {} | samples {}",
            p.x,
            p.y,
            p.z,
            self.camera.yaw,
            self.camera.pitch,
            mode_name(self.mode),
            u8::from(self.noclip),
            u8::from(self.samples)
        );
        if let Some(t) = self.median_frame() {
            let _ = write!(status, " | {:.1} ms", t.as_secs_f64() * 1e3);
        }
        hud::text(fb, 6, 6, &status, [255, 255, 255]);
        for (i, m) in self.messages.iter().enumerate() {
            hud::text(fb, 6, 20 + 10 * i as i64, m, [255, 230, 140]);
        }
        if let Some(line) = console {
            let y = fb.height as i64 - 16;
            hud::rect(fb, 0, y - 4, fb.width, 16, [0, 0, 0]);
            hud::text(fb, 6, y, &format!("> {line}_"), [140, 255, 140]);
        }
    }
}

/// A mode's number and name for the HUD.
pub fn mode_name(m: Mode) -> &'static str {
    match m {
        Mode::Hidden => "0 map",
        Mode::Wireframe => "1 wireframe",
        Mode::ReductionCost => "2 reduction cost",
        Mode::Clearance => "3 clearance",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Bounds;
    use crate::scene::{GraphMesh, WallTriangle};
    use vdgformat::VdgBuilder;

    /// A 400×400 floor at z = 0 and a graph sheet at z = 50 with clearance 40.
    fn viewer() -> Viewer {
        let mut b = VdgBuilder::new();
        let v: Vec<u32> = [[0.0, 0.0], [400.0, 0.0], [0.0, 400.0], [400.0, 400.0]]
            .iter()
            .map(|&[x, y]| b.add_vertex([x, y, 50.0], 40.0))
            .collect();
        b.add_face([v[0], v[1], v[2]]);
        b.add_face([v[1], v[3], v[2]]);
        let file = VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let floor = [
            WallTriangle {
                pts: [
                    Vec3::ZERO,
                    Vec3::new(400.0, 0.0, 0.0),
                    Vec3::new(0.0, 400.0, 0.0),
                ],
                normal: Vec3::Z,
                sky: false,
            },
            WallTriangle {
                pts: [
                    Vec3::new(400.0, 0.0, 0.0),
                    Vec3::new(400.0, 400.0, 0.0),
                    Vec3::new(0.0, 400.0, 0.0),
                ],
                normal: Vec3::Z,
                sky: false,
            },
        ];
        let scene = Scene {
            walls: floor.to_vec(),
            graph: Some(GraphMesh::from_vdg(&file.graph())),
            samples: vec![],
            bounds: Bounds::of([Vec3::ZERO, Vec3::new(400.0, 400.0, 100.0)]).unwrap(),
        };
        Viewer::new(scene, Some(file), Some(Vec3::new(200.0, 200.0, 50.0)))
    }

    #[test]
    fn noclip_0_keeps_the_eye_in_the_volume() {
        let mut v = viewer();
        v.execute("noclip 0");
        v.move_by(Vec3::new(0.0, 0.0, 100.0)); // would leave the 40-unit slab
        assert_eq!(v.camera.pos.z, 50.0);
        v.move_by(Vec3::new(30.0, 0.0, 100.0)); // slides along x
        assert_eq!(v.camera.pos, Vec3::new(230.0, 200.0, 50.0));
        v.execute("gopos 200 200 300");
        assert_eq!(v.camera.pos, Vec3::new(230.0, 200.0, 50.0));
        v.execute("noclip 1");
        v.execute("gopos 200 200 300");
        assert_eq!(v.camera.pos, Vec3::new(200.0, 200.0, 300.0));
    }

    #[test]
    fn crosshair_clearance_mark_and_path() {
        let mut v = viewer();
        v.execute("noclip 1");
        v.execute("gopos 100 100 80");
        v.execute("setang 0 -45");
        let cam = v.camera;
        let mut fb = Framebuffer::new(96, 64, &cam, [0, 0, 0]);
        v.draw(&mut fb, None);
        // Looking down at 45°: the crosshair is on the graph sheet at z = 50.
        let p = v.crosshair.expect("crosshair on the sheet");
        assert!((p.z - 50.0).abs() < 1.0 && (p.x - 130.0).abs() < 2.0, "{p}");
        v.execute("clearance");
        assert!(
            v.messages.last().unwrap().contains("clearance 40.0"),
            "{:?}",
            v.messages
        );
        v.execute("mark 300 300 50");
        let path = v.path.clone().expect("a path");
        assert_eq!(path.first(), Some(&v.camera.pos));
        assert_eq!(path.last(), Some(&Vec3::new(300.0, 300.0, 50.0)));
        v.draw(&mut fb, Some("gopos"));
    }

    #[test]
    fn reduce_steps_the_compilers_reduction() {
        let mut v = viewer();
        // A 12×12 sheet of faces with constant clearance: plenty to remove.
        let mut b = VdgBuilder::new();
        for y in 0..12 {
            for x in 0..12 {
                b.add_vertex([x as f32 * 30.0, y as f32 * 30.0, 50.0], 40.0);
            }
        }
        for y in 0..11u32 {
            for x in 0..11u32 {
                let i = y * 12 + x;
                b.add_face([i, i + 1, i + 12]);
                b.add_face([i + 1, i + 13, i + 12]);
            }
        }
        v.graph = Some(VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap());
        v.execute("reduce 40");
        let after = v.graph.as_ref().unwrap().graph().vertices().len();
        assert!(
            (100..144).contains(&after),
            "{after} vertices, {:?}",
            v.messages.last()
        );
        assert!(v.messages.last().unwrap().contains("nodes 144 -> "));
        assert_eq!(
            v.scene.graph.as_ref().map(|g| g.positions.len()),
            Some(after)
        );
    }

    #[test]
    fn modes_and_bad_commands_report_instead_of_failing() {
        let mut v = viewer();
        v.execute("mode 2");
        assert_eq!(v.mode, Mode::Clearance);
        assert!(v.messages.last().unwrap().contains("not available"));
        v.execute("mode 1");
        assert_eq!(v.mode, Mode::Wireframe);
        v.execute("gopos 1 2");
        assert!(v.messages.last().unwrap().contains("malformed"));
        v.execute("reduce x");
        assert!(v.messages.last().unwrap().contains("expected a number"));
        v.record_frame(Duration::from_millis(10));
        v.execute("stats");
        assert!(v.messages.last().unwrap().contains("frame median 10.0 ms"));
        v.execute("quit");
        assert!(v.quit);
    }
}
