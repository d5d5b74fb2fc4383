//! From bytes to a validated [`Bsp`]: the 17-lump directory, every index the tools
//! follow checked (errors name the lump, the record and the field), then the common
//! model built: draw surfaces as faces, patches as brushes, brushes carved into the
//! tree.

use super::patch::{self, Grid};
use super::{contents as q3, raw};
use crate::carve::{CarveBrush, Carver, Cell, LeafLists, Side};
use crate::entities::parse_entities;
use crate::error::BspError;
use crate::lumps::{Directory, check_finite};
use crate::map::*;
use crate::validate::{LumpNames, validate};
use std::ops::Range;
use toolbox::vec3::{cross, dot, sub};

const LUMP_NAMES: [&str; 17] = [
    "entities",
    "shaders",
    "planes",
    "nodes",
    "leafs",
    "leafsurfaces",
    "leafbrushes",
    "models",
    "brushes",
    "brushsides",
    "drawverts",
    "drawindexes",
    "fogs",
    "surfaces",
    "lightmaps",
    "lightgrid",
    "visibility",
];

const NAMES: LumpNames = LumpNames {
    nodes: "nodes",
    leaves: "leafs",
    marksurfaces: "leafsurfaces",
    models: "models",
    clipnodes: "nodes",
    leafbrushes: "leafbrushes",
    brushes: "brushes",
    brushsides: "brushsides",
};

/// Margin around a model's bounds of the box its tree's cells are cut from.
const CELL_MARGIN: f64 = 64.0;

type P = [f64; 3];

/// The lumps as stored.
struct Raw {
    shaders: Vec<raw::Shader>,
    planes: Vec<Plane>,
    nodes: Vec<raw::Node>,
    leaves: Vec<raw::Leaf>,
    leaf_surfaces: Vec<i32>,
    leaf_brushes: Vec<i32>,
    models: Vec<raw::Model>,
    brushes: Vec<raw::Brush>,
    sides: Vec<raw::BrushSide>,
    verts: Vec<raw::DrawVert>,
    indexes: Vec<i32>,
    surfaces: Vec<raw::Surface>,
}

/// Reads a Quake 3 map (IBSP 46).
pub fn parse(bytes: &[u8]) -> Result<Bsp, BspError> {
    let dir = Directory::new(bytes, 8, &LUMP_NAMES)?;
    let entities = parse_entities(dir.lump(0)?)?;
    let raw = Raw {
        shaders: dir.records(1)?,
        planes: read_planes(&dir)?,
        nodes: dir.records(3)?,
        leaves: dir.records(4)?,
        leaf_surfaces: dir.records(5)?,
        leaf_brushes: dir.records(6)?,
        models: dir.records(7)?,
        brushes: dir.records(8)?,
        sides: dir.records(9)?,
        verts: dir.records(10)?,
        indexes: dir.records(11)?,
        surfaces: dir.records(13)?,
    };
    check_finite("drawverts", raw.verts.iter().map(|v| &v.xyz[..]))?;
    let reached = raw.validate()?;
    let mut bsp = build(&raw, &reached, entities, bytes.len());
    validate(&mut bsp, &NAMES)?;
    Ok(bsp)
}

/// Planes: 16-byte records (no axis type), unit normals and finite distances.
fn read_planes(dir: &Directory) -> Result<Vec<Plane>, BspError> {
    let planes: Vec<raw::Plane> = dir.records(2)?;
    planes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let n = p.normal;
            let len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if !(n.iter().all(|x| x.is_finite())
                && p.dist.is_finite()
                && (0.9..=1.1).contains(&len2))
            {
                return Err(BspError::Malformed {
                    lump: "planes",
                    reason: format!("plane {i} has no unit normal or a non-finite distance"),
                });
            }
            Ok(plane(n.map(f64::from), p.dist as f64))
        })
        .collect()
}

/// A plane in the common model, its axis kind worked out.
fn plane(n: P, d: f64) -> Plane {
    let kind = (0..3).find(|&i| n[i].abs() == 1.0).map_or(3, |i| i as i32);
    Plane {
        normal: n.map(|x| x as f32),
        dist: d as f32,
        kind,
    }
}

fn bad(
    lump: &'static str,
    record: usize,
    field: &'static str,
    value: i64,
    limit: usize,
) -> BspError {
    BspError::BadIndex {
        lump,
        record,
        field,
        value,
        limit,
    }
}

