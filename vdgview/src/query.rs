//! `vdgview query`: the runtime queries of `vdgformat` from the command line —
//! clearance at a point, line of sight, and Voronoi distance with its path.

use anyhow::{Result, bail};
use std::fmt::Write;
use vdgformat::Vdg;

/// One query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Query {
    Clearance([f32; 3]),
    Visible([f32; 3], [f32; 3]),
    Path([f32; 3], [f32; 3]),
}

impl Query {
    /// Parses `clearance X Y Z`, `visible X1 Y1 Z1 X2 Y2 Z2` or `path …`.
    pub fn parse(kind: &str, numbers: &[String]) -> Result<Query> {
        let nums: Vec<f32> = numbers
            .iter()
            .map(|s| match s.parse::<f32>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => bail!("{s:?} is not a finite number"),
            })
            .collect::<Result<_>>()?;
        let want = if kind == "clearance" { 3 } else { 6 };
        if !matches!(kind, "clearance" | "visible" | "path") {
            bail!("unknown query {kind:?}: expected clearance, visible or path");
        }
        if nums.len() != want {
            bail!("query {kind} takes {want} coordinates, got {}", nums.len());
        }
        let p = [nums[0], nums[1], nums[2]];
        Ok(match kind {
            "clearance" => Query::Clearance(p),
            "visible" => Query::Visible(p, [nums[3], nums[4], nums[5]]),
            _ => Query::Path(p, [nums[3], nums[4], nums[5]]),
        })
    }

    /// Runs the query; the text is what the command prints.
    pub fn run(&self, g: &Vdg<'_>) -> String {
        let mut s = String::new();
        match *self {
            Query::Clearance(p) => match g.nearest_face(p) {
                Some(h) => {
                    let _ = writeln!(s, "clearance {}", h.clearance);
                    let _ = writeln!(s, "face {}", h.face);
                    let _ = writeln!(s, "inside {}", h.clearance > 0.0);
                }
                None => s.push_str("clearance -inf (graph has no faces)\n"),
            },
            Query::Visible(a, b) => {
                let _ = writeln!(s, "visible {}", g.visible(a, b));
            }
            Query::Path(a, b) => match g.path(a, b) {
                Some(path) => {
                    let _ = writeln!(s, "vdistance {}", path.length);
                    let _ = writeln!(s, "points {}", path.vertices.len() + 2);
                    let _ = writeln!(s, "{} {} {} start", a[0], a[1], a[2]);
                    for &v in &path.vertices {
                        let vx = g.vertices()[v as usize];
                        let _ = writeln!(
                            s,
                            "{} {} {} vertex {v} clearance {}",
                            vx.pos[0], vx.pos[1], vx.pos[2], vx.clearance
                        );
                    }
                    let _ = writeln!(s, "{} {} {} goal", b[0], b[1], b[2]);
                }
                None => s.push_str(
                    "vdistance none (no path: the points lie in unconnected parts of the graph)\n",
                ),
            },
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vdgformat::{VdgBuilder, VdgFile};

    fn strings(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn parse_checks_kind_and_arity() {
        assert_eq!(
            Query::parse("clearance", &strings(&["1", "2", "3"])).unwrap(),
            Query::Clearance([1.0, 2.0, 3.0])
        );
        assert!(Query::parse("clearance", &strings(&["1", "2"])).is_err());
        assert!(Query::parse("visible", &strings(&["1", "2", "3"])).is_err());
        assert!(Query::parse("teleport", &strings(&["1", "2", "3"])).is_err());
        assert!(Query::parse("path", &strings(&["1", "2", "3", "4", "5", "nan"])).is_err());
    }

    #[test]
    fn queries_answer_on_a_strip() {
        let mut b = VdgBuilder::new();
        let v: Vec<u32> = [[0.0, 0.0], [256.0, 0.0], [0.0, 64.0], [256.0, 64.0]]
            .iter()
            .map(|&[x, y]| b.add_vertex([x, y, 0.0], 32.0))
            .collect();
        b.add_face([v[0], v[1], v[2]]);
        b.add_face([v[1], v[3], v[2]]);
        let file = VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let g = file.graph();
        let c = Query::Clearance([10.0, 10.0, 2.0]).run(&g);
        assert!(c.starts_with("clearance 30"), "{c}");
        assert!(
            Query::Visible([0.0, 10.0, 20.0], [250.0, 50.0, -20.0])
                .run(&g)
                .contains("true")
        );
        assert!(
            Query::Visible([0.0, 10.0, 20.0], [0.0, 10.0, 40.0])
                .run(&g)
                .contains("false")
        );
        let p = Query::Path([0.0, 0.0, 0.0], [256.0, 64.0, 0.0]).run(&g);
        assert!(p.starts_with("vdistance "), "{p}");
        assert!(p.lines().last().unwrap().ends_with("goal"), "{p}");
    }
}
