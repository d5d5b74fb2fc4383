//! The frames of one segment, in the layout of each demo protocol.
//!
//! Every frame starts with a type byte, the demo time (seconds, f32) and the client's
//! frame number (i32). What follows depends on the type, and the type numbers and the
//! layouts differ between protocol 5 and protocol 4.

use crate::cursor::Cursor;
use crate::{Error, MAX_MESSAGE};

/// One frame of a segment.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Demo time in seconds.
    pub time: f32,
    /// The client's frame number.
    pub frame: i32,
    pub kind: FrameKind,
    /// Where the frame starts in the file.
    pub offset: usize,
}

/// What a frame holds.
#[derive(Debug, Clone, PartialEq)]
pub enum FrameKind {
    /// Network messages of one client frame, with the client's view of it.
    NetMsg(Box<NetMsg>),
    /// Playback starts (protocol 5).
    DemoStart,
    /// A console command the player typed (protocol 5; also protocol 4's client command).
    ConsoleCommand(String),
    /// The player's state as the client predicted it.
    ClientData(ClientData),
    /// End of the segment.
    NextSection,
    /// A client-side event (protocol 5).
    Event {
        flags: i32,
        index: i32,
        delay: f32,
        args: EventArgs,
    },
    /// The view model's animation (protocol 5).
    WeaponAnim { anim: i32, body: i32 },
    /// A sound played by the client (protocol 5).
    Sound(Sound),
    /// Client DLL data (protocol 5): its length.
    DemoBuffer(usize),
    /// A sync tick (protocol 4).
    SyncTick,
    /// Network channel sequence numbers (protocol 4).
    SequenceInfo([i32; 7]),
    /// End of one client frame (protocol 4).
    FrameComplete,
}

/// The client's view of one frame of network messages (protocol 5 records its whole
/// `ref_params`; protocol 4 only the view).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NetMsg {
    pub timestamp: f32,
    /// The rendered view's origin and angles.
    pub vieworg: [f32; 3],
    pub viewangles: [f32; 3],
    /// Client time and frame time in seconds.
    pub time: f32,
    pub frametime: f32,
    pub intermission: i32,
    pub paused: i32,
    pub spectator: i32,
    /// Standing on something (1) or in the air (0).
    pub onground: i32,
    /// 0 dry, 1 feet, 2 waist, 3 eyes under water.
    pub waterlevel: i32,
    /// The client's predicted velocity and origin (the centre of the player's hull).
    pub simvel: [f32; 3],
    pub simorg: [f32; 3],
    /// The view offset above the origin (28 standing, 12 crouched in Half-Life).
    pub viewheight: [f32; 3],
    /// Where the player aims (the view angles without punch and bobbing).
    pub cl_viewangles: [f32; 3],
    pub health: i32,
    /// The player's button bits of this frame's user command.
    pub buttons: u16,
    /// Bytes of the network message itself.
    pub message_length: usize,
    /// Protocol 5 (the whole record) or protocol 4 (the view only).
    pub full: bool,
}

/// Protocol 5's client data (`origin` is the view's origin) or protocol 4's (the
/// player's origin, with the view height).
#[derive(Debug, Clone, PartialEq)]
pub struct ClientData {
    pub origin: [f32; 3],
    pub viewangles: [f32; 3],
    pub weapon_bits: i32,
    pub fov: f32,
    /// Protocol 4 only.
    pub view_height: Option<f32>,
}

/// An event's arguments (protocol 5).
#[derive(Debug, Clone, PartialEq)]
pub struct EventArgs {
    pub flags: i32,
    pub entity: i32,
    pub origin: [f32; 3],
    pub angles: [f32; 3],
    pub velocity: [f32; 3],
    pub ducking: i32,
}

/// A sound frame (protocol 5).
#[derive(Debug, Clone, PartialEq)]
pub struct Sound {
    pub channel: i32,
    pub sample: String,
    pub attenuation: f32,
    pub volume: f32,
    pub flags: i32,
    pub pitch: i32,
}

/// Longest sound sample name (the engine's path buffer).
const MAX_SAMPLE: usize = 260;

/// Reads frames from `offset` up to and including the segment's "next section" frame.
pub(crate) fn read_segment(
    bytes: &[u8],
    offset: usize,
    protocol: i32,
) -> Result<Vec<Frame>, Error> {
    let mut c = Cursor::new(bytes, offset);
    let mut out = Vec::new();
    loop {
        // Every frame takes at least its 9-byte header, so the loop ends with the file.
        let at = c.at;
        let kind = c.u8("frame type")?;
        let time = c.f32("frame time")?;
        let frame = c.i32("frame number")?;
        let data = match protocol {
            5 => frame_v5(&mut c, kind, at)?,
            _ => frame_v4(&mut c, kind, at)?,
        };
        let end = data == FrameKind::NextSection;
        out.push(Frame {
            time,
            frame,
            kind: data,
            offset: at,
        });
        if end {
            return Ok(out);
        }
    }
}