fn index(
    lump: &'static str,
    record: usize,
    field: &'static str,
    v: i32,
    limit: usize,
) -> Result<usize, BspError> {
    usize::try_from(v)
        .ok()
        .filter(|&i| i < limit)
        .ok_or_else(|| bad(lump, record, field, v as i64, limit))
}

fn range(
    lump: &'static str,
    record: usize,
    field: &'static str,
    first: i32,
    count: i32,
    limit: usize,
) -> Result<Range<usize>, BspError> {
    let end = first as i64 + count as i64;
    if first < 0 || count < 0 || end > limit as i64 {
        let value = if first < 0 { first as i64 } else { end };
        return Err(bad(lump, record, field, value, limit + 1));
    }
    Ok(first as usize..end as usize)
}

/// What validation found reachable.
struct Reached {
    /// Leaves of the world tree.
    leaves: Vec<bool>,
}

impl Raw {
    /// Checks every index the tools follow, as the game's loaders do.
    ///
    /// One function on purpose, as the GoldSrc reader's: the format's checklist, lump
    /// by lump in the order later checks rely on, each item a few lines.
    fn validate(&self) -> Result<Reached, BspError> {
        if self.models.is_empty() {
            return Err(BspError::Malformed {
                lump: "models",
                reason: "no world model".into(),
            });
        }
        check_finite(
            "models",
            self.models.iter().flat_map(|m| [&m.mins[..], &m.maxs[..]]),
        )?;
        for (i, m) in self.models.iter().enumerate() {
            range(
                "models",
                i,
                "surface range end",
                m.first_surface,
                m.num_surfaces,
                self.surfaces.len(),
            )?;
            range(
                "models",
                i,
                "brush range end",
                m.first_brush,
                m.num_brushes,
                self.brushes.len(),
            )?;
        }
        let (ns, np) = (self.shaders.len(), self.planes.len());
        for (i, b) in self.brushes.iter().enumerate() {
            index("brushes", i, "shader", b.shader, ns)?;
            range(
                "brushes",
                i,
                "side range end",
                b.first_side,
                b.num_sides,
                self.sides.len(),
            )?;
        }
        for (i, s) in self.sides.iter().enumerate() {
            index("brushsides", i, "plane", s.plane, np)?;
            index("brushsides", i, "shader", s.shader, ns)?;
        }
        for (i, s) in self.surfaces.iter().enumerate() {
            index("surfaces", i, "shader", s.shader, ns)?;
            if !matches!(
                s.surface_type,
                raw::MST_PLANAR | raw::MST_PATCH | raw::MST_TRIANGLE_SOUP
            ) {
                continue;
            }
            let verts = range(
                "surfaces",
                i,
                "vertex range end",
                s.first_vert,
                s.num_verts,
                self.verts.len(),
            )?;
            if s.surface_type == raw::MST_PATCH {
                let (w, h) = (s.patch_width, s.patch_height);
                let odd = |x: i32| x >= 3 && x % 2 == 1;
                if !(odd(w) && odd(h) && w as i64 * h as i64 == verts.len() as i64) {
                    return Err(BspError::Malformed {
                        lump: "surfaces",
                        reason: format!(
                            "patch {i} is {w} x {h} control points with {} vertices (odd sizes of at least 3 whose product is the vertex count needed)",
                            verts.len()
                        ),
                    });
                }
                continue;
            }
            let idx = range(
                "surfaces",
                i,
                "index range end",
                s.first_index,
                s.num_indexes,
                self.indexes.len(),
            )?;
            for (k, &v) in self.indexes[idx].iter().enumerate() {
                index(
                    "drawindexes",
                    s.first_index as usize + k,
                    "vertex",
                    v,
                    verts.len(),
                )?;
            }
        }
        // The world tree from node 0: each node once (a tree, no cycle).
        let mut leaves = vec![false; self.leaves.len()];
        let (nn, nl) = (self.nodes.len(), self.leaves.len());
        let child = |i: usize, c: i32| -> Result<(), BspError> {
            if c >= 0 {
                index("nodes", i, "child node", c, nn).map(|_| ())
            } else {
                index("nodes", i, "child leaf", -(c + 1), nl).map(|_| ())
            }
        };
        if nn == 0 {
            index("leafs", 0, "world leaf", 0, nl)?;
            leaves[0] = true;
        } else {
            let mut seen = vec![false; nn];
            let mut stack = vec![0usize];
            while let Some(n) = stack.pop() {
                if std::mem::replace(&mut seen[n], true) {
                    return Err(BspError::Malformed {
                        lump: "nodes",
                        reason: format!("node {n} is reached twice: the tree has a cycle"),
                    });
                }
                let node = &self.nodes[n];
                index("nodes", n, "plane", node.plane, np)?;
                for c in node.children {
                    child(n, c)?;
                    if c >= 0 {
                        stack.push(c as usize);
                    } else {
                        leaves[(-(c + 1)) as usize] = true;
                    }
                }
            }
        }
        for (i, l) in self.leaves.iter().enumerate().filter(|(i, _)| leaves[*i]) {
            let s = range(
                "leafs",
                i,
                "surface range end",
                l.first_leaf_surface,
                l.num_leaf_surfaces,
                self.leaf_surfaces.len(),
            )?;
            for k in s {
                index(
                    "leafsurfaces",
                    k,
                    "surface",
                    self.leaf_surfaces[k],
                    self.surfaces.len(),
                )?;
            }
            let b = range(
                "leafs",
                i,
                "brush range end",
                l.first_leaf_brush,
                l.num_leaf_brushes,
                self.leaf_brushes.len(),
            )?;
            for k in b {
                index(
                    "leafbrushes",
                    k,
                    "brush",
                    self.leaf_brushes[k],
                    self.brushes.len(),
                )?;
            }
        }
        Ok(Reached { leaves })
    }
}

