//! Visible's false negatives against the vertices kept: draws what
//! `scripts/measure/reduction-curve.sh` measured with several `-opts` series — per map
//! and compile options, the share of free sight lines with both ends inside the
//! volume that Visible misses, against the reduced graph's vertex count on a
//! log scale, with the 2 % target as a line. One map's series side by side tell
//! what buys sight lines: more vertices of the same graph (along a series) or a
//! finer graph at the same vertex count (across series).
//!
//! `cargo run --release -p lab --bin fn_vertices -- CURVE.tsv OUT.png`
//!
//! CURVE.tsv rows: `map  rl  ratio  walkable  coverage  stop  fn_inside  vertices
//! options` (options `-` for the defaults; header lines start with `map` or `#`).

use anyhow::{Context, bail};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use vdgview::replay::plots::{PALETTE, err, png};

/// The reduction's quality target: Visible misses at most 2 % of the free sight lines
/// with both ends inside the volume.
const TARGET_PERCENT: f64 = 2.0;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 2 {
        bail!("usage: fn_vertices CURVE.tsv OUT.png");
    }
    let text = std::fs::read_to_string(&args[0]).with_context(|| format!("reading {}", args[0]))?;
    // map → options → (vertices, FN inside %), sorted by vertices.
    let mut maps: BTreeMap<String, BTreeMap<String, Vec<(f64, f64)>>> = BTreeMap::new();
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.starts_with("map") || line.trim().is_empty() {
            continue;
        }
        let f: Vec<&str> = line.split('\t').collect();
        if f.len() < 9 {
            bail!(
                "{}:{}: expected map, rl, ratio, walkable, coverage, stop, fn_inside, vertices, options \
                 (a table from before the vertices column: measure again with scripts/measure/reduction-curve.sh)",
                args[0],
                n + 1
            );
        }
        let num = |i: usize| -> anyhow::Result<f64> {
            f[i].parse::<f64>()
                .with_context(|| format!("{}:{}: column {} is not a number", args[0], n + 1, i + 1))
        };
        let (fn_inside, vertices) = (100.0 * num(6)?, num(7)?);
        if vertices < 1.0 {
            bail!("{}:{}: no vertices", args[0], n + 1);
        }
        let opts = if f[8] == "-" { "default options" } else { f[8] };
        maps.entry(f[0].to_string())
            .or_default()
            .entry(opts.to_string())
            .or_default()
            .push((vertices, fn_inside));
    }
    if maps.is_empty() {
        bail!("{}: no rows", args[0]);
    }
    for series in maps.values_mut().flat_map(|m| m.values_mut()) {
        series.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    let all = || maps.values().flat_map(|m| m.values()).flatten();
    let x_min = all().map(|p| p.0).fold(f64::INFINITY, f64::min) / 1.5;
    let x_max = all().map(|p| p.0).fold(0.0, f64::max) * 1.5;
    let y_max = all().map(|p| p.1).fold(TARGET_PERCENT, f64::max) * 1.1;
    png(Path::new(&args[1]), 1000, 600, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Sight lines Visible misses against the vertices kept",
                ("sans-serif", 24),
            )
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d((x_min..x_max).log_scale(), 0.0..y_max)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("vertices in the graph (log scale)")
            .y_desc("free sight lines missed, both ends inside (%)")
            .x_label_formatter(&|x| format!("{x:.0}"))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(
                [(x_min, TARGET_PERCENT), (x_max, TARGET_PERCENT)],
                10,
                6,
                BLACK.stroke_width(1),
            ))
            .map_err(err)?
            .label("target: 2 % (issue 14)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.stroke_width(1)));
        for (i, (name, series)) in maps.iter().enumerate() {
            let col = PALETTE[i % PALETTE.len()];
            for (j, (opts, pts)) in series.iter().enumerate() {
                // One colour per map; the series of one map differ by their marker.
                let marker = j % 3;
                chart
                    .draw_series(LineSeries::new(pts.iter().copied(), col.stroke_width(2)))
                    .map_err(err)?
                    .label(format!("{name}, {opts}"))
                    .legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new([(0, 0), (20, 0)], col.stroke_width(2))
                            + marker_shape(marker, col, 10)
                    });
                chart
                    .draw_series(
                        pts.iter()
                            .map(|&p| EmptyElement::at(p) + marker_shape(marker, col, 0)),
                    )
                    .map_err(err)?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}

/// The marker of a map's `k`-th series, `dx` pixels right of its anchor: a
/// filled circle, a filled triangle, a hollow square.
fn marker_shape<DB: DrawingBackend>(
    k: usize,
    col: RGBColor,
    dx: i32,
) -> DynElement<'static, DB, (i32, i32)> {
    match k {
        0 => Circle::new((dx, 0), 5, col.filled()).into_dyn(),
        1 => TriangleMarker::new((dx, 0), 6, col.filled()).into_dyn(),
        _ => Rectangle::new([(dx - 5, -5), (dx + 5, 5)], col.stroke_width(2)).into_dyn(),
    }
}
