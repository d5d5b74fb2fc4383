//! Carving brushes into a BSP tree, so that every leaf has one contents value.
//!
//! q3map2 builds the tree from structural brushes; detail brushes, player clip and
//! liquids are only listed in the leaves they touch, and the game tests them one by
//! one (`CM_TestInLeaf`). The tools here walk the tree and want leaves that are
//! wholly solid or wholly free, so each leaf is refined: its cell (a convex polytope)
//! is split by the side planes of each listed brush that cuts it, the pieces outside
//! go on to the next brush and the piece inside takes the brush's contents. A piece
//! inside a solid brush stops there. Brushes are visited solid first, which keeps the
//! subtrees small (a solid piece needs no further splitting).
//!
//! The same carving builds the player's clip hulls of Quake 2 and 3 from their
//! brushes moved out by the player's box ([`crate::oracle::Hull::from_brushes`]).

use crate::map::{Leaf, Node};
use toolbox::vec3::{cross, dot, sub};

type P = [f64; 3];

/// Vertices closer than this to a plane count as on it: a cell is split only when it
/// reaches further than this to both sides.
const ON_PLANE: f64 = 0.01;

/// A convex polytope as its faces' windings (orientation is not kept: only the
/// vertices and edges matter for splitting).
#[derive(Debug, Clone)]
pub(crate) struct Cell {
    faces: Vec<Vec<P>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Side {
    Front,
    Back,
    Split,
}

impl Cell {
    /// What of `cell` (none where the tree's walk left the region) lies in front of
    /// and behind the plane `n·x = d`: a node's two children's pieces.
    pub fn pieces(cell: Option<Cell>, n: P, d: f64) -> [Option<Cell>; 2] {
        match cell.as_ref().map(|c| c.side(n, d)) {
            None => [None, None],
            Some(Side::Front) => [cell, None],
            Some(Side::Back) => [None, cell],
            Some(Side::Split) => match cell {
                Some(c) => {
                    let (front, back) = c.split(n, d);
                    [Some(front), Some(back)]
                }
                None => [None, None],
            },
        }
    }

    /// The box `lo..=hi`.
    pub fn cube(lo: P, hi: P) -> Cell {
        let c = |x: usize, y: usize, z: usize| [[lo, hi][x][0], [lo, hi][y][1], [lo, hi][z][2]];
        let faces = vec![
            vec![c(0, 0, 0), c(0, 1, 0), c(0, 1, 1), c(0, 0, 1)],
            vec![c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)],
            vec![c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
            vec![c(0, 1, 0), c(1, 1, 0), c(1, 1, 1), c(0, 1, 1)],
            vec![c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0)],
            vec![c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)],
        ];
        Cell { faces }
    }

    fn vertices(&self) -> impl Iterator<Item = &P> {
        self.faces.iter().flatten()
    }

    /// Where the cell lies with respect to the plane `n · x = d`.
    pub fn side(&self, n: P, d: f64) -> Side {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in self.vertices() {
            let s = dot(n, *v) - d;
            lo = lo.min(s);
            hi = hi.max(s);
        }
        if hi <= ON_PLANE {
            Side::Back
        } else if lo >= -ON_PLANE {
            Side::Front
        } else {
            Side::Split
        }
    }

    /// The parts in front of and behind the plane (call when [`Cell::side`] is
    /// [`Side::Split`]).
    pub fn split(&self, n: P, d: f64) -> (Cell, Cell) {
        let (mut front, mut back, mut cap) = (Vec::new(), Vec::new(), Vec::new());
        for w in &self.faces {
            let (f, b) = clip(w, n, d, &mut cap);
            if f.len() >= 3 {
                front.push(f);
            }
            if b.len() >= 3 {
                back.push(b);
            }
        }
        if let Some(cap) = order_on_plane(cap, n) {
            front.push(cap.clone());
            back.push(cap);
        }
        (Cell { faces: front }, Cell { faces: back })
    }

    /// The bounding box.
    pub fn bounds(&self) -> (P, P) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in self.vertices() {
            for i in 0..3 {
                lo[i] = lo[i].min(v[i]);
                hi[i] = hi[i].max(v[i]);
            }
        }
        (lo, hi)
    }
}

