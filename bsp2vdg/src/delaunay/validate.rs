//! An independent, exact check of everything the triangulation promises. Used by the tests
//! and by `examples/tetrahedralize.rs --validate`; O(n log n), not meant for production runs.

use std::fmt;

use super::INFINITE;
use super::triangulation::Triangulation;

/// A violated invariant, with the cell it was found at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InvalidTriangulation(pub String);

impl fmt::Display for InvalidTriangulation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid triangulation: {}", self.0)
    }
}

impl std::error::Error for InvalidTriangulation {}

// The checks use `robust` directly, independent of the builder's own predicate stages.
fn orient3d(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3]) -> f64 {
    let p = |q: &[f64; 3]| robust::Coord3D {
        x: q[0],
        y: q[1],
        z: q[2],
    };
    robust::orient3d(p(a), p(b), p(c), p(d))
}

fn insphere(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3], d: &[f64; 3], e: &[f64; 3]) -> f64 {
    let p = |q: &[f64; 3]| robust::Coord3D {
        x: q[0],
        y: q[1],
        z: q[2],
    };
    robust::insphere(p(a), p(b), p(c), p(d), p(e))
}

macro_rules! bail {
    ($($arg:tt)*) => { return Err(InvalidTriangulation(format!($($arg)*))) };
}

impl Triangulation {
    /// Check, with exact predicates: cell vertex ids, positive orientation of finite cells,
    /// symmetric and facet-consistent neighbours, local Delaunay property of every interior
    /// facet (the opposite vertex never strictly inside), local convexity of the hull, the
    /// hull being a closed surface, every distinct input point being a vertex, and the Euler
    /// characteristic of the complex (a 3-sphere with the infinite vertex: V − E + F − C = 0).
    pub fn validate(&self) -> Result<(), InvalidTriangulation> {
        self.validate_cells()?;
        self.validate_neighbors()?;
        self.validate_empty_spheres()?;
        self.validate_hull()?;
        self.validate_euler()
    }

    fn validate_cells(&self) -> Result<(), InvalidTriangulation> {
        let n = self.points().len();
        let mut skipped = vec![false; n];
        for &(d, _) in self.duplicates() {
            skipped[d as usize] = true;
        }
        let mut used = vec![false; n];
        for (t, c) in self.cells().enumerate() {
            let infinite = c.iter().filter(|&&v| v == INFINITE).count();
            let expect = usize::from(!self.is_finite(t as u32));
            if infinite != expect {
                bail!("cell {t} {c:?} has {infinite} infinite vertices, expected {expect}");
            }
            for (i, &v) in c.iter().enumerate() {
                if c[..i].contains(&v) {
                    bail!("cell {t} {c:?} repeats vertex {v}");
                }
                if v == INFINITE {
                    continue;
                }
                if v as usize >= n || skipped[v as usize] {
                    bail!("cell {t} has invalid or skipped vertex {v}");
                }
                used[v as usize] = true;
            }
            if infinite == 0 {
                let p = c.map(|v| self.points()[v as usize]);
                if orient3d(&p[0], &p[1], &p[2], &p[3]) <= 0.0 {
                    bail!("finite cell {t} {c:?} is not positively oriented (flat or inverted)");
                }
            }
        }
        if let Some(v) = (0..n).find(|&v| !used[v] && !skipped[v]) {
            bail!("input point {v} is neither a vertex nor a reported duplicate");
        }
        Ok(())
    }

    fn validate_neighbors(&self) -> Result<(), InvalidTriangulation> {
        let num = self.num_cells() as u32;
        for t in 0..num {
            let c = self.cell(t);
            for i in 0..4 {
                let (n, j) = self.neighbor(t, i);
                if n >= num || n == t {
                    bail!("cell {t} facet {i}: bad neighbour {n}");
                }
                if self.neighbor(n, j) != (t, i) {
                    bail!("cell {t} facet {i} -> ({n}, {j}) is not symmetric");
                }
                let d = self.cell(n);
                let shared = (0..4).filter(|&k| k != i).all(|k| d.contains(&c[k]));
                if !shared || d.contains(&c[i]) || c.contains(&d[j]) {
                    bail!("cells {t} {c:?} and {n} {d:?} do not share facet {i}/{j}");
                }
            }
        }
        Ok(())
    }

