//! `vdgview info`: the thesis' `stats` for a `.vdg` file — counts, bounds, a
//! clearance histogram, and the build options and source map (its game and format)
//! recorded in the metadata — and the same overview of a `.bsp` map
//! ([`map_summary`]): which game and format, counts, bounds, spawns.

use std::fmt::Write;
use vdgformat::Vdg;

/// Number of histogram bins.
const BINS: usize = 10;

/// The format version and which index lists are 16-bit (version 4 writes faces
/// and vertex lists in 16 bits when every index fits; version 2 the leaf lists).
fn format_line(g: &Vdg<'_>) -> String {
    let lists = [
        ("faces", g.faces().is_16_bit()),
        (
            "vertex faces",
            g.vertex_count() > 0 && g.vertex_faces(0).is_16_bit(),
        ),
        (
            "vertex neighbours",
            g.vertex_count() > 0 && g.vertex_neighbours(0).is_16_bit(),
        ),
    ];
    let bits = |narrow: bool| if narrow { 16 } else { 32 };
    let width = if lists.iter().all(|l| l.1 == lists[0].1) {
        format!("faces and vertex lists in {} bits", bits(lists[0].1))
    } else {
        let each: Vec<String> = lists
            .iter()
            .map(|l| format!("{} in {} bits", l.0, bits(l.1)))
            .collect();
        each.join(", ")
    };
    format!("version {}, {width}", g.format_version())
}

/// A human-readable summary of a graph.
pub fn summary(g: &Vdg<'_>) -> String {
    let info = g.info();
    let mut s = String::new();
    if let Some(game) = g.metadata_value("source.game") {
        let format = g.metadata_value("source.format").unwrap_or("");
        let _ = writeln!(s, "source game    {game}, {format}");
    }
    let _ = writeln!(s, "file format    {}", format_line(g));
    let _ = writeln!(s, "vertices       {}", info.vertex_count);
    let _ = writeln!(s, "faces          {}", info.face_count);
    let edges: usize = (0..g.vertex_count() as u32)
        .map(|v| g.vertex_neighbours(v).len())
        .sum::<usize>()
        / 2;
    let _ = writeln!(s, "edges          {edges}");
    let _ = writeln!(
        s,
        "tree nodes     {} (leaf size {})",
        info.tree_node_count, info.leaf_size
    );
    let _ = writeln!(
        s,
        "vertex bounds  {} .. {}",
        fmt3(info.vertex_min),
        fmt3(info.vertex_max)
    );
    let _ = writeln!(
        s,
        "volume bounds  {} .. {}",
        fmt3(info.volume_min),
        fmt3(info.volume_max)
    );
    let _ = writeln!(s, "source hash    {:016x}", info.source_hash);
    let c: Vec<f32> = g.vertices().iter().map(|v| v.clearance).collect();
    if !c.is_empty() {
        let mut sorted = c.clone();
        sorted.sort_unstable_by(f32::total_cmp);
        let mean = c.iter().map(|&x| f64::from(x)).sum::<f64>() / c.len() as f64;
        let _ = writeln!(
            s,
            "clearance      min {:.2}  median {:.2}  mean {:.2}  max {:.2}",
            sorted[0],
            sorted[sorted.len() / 2],
            mean,
            sorted[sorted.len() - 1]
        );
        if let Some(line) = min_clearance_line(g, &sorted) {
            s.push_str(&line);
        }
        let _ = writeln!(s, "clearance histogram (vertices):");
        s.push_str(&histogram(&sorted));
    }
    s.push_str(&corner_radii_line(g));
    let _ = writeln!(s, "metadata:");
    let mut any = false;
    for (k, v) in g.metadata() {
        any = true;
        let _ = writeln!(s, "  {k} = {v}");
    }
    if !any {
        let _ = writeln!(s, "  (none)");
    }
    s
}

