//! Per-frame measures of a camera, with ground truth from the map's BSP (never the
//! graph judging itself), and their summary.
//!
//! - solid: the camera's eye in an obstacle (hull-0 point contents);
//! - near-plane clip: exact wall distance below 6.4 units (the near plane's corner
//!   distance for a 4-unit near plane at 90° × 74°), solid frames included;
//! - visibility: the segment camera → target eye free in the BSP, and the share of the
//!   9 hull points (8 corners + centre) seen;
//! - motion: speed, acceleration, jerk (finite differences, never across a cut or a
//!   route's start), view turn rate; jumps (faster than twice the target's top speed
//!   without a declared cut), stalls (speed falls by more than 80 % in one frame while
//!   the target moves);
//! - distance from the target's eye minus the camera's ideal distance d_μ (112 for the
//!   chase cam and spring arm), cuts, compute time per update;
//! - target outside Volume(VDG): the graph's fault, listed for the graph-quality work;
//! - the graph's own answer for the same sight line (`Visible`, eye → target eye):
//!   a line the BSP sees and the graph does not is a false occlusion, which makes a
//!   camera move for nothing; one the graph sees and the BSP does not would be a
//!   false positive of `Visible` (a camera trusting a blocked line).

use super::cameras::Frame;
use super::route::TargetState;
use bsp::oracle::Oracle;
use bsp::walls::Walls;
use vdgformat::Vdg;

/// Distance below which the near plane cuts into a wall.
pub const NEAR_PLANE: f64 = 6.4;

/// Everything measured in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FrameMeasure {
    pub t: f64,
    pub target: [f32; 3],
    pub eye: [f32; 3],
    pub cut: bool,
    pub solid: bool,
    pub clearance: f32,
    pub eye_visible: bool,
    pub hull_visible: f32,
    pub speed: f32,
    pub accel: f32,
    pub jerk: f32,
    pub turn_rate: f32,
    pub jump: bool,
    pub stall: bool,
    pub dist_error: f32,
    pub micros: f32,
    pub target_outside: bool,
    /// `Visible(eye, target eye)` on the graph.
    pub graph_visible: bool,
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] as f64 - b[i] as f64)
}
fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Measures one camera on one route. `frames[i]` was shown for `targets[i]` and took
/// `micros[i]` to compute; `outside[i]` says whether the target was outside the volume;
/// `d_mu` is the camera's own ideal distance; `graph` answers the same sight lines.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    oracle: &Oracle,
    walls: &Walls,
    graph: &Vdg<'_>,
    targets: &[TargetState],
    frames: &[Frame],
    micros: &[f32],
    outside: &[bool],
    dt: f64,
    d_mu: f64,
) -> Vec<FrameMeasure> {
    let top_speed = targets
        .iter()
        .map(|t| t.speed())
        .fold(0.0f32, f32::max)
        .max(96.0);
    let mut out: Vec<FrameMeasure> = Vec::with_capacity(frames.len());
    let mut vel: Vec<Option<[f64; 3]>> = Vec::with_capacity(frames.len());
    let mut acc: Vec<Option<[f64; 3]>> = Vec::with_capacity(frames.len());
    for (i, (t, f)) in targets.iter().zip(frames).enumerate() {
        let eye = f.eye.map(f64::from);
        let solid = !oracle.is_free(eye);
        let clearance = if solid { 0.0 } else { walls.distance(eye) };
        let target_eye = t.eye().map(f64::from);
        let eye_visible = !solid && oracle.segment_free(eye, target_eye);
        let graph_visible = graph.visible(f.eye, t.eye());
        let hull_visible = if solid {
            0.0
        } else {
            let pts = t.hull_points();
            pts.iter().filter(|p| oracle.segment_free(eye, **p)).count() as f32 / pts.len() as f32
        };
        let v = (i > 0 && !f.cut).then(|| sub(f.eye, frames[i - 1].eye).map(|c| c / dt));
        let a = match (v, vel.last().copied().flatten()) {
            (Some(v), Some(p)) => Some([0, 1, 2].map(|k| (v[k] - p[k]) / dt)),
            _ => None,
        };
        let j = match (a, acc.last().copied().flatten()) {
            (Some(a), Some(p)) => Some([0, 1, 2].map(|k| (a[k] - p[k]) / dt)),
            _ => None,
        };
        let speed = v.map_or(0.0, norm);
        let prev_speed = out.last().map_or(0.0, |m| m.speed as f64);
        let view = sub(f.look_at, f.eye);
        let turn_rate = if i > 0 && !f.cut {
            let pv = sub(frames[i - 1].look_at, frames[i - 1].eye);
            let c = (view[0] * pv[0] + view[1] * pv[1] + view[2] * pv[2])
                / (norm(view) * norm(pv)).max(1e-9);
            c.clamp(-1.0, 1.0).acos().to_degrees() / dt
        } else {
            0.0
        };
        let target_dist = norm(sub(f.eye, t.eye()));
        out.push(FrameMeasure {
            t: t.t,
            target: t.origin,
            eye: f.eye,
            cut: f.cut,
            solid,
            clearance: clearance as f32,
            eye_visible,
            hull_visible,
            speed: speed as f32,
            accel: a.map_or(0.0, norm) as f32,
            jerk: j.map_or(f32::NAN, |j| norm(j) as f32),
            turn_rate: turn_rate as f32,
            jump: v.is_some() && speed > 2.0 * top_speed as f64,
            stall: v.is_some() && prev_speed > 20.0 && speed < 0.2 * prev_speed && t.speed() > 50.0,
            dist_error: (target_dist - d_mu) as f32,
            micros: micros[i],
            target_outside: outside[i],
            graph_visible,
        });
        vel.push(v);
        acc.push(a);
    }
    out
}

