//! Errors of BSP reading: every one names the lump and the problem, so a build log
//! tells the user which part of which file is broken.

use std::fmt;

/// Why a BSP file could not be read.
#[derive(Debug)]
pub enum BspError {
    /// The file could not be opened or mapped.
    Io(std::io::Error),
    /// The file is shorter than its header.
    TooShort { len: usize, need: usize },
    /// The first bytes name no BSP version we read.
    UnknownVersion { found: String },
    /// A BSP format we recognise but do not read (yet).
    Unsupported { format: &'static str },
    /// A lump's directory entry points outside the file.
    LumpOutOfBounds {
        lump: &'static str,
        offset: i64,
        length: i64,
        file_len: usize,
    },
    /// A lump's length is not a multiple of its record size.
    LumpSize {
        lump: &'static str,
        length: usize,
        record: usize,
    },
    /// A record refers to an element that does not exist.
    BadIndex {
        lump: &'static str,
        record: usize,
        field: &'static str,
        value: i64,
        limit: usize,
    },
    /// A lump's content is malformed in some other way.
    Malformed { lump: &'static str, reason: String },
}

impl fmt::Display for BspError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BspError::Io(e) => write!(f, "{e}"),
            BspError::TooShort { len, need } => {
                write!(
                    f,
                    "file is {len} bytes, shorter than a BSP header ({need} bytes)"
                )
            }
            BspError::Unsupported { format } => write!(
                f,
                "{format} is not read yet (we read GoldSrc v30, Quake BSP29, BSP2, 2PSB, Quake 2 IBSP/QBSP 38 and Quake 3 IBSP 46)"
            ),
            BspError::UnknownVersion { found } => write!(
                f,
                "not a BSP file we read: version {found} (expected 29, 30, BSP2 or 2PSB)"
            ),
            BspError::LumpOutOfBounds {
                lump,
                offset,
                length,
                file_len,
            } => write!(
                f,
                "lump {lump}: offset {offset} length {length} lies outside the file ({file_len} bytes); the file is truncated or corrupt"
            ),
            BspError::LumpSize {
                lump,
                length,
                record,
            } => write!(
                f,
                "lump {lump}: length {length} is not a multiple of the record size {record}"
            ),
            BspError::BadIndex {
                lump,
                record,
                field,
                value,
                limit,
            } => write!(
                f,
                "lump {lump}: record {record} has {field} = {value}, out of range (0..{limit})"
            ),
            BspError::Malformed { lump, reason } => write!(f, "lump {lump}: {reason}"),
        }
    }
}

impl std::error::Error for BspError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            BspError::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<std::io::Error> for BspError {
    fn from(e: std::io::Error) -> Self {
        BspError::Io(e)
    }
}
