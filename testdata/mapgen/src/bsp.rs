//! GoldSrc BSP v30 writer.
//!
//! [`compile`] builds every tree of a world (hull 0 and clip hulls 1–3 for
//! the world model and for each brush entity); [`write()`] lays them out as a
//! v30 file: a header of 15 lumps (entities, planes, textures, vertices,
//! visibility, nodes, texinfo, faces, lighting, clipnodes, leaves,
//! marksurfaces, edges, surfedges, models), little-endian, each lump 4-byte
//! aligned. Visibility and lighting are empty (`visofs`/`lightofs` −1);
//! textures are named only (their pixels live in a WAD).

use std::collections::HashMap;

use crate::geometry::{EPS, Plane, PlaneSet, Polygon, Side, V3, polygon_area, split_polygon};
use crate::tree::{
    Child, FaceKind, Tree, TreeFace, build_box_model, build_box_model_shaped,
    build_world_clip_hull_shaped, build_world_hull0, extract_faces,
};
use crate::world::{Aabb, Contents, HullSet, SurfaceClass, World};

/// BSP version number of GoldSrc maps.
pub const BSP_VERSION: i32 = 30;
/// Number of lumps in a v30 header.
pub const LUMP_COUNT: usize = 15;
/// Lump indices, in header order.
pub mod lump {
    pub const ENTITIES: usize = 0;
    pub const PLANES: usize = 1;
    pub const TEXTURES: usize = 2;
    pub const VERTICES: usize = 3;
    pub const VISIBILITY: usize = 4;
    pub const NODES: usize = 5;
    pub const TEXINFO: usize = 6;
    pub const FACES: usize = 7;
    pub const LIGHTING: usize = 8;
    pub const CLIPNODES: usize = 9;
    pub const LEAVES: usize = 10;
    pub const MARKSURFACES: usize = 11;
    pub const EDGES: usize = 12;
    pub const SURFEDGES: usize = 13;
    pub const MODELS: usize = 14;
}
/// Record sizes in bytes, indexed by lump (0 for byte lumps).
pub const RECORD_SIZE: [usize; LUMP_COUNT] = [0, 20, 0, 12, 0, 24, 40, 20, 0, 8, 28, 2, 4, 4, 64];

/// The texture of the water surface (a liquid: not sampled as a wall).
pub const WATER_TEXTURE: &str = "!water";

/// One BSP model: its hull-0 tree, clip trees for hulls 1–3 and its faces.
#[derive(Clone, Debug)]
pub struct CompiledModel {
    pub hull0: Tree,
    pub clip: [Tree; 3],
    /// Faces grouped by node, facing into free space (outward for brushes).
    pub faces: Vec<TreeFace>,
    /// Texture name of each face.
    pub textures: Vec<String>,
    /// Model bounds (min, max).
    pub bounds: (V3, V3),
    /// Entity keys (classname, …) for brush entities; empty for the world.
    pub entity: Vec<(String, String)>,
}

/// All trees of a world: model 0 is the world, then one per brush entity.
#[derive(Clone, Debug)]
pub struct Compiled {
    pub planes: PlaneSet,
    pub models: Vec<CompiledModel>,
}

/// Builds every tree of `world`.
///
/// ```
/// use mapgen::{bsp, worlds};
/// let w = worlds::box_room();
/// let c = bsp::compile(&w);
/// assert_eq!(c.models[0].hull0.contents([100.0, 100.0, 100.0]), w.contents([100.0, 100.0, 100.0]));
/// ```
pub fn compile(world: &World) -> Compiled {
    compile_for(world, HullSet::GoldSrc)
}

/// [`compile`] with the clip hulls of `hulls`' player boxes.
pub fn compile_for(world: &World, hulls: HullSet) -> Compiled {
    let mut planes = PlaneSet::default();
    let hull0 = build_world_hull0(world, &mut planes);
    let clip =
        [1, 2, 3].map(|h| build_world_clip_hull_shaped(world, &hull0, hulls.shape(h), &mut planes));
    let faces = extract_faces(&hull0, &|c| c.is_free());
    let textures = faces
        .iter()
        .map(|f| match f.kind {
            FaceKind::Boundary(c) => SurfaceClass::of(c, f.normal.into()).texture().to_string(),
            FaceKind::WaterSurface => WATER_TEXTURE.to_string(),
        })
        .collect();
    let (faces, textures) = subdivide_for_lightmaps(faces, textures);
    let b = world.bounds();
    let mut models = vec![CompiledModel {
        hull0,
        clip,
        faces,
        textures,
        bounds: (b.lo(), b.hi()),
        entity: Vec::new(),
    }];
    for (i, e) in world.brush_entities.iter().enumerate() {
        let (lo, hi) = (e.bounds.lo(), e.bounds.hi());
        let hull0 = build_box_model(lo, hi, 0, &mut planes);
        let clip = [1, 2, 3].map(|h| build_box_model_shaped(lo, hi, hulls.shape(h), &mut planes));
        let faces = extract_faces(&hull0, &|c| c == Contents::Empty);
        let textures = vec![e.texture.clone(); faces.len()];
        let (faces, textures) = subdivide_for_lightmaps(faces, textures);
        models.push(CompiledModel {
            hull0,
            clip,
            faces,
            textures,
            bounds: (lo, hi),
            entity: brush_entity_keys(&e.classname, &e.texture, i + 1),
        });
    }
    Compiled { planes, models }
}

