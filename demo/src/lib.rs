//! GoldSrc (Half-Life engine) demo files: what the console's `record NAME` writes.
//!
//! A demo is a header (map, game folder, protocols), a directory of segments at the end
//! of the file (a `LOADING` segment of the connection, then the playback segments of the
//! game itself) and, for each segment, a run of frames closed by a "next section" frame.
//! Frames carry the client's view of each client frame: the network messages the server
//! sent and, beside them, what the client predicted (origin, velocity, view angles, view
//! height). [`Demo::player`] extracts the recorded player's motion from the playback
//! segments: what a camera replay follows.
//!
//! Two layouts are read: demo protocol 5 (every Half-Life release since 1.1, Counter-Strike
//! 1.6, Steam) and protocol 4 (Half-Life 1.0.0.5: a shorter header, other frame numbers,
//! the player's state in a "client data" frame of its own). Anything else is refused with
//! an error naming the protocol. Every count and length is checked against the file
//! before it is used, so a truncated or corrupt file gives a one-line [`Error`], never a
//! panic or an allocation larger than the file.
//!
//! ```no_run
//! let demo = demo::Demo::open(std::path::Path::new("playtest.dem")).unwrap();
//! println!("{} on {} ({:.1} s)", demo.header.game_dir, demo.header.map_name, demo.duration());
//! for p in demo.player() {
//!     println!("{:.3} {:?} crouched {}", p.t, p.origin, p.crouched());
//! }
//! ```

mod cursor;
mod frames;
mod player;

pub use frames::{ClientData, EventArgs, Frame, FrameKind, NetMsg, Sound};
pub use player::{CROUCH_VIEW_HEIGHT, PlayerFrame, STAND_VIEW_HEIGHT};

use cursor::Cursor;
use std::fmt;
use std::path::Path;

/// The 8 bytes every demo starts with.
pub const MAGIC: &[u8; 8] = b"HLDEMO\0\0";
/// Most directory entries a demo may have (the engine writes 2).
pub const MAX_SEGMENTS: usize = 1024;
/// Longest network message of one frame (the engine's message buffer).
pub const MAX_MESSAGE: usize = 65_536;

/// Why a file is not a demo this reader can read. Every message is one line.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// The file does not start with `HLDEMO`.
    BadMagic([u8; 8]),
    /// A demo protocol other than 4 and 5.
    UnsupportedProtocol(i32),
    /// The protocol field says one protocol, the layout is the other's.
    LayoutMismatch { stated: i32, layout: i32 },
    /// The directory's entry count is outside 1..=1024.
    BadSegmentCount(i32),
    /// A field points outside the file (directory, segment start).
    BadOffset {
        what: &'static str,
        value: i64,
        len: usize,
    },
    /// A length field outside its range.
    BadLength {
        what: &'static str,
        value: i64,
        max: usize,
        at: usize,
    },
    /// A frame type the protocol does not have.
    UnknownFrameType { kind: u8, protocol: i32, at: usize },
    /// The file ends inside a field.
    Truncated {
        what: &'static str,
        at: usize,
        len: usize,
    },
    /// The file could not be read.
    Io(String),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::BadMagic(m) => write!(
                f,
                "not a GoldSrc demo (starts with {:?}, expected \"HLDEMO\")",
                String::from_utf8_lossy(m).trim_end_matches('\0')
            ),
            Error::UnsupportedProtocol(p) => write!(
                f,
                "unsupported demo protocol {p} (this reader knows protocol 5, every Half-Life since 1.1, and protocol 4, Half-Life 1.0.0.5)"
            ),
            Error::LayoutMismatch { stated, layout } => write!(
                f,
                "corrupt header: it states demo protocol {stated}, but its directory is where protocol {layout} puts it"
            ),
            Error::BadSegmentCount(n) => write!(
                f,
                "corrupt directory: {n} segments (expected 1..={MAX_SEGMENTS})"
            ),
            Error::BadOffset { what, value, len } => write!(
                f,
                "corrupt {what}: offset {value} outside the file ({len} bytes)"
            ),
            Error::BadLength {
                what,
                value,
                max,
                at,
            } => write!(
                f,
                "corrupt {what} at byte {at}: {value} (expected 0..={max})"
            ),
            Error::UnknownFrameType { kind, protocol, at } => write!(
                f,
                "corrupt frame at byte {at}: unknown frame type {kind} for demo protocol {protocol}"
            ),
            Error::Truncated { what, at, len } => write!(
                f,
                "truncated at byte {at} (reading {what}, the file has {len} bytes)"
            ),
            Error::Io(e) => f.write_str(e),
        }
    }
}

impl std::error::Error for Error {}

/// The file's header.
#[derive(Debug, Clone, PartialEq)]
pub struct Header {
    /// 5 (Half-Life 1.1 and later) or 4 (Half-Life 1.0.0.5).
    pub demo_protocol: i32,
    /// The game's network protocol (48 for Steam Half-Life, 35 for 1.0.0.5).
    pub net_protocol: i32,
    /// The map's name without folder and extension (`c1a0`).
    pub map_name: String,
    /// The game folder (`valve`, `cstrike`).
    pub game_dir: String,
    /// The engine's checksum of the map (0 when the recording client did not set it).
    pub map_crc: u32,
    pub directory_offset: usize,
}

/// One directory entry and its frames.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// 0 for the connection (`LOADING`), 1 for playback.
    pub kind: i32,
    pub description: String,
    pub flags: i32,
    pub cd_track: i32,
    /// Seconds, as the directory records them.
    pub track_time: f32,
    /// Frame count as the directory records it (the engine's client frames).
    pub frame_count: i32,
    pub offset: usize,
    pub length: usize,
    pub frames: Vec<Frame>,
}

