//! BSP tree building by recursive splitting of convex cells.
//!
//! The candidate surfaces are the faces of the primitives (boxes and wedges;
//! for clip hulls, the faces of the Minkowski-expanded obstacle cells). Contents
//! can only change across such a surface, so a cell that no candidate
//! fragment crosses is homogeneous and is classified by one interior point.
//! Splits prefer planes whose fragments lie in the cell, that cut few other
//! fragments and that balance the rest (the classic qbsp heuristic).
//!
//! Clip hulls describe where the centre of a hull box may be: the complement
//! of (obstacle ⊕ box). Shrinking each free box on its own would be wrong
//! wherever a hull straddles two overlapping free boxes (a door opening), so
//! the obstacle is taken as the union of the hull-0 obstacle cells, each grown
//! exactly (Minkowski sum with the box: the cell's face normals, the axes and
//! the edge × axis bevel planes), and only the parts of their faces outside
//! the other grown cells become candidates. Cells are classified by the exact
//! [`World::hull_contents`].

use crate::geometry::{
    ConvexCell, EPS, Plane, PlaneSet, Polygon, Side, V3, polygon_area, snap_normal, split_polygon,
};
use crate::world::{Contents, HullSet, HullShape, SurfaceClass, WallPolygon, World};

/// Margin between the world's primitives and the root cell of its trees; it
/// exceeds every hull's half extent so the outer cells are solid in all hulls.
pub const ROOT_MARGIN: f64 = 64.0;

/// A child reference of a tree node.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Child {
    Node(usize),
    Leaf(usize),
}

/// An interior node: a splitting plane (canonical orientation from the plane
/// set) and the children in front of and behind it.
#[derive(Clone, Debug)]
pub struct Node {
    pub plane_id: usize,
    pub plane: Plane,
    pub front: Child,
    pub back: Child,
    /// Bounding box of the node's cell.
    pub bounds: (V3, V3),
}

/// A leaf: a homogeneous convex cell.
#[derive(Clone, Debug)]
pub struct Leaf {
    pub contents: Contents,
    pub cell: ConvexCell,
}

/// A BSP tree over convex cells; nodes are stored in pre-order (root first).
#[derive(Clone, Debug)]
pub struct Tree {
    pub nodes: Vec<Node>,
    pub leaves: Vec<Leaf>,
    pub root: Child,
}

/// A candidate surface fragment inside the current cell.
#[derive(Clone, Debug)]
pub struct Fragment {
    pub plane_id: usize,
    pub polygon: Polygon,
    lo: V3,
    hi: V3,
}

impl Fragment {
    fn new(plane_id: usize, polygon: Polygon) -> Self {
        let mut lo = polygon[0];
        let mut hi = polygon[0];
        for &v in &polygon {
            lo = lo.min(v);
            hi = hi.max(v);
        }
        Fragment {
            plane_id,
            polygon,
            lo,
            hi,
        }
    }
}

impl Tree {
    /// The leaf containing `p` (front on `distance >= 0`, as the engine does).
    pub fn leaf_at(&self, p: V3) -> usize {
        let mut c = self.root;
        loop {
            match c {
                Child::Leaf(l) => return l,
                Child::Node(n) => {
                    let node = &self.nodes[n];
                    c = if node.plane.distance(p) >= 0.0 {
                        node.front
                    } else {
                        node.back
                    };
                }
            }
        }
    }

    /// Contents of the leaf containing `p`.
    pub fn contents(&self, p: [f64; 3]) -> Contents {
        self.leaves[self.leaf_at(p.into())].contents
    }

    /// Smallest distance from `p` to a splitting plane on its path: points
    /// farther than the rounding tolerance are classified unambiguously.
    pub fn path_plane_distance(&self, p: [f64; 3]) -> f64 {
        let p = V3::from(p);
        let mut c = self.root;
        let mut best = f64::INFINITY;
        while let Child::Node(n) = c {
            let node = &self.nodes[n];
            let d = node.plane.distance(p);
            best = best.min(d.abs());
            c = if d >= 0.0 { node.front } else { node.back };
        }
        best
    }
}