/// The common model under construction.
struct Builder {
    planes: Vec<Plane>,
    vertices: Vec<[f32; 3]>,
    faces: Vec<Face>,
    edges: Vec<[u32; 2]>,
    surfedges: Vec<i32>,
}

impl Builder {
    /// Adds a triangle of vertices `t` (indices into `vertices`) facing along `toward`
    /// (the draw vertices' normals; zero: as wound); degenerate ones are dropped.
    fn triangle(&mut self, t: [u32; 3], toward: P, shader: u32) {
        let [a, b, c] = t.map(|i| self.vertices[i as usize].map(f64::from));
        let n = cross(sub(b, a), sub(c, a));
        let len = dot(n, n).sqrt();
        if len < 1e-6 {
            return;
        }
        let (t, n) = if dot(n, toward) < 0.0 {
            ([t[0], t[2], t[1]], n.map(|x| -x / len))
        } else {
            (t, n.map(|x| x / len))
        };
        self.planes.push(plane(n, dot(n, a)));
        let first_edge = self.surfedges.len() as u32;
        for k in 0..3 {
            self.surfedges.push(self.edges.len() as i32);
            self.edges.push([t[k], t[(k + 1) % 3]]);
        }
        self.faces.push(Face {
            plane: self.planes.len() as u32 - 1,
            back_side: false,
            first_edge,
            num_edges: 3,
            texinfo: shader,
        });
    }
}

/// A patch's volume pieces, the shader's contents and the model it belongs to.
struct PatchVolume {
    pieces: Vec<patch::Planes>,
    lo: P,
    hi: P,
    contents: i32,
    shader: i32,
    model: usize,
}

fn normal_of(v: &raw::DrawVert) -> P {
    let n = v.normal.map(f64::from);
    if n.iter().all(|x| x.is_finite()) {
        n
    } else {
        [0.0; 3]
    }
}

