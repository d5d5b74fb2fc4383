//! The on-disk records of Quake 2's BSP (IBSP 38) and of Qbism's wide variant
//! (QBSP 38: 32-bit indices and float bounds), exactly as stored (little endian).
//! Planes, vertices, surfedges and brushes are the same in both.

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct TexInfo {
    pub vecs: [[f32; 4]; 2],
    /// Surface flags (`SURF_*`).
    pub flags: i32,
    pub value: i32,
    pub texture: [u8; 32],
    pub next: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Model {
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub origin: [f32; 3],
    pub headnode: i32,
    pub first_face: i32,
    pub num_faces: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Brush {
    pub first_side: i32,
    pub num_sides: i32,
    /// Contents flags (`CONTENTS_*`).
    pub contents: i32,
}

// ---- IBSP 38: 16-bit indices ----

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Node {
    pub plane: i32,
    pub children: [i32; 2],
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_face: u16,
    pub num_faces: u16,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Face {
    pub plane: u16,
    pub side: i16,
    pub first_edge: i32,
    pub num_edges: i16,
    pub texinfo: i16,
    pub styles: [u8; 4],
    pub lightofs: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Leaf {
    pub contents: i32,
    pub cluster: i16,
    pub area: i16,
    pub mins: [i16; 3],
    pub maxs: [i16; 3],
    pub first_leaf_face: u16,
    pub num_leaf_faces: u16,
    pub first_leaf_brush: u16,
    pub num_leaf_brushes: u16,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct BrushSide {
    pub plane: u16,
    pub texinfo: i16,
}

// ---- QBSP 38 (Qbism): 32-bit indices, float bounds ----

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct NodeQbism {
    pub plane: i32,
    pub children: [i32; 2],
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_face: u32,
    pub num_faces: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct FaceQbism {
    pub plane: u32,
    pub side: i32,
    pub first_edge: i32,
    pub num_edges: i32,
    pub texinfo: i32,
    pub styles: [u8; 4],
    pub lightofs: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct LeafQbism {
    pub contents: i32,
    pub cluster: i32,
    pub area: i32,
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_leaf_face: u32,
    pub num_leaf_faces: u32,
    pub first_leaf_brush: u32,
    pub num_leaf_brushes: u32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct BrushSideQbism {
    pub plane: u32,
    pub texinfo: i32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    #[test]
    fn record_sizes_match_the_file_format() {
        assert_eq!(size_of::<TexInfo>(), 76);
        assert_eq!(size_of::<Model>(), 48);
        assert_eq!(size_of::<Brush>(), 12);
        assert_eq!(size_of::<Node>(), 28);
        assert_eq!(size_of::<Face>(), 20);
        assert_eq!(size_of::<Leaf>(), 28);
        assert_eq!(size_of::<BrushSide>(), 4);
        assert_eq!(size_of::<NodeQbism>(), 44);
        assert_eq!(size_of::<FaceQbism>(), 28);
        assert_eq!(size_of::<LeafQbism>(), 52);
        assert_eq!(size_of::<BrushSideQbism>(), 8);
    }
}