/// The summary of one camera over all routes of a replay.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Summary {
    pub frames: usize,
    pub seconds: f64,
    pub solid_frames: usize,
    pub nearplane_frames: usize,
    pub visible_fraction: f64,
    pub hull_visible_mean: f64,
    pub longest_occlusion_s: f64,
    pub mean_speed: f64,
    pub max_speed: f64,
    pub rms_accel: f64,
    pub rms_jerk: f64,
    pub mean_turn_rate: f64,
    pub max_turn_rate: f64,
    pub jumps: usize,
    pub stalls: usize,
    pub mean_abs_dist_error: f64,
    pub rms_dist_error: f64,
    pub cuts: usize,
    pub cuts_per_min: f64,
    pub median_us: f64,
    pub p99_us: f64,
    pub target_outside_fraction: f64,
    /// `visible_fraction` over the frames whose target stands inside
    /// Volume(VDG): what the camera is answerable for. A target outside the
    /// volume is the graph's fault (Visible traces through the volume), and
    /// the graph-quality figures need the two told apart.
    pub visible_fraction_target_inside: f64,
    /// Of the frames whose target eye the BSP sees, the share the graph's
    /// `Visible` calls hidden: sight lines the camera would move away from for
    /// nothing (Visible's false negatives where the camera actually looks).
    pub graph_false_occlusion: f64,
    /// Frames the graph calls visible and the BSP blocked (must stay 0).
    pub graph_false_visible_frames: usize,
}

/// Summarises the measures of each route (routes are separate: occlusion runs and
/// finite differences never span two of them).
pub fn summarise(routes: &[Vec<FrameMeasure>], dt: f64) -> Summary {
    let all: Vec<&FrameMeasure> = routes.iter().flatten().collect();
    let n = all.len();
    if n == 0 {
        return Summary::default();
    }
    let count = |f: &dyn Fn(&FrameMeasure) -> bool| all.iter().filter(|m| f(m)).count();
    let mean = |f: &dyn Fn(&FrameMeasure) -> f64| all.iter().map(|m| f(m)).sum::<f64>() / n as f64;
    let rms = |f: &dyn Fn(&FrameMeasure) -> f32| {
        let v: Vec<f64> = all
            .iter()
            .map(|m| f(m) as f64)
            .filter(|x| x.is_finite())
            .collect();
        if v.is_empty() {
            0.0
        } else {
            (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
        }
    };
    let mut longest = 0usize;
    for r in routes {
        let mut run = 0;
        for m in r {
            run = if m.eye_visible { 0 } else { run + 1 };
            longest = longest.max(run);
        }
    }
    let mut us: Vec<f32> = all.iter().map(|m| m.micros).collect();
    us.sort_by(f32::total_cmp);
    let seconds = n as f64 * dt;
    let cuts = count(&|m| m.cut);
    Summary {
        frames: n,
        seconds,
        solid_frames: count(&|m| m.solid),
        nearplane_frames: count(&|m| m.solid || (m.clearance as f64) < NEAR_PLANE),
        visible_fraction: count(&|m| m.eye_visible) as f64 / n as f64,
        hull_visible_mean: mean(&|m| m.hull_visible as f64),
        longest_occlusion_s: longest as f64 * dt,
        mean_speed: mean(&|m| m.speed as f64),
        max_speed: all.iter().map(|m| m.speed as f64).fold(0.0, f64::max),
        rms_accel: rms(&|m| m.accel),
        rms_jerk: rms(&|m| m.jerk),
        mean_turn_rate: mean(&|m| m.turn_rate as f64),
        max_turn_rate: all.iter().map(|m| m.turn_rate as f64).fold(0.0, f64::max),
        jumps: count(&|m| m.jump),
        stalls: count(&|m| m.stall),
        mean_abs_dist_error: mean(&|m| (m.dist_error as f64).abs()),
        rms_dist_error: rms(&|m| m.dist_error),
        cuts,
        cuts_per_min: cuts as f64 / (seconds / 60.0),
        median_us: us[n / 2] as f64,
        p99_us: us[((n as f64 * 0.99) as usize).min(n - 1)] as f64,
        target_outside_fraction: count(&|m| m.target_outside) as f64 / n as f64,
        visible_fraction_target_inside: {
            let inside = count(&|m| !m.target_outside);
            if inside == 0 {
                0.0
            } else {
                count(&|m| !m.target_outside && m.eye_visible) as f64 / inside as f64
            }
        },
        graph_false_occlusion: {
            let seen = count(&|m| m.eye_visible);
            if seen == 0 {
                0.0
            } else {
                count(&|m| m.eye_visible && !m.graph_visible) as f64 / seen as f64
            }
        },
        graph_false_visible_frames: count(&|m| m.graph_visible && !m.eye_visible),
    }
}

impl Summary {
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "frames": self.frames,
            "seconds": self.seconds,
            "solid_frames": self.solid_frames,
            "nearplane_frames": self.nearplane_frames,
            "visible_fraction": self.visible_fraction,
            "hull_visible_mean": self.hull_visible_mean,
            "longest_occlusion_s": self.longest_occlusion_s,
            "mean_speed": self.mean_speed,
            "max_speed": self.max_speed,
            "rms_accel": self.rms_accel,
            "rms_jerk": self.rms_jerk,
            "mean_turn_rate": self.mean_turn_rate,
            "max_turn_rate": self.max_turn_rate,
            "jumps": self.jumps,
            "stalls": self.stalls,
            "mean_abs_dist_error": self.mean_abs_dist_error,
            "rms_dist_error": self.rms_dist_error,
            "cuts": self.cuts,
            "cuts_per_min": self.cuts_per_min,
            "median_us": self.median_us,
            "p99_us": self.p99_us,
            "target_outside_fraction": self.target_outside_fraction,
            "visible_fraction_target_inside": self.visible_fraction_target_inside,
            "graph_false_occlusion": self.graph_false_occlusion,
            "graph_false_visible_frames": self.graph_false_visible_frames,
        })
    }
}

