//! What there is to draw: the map's walls as triangles, the graph's vertices,
//! faces and edges, and the compiler's sample points — loaded once, in world
//! coordinates, independent of any camera.

use crate::camera::Bounds;
use anyhow::{Context, Result, bail};
use bsp::Bsp;
use bsp::faces::FaceClass;
use glam::Vec3;
use std::path::Path;
use vdgformat::Vdg;

/// A wall triangle with its (unit) normal towards the free side.
#[derive(Debug, Clone, Copy)]
pub struct WallTriangle {
    pub pts: [Vec3; 3],
    pub normal: Vec3,
    pub sky: bool,
}

/// The graph as triangles with clearances, plus its unique edges for wireframes.
#[derive(Debug, Clone, Default)]
pub struct GraphMesh {
    pub positions: Vec<Vec3>,
    pub clearances: Vec<f32>,
    pub faces: Vec<[u32; 3]>,
    /// Unique vertex pairs, ascending.
    pub edges: Vec<[u32; 2]>,
    /// The clearance mapped to red (2nd percentile) and to blue (98th).
    pub colour_range: (f32, f32),
    /// Each vertex's clearance colour (0..=255 floats), computed once.
    pub colours: Vec<Vec3>,
}

/// Everything drawable.
#[derive(Debug, Clone)]
pub struct Scene {
    pub walls: Vec<WallTriangle>,
    pub graph: Option<GraphMesh>,
    pub samples: Vec<Vec3>,
    /// Bounds of the walls (or of the graph when the map has none).
    pub bounds: Bounds,
}

impl Scene {
    /// Builds a scene from a map, an optional graph and optional samples.
    pub fn new(bsp: &Bsp, graph: Option<&Vdg<'_>>, samples: Vec<Vec3>) -> Result<Scene> {
        let walls = wall_triangles(bsp);
        let graph = graph.map(GraphMesh::from_vdg);
        // Framing follows the walls, not the sky: an open-air level's sky brushes
        // reach far beyond its playable space.
        let bounds = Bounds::of(walls.iter().filter(|t| !t.sky).flat_map(|t| t.pts))
            .or_else(|| Bounds::of(walls.iter().flat_map(|t| t.pts)))
            .or_else(|| {
                graph
                    .as_ref()
                    .and_then(|g| Bounds::of(g.positions.iter().copied()))
            })
            .context("the map has no drawable faces and there is no graph")?;
        Ok(Scene {
            walls,
            graph,
            samples,
            bounds,
        })
    }
}

impl Scene {
    /// The points an automatic camera keeps in the picture: the wall corners
    /// (not the sky), or the graph's vertices when there are no walls.
    pub fn framing_points(&self) -> impl Iterator<Item = Vec3> + '_ {
        let walls = self.walls.iter().filter(|t| !t.sky).flat_map(|t| t.pts);
        let graph = self
            .graph
            .iter()
            .filter(|_| self.walls.iter().all(|t| t.sky))
            .flat_map(|g| g.positions.iter().copied());
        walls.chain(graph)
    }
}

/// Fans the world's visible faces (walls and sky; not triggers, clips or
/// liquids) into triangles.
pub fn wall_triangles(bsp: &Bsp) -> Vec<WallTriangle> {
    let mut out = Vec::new();
    for f in bsp::faces::polygons(bsp, 0) {
        let sky = match f.class {
            FaceClass::Wall => false,
            FaceClass::Sky => true,
            FaceClass::Skip(_) => continue,
        };
        let p: Vec<Vec3> = f
            .polygon
            .iter()
            .map(|v| Vec3::new(v[0] as f32, v[1] as f32, v[2] as f32))
            .collect();
        let normal = Vec3::new(f.normal[0] as f32, f.normal[1] as f32, f.normal[2] as f32);
        for k in 1..p.len().saturating_sub(1) {
            out.push(WallTriangle {
                pts: [p[0], p[k], p[k + 1]],
                normal,
                sky,
            });
        }
    }
    out
}

