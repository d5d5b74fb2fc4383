//! The normalised in-memory map every reader produces and every tool uses: planes,
//! the hull-0 tree and its leaves, clip hulls, faces with their edges, textures,
//! models and entities, with 32-bit indices whatever the file stored.

use crate::entities::Entity;
use crate::error::BspError;
use crate::faces::{FaceClass, classify_texture};
use std::path::Path;

/// Leaf and clip-hull contents values shared by Quake and GoldSrc.
pub mod contents {
    pub const EMPTY: i32 = -1;
    pub const SOLID: i32 = -2;
    pub const WATER: i32 = -3;
    pub const SLIME: i32 = -4;
    pub const LAVA: i32 = -5;
    pub const SKY: i32 = -6;
    /// GoldSrc: origin brushes (removed by the compiler, but tolerated).
    pub const ORIGIN: i32 = -7;
    /// GoldSrc: player clip.
    pub const CLIP: i32 = -8;
    /// GoldSrc: flowing water, six directions (-9 ..= -14).
    pub const CURRENT_0: i32 = -9;
    pub const CURRENT_DOWN: i32 = -14;
    /// GoldSrc: translucent water.
    pub const TRANSLUCENT: i32 = -15;

    /// Whether a contents value is a liquid (water, slime, lava, currents, translucent).
    pub fn is_liquid(c: i32) -> bool {
        matches!(c, WATER | SLIME | LAVA | TRANSLUCENT) || (CURRENT_DOWN..=CURRENT_0).contains(&c)
    }

    /// A short name for logs.
    pub fn name(c: i32) -> &'static str {
        match c {
            EMPTY => "empty",
            SOLID => "solid",
            WATER => "water",
            SLIME => "slime",
            LAVA => "lava",
            SKY => "sky",
            ORIGIN => "origin",
            CLIP => "clip",
            TRANSLUCENT => "translucent",
            c if (CURRENT_DOWN..=CURRENT_0).contains(&c) => "current",
            _ => "unknown",
        }
    }
}

/// Which member of the BSP family a file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BspVersion {
    /// Quake 1 (and the oldest Half-Life maps).
    Bsp29,
    /// GoldSrc (Half-Life, Counter-Strike, ...).
    GoldSrc30,
    /// Quake BSP2: 32-bit indices, float bounds.
    Bsp2,
    /// The first BSP2 draft: 32-bit indices, 16-bit bounds.
    Bsp2psb,
    /// Quake 2 (IBSP 38).
    Quake2,
    /// Quake 2 with Qbism's 32-bit indices (QBSP 38).
    Quake2Qbism,
    /// Quake 3 (IBSP 46: OpenArena, ioquake3).
    Quake3,
}

/// The game (engine family) a map is made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Game {
    /// Quake and its source ports (BSP29, BSP2, 2PSB).
    Quake,
    /// Half-Life, Counter-Strike and the other GoldSrc games (v30).
    GoldSrc,
    /// Quake 2 (IBSP 38, Qbism's QBSP 38).
    Quake2,
    /// Quake 3 Arena and its heirs (IBSP 46: OpenArena, ioquake3).
    Quake3,
}

impl Game {
    /// The game's name for logs and `vdgview info`.
    pub fn name(self) -> &'static str {
        match self {
            Game::Quake => "Quake",
            Game::GoldSrc => "GoldSrc (Half-Life, Counter-Strike)",
            Game::Quake2 => "Quake 2",
            Game::Quake3 => "Quake 3 (OpenArena, ioquake3)",
        }
    }
}

impl BspVersion {
    /// The game the format belongs to. BSP29 is Quake's, though Half-Life's oldest
    /// retail maps use it too.
    pub fn game(self) -> Game {
        match self {
            BspVersion::GoldSrc30 => Game::GoldSrc,
            BspVersion::Bsp29 | BspVersion::Bsp2 | BspVersion::Bsp2psb => Game::Quake,
            BspVersion::Quake2 | BspVersion::Quake2Qbism => Game::Quake2,
            BspVersion::Quake3 => Game::Quake3,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            BspVersion::Bsp29 => "BSP29 (Quake)",
            BspVersion::GoldSrc30 => "BSP30 (GoldSrc)",
            BspVersion::Bsp2 => "BSP2",
            BspVersion::Bsp2psb => "2PSB",
            BspVersion::Quake2 => "IBSP 38 (Quake 2)",
            BspVersion::Quake2Qbism => "QBSP 38 (Quake 2, Qbism)",
            BspVersion::Quake3 => "IBSP 46 (Quake 3)",
        }
    }
}

