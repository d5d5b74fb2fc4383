//! How far the reduced graph's balls stay below the walls: per vertex, its true wall
//! distance minus its clearance, and per face corner, the vertex's wall distance minus
//! the corner radius (what the certificate of the face gave up). Histograms in units.
//!
//! ```text
//! cargo run --release -p lab --bin corner_slack -- MAP.bsp MAP.vdg
//! ```

use bsp::Bsp;
use bsp::oracle::OracleOptions;
use bsp::walls::Walls;

const BINS: [f64; 8] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, f64::INFINITY];

fn hist(xs: &[f64]) -> String {
    let mut h = [0usize; 8];
    for &x in xs {
        h[BINS.iter().position(|&b| x < b).unwrap_or(7)] += 1;
    }
    let n = xs.len().max(1) as f64;
    let mut s: Vec<f64> = xs.to_vec();
    s.sort_by(f64::total_cmp);
    format!(
        "{}  median {:.2}",
        h.iter()
            .map(|&c| format!("{:5.1}", 100.0 * c as f64 / n))
            .collect::<Vec<_>>()
            .join(" "),
        s.get(s.len() / 2).copied().unwrap_or(0.0)
    )
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    anyhow::ensure!(args.len() == 2, "usage: corner_slack MAP.bsp MAP.vdg");
    let bsp = Bsp::open(&args[0])?;
    let file = vdgformat::VdgFile::open(&args[1])?;
    let g = file.graph();
    let walls = Walls::of_map(&bsp, &OracleOptions::default());
    let wd: Vec<f64> = g
        .vertices()
        .iter()
        .map(|v| walls.distance(v.pos.map(f64::from)))
        .collect();
    let vslack: Vec<f64> = g
        .vertices()
        .iter()
        .zip(&wd)
        .map(|(v, d)| d - f64::from(v.clearance))
        .collect();
    let mut cslack = Vec::new();
    for (f, face) in g.faces().iter().enumerate() {
        for (v, r) in face.into_iter().zip(g.face_radii(f as u32)) {
            cslack.push(wd[v as usize] - f64::from(r));
        }
    }
    println!("bins (units)      <0.5   <1   <2   <4   <8  <16  <32  more   (% of them)");
    println!("vertex slack    {}", hist(&vslack));
    println!("corner slack    {}", hist(&cslack));
    Ok(())
}
