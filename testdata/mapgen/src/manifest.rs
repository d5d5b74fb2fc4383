//! The JSON manifest written beside each generated map: the exact world
//! description (so any tool can rebuild the exact answers), the spawn points,
//! bounds and a few counts of the compiled BSP.

use serde::{Deserialize, Serialize};

use crate::bsp::Compiled;
use crate::world::{Aabb, HULL_HALF_EXTENTS, World};

/// Format tag of the manifest.
pub const MANIFEST_FORMAT: &str = "mapgen-manifest-1";

/// The contents rule, spelled out for readers of the JSON.
pub const CONTENTS_RULE: &str = "SOLID inside the open interior of a solid box or ramp wedge \
(box intersected with normal.p <= dist); else WATER inside a closed free box and a water box, \
EMPTY inside a closed free box; else SKY inside a sky box; else SOLID. Free = EMPTY|WATER. \
Points within 1e-3 of any primitive surface are ambiguous.";

/// Counts of the compiled map.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapStats {
    pub bsp_bytes: usize,
    pub planes: usize,
    pub nodes: usize,
    pub leaves: usize,
    /// World faces (walls, floors, ceilings, sky, water surfaces).
    pub world_faces: usize,
    /// Faces of brush entities (`*1`, `*2`, …).
    pub brush_faces: usize,
    /// Clip nodes of hulls 1, 2, 3.
    pub clipnodes: [usize; 3],
    /// Exact wall polygons and their total area.
    pub wall_polygons: usize,
    pub wall_area: f64,
}

/// The manifest of one generated map.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Manifest {
    pub format: String,
    pub name: String,
    pub description: String,
    pub contents_rule: String,
    /// Half extents of hulls 0–3 (clip hull `i` = world shrunk by these).
    pub hull_half_extents: [[f64; 3]; 4],
    /// Bounding box of all primitives.
    pub bounds: Aabb,
    /// Bounding box of the free boxes.
    pub free_bounds: Aabb,
    pub spawn_points: Vec<[f64; 3]>,
    pub stats: MapStats,
    /// The exact description; `World::from_manifest_json` reads it back.
    pub world: World,
}

impl Manifest {
    /// The manifest of `world` compiled to `compiled` (`bsp_bytes` long).
    pub fn new(world: &World, compiled: &Compiled, bsp_bytes: usize) -> Self {
        let m = &compiled.models;
        let walls = world.wall_polygons();
        Manifest {
            format: MANIFEST_FORMAT.to_string(),
            name: world.name.clone(),
            description: world.description.clone(),
            contents_rule: CONTENTS_RULE.to_string(),
            hull_half_extents: HULL_HALF_EXTENTS,
            bounds: world.bounds(),
            free_bounds: world.free_bounds(),
            spawn_points: world.spawns.clone(),
            stats: MapStats {
                bsp_bytes,
                planes: compiled.planes.len(),
                nodes: m.iter().map(|x| x.hull0.nodes.len()).sum(),
                leaves: 1 + m
                    .iter()
                    .flat_map(|x| &x.hull0.leaves)
                    .filter(|l| l.contents != crate::world::Contents::Solid)
                    .count(),
                world_faces: m[0].faces.len(),
                brush_faces: m[1..].iter().map(|x| x.faces.len()).sum(),
                clipnodes: [0, 1, 2].map(|h| m.iter().map(|x| x.clip[h].nodes.len()).sum()),
                wall_polygons: walls.len(),
                wall_area: walls.iter().map(|w| w.area()).sum(),
            },
            world: world.clone(),
        }
    }

    /// Pretty JSON (arrays of numbers kept on one line) with a trailing
    /// newline.
    pub fn to_json(&self) -> String {
        let pretty = serde_json::to_string_pretty(self).expect("manifest serialises");
        let mut s = inline_number_arrays(&pretty);
        s.push('\n');
        s
    }
}

/// Puts every array that holds only numbers on one line: `[1.0, 2.0, 3.0]`.
fn inline_number_arrays(pretty: &str) -> String {
    let mut out = String::with_capacity(pretty.len());
    let mut rest = pretty;
    while let Some(open) = rest.find('[') {
        out.push_str(&rest[..open]);
        let after = &rest[open + 1..];
        let close = after.find(']');
        let inner = close.map(|c| &after[..c]);
        match inner {
            // Pretty-printed arrays span lines; strings cannot hold a raw
            // newline, so this never touches text inside a string.
            Some(inner)
                if inner.contains('\n')
                    && inner
                        .chars()
                        .all(|c| c.is_ascii_digit() || " \n.,-+eE".contains(c)) =>
            {
                let items: Vec<&str> = inner.split(',').map(str::trim).collect();
                out.push('[');
                out.push_str(&items.join(", "));
                out.push(']');
                rest = &after[inner.len() + 1..];
            }
            _ => {
                out.push('[');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

impl World {
    /// Reads the world back from a manifest's JSON text.
    ///
    /// ```
    /// use mapgen::{bsp, manifest::Manifest, world::World, worlds};
    /// let w = worlds::box_room();
    /// let c = bsp::compile(&w);
    /// let json = Manifest::new(&w, &c, 0).to_json();
    /// let back = World::from_manifest_json(&json).unwrap();
    /// assert_eq!(back.free, w.free);
    /// ```
    pub fn from_manifest_json(json: &str) -> Result<World, serde_json::Error> {
        let m: Manifest = serde_json::from_str(json)?;
        Ok(m.world)
    }
}
