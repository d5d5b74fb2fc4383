//! Quake 2: IBSP 38 (id's qbsp3, ericw-tools, TrenchBroom users' compilers) and
//! Qbism's QBSP 38 with 32-bit indices.
//!
//! Nineteen lumps; leaf and brush contents are bit flags ([`contents`]), face kinds
//! are surface flags ([`surface`]), there are no clip hulls (the game collides boxes
//! with the brushes, which the file keeps with their sides). [`parse`] maps it all onto
//! the normalised [`crate::Bsp`]: leaf contents become the Quake values the oracle and
//! boundary understand ([`to_quake_contents`]), brushes and sides are kept for exact
//! brush geometry and the player's box ([`crate::oracle::Oracle::player_contents`]).

mod raw;
mod read;

pub use read::parse;

/// Quake 2's contents flags (`CONTENTS_*` of `q_shared.h`).
pub mod contents {
    pub const SOLID: i32 = 1;
    pub const WINDOW: i32 = 2;
    pub const AUX: i32 = 4;
    pub const LAVA: i32 = 8;
    pub const SLIME: i32 = 16;
    pub const WATER: i32 = 32;
    pub const MIST: i32 = 64;
    pub const AREAPORTAL: i32 = 0x8000;
    pub const PLAYERCLIP: i32 = 0x10000;
    pub const MONSTERCLIP: i32 = 0x20000;
    pub const ORIGIN: i32 = 0x100_0000;
    pub const MONSTER: i32 = 0x200_0000;
    pub const DEADMONSTER: i32 = 0x400_0000;
    pub const DETAIL: i32 = 0x800_0000;
    pub const TRANSLUCENT: i32 = 0x1000_0000;
    pub const LADDER: i32 = 0x2000_0000;
    /// What stops a player (`MASK_PLAYERSOLID`).
    pub const MASK_PLAYERSOLID: i32 = SOLID | PLAYERCLIP | WINDOW | MONSTER;
}

/// Quake 2's surface flags (`SURF_*`).
pub mod surface {
    pub const LIGHT: i32 = 0x1;
    pub const SLICK: i32 = 0x2;
    pub const SKY: i32 = 0x4;
    pub const WARP: i32 = 0x8;
    pub const TRANS33: i32 = 0x10;
    pub const TRANS66: i32 = 0x20;
    pub const FLOWING: i32 = 0x40;
    pub const NODRAW: i32 = 0x80;
    pub const HINT: i32 = 0x100;
    pub const SKIP: i32 = 0x200;
}

/// A Quake 2 contents bit set as the Quake contents value the tools use: solid and
/// window block (windows are glass the player cannot pass), liquids keep their kind,
/// player and monster clip become [`crate::contents::CLIP`] (free by default, as
/// GoldSrc's clip brushes are), everything else is empty.
pub fn to_quake_contents(flags: i32) -> i32 {
    use crate::contents as q;
    if flags & (contents::SOLID | contents::WINDOW) != 0 {
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

/// A face's class from its surface flags, and for walls without flags from the tool
/// texture names compilers leave on helper brushes (`e1u1/trigger`, `*/clip`, ...).
pub fn face_class(flags: i32, texture: &str) -> crate::faces::FaceClass {
    use crate::faces::{FaceClass, SkipReason};
    if flags & (surface::NODRAW | surface::HINT | surface::SKIP) != 0 {
        FaceClass::Skip(SkipReason::Helper)
    } else if flags & surface::SKY != 0 {
        FaceClass::Sky
    } else if flags & surface::WARP != 0 {
        FaceClass::Skip(SkipReason::Liquid)
    } else if flags & (surface::TRANS33 | surface::TRANS66) != 0 {
        FaceClass::Skip(SkipReason::Transparent)
    } else {
        let base = texture.rsplit('/').next().unwrap_or(texture);
        match crate::faces::classify_texture(base) {
            c @ FaceClass::Skip(SkipReason::Trigger | SkipReason::Clip | SkipReason::Helper) => c,
            _ => FaceClass::Wall,
        }
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
            to_quake_contents(contents::WINDOW | contents::TRANSLUCENT),
            q::SOLID
        );
        assert_eq!(
            to_quake_contents(contents::WATER | contents::TRANSLUCENT),
            q::WATER
        );
        assert_eq!(to_quake_contents(contents::LAVA), q::LAVA);
        assert_eq!(to_quake_contents(contents::PLAYERCLIP), q::CLIP);
        assert_eq!(to_quake_contents(contents::MIST), q::EMPTY);
    }

    #[test]
    fn surface_flags_classify_faces() {
        assert_eq!(face_class(0, "e1u1/floor1_3"), FaceClass::Wall);
        assert_eq!(
            face_class(surface::SKY | surface::LIGHT, "e1u1/sky1"),
            FaceClass::Sky
        );
        assert_eq!(
            face_class(surface::WARP | surface::TRANS33, "e1u1/water4"),
            FaceClass::Skip(SkipReason::Liquid)
        );
        assert_eq!(
            face_class(surface::TRANS33, "e1u1/window"),
            FaceClass::Skip(SkipReason::Transparent)
        );
        assert_eq!(
            face_class(surface::NODRAW, "e1u1/clip"),
            FaceClass::Skip(SkipReason::Helper)
        );
        assert_eq!(
            face_class(0, "e1u1/trigger"),
            FaceClass::Skip(SkipReason::Trigger)
        );
        assert_eq!(face_class(0, "e1u1/sky1"), FaceClass::Wall);
    }
}
