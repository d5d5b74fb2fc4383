//! Measures the foundation stages on real maps against the map's own BSP:
//! read/sample figures, player spawns in free space, samples moved 1 unit in front of /
//! behind their face, and the covering distance of random face points.
//!
//! `cargo run --release -p lab --bin foundation_report -- [-sd M] [-n N] MAPS...`

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp2vdg::sample::{self, SampleOptions, classify::FaceClass, grid::PointGrid};
use std::time::Instant;

const SPAWNS: [&str; 4] = [
    "info_player_start",
    "info_player_deathmatch",
    "info_player_terrorist",
    "info_player_counterterrorist",
];

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut spacing = 24.0;
    let mut n_random = 100_000;
    while args.len() >= 2 && (args[0] == "-sd" || args[0] == "-n") {
        let v = args[1].clone();
        if args[0] == "-sd" {
            spacing = v.parse().expect("-sd takes a number");
        } else {
            n_random = v.parse().expect("-n takes a count");
        }
        args.drain(0..2);
    }
    println!(
        "{:<34} {:>6} {:>7} {:>8} {:>6} {:>6} {:>9} {:>8} {:>8} {:>8}",
        "map",
        "faces",
        "sampled",
        "samples",
        "read",
        "sample",
        "spawns",
        "front",
        "behind",
        "max gap"
    );
    for path in &args {
        report(path, spacing, n_random);
    }
}

fn report(path: &str, spacing: f64, n_random: usize) {
    let t = Instant::now();
    let bsp = match Bsp::open(path) {
        Ok(b) => b,
        Err(e) => {
            println!("{path}: ERROR {e}");
            return;
        }
    };
    let t_read = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let options = SampleOptions {
        spacing,
        ..Default::default()
    };
    let oracle = Oracle::new(&bsp, &OracleOptions::default());
    let mut faces = sample::collect_faces(&bsp, &[]);
    sample::cull_by_contents(&mut faces, |p| oracle.is_free(p));
    let samples = sample::sample_faces(&faces, &options);
    let t_sample = t.elapsed().as_secs_f64();
    let polygon_of: std::collections::HashMap<u32, &[[f64; 3]]> = faces
        .iter()
        .map(|f| (f.index, f.polygon.as_slice()))
        .collect();

    // Player spawns must be in free space.
    let spawns: Vec<[f64; 3]> = bsp
        .entities
        .iter()
        .filter(|e| SPAWNS.contains(&e.classname()))
        .filter_map(|e| e.origin())
        .map(|o| o.map(f64::from))
        .collect();
    let spawns_free = spawns.iter().filter(|&&p| oracle.is_free(p)).count();

    // Samples moved one unit along their face normal: in front free, behind blocked.
    // Samples on a face's edge (within 1 unit) are counted apart: moved by one unit they
    // land exactly on the neighbouring face's plane, where "in" and "out" are a tie.
    let (mut front, mut behind, mut inner, mut inner_front, mut inner_behind) = (0, 0, 0, 0, 0);
    for (p, &f) in samples.points.iter().zip(&samples.source_face) {
        let n = bsp.face_normal(&bsp.faces[f as usize]).map(f64::from);
        let ok_front = oracle.is_free([p[0] + n[0], p[1] + n[1], p[2] + n[2]]);
        let ok_behind = !oracle.is_free([p[0] - n[0], p[1] - n[1], p[2] - n[2]]);
        front += ok_front as usize;
        behind += ok_behind as usize;
        if distance_to_boundary(polygon_of[&f], *p) > 1.0 {
            inner += 1;
            inner_front += ok_front as usize;
            inner_behind += ok_behind as usize;
        }
    }
    let total = samples.points.len().max(1) as f64;
    let inner_total = inner.max(1) as f64;

    // Covering: every random point of a sampled face within the spacing of a sample.
    let sampled: Vec<&sample::SampledFace> = faces
        .iter()
        .filter(|f| !matches!(f.class, FaceClass::Skip(_)))
        .collect();
    let grid = PointGrid::from_points(&samples.points, samples.spacing);
    let mut max_gap = 0.0f64;
    for (p, fi) in sample::random_face_points(&sampled, n_random, 1) {
        let limit = if sampled[fi].class == FaceClass::Sky {
            2.0
        } else {
            1.0
        } * samples.spacing;
        let d = grid
            .nearest_within(p, 2.0 * limit)
            .map_or(f64::INFINITY, |(_, d)| d);
        // Sky faces are held to twice the spacing; report gaps relative to each face's m.
        max_gap = max_gap.max(d * samples.spacing / limit);
    }
    let name = std::path::Path::new(path)
        .file_name()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    println!(
        "{:<34} {:>6} {:>7} {:>8} {:>6.3} {:>6.3} {:>4}/{:<4} {:>7.2}% {:>7.2}% {:>8.3}",
        name,
        samples.faces,
        samples.sampled_faces,
        samples.points.len(),
        t_read,
        t_sample,
        spawns_free,
        spawns.len(),
        100.0 * front as f64 / total,
        100.0 * behind as f64 / total,
        max_gap
    );
    println!(
        "{:<34} interior samples {:>7}: front {:.3}%  behind {:.3}%",
        "",
        inner,
        100.0 * inner_front as f64 / inner_total,
        100.0 * inner_behind as f64 / inner_total
    );
}

/// Distance from a point in a polygon's plane to the polygon's boundary.
fn distance_to_boundary(poly: &[[f64; 3]], p: [f64; 3]) -> f64 {
    let mut best = f64::INFINITY;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        let t = if l2 > 0.0 {
            ((ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [0, 1, 2].map(|k| a[k] + t * ab[k] - p[k]);
        best = best.min((q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt());
    }
    best
}
