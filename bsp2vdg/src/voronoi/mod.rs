//! From the Delaunay tetrahedralization of the wall samples to the Voronoi Distance
//! Graph (thesis 3.6, 3.8, 6.1.3).
//!
//! Every finite tetrahedron gives a Voronoi vertex: its circumcentre, whose empty
//! circumsphere makes the circumradius the distance to the nearest sample. Every
//! Delaunay edge between two samples gives a Voronoi face: the cycle of circumcentres of
//! the tetrahedra around it. Only faces lying wholly in free space are kept (all their
//! vertices free and every segment between consecutive vertices free); they are convex
//! planar polygons and are cut into well-shaped triangles by a 2D Delaunay triangulation
//! in their plane.
//!
//! Clearance: the circumradius C is the distance to the nearest *sample*; the wall may
//! come closer between samples. The thesis corrects this with `sqrt(C² − m²)`, which
//! holds only where the nearest wall point is interior to a face sampled at m — not near
//! convex edges, nor at sky faces sampled at 2m (measured: up to 30 units too large on
//! the demo map). We know the walls exactly, so each vertex gets its exact distance to
//! the nearest obstacle face instead (never more than C). Vertices with less than the
//! minimum clearance are removed with their faces, and so are the spurious vertices
//! between neighbouring samples of a wall: nearer to a sample than the spacing
//! (`C ≤ m`) *and* nearer to the wall than half of it. The thesis removed every vertex
//! with `C ≤ m`, which its estimate `sqrt(C² − m²)` needed; with exact distances that
//! also removed the true vertices in the middle of every passage narrower than about
//! `2m` (a 40-unit drop shaft at the default spacing of 24), which then had no graph.
//!
//! Free space comes in through [`FreeSpace`], so this stage can be tested against
//! analytic worlds as well as run against a map's BSP.

mod polygon;

use crate::delaunay::Triangulation;
use crate::graph::Graph;
use crate::progress::{NoProgress, Progress, Ticker};
use crate::sample::grid::PointGrid;
use crate::space::FreeSpace;
use rayon::prelude::*;

/// Parameters of the extraction.
#[derive(Debug, Clone, Copy)]
pub struct VoronoiOptions {
    /// The sample spacing m used for the clearance correction.
    pub spacing: f64,
    /// Vertices whose corrected clearance is below this are removed (`-md`).
    pub min_clearance: f64,
}

/// The counts of thesis table 7.1 and its log.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct VoronoiStats {
    pub tetrahedra: usize,
    /// Voronoi vertices (finite tetrahedra).
    pub voronoi_vertices: usize,
    /// Voronoi vertices in free space.
    pub inner_vertices: usize,
    /// Voronoi faces (Delaunay edges not on the hull).
    pub voronoi_faces: usize,
    /// Voronoi faces wholly in free space.
    pub inner_faces: usize,
    /// Triangles from the inner faces.
    pub triangulated: usize,
    /// Vertices removed as spurious (`C ≤ m` and clearance below `m / 2`) or by `-md`.
    pub removed_low_clearance: usize,
    /// Final vertex and face counts.
    pub vertices: usize,
    pub faces: usize,
}

/// Extracts the Voronoi Distance Graph of a triangulation of wall samples.
pub fn extract(
    tri: &Triangulation,
    space: &dyn FreeSpace,
    options: &VoronoiOptions,
) -> (Graph, VoronoiStats) {
    extract_reporting(tri, space, options, &NoProgress)
}

/// [`extract`], reporting its free-space tests to `progress` as the stage "Voronoi"
/// (a block of cells or vertices at a time).
pub fn extract_reporting(
    tri: &Triangulation,
    space: &dyn FreeSpace,
    options: &VoronoiOptions,
    progress: &dyn Progress,
) -> (Graph, VoronoiStats) {
    // Three passes test free space: each finite cell's centre, each cell's facets, and
    // each graph vertex's clearance (at most one per finite cell).
    let work = (2 * tri.num_finite_cells() + tri.num_cells()) as u64;
    let ticker = Ticker::start(progress, "Voronoi", work, Ticker::BLOCK);
    let mut stats = VoronoiStats {
        tetrahedra: tri.num_cells(),
        voronoi_vertices: tri.num_finite_cells(),
        ..Default::default()
    };
    let spheres = tri.circumspheres();
    let inner: Vec<bool> = spheres
        .par_iter()
        .map_init(
            || ticker.local(),
            |done, (c, r)| {
                done.tick();
                r.is_finite() && c.iter().all(|x| x.is_finite()) && space.is_free(*c)
            },
        )
        .collect();
    stats.inner_vertices = inner.iter().filter(|&&b| b).count();
    let facet_free = free_facets(tri, &spheres, &inner, space, &ticker);

    // Keep the rings that lie wholly in free space.
    let mut kept: Vec<Vec<u32>> = Vec::new();
    tri.for_each_edge_ring(|ring| {
        if ring.touches_infinity {
            return;
        }
        stats.voronoi_faces += 1;
        let cells = ring.cells;
        let all_free = cells.iter().all(|&t| inner[t as usize])
            && (0..cells.len()).all(|k| {
                let (t, u) = (cells[k], cells[(k + 1) % cells.len()]);
                (0..4).any(|i| tri.neighbor(t, i).0 == u && facet_free[t as usize] & (1 << i) != 0)
            });
        if all_free {
            kept.push(cells.to_vec());
        }
    });
    stats.inner_faces = kept.len();

    // One graph vertex per distinct circumcentre: cospherical samples (grids on walls)
    // give many tetrahedra with the same circumsphere.
    let (vertex_of_cell, positions, radii) = merge_vertices(&kept, &spheres);
    let triangles: Vec<[u32; 3]> = kept
        .par_iter()
        .flat_map_iter(|cells| {
            let mut ids: Vec<u32> = cells.iter().map(|&t| vertex_of_cell[t as usize]).collect();
            ids.dedup();
            while ids.len() > 1 && ids.first() == ids.last() {
                ids.pop();
            }
            polygon::triangulate(&ids, &positions)
        })
        .collect();
    stats.triangulated = triangles.len();

    let graph = correct_and_compact(
        &positions, &radii, &triangles, space, options, &mut stats, &ticker,
    );
    (graph, stats)
}

