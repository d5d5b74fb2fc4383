//! The VDG camera (`vdgformat::camera`) behind the replay's [`ReplayCamera`] trait:
//! `vdg` is [`CameraParams::default`] (our improvements on), `vdg-thesis` is
//! [`CameraParams::thesis`] (the thesis' algorithm as written); `--params cam.toml`
//! replaces the parameters of `vdg`. The target is the player's eye (origin + view offset,
//! on GoldSrc 28 standing, 12 crouched; see [`TargetState::eye`]): what the spectator
//! wants in view, what the spring arm pivots on and what the replay's visibility
//! measures. Its heading is the view angles.

use super::cameras::{Frame, ReplayCamera};
use super::route::TargetState;
use vdgformat::Vdg;
use vdgformat::camera::{Camera, CameraParams, Target};

/// A `vdgformat` camera on one graph.
pub struct VdgCamera<'a> {
    name: String,
    graph: Vdg<'a>,
    camera: Camera,
}

impl<'a> VdgCamera<'a> {
    /// `params` is TOML text (`--params`); `None` keeps the variant's defaults.
    pub fn new(name: &str, graph: Vdg<'a>, params: Option<&str>) -> Result<Self, String> {
        let p = match (name, params) {
            ("vdg-thesis", _) => CameraParams::thesis(),
            (_, Some(text)) => {
                CameraParams::from_toml_str(text).map_err(|e| format!("--params: {e}"))?
            }
            _ => CameraParams::default(),
        };
        let camera = Camera::new(p).map_err(|e| format!("camera {name}: {e}"))?;
        Ok(VdgCamera {
            name: name.to_string(),
            graph,
            camera,
        })
    }

    /// The underlying camera (its per-frame debug record, parameters).
    pub fn camera(&self) -> &Camera {
        &self.camera
    }
}

fn target(t: &TargetState) -> Target {
    Target::from_angles(t.eye(), t.angles, t.velocity)
}

impl ReplayCamera for VdgCamera<'_> {
    fn ideal_distance(&self) -> f64 {
        f64::from(self.camera.params().distance_mu)
    }

    fn name(&self) -> &str {
        &self.name
    }
    fn reset(&mut self, t: &TargetState) {
        self.camera.reset(&self.graph, &target(t));
    }
    fn update(&mut self, t: &TargetState, dt: f32) -> Frame {
        let pose = self.camera.update(&self.graph, &target(t), dt);
        Frame {
            eye: pose.eye,
            look_at: pose.look_at,
            cut: pose.cut,
        }
    }
}
