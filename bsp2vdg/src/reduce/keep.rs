//! Points the reduction keeps inside the volume (not in the thesis): the places where
//! a standing player is, so that the camera's target stays where `Visible` can see it.
//! Where keeping them and reaching `-rl` conflict, keeping them wins.
//!
//! Each kept point is held by one face whose volume contains it. A removal is refused
//! when a point held by a face it removes or lowers is then inside none of the faces
//! around the removal (the faces of the vertices it touches — inside the two-ring
//! that the batches keep independent); after a removal those points move to such a
//! face. Points the unreduced volume does not contain are not kept.

use std::collections::HashMap;

use smallvec::SmallVec;

use super::mesh::{Changes, Edit, Mesh};
use super::volume::P3;

/// Cell size of the one-off face grid that finds each point's first holder.
const CELL: f64 = 64.0;

pub(crate) struct Keep {
    points: Vec<P3>,
    /// Per face id, the points it holds.
    held: Vec<SmallVec<[u32; 2]>>,
}

fn face_clearance(mesh: &Mesh, f: u32, p: P3) -> f64 {
    let t = mesh.faces[f as usize];
    vdgformat::triangle_clearance(
        t.map(|v| (mesh.pos[v as usize], mesh.clearance[v as usize])),
        p,
    )
}

fn cell_of(p: P3) -> [i32; 3] {
    p.map(|c| (c / CELL).floor() as i32)
}

impl Keep {
    /// The points of `points` inside the mesh's volume, each held by the face whose
    /// volume holds it deepest.
    pub fn new(mesh: &Mesh, points: &[P3]) -> Keep {
        let mut held = vec![SmallVec::new(); mesh.faces.len()];
        let mut grid: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
        let wanted: std::collections::HashSet<[i32; 3]> =
            points.iter().map(|&p| cell_of(p)).collect();
        for (f, t) in mesh.faces.iter().enumerate() {
            if !mesh.alive[f] {
                continue;
            }
            let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
            for &v in t {
                let (c, r) = (mesh.pos[v as usize], mesh.clearance[v as usize]);
                for i in 0..3 {
                    lo[i] = lo[i].min(c[i] - r);
                    hi[i] = hi[i].max(c[i] + r);
                }
            }
            let (a, b) = (cell_of(lo), cell_of(hi));
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        if wanted.contains(&[x, y, z]) {
                            grid.entry([x, y, z]).or_default().push(f as u32);
                        }
                    }
                }
            }
        }
        let mut kept = Vec::new();
        for &p in points {
            let best = grid.get(&cell_of(p)).and_then(|faces| {
                faces
                    .iter()
                    .map(|&f| (face_clearance(mesh, f, p), f))
                    .filter(|x| x.0 > 0.0)
                    .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
            });
            if let Some((_, f)) = best {
                held[f as usize].push(kept.len() as u32);
                kept.push(p);
            }
        }
        Keep { points: kept, held }
    }

    /// How many points are kept.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Faces whose points an edit puts at risk: the old faces it removes and the
    /// old faces of the vertices it lowers.
    fn at_risk<'a>(&'a self, ch: &'a Changes, base: &'a Mesh) -> impl Iterator<Item = u32> + 'a {
        let old = base.faces.len() as u32;
        ch.removed
            .iter()
            .copied()
            .filter(move |&f| f < old)
            .chain(
                ch.radii
                    .iter()
                    .flat_map(move |&(v, _)| base.vfaces[v as usize].iter().copied()),
            )
            .filter(move |&f| !self.held[f as usize].is_empty())
    }

    /// Whether every point the edit puts at risk is still inside a face around it.
    pub fn holds(&self, e: &Edit) -> bool {
        let ch = e.changes();
        let touched = ch.touched();
        self.at_risk(ch, e.base).all(|f| {
            self.held[f as usize].iter().all(|&i| {
                let p = self.points[i as usize];
                (!ch.removed.contains(&f) && e.clearance_at(f, p) > 0.0)
                    || touched
                        .iter()
                        .any(|&v| e.faces_of(v).iter().any(|&g| e.clearance_at(g, p) > 0.0))
            })
        })
    }

    /// The faces at risk of `ch` before it is applied (see [`Keep::rehome`]).
    pub fn before_apply(&self, ch: &Changes, base: &Mesh) -> Vec<u32> {
        let mut v: Vec<u32> = self.at_risk(ch, base).collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// After an edit was applied: the points of the faces at risk move to a face
    /// around the edit that holds them (the one that holds them deepest).
    pub fn rehome(&mut self, mesh: &Mesh, at_risk: &[u32], touched: &[u32]) {
        self.held.resize(mesh.faces.len(), SmallVec::new());
        for &f in at_risk {
            let points = std::mem::take(&mut self.held[f as usize]);
            for i in points {
                let p = self.points[i as usize];
                let home = if mesh.alive[f as usize] && face_clearance(mesh, f, p) > 0.0 {
                    Some(f)
                } else {
                    touched
                        .iter()
                        .flat_map(|&v| mesh.vfaces[v as usize].iter().copied())
                        .map(|g| (face_clearance(mesh, g, p), g))
                        .filter(|x| x.0 > 0.0)
                        .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)))
                        .map(|x| x.1)
                };
                debug_assert!(home.is_some(), "kept point {p:?} lost its face");
                if let Some(g) = home {
                    self.held[g as usize].push(i);
                }
            }
        }
    }
}
