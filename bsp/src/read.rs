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

impl crate::BspVersion {
    /// The format a file's first bytes name, without reading further (`None`: not a
    /// format we read).
    ///
    /// ```
    /// use bsp::{BspVersion, Game};
    /// let v = BspVersion::identify(b"IBSP\x2e\0\0\0").unwrap();
    /// assert_eq!((v, v.game()), (BspVersion::Quake3, Game::Quake3));
    /// assert_eq!(BspVersion::identify(&[30, 0, 0, 0, 124, 0, 0, 0]), Some(BspVersion::GoldSrc30));
    /// assert_eq!(BspVersion::identify(b"VBSP\x14\0\0\0"), None);
    /// ```
    pub fn identify(bytes: &[u8]) -> Option<crate::BspVersion> {
        use crate::BspVersion as V;
        match magic(bytes) {
            Magic::Quake2 if bytes.starts_with(b"QBSP") => Some(V::Quake2Qbism),
            Magic::Quake2 => Some(V::Quake2),
            Magic::Quake3 => Some(V::Quake3),
            Magic::QuakeFamily => match bytes.get(0..4)? {
                b"BSP2" => Some(V::Bsp2),
                b"2PSB" => Some(V::Bsp2psb),
                h => match i32::from_le_bytes([h[0], h[1], h[2], h[3]]) {
                    29 => Some(V::Bsp29),
                    30 => Some(V::GoldSrc30),
                    _ => None,
                },
            },
            Magic::Unsupported(_) | Magic::Unknown => None,
        }
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