/// The map in the common form: the shaders as textures, the surfaces as triangle
/// faces, the brushes (and one per patch volume piece) carved into the world's tree and
/// each brush model's, as the game's collision sees them.
fn build(raw: &Raw, reached: &Reached, entities: Vec<crate::Entity>, file_size: usize) -> Bsp {
    let (textures, texinfo) = shader_textures(raw);
    let mut b = Builder {
        planes: raw.planes.clone(),
        vertices: raw.verts.iter().map(|v| v.xyz).collect(),
        faces: Vec::new(),
        edges: vec![[0, 0]],
        surfedges: Vec::new(),
    };
    let (face_start, patches) = surface_faces(raw, &mut b);
    let solids = brushes_with_patches(raw, &mut b, &patches);
    let planes64: Vec<(P, f64)> = b
        .planes
        .iter()
        .map(|p| (p.normal.map(f64::from), p.dist as f64))
        .collect();
    let carve_brushes = carve_brushes(&solids, &planes64, &patches);
    let mut leaf_lists = leaf_lists(
        raw,
        reached,
        &planes64,
        &patches,
        &solids.patch_brushes,
        &face_start,
        &carve_brushes,
    );
    let mut carver = Carver {
        planes: &planes64,
        split_planes: Vec::new(),
        brushes: &carve_brushes,
        nodes: raw
            .nodes
            .iter()
            .map(|n| Node {
                plane: n.plane as u32,
                children: n.children,
                first_face: 0,
                num_faces: 0,
            })
            .collect(),
        leaves: Vec::new(),
        classify: super::to_quake_contents,
    };
    let world_root = carve_world(raw, &mut carver, &leaf_lists);
    let models = carve_models(
        raw,
        &mut carver,
        world_root,
        &mut leaf_lists.leaf_brushes,
        &patches,
        &solids.patch_brushes,
        &face_start,
    );
    let Carver {
        nodes,
        leaves,
        split_planes,
        ..
    } = carver;
    b.planes
        .extend(split_planes.into_iter().map(|(n, d)| plane(n, d)));
    Bsp {
        version: BspVersion::Quake3,
        file_size,
        entities,
        planes: b.planes,
        textures,
        vertices: b.vertices,
        nodes,
        texinfo,
        faces: b.faces,
        clipnodes: Vec::new(),
        leaves,
        marksurfaces: leaf_lists.marksurfaces,
        edges: b.edges,
        surfedges: b.surfedges,
        models,
        leaf_brushes: leaf_lists.leaf_brushes,
        brushes: solids.brushes,
        brush_sides: solids.brush_sides,
        unused_bad_records: 0,
        unusable_faces: Vec::new(),
        game: Game::Quake,
        game_reason: String::new(),
    }
}

/// The shaders as textures (names only: Quake 3 keeps no texture sizes in the map)
/// and one texinfo per shader carrying its surface and contents flags.
fn shader_textures(raw: &Raw) -> (Vec<Option<Texture>>, Vec<TexInfo>) {
    let textures = raw
        .shaders
        .iter()
        .map(|s| {
            let len = s.name.iter().position(|&b| b == 0).unwrap_or(64);
            Some(Texture {
                name: String::from_utf8_lossy(&s.name[..len]).into_owned(),
                width: 0,
                height: 0,
            })
        })
        .collect();
    let texinfo = raw
        .shaders
        .iter()
        .enumerate()
        .map(|(i, s)| TexInfo {
            vecs: [[0.0; 4]; 2],
            miptex: i as i32,
            flags: s.surface_flags,
            contents: s.contents,
        })
        .collect();
    (textures, texinfo)
}

/// The triangle faces of every surface (planar faces, triangle soups, tessellated
/// patches), with where each surface's faces begin (one entry more than surfaces),
/// and the volumes of the patches that collide.
fn surface_faces(raw: &Raw, b: &mut Builder) -> (Vec<u32>, Vec<PatchVolume>) {
    // Which model each surface belongs to.
    let mut surface_model = vec![0usize; raw.surfaces.len()];
    for (m, model) in raw.models.iter().enumerate() {
        let first = model.first_surface as usize;
        surface_model[first..first + model.num_surfaces as usize].fill(m);
    }
    let mut face_start = Vec::with_capacity(raw.surfaces.len() + 1);
    let mut patches = Vec::new();
    for (i, s) in raw.surfaces.iter().enumerate() {
        face_start.push(b.faces.len() as u32);
        let first = s.first_vert as usize;
        let verts = &raw.verts[first..first + s.num_verts.max(0) as usize];
        match s.surface_type {
            raw::MST_PLANAR | raw::MST_TRIANGLE_SOUP => triangle_faces(raw, s, verts, b),
            raw::MST_PATCH => {
                if let Some(volume) = patch_faces(raw, s, verts, b, surface_model[i]) {
                    patches.push(volume);
                }
            }
            _ => {}
        }
    }
    face_start.push(b.faces.len() as u32);
    (face_start, patches)
}

