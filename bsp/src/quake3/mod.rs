//! Quake 3: IBSP 46 (id's q3map, q3map2; OpenArena, ioquake3, Urban Terror, ...).
//!
//! Seventeen lumps. Unlike Quake 1 and 2, the leaves carry no contents: the game's
//! collision code (`cm_*`) asks the brushes each leaf lists, with the contents flags
//! of their shaders ([`contents`]), and q3map2 builds the tree from structural
//! brushes only, so detail brushes lie inside "empty" leaves. [`parse`] therefore
//! carves every leaf's brushes into the tree (`crate::carve`): each leaf becomes a small
//! subtree whose leaves have one contents value each, so the oracle, the boundary and
//! every tool that walks the hull-0 tree see the same solids the game collides with.
//! Faces are the draw surfaces: planar faces and triangle meshes from their draw
//! vertices and indices, Bézier patches tessellated (`patch`). Patches block as the
//! game's patch collision does: closed pipes and columns are filled solid, open
//! patches become thin slabs; both are kept as extra brushes. Triangle soups
//! (`misc_model`s) never collide in the game; q3map2 gives the clipped ones real
//! clip brushes, which the tree then holds.

mod patch;
mod raw;
mod read;

pub use read::parse;

/// Quake 3's contents flags (`CONTENTS_*` of `surfaceflags.h`).
pub mod contents {
    pub const SOLID: i32 = 1;
    pub const LAVA: i32 = 8;
    pub const SLIME: i32 = 16;
    pub const WATER: i32 = 32;
    pub const FOG: i32 = 64;
    pub const AREAPORTAL: i32 = 0x8000;
    pub const PLAYERCLIP: i32 = 0x10000;
    pub const MONSTERCLIP: i32 = 0x20000;
    pub const TELEPORTER: i32 = 0x40000;
    pub const JUMPPAD: i32 = 0x80000;
    pub const CLUSTERPORTAL: i32 = 0x10_0000;
    pub const DONOTENTER: i32 = 0x20_0000;
    pub const BOTCLIP: i32 = 0x40_0000;
    pub const MOVER: i32 = 0x80_0000;
    pub const ORIGIN: i32 = 0x100_0000;
    pub const BODY: i32 = 0x200_0000;
    pub const CORPSE: i32 = 0x400_0000;
    pub const DETAIL: i32 = 0x800_0000;
    pub const STRUCTURAL: i32 = 0x1000_0000;
    pub const TRANSLUCENT: i32 = 0x2000_0000;
    pub const TRIGGER: i32 = 0x4000_0000;
    pub const NODROP: i32 = i32::MIN;
    /// What stops a player (`MASK_PLAYERSOLID` of `bg_public.h`).
    pub const MASK_PLAYERSOLID: i32 = SOLID | PLAYERCLIP | BODY;
    /// The contents the tools tell apart: what blocks, the liquids, player clip.
    pub const RELEVANT: i32 = SOLID | LAVA | SLIME | WATER | PLAYERCLIP | MONSTERCLIP;
}

/// Quake 3's surface flags (`SURF_*` of `surfaceflags.h`).
pub mod surface {
    pub const SKY: i32 = 0x4;
    pub const NODRAW: i32 = 0x80;
    pub const HINT: i32 = 0x100;
    pub const SKIP: i32 = 0x200;
    pub const NONSOLID: i32 = 0x4000;
}

/// A Quake 3 contents bit set as the Quake contents value the tools use: solid
/// blocks, liquids keep their kind, player and monster clip become
/// [`crate::contents::CLIP`] (free unless the options make clip solid), everything
/// else (fog, triggers, area portals, bot hints) is empty.
pub fn to_quake_contents(flags: i32) -> i32 {
    use crate::contents as q;
    if flags & contents::SOLID != 0 {
        q::SOLID
    } else if flags & contents::LAVA != 0 {
        q::LAVA
    } else if flags & contents::SLIME != 0 {
        q::SLIME
    } else if flags & contents::WATER != 0 {
        q::WATER
    } else if flags & (contents::PLAYERCLIP | contents::MONSTERCLIP) != 0 {
        q::CLIP
    } else {
        q::EMPTY
    }
}

/// A face's class from its shader's surface and contents flags: helpers (nodraw,
/// hint, skip: caulk, clip, trigger textures) are skipped, sky is sky, liquid and fog
/// surfaces are liquids, surfaces of non-solid shaders (decals, glass-less grates,
/// `surfaceparm nonsolid`) are passable and skipped like transparent textures.
pub fn face_class(surface_flags: i32, shader_contents: i32) -> crate::faces::FaceClass {
    use crate::faces::{FaceClass, SkipReason};
    let c = shader_contents;
    if surface_flags & (surface::NODRAW | surface::HINT | surface::SKIP) != 0 {
        FaceClass::Skip(SkipReason::Helper)
    } else if surface_flags & surface::SKY != 0 {
        FaceClass::Sky
    } else if c & (contents::LAVA | contents::SLIME | contents::WATER | contents::FOG) != 0 {
        FaceClass::Skip(SkipReason::Liquid)
    } else if c & contents::TRIGGER != 0 {
        FaceClass::Skip(SkipReason::Trigger)
    } else if c & contents::SOLID == 0 && c & (contents::PLAYERCLIP | contents::MONSTERCLIP) != 0 {
        FaceClass::Skip(SkipReason::Clip)
    } else if c & contents::SOLID == 0 || surface_flags & surface::NONSOLID != 0 {
        FaceClass::Skip(SkipReason::Transparent)
    } else {
        FaceClass::Wall
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faces::{FaceClass, SkipReason};

    #[test]
    fn contents_flags_map_onto_quake_values() {
        use crate::contents as q;
        assert_eq!(to_quake_contents(0), q::EMPTY);
        assert_eq!(
            to_quake_contents(contents::SOLID | contents::DETAIL),
            q::SOLID
        );
        assert_eq!(
            to_quake_contents(contents::WATER | contents::TRANSLUCENT),
            q::WATER
        );
        assert_eq!(to_quake_contents(contents::LAVA | contents::FOG), q::LAVA);
        assert_eq!(to_quake_contents(contents::PLAYERCLIP), q::CLIP);
        assert_eq!(to_quake_contents(contents::FOG), q::EMPTY);
        assert_eq!(
            to_quake_contents(contents::TRIGGER | contents::NODROP),
            q::EMPTY
        );
    }

    #[test]
    fn shader_flags_classify_faces() {
        assert_eq!(face_class(0, contents::SOLID), FaceClass::Wall);
        assert_eq!(face_class(surface::SKY, contents::SOLID), FaceClass::Sky);
        assert_eq!(
            face_class(surface::NODRAW, contents::SOLID),
            FaceClass::Skip(SkipReason::Helper)
        );
        assert_eq!(
            face_class(0, contents::WATER | contents::TRANSLUCENT),
            FaceClass::Skip(SkipReason::Liquid)
        );
        assert_eq!(
            face_class(0, contents::PLAYERCLIP),
            FaceClass::Skip(SkipReason::Clip)
        );
        assert_eq!(
            face_class(0, contents::TRANSLUCENT),
            FaceClass::Skip(SkipReason::Transparent)
        );
        assert_eq!(
            face_class(surface::NONSOLID, contents::SOLID),
            FaceClass::Skip(SkipReason::Transparent)
        );
    }
}