/// Splits a winding by the plane; points on the plane and crossings go to `cap`.
fn clip(w: &[P], n: P, d: f64, cap: &mut Vec<P>) -> (Vec<P>, Vec<P>) {
    let (mut f, mut b) = (Vec::new(), Vec::new());
    for i in 0..w.len() {
        let (p, q) = (w[i], w[(i + 1) % w.len()]);
        let (sp, sq) = (dot(n, p) - d, dot(n, q) - d);
        if sp >= -ON_PLANE {
            f.push(p);
        }
        if sp <= ON_PLANE {
            b.push(p);
        }
        if sp.abs() <= ON_PLANE {
            cap.push(p);
        }
        if (sp > ON_PLANE && sq < -ON_PLANE) || (sp < -ON_PLANE && sq > ON_PLANE) {
            let t = sp / (sp - sq);
            let m = [0, 1, 2].map(|k| p[k] + t * (q[k] - p[k]));
            f.push(m);
            b.push(m);
            cap.push(m);
        }
    }
    (f, b)
}

/// The convex polygon of points lying on a plane with normal `n`, in angular order;
/// `None` when they span no area.
fn order_on_plane(mut pts: Vec<P>, n: P) -> Option<Vec<P>> {
    if pts.len() < 3 {
        return None;
    }
    let inv = 1.0 / pts.len() as f64;
    let c = pts
        .iter()
        .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]])
        .map(|x| x * inv);
    let axis = if n[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross(n, axis);
    let v = cross(n, u);
    let mut keyed: Vec<(f64, P)> = pts
        .drain(..)
        .map(|p| {
            let r = sub(p, c);
            (dot(r, v).atan2(dot(r, u)), p)
        })
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out: Vec<P> = Vec::with_capacity(keyed.len());
    for (_, p) in keyed {
        if out
            .last()
            .is_none_or(|q| dot(sub(p, *q), sub(p, *q)) > 1e-12)
        {
            out.push(p);
        }
    }
    (out.len() >= 3).then_some(out)
}

/// A brush as the carver sees it: its side planes (indices), contents flags and a
/// box around it (cells outside the box are passed over without splitting).
#[derive(Debug, Clone)]
pub(crate) struct CarveBrush {
    pub planes: Vec<u32>,
    pub contents: i32,
    pub lo: P,
    pub hi: P,
}

impl CarveBrush {
    /// A brush of planes `ids` (into `planes`), its box from its axial sides (the
    /// compilers give every brush all six) or unbounded where one is missing.
    pub fn new(ids: Vec<u32>, contents: i32, planes: &[(P, f64)]) -> CarveBrush {
        let (mut lo, mut hi) = ([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]);
        for &i in &ids {
            let (n, d) = planes[i as usize];
            for k in 0..3 {
                if n[k] == 1.0 {
                    hi[k] = hi[k].min(d);
                } else if n[k] == -1.0 {
                    lo[k] = lo[k].max(-d);
                }
            }
        }
        CarveBrush {
            planes: ids,
            contents,
            lo,
            hi,
        }
    }
}

/// What carved leaves of one original leaf share: its face and brush lists.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LeafLists {
    pub marksurfaces: (u32, u32),
    pub brushes: (u32, u32),
}

/// A cell with more candidate brushes than this is first halved by an axial plane
/// (a k-d split): carving many brushes one after the other into one large cell
/// fragments each brush over the pieces of all earlier ones.
const KD_BRUSHES: usize = 6;

/// Builds carved subtrees into `nodes` and `leaves`.
pub(crate) struct Carver<'a> {
    pub planes: &'a [(P, f64)],
    /// Planes of the k-d splits, numbered on from `planes.len()`.
    pub split_planes: Vec<(P, f64)>,
    pub brushes: &'a [CarveBrush],
    pub nodes: Vec<Node>,
    pub leaves: Vec<Leaf>,
    /// The Quake contents value of a set of native contents flags.
    pub classify: fn(i32) -> i32,
}

