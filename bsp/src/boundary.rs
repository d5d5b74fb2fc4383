//! The obstacle boundary as the map's BSP tree itself describes it.
//!
//! A map's face list is not the whole boundary of its free space: compilers drop the
//! faces nobody is meant to see (ZHLT's `NULL` texture, faces inside other brushes),
//! yet the hull-0 tree still makes those brushes solid. On some maps whole blocks under
//! walkable rooftops have no faces at all, and a graph built from faces alone reached
//! into them. The tree, not the face list, is what the engine collides with and what
//! the oracle answers, so walls are taken from the tree: it splits space into convex
//! leaves, and wherever a free leaf touches an obstacle leaf, the shared piece of their
//! lowest common ancestor's plane is wall. Those pieces are the portals of qbsp and vis
//! restricted to free/obstacle pairs, found here the same way: each node's plane,
//! clipped to the node's cell, is pushed down both subtrees and split by their planes.
//!
//! ```no_run
//! use bsp::{boundary, Bsp, oracle::OracleOptions};
//! let bsp = Bsp::open("maps/crossfire.bsp")?;
//! let walls = boundary::of_map(&bsp, &OracleOptions::default());
//! let area: f64 = walls.iter().map(|w| w.area()).sum();
//! println!("{} wall polygons, {area:.0} square units", walls.len());
//! # Ok::<(), bsp::BspError>(())
//! ```

use rayon::prelude::*;
use toolbox::vec3::polygon_area as area;
use toolbox::vec3::{cross, dot};

use crate::oracle::OracleOptions;
use crate::{Bsp, contents};

type P = [f64; 3];

/// Points closer than this to a plane count as on it. The planes are stored as f32, so
/// coordinates carry errors around 1e-4 at map scale; qbsp uses 0.1 for the same test.
const ON_PLANE: f64 = 0.01;

/// Pieces thinner than this (in square units of area) are dropped: slivers of the
/// splitting that bound nothing a sample or a distance query could notice.
const MIN_AREA: f64 = 1e-3;

/// Deepest node considered; real maps are 20–60 deep.
const MAX_DEPTH: usize = 1024;

/// A node of the tree walk: its parent's index in the walk and the parent's
/// half-space it lies in (`None` for the root).
struct CellNode {
    node: u32,
    parent: Option<(u32, Plane)>,
}

/// A convex piece of the boundary between free space and an obstacle.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryPolygon {
    /// The corners, in order, in world coordinates.
    pub vertices: Vec<P>,
    /// Unit normal pointing into free space.
    pub normal: P,
    /// The contents on the obstacle side (solid, sky, or a liquid when liquids block).
    pub obstacle: i32,
}

impl BoundaryPolygon {
    /// The polygon's area.
    pub fn area(&self) -> f64 {
        area(&self.vertices)
    }
}

/// The boundary of the map's free space under `options`: the world's tree (solid and
/// sky, liquids too when they block) and the trees of the blocking brush models, placed
/// at their entities' origins. Deterministic: the order follows the trees.
pub fn of_map(bsp: &Bsp, options: &OracleOptions) -> Vec<BoundaryPolygon> {
    let mut out = of_tree(bsp, 0, [0.0; 3], |c| options.blocks(c));
    for &m in &options.solid_models {
        if m == 0 || m >= bsp.models.len() {
            continue;
        }
        let origin = bsp
            .entity_of_model(m)
            .and_then(|e| e.origin())
            .unwrap_or([0.0; 3])
            .map(f64::from);
        out.extend(of_tree(bsp, m, origin, |c| c == contents::SOLID));
    }
    out
}

/// The boundary between the leaves of model `model`'s hull-0 tree for which `blocks`
/// is false and those for which it is true, translated by `origin`.
pub fn of_tree(
    bsp: &Bsp,
    model: usize,
    origin: P,
    blocks: impl Fn(i32) -> bool + Sync,
) -> Vec<BoundaryPolygon> {
    let tree = Tree::new(bsp, model);
    let cells = tree.node_cells();
    let per_node: Vec<Vec<BoundaryPolygon>> = (0..cells.len())
        .into_par_iter()
        .map(|i| tree.portals_of(cells[i].node, &Tree::cell_of(&cells, i), &blocks))
        .collect();
    let mut out: Vec<BoundaryPolygon> = per_node.into_iter().flatten().collect();
    for p in &mut out {
        for v in &mut p.vertices {
            *v = [v[0] + origin[0], v[1] + origin[1], v[2] + origin[2]];
        }
    }
    out
}

/// A plane `normal · x = dist`; "front" is `normal · x - dist >= 0` as in the engine.
#[derive(Debug, Clone, Copy)]
struct Plane {
    normal: P,
    dist: f64,
}