/// CSV header of [`csv_row`].
pub const CSV_HEADER: &str = "route,t,target_x,target_y,target_z,eye_x,eye_y,eye_z,cut,solid,clearance,eye_visible,hull_visible,speed,accel,jerk,turn_rate,jump,stall,dist_error,micros,target_outside,graph_visible";

/// One CSV line of a frame.
pub fn csv_row(route: &str, m: &FrameMeasure) -> String {
    let b = |x: bool| x as u8;
    format!(
        "{},{:.4},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{},{},{:.2},{},{:.3},{:.2},{:.1},{:.1},{:.2},{},{},{:.2},{:.2},{},{}",
        route.replace(',', ";"),
        m.t,
        m.target[0],
        m.target[1],
        m.target[2],
        m.eye[0],
        m.eye[1],
        m.eye[2],
        b(m.cut),
        b(m.solid),
        m.clearance,
        b(m.eye_visible),
        m.hull_visible,
        m.speed,
        m.accel,
        if m.jerk.is_finite() { m.jerk } else { 0.0 },
        m.turn_rate,
        b(m.jump),
        b(m.stall),
        m.dist_error,
        m.micros,
        b(m.target_outside),
        b(m.graph_visible)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(eye_visible: bool, target_outside: bool) -> FrameMeasure {
        FrameMeasure {
            eye_visible,
            target_outside,
            clearance: 64.0,
            ..Default::default()
        }
    }

    #[test]
    fn visibility_is_also_counted_over_the_frames_the_camera_answers_for() {
        // 10 frames: 6 visible inside, 2 hidden inside, 2 hidden outside.
        let mut route = vec![frame(true, false); 6];
        route.extend([frame(false, false); 2]);
        route.extend([frame(false, true); 2]);
        let s = summarise(&[route], 1.0 / 60.0);
        assert_eq!(s.frames, 10);
        assert!((s.visible_fraction - 0.6).abs() < 1e-12);
        assert!((s.target_outside_fraction - 0.2).abs() < 1e-12);
        assert!((s.visible_fraction_target_inside - 0.75).abs() < 1e-12);
        assert_eq!(s.to_json()["visible_fraction_target_inside"], 0.75);
    }

    #[test]
    fn false_occlusions_count_the_lines_the_bsp_sees_and_the_graph_does_not() {
        let f = |eye_visible, graph_visible| FrameMeasure {
            eye_visible,
            graph_visible,
            ..Default::default()
        };
        // 8 frames the BSP sees (2 of them hidden for the graph), 2 it does not
        // (1 of them visible for the graph: a false positive).
        let mut route = vec![f(true, true); 6];
        route.extend([f(true, false); 2]);
        route.extend([f(false, false), f(false, true)]);
        let s = summarise(&[route], 1.0 / 60.0);
        assert!((s.graph_false_occlusion - 0.25).abs() < 1e-12);
        assert_eq!(s.graph_false_visible_frames, 1);
        assert_eq!(s.to_json()["graph_false_occlusion"], 0.25);
    }
}