impl GraphMesh {
    /// Copies a graph's geometry out of the mapped file.
    pub fn from_vdg(g: &Vdg<'_>) -> GraphMesh {
        let positions: Vec<Vec3> = g.vertices().iter().map(|v| Vec3::from(v.pos)).collect();
        let clearances: Vec<f32> = g.vertices().iter().map(|v| v.clearance).collect();
        let faces = g.faces().to_vec();
        let mut edges: Vec<[u32; 2]> = faces
            .iter()
            .flat_map(|f| [[f[0], f[1]], [f[1], f[2]], [f[2], f[0]]])
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        let colour_range = percentile_range(&clearances);
        let mut mesh = GraphMesh {
            positions,
            clearances,
            faces,
            edges,
            colour_range,
            colours: Vec::new(),
        };
        mesh.colours = mesh
            .clearances
            .iter()
            .map(|&c| crate::render::ramp(mesh.clearance_t(c)))
            .collect();
        mesh
    }

    /// 0 for small clearance (red) … 1 for large (blue).
    pub fn clearance_t(&self, c: f32) -> f32 {
        let (lo, hi) = self.colour_range;
        if hi > lo {
            ((c - lo) / (hi - lo)).clamp(0.0, 1.0)
        } else {
            0.5
        }
    }
}

/// The 2nd and 98th percentiles, so a few extreme vertices do not wash out the
/// colour ramp.
fn percentile_range(values: &[f32]) -> (f32, f32) {
    if values.is_empty() {
        return (0.0, 1.0);
    }
    let mut v = values.to_vec();
    v.sort_unstable_by(f32::total_cmp);
    let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    (at(0.02), at(0.98))
}

/// Reads a samples file written by `bsp2vdg -savesamples`: `x y z` lines (the
/// qhull variant's one-number header lines are skipped).
pub fn read_samples(path: &Path) -> Result<Vec<Vec3>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read samples {}", path.display()))?;
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let nums: Vec<&str> = line.split_whitespace().collect();
        match nums.len() {
            0 | 1 => continue,
            3 => {
                let v: Option<Vec<f32>> = nums
                    .iter()
                    .map(|s| s.parse::<f32>().ok().filter(|x| x.is_finite()))
                    .collect();
                match v {
                    Some(v) => out.push(Vec3::new(v[0], v[1], v[2])),
                    None => bail!("{}:{}: not three numbers: {line:?}", path.display(), n + 1),
                }
            }
            _ => bail!("{}:{}: not three numbers: {line:?}", path.display(), n + 1),
        }
    }
    Ok(out)
}

/// Opens a map with a one-line error naming the file.
pub fn open_map(path: &Path) -> Result<Bsp> {
    // The error's own Display already names its cause; no source chain.
    Bsp::open(path).map_err(|e| anyhow::anyhow!("cannot read map {}: {e}", path.display()))
}

/// Opens a graph with a one-line error naming the file.
pub fn open_graph(path: &Path) -> Result<vdgformat::VdgFile> {
    vdgformat::VdgFile::open(path)
        .map_err(|e| anyhow::anyhow!("cannot read graph {}: {e}", path.display()))
}

/// Whether the graph was built from this map: the `.vdg` records the XXH64 of its
/// source map's bytes. `Err` names both files when it was built from another map (or
/// another version of this one); graphs that record no hash (0) pass.
pub fn same_map(map: &Path, graph_path: &Path, g: &vdgformat::Vdg<'_>) -> Result<()> {
    let recorded = g.info().source_hash;
    if recorded == 0 {
        return Ok(());
    }
    let bytes = std::fs::read(map).with_context(|| format!("cannot read map {}", map.display()))?;
    let hash = vdgformat::xxh64(&bytes, 0);
    if hash != recorded {
        anyhow::bail!(
            "{} was built from another map than {} (source hash {recorded:016x}, the map's is {hash:016x}); compile the map again or give the map it was built from",
            graph_path.display(),
            map.display()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_ignore_outliers() {
        let mut v: Vec<f32> = (0..100).map(|i| i as f32).collect();
        v.push(1e6);
        let (lo, hi) = percentile_range(&v);
        assert_eq!(lo, 2.0);
        assert!(hi < 100.0);
    }

    #[test]
    fn samples_parse_both_formats_and_reject_garbage() {
        let dir = std::env::temp_dir().join(format!("vdgview-samples-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("s.txt");
        std::fs::write(&p, "3\n2\n1 2 3\n4.5 5 -6\n").unwrap();
        assert_eq!(
            read_samples(&p).unwrap(),
            vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.5, 5.0, -6.0)]
        );
        std::fs::write(&p, "1 2 x\n").unwrap();
        let e = read_samples(&p).unwrap_err().to_string();
        assert!(e.contains(":1:"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
