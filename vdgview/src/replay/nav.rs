//! `--routes nav:FILE.nav`: routes along a Counter-Strike bot navigation mesh (read
//! by the `navmesh` crate): random area pairs joined by the mesh's shortest chain of
//! areas, each walked on the map's own floor.

use super::route::Route;
use super::walk::{WalkStats, Waypoint, walk_parts};
use bsp::oracle::Oracle;
use bsp::player::{above_floor, settle};
pub use navmesh::{NAV_CROUCH, NAV_MAGIC, NavArea, NavMesh};
use toolbox::SplitMix64;

/// Share of a nav mesh's areas a player can stand in on the map for the mesh to count
/// as made for it: de_cbble's own mesh (a slightly different build) scores 82 % on the
/// shared BSP (area centres on ledges, stairs and ladders do not settle within the
/// tolerance), a mesh of another map about 0 %.
pub const FIT_AREAS: f64 = 0.5;

/// Whether a nav mesh was made for the map at `map`. The bot writes the size of the BSP
/// it analysed into the mesh (versions 4 and 5); when the sizes agree (or the mesh
/// records none) it was. When they differ the mesh may still be of this map (another
/// build of it: de_cbble's mesh records 816 bytes less than the shared BSP) or of
/// another one: the areas decide. Where a player settles on the map's floor at (up to
/// 200 of) their centres, at least [`FIT_AREAS`] of them, the mesh is taken with a
/// warning (`Ok(Some)`); else `Err` names both files.
pub fn same_map(
    mesh: &NavMesh,
    nav: &std::path::Path,
    map: &std::path::Path,
    oracle: &Oracle,
) -> Result<Option<String>, String> {
    if mesh.bsp_size == 0 {
        return Ok(None);
    }
    let size = std::fs::metadata(map)
        .map_err(|e| format!("cannot read map {}: {e}", map.display()))?
        .len();
    if size == u64::from(mesh.bsp_size) {
        return Ok(None);
    }
    let fit = fitting_areas(mesh, oracle);
    let what = format!(
        "{} records a {}-byte BSP, {} has {} bytes, and a player stands in {:.0} % of its areas",
        nav.display(),
        mesh.bsp_size,
        map.display(),
        size,
        100.0 * fit
    );
    if fit >= FIT_AREAS {
        Ok(Some(format!("{what}: another build of the same map?")))
    } else {
        Err(format!(
            "{what}: it was made for another map (give its own map, or --force)"
        ))
    }
}

/// The share of (up to 200, evenly chosen) areas at whose centre a player settles on
/// the map's floor within 24 units of the area's height.
fn fitting_areas(mesh: &NavMesh, oracle: &Oracle) -> f64 {
    let n = mesh.areas.len();
    if n == 0 {
        return 0.0;
    }
    let picks = n.min(200);
    let fits = (0..picks)
        .filter(|&k| {
            let a = &mesh.areas[k * n / picks];
            let c = a.center();
            let crouch = a.flags & NAV_CROUCH != 0;
            settle(oracle, c[0] as f64, c[1] as f64, c[2] as f64, crouch).is_some_and(|(o, cr)| {
                let floor = o[2] - above_floor(oracle, cr);
                (floor - c[2] as f64).abs() <= 24.0
            })
        })
        .count();
    fits as f64 / picks as f64
}

/// The floor path through a chain of areas: each centre and the portal to the next.
pub fn waypoints(mesh: &NavMesh, chain: &[usize]) -> Vec<Waypoint> {
    let mut out = Vec::new();
    for (k, &i) in chain.iter().enumerate() {
        let a = &mesh.areas[i];
        let c = a.center();
        let crouch = a.flags & NAV_CROUCH != 0;
        out.push(Waypoint {
            x: c[0] as f64,
            y: c[1] as f64,
            floor: c[2] as f64,
            crouch,
        });
        if let Some(&j) = chain.get(k + 1) {
            let b = &mesh.areas[j];
            let p = a.portal(b);
            out.push(Waypoint {
                x: p[0] as f64,
                y: p[1] as f64,
                floor: a.z_at(p[0], p[1]).max(b.z_at(p[0], p[1])) as f64,
                crouch: crouch || b.flags & NAV_CROUCH != 0,
            });
        }
    }
    out
}

/// `count` routes between random pairs of areas at least 512 units apart (seeded),
/// with the number of pairs that no chain of areas joins.
pub fn routes(
    mesh: &NavMesh,
    oracle: &Oracle,
    seed: u64,
    count: usize,
) -> (Vec<Route>, Vec<WalkStats>, usize) {
    let mut rng = SplitMix64::new(seed);
    let (mut routes, mut stats, mut unreachable) = (Vec::new(), Vec::new(), 0);
    if mesh.areas.len() < 2 {
        return (routes, stats, 0);
    }
    let mut tries = 0;
    // Paths walked (a path the walker cannot follow all along gives several routes).
    let mut walked = 0;
    while walked < count && tries < count * 20 {
        tries += 1;
        let (i, j) = (rng.below(mesh.areas.len()), rng.below(mesh.areas.len()));
        if mesh.areas[i].center_distance(&mesh.areas[j]) < 512.0 {
            continue;
        }
        let Some(chain) = mesh.area_path(i, j) else {
            unreachable += 1;
            continue;
        };
        // Put the nav mesh's points on the map's own floor (the mesh is approximate).
        let path: Vec<Waypoint> = waypoints(mesh, &chain)
            .into_iter()
            .map(|w| match settle(oracle, w.x, w.y, w.floor, w.crouch) {
                Some((o, c)) => Waypoint::from_origin(oracle, o, c),
                None => w,
            })
            .collect();
        let k = walked;
        walked += 1;
        let name = format!("nav{k}:area{}->area{}", mesh.areas[i].id, mesh.areas[j].id);
        for (r, s) in walk_parts(
            oracle,
            &name,
            &path,
            seed ^ (k as u64 + 1).wrapping_mul(0x51ed),
        ) {
            routes.push(r);
            stats.push(s);
        }
    }
    (routes, stats, unreachable)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(id: u32, x: f32, flags: u8) -> NavArea {
        NavArea {
            id,
            flags,
            lo: [x, 0.0, 0.0],
            hi: [x + 100.0, 100.0, 10.0],
            ne_z: 0.0,
            sw_z: 10.0,
            connections: Default::default(),
            place: 0,
        }
    }

    #[test]
    fn waypoints_cross_the_shared_edge() {
        let mesh = NavMesh {
            version: 5,
            bsp_size: 0,
            places: Vec::new(),
            areas: vec![area(1, 0.0, 0), area(2, 100.0, NAV_CROUCH)],
        };
        let w = waypoints(&mesh, &[0, 1]);
        assert_eq!(w.len(), 3);
        assert_eq!((w[0].x, w[0].y, w[0].floor), (50.0, 50.0, 5.0));
        assert_eq!((w[1].x, w[1].y), (100.0, 50.0), "portal on the shared edge");
        assert!(w[1].crouch && !w[0].crouch && w[2].crouch);
    }
}