/// Largest extent of a lit face along a texture axis, in units: GoldSrc
/// rejects faces wider than 256 lightmap texels ("Bad surface extents"), so
/// faces are cut on a 240-unit grid like hlbsp's default subdivision.
pub const SUBDIVIDE_SIZE: f64 = 240.0;

/// Textures without lightmaps (TEX_SPECIAL): sky, liquids, triggers.
pub fn is_special(texture: &str) -> bool {
    texture == "sky" || texture == "aaatrigger" || texture.starts_with(['!', '*'])
}

/// Cuts every lit face along its texture axes at multiples of
/// [`SUBDIVIDE_SIZE`]; the pieces keep node, leaves and texture.
fn subdivide_for_lightmaps(
    faces: Vec<TreeFace>,
    textures: Vec<String>,
) -> (Vec<TreeFace>, Vec<String>) {
    let mut out_faces = Vec::with_capacity(faces.len());
    let mut out_textures = Vec::with_capacity(textures.len());
    for (f, tex) in faces.into_iter().zip(textures) {
        let mut pieces = vec![f.polygon.clone()];
        if !is_special(&tex) {
            let axes = &BASE_AXES[base_axis(f.normal)];
            for v in [axes[1], axes[2]] {
                let axis = (0..3).find(|&i| v[i] != 0.0).expect("axial texture vector");
                pieces = pieces
                    .into_iter()
                    .flat_map(|p| cut_on_grid(p, axis, SUBDIVIDE_SIZE))
                    .collect();
            }
        }
        for polygon in pieces {
            out_faces.push(TreeFace {
                polygon,
                ..f.clone()
            });
            out_textures.push(tex.clone());
        }
    }
    (out_faces, out_textures)
}

/// Cuts a polygon by the planes `coordinate[axis] = k * size`.
fn cut_on_grid(poly: Polygon, axis: usize, size: f64) -> Vec<Polygon> {
    let (lo, hi) = poly
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v.get(axis)), h.max(v.get(axis)))
        });
    let mut pieces = Vec::new();
    let mut rest = poly;
    let mut k = (lo / size).floor() + 1.0;
    while k * size < hi - EPS {
        let plane = Plane {
            normal: V3::axis(axis),
            dist: k * size,
        };
        match split_polygon(&rest, &plane) {
            Side::Spanning(front, back) => {
                if back.len() >= 3 && polygon_area(&back) > EPS {
                    pieces.push(back);
                }
                rest = front;
            }
            Side::Back | Side::On => break,
            Side::Front => {}
        }
        k += 1.0;
    }
    if rest.len() >= 3 && polygon_area(&rest) > EPS {
        pieces.push(rest);
    }
    pieces
}

/// Entity keys of brush model `*model`; `{`-textures (alpha-tested fences)
/// get the render mode that shows them as GoldSrc maps do.
fn brush_entity_keys(classname: &str, texture: &str, model: usize) -> Vec<(String, String)> {
    let mut keys = vec![
        ("classname".to_string(), classname.to_string()),
        ("model".to_string(), format!("*{model}")),
    ];
    if texture.starts_with('{') {
        keys.push(("rendermode".into(), "4".into()));
        keys.push(("renderamt".into(), "255".into()));
    }
    keys
}

/// Compiles `world` and returns the bytes of its BSP v30 file.
///
/// ```
/// let bytes = mapgen::bsp::write_world(&mapgen::worlds::box_room());
/// assert_eq!(&bytes[..4], &30i32.to_le_bytes());
/// ```
pub fn write_world(world: &World) -> Vec<u8> {
    write(world, &compile(world))
}

/// A BSP29 file of `world` (Quake's format, which Half-Life's oldest maps use too)
/// with the clip hulls of `hulls`: the same lumps as v30, version 29.
///
/// ```
/// use mapgen::{bsp, world::HullSet, worlds};
/// let bytes = bsp::write_v29(&worlds::box_room(), HullSet::Quake);
/// assert_eq!(&bytes[..4], &29i32.to_le_bytes());
/// ```
pub fn write_v29(world: &World, hulls: HullSet) -> Vec<u8> {
    let mut bytes = write(world, &compile_for(world, hulls));
    bytes[..4].copy_from_slice(&29i32.to_le_bytes());
    bytes
}

/// The bytes of `world` with the world model's bounds set to `bounds` (for
/// [`crate::worlds::leaking_room`]: free space outside the written bounds).
pub fn write_with_world_bounds(world: &World, bounds: Aabb) -> Vec<u8> {
    let mut compiled = compile(world);
    compiled.models[0].bounds = (bounds.lo(), bounds.hi());
    write(world, &compiled)
}

