//! Condition A for one operation (thesis 4.2): the volume described after
//! the operation lies inside the volume described before it.
//!
//! A face volume is the union of balls `B(x, r(x))` over the triangle with
//! `r` linear. It suffices that each such ball of a changed face lies in one
//! ball of the old faces, i.e. that the old clearance at `x` is at least the
//! new radius `r'(x)`. This is checked on a barycentric grid of each new or
//! shrunk face — the operations themselves are proven by the concavity
//! argument in `swap`; this check guards the implementation.

use super::mesh::{Changes, Mesh};
use super::volume::{P3, add, scale};

/// Points per face edge of the sampling grid.
const GRID: usize = 4;

pub(crate) fn condition_a(mesh: &Mesh, ch: &Changes) -> Result<(), String> {
    let base = mesh.faces.len() as u32;
    let radius = |v: u32| {
        ch.radii
            .iter()
            .find(|x| x.0 == v)
            .map_or(mesh.clearance[v as usize], |x| x.1)
    };
    // Old faces: removed ones and the faces of vertices whose radius dropped.
    let mut old: Vec<u32> = ch.removed.iter().copied().filter(|&f| f < base).collect();
    for &(v, r) in &ch.radii {
        if r > mesh.clearance[v as usize] * (1.0 + 1e-12) + 1e-9 {
            return Err(format!("vertex {v} clearance grew to {r}"));
        }
        old.extend(mesh.vfaces[v as usize].iter().copied());
    }
    old.sort_unstable();
    old.dedup();
    let old_balls: Vec<[(P3, f64); 3]> = old
        .iter()
        .map(|&f| {
            mesh.faces[f as usize].map(|v| (mesh.pos[v as usize], mesh.clearance[v as usize]))
        })
        .collect();
    let mut new: Vec<[u32; 3]> = Vec::new();
    for (i, &t) in ch.new_faces.iter().enumerate() {
        if !ch.removed.contains(&(base + i as u32)) {
            new.push(t);
        }
    }
    for &f in &old {
        if !ch.removed.contains(&f) {
            new.push(mesh.faces[f as usize]);
        }
    }
    for t in new {
        let b = t.map(|v| (mesh.pos[v as usize], radius(v)));
        for i in 0..=GRID {
            for j in 0..=GRID - i {
                let (u, w) = (i as f64 / GRID as f64, j as f64 / GRID as f64);
                let x = add(
                    scale(b[0].0, 1.0 - u - w),
                    add(scale(b[1].0, u), scale(b[2].0, w)),
                );
                let r = b[0].1 * (1.0 - u - w) + b[1].1 * u + b[2].1 * w;
                let have = old_balls
                    .iter()
                    .map(|&ob| vdgformat::triangle_clearance(ob, x))
                    .fold(f64::NEG_INFINITY, f64::max);
                if have < r - 1e-6 * (1.0 + r) {
                    return Err(format!(
                        "face {t:?}: ball of radius {r} at {x:?} exceeds the old clearance {have}"
                    ));
                }
            }
        }
    }
    Ok(())
}