/// Whether the faces carry corner radii of their own (format version 3), and how
/// far above their vertices' clearances those reach.
fn corner_radii_line(g: &Vdg<'_>) -> String {
    if !g.has_face_radii() {
        return "corner radii   the vertices' clearances (no radii of the faces' own)\n".into();
    }
    let (mut above, mut sum) = (0usize, 0.0f64);
    for (f, face) in g.faces().iter().enumerate() {
        for (&v, r) in face.iter().zip(g.face_radii(f as u32)) {
            let up = f64::from(r) - f64::from(g.vertices()[v as usize].clearance);
            if up > 0.0 {
                above += 1;
                sum += up;
            }
        }
    }
    format!(
        "corner radii   the faces' own: {above} of {} corners above their vertex's clearance, by {:.1} on average\n",
        3 * g.face_count(),
        sum / above.max(1) as f64
    )
}

/// What the recorded `-md` (metadata `md`) means for this graph, next to what it holds:
/// `-md` is the minimum clearance of the *unreduced* graph (vertices with less are
/// dropped before the reduction); the reduction then lowers the clearances of the
/// vertices it keeps so the volume never grows (condition A), so a reduced graph may
/// hold vertices below it. `None` when the graph records no `-md` (not from bsp2vdg).
fn min_clearance_line(g: &Vdg<'_>, sorted: &[f32]) -> Option<String> {
    let md: f32 = g.metadata_value("md")?.parse().ok()?;
    let below = sorted.partition_point(|&c| c < md);
    let reduced = g
        .metadata_value("rl")
        .and_then(|v| v.parse::<f64>().ok())
        .is_some_and(|rl| rl < 1.0);
    let why = match (below, reduced) {
        (0, _) => "none below it".to_string(),
        (n, true) => format!(
            "{n} of {} vertices below it: the reduction lowers clearances (condition A)",
            sorted.len()
        ),
        (n, false) => format!("{n} of {} vertices below it", sorted.len()),
    };
    Some(format!(
        "min clearance  -md {md} before the reduction (not a floor of the output); {why}\n"
    ))
}

/// A human-readable overview of a map: its game and format, what it holds, bounds.
pub fn map_summary(bsp: &bsp::Bsp) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "game           {}", bsp.game.name());
    let _ = writeln!(s, "game because   {}", bsp.game_reason);
    let _ = writeln!(s, "format         {}", bsp.format_name());
    let _ = writeln!(s, "file size      {} bytes", bsp.file_size);
    let _ = writeln!(
        s,
        "tree           {} nodes, {} leaves, {} planes, {} clip nodes",
        bsp.nodes.len(),
        bsp.leaves.len(),
        bsp.planes.len(),
        bsp.clipnodes.len()
    );
    let _ = writeln!(
        s,
        "geometry       {} faces, {} vertices, {} brushes, {} models",
        bsp.faces.len(),
        bsp.vertices.len(),
        bsp.brushes.len(),
        bsp.models.len()
    );
    let (lo, hi) = bsp.bounds();
    let _ = writeln!(s, "world bounds   {} .. {}", fmt3(lo), fmt3(hi));
    let _ = writeln!(s, "entities       {}", bsp.entities.len());
    let _ = writeln!(s, "spawns         {}", bsp.spawns().len());
    if bsp.unused_bad_records > 0 {
        let _ = writeln!(
            s,
            "unused records {} with bad indices (never read)",
            bsp.unused_bad_records
        );
    }
    if !bsp.unusable_faces.is_empty() {
        let (world_bad, world_faces) = bsp.unusable_world_faces();
        let _ = writeln!(
            s,
            "unusable faces {} ({world_bad} of the world's {world_faces}): {}",
            bsp.unusable_faces.len(),
            bsp::first_unusable_faces(bsp, 3)
        );
    }
    s
}

/// A text histogram of sorted values in [`BINS`] equal-width bins.
fn histogram(sorted: &[f32]) -> String {
    let (lo, hi) = (sorted[0], sorted[sorted.len() - 1]);
    let width = if hi > lo {
        (hi - lo) / BINS as f32
    } else {
        1.0
    };
    let mut counts = [0usize; BINS];
    for &x in sorted {
        let b = (((x - lo) / width) as usize).min(BINS - 1);
        counts[b] += 1;
    }
    let peak = counts.iter().copied().max().unwrap_or(1).max(1);
    let mut s = String::new();
    for (i, &n) in counts.iter().enumerate() {
        let a = lo + width * i as f32;
        let bar = "#".repeat((n * 40).div_ceil(peak));
        let _ = writeln!(s, "  {:>9.2} .. {:>9.2} {:>9} {bar}", a, a + width, n);
    }
    s
}

