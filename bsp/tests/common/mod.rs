//! What the map tests share: finding the shared maps (skipping when absent) and the
//! oracle-against-brushes measurement.

#![allow(dead_code)]

use bsp::oracle::{Oracle, OracleOptions};
use bsp::{Bsp, contents};
use std::path::{Path, PathBuf};
use toolbox::SplitMix64;

/// The `.bsp` files of `../shared/testmaps/<dir>`, or `None` (with a message) when
/// the folder is absent.
pub fn shared_maps(dir: &str) -> Option<Vec<PathBuf>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/testmaps")
        .join(dir);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("skipped: {} is absent", dir.display());
        return None;
    };
    let mut maps: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bsp"))
        .collect();
    maps.sort();
    Some(maps)
}

/// Points where the tree's leaf contents and the brushes disagree, out of `n` random
/// points in the world's box; a brush is solid when its native contents meet
/// `solid_flags`. Compilers fill every empty space no entity reaches with solid
/// leaves that no brush covers (qbsp's `FillOutside`): the void outside the level,
/// and pockets sealed between brushes (gaps of a unit or two where brushes nearly
/// meet; the game's `CM_PointContents`, which reads the leaves, says solid there
/// too). So a solid tree point without a brush counts only where it opens onto the
/// level: free tree space within 4 units along an axis, reached by a straight line
/// that crosses no solid brush. Points within 0.1 units of a brush side are
/// excepted: qbsp classifies brush fragments against its splitting planes with an
/// `ON_EPSILON` of 0.1, so leaves may end that far from the brush faces (rare points,
/// hundredths of a unit outside a brush, in a solid leaf).
pub fn disagreements(bsp: &Bsp, n: usize, seed: u64, solid_flags: i32) -> usize {
    let oracle = Oracle::new(bsp, &OracleOptions::default());
    let brushes = oracle.brushes().unwrap();
    let (lo, hi) = bsp.bounds();
    let mut rng = SplitMix64::new(seed);
    let solid = |f: i32| f & solid_flags != 0;
    let mut bad = 0;
    for _ in 0..n {
        let p = [0, 1, 2].map(|i| rng.range(lo[i] as f64, hi[i] as f64));
        let tree_solid = oracle.contents(p) == contents::SOLID;
        let brush_solid = solid(brushes.point_contents_exhaustive(p));
        if tree_solid == brush_solid {
            continue;
        }
        if tree_solid {
            let opens_onto_level = (0..6).any(|k| {
                let step = if k % 2 == 0 { 0.125 } else { -0.125 };
                let mut q = p;
                q[k / 2] += 32.0 * step;
                oracle.contents(q) != contents::SOLID
                    && (1..=32).all(|s| {
                        let mut r = p;
                        r[k / 2] += s as f64 * step;
                        !solid(brushes.point_contents_exhaustive(r))
                    })
            });
            if !opens_onto_level {
                continue;
            }
        }
        if !near_brush_side(p, 0.1, |q| {
            solid(brushes.point_contents_exhaustive(q)) == tree_solid
        }) {
            bad += 1;
        }
    }
    bad
}

/// Whether `agrees` holds somewhere within `r` of `p`: along the six axes and the
/// eight diagonals.
fn near_brush_side(p: [f64; 3], r: f64, agrees: impl Fn([f64; 3]) -> bool) -> bool {
    let d = r / 3f64.sqrt();
    let axes = (0..6).map(|k| {
        let mut q = p;
        q[k / 2] += if k % 2 == 0 { r } else { -r };
        q
    });
    let diagonals = (0..8).map(|k| {
        let s = |b: usize| if k >> b & 1 == 0 { d } else { -d };
        [p[0] + s(0), p[1] + s(1), p[2] + s(2)]
    });
    axes.chain(diagonals).any(agrees)
}

/// Points where the player's clip hull 1 built from the brushes and the box test
/// against the brushes (`player_contents`, the game's `CM_BoxTrace` answer) disagree
/// about a standing player being stuck, out of `n` random origins in the world's box.
/// Origins in the hull-0 solid (inside walls or the filled void, where no brush need
/// be) and within 0.01 units of a moved-out plane are excepted.
pub fn hull_disagreements(bsp: &Bsp, n: usize, seed: u64) -> (usize, usize) {
    use bsp::oracle::PlayerHull;
    let oracle = Oracle::new(bsp, &OracleOptions::default());
    let (lo, hi) = bsp.bounds();
    let mut rng = SplitMix64::new(seed);
    let stuck =
        |p: [f64; 3]| oracle.player_contents(PlayerHull::Standing, p) == Some(contents::SOLID);
    let (mut bad, mut tested) = (0, 0);
    for _ in 0..n {
        let p = [0, 1, 2].map(|i| rng.range(lo[i] as f64, hi[i] as f64));
        if oracle.contents(p) == contents::SOLID {
            continue;
        }
        tested += 1;
        let hull = oracle.clip_contents(1, p) == Some(contents::SOLID);
        if hull == stuck(p) {
            continue;
        }
        let near = [-0.01, 0.01]
            .iter()
            .any(|d| stuck([p[0] + d, p[1] + d, p[2] + d]) == hull);
        if !near {
            bad += 1;
        }
    }
    (bad, tested)
}