impl Plane {
    fn distance(&self, p: P) -> f64 {
        dot(self.normal, p) - self.dist
    }

    /// A unit normal and a finite distance: what a valid map has. Corrupt maps may
    /// not, and such a node bounds nothing here.
    fn is_sound(&self) -> bool {
        let l = dot(self.normal, self.normal);
        self.dist.is_finite() && (l - 1.0).abs() < 1e-3
    }

    fn flipped(self) -> Plane {
        Plane {
            normal: self.normal.map(|c| -c),
            dist: -self.dist,
        }
    }
}

/// A model's hull-0 tree in f64, with leaf children replaced by their contents.
struct Tree {
    planes: Vec<Plane>,
    children: Vec<[Child; 2]>,
    root: Child,
    /// The model's box, a little enlarged: leaves reach to infinity, walls do not.
    bounds: (P, P),
}

#[derive(Debug, Clone, Copy)]
enum Child {
    Node(u32),
    Leaf(i32),
}

/// Where a polygon lies relative to a plane.
enum Side {
    Front,
    Back,
    On,
    Split(Vec<P>, Vec<P>),
}

impl Tree {
    fn new(bsp: &Bsp, model: usize) -> Tree {
        let child = |c: i32| {
            if c >= 0 {
                Child::Node(c as u32)
            } else {
                // Contents >= 0 are not part of the Quake family; like the oracle, solid.
                let k = bsp.leaves[(-(c + 1)) as usize].contents;
                Child::Leaf(if k >= 0 { contents::SOLID } else { k })
            }
        };
        let m = &bsp.models[model];
        // Real maps stay within ±32768 units; a corrupt box must not make the base
        // polygons overflow.
        let limit = |c: f32, pad: f64| (c as f64 + pad).clamp(-1e6, 1e6);
        Tree {
            planes: bsp
                .nodes
                .iter()
                .map(|n| {
                    let p = &bsp.planes[n.plane as usize];
                    Plane {
                        normal: p.normal.map(f64::from),
                        dist: p.dist as f64,
                    }
                })
                .collect(),
            children: bsp.nodes.iter().map(|n| n.children.map(child)).collect(),
            root: child(m.headnode[0]),
            bounds: (
                m.mins.map(|c| limit(c, -16.0)),
                m.maxs.map(|c| limit(c, 16.0)),
            ),
        }
    }

    /// Every node reachable from the root, in depth-first order so the output order
    /// is fixed, with the index (in this list) of its parent and the half-space of
    /// the parent it lies in: following the parents gives the node's cell. Storing
    /// parents instead of whole cells keeps memory linear however deep the tree.
    /// Nodes deeper than [`MAX_DEPTH`] are left out: no compiler makes such trees, and
    /// a corrupt map must not cost time quadratic in its node count.
    fn node_cells(&self) -> Vec<CellNode> {
        let mut out = Vec::new();
        let Child::Node(root) = self.root else {
            return out;
        };
        // The loader checked the tree is acyclic, so this terminates.
        let mut stack = vec![(root, None, 0usize)];
        while let Some((n, parent, depth)) = stack.pop() {
            let me = out.len() as u32;
            out.push(CellNode { node: n, parent });
            if depth >= MAX_DEPTH {
                continue;
            }
            let plane = self.planes[n as usize];
            let [front, back] = self.children[n as usize];
            if let Child::Node(b) = back {
                stack.push((b, Some((me, plane.flipped())), depth + 1));
            }
            if let Child::Node(f) = front {
                stack.push((f, Some((me, plane)), depth + 1));
            }
        }
        out
    }

    /// The half-spaces bounding the cell of `cells[i]`.
    fn cell_of(cells: &[CellNode], i: usize) -> Vec<Plane> {
        let mut out = Vec::new();
        let mut at = cells[i].parent;
        while let Some((p, h)) = at {
            out.push(h);
            at = cells[p as usize].parent;
        }
        out
    }

    /// The free/obstacle pieces of node `n`'s plane inside its cell.
    fn portals_of(
        &self,
        n: u32,
        cell: &[Plane],
        blocks: &impl Fn(i32) -> bool,
    ) -> Vec<BoundaryPolygon> {
        let plane = self.planes[n as usize];
        if !plane.is_sound() {
            return Vec::new();
        }
        let Some(mut poly) = self.base_polygon(plane) else {
            return Vec::new();
        };
        for h in cell {
            poly = clip_to_front(&poly, *h);
            if poly.len() < 3 {
                return Vec::new();
            }
        }
        let [front, back] = self.children[n as usize];
        let mut out = Vec::new();
        for (piece, cf) in self.filter(poly, front, plane, true) {
            for (piece, cb) in self.filter(piece, back, plane, false) {
                let (free_front, free_back) = (!blocks(cf), !blocks(cb));
                if free_front == free_back || area(&piece) < MIN_AREA {
                    continue;
                }
                let (normal, obstacle, vertices) = if free_front {
                    (plane.normal, cb, piece)
                } else {
                    (
                        plane.normal.map(|c| -c),
                        cf,
                        piece.into_iter().rev().collect(),
                    )
                };
                out.push(BoundaryPolygon {
                    vertices,
                    normal,
                    obstacle,
                });
            }
        }
        out
    }