/// The faces of a planar surface or a triangle soup, from its index list.
fn triangle_faces(raw: &Raw, s: &raw::Surface, verts: &[raw::DrawVert], b: &mut Builder) {
    let first = s.first_vert as usize;
    let idx = &raw.indexes[s.first_index as usize..][..s.num_indexes as usize];
    let fan: Vec<i32>;
    let tris: &[i32] = if idx.len() >= 3 {
        idx
    } else {
        // Old compilers wrote planar faces as a fan of their vertices.
        fan = (1..verts.len().saturating_sub(1))
            .flat_map(|k| [0, k as i32, k as i32 + 1])
            .collect();
        &fan
    };
    for t in tris.chunks_exact(3) {
        let toward = t.iter().fold([0.0; 3], |a, &k| {
            let n = normal_of(&verts[k as usize]);
            [a[0] + n[0], a[1] + n[1], a[2] + n[2]]
        });
        b.triangle(
            [t[0], t[1], t[2]].map(|k| (first + k as usize) as u32),
            toward,
            s.shader as u32,
        );
    }
}

/// The faces of a Bézier patch, tessellated; and, when its shader collides, its
/// volume: closed pipes and columns as solid tubes, open patches as thin slabs.
fn patch_faces(
    raw: &Raw,
    s: &raw::Surface,
    verts: &[raw::DrawVert],
    b: &mut Builder,
    model: usize,
) -> Option<PatchVolume> {
    let (w, h) = (s.patch_width as usize, s.patch_height as usize);
    let control: Vec<P> = verts.iter().map(|v| v.xyz.map(f64::from)).collect();
    let normals: Vec<P> = verts.iter().map(normal_of).collect();
    let grid = Grid::tessellate(&control, &normals, w, h, patch::TOLERANCE);
    let base = b.vertices.len() as u32;
    b.vertices
        .extend(grid.points.iter().map(|p| p.map(|x| x as f32)));
    for t in grid.triangles() {
        b.triangle(t.map(|k| base + k as u32), [0.0; 3], s.shader as u32);
    }
    let contents = raw.shaders[s.shader as usize].contents;
    if contents & q3::RELEVANT == 0 {
        return None;
    }
    let grid = Grid::tessellate(&control, &normals, w, h, patch::VOLUME_TOLERANCE);
    let pieces = if grid.closed_across() {
        grid.tube_pieces()
    } else if grid.transposed().closed_across() {
        grid.transposed().tube_pieces()
    } else {
        grid.slabs()
    };
    let (lo, hi) = bounds(&grid.points);
    let m = patch::SLAB + 1.0;
    Some(PatchVolume {
        pieces,
        lo: lo.map(|x| x - m),
        hi: hi.map(|x| x + m),
        contents,
        shader: s.shader,
        model,
    })
}

/// The map's brushes: the file's, then one per patch volume piece.
struct Solids {
    brushes: Vec<Brush>,
    brush_sides: Vec<BrushSide>,
    /// Per patch volume, the range of its brushes.
    patch_brushes: Vec<Range<u32>>,
}

/// The file's brushes and sides, then a brush per patch volume piece (its planes added
/// to the builder's).
fn brushes_with_patches(raw: &Raw, b: &mut Builder, patches: &[PatchVolume]) -> Solids {
    let mut brushes: Vec<Brush> = raw
        .brushes
        .iter()
        .map(|r| Brush {
            first_side: r.first_side as u32,
            num_sides: r.num_sides as u32,
            contents: raw.shaders[r.shader as usize].contents,
        })
        .collect();
    let mut brush_sides: Vec<BrushSide> = raw
        .sides
        .iter()
        .map(|s| BrushSide {
            plane: s.plane as u32,
            texinfo: s.shader,
        })
        .collect();
    let mut patch_brushes: Vec<Range<u32>> = Vec::new();
    for pv in patches {
        let first = brushes.len() as u32;
        for piece in &pv.pieces {
            let first_side = brush_sides.len() as u32;
            for &(n, d) in piece {
                b.planes.push(plane(n, d));
                brush_sides.push(BrushSide {
                    plane: b.planes.len() as u32 - 1,
                    texinfo: pv.shader,
                });
            }
            brushes.push(Brush {
                first_side,
                num_sides: piece.len() as u32,
                contents: pv.contents,
            });
        }
        patch_brushes.push(first..brushes.len() as u32);
    }
    Solids {
        brushes,
        brush_sides,
        patch_brushes,
    }
}

