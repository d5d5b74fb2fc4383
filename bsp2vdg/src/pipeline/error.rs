//! Why a compile failed, in words for the log and the `.err` file.

use crate::options::Stage;
use bsp::BspError;
use std::fmt;
use std::path::{Path, PathBuf};

/// Why a compile failed.
#[derive(Debug)]
pub enum CompileError {
    Bsp {
        path: PathBuf,
        error: BspError,
    },
    Write {
        path: PathBuf,
        error: std::io::Error,
    },
    Delaunay(crate::delaunay::DelaunayError),
    /// Too few samples: the map has (almost) no walls around free space.
    NoFreeSpace {
        samples: usize,
        pointfile: Option<Pointfile>,
    },
    Vdg {
        path: PathBuf,
        error: String,
    },
    NotBuilt(Stage),
    /// A BSP of an engine whose format this version does not read.
    OtherFormat {
        path: PathBuf,
        format: String,
    },
    /// So many of the world's faces are unusable that a graph could not be trusted.
    UnusableFaces {
        unusable: usize,
        world_faces: usize,
        examples: String,
    },
    /// `--game` names a game the map's format cannot be read as.
    Game(String),
    /// A stage went over the map's time or memory budget.
    OverBudget {
        stage: &'static str,
        what: String,
    },
    /// No vertex (or no face) survived: nothing to write.
    EmptyGraph {
        min_clearance: f64,
        pointfile: Option<Pointfile>,
    },
}

/// The pointfile a failed compile wrote for the editor (see [`super::pointfiles`]), or
/// why it could not.
#[derive(Debug)]
pub struct Pointfile {
    pub path: PathBuf,
    /// What its points are ("the player starts").
    pub shows: &'static str,
    /// The write's error, if it failed.
    pub error: Option<String>,
}

impl fmt::Display for Pointfile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.error {
            None => write!(
                f,
                "; pointfile {} shows {} (load it in the editor)",
                self.path.display(),
                self.shows
            ),
            Some(e) => write!(
                f,
                "; cannot write the pointfile {}: {e}",
                self.path.display()
            ),
        }
    }
}

/// A pointfile's text in an error: empty when there is none.
fn pointfile_text(p: &Option<Pointfile>) -> String {
    p.as_ref().map(|p| p.to_string()).unwrap_or_default()
}

impl fmt::Display for CompileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CompileError::Bsp { path, error } => write!(f, "{}: {error}", path.display()),
            CompileError::Write { path, error } => {
                write!(f, "cannot write {}: {error}", path.display())
            }
            CompileError::Delaunay(e) => write!(f, "Delaunay stage: {e}"),
            CompileError::NoFreeSpace { samples, pointfile } => write!(
                f,
                "the map has no walls around free space to build a graph from ({samples} samples; is it sealed, with no empty leaves?){}",
                pointfile_text(pointfile)
            ),
            CompileError::Vdg { path, error } => {
                write!(f, "cannot write {}: {error}", path.display())
            }
            CompileError::OtherFormat { path, format } => write!(
                f,
                "{}: {format}, which bsp2vdg does not read (it reads GoldSrc BSP v30, Quake BSP29, BSP2 and 2PSB, Quake 2 IBSP/QBSP 38 and Quake 3 IBSP 46 maps)",
                path.display()
            ),
            CompileError::EmptyGraph {
                min_clearance,
                pointfile,
            } => write!(
                f,
                "the graph is empty: no free space with at least -md {min_clearance} units of clearance survived (is the map sealed, or -md too large?); nothing written{}",
                pointfile_text(pointfile)
            ),
            CompileError::UnusableFaces {
                unusable,
                world_faces,
                examples,
            } => write!(
                f,
                "{unusable} of the world's {world_faces} faces are unusable (their plane, texture or edges do not resolve: {examples}); more than half, so a graph of this map could not be trusted"
            ),
            CompileError::Game(why) => write!(f, "--game: {why}"),
            CompileError::OverBudget { stage, what } => write!(
                f,
                "the {stage} stage went over the map's budget ({what}); --budget scales it, --budget 0 lifts it"
            ),
            CompileError::NotBuilt(stage) => write!(
                f,
                "the {} stage is not built yet in this version",
                stage.name(),
            ),
        }
    }
}

impl std::error::Error for CompileError {}

/// Names the engine of a BSP file the reader refused, from its magic and version, so the
/// user learns "a Quake 3 map" rather than a number.
pub fn other_format(map: &Path) -> Option<String> {
    use std::io::Read;
    let mut head = [0u8; 8];
    std::fs::File::open(map).ok()?.read_exact(&mut head).ok()?;
    let version = i32::from_le_bytes([head[4], head[5], head[6], head[7]]);
    let engine = match (&head[..4], version) {
        (b"IBSP", 38) => "a Quake 2 map",
        (b"IBSP", 46) => "a Quake 3 map",
        (b"IBSP", 47) => "a Quake Live map",
        (b"IBSP", _) => "an id Tech 2/3 map",
        (b"VBSP", _) => "a Source engine map",
        (b"RBSP", _) => "a Raven map (Jedi Knight, Soldier of Fortune 2)",
        (b"FBSP", _) => "a QFusion map (Warsow)",
        (b"QBSP", _) => "a Qfusion/Quake 2 extended map",
        (b"EF2!", _) => "a Star Trek: Elite Force 2 map",
        (b"FAKK", _) => "a Heavy Metal: F.A.K.K. 2 map",
        (b"2PSB", _) | (b"BSP2", _) => return None,
        _ => return None,
    };
    Some(format!(
        "{engine} ({} version {version})",
        String::from_utf8_lossy(&head[..4])
    ))
}
