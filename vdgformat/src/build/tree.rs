//! The thesis' BBox tree over the face volumes (6.1.6): the volume boxes
//! it is built from, the certified test that drops a cell a face's volume
//! misses, the build itself, and the search bounds of every node (which the
//! reader recomputes to validate a file).

use crate::geom::{Aabb, V3};
use crate::index::{FaceList, IndexList};
use crate::layout::{MAX_BUILD_DEPTH, NodeBounds, TreeNode, Vertex};

/// A leaf is not split further once it lists this many faces or fewer.
const LEAF_TARGET: usize = 8;

/// The triangle's box and its largest vertex clearance (see [`Reach`]).
pub(super) fn face_reach(vertices: &[Vertex], f: &[u32; 3], radii: [f32; 3]) -> Reach {
    let mut tri = Aabb::EMPTY;
    let mut r_max = 0.0f32;
    for (&vi, &r) in f.iter().zip(&radii) {
        let v = vertices[vi as usize];
        tri.grow(&Aabb {
            min: v.pos,
            max: v.pos,
        });
        r_max = r_max.max(r);
    }
    let balls = [0, 1, 2].map(|k| {
        let v = vertices[f[k] as usize];
        (V3::from_f32(v.pos), f64::from(radii[k]))
    });
    Reach { tri, r_max, balls }
}

/// is the convex hull of the vertex balls). Rounded outwards to f32 so
/// every point of the volume is inside the stored box.
/// The triangle's box and its largest vertex clearance (see [`Reach`]).
pub(super) fn face_box(vertices: &[Vertex], f: &[u32; 3], radii: [f32; 3]) -> Aabb {
    let mut b = Aabb::EMPTY;
    for (&vi, &r) in f.iter().zip(&radii) {
        let v = vertices[vi as usize];
        for i in 0..3 {
            let c = f64::from(v.pos[i]);
            let r = f64::from(r);
            b.min[i] = b.min[i].min(f32_down(c - r));
            b.max[i] = b.max[i].max(f32_up(c + r));
        }
    }
    b
}

/// Largest f32 ≤ x.
fn f32_down(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) > x {
        step_f32(f, false)
    } else {
        f
    }
}

/// Smallest f32 ≥ x.
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) < x {
        step_f32(f, true)
    } else {
        f
    }
}

/// The neighbouring f32 towards +∞ (`up`) or −∞; for finite non-NaN input.
fn step_f32(f: f32, up: bool) -> f32 {
    if f == 0.0 {
        let tiny = f32::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = f.to_bits();
    let away_from_zero = (f > 0.0) == up;
    f32::from_bits(if away_from_zero { bits + 1 } else { bits - 1 })
}

/// [`NodeBounds`] of every tree node. Nodes are in preorder, so a reverse
/// sweep sees children before parents. Shared by the writer and by the
/// reader, which recomputes them to validate the stored ones.
pub(crate) fn node_bounds(
    nodes: &[TreeNode],
    leaf_faces: IndexList<'_>,
    faces: FaceList<'_>,
    vertices: &[Vertex],
    face_radii: &[[f32; 3]],
) -> Vec<NodeBounds> {
    let empty = NodeBounds {
        tri_min: [0.0; 3],
        r_max: -1.0,
        tri_max: [0.0; 3],
        reserved: 0,
    };
    let mut out = vec![empty; nodes.len()];
    for i in (0..nodes.len()).rev() {
        let node = nodes[i];
        let mut acc = (Aabb::EMPTY, -1.0f32);
        let mut add = |min: [f32; 3], max: [f32; 3], r: f32| {
            if r >= 0.0 {
                acc.0.grow(&Aabb { min, max });
                acc.1 = acc.1.max(r);
            }
        };
        if node.kind == TreeNode::LEAF {
            for f in leaf_faces.range(node.a, node.b).iter() {
                let radii = crate::layout::corner_radii(faces, vertices, face_radii, f as usize);
                for (v, r) in faces.get(f).into_iter().zip(radii) {
                    let v = vertices[v as usize];
                    add(v.pos, v.pos, r);
                }
            }
        } else {
            for c in [node.a, node.b] {
                let b = out[c as usize];
                add(b.tri_min, b.tri_max, b.r_max);
            }
        }
        if acc.1 >= 0.0 {
            out[i] = NodeBounds {
                tri_min: acc.0.min,
                r_max: acc.1,
                tri_max: acc.0.max,
                reserved: 0,
            };
        }
    }
    out
}

pub(crate) struct Tree {
    pub nodes: Vec<TreeNode>,
    pub leaf_faces: Vec<u32>,
}

/// The thesis' BBox tree (6.1.6): the root cell is the box of Volume(VDG);
/// a cell is halved across its longest axis while the halves stay at least
/// `leaf_size` wide; a leaf lists every face whose volume box meets its cell.
/// We also stop when a cell holds few faces or a split separates nothing.
/// Nodes are stored in preorder (children after their parent).
pub(crate) fn build_tree(boxes: &[Aabb], reach: &[Reach], root: Aabb, leaf_size: f32) -> Tree {
    let mut tree = Tree {
        nodes: Vec::new(),
        leaf_faces: Vec::new(),
    };
    let all: Vec<u32> = (0..boxes.len() as u32).collect();
    let faces = Faces { boxes, reach };
    build_node(&mut tree, &faces, root, all, leaf_size, 0);
    tree
}

/// Where a face's volume can be: the union of the balls `B(q, r(q))` over the
/// triangle with the vertex clearances interpolated (the convex hull of the
/// three vertex balls). A cell holds a point of the volume exactly when
/// `min_{q ∈ triangle} dist(q, cell) − r(q) < 0`. The box tests of the writer
/// (the volume's box, then the triangle's box against `r_max`) keep a face in
/// every cell that meets its box; on open maps, where clearances reach hundreds
/// of units and big faces lie slanted, most of those cells miss the volume
/// itself. [`Reach::may_meet`] drops them with a certified lower bound on that
/// minimum, so a leaf lists only faces whose volume can meet its cell.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Reach {
    pub tri: Aabb,
    pub r_max: f32,
    /// The three vertices and their clearances, in f64.
    pub balls: [(V3, f64); 3],
}

