//! Tetrahedralize a point file in qhull's text format (first line the dimension 3, second
//! line the count, then one `x y z` line per point) and print one JSON object with the
//! counts and the triangulation time (file reading excluded).
//!
//! ```text
//! cargo run --release -p bsp2vdg --example tetrahedralize -- points.txt [--validate] [--rings]
//! ```
//!
//! `--validate` runs the exact validity check afterwards; `--rings` also times the
//! circumspheres and the edge-ring enumeration the Voronoi stage uses; `--repeat N`
//! reports the fastest of N triangulations; `--hash` prints a hash of every cell's vertices
//! and neighbours in cell order, to check that two builds triangulate identically.

use std::time::Instant;

use anyhow::{Context, bail};
use bsp2vdg::delaunay::Triangulation;

fn read_qhull_points(path: &str) -> anyhow::Result<Vec<[f64; 3]>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {path}"))?;
    let mut tokens = text.split_ascii_whitespace();
    let mut next = |what: &str| {
        tokens
            .next()
            .with_context(|| format!("{path}: missing {what}"))
    };
    let dim: usize = next("dimension")?.parse().context("bad dimension")?;
    if dim != 3 {
        bail!("{path}: dimension is {dim}, expected 3");
    }
    let count: usize = next("point count")?.parse().context("bad point count")?;
    // The count comes from the file: cap the preallocation by what the text can hold.
    let mut pts = Vec::with_capacity(count.min(text.len() / 6));
    for i in 0..count {
        let mut p = [0.0; 3];
        for c in &mut p {
            let tok = next("coordinate")?;
            *c = tok
                .parse()
                .with_context(|| format!("{path}: point {i}: bad coordinate {tok:?}"))?;
        }
        pts.push(p);
    }
    Ok(pts)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let validate = args.iter().any(|a| a == "--validate");
    let rings = args.iter().any(|a| a == "--rings");
    let hash = args.iter().any(|a| a == "--hash");
    let Some(path) = args
        .iter()
        .enumerate()
        .find(|&(i, a)| !a.starts_with("--") && (i == 0 || args[i - 1] != "--repeat"))
        .map(|(_, a)| a)
    else {
        bail!("usage: tetrahedralize POINTS.txt [--validate] [--rings] [--hash] [--repeat N]");
    };
    let pts = read_qhull_points(path)?;
    // `--repeat N`: triangulate N times and report the fastest (a noisy machine's floor).
    let repeat: usize = match args.iter().position(|a| a == "--repeat") {
        Some(i) => args.get(i + 1).context("--repeat needs a count")?.parse()?,
        None => 1,
    };
    let mut seconds = f64::INFINITY;
    let mut tri = None;
    for _ in 0..repeat.max(1) {
        drop(tri.take());
        let start = Instant::now();
        tri = Some(Triangulation::new(&pts)?);
        seconds = seconds.min(start.elapsed().as_secs_f64());
    }
    let tri = tri.expect("at least one run");
    let mut extra = String::new();
    if rings {
        let start = Instant::now();
        let spheres = tri.circumspheres();
        let (mut faces, mut ring_cells) = (0usize, 0usize);
        tri.for_each_edge_ring(|r| {
            if !r.touches_infinity {
                faces += 1;
                ring_cells += r.cells.len();
            }
        });
        extra += &format!(
            ", \"circumspheres\": {}, \"bounded_voronoi_faces\": {faces}, \"ring_cells\": {ring_cells}, \"voronoi_seconds\": {:.6}",
            spheres.len(),
            start.elapsed().as_secs_f64()
        );
    }
    if hash {
        // FNV-1a over the cells' vertex ids and neighbour ids, in cell order.
        let mut h = 0xcbf2_9ce4_8422_2325u64;
        for t in 0..tri.num_cells() as u32 {
            for x in tri.cell(t).into_iter().chain(tri.neighbors(t)) {
                for byte in x.to_le_bytes() {
                    h = (h ^ u64::from(byte)).wrapping_mul(0x100_0000_01b3);
                }
            }
        }
        extra += &format!(", \"cells_hash\": \"{h:016x}\"");
    }
    if validate {
        let start = Instant::now();
        let ok = match tri.validate() {
            Ok(()) => "true".to_string(),
            Err(e) => format!("{:?}", e.to_string()),
        };
        extra += &format!(
            ", \"valid\": {ok}, \"validate_seconds\": {:.3}",
            start.elapsed().as_secs_f64()
        );
    }
    println!(
        "{{\"points\": {}, \"vertices\": {}, \"duplicates\": {}, \"tetrahedra\": {}, \"cells\": {}, \"seconds\": {:.6}{extra}}}",
        pts.len(),
        tri.num_vertices(),
        tri.duplicates().len(),
        tri.num_finite_cells(),
        tri.num_cells(),
        seconds
    );
    Ok(())
}
