//! Pointfiles for the level editor where the compile found a problem a designer fixes
//! in the map: the leak-file format (one `x y z` line per point, a line drawn through
//! them in order) that Quake's and Half-Life's compilers write as `MAP.pts` (Quake 2 and
//! 3's as `MAP.lin`) and TrenchBroom and J.A.C.K. load.
//!
//! - A map with no graph (no walls around free space, or nothing left above `-md`)
//!   gets `OUT.pts`/`OUT.lin` through the places where free space was looked for: the
//!   player starts, or, on a map without any, the diagonal of the world's bounds.
//! - Standing places that the written graph misses get `OUT.missed.pts`/`.lin`: a path
//!   through them, cluster by cluster (the largest first). A standing place is a player
//!   origin on a floor of the grid the reduction keeps ([`bsp::player::grid_origins`]
//!   every [`bsp::player::KEEP_SPACING`] units); it is missed when it lies outside the
//!   graph's volume (no face's interpolated clearance holds it: `Graph::contains`, the
//!   test `vdgcheck`'s walkable coverage counts), i.e. where the camera's target would
//!   have no graph.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

type P = [f64; 3];

/// Points beyond which the missed places' path keeps one point per cluster (a path
/// through every place would take the editor's line through thousands of points).
const MAX_PATH_POINTS: usize = 4000;

/// The pointfile of a failed compile: the leak pointfile's name, `OUT.pts` (`OUT.lin`
/// for Quake 2 and 3).
pub fn failure_path(output: &Path, game: bsp::Game) -> PathBuf {
    output.with_extension(bsp::leak::pointfile_extension(game))
}

/// The pointfile of the missed standing places, `OUT.missed.pts` (`.lin`).
pub fn missed_path(output: &Path, game: bsp::Game) -> PathBuf {
    output.with_extension(format!("missed.{}", bsp::leak::pointfile_extension(game)))
}

/// Writes `points` as a pointfile at `path`, atomically.
pub fn write(path: &Path, points: &[P]) -> std::io::Result<()> {
    toolbox::write_bytes_atomic(path, bsp::leak::pointfile(points).as_bytes())
}

/// Where a map without a graph should have had free space, for the failure's pointfile,
/// and what those points are: the player starts, else the diagonal of the world's bounds.
pub fn where_free_space_was_looked_for(bsp: &bsp::Bsp) -> (Vec<P>, &'static str) {
    let mut spawns: Vec<P> = bsp
        .spawns()
        .iter()
        .map(|s| s.map(f64::from))
        .filter(|p| p.iter().all(|x| x.is_finite()))
        .collect();
    spawns.dedup();
    if spawns.is_empty() {
        let (lo, hi) = bsp.bounds();
        (
            vec![lo.map(f64::from), hi.map(f64::from)],
            "the world's bounds (the map has no player start)",
        )
    } else {
        (spawns, "the player starts")
    }
}

/// Groups of places, each a set of grid neighbours (closer than `link`), the largest
/// first, each group's members in the order of a nearest-neighbour walk from its first.
pub fn clusters(places: &[P], link: f64) -> Vec<Vec<P>> {
    let n = places.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let cell = |p: &P| p.map(|x| (x / link).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, p) in places.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    for (i, p) in places.iter().enumerate() {
        let c = cell(p);
        for d in 0..27 {
            let o = [d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1];
            let Some(near) = grid.get(&[c[0] + o[0], c[1] + o[1], c[2] + o[2]]) else {
                continue;
            };
            for &j in near {
                if j > i && distance(*p, places[j]) <= link {
                    let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    let mut groups: HashMap<usize, Vec<P>> = HashMap::new();
    for (i, p) in places.iter().enumerate() {
        let r = root(&mut parent, i);
        groups.entry(r).or_default().push(*p);
    }
    let mut out: Vec<(usize, Vec<P>)> = groups.into_iter().collect();
    // Largest first; among equals, the one whose first place came first (deterministic).
    out.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then(a.0.cmp(&b.0)));
    out.into_iter().map(|(_, g)| walk(g)).collect()
}

/// The points in the order of a nearest-neighbour walk from the first.
fn walk(mut rest: Vec<P>) -> Vec<P> {
    let mut out = Vec::with_capacity(rest.len());
    if rest.is_empty() {
        return out;
    }
    let mut at = rest.swap_remove(0);
    out.push(at);
    while !rest.is_empty() {
        let (k, _) = rest
            .iter()
            .enumerate()
            .map(|(k, p)| (k, distance(at, *p)))
            .fold(
                (0, f64::INFINITY),
                |best, x| if x.1 < best.1 { x } else { best },
            );
        at = rest.remove(k);
        out.push(at);
    }
    out
}

/// The pointfile's path through clustered places: every place, cluster after cluster,
/// or (past [`MAX_PATH_POINTS`]) the member of each cluster nearest its centre.
pub fn path_through(groups: &[Vec<P>]) -> Vec<P> {
    let total: usize = groups.iter().map(Vec::len).sum();
    if total <= MAX_PATH_POINTS {
        return groups.concat();
    }
    groups.iter().map(|g| centre_member(g)).collect()
}

/// The member of a group nearest the group's centre.
pub fn centre_member(group: &[P]) -> P {
    let n = group.len().max(1) as f64;
    let mut c = [0.0; 3];
    for p in group {
        for i in 0..3 {
            c[i] += p[i] / n;
        }
    }
    group
        .iter()
        .copied()
        .fold((c, f64::INFINITY), |best, p| {
            let d = distance(p, c);
            if d < best.1 { (p, d) } else { best }
        })
        .0
}

fn distance(a: P, b: P) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_cluster_and_the_largest_comes_first() {
        let s = 16.0;
        let mut places = vec![[1000.0, 0.0, 0.0]];
        places.extend((0..5).map(|i| [i as f64 * s, 0.0, 0.0]));
        places.push([0.0, 500.0, 0.0]);
        places.push([s, 500.0, 0.0]);
        let groups = clusters(&places, 1.5 * s);
        let sizes: Vec<usize> = groups.iter().map(Vec::len).collect();
        assert_eq!(sizes, [5, 2, 1]);
        // The walk goes along the row, not back and forth.
        let xs: Vec<f64> = groups[0].iter().map(|p| p[0]).collect();
        assert!(xs.windows(2).all(|w| (w[1] - w[0]).abs() == s), "{xs:?}");
        assert_eq!(path_through(&groups).len(), 8);
        assert_eq!(centre_member(&groups[0]), [32.0, 0.0, 0.0]);
    }
}
