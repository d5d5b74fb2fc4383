//! The vertex adjacency the file stores in CSR form (offsets, then the
//! concatenated rows): vertex → faces and vertex → vertices.

/// CSR vertex → faces, faces ascending per vertex.
pub(super) fn vertex_faces(vcount: usize, faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; vcount + 1];
    for f in faces {
        for &v in f {
            offsets[v as usize + 1] += 1;
        }
    }
    for i in 0..vcount {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut targets = vec![0u32; faces.len() * 3];
    for (fi, f) in faces.iter().enumerate() {
        for &v in f {
            targets[fill[v as usize] as usize] = fi as u32;
            fill[v as usize] += 1;
        }
    }
    (offsets, targets)
}

/// CSR vertex → adjacent vertices (sharing a face), ascending and unique.
pub(super) fn vertex_neighbours(vcount: usize, faces: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let (fo, ft) = vertex_faces(vcount, faces);
    let mut offsets = Vec::with_capacity(vcount + 1);
    let mut targets = Vec::with_capacity(faces.len() * 3);
    offsets.push(0u32);
    let mut row = Vec::new();
    for v in 0..vcount {
        row.clear();
        for &f in &ft[fo[v] as usize..fo[v + 1] as usize] {
            row.extend(
                faces[f as usize]
                    .iter()
                    .copied()
                    .filter(|&w| w as usize != v),
            );
        }
        row.sort_unstable();
        row.dedup();
        targets.extend_from_slice(&row);
        offsets.push(targets.len() as u32);
    }
    (offsets, targets)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csr_adjacency() {
        let faces = [[0, 1, 2], [1, 2, 3]];
        let (o, t) = vertex_faces(5, &faces);
        assert_eq!(o, vec![0, 1, 3, 5, 6, 6]);
        assert_eq!(t, vec![0, 0, 1, 0, 1, 1]);
        let (o, t) = vertex_neighbours(5, &faces);
        assert_eq!(o, vec![0, 2, 5, 8, 10, 10]);
        assert_eq!(t, vec![1, 2, 0, 2, 3, 0, 1, 3, 1, 2]);
    }
}
