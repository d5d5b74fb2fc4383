//! The compiler's graph: triangles over vertices with clearance, as every stage from
//! the Voronoi extraction to the writer passes it on, and its conversion into the
//! runtime's builder.

/// The extracted graph: triangles over vertices with clearance.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Graph {
    pub vertices: Vec<[f64; 3]>,
    /// Corrected clearance of each vertex.
    pub clearance: Vec<f64>,
    pub faces: Vec<[u32; 3]>,
}

impl Graph {
    /// A graph read back from a `.vdg` (vertex positions and clearances widened to
    /// `f64`; the faces' own corner radii are not carried: the reduction recomputes
    /// what it needs from the clearances).
    pub fn from_vdg(g: &vdgformat::Vdg<'_>) -> Graph {
        Graph {
            vertices: g.vertices().iter().map(|v| v.pos.map(f64::from)).collect(),
            clearance: g
                .vertices()
                .iter()
                .map(|v| f64::from(v.clearance))
                .collect(),
            faces: g.faces().to_vec(),
        }
    }

    /// The graph as a `.vdg` builder: its vertices with their clearances (rounded to
    /// `f32`) and its faces, each with its own corner radii when `corners` gives them
    /// (one per face, [`crate::raise::raise_to_walls_and_corners`]).
    pub fn to_builder(&self, corners: Option<&[[f64; 3]]>) -> vdgformat::VdgBuilder {
        let mut b = vdgformat::VdgBuilder::new();
        for (p, &c) in self.vertices.iter().zip(&self.clearance) {
            b.add_vertex(p.map(|x| x as f32), c as f32);
        }
        match corners {
            // Rounded as the vertex clearances are, so a corner never falls below its vertex's.
            Some(radii) => {
                debug_assert_eq!(radii.len(), self.faces.len());
                for (f, r) in self.faces.iter().zip(radii) {
                    b.add_face_with_radii(*f, r.map(|x| x as f32));
                }
            }
            None => {
                for f in &self.faces {
                    b.add_face(*f);
                }
            }
        }
        b
    }
}
