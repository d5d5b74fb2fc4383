//! Random scan-line tiling benchmark: prints the median wall time of
//! `flowtile_bake::tiling::Tiling::random_fill` for several grid sizes and
//! tile sets. Run with `cargo bench -p flowtile-bake --bench tiling`.

use std::time::Instant;

use flowtile_bake::rng::Rng;
use flowtile_bake::tileset::TileSet;
use flowtile_bake::tiling::{Border, Conditions, Tiling};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn run(label: &str, set: &TileSet, side: u32, cond: &Conditions, reps: usize) {
    let mut times = Vec::with_capacity(reps);
    let mut setup = Vec::with_capacity(reps);
    for seed in 0..reps as u64 {
        let t0 = Instant::now();
        let mut t = Tiling::new(set.clone(), side, side, cond).expect("feasible");
        let t1 = Instant::now();
        t.random_fill(&mut Rng::new(seed + 1)).expect("completes");
        let t2 = Instant::now();
        assert!(t.is_complete());
        setup.push((t1 - t0).as_secs_f64());
        times.push((t2 - t0).as_secs_f64());
    }
    // The minimum is printed beside the median: on a shared, loaded machine
    // the median carries the other processes' load, the minimum much less.
    let min = times.iter().copied().fold(f64::INFINITY, f64::min);
    println!(
        "{label:<28} {side:>4}x{side:<4} median {:>10.3} ms  min {:>10.3} ms  (setup {:.3} ms, {reps} runs)",
        median(times) * 1e3,
        min * 1e3,
        median(setup) * 1e3
    );
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let free = Conditions::borders(Border::Free, Border::Free);
    let walls = Conditions::borders(Border::Zero, Border::Zero);
    let torus = Conditions::borders(Border::Periodic, Border::Periodic);
    for (name, set) in [
        ("(5,5,1)", TileSet::paper(5, 5, 1, 8).unwrap()),
        ("(3,3,5)", TileSet::paper(3, 3, 5, 8).unwrap()),
    ] {
        for (bname, cond) in [("free", &free), ("walls", &walls), ("periodic", &torus)] {
            let label = format!("{name} {bname}");
            run(&label, &set, 32, cond, if quick { 11 } else { 101 });
            run(&label, &set, 256, cond, if quick { 3 } else { 11 });
        }
    }
}
