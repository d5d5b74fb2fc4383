//! Contents from the brushes a Quake 2 map keeps: a box (the player's) against the
//! brushes touching the leaves the box reaches, as the game's `CM_BoxTrace` does.
//! qbsp stores every brush with its axial and edge bevel sides, so moving each side
//! plane out by the box's support distance gives the box's exact collision.

use crate::Bsp;
use toolbox::vec3::dot;

/// One brush as planes `normal · x <= dist` (inside) and its native contents.
#[derive(Debug, Clone)]
struct BrushGeom {
    planes: Vec<([f64; 3], f64)>,
    contents: i32,
}

/// A model's tree with the brushes of its leaves.
#[derive(Debug, Clone)]
pub struct BrushSet {
    /// Per node: plane, children (`< 0`: leaf `-(c + 1)`).
    nodes: Vec<([f64; 3], f64, [i32; 2])>,
    root: i32,
    /// Per leaf: its brushes (indices into `brushes`).
    leaf_brushes: Vec<Vec<u32>>,
    brushes: Vec<BrushGeom>,
    /// The brushes some leaf lists (the exhaustive test's candidates).
    listed: Vec<u32>,
}

impl BrushSet {
    /// The brushes of model `model`'s tree, or `None` when the map keeps no brushes.
    pub fn new(bsp: &Bsp, model: usize) -> Option<BrushSet> {
        if bsp.brushes.is_empty() {
            return None;
        }
        let plane = |i: u32| {
            let p = &bsp.planes[i as usize];
            (p.normal.map(f64::from), p.dist as f64)
        };
        let nodes = bsp
            .nodes
            .iter()
            .map(|n| {
                let (normal, dist) = plane(n.plane);
                (normal, dist, n.children)
            })
            .collect();
        let leaf_brushes = bsp
            .leaves
            .iter()
            .map(|l| bsp.leaf_brushes[l.first_brush as usize..][..l.num_brushes as usize].to_vec())
            .collect();
        let brushes = bsp
            .brushes
            .iter()
            .map(|b| BrushGeom {
                planes: bsp.brush_sides(b).iter().map(|s| plane(s.plane)).collect(),
                contents: b.contents,
            })
            .collect();
        let root = bsp.models[model].headnode[0];
        let listed = listed_brushes(bsp, model);
        Some(BrushSet {
            listed,
            nodes,
            root,
            leaf_brushes,
            brushes,
        })
    }

    /// The OR of the native contents of the brushes whose inside meets the box
    /// `p + mins ..= p + maxs` (a point when both are zero). Touching a brush's surface
    /// is not meeting it, as in the game.
    pub fn box_contents(&self, p: [f64; 3], mins: [f64; 3], maxs: [f64; 3]) -> i32 {
        let lo = [0, 1, 2].map(|i| p[i] + mins[i]);
        let hi = [0, 1, 2].map(|i| p[i] + maxs[i]);
        let mut flags = 0;
        let mut stack = vec![self.root];
        while let Some(n) = stack.pop() {
            if n < 0 {
                for &b in &self.leaf_brushes[(-(n + 1)) as usize] {
                    let b = &self.brushes[b as usize];
                    if flags & b.contents != b.contents && box_meets(b, p, mins, maxs) {
                        flags |= b.contents;
                    }
                }
                continue;
            }
            let (normal, dist, children) = &self.nodes[n as usize];
            // The box's extreme distances from the plane.
            let (mut dmin, mut dmax) = (-dist, -dist);
            for i in 0..3 {
                let (a, b) = (normal[i] * lo[i], normal[i] * hi[i]);
                dmin += a.min(b);
                dmax += a.max(b);
            }
            if dmin >= 0.0 {
                stack.push(children[0]);
            } else if dmax < 0.0 {
                stack.push(children[1]);
            } else {
                stack.push(children[0]);
                stack.push(children[1]);
            }
        }
        flags
    }

    /// The leaf of the tree that holds `p` (front on the plane, as the engine).
    pub fn leaf_at(&self, p: [f64; 3]) -> usize {
        let mut n = self.root;
        while n >= 0 {
            let (normal, dist, children) = &self.nodes[n as usize];
            n = children[(dot(*normal, p) - dist < 0.0) as usize];
        }
        (-(n + 1)) as usize
    }

    /// Ground truth without the tree: the OR of the contents of every brush the
    /// point lies strictly inside (for tests and measurements).
    pub fn point_contents_exhaustive(&self, p: [f64; 3]) -> i32 {
        self.listed
            .iter()
            .map(|&b| &self.brushes[b as usize])
            .filter(|b| box_meets(b, p, [0.0; 3], [0.0; 3]))
            .fold(0, |f, b| f | b.contents)
    }
}

/// The brushes the leaves of model `model`'s tree list (every model has its own
/// tree), sorted, each once.
pub(crate) fn listed_brushes(bsp: &Bsp, model: usize) -> Vec<u32> {
    let root = bsp.models[model].headnode[0];
    let mut listed: Vec<u32> = Vec::new();
    let mut stack = vec![root];
    let mut seen = vec![false; bsp.nodes.len()];
    while let Some(n) = stack.pop() {
        if n < 0 {
            let l = &bsp.leaves[(-(n + 1)) as usize];
            listed.extend_from_slice(
                &bsp.leaf_brushes[l.first_brush as usize..][..l.num_brushes as usize],
            );
        } else if !std::mem::replace(&mut seen[n as usize], true) {
            stack.extend(bsp.nodes[n as usize].children);
        }
    }
    listed.sort_unstable();
    listed.dedup();
    listed
}

/// Whether the box `p + mins ..= p + maxs` meets the brush's inside: `p` lies behind
/// every side plane moved out by the box's support distance along its normal.
fn box_meets(b: &BrushGeom, p: [f64; 3], mins: [f64; 3], maxs: [f64; 3]) -> bool {
    !b.planes.is_empty()
        && b.planes.iter().all(|(n, d)| {
            let support: f64 = (0..3).map(|i| (n[i] * mins[i]).min(n[i] * maxs[i])).sum();
            dot(*n, p) + support < *d
        })
}
