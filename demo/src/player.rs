//! The recorded player's motion: what the client predicted each client frame.
//!
//! Protocol 5 records the client's whole view state with every network message frame:
//! the simulated origin (the centre of the player's hull, as the game's movement code
//! moved it), its velocity, the view angles the player aimed with and the view height.
//! Protocol 4 records origin, view height and angles in a client data frame of its own.
//! Frames whose time does not advance (a paused game, a second message in the same
//! client frame) or that hold non-finite numbers are left out.

use crate::frames::FrameKind;
use crate::{Demo, Segment};

/// Half-Life's view height standing (`VEC_VIEW`; Counter-Strike's is 17).
pub const STAND_VIEW_HEIGHT: f32 = 28.0;
/// The view height of a player whose crouch is complete (`VEC_DUCK_VIEW`, every GoldSrc
/// game). While the player goes down the view height slides from the standing one to
/// this, with the standing hull; the crouched hull is taken once it reaches it.
pub const CROUCH_VIEW_HEIGHT: f32 = 12.0;

/// The player in one client frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlayerFrame {
    /// Demo time in seconds.
    pub t: f64,
    /// Centre of the player's hull.
    pub origin: [f32; 3],
    /// Quake view angles `[pitch, yaw, roll]`, degrees.
    pub angles: [f32; 3],
    /// The client's predicted velocity (protocol 5), units per second.
    pub velocity: Option<[f32; 3]>,
    /// The eye's height above the origin.
    pub view_height: f32,
    /// Standing on something (protocol 5).
    pub on_ground: Option<bool>,
    /// Index of the segment in the demo's directory.
    pub segment: usize,
}

impl PlayerFrame {
    /// The crouched hull is in use (the view height is the crouched one).
    pub fn crouched(&self) -> bool {
        self.view_height <= CROUCH_VIEW_HEIGHT + 0.5
    }
}

pub(crate) fn frames(demo: &Demo) -> Vec<PlayerFrame> {
    let mut out: Vec<PlayerFrame> = Vec::new();
    for (k, seg) in demo.segments.iter().enumerate() {
        if !seg.is_playback() {
            continue;
        }
        let before = out.len();
        for p in segment_frames(seg, k, demo.header.demo_protocol) {
            let finite = p.t.is_finite()
                && p.origin.iter().chain(&p.angles).all(|v| v.is_finite())
                && p.view_height.is_finite()
                && p.velocity.is_none_or(|v| v.iter().all(|x| x.is_finite()));
            if !finite {
                continue;
            }
            if out.len() > before && p.t <= out[out.len() - 1].t {
                continue;
            }
            out.push(p);
        }
    }
    out
}

fn segment_frames(
    seg: &Segment,
    k: usize,
    protocol: i32,
) -> impl Iterator<Item = PlayerFrame> + '_ {
    seg.frames
        .iter()
        .filter_map(move |f| match (&f.kind, protocol) {
            (FrameKind::NetMsg(m), 5) if m.full => Some(PlayerFrame {
                t: f.time as f64,
                origin: m.simorg,
                angles: m.cl_viewangles,
                velocity: Some(m.simvel),
                view_height: m.viewheight[2],
                on_ground: Some(m.onground != 0),
                segment: k,
            }),
            (FrameKind::ClientData(d), 4) => Some(PlayerFrame {
                t: f.time as f64,
                origin: d.origin,
                angles: d.viewangles,
                velocity: None,
                view_height: d.view_height.unwrap_or(STAND_VIEW_HEIGHT),
                on_ground: None,
                segment: k,
            }),
            _ => None,
        })
}
