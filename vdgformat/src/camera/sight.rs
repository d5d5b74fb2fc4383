//! Sight lines from candidate positions, vertices and the pose to the
//! target: the one-face shortcut, the update's allowance of hops and leaf
//! searches, and the hints that let a test follow the way the same sight
//! line took last frame.

use super::scene::INSIDE;
use super::types::Ahead;
use super::{Camera, Scene};
use crate::geom::V3;
use crate::query::{CoverBudget, CoverHint, FaceCache};
use crate::read::Vdg;

/// Which remembered sight line a test continues.
#[derive(Clone, Copy, Debug)]
pub(super) enum Slot {
    /// A candidate's (by its index in the frame) or the pose's.
    Line(usize),
    /// A reachable vertex's.
    Vertex(u32),
}

/// Hints for the sight lines of the last few vertices tested (the
/// reachable set changes slowly), replaced oldest first.
#[derive(Clone, Debug)]
pub(super) struct VertexHints {
    vertices: [u32; VERTEX_HINTS],
    hints: [CoverHint; VERTEX_HINTS],
    next: usize,
}

const VERTEX_HINTS: usize = 32;

impl Default for VertexHints {
    fn default() -> Self {
        VertexHints {
            vertices: [u32::MAX; VERTEX_HINTS],
            hints: [CoverHint::default(); VERTEX_HINTS],
            next: 0,
        }
    }
}

impl VertexHints {
    /// The hint of vertex `v`, a fresh one if it has none.
    pub(super) fn get(&mut self, v: u32) -> &mut CoverHint {
        let i = match self.vertices.iter().position(|&u| u == v) {
            Some(i) => i,
            None => {
                let i = self.next;
                self.next = (i + 1) % VERTEX_HINTS;
                self.vertices[i] = v;
                self.hints[i] = CoverHint::default();
                i
            }
        };
        &mut self.hints[i]
    }
}

/// A line of sight crossing more face volumes than this counts as blocked
/// (a camera's sight lines span a few faces; the bound caps the worst case
/// of an update).
pub(super) const VISIBILITY_HOPS: u32 = 48;

/// Most exact face evaluations one searching step of the camera's sight
/// lines, clamps and moves makes (the covers' `step_evals`). The hop budgets
/// bound how many steps an update takes, not what a step costs: in a big
/// open room, where hundreds of face volumes overlap, one step of a failing
/// sight line tried hundreds of faces. Set above what the steps on the
/// shared maps make, so it only bounds such rooms
/// (docs/measurements/2026-12-07h-camera-step-limit.md).
pub(super) const STEP_EVALS: u32 = 128;

/// The hint slot of the pose's own sight line (after the 7 candidates').
pub(super) const POSE_HINT: usize = 8;

impl Camera {
    /// Visible(k, t) from face `face` (counted in the debug view). When
    /// `k` lies in the volume of the target's face, which holds `t` too,
    /// the segment does (the volume is convex): one evaluation instead of a
    /// trace.
    ///
    /// The test's hops and tree-leaf searches come out of the update's
    /// allowance ([`CameraParams::sight_hops`](super::CameraParams::sight_hops), [`CameraParams::leaf_searches`](super::CameraParams::leaf_searches));
    /// the pose's own test, [`Camera::sees_finally`], has one of its own.
    ///
    /// `slot` names a sight line the camera tests again and again (a
    /// candidate kind, the pose, a reachable vertex): its [`CoverHint`]
    /// from the last time guides the test.
    pub(super) fn sees(
        &mut self,
        g: &Vdg<'_>,
        face: u32,
        k: V3,
        scene: &Scene,
        slot: Option<Slot>,
    ) -> bool {
        if scene.t_vis_in_face && self.faces.fc(g, scene.face, k) > INSIDE {
            return true;
        }
        self.debug.visibility_tests += 1;
        let hint = match slot {
            Some(Slot::Line(i)) => Some(&mut self.hints[i]),
            Some(Slot::Vertex(v)) => Some(self.vertex_hints.get(v)),
            None => None,
        };
        charged_sight(
            g,
            &mut self.sight_budget,
            &self.faces,
            (face, k, scene.t_vis),
            hint,
        )
    }

    /// Visible(k, ahead) from face `face` for the `slot`-th candidate (or,
    /// at [`POSE_HINT`], the camera's own place): the sight line to the
    /// point ahead of the target ([`Scene::ahead`]), on its own allowance
    /// and hints.
    pub(super) fn sees_ahead(
        &mut self,
        g: &Vdg<'_>,
        face: u32,
        k: V3,
        ahead: &Ahead,
        slot: usize,
    ) -> bool {
        if self.faces.fc(g, ahead.face, k) > INSIDE
            && self.faces.fc(g, ahead.face, ahead.point) > INSIDE
        {
            return true;
        }
        self.debug.visibility_tests += 1;
        charged_sight(
            g,
            &mut self.ahead_budget,
            &self.faces,
            (face, k, ahead.point),
            Some(&mut self.ahead_hints[slot]),
        )
    }

    /// [`Camera::sees`] from vertex `v` (in its first face), continuing
    /// that vertex's remembered sight line.
    pub(super) fn sees_vertex(&mut self, g: &Vdg<'_>, scene: &Scene, v: u32) -> bool {
        self.sees(
            g,
            g.vertex_faces(v).get(0),
            g.pos(v),
            scene,
            Some(Slot::Vertex(v)),
        )
    }

    /// [`Camera::sees`] for the pose the update returns: `target_visible`
    /// and the hidden-time clock (which makes cuts) rest on it, so it does
    /// not share the candidates' allowance.
    pub(super) fn sees_finally(&mut self, g: &Vdg<'_>, face: u32, k: V3, scene: &Scene) -> bool {
        self.sight_budget = CoverBudget {
            hops: VISIBILITY_HOPS,
            leaf_searches: self.params.leaf_searches,
        };
        self.sees(g, face, k, scene, Some(Slot::Line(POSE_HINT)))
    }
}

/// One budgeted sight test from `k` (in face `face`) to `to`, charged to
/// `allowance`: at most [`VISIBILITY_HOPS`] of its hops, and the tree-leaf
/// searches it made.
fn charged_sight(
    g: &Vdg<'_>,
    allowance: &mut CoverBudget,
    faces: &FaceCache,
    (face, k, to): (u32, V3, V3),
    hint: Option<&mut CoverHint>,
) -> bool {
    let hops = allowance.hops.min(VISIBILITY_HOPS);
    let mut budget = CoverBudget {
        hops,
        leaf_searches: allowance.leaf_searches,
    };
    let seen = g.visible_hinted_cached(
        face,
        k.to_f32(),
        to.to_f32(),
        &mut budget,
        hint,
        Some(faces),
        STEP_EVALS,
    );
    allowance.hops -= hops - budget.hops;
    allowance.leaf_searches = budget.leaf_searches;
    seen
}
