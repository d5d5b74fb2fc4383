//! `flowtile-bake animate`: key tilings blended over a period, particles
//! advected through them, an animated GIF.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};

use flowtile_bake::bake::{BakedTiling, write_atomic};
use flowtile_bake::rng::Rng;
use flowtile_bake::runtime::KeyBlend;
use flowtile_bake::spec::Problem;
use flowtile_bake::world::{AnimationOptions, Flow, Mesh, PictureOptions, WorldField, animate_gif};

// The options of `flowtile-bake animate`; its help text is the doc comment of
// `Command::Animate` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Spec file (TOML) to tile once per key, or baked key files (.ftb).
    pub inputs: Vec<PathBuf>,
    /// GIF to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Keys to tile from a spec (seeds seed, seed+1, ...).
    #[arg(long, default_value_t = 4)]
    pub keys: usize,
    /// Flow time between consecutive keys (blend period).
    #[arg(long, default_value_t = 2.0)]
    pub period: f64,
    /// Mesh (OBJ) placing the flow in the world; without it the world is flow space.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Frames of the GIF.
    #[arg(long, default_value_t = 80)]
    pub frames: usize,
    /// Flow time per frame.
    #[arg(long, default_value_t = 0.1)]
    pub dt: f64,
    /// Frame delay in hundredths of a second.
    #[arg(long, default_value_t = 5)]
    pub delay: u16,
    /// Particles.
    #[arg(long, default_value_t = 500)]
    pub particles: usize,
    /// Plot width in pixels.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Name of the world length unit for the axes.
    #[arg(long, default_value = "tiles")]
    pub units: String,
    /// Seed of the key sequence (overrides the spec's) and of the particles.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Also write the keys' baked files as PREFIX-K.ftb.
    #[arg(long)]
    pub save_keys: Option<PathBuf>,
}

/// Runs `flowtile-bake animate`.
pub fn run(a: Args) -> Result<()> {
    let keys = load_keys(&a.inputs, a.keys, a.seed, a.save_keys.as_deref())?;
    let period = a.period;
    let blend = KeyBlend::new(keys, period)?;
    let mesh = match &a.mesh {
        Some(p) => super::read_mesh(p)?,
        None => flow_space_mesh(blend.key(0)),
    };
    let field = WorldField::new(&mesh, Flow::Keys(blend.clone()))?;
    let opt = PictureOptions {
        width: a.width,
        particles: a.particles,
        seed: a.seed.unwrap_or(1),
        title: format!("{} keys, period {period}", blend.len()),
        units: a.units,
    };
    let anim = AnimationOptions {
        frames: a.frames,
        dt: a.dt,
        delay: a.delay,
    };
    let mut bytes = Vec::new();
    animate_gif(&field, &opt, &anim, None, &mut bytes)?;
    let output = &a.output;
    write_atomic(output, &bytes).with_context(|| format!("{}", output.display()))?;
    outln!(
        "wrote {} ({} frames, {} keys, {} bytes)",
        output.display(),
        a.frames,
        blend.len(),
        bytes.len()
    )?;
    Ok(())
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
