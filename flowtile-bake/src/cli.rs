//! Command-line interface (binary only; errors are `anyhow`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand, ValueEnum};
use serde_json::json;

use flowtile_bake::bake::BakedTiling;
use flowtile_bake::render::{RenderOptions, Style, render_to_file};
use flowtile_bake::rng::Rng;
use flowtile_bake::runtime::KeyBlend;
use flowtile_bake::spec::Problem;
use flowtile_bake::stats;
use flowtile_bake::tileset::TileSet;
use flowtile_bake::tiling::{Border, Conditions, Tiling};
use flowtile_bake::world::{
    AnimationOptions, Flow, Mesh, PictureOptions, WorldField, animate_gif, streamlines,
};

#[derive(Parser, Debug)]
#[command(
    name = "flowtile-bake",
    version,
    about = "Flow tiles: divergence-free flow fields from tiles"
)]
struct Args {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Print the number of tiles in an (M_x, M_y, c) set.
    Count {
        /// Flux options on vertical edges.
        #[arg(long)]
        mx: u32,
        /// Flux options on horizontal edges.
        #[arg(long)]
        my: u32,
        /// Corner velocity options.
        #[arg(long, default_value_t = 1)]
        corners: usize,
        /// Also print the number of rotational symmetry classes.
        #[arg(long)]
        classes: bool,
    },
    /// Tile a grid (from a spec file, or --grid/--set) and bake it.
    Tile {
        /// Spec file (TOML); see testdata/flowtiles/.
        spec: Option<PathBuf>,
        /// Baked tiling to write.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Grid size WxH (without a spec file).
        #[arg(long)]
        grid: Option<String>,
        /// Tile set MX,MY,C (without a spec file).
        #[arg(long, default_value = "5,5,1")]
        set: String,
        /// Tile resolution in cells (without a spec file).
        #[arg(long, default_value_t = 8)]
        n: usize,
        /// Outer borders (without a spec file).
        #[arg(long, value_enum, default_value_t = BorderArg::Free)]
        border: BorderArg,
        /// Random seed (overrides the spec's).
        #[arg(long)]
        seed: Option<u64>,
        /// Fill slots with a single option before the random fill.
        #[arg(long)]
        fill_forced: bool,
        /// Print statistics as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Render a baked tiling to PNG.
    Render {
        /// Baked tiling file.
        input: PathBuf,
        /// PNG to write.
        #[arg(short, long)]
        output: PathBuf,
        /// What to draw.
        #[arg(long, value_enum, default_value_t = StyleArg::Streamlines)]
        style: StyleArg,
        /// Pixels per tile.
        #[arg(long, default_value_t = 48)]
        px: u32,
        /// Do not draw tile seams.
        #[arg(long)]
        no_seams: bool,
        /// Particles to advect (particle style).
        #[arg(long, default_value_t = 600)]
        particles: usize,
        /// Advection steps per particle.
        #[arg(long, default_value_t = 400)]
        steps: usize,
        /// Seed for streamline seeds and particles.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Place a baked tiling onto world triangles (OBJ with flow coordinates as
    /// vt) and draw its streamlines in world space; optionally write a sampler
    /// grid of world velocities.
    Map {
        /// Baked tiling file.
        input: PathBuf,
        /// Mesh: OBJ with `v` world positions (x, y used), `vt` flow coordinates.
        #[arg(long)]
        mesh: PathBuf,
        /// Picture (PNG) to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Sampler file (JSON) of world velocities on a regular grid.
        #[arg(long)]
        sampler: Option<PathBuf>,
        /// Sampler grid spacing in world units.
        #[arg(long, default_value_t = 16.0)]
        cell: f64,
        /// Plot width in pixels.
        #[arg(long, default_value_t = 800)]
        width: u32,
        /// Name of the world length unit for the axes.
        #[arg(long, default_value = "units")]
        units: String,
        /// Seed for streamline seeds.
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Build a time-varying flow from key tilings (a spec tiled with a random
    /// key sequence, or baked keys) blended over a period, and write an
    /// animated GIF of advected particles, in world space with --mesh.
    Animate {
        /// Spec file (TOML) to tile once per key, or baked key files (.ftb).
        inputs: Vec<PathBuf>,
        /// GIF to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Keys to tile from a spec (seeds seed, seed+1, ...).
        #[arg(long, default_value_t = 4)]
        keys: usize,
        /// Flow time between consecutive keys (blend period).
        #[arg(long, default_value_t = 2.0)]
        period: f64,
        /// Mesh (OBJ) placing the flow in the world; without it the world is flow space.
        #[arg(long)]
        mesh: Option<PathBuf>,
        /// Frames of the GIF.
        #[arg(long, default_value_t = 80)]
        frames: usize,
        /// Flow time per frame.
        #[arg(long, default_value_t = 0.1)]
        dt: f64,
        /// Frame delay in hundredths of a second.
        #[arg(long, default_value_t = 5)]
        delay: u16,
        /// Particles.
        #[arg(long, default_value_t = 500)]
        particles: usize,
        /// Plot width in pixels.
        #[arg(long, default_value_t = 640)]
        width: u32,
        /// Name of the world length unit for the axes.
        #[arg(long, default_value = "tiles")]
        units: String,
        /// Seed of the key sequence (overrides the spec's) and of the particles.
        #[arg(long)]
        seed: Option<u64>,
        /// Also write the keys' baked files as PREFIX-K.ftb.
        #[arg(long)]
        save_keys: Option<PathBuf>,
    },
    /// Derive a tiling spec from a map: the walkable floor at one level (where a
    /// standing player fits, from the map's player clip hull), walls as blocked
    /// slots, spawns/named entities as sources and sinks of a designed flow.
    Region {
        /// The map (GoldSrc or Quake BSP).
        map: PathBuf,
        /// Floor height of the level (default: the floor under the spawns).
        #[arg(long, allow_hyphen_values = true)]
        floor: Option<f64>,
        /// Floors from the areas of this bot navigation mesh (Counter-Strike .nav,
        /// v1-5) instead of the map's hulls.
        #[arg(long)]
        nav: Option<PathBuf>,
        /// Slot side in world units.
        #[arg(long, default_value_t = 64.0)]
        tile: f64,
        /// Floors within this height of the level belong to it.
        #[arg(long, default_value_t = 48.0)]
        band: f64,
        /// Entity class names that are flow sources (repeatable).
        #[arg(long = "from")]
        from: Vec<String>,
        /// Entity class names that are flow sinks (repeatable).
        #[arg(long = "to")]
        to: Vec<String>,
        /// Spec (TOML) to write; the map's top view under the grid (for
        /// `edit`) goes beside it as NAME.top.png.
        #[arg(short, long)]
        output: PathBuf,
        /// Top-view picture (PNG) of the region over the map.
        #[arg(long)]
        picture: Option<PathBuf>,
        /// Also tile the spec and draw its streamlines over the map's top view (PNG).
        #[arg(long)]
        flow_picture: Option<PathBuf>,
        /// Also tile 4 keys of the spec and animate particles over the map (GIF).
        #[arg(long)]
        flow_gif: Option<PathBuf>,
        /// Seed written into the spec.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Print statistics as JSON.
        #[arg(long)]
        json: bool,
    },
    /// The interactive editor: paint the region, fix edge fluxes and corner
    /// velocities, place tiles from the palette of a slot (only tiles that
    /// keep the tiling completable; the others greyed with the reason), fill
    /// the rest, undo/redo, save the spec, bake the file. With --script the
    /// commands of a file are applied first and the editor runs headless
    /// (add --window to open it afterwards); --screenshot writes a PNG.
    Edit {
        /// A spec (TOML, also from `region`) or a baked tiling (.ftb); none: a blank grid.
        input: Option<PathBuf>,
        /// Size WxH of the blank grid (without an input).
        #[arg(long, default_value = "16x12")]
        grid: String,
        /// Commands to apply, one per line (see `flowtile_bake::editor::commands`).
        #[arg(long)]
        script: Option<PathBuf>,
        /// Write a picture of the editor (PNG) after the script, rendered without a display.
        #[arg(long)]
        screenshot: Option<PathBuf>,
        /// Window and screenshot size in pixels, WxH.
        #[arg(long, default_value = "1280x800")]
        size: String,
        /// Picture (PNG) under the grid, spanning it (default: the spec's `background`).
        #[arg(long)]
        background: Option<PathBuf>,
        /// Where Save writes the spec (default: the input spec; for others NAME.edited.toml).
        #[arg(long)]
        save_as: Option<PathBuf>,
        /// Where Bake writes the tiling (default: the spec's name with .ftb).
        #[arg(long)]
        bake_as: Option<PathBuf>,
        /// Open the window after a script.
        #[arg(long)]
        window: bool,
        /// Close the window after this many seconds.
        #[arg(long)]
        seconds: Option<f64>,
    },
    /// Describe a baked tiling and check it.
    Info {
        /// Baked tiling file.
        input: PathBuf,
        /// Print as JSON.
        #[arg(long)]
        json: bool,
    },
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum BorderArg {
    Free,
    Zero,
    Periodic,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum StyleArg {
    Arrows,
    Streamlines,
    Particles,
}

/// Runs the command line.
pub fn run() -> Result<()> {
    let args = Args::parse();
    match args.command {
        Command::Count {
            mx,
            my,
            corners,
            classes,
        } => count(mx, my, corners, classes),
        Command::Tile {
            spec,
            output,
            grid,
            set,
            n,
            border,
            seed,
            fill_forced,
            json,
        } => {
            let mut problem = match (&spec, &grid) {
                (Some(_), Some(_)) => bail!("give either a spec file or --grid, not both"),
                (None, None) => bail!("give a spec file or --grid WxH"),
                (Some(path), None) => {
                    let text = std::fs::read_to_string(path)
                        .with_context(|| format!("{}", path.display()))?;
                    Problem::from_toml(&text).with_context(|| format!("{}", path.display()))?
                }
                (None, Some(g)) => grid_problem(g, &set, n, border)?,
            };
            problem.fill_forced |= fill_forced;
            tile(problem, seed, output.as_deref(), json)
        }
        Command::Render {
            input,
            output,
            style,
            px,
            no_seams,
            particles,
            steps,
            seed,
        } => {
            let baked =
                BakedTiling::read(&input).with_context(|| format!("{}", input.display()))?;
            let opt = RenderOptions {
                px_per_tile: px,
                style: match style {
                    StyleArg::Arrows => Style::Arrows,
                    StyleArg::Streamlines => Style::Streamlines,
                    StyleArg::Particles => Style::Particles,
                },
                seams: !no_seams,
                particles,
                steps,
                seed,
            };
            render_to_file(&baked, &opt, &output)
                .with_context(|| format!("{}", output.display()))?;
            outln!("wrote {}", output.display())?;
            Ok(())
        }
        Command::Info { input, json } => info(&input, json),
        Command::Edit {
            input,
            grid,
            script,
            screenshot,
            size,
            background,
            save_as,
            bake_as,
            window,
            seconds,
        } => crate::edit::edit(crate::edit::EditArgs {
            input,
            grid,
            script,
            screenshot,
            size,
            background,
            save_as,
            bake_as,
            window,
            seconds,
        }),
        Command::Region {
            map,
            floor,
            nav,
            tile,
            band,
            from,
            to,
            output,
            picture,
            flow_picture,
            flow_gif,
            seed,
            json,
        } => {
            let flows = [flow_picture.as_deref(), flow_gif.as_deref()];
            region(
                &map,
                nav.as_deref(),
                floor,
                tile,
                band,
                from,
                to,
                &output,
                picture.as_deref(),
                flows,
                seed,
                json,
            )
        }
        Command::Map {
            input,
            mesh,
            output,
            sampler,
            cell,
            width,
            units,
            seed,
        } => map(
            &input,
            &mesh,
            &output,
            sampler.as_deref(),
            cell,
            width,
            &units,
            seed,
        ),
        Command::Animate {
            inputs,
            output,
            keys,
            period,
            mesh,
            frames,
            dt,
            delay,
            particles,
            width,
            units,
            seed,
            save_keys,
        } => {
            let keys = load_keys(&inputs, keys, seed, save_keys.as_deref())?;
            let blend = KeyBlend::new(keys, period)?;
            let mesh = match &mesh {
                Some(p) => read_mesh(p)?,
                None => flow_space_mesh(blend.key(0)),
            };
            let field = WorldField::new(&mesh, Flow::Keys(blend.clone()))?;
            let opt = PictureOptions {
                width,
                particles,
                seed: seed.unwrap_or(1),
                title: format!("{} keys, period {period}", blend.len()),
                units,
            };
            let anim = AnimationOptions { frames, dt, delay };
            let mut bytes = Vec::new();
            animate_gif(&field, &opt, &anim, None, &mut bytes)?;
            flowtile_bake::bake::write_atomic(&output, &bytes)
                .with_context(|| format!("{}", output.display()))?;
            outln!(
                "wrote {} ({} frames, {} keys, {} bytes)",
                output.display(),
                frames,
                blend.len(),
                bytes.len()
            )?;
            Ok(())
        }
    }
}

#[allow(clippy::too_many_arguments)]
fn region(
    map: &Path,
    nav: Option<&Path>,
    floor: Option<f64>,
    tile: f64,
    band: f64,
    mut from: Vec<String>,
    mut to: Vec<String>,
    output: &Path,
    picture: Option<&Path>,
    flows: [Option<&Path>; 2],
    seed: u64,
    json: bool,
) -> Result<()> {
    let t0 = Instant::now();
    let bsp = bsp::Bsp::open(map).with_context(|| format!("{}", map.display()))?;
    let nav = match nav {
        Some(p) => {
            let mesh = navmesh::NavMesh::open(p).map_err(anyhow::Error::msg)?;
            let size = std::fs::metadata(map).map(|m| m.len()).unwrap_or(0);
            if mesh.bsp_size != 0 && u64::from(mesh.bsp_size) != size {
                eprintln!(
                    "warning: {} was made for a map of {} bytes, {} has {size} (an older build of the map?)",
                    p.display(),
                    mesh.bsp_size,
                    map.display()
                );
            }
            Some(mesh)
        }
        None => None,
    };
    let read_s = t0.elapsed().as_secs_f64();
    let has = |c: &str| bsp.entities.iter().any(|e| e.classname() == c);
    if from.is_empty() && to.is_empty() {
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
    let opt = flowtile_bake::region::RegionOptions {
        floor,
        tile,
        band,
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
        Some(mesh) => flowtile_bake::region::Floors::Nav(mesh),
        None => flowtile_bake::region::Floors::Hulls,
    };
    let region = flowtile_bake::region::extract_with(&bsp, floors, &name, &opt)
        .with_context(|| format!("{}", map.display()))?;
    let extract_s = t1.elapsed().as_secs_f64();
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
    flowtile_bake::bake::write_atomic(&top, &region.top_view_image(2)?.to_png()?)
        .with_context(|| format!("{}", top.display()))?;
    flowtile_bake::bake::write_atomic(output, spec.as_bytes())
        .with_context(|| format!("{}", output.display()))?;
    if let Some(p) = picture {
        let c = region.picture(800)?;
        flowtile_bake::bake::write_atomic(p, &c.to_png()?)
            .with_context(|| format!("{}", p.display()))?;
    }
    let [flow_png, flow_gif] = flows;
    if flow_png.is_some() || flow_gif.is_some() {
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
            flowtile_bake::bake::write_atomic(p, &c.to_png()?)
                .with_context(|| format!("{}", p.display()))?;
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
            flowtile_bake::bake::write_atomic(p, &bytes)
                .with_context(|| format!("{}", p.display()))?;
        }
    }
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

fn read_mesh(path: &Path) -> Result<Mesh> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    Mesh::from_obj(&text).with_context(|| format!("{}", path.display()))
}

/// The identity placement: the tiling's rectangle as two triangles, world = flow space.
fn flow_space_mesh(b: &BakedTiling) -> Mesh {
    let (w, h) = (b.width as f64, b.height as f64);
    let corners = vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
    Mesh {
        world: corners.clone(),
        flow: corners,
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// Key tilings: baked files as given, or one spec tiled `count` times with
/// seeds `seed, seed + 1, ...` (a random key sequence).
fn load_keys(
    inputs: &[PathBuf],
    count: usize,
    seed: Option<u64>,
    save: Option<&Path>,
) -> Result<Vec<BakedTiling>> {
    if inputs.is_empty() {
        bail!("give a spec file or baked key files");
    }
    let is_spec = inputs.len() == 1 && inputs[0].extension().is_some_and(|e| e == "toml");
    if !is_spec {
        return inputs
            .iter()
            .map(|p| BakedTiling::read(p).with_context(|| format!("{}", p.display())))
            .collect();
    }
    if count == 0 || count > 1000 {
        bail!("--keys {count}: give 1..=1000 keys");
    }
    let path = &inputs[0];
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    let problem = Problem::from_toml(&text).with_context(|| format!("{}", path.display()))?;
    let first = seed.unwrap_or(problem.seed);
    let mut keys = Vec::with_capacity(count);
    for k in 0..count as u64 {
        let mut t = problem.tiling()?;
        if problem.fill_forced {
            t.fill_forced()?;
        }
        t.random_fill_preferring(&mut Rng::new(first.wrapping_add(k)), &problem.preferences)?;
        let b = BakedTiling::from_tiling(&t)?;
        if let Some(prefix) = save {
            let p = PathBuf::from(format!("{}-{k}.ftb", prefix.display()));
            b.write(&p).with_context(|| format!("{}", p.display()))?;
        }
        keys.push(b);
    }
    Ok(keys)
}

#[allow(clippy::too_many_arguments)]
fn map(
    input: &Path,
    mesh: &Path,
    output: &Path,
    sampler: Option<&Path>,
    cell: f64,
    width: u32,
    units: &str,
    seed: u64,
) -> Result<()> {
    let baked = BakedTiling::read(input).with_context(|| format!("{}", input.display()))?;
    let mesh = read_mesh(mesh)?;
    let field = WorldField::new(&mesh, Flow::Steady(baked))?;
    if let Some(path) = sampler {
        let s = field.sample(cell, 0.0)?;
        flowtile_bake::bake::write_atomic(path, s.to_json().as_bytes())
            .with_context(|| format!("{}", path.display()))?;
        outln!(
            "wrote {} ({}x{} samples, {} world units apart)",
            path.display(),
            s.cols,
            s.rows,
            cell
        )?;
    }
    let opt = PictureOptions {
        width,
        particles: 0,
        seed,
        title: format!("{} on {} triangles", input.display(), mesh.triangles.len()),
        units: units.to_string(),
    };
    let canvas = streamlines(&field, &opt, 0.0, None)?;
    flowtile_bake::bake::write_atomic(output, &canvas.to_png()?)
        .with_context(|| format!("{}", output.display()))?;
    outln!("wrote {}", output.display())?;
    Ok(())
}

fn count(mx: u32, my: u32, corners: usize, classes: bool) -> Result<()> {
    if mx == 0 || my == 0 || corners == 0 {
        bail!("--mx, --my and --corners must be at least 1");
    }
    let set = TileSet::paper(mx, my, corners, 3)?;
    outln!("{}", set.count())?;
    if classes {
        let c = set.rotation_classes()?;
        outln!("rotation classes: {}", c.len())?;
    }
    Ok(())
}

fn grid_problem(grid: &str, set: &str, n: usize, border: BorderArg) -> Result<Problem> {
    let (w, h) = grid
        .split_once(['x', 'X'])
        .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)))
        .with_context(|| format!("--grid {grid:?}: expected WxH, e.g. 32x32"))?;
    let parts: Vec<&str> = set.split(',').collect();
    let nums: Option<Vec<u32>> = parts.iter().map(|p| p.trim().parse().ok()).collect();
    let Some([mx, my, c]) = nums.as_deref().and_then(|v| <[u32; 3]>::try_from(v).ok()) else {
        bail!("--set {set:?}: expected MX,MY,C, e.g. 5,5,1");
    };
    if mx == 0 || my == 0 || c == 0 {
        bail!("--set {set:?}: every number must be at least 1");
    }
    let border = match border {
        BorderArg::Free => Border::Free,
        BorderArg::Zero => Border::Zero,
        BorderArg::Periodic => Border::Periodic,
    };
    Ok(Problem {
        set: TileSet::paper(mx, my, c as usize, n)?,
        width: w,
        height: h,
        conditions: Conditions::borders(border, border),
        seed: 1,
        fill_forced: false,
        description: None,
        background: None,
        preferences: Default::default(),
        tiles: Vec::new(),
    })
}

/// Processor time this thread has run so far (POSIX's per-thread CPU clock,
/// nanosecond resolution); `None` where there is none. On a shared machine the
/// wall-clock `seconds` of `tile` include the time spent waiting for a core;
/// this does not, so benchmarks report both.
#[cfg(unix)]
fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes one timespec through a valid pointer.
    let r = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (r == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

#[cfg(not(unix))]
fn thread_cpu_seconds() -> Option<f64> {
    None
}

fn tile(problem: Problem, seed: Option<u64>, output: Option<&Path>, json: bool) -> Result<()> {
    let seed = seed.unwrap_or(problem.seed);
    let set_size = problem.set.count();
    let t0 = Instant::now();
    let cpu0 = thread_cpu_seconds();
    let mut tiling = problem.tiling()?;
    let forced = if problem.fill_forced {
        tiling.fill_forced()?
    } else {
        0
    };
    tiling.random_fill_preferring(&mut Rng::new(seed), &problem.preferences)?;
    let seconds = t0.elapsed().as_secs_f64();
    let cpu_seconds = thread_cpu_seconds().zip(cpu0).map(|(b, a)| b - a);
    let t1 = Instant::now();
    let baked = BakedTiling::from_tiling(&tiling)?;
    let bytes = baked.to_bytes();
    let bake_seconds = t1.elapsed().as_secs_f64();
    if let Some(path) = output {
        flowtile_bake::bake::write_atomic(path, &bytes)?;
    }
    let dirs = problem
        .preferences
        .slot_directions(problem.width, problem.height);
    let against = stats::against_fraction(&baked, &dirs);
    let corridors = stats::corridors(&baked);
    let empty_corridors = corridors.iter().filter(|c| c.flux == 0).count();
    let box_flux = stats::max_box_net_flux(&baked, 1000, seed);
    let stats = json!({
        "width": problem.width,
        "height": problem.height,
        "slots": tiling.open_slots(),
        "blocked": (problem.width * problem.height) as usize - tiling.open_slots(),
        "tiles_used": baked.tiles.len(),
        "tile_set_size": set_size,
        "forced": forced,
        "seed": seed,
        "seconds": seconds,
        "cpu_seconds": cpu_seconds,
        "bake_seconds": bake_seconds,
        "bytes": bytes.len(),
        "output": output.map(|p| p.display().to_string()),
        "max_divergence": baked.max_cell_divergence(),
        "max_flux_error": baked.max_flux_error(),
        "max_seam_mismatch": baked.max_seam_mismatch(),
        "distinct_tiles_per_slot": stats::reuse_ratio(&baked),
        "symmetry_classes_used": baked.symmetry_classes_used(),
        "bytes_plain": baked.storage_bytes().0,
        "bytes_rotated": baked.storage_bytes().1,
        "against_main_direction": against,
        "corridors": corridors.len(),
        "corridors_without_flow": empty_corridors,
        "max_box_net_flux": box_flux,
    });
    if json {
        outln!("{stats}")?;
    } else {
        outln!(
            "tiled {}x{} ({} slots) with {} of {} tiles in {:.3} ms (seed {seed}); baked {} bytes{}",
            problem.width,
            problem.height,
            tiling.open_slots(),
            baked.tiles.len(),
            set_size,
            seconds * 1e3,
            bytes.len(),
            output
                .map(|p| format!(" to {}", p.display()))
                .unwrap_or_default()
        )?;
        outln!(
            "max |divergence| {:.1e}, max flux error {:.1e}, max seam mismatch {:.1e}, max |net flux|/boundary flux over 1000 random boxes {:.1e}",
            baked.max_cell_divergence(),
            baked.max_flux_error(),
            baked.max_seam_mismatch(),
            box_flux
        )?;
        let (plain, rotated) = baked.storage_bytes();
        outln!(
            "reuse: {} distinct tiles / {} slots = {:.3}, {} symmetry classes (file {} bytes, {plain} storing every tile); corridors {} ({} without flow){}",
            baked.tiles.len(),
            tiling.open_slots(),
            stats::reuse_ratio(&baked),
            baked.symmetry_classes_used(),
            rotated.unwrap_or(plain),
            corridors.len(),
            empty_corridors,
            against
                .map(|a| format!("; area against the main direction {:.2}%", a * 100.0))
                .unwrap_or_default()
        )?;
    }
    Ok(())
}

fn info(path: &Path, json: bool) -> Result<()> {
    let bytes = std::fs::read(path).with_context(|| format!("{}", path.display()))?;
    let b = BakedTiling::from_bytes(&bytes).with_context(|| format!("{}", path.display()))?;
    let slots = b
        .grid
        .iter()
        .filter(|&&g| g != flowtile_bake::bake::BLOCKED)
        .count();
    let nodes = (b.set.n + 1) * (b.set.n + 1);
    // What storing every slot's stream function would take.
    let unshared = slots * nodes * 8;
    let s = &b.set;
    // Version 2 stores one tile per symmetry class; `tiles_used` counts the
    // distinct tiles of the grid either way.
    let version = u32::from_le_bytes(bytes[4..8].try_into().expect("read checked the header"));
    let stored = if version == flowtile_bake::bake::VERSION_ROTATED {
        b.symmetry_classes_used()
    } else {
        b.tiles.len()
    };
    let stats = json!({
        "file": path.display().to_string(),
        "bytes": bytes.len(),
        "version": version,
        "tiles_stored": stored,
        "width": b.width,
        "height": b.height,
        "periodic_x": b.periodic_x,
        "periodic_y": b.periodic_y,
        "n": s.n,
        "mx": [s.mx.min, s.mx.max],
        "my": [s.my.min, s.my.max],
        "corners": s.corners,
        "f_base": s.f_base,
        "tile_set_size": s.count(),
        "slots": slots,
        "tiles_used": b.tiles.len(),
        "stream_bytes_vs_unshared": (stored * nodes * 8) as f64 / unshared.max(1) as f64,
        "max_divergence": b.max_cell_divergence(),
        "max_flux_error": b.max_flux_error(),
        "max_seam_mismatch": b.max_seam_mismatch(),
    });
    if json {
        outln!("{stats}")?;
    } else {
        outln!(
            "{}: {} bytes, format version {version}",
            path.display(),
            bytes.len(),
        )?;
        outln!(
            "grid {}x{} ({} slots, {} blocked){}{}",
            b.width,
            b.height,
            slots,
            b.grid.len() - slots,
            if b.periodic_x { ", periodic in x" } else { "" },
            if b.periodic_y { ", periodic in y" } else { "" }
        )?;
        outln!(
            "tile set: m_x {}..{}, m_y {}..{}, {} corner velocities, f_base {}, {} cells per tile; {} tiles",
            s.mx.min,
            s.mx.max,
            s.my.min,
            s.my.max,
            s.corners.len(),
            s.f_base,
            s.n,
            s.count()
        )?;
        outln!(
            "tiles: {} distinct, {stored} stored ({:.1}% of the stream data of storing every slot)",
            b.tiles.len(),
            100.0 * (stored * nodes * 8) as f64 / unshared.max(1) as f64
        )?;
        outln!(
            "max |divergence| {:.1e}, max flux error {:.1e}, max seam mismatch {:.1e}",
            b.max_cell_divergence(),
            b.max_flux_error(),
            b.max_seam_mismatch()
        )?;
    }
    Ok(())
}
