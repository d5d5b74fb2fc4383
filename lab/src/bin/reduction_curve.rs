//! Coverage against the reduction ratio: draws what
//! `scripts/measure/reduction-curve.sh` measured — per map, walkable coverage (standing
//! player origins inside the volume), coverage (free points with clearance ≥ 32)
//! and, when measured, the free sight lines with both ends inside the volume that
//! Visible sees (100 % − its false negatives there) against the share of vertices
//! left, one line per map and measure — as a PNG.
//!
//! `cargo run --release -p lab --bin reduction_curve -- CURVE.tsv OUT.png`
//!
//! CURVE.tsv rows: `map  rl  ratio  walkable  coverage  stop  [fn_inside  [vertices
//! options]]` (ratio = vertices left / before; walkable `n/a` on maps without
//! standing places; options `-` for the defaults, else a line of its own per map
//! and options; header lines start with `map` or `#`).

use anyhow::{Context, bail};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use vdgview::replay::plots::{PALETTE, err, png};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 2 {
        bail!("usage: reduction_curve CURVE.tsv OUT.png");
    }
    let text = std::fs::read_to_string(&args[0]).with_context(|| format!("reading {}", args[0]))?;
    // Per map: (ratio %, walkable %, coverage %, sight lines seen %), sorted by
    // ratio; NaN where not measured.
    let mut maps: BTreeMap<String, Vec<(f64, f64, f64, f64)>> = BTreeMap::new();
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.starts_with("map") || line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        if f.len() < 5 {
            bail!(
                "{}:{}: expected map, rl, ratio, walkable, coverage",
                args[0],
                n + 1
            );
        }
        let num = |i: usize| -> anyhow::Result<f64> {
            f[i].parse::<f64>()
                .with_context(|| format!("{}:{}: column {} is not a number", args[0], n + 1, i + 1))
        };
        let walkable = if f[3] == "n/a" {
            f64::NAN
        } else {
            100.0 * num(3)?
        };
        let seen = match f.get(6) {
            Some(_) => 100.0 - 100.0 * num(6)?,
            None => f64::NAN,
        };
        let series = match f.get(8) {
            Some(&opts) if opts != "-" && !opts.is_empty() => format!("{} {opts}", f[0]),
            _ => f[0].to_string(),
        };
        maps.entry(series)
            .or_default()
            .push((100.0 * num(2)?, walkable, 100.0 * num(4)?, seen));
    }
    if maps.is_empty() {
        bail!("{}: no rows", args[0]);
    }
    for v in maps.values_mut() {
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let all = maps.values().flatten();
    let x_max = all.clone().map(|p| p.0).fold(0.0, f64::max) * 1.1;
    // `f64::min` skips NaN (a measure not taken).
    let y_min = all
        .map(|p| p.1.min(p.2).min(p.3))
        .fold(100.0, f64::min)
        .min(99.0)
        - 0.5;
    png(Path::new(&args[1]), 1000, 600, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Coverage and sight lines against reduction ratio",
                ("sans-serif", 24),
            )
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d(0.0..x_max, y_min..100.0)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("vertices left (% of the unreduced graph)")
            .y_desc("points inside the volume / sight lines seen (%)")
            .draw()
            .map_err(err)?;
        for (i, (name, pts)) in maps.iter().enumerate() {
            let col = PALETTE[i % PALETTE.len()];
            chart
                .draw_series(LineSeries::new(
                    pts.iter().filter(|p| p.1.is_finite()).map(|p| (p.0, p.1)),
                    col.stroke_width(3),
                ))
                .map_err(err)?
                .label(format!("{name}: walkable (standing origins)"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], col.stroke_width(3)));
            chart
                .draw_series(
                    pts.iter()
                        .filter(|p| p.1.is_finite())
                        .map(|p| Circle::new((p.0, p.1), 4, col.filled())),
                )
                .map_err(err)?;
            chart
                .draw_series(DashedLineSeries::new(
                    pts.iter().map(|p| (p.0, p.2)),
                    6,
                    4,
                    col.stroke_width(2),
                ))
                .map_err(err)?
                .label(format!("{name}: coverage (clearance >= 32)"))
                // Dashed in the legend as in the plot: two dashes.
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new([(0, 0), (8, 0)], col.stroke_width(2))
                        + PathElement::new([(12, 0), (20, 0)], col.stroke_width(2))
                });
            chart
                .draw_series(
                    pts.iter()
                        .map(|p| Circle::new((p.0, p.2), 3, col.stroke_width(1))),
                )
                .map_err(err)?;
            let seen: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.3.is_finite())
                .map(|p| (p.0, p.3))
                .collect();
            if !seen.is_empty() {
                chart
                    .draw_series(DashedLineSeries::new(
                        seen.iter().copied(),
                        2,
                        4,
                        col.stroke_width(2),
                    ))
                    .map_err(err)?
                    .label(format!(
                        "{name}: free sight lines seen (100 % - Visible FN, ends inside)"
                    ))
                    .legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new([(0, 0), (2, 0)], col.stroke_width(2))
                            + PathElement::new([(6, 0), (8, 0)], col.stroke_width(2))
                            + PathElement::new([(12, 0), (14, 0)], col.stroke_width(2))
                            + PathElement::new([(18, 0), (20, 0)], col.stroke_width(2))
                    });
                chart
                    .draw_series(
                        seen.iter()
                            .map(|&p| TriangleMarker::new(p, 4, col.filled())),
                    )
                    .map_err(err)?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}