    /// A square on `plane` larger than the model, clipped to the model's box.
    fn base_polygon(&self, plane: Plane) -> Option<Vec<P>> {
        let (lo, hi) = self.bounds;
        if !(0..3).all(|i| lo[i] < hi[i]) {
            return None;
        }
        let centre = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let size = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max) * 2.0;
        let n = plane.normal;
        let major = (0..3)
            .max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))
            .unwrap_or(2);
        let up = if major == 2 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let u = normalize(cross(up, n));
        let v = cross(n, u);
        let h = plane.distance(centre);
        let o = [0, 1, 2].map(|i| centre[i] - h * n[i]);
        let corner = |a: f64, b: f64| [0, 1, 2].map(|i| o[i] + size * (a * u[i] + b * v[i]));
        let mut poly = vec![
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        for axis in 0..3 {
            let e = [0, 1, 2].map(|i| if i == axis { 1.0 } else { 0.0 });
            poly = clip_to_front(
                &poly,
                Plane {
                    normal: e,
                    dist: lo[axis],
                },
            );
            poly = clip_to_front(
                &poly,
                Plane {
                    normal: e.map(|c: f64| -c),
                    dist: -hi[axis],
                },
            );
        }
        (poly.len() >= 3).then_some(poly)
    }

    /// Splits `poly`, which lies on `on` with the region of interest on its front
    /// (`front == true`) or back, by the subtree `start` into pieces with the contents
    /// of the leaf each ends in.
    fn filter(&self, poly: Vec<P>, start: Child, on: Plane, front: bool) -> Vec<(Vec<P>, i32)> {
        let mut out = Vec::new();
        let mut stack = vec![(poly, start)];
        while let Some((poly, at)) = stack.pop() {
            let n = match at {
                Child::Leaf(c) => {
                    out.push((poly, c));
                    continue;
                }
                Child::Node(n) => n as usize,
            };
            let plane = self.planes[n];
            let [f, b] = self.children[n];
            match classify(&poly, plane) {
                Side::Front => stack.push((poly, f)),
                Side::Back => stack.push((poly, b)),
                // The polygon lies on this node's plane: the region of interest is on
                // `on`'s `front` side, which is this plane's front when both face alike.
                Side::On => {
                    let same = dot(plane.normal, on.normal) > 0.0;
                    stack.push((poly, if same == front { f } else { b }));
                }
                Side::Split(pf, pb) => {
                    stack.push((pb, b));
                    stack.push((pf, f));
                }
            }
        }
        out
    }
}

fn classify(poly: &[P], plane: Plane) -> Side {
    let (mut front, mut back) = (false, false);
    for &p in poly {
        let d = plane.distance(p);
        front |= d > ON_PLANE;
        back |= d < -ON_PLANE;
    }
    match (front, back) {
        (true, false) => Side::Front,
        (false, true) => Side::Back,
        (false, false) => Side::On,
        (true, true) => Side::Split(
            clip_to_front(poly, plane),
            clip_to_front(poly, plane.flipped()),
        ),
    }
}

/// The part of a convex polygon in front of (or on) `plane` (Sutherland–Hodgman).
fn clip_to_front(poly: &[P], plane: Plane) -> Vec<P> {
    let d: Vec<f64> = poly.iter().map(|&p| plane.distance(p)).collect();
    if d.iter().all(|&x| x >= -ON_PLANE) {
        return poly.to_vec();
    }
    if d.iter().all(|&x| x <= ON_PLANE) {
        return Vec::new();
    }
    let mut out = Vec::with_capacity(poly.len() + 1);
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        let (a, b, da, db) = (poly[i], poly[j], d[i], d[j]);
        if da >= -ON_PLANE {
            out.push(a);
        }
        // A proper crossing: one end clearly in front, the other clearly behind.
        if (da > ON_PLANE && db < -ON_PLANE) || (da < -ON_PLANE && db > ON_PLANE) {
            let t = da / (da - db);
            out.push([0, 1, 2].map(|k| a[k] + t * (b[k] - a[k])));
        }
    }
    if out.len() < 3 { Vec::new() } else { out }
}

fn normalize(a: P) -> P {
    let l = dot(a, a).sqrt();
    a.map(|c| c / l)
}
