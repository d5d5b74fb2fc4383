//! Every setting of a compile, declared once: its default ([`defaults`], which the
//! command line, [`CompileOptions::new`] and the stages' own option types all use), its
//! meaning (the field's documentation; the command line's help says the same in
//! short) and the metadata key the `.vdg` records it under ([`recorded_options`]).

use crate::reduce::ReductionCost;
use crate::sample::SampleOptions;
use std::path::{Path, PathBuf};

/// The defaults of the compile options.
pub mod defaults {
    use crate::reduce::ReductionCost;

    /// `-sd`: the sample spacing m; every point of a wall lies within m of a sample.
    pub const SAMPLE_SPACING: f64 = 24.0;
    /// `-ms`: the cap on the number of samples (the spacing is raised until it holds).
    pub const MAX_SAMPLES: usize = 250_000;
    /// Sky faces are sampled at this multiple of the spacing: the sky is a wall the
    /// camera must not cross, but nothing looks along it.
    pub const SKY_FACTOR: f64 = 2.0;
    /// `-rl`: stop reducing at this fraction of the vertices.
    pub const REDUCTION_LIMIT: f64 = 0.025;
    /// `-rv`: small maps keep at least this many vertices. A fraction made for maps of
    /// thousands of vertices would leave a small map a few dozen, too few to see
    /// across its rooms; a Half-Life or Quake map reduces to more than this anyway.
    pub const REDUCTION_FLOOR: usize = 1000;
    /// `-rc`: the relative cost (volume / clearance²) removes the small vertices
    /// along the walls last, where sight lines along them run.
    pub const REDUCTION_COST: ReductionCost = ReductionCost::Relative;
    /// `-md`: Voronoi vertices with less clearance are dropped before the reduction.
    /// 16, not the thesis' 20: a passage a player fits through crouching (a vent, a
    /// crawl space, a 40-unit drop hole) has about 16–20 units at its middle, and at
    /// 20 the graph lost it, and the camera its way to a player inside.
    pub const MIN_CLEARANCE: f64 = 16.0;
    /// `-bb`: the smallest leaf box of the `.vdg`'s face tree (the runtime's own
    /// default, so a graph built without the compiler gets the same tree).
    pub const TREE_LEAF_SIZE: f64 = vdgformat::DEFAULT_LEAF_SIZE as f64;
}

/// The pipeline's stages, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    Samples,
    Delaunay,
    Voronoi,
    Reduce,
}

impl Stage {
    pub fn name(self) -> &'static str {
        match self {
            Stage::Samples => "samples",
            Stage::Delaunay => "delaunay",
            Stage::Voronoi => "voronoi",
            Stage::Reduce => "reduce",
        }
    }
}

/// Format of the `-savesamples` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SamplesFormat {
    /// One `x y z` line per sample.
    #[default]
    Xyz,
    /// qhull's input format: `3`, the count, then `x y z` lines.
    Qhull,
}

/// Everything that steers a compile.
#[derive(Debug, Clone)]
pub struct CompileOptions {
    pub sampling: SampleOptions,
    /// `-rl`: stop reducing at this fraction of the vertices.
    pub reduction_limit: f64,
    /// `-rv`: never reduce below this many vertices (see
    /// [`crate::reduce::ReduceOptions::min_vertices`]).
    pub reduction_floor: usize,
    /// `-rc`: what a removal costs (see [`ReductionCost`]).
    pub reduction_cost: ReductionCost,
    /// `-md`: vertices with less clearance are removed before reduction.
    pub min_clearance: f64,
    /// `-bb`: the smallest leaf box of the face tree.
    pub tree_leaf_size: f64,
    pub liquids_are_solid: bool,
    /// Player and monster clip brushes are walls (`--clip-solid`).
    pub clip_is_solid: bool,
    /// Brush entity classnames whose models are walls too.
    pub entity_classes: Vec<String>,
    pub save_samples: bool,
    pub samples_format: SamplesFormat,
    pub stop_after: Stage,
    /// Where the `.vdg` goes; other outputs go beside it.
    pub output: PathBuf,
    /// The source name recorded in the `.vdg` (`--source-name`); by default none, so
    /// the output does not depend on the map file's name.
    pub source_name: Option<String>,
    /// Raise the clearances towards the walls and each face's corners after the
    /// reduction (on by default). Off (`--no-wall-raise`), the graph keeps the
    /// reduction's own raise back towards the unreduced graph, whose volume then
    /// contains the reduced one (condition A): what the reduction's tests check on
    /// the written file. Recorded in the `.vdg` when off.
    pub wall_raise: bool,
    /// The reduction's coverage guards: the kept player places and the seam phase's
    /// deep points (on by default). Off (`--no-coverage-guards`) is a measurement
    /// switch that shows whether the reduction stops above `-rl` because of them;
    /// never for graphs you ship. Recorded in the `.vdg` when off.
    pub coverage_guards: bool,
    /// `--game`: read a Quake-family map as this game's (GoldSrc or Quake) whatever the
    /// map itself says (see [`bsp::game`]); `None` lets the map decide.
    pub game: Option<bsp::Game>,
    /// `--budget`: the scale of each map's time and memory budget (see
    /// [`crate::pipeline::Budget`]); 0 gives no budget.
    pub budget: f64,
}

