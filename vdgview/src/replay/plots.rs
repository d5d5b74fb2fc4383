//! `--plots DIR`: PNG charts people read at a glance, drawn with `plotters` (axes,
//! units and a legend on every chart; text from an embedded font, so nothing depends
//! on the fonts of the machine).
//!
//! - `speed.png`: camera speed per frame on one route, every camera on one axis (log
//!   scale), with a one-second running mean, the player's own speed per frame and its
//!   96–265 units/s band:
//!   the thesis' figs. 7.2 and 7.3 side by side;
//! - `occlusion.png`: per camera, when the target's eye was hidden, when the camera
//!   was in a wall or clipping it with the near plane, over all routes;
//! - `summary.png` (and [`summary_chart`] across maps): the key measures per camera.

use super::Report;
use anyhow::{Result, anyhow};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::Once;

const W: u32 = 1200;
const H: u32 = 600;

/// Colours per camera, in the order the cameras were given.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is valid; a failure would only leave text out.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// A plotters error as ours ("plotting: …"), for `.map_err(err)?` on every drawing
/// call of a chart (here and in the examples that draw measurements).
pub fn err<E: std::fmt::Display>(e: E) -> anyhow::Error {
    anyhow!("plotting: {e}")
}

/// Draws into an RGB buffer with `draw` (the embedded font registered) and writes
/// it as a PNG of `w` × `h` pixels: the one way every chart of this crate is saved.
pub fn png(
    path: &Path,
    w: u32,
    h: u32,
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw(&root)?;
        root.present().map_err(err)?;
    }
    let pixels: Vec<u32> = buf
        .chunks_exact(3)
        .map(|p| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32)
        .collect();
    let bytes = crate::render::encode_png(&pixels, w as usize, h as usize)?;
    crate::render::write_atomic(path, &bytes)
}

/// Writes `speed.png`, `occlusion.png` and `summary.png` into `dir`.
pub fn write_all(report: &Report, map_name: &str, dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| anyhow!("creating {}: {e}", dir.display()))?;
    speed(report, map_name, &dir.join("speed.png"))?;
    occlusion(report, map_name, &dir.join("occlusion.png"))?;
    let rows: Vec<(String, Vec<(String, serde_json::Value)>)> = vec![(
        map_name.to_string(),
        report
            .cameras
            .iter()
            .map(|c| (c.name.clone(), c.summary.to_json()))
            .collect(),
    )];
    summary_chart(
        &rows,
        &format!("{map_name}: camera measures"),
        &dir.join("summary.png"),
    )
}

/// The longest route's index.
fn longest_route(report: &Report) -> usize {
    (0..report.routes.routes.len())
        .max_by_key(|&i| report.cameras.first().map_or(0, |c| c.routes[i].len()))
        .unwrap_or(0)
}

fn speed(report: &Report, map_name: &str, path: &Path) -> Result<()> {
    let k = longest_route(report);
    let dt = report.dt;
    let tmax = report
        .cameras
        .iter()
        .filter_map(|c| c.routes[k].last().map(|m| m.t))
        .fold(1.0, f64::max);
    png(path, W, H, |root| {
        let title = format!(
            "{map_name}: camera and player speed per frame ({}, dt {:.4} s)",
            report.routes.routes[k].name, dt
        );
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(0f64..tmax, (1f64..20_000f64).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("camera speed (units/s, log scale)")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(err)?;
        for (band, label) in [(96.0, "crouch 96"), (265.0, "run 265")] {
            chart
                .draw_series(DashedLineSeries::new(
                    [(0.0, band), (tmax, band)],
                    6,
                    4,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(err)?
                .label(format!("player {label} units/s"))
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.5)));
        }
        // The player's own speed per frame (from its positions): what the cameras
        // follow, so their speeds read against it.
        if let Some(c) = report.cameras.first() {
            let ms = &c.routes[k];
            let player = ms.windows(2).map(|w| {
                let d = (0..3)
                    .map(|i| (w[1].target[i] as f64 - w[0].target[i] as f64).powi(2))
                    .sum::<f64>()
                    .sqrt();
                (w[1].t, (d / dt).max(1.0))
            });
            chart
                .draw_series(LineSeries::new(player, BLACK.stroke_width(2)))
                .map_err(err)?
                .label("player (the target) per frame")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2))
                });
        }
        let window = (1.0 / dt).round().max(1.0) as usize;
        for (ci, c) in report.cameras.iter().enumerate() {
            let col = PALETTE[ci % PALETTE.len()];
            let ms = &c.routes[k];
            let raw = ms.iter().map(|m| (m.t, (m.speed as f64).max(1.0)));
            chart
                .draw_series(LineSeries::new(raw, col.mix(0.35).stroke_width(1)))
                .map_err(err)?;
            let mut mean = Vec::with_capacity(ms.len());
            let mut sum = 0.0;
            for (i, m) in ms.iter().enumerate() {
                sum += m.speed as f64;
                if i >= window {
                    sum -= ms[i - window].speed as f64;
                }
                mean.push((m.t, (sum / (i + 1).min(window) as f64).max(1.0)));
            }
            chart
                .draw_series(LineSeries::new(mean, col.stroke_width(3)))
                .map_err(err)?
                .label(format!("{} (thin: per frame, thick: 1 s mean)", c.name))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], col.stroke_width(3))
                });
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)
    })
}

