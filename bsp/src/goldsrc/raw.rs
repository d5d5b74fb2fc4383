//! The on-disk records of the Quake BSP family, exactly as stored (little endian).
//!
//! GoldSrc v30 and Quake BSP29 share one layout with 16-bit indices; BSP2 widens
//! every index to 32 bits and stores bounds as floats; the older "2PSB" variant of
//! BSP2 widens indices but keeps 16-bit bounds. These types are only read through
//! [`bytemuck::pod_collect_to_vec`], which copes with any alignment of the lump.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct TexInfo {
    pub vecs: [[f32; 4]; 2],
    pub miptex: i32,
    pub flags: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Model {
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub origin: [f32; 3],
    pub headnode: [i32; 4],
    pub visleafs: i32,
    pub first_face: i32,
    pub num_faces: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct MipTexHeader {
    pub name: [u8; 16],
    pub width: u32,
    pub height: u32,
    pub offsets: [u32; 4],
}

// ---- 16-bit family: GoldSrc v30, Quake BSP29 ----

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Node29 {
    pub plane: i32,
    pub children: [i16; 2],
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_face: u16,
    pub num_faces: u16,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Leaf29 {
    pub contents: i32,
    pub visofs: i32,
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_marksurface: u16,
    pub num_marksurfaces: u16,
    pub ambient: [u8; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ClipNode29 {
    pub plane: i32,
    pub children: [i16; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Face29 {
    pub plane: u16,
    pub side: u16,
    pub first_edge: i32,
    pub num_edges: u16,
    pub texinfo: u16,
    pub styles: [u8; 4],
    pub lightofs: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Edge29 {
    pub v: [u16; 2],
}

// ---- 32-bit family: BSP2 ("BSP2") and its predecessor ("2PSB") ----

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct NodeBsp2 {
    pub plane: i32,
    pub children: [i32; 2],
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_face: u32,
    pub num_faces: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Node2psb {
    pub plane: i32,
    pub children: [i32; 2],
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_face: u32,
    pub num_faces: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LeafBsp2 {
    pub contents: i32,
    pub visofs: i32,
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_marksurface: u32,
    pub num_marksurfaces: u32,
    pub ambient: [u8; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Leaf2psb {
    pub contents: i32,
    pub visofs: i32,
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_marksurface: u32,
    pub num_marksurfaces: u32,
    pub ambient: [u8; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct ClipNodeBsp2 {
    pub plane: i32,
    pub children: [i32; 2],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct FaceBsp2 {
    pub plane: i32,
    pub side: i32,
    pub first_edge: i32,
    pub num_edges: i32,
    pub texinfo: i32,
    pub styles: [u8; 4],
    pub lightofs: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct EdgeBsp2 {
    pub v: [u32; 2],
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    #[test]
    fn record_sizes_match_the_file_format() {
        assert_eq!(size_of::<TexInfo>(), 40);
        assert_eq!(size_of::<Model>(), 64);
        assert_eq!(size_of::<MipTexHeader>(), 40);
        assert_eq!(size_of::<Node29>(), 24);
        assert_eq!(size_of::<Leaf29>(), 28);
        assert_eq!(size_of::<ClipNode29>(), 8);
        assert_eq!(size_of::<Face29>(), 20);
        assert_eq!(size_of::<Edge29>(), 4);
        assert_eq!(size_of::<NodeBsp2>(), 44);
        assert_eq!(size_of::<Node2psb>(), 32);
        assert_eq!(size_of::<LeafBsp2>(), 44);
        assert_eq!(size_of::<Leaf2psb>(), 32);
        assert_eq!(size_of::<ClipNodeBsp2>(), 12);
        assert_eq!(size_of::<FaceBsp2>(), 28);
        assert_eq!(size_of::<EdgeBsp2>(), 8);
    }
}