impl CompileOptions {
    /// The command line's defaults ([`defaults`]), writing to `output`.
    pub fn new(output: PathBuf) -> CompileOptions {
        CompileOptions {
            sampling: SampleOptions::default(),
            reduction_limit: defaults::REDUCTION_LIMIT,
            reduction_floor: defaults::REDUCTION_FLOOR,
            reduction_cost: defaults::REDUCTION_COST,
            min_clearance: defaults::MIN_CLEARANCE,
            tree_leaf_size: defaults::TREE_LEAF_SIZE,
            liquids_are_solid: false,
            clip_is_solid: false,
            entity_classes: Vec::new(),
            save_samples: false,
            samples_format: SamplesFormat::Xyz,
            stop_after: Stage::Reduce,
            output,
            source_name: None,
            wall_raise: true,
            coverage_guards: true,
            game: None,
            budget: 1.0,
        }
    }
}

/// The build identity: a hash of the source that shapes a graph (see `build.rs`),
/// recorded in every `.vdg` as `tool.build` and shown by `--version`, so the
/// up-to-date skip and the bake caches rebuild after the compiler changed.
pub const BUILD: &str = env!("BSP2VDG_BUILD");

/// The metadata entries written into the `.vdg` besides the source hash: the tool, the
/// options that shape the graph and, when asked, the source name. Both the writer and
/// the up-to-date check use this one list, so they cannot disagree.
///
/// ```
/// use bsp2vdg::options::{CompileOptions, recorded_options};
/// let o = CompileOptions::new("out.vdg".into());
/// let rec = recorded_options(&o);
/// assert!(rec.iter().any(|(k, v)| k == "sd" && v == "24"));
/// assert!(rec.iter().all(|(k, _)| k != "source.name"));
/// ```
pub fn recorded_options(options: &CompileOptions) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = [
        ("tool.name", "bsp2vdg".to_string()),
        ("tool.version", env!("CARGO_PKG_VERSION").to_string()),
        ("tool.build", BUILD.to_string()),
        ("sd", options.sampling.spacing.to_string()),
        ("ms", options.sampling.max_samples.to_string()),
        ("rl", options.reduction_limit.to_string()),
        ("rv", options.reduction_floor.to_string()),
        ("rc", options.reduction_cost.as_str().to_string()),
        ("md", options.min_clearance.to_string()),
        ("bb", options.tree_leaf_size.to_string()),
        ("subset", options.sampling.subset.to_string()),
        ("liquids_solid", options.liquids_are_solid.to_string()),
        ("clip_solid", options.clip_is_solid.to_string()),
        ("entities", options.entity_classes.join(",")),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    // Switches that only measurements turn off are recorded only then, so that every
    // default graph keeps the same bytes.
    if !options.wall_raise {
        v.push(("wall_raise".to_string(), "false".to_string()));
    }
    if !options.coverage_guards {
        v.push(("coverage_guards".to_string(), "false".to_string()));
    }
    // A forced game shapes the graph (the player's body); the map's own is not recorded.
    if let Some(game) = options.game {
        v.push(("game".to_string(), game.name().to_string()));
    }
    if let Some(name) = &options.source_name {
        v.push(("source.name".to_string(), name.clone()));
    }
    v
}

/// `out/map.vdg` → `out/map.samples.txt`.
pub fn samples_path(output: &Path) -> PathBuf {
    output.with_extension("samples.txt")
}
