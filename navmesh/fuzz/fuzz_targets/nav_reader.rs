//! Any byte string must either parse into a navigation mesh whose areas answer
//! their queries, or give a one-line error — never a panic, a hang or an
//! allocation larger than the file could describe.
#![no_main]

use libfuzzer_sys::fuzz_target;
use navmesh::NavMesh;

fuzz_target!(|data: &[u8]| {
    let Ok(mesh) = NavMesh::parse(data) else { return };
    for area in &mesh.areas {
        let c = area.center();
        let _ = area.z_at(c[0], c[1]);
        let _ = area.z_at(area.lo[0], area.hi[1]);
    }
});