/// A splitting plane: points p with `normal · p - dist >= 0` are in front.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Plane {
    pub normal: [f32; 3],
    pub dist: f32,
    /// 0, 1, 2: axial along X, Y, Z; 3, 4, 5: non-axial, mostly along X, Y, Z.
    pub kind: i32,
}

/// A node of the hull-0 tree. A child `c >= 0` is a node, `c < 0` is leaf `-(c + 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Node {
    pub plane: u32,
    pub children: [i32; 2],
    pub first_face: u32,
    pub num_faces: u32,
}

/// A leaf of the hull-0 tree: a convex cell with one contents value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leaf {
    /// In the Quake convention ([`contents`]) whatever the format stored.
    pub contents: i32,
    /// As the file stored it: the same value in the Quake 1 family, the contents bit
    /// flags in Quake 2 ([`crate::quake2::contents`]).
    pub native_contents: i32,
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_marksurface: u32,
    pub num_marksurfaces: u32,
    /// The brushes that touch the leaf, in [`Bsp::leaf_brushes`] (Quake 2 and 3; none
    /// in the Quake 1 family, whose files keep no brushes).
    pub first_brush: u32,
    pub num_brushes: u32,
}

/// A convex brush of the source map (Quake 2 keeps them for collision): the
/// intersection of its sides' back half-spaces.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Brush {
    pub first_side: u32,
    pub num_sides: u32,
    /// The format's native contents flags ([`crate::quake2::contents`]).
    pub contents: i32,
}

/// A side of a brush: its plane faces out of the brush.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BrushSide {
    pub plane: u32,
    pub texinfo: i32,
}

/// A node of a clip hull. A child `c >= 0` is a clip node, `c < 0` is a contents value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipNode {
    pub plane: u32,
    pub children: [i32; 2],
}

/// A planar convex polygon of the map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Face {
    pub plane: u32,
    /// True when the face looks along the negative plane normal.
    pub back_side: bool,
    pub first_edge: u32,
    pub num_edges: u32,
    pub texinfo: u32,
}

/// Texture projection and the texture it uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexInfo {
    pub vecs: [[f32; 4]; 2],
    /// Index into [`Bsp::textures`]; may be out of range in odd maps (treated as unnamed).
    pub miptex: i32,
    /// Surface flags where the format has them (Quake 2 and 3).
    pub flags: i32,
    /// The shader's contents flags (Quake 3, [`crate::quake3::contents`]); 0 elsewhere.
    pub contents: i32,
}

/// A texture's name and size (the pixels are not needed here).
#[derive(Debug, Clone, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
}

/// A brush model: model 0 is the world, `*N` are brush entities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Model {
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub origin: [f32; 3],
    /// Hull 0 root in [`Bsp::nodes`]; hulls 1..3 roots in [`Bsp::clipnodes`]
    /// (a negative root is a contents value, i.e. an empty hull). Clip hull roots are
    /// stored as in the file and may be out of range: read them through
    /// [`Model::clip_headnode`].
    pub headnode: [i32; 4],
    pub first_face: u32,
    pub num_faces: u32,
}

impl Model {
    /// The root of clip hull `hull` (1..=3) in a map with `clipnodes` clip nodes, or
    /// `None` when the hull has no tree to walk.
    ///
    /// The engines copy these roots unchecked and trace a hull only for the model's
    /// own entity; compilers write the clip node count as the root of a hull that got
    /// no node (found in 18 of 331 Counter-Strike maps of a public server). Such a hull
    /// is unused, as is every hull of a map compiled without clip hulls.
    pub fn clip_headnode(&self, hull: usize, clipnodes: usize) -> Option<i32> {
        let h = *self.headnode.get(hull).filter(|_| hull >= 1)?;
        (clipnodes > 0 && (h as i64) < clipnodes as i64).then_some(h)
    }
}