/// The brushes as the carver takes them; patch pieces have no axial sides, so they
/// get their patch's box.
fn carve_brushes(
    solids: &Solids,
    planes64: &[(P, f64)],
    patches: &[PatchVolume],
) -> Vec<CarveBrush> {
    let mut carve_brushes: Vec<CarveBrush> = solids
        .brushes
        .iter()
        .map(|br| {
            let ids = solids.brush_sides[br.first_side as usize..][..br.num_sides as usize]
                .iter()
                .map(|s| s.plane)
                .collect();
            CarveBrush::new(ids, br.contents, planes64)
        })
        .collect();
    for (pv, range) in patches.iter().zip(&solids.patch_brushes) {
        for b in range.clone() {
            carve_brushes[b as usize].lo = pv.lo;
            carve_brushes[b as usize].hi = pv.hi;
        }
    }
    carve_brushes
}

/// A brush list in carving order: only the brushes whose contents the tools tell
/// apart, solid ones first.
fn carve_order(list: &mut Vec<u32>, carve_brushes: &[CarveBrush]) {
    list.retain(|&i| carve_brushes[i as usize].contents & q3::RELEVANT != 0);
    list.sort_by_key(|&i| (carve_brushes[i as usize].contents & q3::SOLID == 0, i));
    list.dedup();
}

/// The leaves' lists in the common form, and each reached leaf's brushes in carving
/// order.
struct LeafListing {
    leaf_brushes: Vec<u32>,
    marksurfaces: Vec<u32>,
    lists: Vec<LeafLists>,
    carve_lists: Vec<Vec<u32>>,
}

/// The leaves' lists: the file's brushes plus the patch brushes whose box reaches the
/// leaf; the faces of the leaf's surfaces.
fn leaf_lists(
    raw: &Raw,
    reached: &Reached,
    planes64: &[(P, f64)],
    patches: &[PatchVolume],
    patch_brushes: &[Range<u32>],
    face_start: &[u32],
    carve_brushes: &[CarveBrush],
) -> LeafListing {
    let mut leaf_extra: Vec<Vec<u32>> = vec![Vec::new(); raw.leaves.len()];
    for (pv, range) in patches.iter().zip(patch_brushes) {
        if pv.model == 0 {
            for l in leaves_in_box(raw, planes64, pv.lo, pv.hi) {
                leaf_extra[l].extend(range.clone());
            }
        }
    }
    let mut leaf_brushes: Vec<u32> = Vec::new();
    let mut marksurfaces: Vec<u32> = Vec::new();
    let mut lists = vec![LeafLists::default(); raw.leaves.len()];
    let mut carve_lists: Vec<Vec<u32>> = vec![Vec::new(); raw.leaves.len()];
    for (i, l) in raw
        .leaves
        .iter()
        .enumerate()
        .filter(|(i, _)| reached.leaves[*i])
    {
        let first = leaf_brushes.len() as u32;
        leaf_brushes.extend(
            raw.leaf_brushes[l.first_leaf_brush as usize..][..l.num_leaf_brushes as usize]
                .iter()
                .map(|&x| x as u32),
        );
        leaf_brushes.extend(&leaf_extra[i]);
        let first_mark = marksurfaces.len() as u32;
        for &s in
            &raw.leaf_surfaces[l.first_leaf_surface as usize..][..l.num_leaf_surfaces as usize]
        {
            marksurfaces.extend(face_start[s as usize]..face_start[s as usize + 1]);
        }
        lists[i] = LeafLists {
            marksurfaces: (first_mark, marksurfaces.len() as u32 - first_mark),
            brushes: (first, leaf_brushes.len() as u32 - first),
        };
        let mut c = leaf_brushes[first as usize..].to_vec();
        carve_order(&mut c, carve_brushes);
        carve_lists[i] = c;
    }
    LeafListing {
        leaf_brushes,
        marksurfaces,
        lists,
        carve_lists,
    }
}

