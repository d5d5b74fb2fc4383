//! `flowtile-bake region`: a tiling spec from a map's walkable floor at one
//! level, with its top view and optional pictures of the designed flow.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::json;

use flowtile_bake::bake::{BakedTiling, write_atomic};
use flowtile_bake::region::{Floors, Region, RegionOptions};
use flowtile_bake::rng::Rng;
use flowtile_bake::runtime::KeyBlend;
use flowtile_bake::spec::Problem;
use flowtile_bake::tiling::Tiling;
use flowtile_bake::world::{
    AnimationOptions, Flow, PictureOptions, WorldField, animate_gif, streamlines,
};

// The options of `flowtile-bake region`; its help text is the doc comment of
// `Command::Region` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The map (GoldSrc or Quake BSP).
    pub map: PathBuf,
    /// Floor height of the level (default: the floor under the spawns).
    #[arg(long, allow_hyphen_values = true)]
    pub floor: Option<f64>,
    /// Floors from the areas of this bot navigation mesh (Counter-Strike .nav,
    /// v1-5) instead of the map's hulls.
    #[arg(long)]
    pub nav: Option<PathBuf>,
    /// Slot side in world units.
    #[arg(long, default_value_t = 64.0)]
    pub tile: f64,
    /// Floors within this height of the level belong to it.
    #[arg(long, default_value_t = 48.0)]
    pub band: f64,
    /// Entity class names that are flow sources (repeatable).
    #[arg(long = "from")]
    pub from: Vec<String>,
    /// Entity class names that are flow sinks (repeatable).
    #[arg(long = "to")]
    pub to: Vec<String>,
    /// Spec (TOML) to write; the map's top view under the grid (for
    /// `edit`) goes beside it as NAME.top.png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Top-view picture (PNG) of the region over the map.
    #[arg(long)]
    pub picture: Option<PathBuf>,
    /// Also tile the spec and draw its streamlines over the map's top view (PNG).
    #[arg(long)]
    pub flow_picture: Option<PathBuf>,
    /// Also tile 4 keys of the spec and animate particles over the map (GIF).
    #[arg(long)]
    pub flow_gif: Option<PathBuf>,
    /// Seed written into the spec.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Print statistics as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `flowtile-bake region`: the map and its nav mesh read, the flow's
/// ends chosen, the region extracted, the spec and pictures written, the
/// statistics printed.
pub fn run(a: Args) -> Result<()> {
    let t0 = Instant::now();
    let map = a.map.as_path();
    let bsp = bsp::Bsp::open(map).with_context(|| format!("{}", map.display()))?;
    let nav = match a.nav.as_deref() {
        Some(p) => Some(open_nav(p, map)?),
        None => None,
    };
    let read_s = t0.elapsed().as_secs_f64();
    let (mut from, mut to) = (a.from, a.to);
    if from.is_empty() && to.is_empty() {
        default_ends(&bsp, &mut from, &mut to);
    }
    let opt = RegionOptions {
        floor: a.floor,
        tile: a.tile,
        band: a.band,
        sources: from,
        sinks: to,
        ..Default::default()
    };
    let name = map
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let t1 = Instant::now();
    let floors = match &nav {
        Some(mesh) => Floors::Nav(mesh),
        None => Floors::Hulls,
    };
    let region = flowtile_bake::region::extract_with(&bsp, floors, &name, &opt)
        .with_context(|| format!("{}", map.display()))?;
    let extract_s = t1.elapsed().as_secs_f64();
    let unconnected = region.unconnected();
    if let Some(line) = unconnected_warning(&unconnected, &region) {
        toolbox::errln!("{line}");
    }
    let problem = write_spec(&region, &a.output, a.picture.as_deref(), a.seed)?;
    let flows = [a.flow_picture.as_deref(), a.flow_gif.as_deref()];
    flow_pictures(&region, &problem, &name, a.seed, flows)?;
    let times = [read_s, extract_s];
    report(
        &region,
        &name,
        times,
        &a.output,
        a.picture.as_deref(),
        a.json,
    )
}

/// The warning for sources and sinks that the region's open slots do not connect, or
/// `None` when every one is connected.
fn unconnected_warning(u: &flowtile_bake::region::Unconnected, region: &Region) -> Option<String> {
    if u.is_empty() {
        return None;
    }
    let at = |p: &[f64; 3]| format!("({:.0} {:.0} {:.0})", p[0], p[1], p[2]);
    let mut parts = Vec::new();
    if let Some(p) = u.sources.first() {
        parts.push(format!(
            "{} of {} sources reach no sink through open slots (the first at {})",
            u.sources.len(),
            region.sources.len(),
            at(p)
        ));
    }
    if let Some(p) = u.sinks.first() {
        parts.push(format!(
            "{} of {} sinks are reached from no source (the first at {})",
            u.sinks.len(),
            region.sinks.len(),
            at(p)
        ));
    }
    Some(format!(
        "warning: {}: the region's sources and sinks are not connected; the flow there has no designed direction (a larger --band or a smaller --tile may join the parts)",
        parts.join("; ")
    ))
}

/// Reads the nav mesh, warning when it was made for another build of the map.
fn open_nav(p: &Path, map: &Path) -> Result<navmesh::NavMesh> {
    let mesh = navmesh::NavMesh::open(p).map_err(anyhow::Error::msg)?;
    let size = std::fs::metadata(map).map(|m| m.len()).unwrap_or(0);
    if mesh.bsp_size != 0 && u64::from(mesh.bsp_size) != size {
        toolbox::errln!(
            "warning: {} was made for a map of {} bytes, {} has {size} (an older build of the map?)",
            p.display(),
            mesh.bsp_size,
            map.display()
        );
    }
    Ok(mesh)
}

