//! `vdgview <command> ...`: one subcommand per module of the library.

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use vdgview::check::{CheckOptions, check};

#[derive(Parser, Debug)]
#[command(
    name = "vdgview",
    version,
    about = "Inspect, check, query and render Voronoi Distance Graphs"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Measure a graph against its map's BSP: leak, coverage, visibility errors (SPEC §8).
    /// Exits non-zero when anything leaks or is seen through a wall.
    Check {
        #[arg(value_name = "MAP.bsp")]
        map: PathBuf,
        #[arg(value_name = "FILE.vdg")]
        vdg: PathBuf,
        /// Random points for leak and for coverage each (a tenth as many segments).
        #[arg(long, default_value_t = 1_000_000)]
        samples: usize,
        /// Seed of the random points.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Treat water, slime and lava as walls.
        #[arg(long)]
        liquids_solid: bool,
        /// Print one JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
}

fn main() {
    let cli = Cli::parse();
    match run(cli) {
        Ok(true) => {}
        Ok(false) => std::process::exit(1),
        Err(e) => {
            eprintln!("vdgview: error: {e:#}");
            std::process::exit(1);
        }
    }
}

/// Returns whether the command's verdict was positive.
fn run(cli: Cli) -> Result<bool> {
    match cli.command {
        Command::Check {
            map,
            vdg,
            samples,
            seed,
            liquids_solid,
            json,
        } => {
            if samples == 0 {
                bail!("--samples must be at least 1");
            }
            let bsp = bsp2vdg::bsp::Bsp::open(&map).with_context(|| map.display().to_string())?;
            let file = vdgformat::VdgFile::open(&vdg).with_context(|| vdg.display().to_string())?;
            let bytes = std::fs::metadata(&vdg)
                .map(|m| m.len() as usize)
                .unwrap_or(0);
            let options = CheckOptions {
                samples,
                seed,
                liquids_are_solid: liquids_solid,
                ..Default::default()
            };
            let r = check(&bsp, &file.graph(), bytes, &options);
            if json {
                println!("{}", r.to_json());
            } else {
                println!("check {} against {}", vdg.display(), map.display());
                println!(
                    "  graph      {} vertices, {} faces, {} bytes",
                    r.vertices, r.faces, r.bytes
                );
                println!(
                    "  leak       {:.6}  ({} of {} volume points in walls)",
                    r.leak(),
                    r.leaked,
                    r.leak_points
                );
                println!(
                    "  coverage   {:.4}  ({} of {} free points with clearance >= {} inside)",
                    r.coverage(),
                    r.covered,
                    r.coverage_points,
                    options.coverage_clearance
                );
                println!(
                    "  visible    fp {:.6} ({} of {} blocked), fn {:.4} ({} of {} free; {:.4} with both ends inside)",
                    r.visible_fp(),
                    r.false_positives,
                    r.segments - r.free_segments,
                    r.visible_fn(),
                    r.false_negatives,
                    r.free_segments,
                    r.visible_fn_inside()
                );
                println!(
                    "  {} in {:.1} s",
                    if r.passed() { "PASSED" } else { "FAILED" },
                    r.seconds
                );
            }
            Ok(r.passed())
        }
    }
}