/// A parsed and validated BSP map.
#[derive(Debug, Clone)]
pub struct Bsp {
    pub version: BspVersion,
    /// Size of the file in bytes.
    pub file_size: usize,
    pub entities: Vec<Entity>,
    pub planes: Vec<Plane>,
    /// `None` where the texture directory has an empty slot.
    pub textures: Vec<Option<Texture>>,
    pub vertices: Vec<[f32; 3]>,
    pub nodes: Vec<Node>,
    pub texinfo: Vec<TexInfo>,
    pub faces: Vec<Face>,
    pub clipnodes: Vec<ClipNode>,
    pub leaves: Vec<Leaf>,
    pub marksurfaces: Vec<u32>,
    pub edges: Vec<[u32; 2]>,
    pub surfedges: Vec<i32>,
    pub models: Vec<Model>,
    /// Brush indices listed by the leaves (Quake 2).
    pub leaf_brushes: Vec<u32>,
    pub brushes: Vec<Brush>,
    pub brush_sides: Vec<BrushSide>,
    /// Records no model's trees or faces reach that held bad indices (maps "protected"
    /// against decompilers carry such garbage; the engines never read it). Their bad
    /// indices were replaced by harmless ones; only reachable records are validated.
    pub unused_bad_records: usize,
    /// Faces a model reaches that the engine could not draw: their plane, texture or
    /// edges do not resolve (maps "protected" against decompilers write garbage there
    /// for faces the game never needs). They were given no edges, so no tool samples
    /// them; the walls they would show are still in the tree. In face order.
    pub unusable_faces: Vec<UnusableFace>,
    /// The game the map is made for: the format's, except for BSP29, which Quake and
    /// Half-Life's oldest maps share and which is decided from the map itself
    /// ([`crate::game::decide`]).
    pub game: Game,
    /// Why [`Bsp::game`] is what it is, in one line for logs and `vdgview info`.
    pub game_reason: String,
}

/// The first `n` unusable faces as "face I (reason)", comma-separated, with "..."
/// when there are more: for one-line log and error messages.
pub fn first_unusable_faces(bsp: &Bsp, n: usize) -> String {
    let mut v: Vec<String> = bsp
        .unusable_faces
        .iter()
        .take(n)
        .map(|u| format!("face {} ({})", u.index, u.reason))
        .collect();
    if bsp.unusable_faces.len() > n {
        v.push("...".into());
    }
    v.join(", ")
}

/// A face the engine could not draw, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct UnusableFace {
    /// Index into [`Bsp::faces`].
    pub index: u32,
    pub reason: String,
}

impl Bsp {
    /// Memory-maps and parses a BSP file.
    pub fn open(path: impl AsRef<Path>) -> Result<Bsp, BspError> {
        let file = std::fs::File::open(path.as_ref())?;
        // SAFETY: the map is read-only and only borrowed while parsing; a file truncated
        // underneath us by another process is the one hazard memmap2 documents, and
        // compile tools do not rewrite a map while it is being read.
        let map = unsafe { memmap2::Mmap::map(&file)? };
        Bsp::parse(&map)
    }

    /// Parses a BSP file held in memory, whichever format its first bytes name.
    pub fn parse(bytes: &[u8]) -> Result<Bsp, BspError> {
        crate::read::parse(bytes)
    }