/// Turns polygons into fragments inside the root box (`lo`, `hi`), dropping
/// parts outside it or on its faces.
pub fn fragments_in_box(
    surfaces: impl IntoIterator<Item = (Plane, Polygon)>,
    lo: V3,
    hi: V3,
    planes: &mut PlaneSet,
) -> Vec<Fragment> {
    let root = ConvexCell::from_box(lo, hi);
    let mut out = Vec::new();
    'surface: for (plane, poly) in surfaces {
        let mut poly = poly;
        for f in &root.faces {
            match split_polygon(&poly, &f.plane) {
                Side::On | Side::Front => continue 'surface,
                Side::Back => {}
                Side::Spanning(_, b) => poly = b,
            }
            if poly.len() < 3 || polygon_area(&poly) <= EPS {
                continue 'surface;
            }
        }
        let (id, _) = planes.insert(plane);
        out.push(Fragment::new(id, poly));
    }
    out
}

/// Builds a tree over the box (`lo`, `hi`) from candidate fragments,
/// classifying homogeneous cells with `classify`.
pub fn build(
    lo: V3,
    hi: V3,
    fragments: Vec<Fragment>,
    planes: &PlaneSet,
    classify: &dyn Fn(V3) -> Contents,
) -> Tree {
    let mut tree = Tree {
        nodes: Vec::new(),
        leaves: Vec::new(),
        root: Child::Leaf(0),
    };
    let root_cell = ConvexCell::from_box(lo, hi);
    tree.root = build_cell(&mut tree, root_cell, fragments, planes, classify);
    tree
}

fn build_cell(
    tree: &mut Tree,
    cell: ConvexCell,
    mut fragments: Vec<Fragment>,
    planes: &PlaneSet,
    classify: &dyn Fn(V3) -> Contents,
) -> Child {
    loop {
        let Some(plane_id) = choose_plane(&fragments, planes) else {
            let contents = classify(cell.interior_point());
            tree.leaves.push(Leaf { contents, cell });
            return Child::Leaf(tree.leaves.len() - 1);
        };
        let plane = planes.get(plane_id);
        let (front_cell, back_cell) = cell.split(&plane, Some(plane_id));
        let (Some(front_cell), Some(back_cell)) = (front_cell, back_cell) else {
            // The plane only grazes the cell (rounding): its fragments are
            // not really inside, drop them and try again.
            fragments.retain(|f| f.plane_id != plane_id);
            continue;
        };
        let (mut front, mut back) = (Vec::new(), Vec::new());
        for f in fragments {
            if f.plane_id == plane_id {
                continue;
            }
            match split_polygon(&f.polygon, &plane) {
                Side::Front => front.push(f),
                Side::Back => back.push(f),
                Side::On => {}
                Side::Spanning(a, b) => {
                    for (part, list) in [(a, &mut front), (b, &mut back)] {
                        if part.len() >= 3 && polygon_area(&part) > EPS {
                            list.push(Fragment::new(f.plane_id, part));
                        }
                    }
                }
            }
        }
        let bounds = cell.bounds();
        let index = tree.nodes.len();
        tree.nodes.push(Node {
            plane_id,
            plane,
            front: Child::Leaf(0),
            back: Child::Leaf(0),
            bounds,
        });
        drop(cell); // the children own their halves; free it before recursing
        let f = build_cell(tree, front_cell, front, planes, classify);
        let b = build_cell(tree, back_cell, back, planes, classify);
        tree.nodes[index].front = f;
        tree.nodes[index].back = b;
        return Child::Node(index);
    }
}

/// Picks the splitting plane: fewest cut fragments, then best balance, then
/// most coplanar fragments; ties go to the lowest plane id (determinism).
fn choose_plane(fragments: &[Fragment], planes: &PlaneSet) -> Option<usize> {
    let mut ids: Vec<usize> = fragments.iter().map(|f| f.plane_id).collect();
    ids.sort_unstable();
    ids.dedup();
    let mut best: Option<(i64, usize)> = None;
    for id in ids {
        let plane = planes.get(id);
        let (mut front, mut back, mut split, mut on) = (0i64, 0i64, 0i64, 0i64);
        for f in fragments {
            if f.plane_id == id {
                on += 1;
                continue;
            }
            let side = match plane.axial() {
                Some(ax) => {
                    let d = plane.dist;
                    if f.hi.get(ax) <= d + EPS {
                        -1
                    } else if f.lo.get(ax) >= d - EPS {
                        1
                    } else {
                        0
                    }
                }
                None => match split_polygon(&f.polygon, &plane) {
                    Side::Front => 1,
                    Side::Back | Side::On => -1,
                    Side::Spanning(..) => 0,
                },
            };
            match side {
                1 => front += 1,
                -1 => back += 1,
                _ => split += 1,
            }
        }
        let axial_bonus = if plane.axial().is_some() { 0 } else { 4 };
        let score = 8 * split + (front - back).abs() - 2 * on + axial_bonus;
        if best.is_none_or(|(s, _)| score < s) {
            best = Some((score, id));
        }
    }
    best.map(|(_, id)| id)
}