fn frame_v5(c: &mut Cursor<'_>, kind: u8, at: usize) -> Result<FrameKind, Error> {
    Ok(match kind {
        0 | 1 => FrameKind::NetMsg(Box::new(netmsg_v5(c)?)),
        2 => FrameKind::DemoStart,
        3 => FrameKind::ConsoleCommand(c.string(64, "console command")?),
        4 => FrameKind::ClientData(ClientData {
            origin: c.vec3("client data origin")?,
            viewangles: c.vec3("client data angles")?,
            weapon_bits: c.i32("client data weapons")?,
            fov: c.f32("client data fov")?,
            view_height: None,
        }),
        5 => FrameKind::NextSection,
        6 => {
            let flags = c.i32("event flags")?;
            let index = c.i32("event index")?;
            let delay = c.f32("event delay")?;
            let args = EventArgs {
                flags: c.i32("event arguments")?,
                entity: c.i32("event arguments")?,
                origin: c.vec3("event arguments")?,
                angles: c.vec3("event arguments")?,
                velocity: c.vec3("event arguments")?,
                ducking: c.i32("event arguments")?,
            };
            // fparam1, fparam2, iparam1, iparam2, bparam1, bparam2.
            c.skip(24, "event arguments")?;
            FrameKind::Event {
                flags,
                index,
                delay,
                args,
            }
        }
        7 => FrameKind::WeaponAnim {
            anim: c.i32("weapon animation")?,
            body: c.i32("weapon body")?,
        },
        8 => {
            let channel = c.i32("sound channel")?;
            let n = c.length(MAX_SAMPLE, "sound sample length")?;
            let sample = c.string(n, "sound sample")?;
            Sound {
                channel,
                sample,
                attenuation: c.f32("sound attenuation")?,
                volume: c.f32("sound volume")?,
                flags: c.i32("sound flags")?,
                pitch: c.i32("sound pitch")?,
            }
            .into()
        }
        9 => {
            let n = c.length(MAX_MESSAGE, "demo buffer length")?;
            c.skip(n, "demo buffer")?;
            FrameKind::DemoBuffer(n)
        }
        other => {
            return Err(Error::UnknownFrameType {
                kind: other,
                protocol: 5,
                at,
            });
        }
    })
}

impl From<Sound> for FrameKind {
    fn from(s: Sound) -> FrameKind {
        FrameKind::Sound(s)
    }
}

/// Protocol 5's network message frame: timestamp, the client's `ref_params`, the user
/// command, the movement variables, the view, the view model, the channel's sequence
/// numbers and the message.
fn netmsg_v5(c: &mut Cursor<'_>) -> Result<NetMsg, Error> {
    const W: &str = "network message frame";
    let mut m = NetMsg {
        timestamp: c.f32(W)?,
        vieworg: c.vec3(W)?,
        viewangles: c.vec3(W)?,
        full: true,
        ..NetMsg::default()
    };
    c.skip(36, W)?; // forward, right, up
    m.frametime = c.f32(W)?;
    m.time = c.f32(W)?;
    m.intermission = c.i32(W)?;
    m.paused = c.i32(W)?;
    m.spectator = c.i32(W)?;
    m.onground = c.i32(W)?;
    m.waterlevel = c.i32(W)?;
    m.simvel = c.vec3(W)?;
    m.simorg = c.vec3(W)?;
    m.viewheight = c.vec3(W)?;
    c.skip(4, W)?; // idealpitch
    m.cl_viewangles = c.vec3(W)?;
    m.health = c.i32(W)?;
    // crosshairangle, viewsize, punchangle, 9 ints (maxclients … ptr_movevars),
    // viewport[4], next_view, only_client_draw.
    c.skip(12 + 4 + 12 + 36 + 16 + 8, W)?;
    // The user command: lerp_msec, msec, pad, viewangles, forward/side/up move,
    // lightlevel, pad, then the buttons.
    c.skip(2 + 1 + 1 + 12 + 12 + 1 + 1, W)?;
    let b = c.take(2, W)?;
    m.buttons = u16::from_le_bytes([b[0], b[1]]);
    // impulse, weaponselect, pad, impact index and position.
    c.skip(1 + 1 + 2 + 4 + 12, W)?;
    // Movement variables (16 floats, footsteps, sky name, 8 floats), view, view model.
    c.skip(64 + 4 + 32 + 32 + 12 + 4, W)?;
    // Seven sequence numbers.
    c.skip(28, W)?;
    m.message_length = c.length(MAX_MESSAGE, "network message length")?;
    c.skip(m.message_length, "network message")?;
    Ok(m)
}

fn frame_v4(c: &mut Cursor<'_>, kind: u8, at: usize) -> Result<FrameKind, Error> {
    Ok(match kind {
        0 | 1 => {
            const W: &str = "network message frame";
            // The view's origin and angles, then the message.
            let m = NetMsg {
                vieworg: c.vec3(W)?,
                viewangles: c.vec3(W)?,
                message_length: c.length(MAX_MESSAGE, "network message length")?,
                ..NetMsg::default()
            };
            c.skip(m.message_length, "network message")?;
            FrameKind::NetMsg(Box::new(m))
        }
        2 => FrameKind::SyncTick,
        3 => {
            let mut s = [0i32; 7];
            for v in &mut s {
                *v = c.i32("sequence info")?;
            }
            FrameKind::SequenceInfo(s)
        }
        4 => FrameKind::FrameComplete,
        5 => FrameKind::ConsoleCommand(c.string(64, "client command")?),
        6 => {
            const W: &str = "client data";
            let origin = c.vec3(W)?;
            let view_height = c.f32(W)?;
            c.skip(4, W)?; // maxspeed
            let viewangles = c.vec3(W)?;
            c.skip(12 + 4, W)?; // punch angles, key bits
            FrameKind::ClientData(ClientData {
                origin,
                viewangles,
                weapon_bits: c.i32(W)?,
                fov: c.f32(W)?,
                view_height: Some(view_height),
            })
        }
        8 => FrameKind::NextSection,
        other => {
            return Err(Error::UnknownFrameType {
                kind: other,
                protocol: 4,
                at,
            });
        }
    })
}