/// The entity lump text: worldspawn, player starts at the spawn points, the
/// brush entities; NUL-terminated.
pub fn entities_text(world: &World, compiled: &Compiled) -> String {
    let mut s = String::new();
    s.push_str("{\n\"classname\" \"worldspawn\"\n");
    s.push_str(&format!("\"message\" \"mapgen: {}\"\n", world.name));
    s.push_str("\"skyname\" \"desert\"\n\"mapversion\" \"220\"\n}\n");
    for (i, p) in world.spawns.iter().enumerate() {
        let origin = format!("{} {} {}", p[0], p[1], p[2]);
        if i == 0 {
            s.push_str(&format!(
                "{{\n\"classname\" \"info_player_start\"\n\"origin\" \"{origin}\"\n\"angle\" \"0\"\n}}\n"
            ));
        }
        s.push_str(&format!(
            "{{\n\"classname\" \"info_player_deathmatch\"\n\"origin\" \"{origin}\"\n\"angle\" \"0\"\n}}\n"
        ));
    }
    for m in &compiled.models[1..] {
        s.push_str("{\n");
        for (k, v) in &m.entity {
            s.push_str(&format!("\"{k}\" \"{v}\"\n"));
        }
        s.push_str("}\n");
    }
    s.push('\0');
    s
}

