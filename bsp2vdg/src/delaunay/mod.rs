//! Exact, degeneracy-proof 3D Delaunay triangulation (thesis 3.5–3.6; docs/design/pipeline.md).
//!
//! The Voronoi stage needs the Delaunay tetrahedralization of wall samples: points on regular
//! grids on axis-aligned planes, so most of the input is exactly coplanar and exactly
//! cospherical. [`Triangulation::new`] builds it incrementally and never produces a flat
//! cell, whatever the input.
//!
//! # Design
//!
//! * **Insertion order** ([`sort`]): a biased randomized insertion order (BRIO) with every
//!   round sorted along a Hilbert curve. Randomization bounds the expected work even on
//!   adversarial grids (a scan-order sweep over a grid makes huge cavities); the Hilbert
//!   order inside rounds makes consecutive points neighbours, so locating the next point
//!   from the previous one takes a few steps and touches memory that is still cached.
//! * **Point location** (module `locate`): a remembering visibility walk from the last created
//!   cell, its facet order drawn from a seeded generator (the stochastic walk, made
//!   deterministic).
//! * **Insertion** (module `insert`): Bowyer–Watson. The cavity (cells whose circumsphere contains
//!   the point) is found by a breadth-first search with visit flags kept inside the cells,
//!   its boundary is starred from the new point (new cells glued to each other through a
//!   small table of the boundary's directed edges, indexed by local vertex numbers, as HXT
//!   does; turning around the edges inside the cavity, as CGAL does, is the fallback for
//!   very large cavities), and the freed slots are reused by the next insertion, which is
//!   next door.
//! * **Infinite vertex**: the convex hull is closed by cells `(hull facet, ∞)`, so every cell
//!   has four neighbours and points outside the hull need no special case.
//! * **Exact predicates** ([`predicates`]): `orient3d` and `insphere` in three stages. A
//!   float evaluation with a static error bound (from the largest coordinate difference, so
//!   no permanent is computed) decides nearly every call; if it cannot, an integer stage
//!   evaluates the determinant exactly in 128-bit arithmetic whenever the coordinate
//!   differences are dyadic numbers of few significant bits (always true for grid-aligned
//!   wall samples, where exact ties are the common case) — for integer points close
//!   together the float evaluation was already exact and its value, zero included, is the
//!   answer without any further arithmetic; otherwise Shewchuk's adaptive
//!   predicates (`robust` crate) decide, up to exact expansion arithmetic. Every decision
//!   the algorithm takes is a sign of one of these predicates on input coordinates — no
//!   constructed point is ever tested — so every decision is exact.
//! * **Symbolic perturbation**: an exact zero of `insphere` (five cospherical points) is
//!   broken as if each point's paraboloid lift were raised by `ε^(N − id)`, the largest id
//!   dominating (Devillers & Teillaud, the scheme of CGAL's `side_of_oriented_sphere`).
//!   It is consistent because it is one fixed perturbation of the lifted points, not a
//!   per-test choice: all tests agree with the Delaunay triangulation of the perturbed
//!   points, which is unique, simplicial, and a Delaunay triangulation of the input. The
//!   perturbed sign reduces to the first non-zero `orient3d` of at most two point
//!   substitutions, all exact. Coplanar points on the hull are decided by the finite cell
//!   behind the hull facet, so hull and interior decisions agree. Orientation zeros need no
//!   perturbation: a cell is only ever created on a facet strictly visible from its apex.
//! * **Memory**: a cell is 4 vertex ids + 4 packed neighbours (`cell << 2 | facet`, the
//!   top bit doubling as the cavity search's visit flag): 32 bytes, aligned to half a
//!   cache line, both while building and in the result. Compaction at the end is in place.
//!   Whole-process peak on 1M uniform points is about 40 bytes per tetrahedron (65 on
//!   wall samples, whose many hull facets make many infinite cells).
//! * **Determinism**: the shuffle and the walk use fixed seeds, so the output depends on the
//!   input only; cells are numbered finite-first in creation-slot order. The sort and the
//!   final renumbering run on all threads (rayon) with thread-count independent results;
//!   the insertion itself is sequential.
//! * **Speed** (`scripts/peers/bench-delaunay.sh` compares with CGAL in the same run): the
//!   insphere filter evaluates two rows per SSE2 instruction (same bits as the scalar
//!   order), a walk step filters its cell's four facets with shared arithmetic, the Hilbert
//!   keys are computed without branches.
//!
//! # API for the Voronoi stage
//!
//! [`Triangulation::new`], then cells by id (`0..num_finite_cells()` finite, the rest
//! infinite, containing [`INFINITE`]): [`Triangulation::cell`], [`Triangulation::neighbor`]
//! / [`Triangulation::neighbors`] (neighbour `i` opposite vertex `i`),
//! [`Triangulation::is_finite`], [`Triangulation::circumcenter`] /
//! [`Triangulation::circumradius`] / [`Triangulation::circumspheres`], and
//! [`Triangulation::for_each_edge_ring`]: every Delaunay edge with its cycle of cells — the
//! Voronoi face of that edge. [`Triangulation::validate`] re-checks everything exactly.
//!
//! # Example
//!
//! ```
//! use bsp2vdg::delaunay::Triangulation;
//! // A 3×3×3 grid: every cube of it has 8 cospherical corners.
//! let pts: Vec<[f64; 3]> = (0..27).map(|i| [(i % 3) as f64, (i / 3 % 3) as f64, (i / 9) as f64]).collect();
//! let tri = Triangulation::new(&pts).unwrap();
//! tri.validate().unwrap();
//! let mut faces = 0;
//! tri.for_each_edge_ring(|ring| if !ring.touches_infinity { faces += 1 });
//! assert!(faces > 0);
//! ```

mod build;
mod insert;
mod locate;
pub mod predicates;
pub mod sort;
mod triangulation;
mod validate;

use std::fmt;

pub use triangulation::{EdgeRing, Triangulation};
pub use validate::InvalidTriangulation;

/// The vertex id standing for the point at infinity in infinite cells.
pub const INFINITE: u32 = u32::MAX;

/// Why a point set cannot be triangulated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DelaunayError {
    /// Point `index` has a NaN or infinite coordinate.
    NonFinite { index: usize },
    /// Fewer than four affinely independent points (all coplanar, collinear or equal).
    Degenerate { count: usize },
    /// The triangulation needs more cells than 29-bit cell ids (or the memory) allow.
    TooManyPoints { count: usize },
}

impl fmt::Display for DelaunayError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DelaunayError::NonFinite { index } => {
                write!(f, "point {index} has a non-finite coordinate")
            }
            DelaunayError::Degenerate { count } => write!(
                f,
                "cannot tetrahedralize {count} points: fewer than 4 of them are affinely \
                 independent (all coplanar, collinear or equal)"
            ),
            DelaunayError::TooManyPoints { count } => {
                write!(f, "too many points to tetrahedralize: {count}")
            }
        }
    }
}

impl std::error::Error for DelaunayError {}
