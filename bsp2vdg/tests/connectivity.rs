//! The graph stays in one piece where players walk: on real maps, places a camera
//! and the player it followed stood in (from the camera replays, where the camera
//! was cut to the player because the graph had no way between them) are joined by a
//! path through the graph.

mod common;

use toolbox::ScratchDir;

/// Compiles `map` (a path under ../shared/testmaps) unreduced and asks for a path
/// between each pair of points; `None` when the shared maps are absent.
fn paths(map: &str, pairs: &[([f32; 3], [f32; 3])]) -> Option<Vec<Option<f32>>> {
    let root = common::repo_root().join("../shared/testmaps");
    let bsp = root.join(map);
    if !bsp.is_file() {
        eprintln!("skipped: {} is absent", bsp.display());
        return None;
    }
    let dir = ScratchDir::new("bsp2vdg-connectivity").unwrap();
    // Unreduced (`-rl 1.0`): the pieces come from the stages before the reduction,
    // which keeps the components it is given.
    let file = common::compile(&bsp, &dir.join("out.vdg"), &["-rl", "1.0"]);
    let g = file.graph();
    Some(
        pairs
            .iter()
            .map(|&(a, b)| g.path(a, b).map(|p| p.length))
            .collect(),
    )
}

/// Where the guard lowered the vertices of a doorway just wider than `-md` allows
/// below `-md`, it dropped them with their faces, and the graph came apart there.
#[test]
fn a_doorway_players_walk_through_does_not_split_the_graph() {
    for (map, pairs) in [
        (
            "goldsrc/nonfree/bspview-halflife_c1a1b.bsp",
            vec![([-493.0, -209.0, -119.0], [-134.0, -309.0, -180.0])],
        ),
        (
            "goldsrc/nonfree/bspview-halflife_c1a1.bsp",
            vec![([1640.0, 1854.0, -41.0], [1304.0, 2174.0, -108.0])],
        ),
    ] {
        let Some(lengths) = paths(map, &pairs) else {
            return;
        };
        for ((a, b), length) in pairs.iter().zip(lengths) {
            assert!(
                length.is_some(),
                "{map}: no way through the graph from {a:?} to {b:?}"
            );
        }
    }
}
