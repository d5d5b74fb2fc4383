//! The on-disk records of Quake 3's BSP (IBSP 46), exactly as stored (little endian),
//! after id's `qfiles.h`. Planes have no axis type here (16 bytes, unlike Quake 1/2).

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Shader {
    pub name: [u8; 64],
    /// Surface flags (`SURF_*`).
    pub surface_flags: i32,
    /// Contents flags (`CONTENTS_*`) of brushes and patches using the shader.
    pub contents: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Plane {
    pub normal: [f32; 3],
    pub dist: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Node {
    pub plane: i32,
    /// `>= 0`: a node; `< 0`: leaf `-(c + 1)`.
    pub children: [i32; 2],
    pub mins: [i32; 3],
    pub maxs: [i32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Leaf {
    /// -1: opaque (inside structural solid, or the filled void outside the level).
    pub cluster: i32,
    pub area: i32,
    pub mins: [i32; 3],
    pub maxs: [i32; 3],
    pub first_leaf_surface: i32,
    pub num_leaf_surfaces: i32,
    pub first_leaf_brush: i32,
    pub num_leaf_brushes: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Model {
    pub mins: [f32; 3],
    pub maxs: [f32; 3],
    pub first_surface: i32,
    pub num_surfaces: i32,
    pub first_brush: i32,
    pub num_brushes: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Brush {
    pub first_side: i32,
    pub num_sides: i32,
    pub shader: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct BrushSide {
    pub plane: i32,
    pub shader: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct DrawVert {
    pub xyz: [f32; 3],
    pub st: [f32; 2],
    pub lightmap: [f32; 2],
    pub normal: [f32; 3],
    pub color: [u8; 4],
}

/// `surfaceType` values.
pub const MST_PLANAR: i32 = 1;
pub const MST_PATCH: i32 = 2;
pub const MST_TRIANGLE_SOUP: i32 = 3;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub struct Surface {
    pub shader: i32,
    pub fog: i32,
    pub surface_type: i32,
    pub first_vert: i32,
    pub num_verts: i32,
    pub first_index: i32,
    pub num_indexes: i32,
    pub lightmap_num: i32,
    pub lightmap_xy: [i32; 2],
    pub lightmap_size: [i32; 2],
    pub lightmap_origin: [f32; 3],
    pub lightmap_vecs: [[f32; 3]; 3],
    pub patch_width: i32,
    pub patch_height: i32,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::mem::size_of;

    #[test]
    fn record_sizes_match_the_file_format() {
        assert_eq!(size_of::<Shader>(), 72);
        assert_eq!(size_of::<Plane>(), 16);
        assert_eq!(size_of::<Node>(), 36);
        assert_eq!(size_of::<Leaf>(), 48);
        assert_eq!(size_of::<Model>(), 40);
        assert_eq!(size_of::<Brush>(), 12);
        assert_eq!(size_of::<BrushSide>(), 8);
        assert_eq!(size_of::<DrawVert>(), 44);
        assert_eq!(size_of::<Surface>(), 104);
    }
}