/// Frank–Wolfe rounds [`Reach::may_meet`] spends before it keeps a face (conservatively).
const MEET_ROUNDS: usize = 24;

impl Reach {
    /// Whether the volume may meet `cell` (conservative: `true` when unsure).
    fn may_meet(&self, cell: &Aabb) -> bool {
        let mut d2 = 0.0f64;
        for i in 0..3 {
            let gap = (f64::from(cell.min[i]) - f64::from(self.tri.max[i]))
                .max(f64::from(self.tri.min[i]) - f64::from(cell.max[i]))
                .max(0.0);
            d2 += gap * gap;
        }
        let r = f64::from(self.r_max);
        // Slack for the f32 data and the rounding of the queries' evaluations.
        let slack = 1e-3 + 1e-6 * r;
        let r = r + slack;
        if d2 >= r * r {
            return false;
        }
        // Most faces that meet a cell have a corner ball in it: decided without a search.
        if self
            .balls
            .iter()
            .any(|&(v, r)| cell.distance2(v) < (r + slack) * (r + slack))
        {
            return true;
        }
        self.may_meet_exactly(cell, slack)
    }

    /// Minimises `f(λ) = dist(q(λ), cell) − r(λ)` over the triangle's barycentric
    /// coordinates by Frank–Wolfe. `f` is convex (a distance to a convex set minus
    /// a linear function), so at any `λ` the linearisation's minimum over the
    /// triangle's corners bounds `min f` from below (the duality gap): once that
    /// bound exceeds `slack`, no point of the volume lies in the cell. When a
    /// point with `f ≤ slack` turns up, or the rounds run out, the face is kept.
    fn may_meet_exactly(&self, cell: &Aabb, slack: f64) -> bool {
        let lo = V3(
            f64::from(cell.min[0]),
            f64::from(cell.min[1]),
            f64::from(cell.min[2]),
        );
        let hi = V3(
            f64::from(cell.max[0]),
            f64::from(cell.max[1]),
            f64::from(cell.max[2]),
        );
        let f_at = |lam: [f64; 3]| -> (f64, V3) {
            let q = self.balls[0].0 * lam[0] + self.balls[1].0 * lam[1] + self.balls[2].0 * lam[2];
            let r = self.balls[0].1 * lam[0] + self.balls[1].1 * lam[1] + self.balls[2].1 * lam[2];
            let clamp = V3(
                q.0.clamp(lo.0, hi.0),
                q.1.clamp(lo.1, hi.1),
                q.2.clamp(lo.2, hi.2),
            );
            let d = q - clamp;
            let n = d.norm();
            let grad = if n > 0.0 {
                d * (1.0 / n)
            } else {
                V3(0.0, 0.0, 0.0)
            };
            (n - r, grad)
        };
        // Start at the best corner.
        let mut lam = [0.0; 3];
        let mut best = (f64::INFINITY, 0);
        for (i, _) in self.balls.iter().enumerate() {
            let mut e = [0.0; 3];
            e[i] = 1.0;
            let v = f_at(e).0;
            if v < best.0 {
                best = (v, i);
            }
        }
        lam[best.1] = 1.0;
        for _ in 0..MEET_ROUNDS {
            let (f, g) = f_at(lam);
            if f <= slack {
                return true;
            }
            // Gradient in λ: ∂f/∂λ_i = g·v_i − r_i.
            let h = self.balls.map(|(v, r)| g.dot(v) - r);
            let (s, hmin) = (0..3).fold(
                (0, f64::INFINITY),
                |a, i| if h[i] < a.1 { (i, h[i]) } else { a },
            );
            let at = lam[0] * h[0] + lam[1] * h[1] + lam[2] * h[2];
            let lower = f + hmin - at;
            if lower > slack {
                return false;
            }
            // Golden-section line search towards corner s (f is convex along the segment).
            let towards = |t: f64| {
                let mut l = lam.map(|x| x * (1.0 - t));
                l[s] += t;
                l
            };
            let (mut a, mut b) = (0.0f64, 1.0f64);
            const PHI: f64 = 0.618_033_988_749_894_9;
            let mut c = b - PHI * (b - a);
            let mut d = a + PHI * (b - a);
            let (mut fc, mut fd) = (f_at(towards(c)).0, f_at(towards(d)).0);
            for _ in 0..16 {
                if fc < fd {
                    b = d;
                    d = c;
                    fd = fc;
                    c = b - PHI * (b - a);
                    fc = f_at(towards(c)).0;
                } else {
                    a = c;
                    c = d;
                    fc = fd;
                    d = a + PHI * (b - a);
                    fd = f_at(towards(d)).0;
                }
            }
            lam = towards(0.5 * (a + b));
        }
        true
    }
}

