//! The one dispatch on a file's first bytes: which format it is, and which folder's
//! reader turns it into a [`Bsp`]. Formats we know but do not read are named in the
//! error, so a user learns what the file is.

use crate::error::BspError;
use crate::goldsrc;
use crate::map::Bsp;

/// What the first bytes of a file say it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Magic {
    /// Read by [`goldsrc`]: Quake BSP29, GoldSrc v30, BSP2, 2PSB.
    QuakeFamily,
    /// Read by [`crate::quake2`]: IBSP 38, QBSP 38.
    Quake2,
    /// Read by [`crate::quake3`]: IBSP 46.
    Quake3,
    /// A BSP format we recognise but do not read: its name for the error.
    Unsupported(&'static str),
    Unknown,
}

pub(crate) fn magic(bytes: &[u8]) -> Magic {
    let Some(head) = bytes.get(0..8) else {
        return match bytes.get(0..4) {
            Some(b"BSP2" | b"2PSB") => Magic::QuakeFamily,
            _ => Magic::Unknown,
        };
    };
    let version = i32::from_le_bytes([head[4], head[5], head[6], head[7]]);
    match (&head[0..4], version) {
        (b"BSP2" | b"2PSB", _) => Magic::QuakeFamily,
        (b"IBSP" | b"QBSP", 38) => Magic::Quake2,
        (b"IBSP", 46) => Magic::Quake3,
        (b"IBSP", 47) => Magic::Unsupported("Quake Live / Wolfenstein: ET BSP (IBSP 47)"),
        (b"RBSP", _) => Magic::Unsupported("Raven BSP (RBSP: Jedi Knight, Soldier of Fortune 2)"),
        (b"VBSP", _) => Magic::Unsupported("Source BSP (VBSP)"),
        (b"FBSP", _) => Magic::Unsupported("Quake 3 Team Arena / QFusion BSP (FBSP)"),
        _ => match i32::from_le_bytes([head[0], head[1], head[2], head[3]]) {
            29 | 30 => Magic::QuakeFamily,
            _ => Magic::Unknown,
        },
    }
}

pub(crate) fn parse(bytes: &[u8]) -> Result<Bsp, BspError> {
    match magic(bytes) {
        Magic::Unsupported(format) => Err(BspError::Unsupported { format }),
        Magic::Quake2 => crate::quake2::parse(bytes),
        Magic::Quake3 => crate::quake3::parse(bytes),
        // The Quake family reader also reports short and unknown files.
        Magic::QuakeFamily | Magic::Unknown => goldsrc::parse(bytes),
    }
}