impl Carver<'_> {
    fn blocks(&self, flags: i32) -> bool {
        (self.classify)(flags) == crate::contents::SOLID
    }

    /// The subtree for `cell` (`None`: a cell of no volume) with the brushes
    /// `brushes` (sorted solid first) and the contents `flags` the whole cell has;
    /// returns the child value (a node index, or `-(leaf + 1)`).
    pub fn carve(
        &mut self,
        cell: Option<Cell>,
        brushes: &[u32],
        flags: i32,
        lists: LeafLists,
    ) -> i32 {
        let Some(cell) = cell else {
            return self.leaf(flags, None, lists);
        };
        if self.blocks(flags) {
            return self.leaf(flags, Some(&cell), lists);
        }
        let (clo, chi) = cell.bounds();
        let meets = |brush: &CarveBrush, lo: P, hi: P| {
            (0..3).all(|i| brush.lo[i] < hi[i] - ON_PLANE && brush.hi[i] > lo[i] + ON_PLANE)
        };
        let candidates: Vec<u32> = brushes
            .iter()
            .copied()
            .filter(|&b| {
                let brush = &self.brushes[b as usize];
                flags & brush.contents != brush.contents
                    && !brush.planes.is_empty()
                    && meets(brush, clo, chi)
            })
            .collect();
        if candidates.len() > KD_BRUSHES
            && let Some(split) = self.kd_split(&candidates, clo, chi)
        {
            let (n, d) = split;
            let (f, b) = cell.split(n, d);
            let front = self.carve(Some(f), &candidates, flags, lists);
            let back = self.carve(Some(b), &candidates, flags, lists);
            self.split_planes.push(split);
            let plane = (self.planes.len() + self.split_planes.len() - 1) as u32;
            return self.node(plane, front, back);
        }
        for (k, &b) in candidates.iter().enumerate() {
            let brush = &self.brushes[b as usize];
            let mut inside = cell.clone();
            let mut cuts: Vec<(u32, Cell)> = Vec::new();
            let mut misses = false;
            for &pl in &brush.planes {
                let (n, d) = self.plane(pl);
                match inside.side(n, d) {
                    Side::Front => {
                        misses = true;
                        break;
                    }
                    Side::Back => {}
                    Side::Split => {
                        let (f, b) = inside.split(n, d);
                        cuts.push((pl, f));
                        inside = b;
                    }
                }
            }
            if misses {
                continue;
            }
            let rest = &candidates[k + 1..];
            let contents = brush.contents;
            let mut child = self.carve(Some(inside), rest, flags | contents, lists);
            for (pl, front) in cuts.into_iter().rev() {
                let outside = self.carve(Some(front), rest, flags, lists);
                child = self.node(pl, outside, child);
            }
            return child;
        }
        self.leaf(flags, Some(&cell), lists)
    }

    /// Plane `i`: of the input, or of a k-d split.
    pub fn plane(&self, i: u32) -> (P, f64) {
        let i = i as usize;
        match self.planes.get(i) {
            Some(&p) => p,
            None => self.split_planes[i - self.planes.len()],
        }
    }

    /// An axial plane through the cell `lo..hi` at the median of the candidates'
    /// centres along its longest side, if both halves then hold fewer candidates.
    fn kd_split(&self, candidates: &[u32], lo: P, hi: P) -> Option<(P, f64)> {
        let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))?;
        let mut centres: Vec<f64> = candidates
            .iter()
            .map(|&b| {
                let br = &self.brushes[b as usize];
                0.5 * (br.lo[axis].max(lo[axis]) + br.hi[axis].min(hi[axis]))
            })
            .collect();
        centres.sort_by(f64::total_cmp);
        let d = centres[centres.len() / 2].round();
        if d <= lo[axis] + 1.0 || d >= hi[axis] - 1.0 {
            return None;
        }
        let below = candidates
            .iter()
            .filter(|&&b| self.brushes[b as usize].lo[axis] < d)
            .count();
        let above = candidates
            .iter()
            .filter(|&&b| self.brushes[b as usize].hi[axis] > d)
            .count();
        if below >= candidates.len() || above >= candidates.len() {
            return None;
        }
        let mut n = [0.0; 3];
        n[axis] = 1.0;
        Some((n, d))
    }

    pub fn node(&mut self, plane: u32, front: i32, back: i32) -> i32 {
        self.nodes.push(Node {
            plane,
            children: [front, back],
            first_face: 0,
            num_faces: 0,
        });
        self.nodes.len() as i32 - 1
    }

    fn leaf(&mut self, flags: i32, cell: Option<&Cell>, lists: LeafLists) -> i32 {
        let (mins, maxs) = cell.map_or(([0.0; 3], [0.0; 3]), |c| {
            let (lo, hi) = c.bounds();
            (lo.map(|x| x as f32), hi.map(|x| x as f32))
        });
        self.leaves.push(Leaf {
            contents: (self.classify)(flags),
            native_contents: flags,
            mins,
            maxs,
            first_marksurface: lists.marksurfaces.0,
            num_marksurfaces: lists.marksurfaces.1,
            first_brush: lists.brushes.0,
            num_brushes: lists.brushes.1,
        });
        -(self.leaves.len() as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contents as q;
    use crate::quake3::contents as q3;

    fn contents_at(nodes: &[Node], leaves: &[Leaf], planes: &[(P, f64)], root: i32, p: P) -> i32 {
        let mut n = root;
        while n >= 0 {
            let node = &nodes[n as usize];
            let (nn, d) = planes[node.plane as usize];
            n = node.children[(dot(nn, p) - d < 0.0) as usize];
        }
        leaves[(-(n + 1)) as usize].contents
    }

    #[test]
    fn a_split_cube_halves_its_volume() {
        let c = Cell::cube([0.0; 3], [2.0; 3]);
        assert_eq!(c.side([1.0, 0.0, 0.0], 3.0), Side::Back);
        assert_eq!(c.side([1.0, 0.0, 0.0], -1.0), Side::Front);
        assert_eq!(c.side([1.0, 0.0, 0.0], 1.0), Side::Split);
        let (f, b) = c.split([1.0, 0.0, 0.0], 1.0);
        assert_eq!(f.bounds(), ([1.0, 0.0, 0.0], [2.0, 2.0, 2.0]));
        assert_eq!(b.bounds(), ([0.0; 3], [1.0, 2.0, 2.0]));
        assert_eq!(f.faces.len(), 6);
        // A diagonal cut leaves a triangular prism on one side.
        let n = [
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::FRAC_1_SQRT_2,
            0.0,
        ];
        let (f, _) = c.split(n, 2.0 * n[0] * 1.5);
        assert_eq!(f.faces.len(), 5);
    }

    #[test]
    fn carving_gives_brush_contents_inside_and_keeps_the_rest() {
        // A solid box 2..4 and water 3..6 along x, inside a cell 0..8.
        let mut planes = Vec::new();
        let mut boxed = |lo: f64, hi: f64| {
            let first = planes.len() as u32;
            for i in 0..3 {
                let mut n = [0.0; 3];
                n[i] = 1.0;
                planes.push((n, hi));
                planes.push((n.map(|x: f64| -x), -lo));
            }
            (first..first + 6).collect::<Vec<_>>()
        };
        let solid = boxed(2.0, 4.0);
        let water = boxed(3.0, 6.0);
        let brushes = vec![
            CarveBrush::new(solid, q3::SOLID, &planes),
            CarveBrush::new(water, q3::WATER, &planes),
        ];
        let mut carver = Carver {
            planes: &planes,
            split_planes: Vec::new(),
            brushes: &brushes,
            nodes: Vec::new(),
            leaves: Vec::new(),
            classify: crate::quake3::to_quake_contents,
        };
        let root = carver.carve(
            Some(Cell::cube([0.0; 3], [8.0; 3])),
            &[0, 1],
            0,
            LeafLists::default(),
        );
        let all: Vec<(P, f64)> = planes.iter().chain(&carver.split_planes).copied().collect();
        let at = |p: P| contents_at(&carver.nodes, &carver.leaves, &all, root, p);
        assert_eq!(at([1.0; 3]), q::EMPTY);
        assert_eq!(at([3.0; 3]), q::SOLID);
        assert_eq!(at([3.9; 3]), q::SOLID);
        assert_eq!(at([5.0; 3]), q::WATER);
        assert_eq!(at([7.0; 3]), q::EMPTY);
        assert_eq!(at([5.0, 5.0, 2.0]), q::EMPTY);
        assert!(
            carver
                .leaves
                .iter()
                .all(|l| l.contents != q::SOLID || l.native_contents & q3::SOLID != 0)
        );
    }
}