/// For every cell, a bit per facet: the Voronoi edge through that facet (between the
/// two cells' circumcentres) lies in free space. Each segment is tested once.
fn free_facets(
    tri: &Triangulation,
    spheres: &[([f64; 3], f64)],
    inner: &[bool],
    space: &dyn FreeSpace,
    ticker: &Ticker,
) -> Vec<u8> {
    let finite = spheres.len() as u32;
    let mut bits: Vec<u8> = (0..tri.num_cells() as u32)
        .into_par_iter()
        .map_init(
            || ticker.local(),
            |done, t| {
                done.tick();
                let mut b = 0u8;
                if t < finite && inner[t as usize] {
                    for i in 0..4 {
                        let (u, _) = tri.neighbor(t, i);
                        if t < u
                            && u < finite
                            && inner[u as usize]
                            && space.segment_free(spheres[t as usize].0, spheres[u as usize].0)
                        {
                            b |= 1 << i;
                        }
                    }
                }
                b
            },
        )
        .collect();
    for t in 0..finite {
        for i in 0..4 {
            if bits[t as usize] & (1 << i) != 0 {
                let (u, j) = tri.neighbor(t, i);
                bits[u as usize] |= 1 << j;
            }
        }
    }
    bits
}

/// Maps every cell used by a kept face to a graph vertex, merging circumcentres that
/// coincide (within 1e-6 units) in order of first use.
fn merge_vertices(
    kept: &[Vec<u32>],
    spheres: &[([f64; 3], f64)],
) -> (Vec<u32>, Vec<[f64; 3]>, Vec<f64>) {
    const UNUSED: u32 = u32::MAX;
    let mut vertex_of_cell = vec![UNUSED; spheres.len()];
    let mut grid = PointGrid::new(1e-3);
    let mut radii = Vec::new();
    for cells in kept {
        for &t in cells {
            if vertex_of_cell[t as usize] != UNUSED {
                continue;
            }
            let (c, r) = spheres[t as usize];
            let id = match grid.nearest_within(c, 1e-6) {
                Some((id, _)) => id,
                None => {
                    radii.push(r);
                    grid.insert(c)
                }
            };
            vertex_of_cell[t as usize] = id;
        }
    }
    (vertex_of_cell, grid.points().to_vec(), radii)
}

/// Gives every vertex its exact wall distance, removes the spurious vertices (`C ≤ m`
/// and clearance below `m / 2`) and those below the minimum clearance with their faces,
/// and renumbers the vertices still used in order of first use.
fn correct_and_compact(
    positions: &[[f64; 3]],
    radii: &[f64],
    triangles: &[[u32; 3]],
    space: &dyn FreeSpace,
    options: &VoronoiOptions,
    stats: &mut VoronoiStats,
    ticker: &Ticker,
) -> Graph {
    let corrected: Vec<Option<f64>> = positions
        .par_iter()
        .zip(radii)
        .map_init(
            || ticker.local(),
            |done, (&p, &r)| {
                done.tick();
                // Samples lie on the walls, so the exact distance never exceeds C.
                let c = space.wall_distance_within(p, r).unwrap_or(r);
                let spurious = r <= options.spacing && c < 0.5 * options.spacing;
                (c >= options.min_clearance && !spurious).then_some(c)
            },
        )
        .collect();
    stats.removed_low_clearance = corrected.iter().filter(|c| c.is_none()).count();
    let mut new_id = vec![u32::MAX; positions.len()];
    let mut graph = Graph::default();
    for tri in triangles {
        if tri.iter().any(|&v| corrected[v as usize].is_none()) {
            continue;
        }
        let mut face = [0u32; 3];
        for (k, &v) in tri.iter().enumerate() {
            if new_id[v as usize] == u32::MAX {
                new_id[v as usize] = graph.vertices.len() as u32;
                graph.vertices.push(positions[v as usize]);
                graph.clearance.push(corrected[v as usize].unwrap_or(0.0));
            }
            face[k] = new_id[v as usize];
        }
        graph.faces.push(face);
    }
    stats.vertices = graph.vertices.len();
    stats.faces = graph.faces.len();
    graph
}

#[cfg(test)]
mod tests;
