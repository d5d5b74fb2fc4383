//! Nearest-wall queries on real maps (`Walls::distance_within`, the exact wall
//! distance behind the compiler's clearances, its interpolation guard and its wall
//! raise): queries per second on one core, median of 5 runs, and a checksum of the
//! answers, so that two builds can be compared for speed and for identical results.
//!
//! `cargo bench -p bsp --bench walls [-- MAP.bsp ...]` — without maps it uses
//! de_dust2, de_cbble and c1a0 from ../shared/testmaps.
//!
//! The queries are like the compiler's: points in free space, each with a radius
//! around its wall distance (0.6–1.6 times it, plus a unit), so that most find a
//! wall and some prove there is none within the radius. Asked one by one
//! (`distance_within`), and at once in groups of points close together
//! (`distances_within`) like the grids on the graph's faces that the guard (a few
//! points within 16 units) and the wall raise (a 16 × 16 grid of spacing 6 on a
//! plane) ask.

use bsp::Bsp;
use bsp::oracle::{Oracle, OracleOptions};
use bsp::walls::Walls;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;
use toolbox::SplitMix64;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn default_maps() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let dir = root.join("../shared/testmaps/goldsrc/nonfree");
    [
        "bspview-cstrike-de_dust2",
        "bspview-cstrike-de_cbble",
        "bspview-halflife_c1a0",
    ]
    .iter()
    .map(|n| dir.join(format!("{n}.bsp")))
    .filter(|p| p.exists())
    .collect()
}

fn main() {
    let args: Vec<PathBuf> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .map(PathBuf::from)
        .collect();
    let maps = if args.is_empty() {
        default_maps()
    } else {
        args
    };
    if maps.is_empty() {
        println!("walls bench skipped: no maps (../shared/testmaps is absent)");
        return;
    }
    println!(
        "{:<34} {:>8} {:>12} {:>18} {:>12} {:>12} {:>18}",
        "map", "walls", "1 by 1 M/s", "checksum", "6 in 16 M/s", "grid M/s", "checksum"
    );
    for path in maps {
        let bsp = match Bsp::open(&path) {
            Ok(b) => b,
            Err(e) => {
                println!("{}: {e}", path.display());
                continue;
            }
        };
        let options = OracleOptions::default();
        let oracle = Oracle::new(&bsp, &options);
        let walls = Walls::of_map(&bsp, &options);
        let w = bsp.world();
        let mut rng = SplitMix64::new(7);
        let mut queries = Vec::with_capacity(200_000);
        while queries.len() < 200_000 {
            let p = [0, 1, 2].map(|i| rng.range(w.mins[i] as f64, w.maxs[i] as f64));
            if !oracle.is_free(p) {
                continue;
            }
            let d = walls.distance(p);
            if d.is_finite() {
                queries.push((p, d * rng.range(0.6, 1.6) + 1.0));
            }
        }
        let mut checksum = 0u64;
        let rates: Vec<f64> = (0..5)
            .map(|_| {
                let t = Instant::now();
                let mut sum = 0u64;
                for &(p, r) in &queries {
                    let d = walls.distance_within(black_box(p), black_box(r));
                    sum = mix(sum, d);
                }
                checksum = black_box(sum);
                queries.len() as f64 / t.elapsed().as_secs_f64()
            })
            .collect();
        // Groups: 6 points scattered within 16 units of a query point, or a
        // 16 × 16 grid of spacing 6 on a plane through it; each point with a
        // radius around its own wall distance.
        let mut group_rates = Vec::new();
        let mut group_sum = 0u64;
        for grid in [false, true] {
            let size = if grid { 256 } else { 6 };
            let mut groups = Vec::new();
            let mut total = 0;
            for &(c, _) in queries.iter().take(200_000 / size) {
                let (u, v) = plane(&mut rng);
                let mut points = Vec::with_capacity(size);
                let mut radii = Vec::with_capacity(size);
                while points.len() < size {
                    let p = if grid {
                        let (a, b) = ((points.len() % 16) as f64, (points.len() / 16) as f64);
                        [0, 1, 2].map(|i| c[i] + 6.0 * (a * u[i] + b * v[i]))
                    } else {
                        [0, 1, 2].map(|i| c[i] + rng.range(-16.0, 16.0))
                    };
                    let d = walls.distance(p);
                    if d.is_finite() {
                        points.push(p);
                        radii.push(d * rng.range(0.6, 1.6) + 1.0);
                    }
                }
                total += size;
                groups.push((points, radii));
            }
            let mut out = Vec::new();
            let rates: Vec<f64> = (0..5)
                .map(|_| {
                    let t = Instant::now();
                    let mut sum = 0u64;
                    for (points, radii) in &groups {
                        walls.distances_within(black_box(points), black_box(radii), &mut out);
                        for &d in &out {
                            sum = mix(sum, d);
                        }
                    }
                    group_sum = black_box(group_sum ^ sum);
                    total as f64 / t.elapsed().as_secs_f64()
                })
                .collect();
            group_rates.push(median(rates));
        }
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        println!(
            "{:<34} {:>8} {:>12.2} {:>18x} {:>12.2} {:>12.2} {:>18x}",
            name,
            walls.len(),
            median(rates) / 1e6,
            checksum,
            group_rates[0] / 1e6,
            group_rates[1] / 1e6,
            group_sum
        );
    }
}

/// Folds an answer into a checksum.
fn mix(sum: u64, d: Option<f64>) -> u64 {
    sum.rotate_left(5)
        .wrapping_add(d.map_or(u64::MAX, f64::to_bits))
}

/// Two orthonormal directions of a random plane.
fn plane(rng: &mut SplitMix64) -> ([f64; 3], [f64; 3]) {
    let n = loop {
        let n = [0, 1, 2].map(|_| rng.range(-1.0, 1.0));
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if l > 0.1 && l <= 1.0 {
            break n.map(|x| x / l);
        }
    };
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = cross(n, a);
    let l = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
    let u = u.map(|x| x / l);
    (u, cross(n, u))
}