/// What a boundary face separates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceKind {
    /// Free space against an obstacle with these contents.
    Boundary(Contents),
    /// The surface between EMPTY and WATER.
    WaterSurface,
}

/// A face of the tree: a convex polygon on a node plane between a free leaf
/// and a leaf of other contents, facing into the free leaf.
#[derive(Clone, Debug)]
pub struct TreeFace {
    /// The node whose plane holds the face (the two leaves' common ancestor).
    pub node: usize,
    /// Counter-clockwise around `normal`.
    pub polygon: Polygon,
    /// Unit normal pointing into `free_leaf`.
    pub normal: V3,
    pub free_leaf: usize,
    pub other_leaf: usize,
    pub kind: FaceKind,
}

/// The faces between the leaves for which `is_source` holds and leaves of
/// other contents, in a deterministic order grouped by node.
pub fn extract_faces(tree: &Tree, is_source: &dyn Fn(Contents) -> bool) -> Vec<TreeFace> {
    let mut out = Vec::new();
    for (li, leaf) in tree.leaves.iter().enumerate() {
        if !is_source(leaf.contents) {
            continue;
        }
        for f in &leaf.cell.faces {
            let walk = Walk {
                tree,
                face_plane_id: f.plane_id,
                outward: f.plane.normal,
                source_leaf: li,
                source_contents: leaf.contents,
                is_source,
            };
            walk.push(tree.root, f.polygon.clone(), None, &mut out);
        }
    }
    out.sort_by_key(|f| f.node);
    out
}

struct Walk<'a> {
    tree: &'a Tree,
    face_plane_id: Option<usize>,
    outward: V3,
    source_leaf: usize,
    source_contents: Contents,
    is_source: &'a dyn Fn(Contents) -> bool,
}

impl Walk<'_> {
    fn push(&self, c: Child, poly: Polygon, lca: Option<usize>, out: &mut Vec<TreeFace>) {
        match c {
            Child::Leaf(m) => {
                let contents = self.tree.leaves[m].contents;
                let Some(node) = lca else { return };
                let kind = if !(self.is_source)(contents) {
                    FaceKind::Boundary(contents)
                } else if contents != self.source_contents {
                    FaceKind::WaterSurface
                } else {
                    return;
                };
                let mut polygon = poly;
                polygon.reverse();
                out.push(TreeFace {
                    node,
                    polygon,
                    normal: -self.outward,
                    free_leaf: self.source_leaf,
                    other_leaf: m,
                    kind,
                });
            }
            Child::Node(i) => {
                let n = &self.tree.nodes[i];
                let coincident = || {
                    let next = if self.outward.dot(n.plane.normal) > 0.0 {
                        n.front
                    } else {
                        n.back
                    };
                    (next, lca.or(Some(i)))
                };
                if self.face_plane_id == Some(n.plane_id) {
                    let (next, l) = coincident();
                    return self.push(next, poly, l, out);
                }
                match split_polygon(&poly, &n.plane) {
                    Side::Front => self.push(n.front, poly, lca, out),
                    Side::Back => self.push(n.back, poly, lca, out),
                    Side::On => {
                        let (next, l) = coincident();
                        self.push(next, poly, l, out)
                    }
                    Side::Spanning(a, b) => {
                        if a.len() >= 3 && polygon_area(&a) > EPS {
                            self.push(n.front, a, lca, out);
                        }
                        if b.len() >= 3 && polygon_area(&b) > EPS {
                            self.push(n.back, b, lca, out);
                        }
                    }
                }
            }
        }
    }
}

/// The root box of a world's trees.
pub fn root_box(world: &World) -> (V3, V3) {
    let b = world.bounds();
    let m = V3::new(ROOT_MARGIN, ROOT_MARGIN, ROOT_MARGIN);
    (b.lo() - m, b.hi() + m)
}

