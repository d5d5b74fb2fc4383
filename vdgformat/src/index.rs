//! Index lists as a file stores them: 32-bit, or 16-bit where every index
//! fits (format versions 2 and 4). Queries read them through these views, so
//! they never care which width a file chose.
//!
//! A reduced graph is mostly indices: faces (three vertex indices), the
//! vertex → face and vertex → vertex adjacency and the tree's leaf lists. On
//! every graph of at most 65 536 vertices and faces (the usual size of a
//! reduced graph) half of those bytes are zeros in 32 bits.

/// A list of `u32` indices stored as `u32` or as `u16`: a vertex's faces or
/// neighbours ([`crate::Vdg::vertex_faces`], [`crate::Vdg::vertex_neighbours`])
/// or a tree leaf's faces. Cheap to copy; iterating yields `u32`.
///
/// ```
/// let mut b = vdgformat::VdgBuilder::new();
/// let v = [0., 1., 2., 3.].map(|x| b.add_vertex([x * 10.0, x * x, 0.0], 5.0));
/// b.add_face([v[0], v[1], v[2]]);
/// b.add_face([v[1], v[2], v[3]]);
/// let file = vdgformat::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
/// let g = file.graph();
/// let around = g.vertex_faces(v[1]);
/// assert_eq!(around.len(), 2);
/// assert_eq!(around.iter().collect::<Vec<u32>>(), vec![0, 1]);
/// assert!(g.vertex_neighbours(v[0]).contains(v[2]));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct IndexList<'a>(Repr<'a, u32, u16>);

/// The faces of a graph, each three vertex indices, stored as `[u32; 3]` or
/// as `[u16; 3]` ([`crate::Vdg::faces`]). Cheap to copy; iterating and
/// [`FaceList::get`] yield `[u32; 3]`.
#[derive(Clone, Copy, Debug)]
pub struct FaceList<'a>(Repr<'a, [u32; 3], [u16; 3]>);

#[derive(Clone, Copy, Debug)]
enum Repr<'a, W, N> {
    Wide(&'a [W]),
    Narrow(&'a [N]),
}

impl<W, N> Repr<'_, W, N> {
    #[inline]
    fn len(&self) -> usize {
        match self {
            Repr::Wide(s) => s.len(),
            Repr::Narrow(s) => s.len(),
        }
    }
}

impl<'a> IndexList<'a> {
    pub(crate) fn wide(s: &'a [u32]) -> Self {
        IndexList(Repr::Wide(s))
    }

    pub(crate) fn narrow(s: &'a [u16]) -> Self {
        IndexList(Repr::Narrow(s))
    }

    /// Number of entries.
    #[inline]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the list has no entries.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the file stores this list in 16 bits.
    pub fn is_16_bit(&self) -> bool {
        matches!(self.0, Repr::Narrow(_))
    }

    /// Entry `i`. Panics if `i` is out of range.
    #[inline]
    pub fn get(&self, i: usize) -> u32 {
        match self.0 {
            Repr::Wide(s) => s[i],
            Repr::Narrow(s) => u32::from(s[i]),
        }
    }

    /// The first entry, `None` when empty.
    #[inline]
    pub fn first(&self) -> Option<u32> {
        (!self.is_empty()).then(|| self.get(0))
    }

    /// Whether `x` is an entry.
    #[inline]
    pub fn contains(&self, x: u32) -> bool {
        match self.0 {
            Repr::Wide(s) => s.contains(&x),
            Repr::Narrow(s) => u16::try_from(x).is_ok_and(|x| s.contains(&x)),
        }
    }

    /// The entries, in order.
    #[inline]
    pub fn iter(&self) -> IndexIter<'a> {
        match self.0 {
            Repr::Wide(s) => IndexIter(IterRepr::Wide(s.iter())),
            Repr::Narrow(s) => IndexIter(IterRepr::Narrow(s.iter())),
        }
    }

    /// The entries as a vector.
    pub fn to_vec(&self) -> Vec<u32> {
        self.iter().collect()
    }

    /// Entries `start .. start + count`. Panics when out of range.
    #[inline]
    pub(crate) fn range(&self, start: u32, count: u32) -> IndexList<'a> {
        let r = start as usize..start as usize + count as usize;
        match self.0 {
            Repr::Wide(s) => IndexList(Repr::Wide(&s[r])),
            Repr::Narrow(s) => IndexList(Repr::Narrow(&s[r])),
        }
    }

    /// Entries `start .. end` (CSR offsets, which validation made monotone and
    /// in range). Panics when `end < start` or out of range.
    #[inline]
    pub(crate) fn between(&self, start: u32, end: u32) -> IndexList<'a> {
        self.range(start, end - start)
    }
}