    fn validate_empty_spheres(&self) -> Result<(), InvalidTriangulation> {
        let pts = self.points();
        for t in 0..self.num_finite_cells() as u32 {
            let c = self.cell(t).map(|v| pts[v as usize]);
            for i in 0..4 {
                let (n, j) = self.neighbor(t, i);
                if !self.is_finite(n) {
                    continue;
                }
                let q = pts[self.cell(n)[j] as usize];
                if insphere(&c[0], &c[1], &c[2], &c[3], &q) > 0.0 {
                    bail!("facet {i} of cell {t} is not locally Delaunay");
                }
            }
        }
        Ok(())
    }

    /// Hull facets (finite facets of infinite cells): locally convex and closed.
    fn validate_hull(&self) -> Result<(), InvalidTriangulation> {
        let pts = self.points();
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for t in self.num_finite_cells() as u32..self.num_cells() as u32 {
            let c = self.cell(t);
            let k = c.iter().position(|&v| v == INFINITE).unwrap();
            let (f, _) = self.neighbor(t, k);
            if !self.is_finite(f) {
                bail!("hull facet of infinite cell {t} borders no finite cell");
            }
            for i in (0..4).filter(|&i| i != k) {
                let (n, j) = self.neighbor(t, i);
                let apex = self.cell(n)[j];
                let mut w = c;
                w[k] = apex;
                let p = w.map(|v| pts[v as usize]);
                if orient3d(&p[0], &p[1], &p[2], &p[3]) > 0.0 {
                    bail!("hull is not convex at infinite cells {t} and {n}");
                }
                // The hull edge shared with the neighbouring hull facet.
                let mut e = [0u32; 2];
                let mut m = 0;
                for (l, &v) in c.iter().enumerate() {
                    if l != k && l != i {
                        e[m] = v;
                        m += 1;
                    }
                }
                edges.push((e[0].min(e[1]), e[0].max(e[1])));
            }
        }
        edges.sort_unstable();
        let mut i = 0;
        while i < edges.len() {
            let mut j = i;
            while j < edges.len() && edges[j] == edges[i] {
                j += 1;
            }
            if j - i != 2 {
                bail!(
                    "hull edge {:?} is used by {} hull facets, not 2",
                    edges[i],
                    j - i
                );
            }
            i = j;
        }
        Ok(())
    }

    fn validate_euler(&self) -> Result<(), InvalidTriangulation> {
        let mut edges: Vec<u64> = Vec::with_capacity(self.num_cells() * 6);
        for c in self.cells() {
            for i in 0..4 {
                for j in i + 1..4 {
                    let (a, b) = (c[i].min(c[j]) as u64, c[i].max(c[j]) as u64);
                    edges.push((a << 32) | b);
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let v = self.num_vertices() as i64 + 1;
        let e = edges.len() as i64;
        let c = self.num_cells() as i64;
        let f = 2 * c;
        if v - e + f - c != 0 {
            bail!("Euler characteristic V-E+F-C = {v}-{e}+{f}-{c} != 0");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::Triangulation;

    fn cube_grid(n: usize) -> Vec<[f64; 3]> {
        let mut p = Vec::new();
        for x in 0..n {
            for y in 0..n {
                for z in 0..n {
                    p.push([x as f64, y as f64, z as f64]);
                }
            }
        }
        p
    }

    /// The validator must catch corrupted triangulations (so the tests using it can fail).
    #[test]
    fn validator_detects_corruption() {
        let tri = Triangulation::new(&cube_grid(4)).unwrap();
        tri.validate().unwrap();

        let mut t = tri.clone();
        t.corrupt_swap_vertices(0);
        assert!(t.validate().unwrap_err().0.contains("oriented"));

        let mut t = tri.clone();
        t.corrupt_neighbor(0);
        assert!(t.validate().is_err());

        // Flip a locally Delaunay facet into a non-Delaunay one by moving a vertex.
        let mut t = tri.clone();
        t.corrupt_point(0, [1.4, 1.6, 1.5]);
        assert!(t.validate().is_err());
    }
}