/// The faces of every primitive of the world: the hull-0 candidate surfaces.
fn primitive_surfaces(world: &World) -> Vec<(Plane, Polygon)> {
    let boxes = world
        .free
        .iter()
        .chain(&world.solids)
        .chain(&world.sky)
        .chain(&world.water);
    let mut cells: Vec<ConvexCell> = boxes
        .map(|b| ConvexCell::from_box(b.lo(), b.hi()))
        .collect();
    cells.extend(world.ramps.iter().filter_map(|r| r.cell()));
    cells
        .into_iter()
        .flat_map(|c| c.faces.into_iter().map(|f| (f.plane, f.polygon)))
        .collect()
}

/// The hull-0 tree of a world.
pub fn build_world_hull0(world: &World, planes: &mut PlaneSet) -> Tree {
    let (lo, hi) = root_box(world);
    let frags = fragments_in_box(primitive_surfaces(world), lo, hi, planes);
    build(lo, hi, frags, planes, &|p| world.contents(p.into()))
}

/// The Minkowski sum of a convex cell and the symmetric box `±h`: the
/// half-spaces of the cell's face normals, the axes and the cross products of
/// its edges with the axes, each pushed out by its support distance.
pub fn expand_cell(cell: &ConvexCell, h: V3, lo: V3, hi: V3) -> Option<ConvexCell> {
    expand_cell_shifted(cell, h, V3::new(0.0, 0.0, 0.0), lo, hi)
}

/// [`expand_cell`] for a box centred `c` off the origin: the origins where the box
/// `[o + c - h, o + c + h]` meets the cell.
pub fn expand_cell_shifted(cell: &ConvexCell, h: V3, c: V3, lo: V3, hi: V3) -> Option<ConvexCell> {
    let mut normals: Vec<V3> = Vec::new();
    let mut add = |n: V3| {
        if n.length() < 1e-9 {
            return;
        }
        let n = snap_normal(n.normalized());
        if !normals.iter().any(|m| (*m - n).length() < 1e-9) {
            normals.push(n);
        }
    };
    for axis in 0..3 {
        add(V3::axis(axis));
        add(-V3::axis(axis));
    }
    for f in &cell.faces {
        add(f.plane.normal);
    }
    for f in &cell.faces {
        let p = &f.polygon;
        for i in 0..p.len() {
            let e = p[(i + 1) % p.len()] - p[i];
            if e.length() < EPS {
                continue;
            }
            for axis in 0..3 {
                let c = e.cross(V3::axis(axis));
                add(c);
                add(-c);
            }
        }
    }
    let verts: Vec<V3> = cell.vertices().collect();
    let halfspaces: Vec<Plane> = normals
        .iter()
        .map(|&n| {
            let support = verts.iter().map(|&v| n.dot(v)).fold(f64::MIN, f64::max);
            Plane {
                normal: n,
                dist: support + n.abs().dot(h) - n.dot(c),
            }
        })
        .collect();
    ConvexCell::from_halfspaces(lo, hi, &halfspaces)
}

/// The clip-hull tree of a world for hull 1–3: candidate surfaces are the
/// expanded obstacle cells of the hull-0 tree; cells are classified by the
/// exact [`World::hull_contents`].
pub fn build_world_clip_hull(
    world: &World,
    hull0: &Tree,
    hull: usize,
    planes: &mut PlaneSet,
) -> Tree {
    build_world_clip_hull_shaped(world, hull0, HullSet::GoldSrc.shape(hull), planes)
}

/// [`build_world_clip_hull`] for a hull of any box (Quake's are off-centre).
pub fn build_world_clip_hull_shaped(
    world: &World,
    hull0: &Tree,
    shape: HullShape,
    planes: &mut PlaneSet,
) -> Tree {
    let (lo, hi) = root_box(world);
    let h = V3::from(shape.half);
    let centre = V3::from(shape.center);
    let big = V3::new(1.0, 1.0, 1.0) * (2.0 * ROOT_MARGIN);
    let f = world.free_bounds();
    let cells: Vec<(ConvexCell, (V3, V3))> = hull0
        .leaves
        .iter()
        .filter(|leaf| !leaf.contents.is_free())
        .filter(|leaf| {
            // Cells far inside the solid border cannot reach free space.
            let (clo, chi) = leaf.cell.bounds();
            (0..3).all(|i| clo.get(i) <= f.max[i] + h.get(i) && chi.get(i) >= f.min[i] - h.get(i))
        })
        .filter_map(|leaf| expand_cell_shifted(&leaf.cell, h, centre, lo - big, hi + big))
        .map(|c| {
            let b = c.bounds();
            (c, b)
        })
        .collect();
    // Only the parts of the grown cells' faces outside every other grown
    // cell can carry the boundary of the union: the rest would only add
    // needless splits.
    let mut surfaces = Vec::new();
    for (i, (c, _)) in cells.iter().enumerate() {
        for face in &c.faces {
            for piece in outside_other_cells(face.polygon.clone(), &cells, i) {
                surfaces.push((face.plane, piece));
            }
        }
    }
    let frags = fragments_in_box(surfaces, lo, hi, planes);
    build(lo, hi, frags, planes, &|p| {
        world.shaped_contents(shape, p.into())
    })
}