/// The flow's sources and sinks when none are given.
fn default_ends(bsp: &bsp::Bsp, from: &mut Vec<String>, to: &mut Vec<String>) {
    let has = |c: &str| bsp.entities.iter().any(|e| e.classname() == c);
    // Counter-Strike: terrorists (info_player_deathmatch) towards the
    // counter-terrorists (info_player_start); elsewhere away from the spawns.
    if has("info_player_deathmatch") && has("info_player_start") {
        from.push("info_player_deathmatch".into());
        to.push("info_player_start".into());
    } else {
        for c in [
            "info_player_start",
            "info_player_deathmatch",
            "info_player_coop",
        ] {
            if has(c) {
                from.push(c.into());
            }
        }
    }
}

/// Writes the spec (checked to be a completable problem first), the map's
/// top view beside it and the optional picture; returns the spec's problem.
fn write_spec(
    region: &Region,
    output: &Path,
    picture: Option<&Path>,
    seed: u64,
) -> Result<Problem> {
    // The map's top view beside the spec, for the editor's background.
    let top = output.with_extension("top.png");
    let top_name = top
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let spec = format!(
        "background = {}   # the map's top view under the grid in `flowtile-bake edit`\n{}",
        flowtile_bake::spec::toml_string(&top_name),
        region.to_spec_toml(seed)
    );
    // The spec must be a valid, completable problem before it is written.
    let problem = Problem::from_toml(&spec).context("internal: region spec does not parse")?;
    Tiling::new(
        problem.set.clone(),
        problem.width,
        problem.height,
        &problem.conditions,
    )
    .context("region spec")?;
    write_atomic(&top, &region.top_view_image(2)?.to_png()?)
        .with_context(|| format!("{}", top.display()))?;
    write_atomic(output, spec.as_bytes()).with_context(|| format!("{}", output.display()))?;
    if let Some(p) = picture {
        let c = region.picture(800)?;
        write_atomic(p, &c.to_png()?).with_context(|| format!("{}", p.display()))?;
    }
    Ok(problem)
}

/// With `--flow-picture` / `--flow-gif`: the spec tiled (one key, or four
/// for the animation) and its flow drawn over the map's top view.
fn flow_pictures(
    region: &Region,
    problem: &Problem,
    name: &str,
    seed: u64,
    [flow_png, flow_gif]: [Option<&Path>; 2],
) -> Result<()> {
    if flow_png.is_none() && flow_gif.is_none() {
        return Ok(());
    }
    let keys = (0..if flow_gif.is_some() { 4 } else { 1 })
        .map(|k| {
            let mut t = Tiling::new(
                problem.set.clone(),
                problem.width,
                problem.height,
                &problem.conditions,
            )?;
            t.random_fill_preferring(&mut Rng::new(seed + k), &problem.preferences)?;
            Ok(BakedTiling::from_tiling(&t)?)
        })
        .collect::<Result<Vec<_>>>()?;
    let mesh = region.mesh();
    let bg = |c: &mut flowtile_bake::render::Canvas, v: &flowtile_bake::world::View| {
        region.draw_top_view(c, v)
    };
    let opt = PictureOptions {
        width: 800,
        particles: 1500,
        seed,
        title: format!("{name}: designed flow at floor z {:.0}", region.floor),
        units: "units".into(),
    };
    if let Some(p) = flow_png {
        let field = WorldField::new(&mesh, Flow::Steady(keys[0].clone()))?;
        let c = streamlines(&field, &opt, 0.0, Some(&bg))?;
        write_atomic(p, &c.to_png()?).with_context(|| format!("{}", p.display()))?;
    }
    if let Some(p) = flow_gif {
        let field = WorldField::new(&mesh, Flow::Keys(KeyBlend::new(keys, 2.0)?))?;
        let opt = PictureOptions { width: 480, ..opt };
        let anim = AnimationOptions {
            frames: 48,
            dt: 0.1,
            delay: 6,
        };
        let mut bytes = Vec::new();
        animate_gif(&field, &opt, &anim, Some(&bg), &mut bytes)?;
        write_atomic(p, &bytes).with_context(|| format!("{}", p.display()))?;
    }
    Ok(())
}

/// Prints the region's statistics (JSON, or one line); `times` are the
/// seconds of reading the map and of extracting the region.
fn report(
    region: &Region,
    name: &str,
    [read_s, extract_s]: [f64; 2],
    output: &Path,
    picture: Option<&Path>,
    json: bool,
) -> Result<()> {
    let stats = json!({
        "map": name,
        "floor": region.floor,
        "band": region.band,
        "tile": region.tile,
        "width": region.width,
        "height": region.height,
        "open_slots": region.open_slots(),
        "floors_from": region.floors_from,
        "sources": region.sources.len(),
        "sinks": region.sinks.len(),
        "unconnected_sources": region.unconnected().sources.len(),
        "unconnected_sinks": region.unconnected().sinks.len(),
        "read_seconds": read_s,
        "extract_seconds": extract_s,
        "output": output.display().to_string(),
    });
    if json {
        outln!("{stats}")?;
    } else {
        outln!(
            "{name}: floor z {:.1} ± {}, {}x{} slots of {} units, {} open; {} sources, {} sinks; read {:.3} s, region {:.3} s; wrote {}{}",
            region.floor,
            region.band,
            region.width,
            region.height,
            region.tile,
            region.open_slots(),
            region.sources.len(),
            region.sinks.len(),
            read_s,
            extract_s,
            output.display(),
            picture
                .map(|p| format!(" and {}", p.display()))
                .unwrap_or_default()
        )?;
    }
    Ok(())
}
