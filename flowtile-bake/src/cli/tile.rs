//! `flowtile-bake tile`: a grid tiled under its boundary conditions (from a
//! spec or the options), baked, and its statistics printed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use serde_json::json;

use flowtile_bake::bake::{BakedTiling, write_atomic};
use flowtile_bake::rng::Rng;
use flowtile_bake::spec::Problem;
use flowtile_bake::stats;
use flowtile_bake::tileset::TileSet;
use flowtile_bake::tiling::{Border, Conditions};

// The options of `flowtile-bake tile`; its help text is the doc comment of
// `Command::Tile` in `cli/mod.rs`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Spec file (TOML); see testdata/flowtiles/.
    pub spec: Option<PathBuf>,
    /// Baked tiling to write.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Grid size WxH (without a spec file).
    #[arg(long)]
    pub grid: Option<String>,
    /// Tile set MX,MY,C (without a spec file).
    #[arg(long, default_value = "5,5,1")]
    pub set: String,
    /// Tile resolution in cells (without a spec file).
    #[arg(long, default_value_t = 8)]
    pub n: usize,
    /// Outer borders (without a spec file).
    #[arg(long, value_enum, default_value_t = BorderArg::Free)]
    pub border: BorderArg,
    /// Random seed (overrides the spec's).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Fill slots with a single option before the random fill.
    #[arg(long)]
    pub fill_forced: bool,
    /// Print statistics as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum BorderArg {
    Free,
    Zero,
    Periodic,
}

/// Runs `flowtile-bake tile`: the problem from the spec or the options,
/// tiled, baked and described.
pub fn run(a: Args) -> Result<()> {
    let mut problem = match (&a.spec, &a.grid) {
        (Some(_), Some(_)) => bail!("give either a spec file or --grid, not both"),
        (None, None) => bail!("give a spec file or --grid WxH"),
        (Some(path), None) => {
            let text =
                std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
            Problem::from_toml(&text).with_context(|| format!("{}", path.display()))?
        }
        (None, Some(g)) => grid_problem(g, &a.set, a.n, a.border)?,
    };
    problem.fill_forced |= a.fill_forced;
    tile(problem, a.seed, a.output.as_deref(), a.json)
}

fn grid_problem(grid: &str, set: &str, n: usize, border: BorderArg) -> Result<Problem> {
    let (w, h) =
        super::wxh(grid).with_context(|| format!("--grid {grid:?}: expected WxH, e.g. 32x32"))?;
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
    Ok(Problem::new(
        TileSet::paper(mx, my, c as usize, n)?,
        w,
        h,
        Conditions::borders(border, border),
    ))
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
        write_atomic(path, &bytes)?;
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