fn occlusion(report: &Report, map_name: &str, path: &Path) -> Result<()> {
    let dt = report.dt;
    let total = report.frames_per_camera as f64 * dt;
    let n = report.cameras.len();
    png(path, W, (140 + 60 * n as u32).max(300), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "{map_name}: target hidden / camera in or near walls, all routes back to back"
                ),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(110)
            .build_cartesian_2d(0f64..total.max(dt), 0f64..n as f64)
            .map_err(err)?;
        let names: Vec<String> = report.cameras.iter().map(|c| c.name.clone()).collect();
        chart
            .configure_mesh()
            .x_desc("replay time (s)")
            .y_desc("camera")
            .y_labels(n * 2 + 1)
            .y_label_formatter(&|y| {
                let f = y - y.floor();
                if (f - 0.5).abs() < 0.01 {
                    names.get(y.floor() as usize).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            })
            .disable_y_mesh()
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(err)?;
        let kinds: [(&str, RGBColor, f64, f64); 4] = [
            (
                "target eye hidden (BSP trace)",
                RGBColor(214, 39, 40),
                0.55,
                0.9,
            ),
            (
                "camera within 6.4 of a wall",
                RGBColor(255, 160, 0),
                0.3,
                0.5,
            ),
            ("camera in solid", BLACK, 0.1, 0.25),
            (
                "target outside Volume(VDG) (the graph's gap)",
                RGBColor(150, 150, 150),
                0.0,
                0.07,
            ),
        ];
        for (kind, (label, col, y0, y1)) in kinds.iter().enumerate() {
            let mut rects = Vec::new();
            for (ci, c) in report.cameras.iter().enumerate() {
                let mut t = 0.0;
                for ms in &c.routes {
                    for m in ms {
                        let on = match kind {
                            0 => !m.eye_visible,
                            1 => !m.solid && (m.clearance as f64) < super::metrics::NEAR_PLANE,
                            2 => m.solid,
                            _ => m.target_outside,
                        };
                        if on {
                            rects.push(Rectangle::new(
                                [(t, ci as f64 + y0), (t + dt, ci as f64 + y1)],
                                col.filled(),
                            ));
                        }
                        t += dt;
                    }
                }
            }
            let col = *col;
            chart
                .draw_series(rects)
                .map_err(err)?
                .label(*label)
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 16, y + 5)], col.filled()));
        }
        chart
            .configure_series_labels()
            .label_font(("sans-serif", 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)
    })
}

/// The measures of [`summary_chart`]: JSON key, panel title, scale.
const PANELS: [(&str, &str, bool); 6] = [
    (
        "visible_fraction",
        "target eye visible (% of frames)",
        false,
    ),
    ("nearplane_frames", "near-plane or solid frames (%)", false),
    ("jumps", "jumps per minute", false),
    ("rms_jerk", "RMS jerk (units/s³, log)", true),
    ("cuts_per_min", "cuts per minute", false),
    ("median_us", "median µs per update (log)", true),
];