/// Quake's texture projection axes: (face normal, s axis, t axis).
const BASE_AXES: [[[f32; 3]; 3]; 6] = [
    [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
    [[0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
    [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
    [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]],
];

fn base_axis(normal: V3) -> usize {
    let mut best = (f64::MIN, 0);
    for (i, a) in BASE_AXES.iter().enumerate() {
        let d = normal.dot(V3::new(a[0][0].into(), a[0][1].into(), a[0][2].into()));
        if d > best.0 {
            best = (d, i);
        }
    }
    best.1
}

/// Little-endian byte sink.
#[derive(Default)]
struct Buf(Vec<u8>);

impl Buf {
    fn i32(&mut self, v: i32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u32(&mut self, v: u32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn i16(&mut self, v: i16) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn u16(&mut self, v: u16) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn f32(&mut self, v: f32) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn bounds16(&mut self, (lo, hi): (V3, V3)) {
        let clamp = |v: f64| v.clamp(-32768.0, 32767.0) as i16;
        for i in 0..3 {
            self.i16(clamp(lo.get(i).floor()));
        }
        for i in 0..3 {
            self.i16(clamp(hi.get(i).ceil()));
        }
    }
}

fn u16_index(v: usize, what: &str) -> u16 {
    u16::try_from(v).unwrap_or_else(|_| panic!("too many {what} for BSP v30: {v}"))
}

fn i16_index(v: i64, what: &str) -> i16 {
    i16::try_from(v).unwrap_or_else(|_| panic!("{what} index out of i16 range: {v}"))
}

/// Where each model's records start in the shared lumps, and which BSP leaf
/// each tree leaf becomes.
struct Layout {
    /// Per model: tree leaf index → BSP leaf index (0 = the shared solid leaf).
    leaf_maps: Vec<Vec<usize>>,
    /// BSP leaves 1.. as (model, tree leaf).
    leaf_list: Vec<(usize, usize)>,
    face_offsets: Vec<usize>,
    node_offsets: Vec<usize>,
    /// Per model: the first clipnode of hulls 1, 2, 3.
    clip_roots: Vec<[usize; 3]>,
}

impl Layout {
    fn new(compiled: &Compiled) -> Self {
        let mut layout = Layout {
            leaf_maps: Vec::new(),
            leaf_list: Vec::new(),
            face_offsets: Vec::new(),
            node_offsets: Vec::new(),
            clip_roots: Vec::new(),
        };
        let (mut faces, mut nodes, mut clipnodes) = (0, 0, 0);
        for (mi, m) in compiled.models.iter().enumerate() {
            let mut map = Vec::with_capacity(m.hull0.leaves.len());
            for (li, l) in m.hull0.leaves.iter().enumerate() {
                if l.contents == Contents::Solid {
                    map.push(0);
                } else {
                    layout.leaf_list.push((mi, li));
                    map.push(layout.leaf_list.len());
                }
            }
            layout.leaf_maps.push(map);
            layout.face_offsets.push(faces);
            layout.node_offsets.push(nodes);
            faces += m.faces.len();
            nodes += m.hull0.nodes.len();
            let mut roots = [0; 3];
            for (root, t) in roots.iter_mut().zip(&m.clip) {
                *root = clipnodes;
                clipnodes += t.nodes.len();
            }
            layout.clip_roots.push(roots);
        }
        layout
    }
}

/// Serialises compiled trees as a BSP v30 file.
///
/// Panics only if the world is far too big for the format's 16-bit indices
/// (the standard worlds are tiny).
pub fn write(world: &World, compiled: &Compiled) -> Vec<u8> {
    let layout = Layout::new(compiled);
    let mut lumps: Vec<Buf> = (0..LUMP_COUNT).map(|_| Buf::default()).collect();
    write_planes(&compiled.planes, &mut lumps[lump::PLANES]);
    let (textures, texinfos) = write_faces(compiled, &mut lumps);
    write_texinfo(&textures, &texinfos, &mut lumps[lump::TEXINFO]);
    write_textures(&textures, &mut lumps[lump::TEXTURES]);
    write_nodes(compiled, &layout, &mut lumps[lump::NODES]);
    let (leaves, marks) = two_lumps(&mut lumps, lump::LEAVES, lump::MARKSURFACES);
    write_leaves(compiled, &layout, leaves, marks);
    write_clipnodes(compiled, &layout, &mut lumps[lump::CLIPNODES]);
    write_models(compiled, &layout, &mut lumps[lump::MODELS]);
    lumps[lump::ENTITIES]
        .0
        .extend_from_slice(entities_text(world, compiled).as_bytes());
    assemble(&lumps)
}

fn two_lumps(lumps: &mut [Buf], a: usize, b: usize) -> (&mut Buf, &mut Buf) {
    assert!(a < b);
    let (lo, hi) = lumps.split_at_mut(b);
    (&mut lo[a], &mut hi[0])
}

fn write_planes(planes: &PlaneSet, b: &mut Buf) {
    for p in planes.iter() {
        for i in 0..3 {
            b.f32(p.normal.get(i) as f32);
        }
        b.f32(p.dist as f32);
        b.i32(match p.axial() {
            Some(a) => a as i32,
            None => 3 + p.dominant_axis() as i32,
        });
    }
}

/// Faces with their vertices, edges and surfedges; returns the texture names
/// and the (texture, projection axis) pairs of the texinfo records.
fn write_faces(compiled: &Compiled, lumps: &mut [Buf]) -> (Vec<String>, Vec<(usize, usize)>) {
    let mut textures: Vec<String> = Vec::new();
    let mut texinfos: Vec<(usize, usize)> = Vec::new();
    let mut vertex_ids: HashMap<[u32; 3], u16> = HashMap::new();
    let mut edge_ids: HashMap<(u16, u16), i32> = HashMap::new();
    let mut edge_count = 1usize; // edge 0 is unused
    lumps[lump::EDGES].u16(0);
    lumps[lump::EDGES].u16(0);
    let mut surfedge_count = 0usize;
    for m in &compiled.models {
        for (f, tex) in m.faces.iter().zip(&m.textures) {
            let t = index_of(&mut textures, tex.clone());
            let ti = index_of(&mut texinfos, (t, base_axis(f.normal)));
            let node = &m.hull0.nodes[f.node];
            let side = u16::from(f.normal.dot(node.plane.normal) < 0.0);
            // BSP windings run clockwise seen from the front.
            let mut ids = Vec::with_capacity(f.polygon.len());
            for v in f.polygon.iter().rev() {
                let key = [v.x as f32, v.y as f32, v.z as f32].map(f32::to_bits);
                let next = vertex_ids.len();
                let id = *vertex_ids.entry(key).or_insert_with(|| {
                    for c in key {
                        lumps[lump::VERTICES].f32(f32::from_bits(c));
                    }
                    u16_index(next, "vertices")
                });
                ids.push(id);
            }
            let first_edge = surfedge_count;
            for i in 0..ids.len() {
                let (a, b) = (ids[i], ids[(i + 1) % ids.len()]);
                let se = if let Some(&e) = edge_ids.get(&(b, a)) {
                    -e
                } else if let Some(&e) = edge_ids.get(&(a, b)) {
                    e
                } else {
                    let e = edge_count as i32;
                    edge_count += 1;
                    edge_ids.insert((a, b), e);
                    lumps[lump::EDGES].u16(a);
                    lumps[lump::EDGES].u16(b);
                    e
                };
                lumps[lump::SURFEDGES].i32(se);
                surfedge_count += 1;
            }
            let b = &mut lumps[lump::FACES];
            b.u16(u16_index(node.plane_id, "planes"));
            b.u16(side);
            b.i32(first_edge as i32);
            b.u16(u16_index(ids.len(), "edges per face"));
            b.u16(u16_index(ti, "texinfo"));
            b.0.extend_from_slice(&[0, 255, 255, 255]);
            b.i32(-1);
        }
    }
    u16_index(edge_count, "edges");
    (textures, texinfos)
}

/// Index of `item` in `list`, appending it when new (first-use order).
fn index_of<T: PartialEq>(list: &mut Vec<T>, item: T) -> usize {
    match list.iter().position(|x| *x == item) {
        Some(i) => i,
        None => {
            list.push(item);
            list.len() - 1
        }
    }
}

fn write_texinfo(textures: &[String], texinfos: &[(usize, usize)], b: &mut Buf) {
    for &(t, axis) in texinfos {
        for v in [BASE_AXES[axis][1], BASE_AXES[axis][2]] {
            for c in v {
                b.f32(c);
            }
            b.f32(0.0);
        }
        b.i32(t as i32);
        let name = &textures[t];
        b.i32(i32::from(is_special(name)));
    }
}

/// The miptex lump: named 64×64 headers without pixels (they live in a WAD).
fn write_textures(textures: &[String], b: &mut Buf) {
    b.i32(textures.len() as i32);
    let header = 4 + 4 * textures.len();
    for i in 0..textures.len() {
        b.i32((header + 40 * i) as i32);
    }
    for t in textures {
        let mut name = [0u8; 16];
        let bytes = t.as_bytes();
        assert!(bytes.len() < 16, "texture name too long: {t}");
        name[..bytes.len()].copy_from_slice(bytes);
        b.0.extend_from_slice(&name);
        b.u32(64);
        b.u32(64);
        for _ in 0..4 {
            b.u32(0);
        }
    }
}

fn write_nodes(compiled: &Compiled, layout: &Layout, b: &mut Buf) {
    for (mi, m) in compiled.models.iter().enumerate() {
        let mut first = vec![0usize; m.hull0.nodes.len()];
        let mut count = vec![0usize; m.hull0.nodes.len()];
        for (fi, f) in m.faces.iter().enumerate().rev() {
            first[f.node] = fi;
            count[f.node] += 1;
        }
        for (ni, n) in m.hull0.nodes.iter().enumerate() {
            b.i32(n.plane_id as i32);
            for c in [n.front, n.back] {
                let v = match c {
                    Child::Node(i) => (layout.node_offsets[mi] + i) as i64,
                    Child::Leaf(l) => -(layout.leaf_maps[mi][l] as i64) - 1,
                };
                b.i16(i16_index(v, "node child"));
            }
            b.bounds16(n.bounds);
            let ff = if count[ni] == 0 {
                0
            } else {
                layout.face_offsets[mi] + first[ni]
            };
            b.u16(u16_index(ff, "faces"));
            b.u16(u16_index(count[ni], "faces per node"));
        }
    }
}

/// Leaf 0 (shared solid), then every other leaf with the faces bordering it
/// as its marksurfaces.
fn write_leaves(compiled: &Compiled, layout: &Layout, b: &mut Buf, marks: &mut Buf) {
    b.i32(Contents::Solid.bsp_value());
    b.i32(-1);
    b.bounds16((V3::ZERO, V3::ZERO));
    b.u16(0);
    b.u16(0);
    b.0.extend_from_slice(&[0; 4]);
    let mut mark_count = 0usize;
    for &(mi, li) in &layout.leaf_list {
        let m = &compiled.models[mi];
        let leaf = &m.hull0.leaves[li];
        let first = mark_count;
        for (fi, f) in m.faces.iter().enumerate() {
            if f.free_leaf == li {
                marks.u16(u16_index(layout.face_offsets[mi] + fi, "faces"));
                mark_count += 1;
            }
        }
        b.i32(leaf.contents.bsp_value());
        b.i32(-1);
        b.bounds16(leaf.cell.bounds());
        b.u16(u16_index(first, "marksurfaces"));
        b.u16(u16_index(mark_count - first, "marksurfaces"));
        b.0.extend_from_slice(&[0; 4]);
    }
}

fn write_clipnodes(compiled: &Compiled, layout: &Layout, b: &mut Buf) {
    for (mi, m) in compiled.models.iter().enumerate() {
        for (h, t) in m.clip.iter().enumerate() {
            for n in &t.nodes {
                b.i32(n.plane_id as i32);
                for c in [n.front, n.back] {
                    let v = match c {
                        Child::Node(i) => (layout.clip_roots[mi][h] + i) as i64,
                        Child::Leaf(l) => t.leaves[l].contents.bsp_value() as i64,
                    };
                    b.i16(i16_index(v, "clipnode child"));
                }
            }
        }
    }
}

fn write_models(compiled: &Compiled, layout: &Layout, b: &mut Buf) {
    for (mi, m) in compiled.models.iter().enumerate() {
        for v in [m.bounds.0, m.bounds.1, V3::ZERO] {
            for i in 0..3 {
                b.f32(v.get(i) as f32);
            }
        }
        b.i32(layout.node_offsets[mi] as i32);
        for root in layout.clip_roots[mi] {
            b.i32(root as i32);
        }
        let visleafs = if mi == 0 {
            layout.leaf_list.iter().filter(|(m, _)| *m == 0).count()
        } else {
            0
        };
        b.i32(visleafs as i32);
        b.i32(layout.face_offsets[mi] as i32);
        b.i32(m.faces.len() as i32);
    }
}

/// Header (version + lump directory) followed by the lumps, each padded to
/// a multiple of 4 bytes.
fn assemble(lumps: &[Buf]) -> Vec<u8> {
    let header_len = 4 + 8 * LUMP_COUNT;
    let mut out = Buf::default();
    out.i32(BSP_VERSION);
    let mut offset = header_len;
    for l in lumps {
        out.i32(offset as i32);
        out.i32(l.0.len() as i32);
        offset += l.0.len().next_multiple_of(4);
    }
    for l in lumps {
        out.0.extend_from_slice(&l.0);
        out.0.resize(out.0.len().next_multiple_of(4), 0);
    }
    out.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::manifest::Manifest;
    use crate::testutil::{Rng, standard};

    /// A minimal independent reader of the bytes we write: lump table,
    /// records, and point walks through nodes and clipnodes with f32 planes.
    struct Parsed<'a> {
        data: &'a [u8],
        lumps: [(usize, usize); LUMP_COUNT],
    }

    impl<'a> Parsed<'a> {
        fn new(data: &'a [u8]) -> Self {
            assert!(data.len() >= 4 + 8 * LUMP_COUNT);
            assert_eq!(
                i32::from_le_bytes(data[0..4].try_into().unwrap()),
                BSP_VERSION
            );
            let mut lumps = [(0, 0); LUMP_COUNT];
            let mut spans = Vec::new();
            for (i, l) in lumps.iter_mut().enumerate() {
                let at = 4 + 8 * i;
                let ofs = i32::from_le_bytes(data[at..at + 4].try_into().unwrap());
                let len = i32::from_le_bytes(data[at + 4..at + 8].try_into().unwrap());
                assert!(ofs >= 0 && len >= 0, "lump {i}");
                let (ofs, len) = (ofs as usize, len as usize);
                assert_eq!(ofs % 4, 0, "lump {i} alignment");
                assert!(ofs + len <= data.len(), "lump {i} past the end");
                if RECORD_SIZE[i] > 0 {
                    assert_eq!(len % RECORD_SIZE[i], 0, "lump {i} record size");
                }
                spans.push((ofs, ofs + len));
                *l = (ofs, len);
            }
            spans.sort();
            for p in spans.windows(2) {
                assert!(p[0].1 <= p[1].0, "overlapping lumps");
            }
            Parsed { data, lumps }
        }
        fn count(&self, l: usize) -> usize {
            self.lumps[l].1 / RECORD_SIZE[l]
        }
        fn bytes(&self, l: usize, i: usize, at: usize, n: usize) -> &[u8] {
            let start = self.lumps[l].0 + i * RECORD_SIZE[l] + at;
            &self.data[start..start + n]
        }
        fn i32(&self, l: usize, i: usize, at: usize) -> i32 {
            i32::from_le_bytes(self.bytes(l, i, at, 4).try_into().unwrap())
        }
        fn f32(&self, l: usize, i: usize, at: usize) -> f32 {
            f32::from_le_bytes(self.bytes(l, i, at, 4).try_into().unwrap())
        }
        fn i16(&self, l: usize, i: usize, at: usize) -> i16 {
            i16::from_le_bytes(self.bytes(l, i, at, 2).try_into().unwrap())
        }
        fn u16(&self, l: usize, i: usize, at: usize) -> u16 {
            u16::from_le_bytes(self.bytes(l, i, at, 2).try_into().unwrap())
        }
        fn plane_distance(&self, plane: usize, p: [f64; 3]) -> f64 {
            let n = [0, 4, 8].map(|at| f64::from(self.f32(lump::PLANES, plane, at)));
            n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - f64::from(self.f32(lump::PLANES, plane, 12))
        }
        /// Hull-0 leaf contents at `p`, starting from node `head`.
        fn point_contents(&self, head: i32, p: [f64; 3]) -> i32 {
            let mut n = head;
            while n >= 0 {
                let plane = self.i32(lump::NODES, n as usize, 0) as usize;
                let side = if self.plane_distance(plane, p) >= 0.0 {
                    4
                } else {
                    6
                };
                n = self.i16(lump::NODES, n as usize, side).into();
            }
            self.i32(lump::LEAVES, (-n - 1) as usize, 0)
        }
        /// Clip-hull contents at `p`, starting from clipnode `head`.
        fn clip_contents(&self, head: i32, p: [f64; 3]) -> i32 {
            let mut n = head;
            while n >= 0 {
                let plane = self.i32(lump::CLIPNODES, n as usize, 0) as usize;
                let side = if self.plane_distance(plane, p) >= 0.0 {
                    4
                } else {
                    6
                };
                n = self.i16(lump::CLIPNODES, n as usize, side).into();
            }
            n
        }
        fn texture_name(&self, miptex: usize) -> String {
            let (ofs, _) = self.lumps[lump::TEXTURES];
            let at = i32::from_le_bytes(
                self.data[ofs + 4 + 4 * miptex..ofs + 8 + 4 * miptex]
                    .try_into()
                    .unwrap(),
            ) as usize;
            let name = &self.data[ofs + at..ofs + at + 16];
            let end = name.iter().position(|&b| b == 0).unwrap();
            String::from_utf8(name[..end].to_vec()).unwrap()
        }
    }

    #[test]
    fn written_maps_have_consistent_lumps_and_indices() {
        for (w, c) in standard() {
            let bytes = write(w, c);
            assert!(bytes.len() <= 200_000, "{}: {} bytes", w.name, bytes.len());
            let p = Parsed::new(&bytes);
            let n = |l| p.count(l);
            let (planes, nodes, leaves, faces) = (
                n(lump::PLANES),
                n(lump::NODES),
                n(lump::LEAVES),
                n(lump::FACES),
            );
            for i in 0..planes {
                let t = p.i32(lump::PLANES, i, 16);
                assert!((0..6).contains(&t));
                if t < 3 {
                    assert_eq!(
                        p.f32(lump::PLANES, i, 4 * t as usize),
                        1.0,
                        "axial plane {i}"
                    );
                }
            }
            for i in 0..nodes {
                assert!((p.i32(lump::NODES, i, 0) as usize) < planes);
                for side in [4, 6] {
                    let ch = p.i16(lump::NODES, i, side) as i64;
                    assert!(if ch >= 0 {
                        (ch as usize) < nodes
                    } else {
                        ((-ch - 1) as usize) < leaves
                    });
                }
                let (ff, nf) = (
                    p.u16(lump::NODES, i, 20) as usize,
                    p.u16(lump::NODES, i, 22) as usize,
                );
                assert!(ff + nf <= faces);
            }
            assert_eq!(p.i32(lump::LEAVES, 0, 0), Contents::Solid.bsp_value());
            let marks = n(lump::MARKSURFACES);
            for i in 0..leaves {
                let c = p.i32(lump::LEAVES, i, 0);
                assert!([-1, -2, -3, -6].contains(&c));
                assert_eq!(p.i32(lump::LEAVES, i, 4), -1);
                let (fm, nm) = (
                    p.u16(lump::LEAVES, i, 20) as usize,
                    p.u16(lump::LEAVES, i, 22) as usize,
                );
                assert!(fm + nm <= marks);
            }
            // Every face is listed by exactly one node and by the
            // marksurfaces of exactly one leaf (the free leaf it faces).
            let mut by_node = vec![0; faces];
            for i in 0..nodes {
                let (ff, nf) = (
                    p.u16(lump::NODES, i, 20) as usize,
                    p.u16(lump::NODES, i, 22) as usize,
                );
                by_node[ff..ff + nf].iter_mut().for_each(|c| *c += 1);
            }
            let mut by_leaf = vec![0; faces];
            for i in 0..marks {
                let f = p.u16(lump::MARKSURFACES, i, 0) as usize;
                assert!(f < faces);
                by_leaf[f] += 1;
            }
            let world_face_count = p.i32(lump::MODELS, 0, 60) as usize;
            assert!(
                by_node.iter().all(|&c| c == 1),
                "{}: node face ranges",
                w.name
            );
            assert!(
                by_leaf[..world_face_count].iter().all(|&c| c == 1),
                "{}: marksurfaces",
                w.name
            );
            let (edges, surfedges, verts, texinfo) = (
                n(lump::EDGES),
                n(lump::SURFEDGES),
                n(lump::VERTICES),
                n(lump::TEXINFO),
            );
            for i in 0..edges {
                for at in [0, 2] {
                    assert!((p.u16(lump::EDGES, i, at) as usize) < verts);
                }
            }
            for i in 0..surfedges {
                let e = p.i32(lump::SURFEDGES, i, 0);
                assert!(e != 0 && (e.unsigned_abs() as usize) < edges);
            }
            let textures = i32::from_le_bytes(
                p.data[p.lumps[lump::TEXTURES].0..p.lumps[lump::TEXTURES].0 + 4]
                    .try_into()
                    .unwrap(),
            ) as usize;
            for i in 0..texinfo {
                assert!((p.i32(lump::TEXINFO, i, 32) as usize) < textures);
            }
            let models = n(lump::MODELS);
            assert_eq!(models, 1 + w.brush_entities.len());
            let world_faces = p.i32(lump::MODELS, 0, 60) as usize;
            for i in 0..faces {
                let plane = p.u16(lump::FACES, i, 0) as usize;
                assert!(plane < planes);
                let side = p.u16(lump::FACES, i, 2);
                let (fe, ne) = (
                    p.i32(lump::FACES, i, 4) as usize,
                    p.u16(lump::FACES, i, 8) as usize,
                );
                assert!(ne >= 3 && fe + ne <= surfedges);
                let ti = p.u16(lump::FACES, i, 10) as usize;
                assert!(ti < texinfo);
                // Vertices on the plane; clockwise winding seen from the front.
                let vs: Vec<V3> = (fe..fe + ne)
                    .map(|k| {
                        let e = p.i32(lump::SURFEDGES, k, 0);
                        let v = if e > 0 {
                            p.u16(lump::EDGES, e as usize, 0)
                        } else {
                            p.u16(lump::EDGES, (-e) as usize, 2)
                        } as usize;
                        V3::new(
                            p.f32(lump::VERTICES, v, 0).into(),
                            p.f32(lump::VERTICES, v, 4).into(),
                            p.f32(lump::VERTICES, v, 8).into(),
                        )
                    })
                    .collect();
                for v in &vs {
                    assert!(p.plane_distance(plane, (*v).into()).abs() < 1e-3);
                }
                let mut facing = -crate::geometry::polygon_area_vector(&vs).normalized();
                let pn = V3::new(
                    p.f32(lump::PLANES, plane, 0).into(),
                    p.f32(lump::PLANES, plane, 4).into(),
                    p.f32(lump::PLANES, plane, 8).into(),
                );
                if side == 1 {
                    facing = -facing;
                }
                assert!(
                    (facing - pn).length() < 1e-4,
                    "{} face {i} winding/side",
                    w.name
                );
                let name = p.texture_name(p.i32(lump::TEXINFO, ti, 32) as usize);
                // Lightmap extents as GoldSrc computes them (16-unit texels).
                if !is_special(&name) {
                    for axis in 0..2 {
                        let st: Vec<f64> = vs
                            .iter()
                            .map(|v| {
                                let at = 16 * axis;
                                let c = [0, 4, 8, 12]
                                    .map(|o| f64::from(p.f32(lump::TEXINFO, ti, at + o)));
                                v.x * c[0] + v.y * c[1] + v.z * c[2] + c[3]
                            })
                            .collect();
                        let lo = (st.iter().cloned().fold(f64::MAX, f64::min) / 16.0).floor();
                        let hi = (st.iter().cloned().fold(f64::MIN, f64::max) / 16.0).ceil();
                        assert!((hi - lo) * 16.0 <= 256.0, "{} face {i}: extents", w.name);
                    }
                }
                let allowed: &[&str] = if i < world_faces {
                    &["wall", "floor", "ceiling", "sky", WATER_TEXTURE]
                } else {
                    &["aaatrigger", "{fence"]
                };
                assert!(
                    allowed.contains(&name.as_str()),
                    "{} face {i}: {name}",
                    w.name
                );
            }
            let ents = &p.data[p.lumps[0].0..p.lumps[0].0 + p.lumps[0].1];
            assert_eq!(ents.last(), Some(&0));
            let text = std::str::from_utf8(&ents[..ents.len() - 1]).unwrap();
            assert_eq!(
                text.matches("info_player_deathmatch").count(),
                w.spawns.len()
            );
            assert!(text.starts_with("{\n\"classname\" \"worldspawn\""));
        }
    }

    #[test]
    fn written_trees_answer_like_the_world() {
        for (w, c) in standard() {
            let bytes = write(w, c);
            let p = Parsed::new(&bytes);
            let head = |h: usize| p.i32(lump::MODELS, 0, 36 + 4 * h);
            let mut rng = Rng::new(7);
            for _ in 0..20_000 {
                let q = rng.point_in(&w.bounds(), 32.0);
                if w.distance_to_boundary(q) < 1e-3 {
                    continue;
                }
                assert_eq!(
                    p.point_contents(head(0), q),
                    w.contents(q).bsp_value(),
                    "{} {q:?}",
                    w.name
                );
            }
            for hull in 1..=3 {
                let tree = &c.models[0].clip[hull - 1];
                for _ in 0..5_000 {
                    let q = rng.point_in(&w.free_bounds(), 48.0);
                    if tree.path_plane_distance(q) < 1e-3 {
                        continue;
                    }
                    let expected = w.hull_contents(hull, q).bsp_value();
                    assert_eq!(
                        p.clip_contents(head(hull), q),
                        expected,
                        "{} hull {hull}",
                        w.name
                    );
                }
            }
            // Brush entities: solid inside their box in every hull.
            for (i, e) in w.brush_entities.iter().enumerate() {
                let m = i + 1;
                let centre = [0, 1, 2].map(|k| 0.5 * (e.bounds.min[k] + e.bounds.max[k]));
                let head0 = p.i32(lump::MODELS, m, 36);
                assert_eq!(p.point_contents(head0, centre), -2);
                let outside = [centre[0], centre[1], e.bounds.max[2] + 40.0];
                assert_eq!(p.point_contents(head0, outside), -1);
                for hull in 1..=3 {
                    let h = p.i32(lump::MODELS, m, 36 + 4 * hull);
                    assert_eq!(p.clip_contents(h, centre), -2);
                    assert_eq!(
                        p.clip_contents(h, [centre[0], centre[1], e.bounds.max[2] + 40.0]),
                        -1
                    );
                }
            }
        }
    }

    #[test]
    fn written_trees_are_exact_to_1e3_next_to_walls() {
        // Points 1.5e-3 in front of and behind every wall polygon: the f32
        // planes of the file must still classify them like the world.
        for (w, c) in standard() {
            let bytes = write(w, c);
            let p = Parsed::new(&bytes);
            let head = p.i32(lump::MODELS, 0, 36);
            let mut rng = Rng::new(10);
            let mut tested = 0;
            for poly in w.wall_polygons() {
                let v: Vec<V3> = poly.vertices.iter().map(|&x| x.into()).collect();
                let n = V3::from(poly.normal);
                for _ in 0..20 {
                    let k = 1 + (rng.next_u64() as usize) % (v.len() - 2);
                    let (mut a, mut b) = (rng.unit(), rng.unit());
                    if a + b > 1.0 {
                        (a, b) = (1.0 - a, 1.0 - b);
                    }
                    let on = v[0] + (v[k] - v[0]) * a + (v[k + 1] - v[0]) * b;
                    for off in [1.5e-3, -1.5e-3] {
                        let q: [f64; 3] = (on + n * off).into();
                        if w.distance_to_boundary(q) < 1e-3 {
                            continue;
                        }
                        tested += 1;
                        assert_eq!(
                            p.point_contents(head, q),
                            w.contents(q).bsp_value(),
                            "{} {q:?}",
                            w.name
                        );
                    }
                }
            }
            assert!(tested > 100, "{}: {tested}", w.name);
        }
    }

    #[test]
    fn committed_maps_are_regenerated_byte_identically() {
        for (w, c) in standard() {
            let bytes = write(w, c);
            let json = Manifest::new(w, c, bytes.len()).to_json();
            let bsp_path = crate::worlds::committed_map_path(&w.name, "bsp");
            let json_path = crate::worlds::committed_map_path(&w.name, "json");
            let on_disk = std::fs::read(&bsp_path).expect("committed map");
            assert!(
                on_disk == bytes,
                "{} differs from the generator: run `cargo run -p mapgen -- --out testdata/maps`",
                bsp_path.display()
            );
            let on_disk = std::fs::read_to_string(&json_path).expect("committed manifest");
            assert!(
                on_disk == json,
                "{} differs from the generator",
                json_path.display()
            );
            let back = World::from_manifest_json(&on_disk).unwrap();
            assert_eq!(back.contents([1.0, 1.0, 1.0]), w.contents([1.0, 1.0, 1.0]));
            assert_eq!(back.free, w.free);
            assert_eq!(back.ramps, w.ramps);
        }
    }

    #[test]
    fn writing_twice_gives_the_same_bytes() {
        let w = crate::worlds::complex();
        assert_eq!(write_world(&w), write_world(&w));
    }
}
