//! The automatic camera of the thesis (ch. 5, 6.2): it follows a target
//! through the VDG, keeps it in view, never leaves Volume(VDG) (so never
//! enters a wall) and moves smoothly.
//!
//! Each update builds candidate positions near the optima of the criteria
//! (distance, angle, inertia, clearance, visibility, the best local vertex),
//! pulls them back into the free volume, recombines them once, picks the
//! cheapest and moves towards it at a speed that grows with the current cost
//! (thesis 5.2/5.3). `CAMERA.md` next to this crate records our decisions
//! where the thesis is silent; each improvement beyond the thesis is a
//! switch in [`CameraParams`], and [`CameraParams::thesis`] turns them all
//! off.
//!
//! The graph is borrowed per call, so one mapped file serves many cameras;
//! each camera owns its scratch memory and allocates nothing per frame once
//! warmed up on a graph (the thesis variant's A* excepted).
//!
//! ```
//! use vdgformat::camera::{Camera, CameraParams, Target};
//! # let mut b = vdgformat::VdgBuilder::new();
//! # let v: Vec<u32> = [[0.0, 0.0], [512.0, 0.0], [0.0, 512.0], [512.0, 512.0]]
//! #     .iter().map(|&[x, y]| b.add_vertex([x, y, 64.0], 64.0)).collect();
//! # b.add_face([v[0], v[1], v[2]]);
//! # b.add_face([v[1], v[3], v[2]]);
//! # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes()?)?;
//! let g = file.graph();
//! let mut camera = Camera::new(CameraParams::default())?;
//! let mut player = Target::new([100.0, 250.0, 60.0], [1.0, 0.0, 0.0], [200.0, 0.0, 0.0]);
//! camera.reset(&g, &player);
//! for _ in 0..120 {
//!     player.position[0] += 200.0 / 60.0;
//!     let pose = camera.update(&g, &player, 1.0 / 60.0);
//!     assert!(g.contains(pose.eye)); // never outside the free volume
//! }
//! let pose = camera.update(&g, &player, 1.0 / 60.0);
//! assert!(pose.target_visible && pose.eye[0] < player.position[0]); // behind the player
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The parts, one file each:
//!
//! | file | what |
//! |---|---|
//! | `types.rs` | [`Target`], [`Pose`], [`Status`], the debug view; the configuration c_i and the frame's view of the target |
//! | `params.rs` | [`CameraParams`]: the constraints (μ, σ) and the switches beyond the thesis |
//! | `update.rs` | [`Camera`]: one update from the input to the pose |
//! | `scene.rs` | the target located in the graph, a_n, the frame's fixed terms |
//! | `cut.rs` | cuts: the camera placed anew |
//! | `motion.rs` | the step rule, the smoothed move across face volumes, sliding along walls |
//! | `candidates.rs` | k_dist … k_path, their clamps, k_comb and the choice |
//! | `costs.rs` | f_dist, f_angle, f_inertia, f_clear, f_vis, f_novis, f_total |
//! | `sight.rs` | the sight-line tests to the target, their allowance and hints |
//! | `director.rs` | [`Director`]: several cameras on one graph |

mod candidates;
mod costs;
mod cut;
mod director;
mod motion;
mod params;
mod scene;
mod sight;
mod types;
mod update;

pub use candidates::CandidateKind;
pub use costs::Costs;
pub use director::{CameraId, Director, DirectorEvent};
pub use params::{CameraError, CameraParams};
pub use types::{CandidateDebug, FrameDebug, Pose, Status, Target};
pub use update::Camera;

use candidates::{Scratch, VisMemo};
use sight::Slot;
use types::{GraphKey, Scene, State};