/// A chart of the key measures: one panel per measure, a group of bars per map
/// (`rows`: map label → per-camera summary JSON), one colour per camera.
pub fn summary_chart(
    rows: &[(String, Vec<(String, serde_json::Value)>)],
    title: &str,
    path: &Path,
) -> Result<()> {
    let mut cams: Vec<String> = Vec::new();
    for (_, cs) in rows {
        for (c, _) in cs {
            if !cams.contains(c) {
                cams.push(c.clone());
            }
        }
    }
    // The replay's own order (and colours) first, others after.
    let rank = |c: &String| {
        super::CAMERA_NAMES
            .iter()
            .position(|n| n == c)
            .unwrap_or(usize::MAX)
    };
    cams.sort_by_key(rank);
    let value = |v: &serde_json::Value, key: &str| -> f64 {
        let g = |k: &str| v.get(k).and_then(|x| x.as_f64()).unwrap_or(0.0);
        let frames = g("frames").max(1.0);
        let minutes = (g("seconds") / 60.0).max(1e-9);
        match key {
            "visible_fraction" => 100.0 * g(key),
            "nearplane_frames" => 100.0 * g(key) / frames,
            "jumps" => g(key) / minutes,
            _ => g(key),
        }
    };
    // Room for each map's label under its group of bars (ab_glyph text is not rotated).
    let width = (W as usize).max(3 * (100 + rows.len() * 95)) as u32;
    png(path, width, 900, |root| {
        let root = root.titled(title, ("sans-serif", 22)).map_err(err)?;
        // One legend for all six panels, in a strip of its own above them: inside a
        // panel it would cover the bars that reach the top (seen near 100 %).
        let (strip, panels) = root.split_vertically(LEGEND_STRIP);
        legend_strip(&strip, &cams)?;
        let areas = panels.split_evenly((2, 3));
        for (area, (key, label, log)) in areas.iter().zip(PANELS) {
            let vals: Vec<Vec<f64>> = rows
                .iter()
                .map(|(_, cs)| {
                    cams.iter()
                        .map(|c| {
                            cs.iter()
                                .find(|(n, _)| n == c)
                                .map_or(0.0, |(_, v)| value(v, key))
                        })
                        .collect()
                })
                .collect();
            let max = vals.iter().flatten().copied().fold(0.0, f64::max);
            let nx = rows.len() as f64;
            let labels: Vec<String> = rows.iter().map(|(m, _)| m.clone()).collect();
            let mut builder = ChartBuilder::on(area);
            builder
                .caption(label, ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(60);
            let bar = 0.8 / cams.len().max(1) as f64;
            let fmt = |x: &f64| {
                let i = x.floor() as usize;
                if (x - x.floor() - 0.5).abs() < 0.01 {
                    labels.get(i).cloned().unwrap_or_default()
                } else {
                    String::new()
                }
            };
            let rects = |floor: f64| {
                let mut out = Vec::new();
                for (mi, row) in vals.iter().enumerate() {
                    for (ci, v) in row.iter().enumerate() {
                        let x0 = mi as f64 + 0.1 + ci as f64 * bar;
                        out.push(Rectangle::new(
                            [(x0, floor), (x0 + bar * 0.9, v.max(floor))],
                            PALETTE[ci % PALETTE.len()].filled(),
                        ));
                    }
                }
                out
            };
            if log {
                let top = (max * 2.0).max(10.0);
                let mut chart = builder
                    .build_cartesian_2d(0f64..nx, (0.1f64..top).log_scale())
                    .map_err(err)?;
                chart
                    .configure_mesh()
                    .x_labels(rows.len() * 2 + 1)
                    .x_label_formatter(&fmt)
                    .x_label_style(label_style(rows.len()))
                    .disable_x_mesh()
                    .label_style(("sans-serif", 12))
                    .draw()
                    .map_err(err)?;
                chart.draw_series(rects(0.1)).map_err(err)?;
            } else {
                let top = if key == "visible_fraction" {
                    100.0
                } else {
                    (max * 1.15).max(1.0)
                };
                let mut chart = builder
                    .build_cartesian_2d(0f64..nx, 0f64..top)
                    .map_err(err)?;
                chart
                    .configure_mesh()
                    .x_labels(rows.len() * 2 + 1)
                    .x_label_formatter(&fmt)
                    .x_label_style(label_style(rows.len()))
                    .disable_x_mesh()
                    .label_style(("sans-serif", 12))
                    .draw()
                    .map_err(err)?;
                chart.draw_series(rects(0.0)).map_err(err)?;
            }
        }
        Ok(())
    })
}

/// Map labels: upright for one map, turned 90° for many.
fn label_style(n: usize) -> TextStyle<'static> {
    let font = ("sans-serif", 12).into_font();
    if n > 1 {
        font.transform(FontTransform::Rotate90).into()
    } else {
        font.into()
    }
}