impl<'a> IntoIterator for IndexList<'a> {
    type Item = u32;
    type IntoIter = IndexIter<'a>;
    fn into_iter(self) -> IndexIter<'a> {
        self.iter()
    }
}

/// Iterator over an [`IndexList`].
#[derive(Clone, Debug)]
pub struct IndexIter<'a>(IterRepr<'a>);

#[derive(Clone, Debug)]
enum IterRepr<'a> {
    Wide(std::slice::Iter<'a, u32>),
    Narrow(std::slice::Iter<'a, u16>),
}

impl<'a> Iterator for IndexIter<'a> {
    type Item = u32;
    #[inline]
    fn next(&mut self) -> Option<u32> {
        match &mut self.0 {
            IterRepr::Wide(i) => i.next().copied(),
            IterRepr::Narrow(i) => i.next().map(|&x| u32::from(x)),
        }
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        match &self.0 {
            IterRepr::Wide(i) => i.size_hint(),
            IterRepr::Narrow(i) => i.size_hint(),
        }
    }
}

impl ExactSizeIterator for IndexIter<'_> {}

impl<'a> FaceList<'a> {
    pub(crate) fn wide(s: &'a [[u32; 3]]) -> Self {
        FaceList(Repr::Wide(s))
    }

    pub(crate) fn narrow(s: &'a [[u16; 3]]) -> Self {
        FaceList(Repr::Narrow(s))
    }

    /// Number of faces.
    #[inline]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are no faces.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether the file stores the faces' indices in 16 bits.
    pub fn is_16_bit(&self) -> bool {
        matches!(self.0, Repr::Narrow(_))
    }

    /// The vertex indices of face `f`. Panics if `f` is out of range.
    #[inline]
    pub fn get(&self, f: u32) -> [u32; 3] {
        match self.0 {
            Repr::Wide(s) => s[f as usize],
            Repr::Narrow(s) => s[f as usize].map(u32::from),
        }
    }

    /// The faces, in order.
    pub fn iter(&self) -> FaceIter<'a> {
        FaceIter {
            list: *self,
            next: 0,
        }
    }

    /// The faces as a vector.
    pub fn to_vec(&self) -> Vec<[u32; 3]> {
        self.iter().collect()
    }
}

impl<'a> IntoIterator for FaceList<'a> {
    type Item = [u32; 3];
    type IntoIter = FaceIter<'a>;
    fn into_iter(self) -> FaceIter<'a> {
        self.iter()
    }
}

/// Iterator over a [`FaceList`].
#[derive(Clone, Debug)]
pub struct FaceIter<'a> {
    list: FaceList<'a>,
    next: usize,
}

impl Iterator for FaceIter<'_> {
    type Item = [u32; 3];
    #[inline]
    fn next(&mut self) -> Option<[u32; 3]> {
        let f = (self.next < self.list.len()).then(|| self.list.get(self.next as u32))?;
        self.next += 1;
        Some(f)
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.list.len() - self.next;
        (n, Some(n))
    }
}

impl ExactSizeIterator for FaceIter<'_> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_widths_read_the_same() {
        let wide = [3u32, 7, 65535, 9];
        let narrow = [3u16, 7, 65535, 9];
        let (w, n) = (IndexList::wide(&wide), IndexList::narrow(&narrow));
        assert_eq!(w.to_vec(), n.to_vec());
        assert_eq!(w.range(1, 2).to_vec(), vec![7, 65535]);
        assert_eq!(n.range(1, 2).to_vec(), vec![7, 65535]);
        assert_eq!(n.between(2, 4).to_vec(), vec![65535, 9]);
        assert!(n.contains(65535) && !n.contains(65536 + 3) && !n.contains(4));
        assert!(w.contains(9) && !w.contains(4));
        assert_eq!((w.first(), n.range(0, 0).first()), (Some(3), None));
        assert_eq!(n.iter().len(), 4);
        let fw = [[0u32, 1, 70000]];
        let fnar = [[0u16, 1, 7]];
        assert_eq!(FaceList::wide(&fw).get(0), [0, 1, 70000]);
        assert_eq!(FaceList::narrow(&fnar).to_vec(), vec![[0, 1, 7]]);
    }
}