/// The parts of `poly` outside the open interior of every cell but `skip`.
fn outside_other_cells(
    poly: Polygon,
    cells: &[(ConvexCell, (V3, V3))],
    skip: usize,
) -> Vec<Polygon> {
    let mut pieces = vec![poly];
    for (j, (cell, (lo, hi))) in cells.iter().enumerate() {
        if j == skip || pieces.is_empty() {
            continue;
        }
        let mut next = Vec::new();
        for piece in pieces {
            let (mut plo, mut phi) = (piece[0], piece[0]);
            for &v in &piece {
                plo = plo.min(v);
                phi = phi.max(v);
            }
            if (0..3).any(|k| plo.get(k) >= hi.get(k) - EPS || phi.get(k) <= lo.get(k) + EPS) {
                next.push(piece);
                continue;
            }
            let mut rest = Some(piece);
            for f in &cell.faces {
                let Some(r) = rest.take() else { break };
                match split_polygon(&r, &f.plane) {
                    // On the cell's boundary or outside it: not interior.
                    Side::Front | Side::On => next.push(r),
                    Side::Back => rest = Some(r),
                    Side::Spanning(front, back) => {
                        if front.len() >= 3 && polygon_area(&front) > EPS {
                            next.push(front);
                        }
                        if back.len() >= 3 && polygon_area(&back) > EPS {
                            rest = Some(back);
                        }
                    }
                }
            }
            // Whatever is left lies inside the cell: dropped.
        }
        pieces = next;
    }
    pieces
}

/// The exact boundary polygons of a world's free space.
pub fn wall_polygons(world: &World) -> Vec<WallPolygon> {
    let mut planes = PlaneSet::default();
    let tree = build_world_hull0(world, &mut planes);
    extract_faces(&tree, &|c| c.is_free())
        .into_iter()
        .filter_map(|f| match f.kind {
            FaceKind::Boundary(obstacle) => Some(WallPolygon {
                vertices: f.polygon.iter().map(|&v| v.into()).collect(),
                normal: f.normal.into(),
                class: SurfaceClass::of(obstacle, f.normal.into()),
            }),
            FaceKind::WaterSurface => None,
        })
        .collect()
}

/// A single solid box as its own little tree (brush entity models): hull 0
/// with the box faces as candidates, or a clip hull with the box grown by the
/// hull's half extents.
pub fn build_box_model(lo: V3, hi: V3, hull: usize, planes: &mut PlaneSet) -> Tree {
    build_box_model_shaped(lo, hi, HullSet::GoldSrc.shape(hull), planes)
}

