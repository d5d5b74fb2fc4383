//! Writes a `.vdg` again with this build's writer: the same vertices, faces,
//! metadata and source hash, with the adjacency and BBox tree built anew. For
//! comparing tree layouts on one graph (e.g. the query benchmark's
//! `VDG_BENCH_FILE` on a file before and after a change of the tree builder).
//!
//! ```text
//! cargo run --release -p vdgformat --example retree -- IN.vdg OUT.vdg
//! ```

use vdgformat::{VdgBuilder, VdgFile};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() != 2 {
        return Err("usage: retree IN.vdg OUT.vdg".into());
    }
    let file = VdgFile::open(&args[0])?;
    let g = file.graph();
    let mut b = VdgBuilder::new();
    for v in g.vertices() {
        b.add_vertex(v.pos, v.clearance);
    }
    for (i, f) in g.faces().iter().enumerate() {
        if g.has_face_radii() {
            b.add_face_with_radii(f, g.face_radii(i as u32));
        } else {
            b.add_face(f);
        }
    }
    for (k, v) in g.metadata() {
        b.set_metadata(k, v);
    }
    b.set_source_hash(g.source_hash());
    b.set_leaf_size(g.info().leaf_size);
    b.write_atomic(&args[1])?;
    let (before, after) = (
        std::fs::metadata(&args[0])?.len(),
        std::fs::metadata(&args[1])?.len(),
    );
    let faces = g.faces().len().max(1) as f64;
    println!(
        "{}: {before} bytes ({:.1} per face) -> {}: {after} bytes ({:.1} per face)",
        args[0],
        before as f64 / faces,
        args[1],
        after as f64 / faces
    );
    Ok(())
}