fn fmt3(v: [f32; 3]) -> String {
    format!("({:.1}, {:.1}, {:.1})", v[0], v[1], v[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use vdgformat::{VdgBuilder, VdgFile};

    #[test]
    fn summary_counts_and_bins() {
        let mut b = VdgBuilder::new();
        let v: Vec<u32> = [
            [0.0, 0.0, 1.0],
            [100.0, 0.0, 5.0],
            [0.0, 100.0, 9.0],
            [100.0, 100.0, 9.0],
        ]
        .iter()
        .map(|&[x, y, c]| b.add_vertex([x, y, 0.0], c))
        .collect();
        b.add_face([v[0], v[1], v[2]]);
        b.add_face([v[1], v[3], v[2]]);
        b.set_metadata("source.name", "m.bsp");
        b.set_metadata("source.game", "Quake 3 (OpenArena, ioquake3)");
        b.set_metadata("source.format", "IBSP 46 (Quake 3)");
        let file = VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let s = summary(&file.graph());
        assert!(
            s.contains("source game    Quake 3 (OpenArena, ioquake3), IBSP 46 (Quake 3)"),
            "{s}"
        );
        assert!(s.contains("vertices       4"), "{s}");
        assert!(s.contains("faces          2"), "{s}");
        assert!(s.contains("edges          5"), "{s}");
        assert!(s.contains("min 1.00"), "{s}");
        assert!(s.contains("max 9.00"), "{s}");
        // 4 vertices over the bins.
        let total: usize = s
            .lines()
            .filter(|l| l.contains(" .. ") && !l.contains('('))
            .map(|l| {
                l.split_whitespace()
                    .nth(3)
                    .unwrap()
                    .parse::<usize>()
                    .unwrap()
            })
            .sum();
        assert_eq!(total, 4, "{s}");
        // No `md` recorded (not from bsp2vdg): no claim about it.
        assert!(!s.contains("-md"), "{s}");
    }

    /// The `-md` line counts the vertices below the recorded value and says why a
    /// reduced graph may hold them.
    #[test]
    fn min_clearance_line_counts_vertices_below_md() {
        let graph = |rl: &str| {
            let mut b = VdgBuilder::new();
            let v: Vec<u32> = [(0.0, 0.0, 0.0), (100.0, 0.0, 12.5), (0.0, 100.0, 30.0)]
                .iter()
                .map(|&(x, y, c)| b.add_vertex([x, y, 0.0], c))
                .collect();
            b.add_face([v[0], v[1], v[2]]);
            b.set_metadata("md", "20").set_metadata("rl", rl);
            VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap()
        };
        let s = summary(&graph("0.025").graph());
        assert!(
            s.contains("min clearance  -md 20 before the reduction (not a floor of the output); 2 of 3 vertices below it: the reduction lowers clearances"),
            "{s}"
        );
        let s = summary(&graph("1").graph());
        assert!(s.contains("; 2 of 3 vertices below it\n"), "{s}");
    }

    #[test]
    fn corner_radii_line_counts_corners_above_their_vertex() {
        let mut b = VdgBuilder::new();
        let v: Vec<u32> = [(0.0, 0.0), (100.0, 0.0), (0.0, 100.0)]
            .iter()
            .map(|&(x, y)| b.add_vertex([x, y, 0.0], 10.0))
            .collect();
        b.add_face_with_radii([v[0], v[1], v[2]], [10.0, 14.0, 12.0]);
        let file = VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let s = summary(&file.graph());
        assert!(
            s.contains("corner radii   the faces' own: 2 of 3 corners above their vertex's clearance, by 3.0 on average"),
            "{s}"
        );
    }
}
