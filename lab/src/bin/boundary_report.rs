//! How much of each map's obstacle boundary (from its BSP tree) has no face: the walls
//! a face-based compile would miss.
//!
//! ```text
//! cargo run --release -p lab --bin boundary_report -- MAP.bsp...
//! ```

use std::time::Instant;

use bsp::Bsp;
use bsp::boundary;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use bsp2vdg::sample;

fn main() -> anyhow::Result<()> {
    println!(
        "map\tfaces\twall_faces\tface_area\tpolygons\tboundary_area\tfaceless_area\tfaceless_pct\tseconds"
    );
    for path in std::env::args().skip(1) {
        let bsp = Bsp::open(&path)?;
        let options = OracleOptions::default();
        let t = Instant::now();
        let b = boundary::of_map(&bsp, &options);
        let secs = t.elapsed().as_secs_f64();
        let oracle = Oracle::new(&bsp, &options);
        let mut faces = sample::collect_faces(&bsp, &[]);
        sample::cull_by_contents(&mut faces, |p| oracle.is_free(p));
        let walls = Walls::from_faces(&faces);
        let face_area: f64 = faces
            .iter()
            .filter(|f| !matches!(f.class, sample::classify::FaceClass::Skip(_)))
            .map(|f| sample::polygon_area(&f.polygon))
            .sum();
        let wall_faces = faces
            .iter()
            .filter(|f| !matches!(f.class, sample::classify::FaceClass::Skip(_)))
            .count();
        let area: f64 = b.iter().map(|p| p.area()).sum();
        // Faceless area: the boundary's pieces whose sample points have no face near.
        let mut faceless = 0.0;
        for p in &b {
            let (pts, _) = sample::sample_polygon(&p.vertices, 4.0, 1 << 20);
            let off = pts
                .iter()
                .filter(|&&q| walls.distance_within(q, 0.5).is_none())
                .count();
            faceless += p.area() * off as f64 / pts.len().max(1) as f64;
        }
        let name = std::path::Path::new(&path)
            .file_stem()
            .map_or(path.clone(), |s| s.to_string_lossy().into_owned());
        println!(
            "{name}\t{}\t{wall_faces}\t{face_area:.0}\t{}\t{area:.0}\t{faceless:.0}\t{:.2}\t{secs:.3}",
            faces.len(),
            b.len(),
            100.0 * faceless / area.max(1.0)
        );
    }
    Ok(())
}