/// The per-face data the tree is built from.
struct Faces<'a> {
    /// The volume boxes (see [`face_box`]).
    boxes: &'a [Aabb],
    reach: &'a [Reach],
}

fn build_node(
    tree: &mut Tree,
    all: &Faces<'_>,
    cell: Aabb,
    faces: Vec<u32>,
    bb: f32,
    depth: usize,
) {
    let boxes = all.boxes;
    let me = tree.nodes.len();
    tree.nodes.push(TreeNode {
        kind: TreeNode::LEAF,
        split: 0.0,
        a: 0,
        b: 0,
    });
    let extent = |i: usize| cell.max[i] - cell.min[i];
    let axis = (0..3)
        .max_by(|&i, &j| extent(i).total_cmp(&extent(j)).then(j.cmp(&i)))
        .unwrap_or(0);
    let split = cell.min[axis] + 0.5 * extent(axis);
    let splittable = faces.len() > LEAF_TARGET
        && depth < MAX_BUILD_DEPTH
        && extent(axis) >= 2.0 * bb
        && split > cell.min[axis]
        && split < cell.max[axis];
    if splittable {
        let mut lcell = cell;
        lcell.max[axis] = split;
        let mut rcell = cell;
        rcell.min[axis] = split;
        let left: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| {
                boxes[f as usize].min[axis] <= split && all.reach[f as usize].may_meet(&lcell)
            })
            .collect();
        let right: Vec<u32> = faces
            .iter()
            .copied()
            .filter(|&f| {
                boxes[f as usize].max[axis] >= split && all.reach[f as usize].may_meet(&rcell)
            })
            .collect();
        if left.len() < faces.len() || right.len() < faces.len() {
            drop(faces);
            let l = tree.nodes.len() as u32;
            build_node(tree, all, lcell, left, bb, depth + 1);
            let r = tree.nodes.len() as u32;
            build_node(tree, all, rcell, right, bb, depth + 1);
            tree.nodes[me] = TreeNode {
                kind: axis as u32,
                split,
                a: l,
                b: r,
            };
            return;
        }
    }
    tree.nodes[me] = TreeNode {
        kind: TreeNode::LEAF,
        split: 0.0,
        a: tree.leaf_faces.len() as u32,
        b: faces.len() as u32,
    };
    tree.leaf_faces.extend_from_slice(&faces);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::VdgBuilder;

    #[test]
    fn outward_rounding() {
        for x in [0.1f64, -0.1, 1e-30, -1e-30, 12345.678, 0.0, -7.25] {
            assert!(f64::from(f32_down(x)) <= x);
            assert!(f64::from(f32_up(x)) >= x);
            assert!(f64::from(f32_up(x)) - f64::from(f32_down(x)) <= x.abs() * 1e-6 + 1e-40);
        }
    }

    /// `min_{q ∈ triangle} dist(q, cell) − r(q)` on a fine barycentric grid: an
    /// upper bound on the true minimum, within grid spacing of it.
    fn sampled_gap(reach: &Reach, cell: &Aabb) -> f64 {
        let n = 60;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n - i {
                let l = [
                    i as f64 / n as f64,
                    j as f64 / n as f64,
                    (n - i - j) as f64 / n as f64,
                ];
                let q = reach.balls[0].0 * l[0] + reach.balls[1].0 * l[1] + reach.balls[2].0 * l[2];
                let r = reach.balls[0].1 * l[0] + reach.balls[1].1 * l[1] + reach.balls[2].1 * l[2];
                best = best.min(cell.distance(q) - r);
            }
        }
        best
    }

    #[test]
    fn a_cell_is_dropped_only_when_the_volume_misses_it() {
        let mut rng = toolbox::SplitMix64::new(7);
        let (mut dropped, mut kept_far) = (0, 0);
        for _ in 0..4000 {
            let mut b = VdgBuilder::new();
            let vs: Vec<u32> = (0..3)
                .map(|_| {
                    let p = [0; 3].map(|_| rng.range(-300.0, 300.0) as f32);
                    b.add_vertex(p, rng.range(0.0, 200.0) as f32)
                })
                .collect();
            let f = [vs[0], vs[1], vs[2]];
            let reach = face_reach(&b.vertices, &f, f.map(|v| b.vertices[v as usize].clearance));
            let lo = [0; 3].map(|_| rng.range(-500.0, 400.0) as f32);
            let size = [0; 3].map(|_| rng.range(10.0, 300.0) as f32);
            let cell = Aabb {
                min: lo,
                max: [0, 1, 2].map(|i| lo[i] + size[i]),
            };
            let gap = sampled_gap(&reach, &cell);
            if !reach.may_meet(&cell) {
                dropped += 1;
                assert!(gap > 0.0, "dropped a cell the volume meets (gap {gap})");
            } else if gap > 10.0 {
                kept_far += 1;
            }
        }
        // The test is tight: cells missed by more than 10 units are nearly always dropped.
        assert!(dropped > 500, "{dropped}");
        assert!(
            kept_far * 50 < dropped,
            "kept {kept_far} far cells, dropped {dropped}"
        );
    }

    #[test]
    fn tree_leaves_respect_leaf_size() {
        // 1000 tiny boxes spread over [0, 4096]: cells never shrink below bb.
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| {
                let x = (i as f32 * 37.0) % 4096.0;
                let y = (i as f32 * 91.0) % 4096.0;
                Aabb {
                    min: [x, y, 0.0],
                    max: [x + 1.0, y + 1.0, 1.0],
                }
            })
            .collect();
        let root = Aabb {
            min: [0.0; 3],
            max: [4097.0, 4097.0, 1.0],
        };
        // Point triangles at the box centres with radius 0.5: their volumes fill the boxes.
        let reach: Vec<Reach> = boxes
            .iter()
            .map(|b| {
                let c = [0, 1, 2].map(|i| 0.5 * (b.min[i] + b.max[i]));
                Reach {
                    tri: Aabb { min: c, max: c },
                    r_max: 0.5,
                    balls: [(V3::from_f32(c), 0.5); 3],
                }
            })
            .collect();
        let tree = build_tree(&boxes, &reach, root, 256.0);
        let mut stack = vec![(0usize, root)];
        let mut seen = vec![false; boxes.len()];
        while let Some((n, cell)) = stack.pop() {
            let node = tree.nodes[n];
            if node.kind == TreeNode::LEAF {
                for i in 0..3 {
                    assert!(cell.max[i] - cell.min[i] >= 256.0 || i == 2);
                }
                for &f in &tree.leaf_faces[node.a as usize..(node.a + node.b) as usize] {
                    seen[f as usize] = true;
                }
            } else {
                let ax = node.kind as usize;
                let (mut l, mut r) = (cell, cell);
                l.max[ax] = node.split;
                r.min[ax] = node.split;
                stack.push((node.a as usize, l));
                stack.push((node.b as usize, r));
            }
        }
        assert!(seen.iter().all(|&s| s));
        assert!(tree.nodes.len() > 1);
    }
}
