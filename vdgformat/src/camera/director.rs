//! The director (thesis 6.2, `CDirector`): several cameras with their own
//! targets and parameters on one graph, one of them active.

use super::{Camera, CameraError, CameraParams, GraphKey, Pose, Target};
use crate::read::Vdg;

/// A camera's handle in a [`Director`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CameraId(pub u32);

/// Something the engine may want to react to (e.g. skip motion blur or
/// interpolation across a cut).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectorEvent {
    /// The active camera changed.
    Switched {
        from: Option<CameraId>,
        to: CameraId,
    },
    /// A camera cut (reset, teleported or long-hidden target, new graph).
    Cut { camera: CameraId },
    /// The graph handed to [`Director::update`] is not the one of the last
    /// update (a new map): every camera starts anew.
    GraphChanged,
}

#[derive(Debug)]
struct Entry {
    id: CameraId,
    camera: Camera,
    target: Option<Target>,
    pose: Option<Pose>,
}

/// Several cameras on one graph and which one is shown. Call
/// [`Director::update`] once per frame; it updates every camera that has a
/// target and returns the active camera's pose.
///
/// ```
/// use vdgformat::camera::{CameraParams, Director, DirectorEvent, Target};
/// # let mut b = vdgformat::VdgBuilder::new();
/// # let v: Vec<u32> = [[0.0, 0.0], [512.0, 0.0], [0.0, 512.0], [512.0, 512.0]]
/// #     .iter().map(|&[x, y]| b.add_vertex([x, y, 64.0], 64.0)).collect();
/// # b.add_face([v[0], v[1], v[2]]);
/// # b.add_face([v[1], v[3], v[2]]);
/// # let file = vdgformat::VdgFile::from_bytes(&b.to_bytes()?)?;
/// let g = file.graph();
/// let mut director = Director::new();
/// let a = director.add_camera(CameraParams::default())?;
/// let b = director.add_camera(CameraParams { distance_mu: 80.0, ..CameraParams::default() })?;
/// director.set_target(a, Target::new([100.0, 100.0, 60.0], [1.0, 0.0, 0.0], [0.0; 3]));
/// director.set_target(b, Target::new([400.0, 400.0, 60.0], [0.0, 1.0, 0.0], [0.0; 3]));
/// let first = director.update(&g, 1.0 / 60.0).unwrap();
/// assert!(director.activate(b));
/// let second = director.update(&g, 1.0 / 60.0).unwrap();
/// assert!(director.events().contains(&DirectorEvent::Switched { from: Some(a), to: b }));
/// assert!(first.eye != second.eye);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Default)]
pub struct Director {
    entries: Vec<Entry>,
    active: Option<CameraId>,
    next_id: u32,
    events: Vec<DirectorEvent>,
    /// A switch requested since the last update.
    switched_from: Option<Option<CameraId>>,
    graph: Option<GraphKey>,
}

impl Director {
    /// A director without cameras.
    pub fn new() -> Director {
        Director::default()
    }

    /// Adds a camera; the first one added becomes active.
    pub fn add_camera(&mut self, params: CameraParams) -> Result<CameraId, CameraError> {
        let camera = Camera::new(params)?;
        let id = CameraId(self.next_id);
        self.next_id += 1;
        self.entries.push(Entry {
            id,
            camera,
            target: None,
            pose: None,
        });
        self.events.reserve(2 * self.entries.len() + 2);
        if self.active.is_none() {
            self.active = Some(id);
        }
        Ok(id)
    }

    /// Removes a camera (if it was active, none is). Whether it existed.
    pub fn remove_camera(&mut self, id: CameraId) -> bool {
        let before = self.entries.len();
        self.entries.retain(|e| e.id != id);
        if self.active == Some(id) {
            self.active = None;
        }
        self.entries.len() != before
    }

    fn entry(&self, id: CameraId) -> Option<&Entry> {
        self.entries.iter().find(|e| e.id == id)
    }

    fn entry_mut(&mut self, id: CameraId) -> Option<&mut Entry> {
        self.entries.iter_mut().find(|e| e.id == id)
    }

    /// A camera, e.g. for its [`Camera::debug`] view.
    pub fn camera(&self, id: CameraId) -> Option<&Camera> {
        self.entry(id).map(|e| &e.camera)
    }

    /// A camera, e.g. to change its parameters.
    pub fn camera_mut(&mut self, id: CameraId) -> Option<&mut Camera> {
        self.entry_mut(id).map(|e| &mut e.camera)
    }

    /// Sets what a camera follows from the next update on. Whether the
    /// camera exists.
    pub fn set_target(&mut self, id: CameraId, target: Target) -> bool {
        self.entry_mut(id)
            .map(|e| e.target = Some(target))
            .is_some()
    }

    /// Makes a camera the one shown. Whether it exists.
    pub fn activate(&mut self, id: CameraId) -> bool {
        if self.entry(id).is_none() {
            return false;
        }
        if self.active != Some(id) {
            self.switched_from.get_or_insert(self.active);
            self.active = Some(id);
        }
        true
    }

    /// The camera shown.
    pub fn active(&self) -> Option<CameraId> {
        self.active
    }

    /// The cameras, in the order they were added.
    pub fn cameras(&self) -> impl Iterator<Item = CameraId> + '_ {
        self.entries.iter().map(|e| e.id)
    }

    /// A camera's pose of the last update.
    pub fn pose(&self, id: CameraId) -> Option<Pose> {
        self.entry(id).and_then(|e| e.pose)
    }

    /// What happened in the last update.
    pub fn events(&self) -> &[DirectorEvent] {
        &self.events
    }

    /// Once per frame: updates every camera that has a target and returns
    /// the active camera's pose (`None` if there is none or it has no
    /// target yet). A different graph than last time (a map change) is
    /// noticed here: every camera restarts on it.
    pub fn update(&mut self, g: &Vdg<'_>, dt: f32) -> Option<Pose> {
        self.events.clear();
        let key = GraphKey::of(g);
        if self.graph.is_some_and(|k| k != key) {
            self.events.push(DirectorEvent::GraphChanged);
        }
        self.graph = Some(key);
        if let (Some(from), Some(to)) = (self.switched_from.take(), self.active) {
            self.events.push(DirectorEvent::Switched { from, to });
        }
        for e in &mut self.entries {
            if let Some(t) = e.target {
                let pose = e.camera.update(g, &t, dt);
                if pose.cut {
                    self.events.push(DirectorEvent::Cut { camera: e.id });
                }
                e.pose = Some(pose);
            }
        }
        self.active.and_then(|id| self.pose(id))
    }
}