/// [`build_box_model`] for a hull of any box.
pub fn build_box_model_shaped(lo: V3, hi: V3, shape: HullShape, planes: &mut PlaneSet) -> Tree {
    let h = V3::from(shape.half);
    let c = V3::from(shape.center);
    let (blo, bhi) = (lo - h - c, hi + h - c);
    let m = V3::new(1.0, 1.0, 1.0) * 16.0;
    let (rlo, rhi) = (blo - m, bhi + m);
    let cell = ConvexCell::from_box(blo, bhi);
    let frags = fragments_in_box(
        cell.faces.into_iter().map(|f| (f.plane, f.polygon)),
        rlo,
        rhi,
        planes,
    );
    let inside = |p: V3| (0..3).all(|i| blo.get(i) < p.get(i) && p.get(i) < bhi.get(i));
    build(rlo, rhi, frags, planes, &|p| {
        if inside(p) {
            Contents::Solid
        } else {
            Contents::Empty
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::{Rng, standard};
    use crate::world::Aabb;

    #[test]
    fn hull0_tree_matches_world_contents() {
        for (w, c) in standard() {
            let tree = &c.models[0].hull0;
            let mut rng = Rng::new(1);
            let (mut tested, mut seen) = (0, std::collections::HashSet::new());
            for _ in 0..100_000 {
                let p = rng.point_in(&w.bounds(), 32.0);
                if w.distance_to_boundary(p) < 1e-3 {
                    continue;
                }
                tested += 1;
                let expected = w.contents(p);
                seen.insert(expected);
                assert_eq!(tree.contents(p), expected, "{} at {p:?}", w.name);
            }
            assert!(tested > 99_000, "{}: only {tested} points tested", w.name);
            assert!(seen.contains(&Contents::Empty) && seen.contains(&Contents::Solid));
        }
    }

    #[test]
    fn clip_hull_trees_match_expanded_world() {
        for (w, c) in standard() {
            let mut rng = Rng::new(2);
            for hull in 1..=3 {
                let tree = &c.models[0].clip[hull - 1];
                let mut empty = 0;
                for _ in 0..20_000 {
                    let p = rng.point_in(&w.free_bounds(), 48.0);
                    if tree.path_plane_distance(p) < 1e-3 {
                        continue;
                    }
                    let expected = w.hull_contents(hull, p);
                    empty += usize::from(expected == Contents::Empty);
                    assert_eq!(
                        tree.contents(p),
                        expected,
                        "{} hull {hull} at {p:?}",
                        w.name
                    );
                }
                // Enough empty points to mean something: 2.5 % (the L
                // corridor, 128 wide, leaves hull 2 about 5 % of its box).
                assert!(empty > 500, "{} hull {hull}: {empty} empty points", w.name);
            }
        }
    }

    #[test]
    fn wall_polygons_separate_free_space_from_obstacles() {
        for (w, _) in standard() {
            for poly in w.wall_polygons() {
                let v: Vec<V3> = poly.vertices.iter().map(|&p| p.into()).collect();
                let n = V3::from(poly.normal);
                let area_normal = crate::geometry::polygon_area_vector(&v).normalized();
                assert!((area_normal - n).length() < 1e-9, "{}: winding", w.name);
                let c = crate::geometry::centroid(&v);
                let probes = std::iter::once(c).chain(v.iter().map(|&p| p + (c - p) * 0.05));
                for q in probes {
                    let front = w.contents((q + n * 0.01).into());
                    let back = w.contents((q - n * 0.01).into());
                    assert!(
                        front.is_free(),
                        "{}: front of {poly:?} is {front:?}",
                        w.name
                    );
                    assert!(!back.is_free(), "{}: back of {poly:?}", w.name);
                    assert_eq!(
                        poly.class == SurfaceClass::Sky,
                        back == Contents::Sky,
                        "{}: class of {poly:?}",
                        w.name
                    );
                }
            }
        }
    }

    /// The area of free/obstacle boundary on a plane, facing `n`, by midpoint
    /// sampling on a 4-unit grid over the primitive faces lying on the plane.
    fn sampled_boundary_area(w: &World, plane: &Plane, region: (V3, V3)) -> f64 {
        let n = plane.normal;
        let k = plane.dominant_axis();
        let (u, v) = ((k + 1) % 3, (k + 2) % 3);
        let step = 4.0;
        let (lo, hi) = region;
        let mut count = 0usize;
        let nu = ((hi.get(u) - lo.get(u)) / step).round() as usize;
        let nv = ((hi.get(v) - lo.get(v)) / step).round() as usize;
        for i in 0..nu {
            for j in 0..nv {
                let a = lo.get(u) + step * (i as f64 + 0.5);
                let b = lo.get(v) + step * (j as f64 + 0.5);
                let mut p = V3::ZERO.with(u, a).with(v, b);
                let rest = plane.dist - n.get(u) * a - n.get(v) * b;
                p = p.with(k, rest / n.get(k));
                let front = w.contents((p + n * 0.01).into());
                let back = w.contents((p - n * 0.01).into());
                if front.is_free() && !back.is_free() {
                    count += 1;
                }
            }
        }
        count as f64 * step * step / n.get(k).abs()
    }

    #[test]
    fn wall_area_per_plane_matches_sampling() {
        for (w, _) in standard() {
            // Every primitive face plane, both facings, with the box of the
            // primitive faces on it (the only places the boundary can be).
            let mut planes: Vec<(Plane, (V3, V3))> = Vec::new();
            for (plane, poly) in primitive_surfaces(w) {
                let (mut lo, mut hi) = (poly[0], poly[0]);
                for &p in &poly {
                    lo = lo.min(p);
                    hi = hi.max(p);
                }
                for pl in [plane, plane.flipped()] {
                    match planes.iter_mut().find(|(q, _)| {
                        (q.normal - pl.normal).length() < 1e-9 && (q.dist - pl.dist).abs() < 1e-6
                    }) {
                        Some((_, r)) => *r = (r.0.min(lo), r.1.max(hi)),
                        None => planes.push((pl, (lo, hi))),
                    }
                }
            }
            let walls = w.wall_polygons();
            let mut matched = 0;
            for (plane, region) in &planes {
                let on_plane: Vec<&WallPolygon> = walls
                    .iter()
                    .filter(|p| {
                        (V3::from(p.normal) - plane.normal).length() < 1e-9
                            && (plane.distance(p.vertices[0].into())).abs() < 1e-6
                    })
                    .collect();
                matched += on_plane.len();
                let exact: f64 = on_plane.iter().map(|p| p.area()).sum();
                let sampled = sampled_boundary_area(w, plane, *region);
                let slanted = plane.axial().is_none();
                let tol = if w.ramps.is_empty() {
                    1e-6 * exact.max(1.0)
                } else if slanted {
                    0.03 * exact.max(100.0)
                } else {
                    0.01 * exact.max(1000.0)
                };
                assert!(
                    (exact - sampled).abs() <= tol,
                    "{}: plane {plane:?}: polygons {exact}, sampled {sampled}",
                    w.name
                );
            }
            assert_eq!(
                matched,
                walls.len(),
                "{}: polygons off every primitive plane",
                w.name
            );
        }
    }

    #[test]
    fn box_room_has_six_exact_walls() {
        let w = crate::worlds::box_room();
        let walls = w.wall_polygons();
        assert_eq!(walls.len(), 6);
        let total: f64 = walls.iter().map(|p| p.area()).sum();
        let (a, b, c) = (512.0, 384.0, 256.0);
        assert!((total - 2.0 * (a * b + b * c + a * c)).abs() < 1e-6);
    }

    #[test]
    fn two_rooms_wall_area_is_analytic() {
        // Two 384x384x192 rooms, minus two 128x112 door openings, plus the
        // visible 256-long corridor (floor, ceiling 128 wide; walls 112 high).
        let room = 2.0 * 384.0 * 384.0 + 4.0 * 384.0 * 192.0;
        let doors = 2.0 * 128.0 * 112.0;
        let corridor = 2.0 * 256.0 * 128.0 + 2.0 * 256.0 * 112.0;
        let total: f64 = crate::worlds::two_rooms()
            .wall_polygons()
            .iter()
            .map(|p| p.area())
            .sum();
        assert!(
            (total - (2.0 * room - doors + corridor)).abs() < 1e-6,
            "{total}"
        );
    }

    #[test]
    fn expanded_cell_of_a_wedge_is_its_minkowski_sum() {
        let r = crate::world::Ramp::rising(
            Aabb::new([0.0, 0.0, 0.0], [256.0, 128.0, 128.0]),
            crate::world::Rise::PlusX,
        );
        let cell = r.cell().unwrap();
        let h = V3::new(16.0, 16.0, 36.0);
        let big = V3::new(1e4, 1e4, 1e4);
        let e = expand_cell(&cell, h, -big, big).unwrap();
        let mut rng = Rng::new(3);
        for _ in 0..20_000 {
            let p = rng.point_in(
                &Aabb::new([-40.0, -40.0, -60.0], [300.0, 170.0, 170.0]),
                0.0,
            );
            // Box centred at p intersects the open wedge?
            let q = Aabb::new(p, p).expanded([16.0, 16.0, 36.0]);
            let lo = V3::from(q.min).max(V3::ZERO);
            let hi = V3::from(q.max).min(V3::new(256.0, 128.0, 128.0));
            let overlap = (0..3).all(|i| lo.get(i) < hi.get(i));
            let n = r.plane().normal;
            let lowest: f64 = (0..3)
                .map(|i| n.get(i) * if n.get(i) > 0.0 { lo.get(i) } else { hi.get(i) })
                .sum();
            let hit = overlap && lowest < r.dist;
            let margin = e
                .faces
                .iter()
                .map(|f| f.plane.distance(p.into()).abs())
                .fold(f64::MAX, f64::min);
            if margin > 1e-6 {
                assert_eq!(e.contains(p.into()), hit, "{p:?}");
            }
        }
    }
}