impl Segment {
    /// A segment of the game itself (not the connection's `LOADING`).
    pub fn is_playback(&self) -> bool {
        self.kind != 0
    }
}

/// A whole demo file.
#[derive(Debug, Clone, PartialEq)]
pub struct Demo {
    pub header: Header,
    pub segments: Vec<Segment>,
}

impl Demo {
    /// Parses a demo held in memory.
    pub fn parse(bytes: &[u8]) -> Result<Demo, Error> {
        let mut c = Cursor::new(bytes, 0);
        let magic: [u8; 8] = c.take(8, "magic")?.try_into().unwrap_or([0; 8]);
        if &magic != MAGIC {
            // "HLDEMO" with other padding is still a demo header.
            if magic[..6] != MAGIC[..6] {
                return Err(Error::BadMagic(magic));
            }
        }
        let demo_protocol = c.i32("demo protocol")?;
        // Protocol 4 (Half-Life 1.0.0.5) has 128-byte name fields, protocol 5 260-byte ones.
        let name_len = match demo_protocol {
            5 => 260,
            4 => 128,
            p => return Err(Error::UnsupportedProtocol(p)),
        };
        let net_protocol = c.i32("network protocol")?;
        let map_name = c.string(name_len, "map name")?;
        let game_dir = c.string(name_len, "game folder")?;
        let map_crc = c.u32("map checksum")?;
        let dir = c.i32("directory offset")?;
        let header_end = c.at;
        let valid = |dir: i32| dir >= header_end as i32 && (dir as usize) < bytes.len();
        if !valid(dir) {
            // A file whose protocol field is corrupt: its directory offset sits where the
            // other protocol's header puts it (byte 540 after 260-byte name fields in
            // protocol 5, byte 276 after 128-byte ones in protocol 4).
            let (other, slot) = if demo_protocol == 4 {
                (5, 540)
            } else {
                (4, 276)
            };
            if let Some(b) = bytes.get(slot..slot + 4) {
                let d = i32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                if d >= slot as i32 + 4 && (d as usize) < bytes.len() {
                    return Err(Error::LayoutMismatch {
                        stated: demo_protocol,
                        layout: other,
                    });
                }
            }
        }
        if !valid(dir) {
            return Err(Error::BadOffset {
                what: "directory",
                value: dir as i64,
                len: bytes.len(),
            });
        }
        let header = Header {
            demo_protocol,
            net_protocol,
            map_name: map_name.trim_start_matches("maps/").to_string(),
            game_dir,
            map_crc,
            directory_offset: dir as usize,
        };
        let mut d = Cursor::new(bytes, header.directory_offset);
        let n = d.i32("directory entry count")?;
        if !(1..=MAX_SEGMENTS as i32).contains(&n) {
            return Err(Error::BadSegmentCount(n));
        }
        const ENTRY: usize = 92;
        if (n as usize) * ENTRY > bytes.len() - d.at {
            return Err(Error::Truncated {
                what: "directory entries",
                at: d.at,
                len: bytes.len(),
            });
        }
        let mut segments = Vec::with_capacity(n as usize);
        for _ in 0..n {
            let kind = d.i32("segment type")?;
            let description = d.string(64, "segment description")?;
            let flags = d.i32("segment flags")?;
            let cd_track = d.i32("segment CD track")?;
            let track_time = d.f32("segment time")?;
            let frame_count = d.i32("segment frame count")?;
            let offset = d.i32("segment offset")?;
            let length = d.i32("segment length")?;
            if offset < header_end as i32 || offset as usize >= bytes.len() {
                return Err(Error::BadOffset {
                    what: "segment start",
                    value: offset as i64,
                    len: bytes.len(),
                });
            }
            if length < 0 {
                return Err(Error::BadLength {
                    what: "segment length",
                    value: length as i64,
                    max: bytes.len(),
                    at: d.at - 4,
                });
            }
            let frames = frames::read_segment(bytes, offset as usize, demo_protocol)?;
            segments.push(Segment {
                kind,
                description,
                flags,
                cd_track,
                track_time,
                frame_count,
                offset: offset as usize,
                length: length as usize,
                frames,
            });
        }
        Ok(Demo { header, segments })
    }

    /// Reads and parses a file; errors name the file.
    pub fn open(path: &Path) -> Result<Demo, Error> {
        let bytes =
            std::fs::read(path).map_err(|e| Error::Io(format!("{}: {e}", path.display())))?;
        Demo::parse(&bytes)
    }

    /// Seconds of play: the playback segments' recorded times (their frames' time span
    /// where the directory records none).
    pub fn duration(&self) -> f64 {
        self.segments
            .iter()
            .filter(|s| s.is_playback())
            .map(|s| {
                let recorded = s.track_time as f64;
                if recorded.is_finite() && recorded > 0.0 {
                    recorded
                } else {
                    let times = || s.frames.iter().map(|f| f.time as f64);
                    let lo = times().fold(f64::INFINITY, f64::min);
                    let hi = times().fold(f64::NEG_INFINITY, f64::max);
                    if hi > lo { hi - lo } else { 0.0 }
                }
            })
            .fold(0.0, |a, b| a + b)
    }

    /// Frames of every segment.
    pub fn frame_count(&self) -> usize {
        self.segments.iter().map(|s| s.frames.len()).sum()
    }

    /// The playback segments' client frames as the directory counts them.
    pub fn client_frames(&self) -> usize {
        self.segments
            .iter()
            .filter(|s| s.is_playback())
            .map(|s| s.frame_count.max(0) as usize)
            .sum()
    }

    /// The recorded player's motion, one entry per client frame of the playback
    /// segments, in time order (see [`PlayerFrame`]).
    pub fn player(&self) -> Vec<PlayerFrame> {
        player::frames(self)
    }
}

#[cfg(test)]
mod tests;