/// Height in pixels of the summary chart's legend strip.
const LEGEND_STRIP: u32 = 30;

/// The summary chart's legend: a swatch and the name of each camera in one row,
/// centred in `area` (a strip above the panels, so no bar is ever hidden by it).
fn legend_strip(area: &DrawingArea<BitMapBackend<'_>, Shift>, cams: &[String]) -> Result<()> {
    let font: TextStyle = ("sans-serif", 14).into_font().into();
    let widths: Vec<i32> = cams
        .iter()
        .map(|c| {
            area.estimate_text_size(c, &font)
                .map_or(8 * c.len() as i32, |(w, _)| w as i32)
        })
        .collect();
    // Swatch 14 px, 6 px to its name, 24 px to the next camera.
    let total: i32 = widths.iter().map(|w| 14 + 6 + w + 24).sum::<i32>() - 24;
    let (w, h) = area.dim_in_pixel();
    let mut x = ((w as i32 - total) / 2).max(4);
    let y = h as i32 / 2;
    for (ci, (c, tw)) in cams.iter().zip(&widths).enumerate() {
        let col = PALETTE[ci % PALETTE.len()];
        area.draw(&Rectangle::new([(x, y - 6), (x + 14, y + 6)], col.filled()))
            .map_err(err)?;
        area.draw(&Text::new(
            c.as_str(),
            (x + 20, y),
            font.pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(err)?;
        x += 14 + 6 + tw + 24;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The legend covers no bar: a bar at 100 % keeps its own colour across its whole
    /// width right up to the top of its panel (a legend inside the panel, at its upper
    /// right, used to paint over the top of the bars there).
    #[test]
    fn the_summary_legend_covers_no_bar() {
        let dir = toolbox::ScratchDir::new("plots-legend").unwrap();
        let path = dir.path().join("summary.png");
        let cam = serde_json::json!({"visible_fraction": 1.0, "frames": 100.0, "seconds": 60.0});
        let rows = vec![("map".to_string(), vec![("vdg".to_string(), cam)])];
        summary_chart(&rows, "legend test", &path).unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        let (w, h, px) = (
            info.width as usize,
            info.height as usize,
            info.line_size / info.width as usize,
        );
        let blue = PALETTE[0];
        let is_bar = |x: usize, y: usize| {
            let p = &buf[(y * w + x) * px..];
            (p[0], p[1], p[2]) == (blue.0, blue.1, blue.2)
        };
        // The first panel (upper left third): its bar's columns, found on a row half
        // way down, must be bar-coloured on every row from the bar's top down.
        let (pw, y_mid) = (w / 3, h / 4);
        let columns: Vec<usize> = (0..pw).filter(|&x| is_bar(x, y_mid)).collect();
        assert!(
            columns.len() > pw / 3,
            "no bar found: {} columns",
            columns.len()
        );
        let top = (0..y_mid)
            .find(|&y| columns.iter().any(|&x| is_bar(x, y)))
            .unwrap();
        for y in top..y_mid {
            let covered = columns.iter().filter(|&&x| !is_bar(x, y)).count();
            assert_eq!(
                covered, 0,
                "row {y}: {covered} of the bar's columns painted over"
            );
        }
    }
}
