//! Why a graph cannot be built or written.

use std::fmt;
use std::path::PathBuf;

/// Why a [`VdgBuilder`](crate::VdgBuilder) cannot produce a file.
#[derive(Debug, Clone, PartialEq)]
pub enum BuildError {
    /// A vertex position or clearance is NaN or infinite.
    NonFiniteVertex { vertex: u32 },
    /// A vertex has a negative clearance.
    NegativeClearance { vertex: u32, clearance: f32 },
    /// A face refers to a vertex that does not exist.
    FaceIndexOutOfRange {
        face: u32,
        vertex: u32,
        vertex_count: u32,
    },
    /// A face uses the same vertex twice (thesis 3.7 forbids it).
    DegenerateFace { face: u32 },
    /// A face's own corner radius is not finite or below its vertex's clearance.
    BadCornerRadius { face: u32, corner: u8, radius: f32 },
    /// `-bb` must be finite and positive.
    BadLeafSize(f32),
    /// Metadata keys are non-empty `[A-Za-z0-9._-]` words.
    BadMetadataKey(String),
    /// Metadata values are one line (no `\n` or `\r`).
    BadMetadataValue { key: String },
    /// More vertices, faces or tree entries than 32-bit indices can address.
    TooLarge(&'static str),
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BuildError::NonFiniteVertex { vertex } => {
                write!(f, "vertex {vertex} has a non-finite position or clearance")
            }
            BuildError::NegativeClearance { vertex, clearance } => {
                write!(f, "vertex {vertex} has negative clearance {clearance}")
            }
            BuildError::FaceIndexOutOfRange {
                face,
                vertex,
                vertex_count,
            } => write!(
                f,
                "face {face} refers to vertex {vertex}, but there are only {vertex_count} vertices"
            ),
            BuildError::BadCornerRadius {
                face,
                corner,
                radius,
            } => write!(
                f,
                "corner {corner} of face {face} has radius {radius}: it must be finite and at least its vertex's clearance"
            ),
            BuildError::DegenerateFace { face } => {
                write!(f, "face {face} uses the same vertex twice")
            }
            BuildError::BadLeafSize(bb) => {
                write!(f, "tree leaf size (-bb) must be finite and > 0, got {bb}")
            }
            BuildError::BadMetadataKey(k) => write!(
                f,
                "metadata key {k:?} is not a non-empty word of [A-Za-z0-9._-]"
            ),
            BuildError::BadMetadataValue { key } => {
                write!(f, "metadata value of {key:?} contains a line break")
            }
            BuildError::TooLarge(what) => write!(f, "too many {what} for 32-bit indices"),
        }
    }
}

impl std::error::Error for BuildError {}

/// Why [`VdgBuilder::write_atomic`](crate::VdgBuilder::write_atomic) failed. No partial file is left behind.
#[derive(Debug)]
pub enum WriteError {
    /// The graph itself is invalid.
    Build(BuildError),
    /// Creating, writing, syncing or renaming the file failed.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
}

impl fmt::Display for WriteError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WriteError::Build(e) => write!(f, "cannot build .vdg: {e}"),
            WriteError::Io { path, source } => {
                write!(f, "cannot write {}: {source}", path.display())
            }
        }
    }
}

impl std::error::Error for WriteError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            WriteError::Build(e) => Some(e),
            WriteError::Io { source, .. } => Some(source),
        }
    }
}

impl From<BuildError> for WriteError {
    fn from(e: BuildError) -> Self {
        WriteError::Build(e)
    }
}