/// The world tree: the file's nodes first, every leaf replaced by its carving. Returns
/// the world's root.
fn carve_world(raw: &Raw, carver: &mut Carver, listing: &LeafListing) -> i32 {
    let planes64 = carver.planes;
    let carve_brushes = carver.brushes;
    let world = &raw.models[0];
    let cell = model_cell(world);
    // Opaque leaves (cluster -1) are inside structural solid or the filled void
    // outside the level: solid, unless the leaf lies inside a structural brush that
    // blocks vis but not players (`common/nodrawnonsolid`).
    let base = |l: usize, cell: Option<&Cell>| {
        let leaf = &raw.leaves[l];
        if leaf.cluster >= 0 {
            return 0;
        }
        let listed =
            &raw.leaf_brushes[leaf.first_leaf_brush as usize..][..leaf.num_leaf_brushes as usize];
        let inside_passable = cell.is_some_and(|cell| {
            listed.iter().any(|&b| {
                let br = &carve_brushes[b as usize];
                br.contents & (q3::SOLID | q3::DETAIL) == 0
                    && br.planes.iter().all(|&p| {
                        let (n, d) = planes64[p as usize];
                        cell.side(n, d) == Side::Back
                    })
            })
        });
        if inside_passable { 0 } else { q3::SOLID }
    };
    let (lists, carve_lists) = (&listing.lists, &listing.carve_lists);
    if raw.nodes.is_empty() {
        return carver.carve(
            Some(cell.clone()),
            &carve_lists[0],
            base(0, Some(&cell)),
            lists[0],
        );
    }
    let mut stack: Vec<(usize, Option<Cell>)> = vec![(0, Some(cell))];
    while let Some((n, cell)) = stack.pop() {
        let node = raw.nodes[n];
        let (nrm, d) = planes64[node.plane as usize];
        let pieces = Cell::pieces(cell, nrm, d);
        for (side, piece) in pieces.into_iter().enumerate() {
            let c = node.children[side];
            if c >= 0 {
                stack.push((c as usize, piece));
            } else {
                let l = (-(c + 1)) as usize;
                let flags = base(l, piece.as_ref());
                let new = carver.carve(piece, &carve_lists[l], flags, lists[l]);
                carver.nodes[n].children[side] = new;
            }
        }
    }
    0
}

/// The models in the common form; each brush model's brushes (and patches) carved
/// into its box.
fn carve_models(
    raw: &Raw,
    carver: &mut Carver,
    world_root: i32,
    leaf_brushes: &mut Vec<u32>,
    patches: &[PatchVolume],
    patch_brushes: &[Range<u32>],
    face_start: &[u32],
) -> Vec<Model> {
    let mut models = Vec::with_capacity(raw.models.len());
    for (m, model) in raw.models.iter().enumerate() {
        let root = if m == 0 {
            world_root
        } else {
            let first = leaf_brushes.len() as u32;
            leaf_brushes
                .extend(model.first_brush as u32..(model.first_brush + model.num_brushes) as u32);
            for (pv, range) in patches.iter().zip(patch_brushes) {
                if pv.model == m {
                    leaf_brushes.extend(range.clone());
                }
            }
            let list = LeafLists {
                marksurfaces: (0, 0),
                brushes: (first, leaf_brushes.len() as u32 - first),
            };
            let mut c = leaf_brushes[first as usize..].to_vec();
            carve_order(&mut c, carver.brushes);
            carver.carve(Some(model_cell(model)), &c, 0, list)
        };
        let faces = face_start[model.first_surface as usize]
            ..face_start[(model.first_surface + model.num_surfaces) as usize];
        models.push(Model {
            mins: model.mins,
            maxs: model.maxs,
            origin: [0.0; 3],
            headnode: [root, 0, 0, 0],
            first_face: faces.start,
            num_faces: faces.end - faces.start,
        });
    }
    models
}

/// The box a model's cells are cut from.
fn model_cell(m: &raw::Model) -> Cell {
    let lo = m.mins.map(|x| x as f64 - CELL_MARGIN);
    let hi = m.maxs.map(|x| x as f64 + CELL_MARGIN);
    Cell::cube(lo, hi)
}

fn bounds(points: &[P]) -> (P, P) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (lo, hi)
}

/// The world leaves (of the file's tree) the box `lo..=hi` reaches.
fn leaves_in_box(raw: &Raw, planes: &[(P, f64)], lo: P, hi: P) -> Vec<usize> {
    let mut out = Vec::new();
    if raw.nodes.is_empty() {
        return vec![0];
    }
    let mut stack = vec![0i32];
    while let Some(n) = stack.pop() {
        if n < 0 {
            out.push((-(n + 1)) as usize);
            continue;
        }
        let node = &raw.nodes[n as usize];
        let (nrm, d) = planes[node.plane as usize];
        let (mut dmin, mut dmax) = (-d, -d);
        for i in 0..3 {
            let (a, b) = (nrm[i] * lo[i], nrm[i] * hi[i]);
            dmin += a.min(b);
            dmax += a.max(b);
        }
        if dmax >= 0.0 {
            stack.push(node.children[0]);
        }
        if dmin < 0.0 {
            stack.push(node.children[1]);
        }
    }
    out
}