    /// The format's name as the map uses it: BSP29 names the game it was decided to
    /// be (Quake's format, or Half-Life's oldest maps), the others their format.
    pub fn format_name(&self) -> &'static str {
        match (self.version, self.game) {
            (BspVersion::Bsp29, Game::GoldSrc) => "BSP29 (Half-Life)",
            (v, _) => v.name(),
        }
    }

    /// The unusable faces among the world model's own, and how many faces it has.
    pub fn unusable_world_faces(&self) -> (usize, usize) {
        let w = self.world();
        let range = w.first_face..w.first_face + w.num_faces;
        let bad = self
            .unusable_faces
            .iter()
            .filter(|u| range.contains(&u.index))
            .count();
        (bad, w.num_faces as usize)
    }

    /// Makes the map one of `game`'s (the user's `--game`), saying so in
    /// [`Bsp::game_reason`]. Only the Quake 1 family's formats can be read as another
    /// game (GoldSrc or Quake); for the others this is an error naming the format.
    pub fn force_game(&mut self, game: Game) -> Result<(), String> {
        let family = matches!(self.game, Game::Quake | Game::GoldSrc);
        if !family || !matches!(game, Game::Quake | Game::GoldSrc) {
            return Err(format!(
                "a {} map cannot be read as a {} map",
                self.version.name(),
                game.name()
            ));
        }
        if game != self.game {
            self.game_reason = format!(
                "forced by the user (the map itself says: {})",
                self.game_reason
            );
        } else {
            self.game_reason = format!(
                "forced by the user, as the map itself says ({})",
                self.game_reason
            );
        }
        self.game = game;
        Ok(())
    }

    /// The world model (model 0).
    pub fn world(&self) -> &Model {
        &self.models[0]
    }

    /// The polygon of a face, in winding order.
    pub fn face_vertices(&self, face: &Face) -> impl Iterator<Item = [f32; 3]> + '_ {
        let first = face.first_edge as usize;
        self.surfedges[first..first + face.num_edges as usize]
            .iter()
            .map(|&se| {
                let e = self.edges[se.unsigned_abs() as usize];
                let v = if se >= 0 { e[0] } else { e[1] };
                self.vertices[v as usize]
            })
    }

    /// The unit normal of a face, pointing to the side it is seen from.
    pub fn face_normal(&self, face: &Face) -> [f32; 3] {
        let n = self.planes[face.plane as usize].normal;
        if face.back_side {
            [-n[0], -n[1], -n[2]]
        } else {
            n
        }
    }

    /// The texture name of a face ("" when it has none).
    pub fn face_texture_name(&self, face: &Face) -> &str {
        let miptex = self.texinfo[face.texinfo as usize].miptex;
        usize::try_from(miptex)
            .ok()
            .and_then(|i| self.textures.get(i))
            .and_then(|t| t.as_ref())
            .map_or("", |t| t.name.as_str())
    }

    /// What a face is (wall, sky, or skipped and why), from the source the format
    /// has: the texture name in the Quake 1 family, the surface flags in Quake 2.
    pub fn face_class(&self, face: &Face) -> FaceClass {
        match self.game {
            Game::Quake2 => crate::quake2::face_class(
                self.texinfo[face.texinfo as usize].flags,
                self.face_texture_name(face),
            ),
            Game::Quake3 => {
                let t = &self.texinfo[face.texinfo as usize];
                crate::quake3::face_class(t.flags, t.contents)
            }
            Game::Quake | Game::GoldSrc => classify_texture(self.face_texture_name(face)),
        }
    }

    /// The sides of a brush.
    pub fn brush_sides(&self, brush: &Brush) -> &[BrushSide] {
        &self.brush_sides[brush.first_side as usize..][..brush.num_sides as usize]
    }

    /// The world's bounding box (model 0's, as the compiler wrote it).
    pub fn bounds(&self) -> ([f32; 3], [f32; 3]) {
        (self.world().mins, self.world().maxs)
    }

    /// Where players start: the origins of the spawn entities of every game we read
    /// (`info_player_start`, `info_player_deathmatch`, `info_player_coop`,
    /// Counter-Strike's `info_player_terrorist`, `info_player_counterterrorist`
    /// (`info_player_start` there), `info_vip_start`, team CTF spawns).
    pub fn spawns(&self) -> Vec<[f32; 3]> {
        self.entities
            .iter()
            .filter(|e| is_spawn_class(e.classname()))
            .filter_map(|e| e.origin())
            .collect()
    }

    /// The faces of a model.
    pub fn model_faces(&self, model: &Model) -> &[Face] {
        let first = model.first_face as usize;
        &self.faces[first..first + model.num_faces as usize]
    }

    /// The entity that uses brush model `index`, if any.
    pub fn entity_of_model(&self, index: usize) -> Option<&Entity> {
        self.entities
            .iter()
            .find(|e| e.model_index() == Some(index))
    }
}

/// Whether an entity class is a player spawn point.
pub fn is_spawn_class(class: &str) -> bool {
    matches!(
        class,
        "info_player_start"
            | "info_player_deathmatch"
            | "info_player_coop"
            | "info_player_terrorist"
            | "info_player_counterterrorist"
            | "info_vip_start"
            | "team_CTF_redplayer"
            | "team_CTF_blueplayer"
            | "team_CTF_redspawn"
            | "team_CTF_bluespawn"
    )
}
