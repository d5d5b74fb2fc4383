//! Opening a `.vdg` file: one validation pass, then a zero-copy view.

use std::fmt;
use std::path::Path;

use crate::hash::xxh64;
use crate::index::{FaceList, IndexList};
use crate::layout::{
    CHECKSUM_END, FORMAT_VERSION, Header, Info, MAGIC, MAX_TREE_DEPTH, NodeBounds,
    OLDEST_READABLE_VERSION, SECTION_ALIGN, SectionEntry, TreeNode, Vertex, is_metadata_key,
    section,
};

/// Why a file was rejected. Every malformed-file class has its own variant;
/// `Display` gives a one-line message naming the problem.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be opened or mapped.
    Io(std::io::Error),
    /// Shorter than its header or than the length the header announces.
    Truncated { expected: u64, actual: u64 },
    /// Longer than the length the header announces.
    TrailingData { expected: u64, actual: u64 },
    /// Not a `.vdg` file.
    BadMagic,
    /// A `.vdg` file of a version this reader does not understand.
    UnsupportedVersion { found: u32, supported: u32 },
    /// Header fields are inconsistent (header length, table offset, reserved bytes).
    BadHeader(&'static str),
    /// The stored checksum does not match the contents.
    ChecksumMismatch { stored: u64, computed: u64 },
    /// The section table does not fit in the file.
    SectionTableOutOfBounds,
    /// A section extends past the end of the file or into the header/table.
    SectionOutOfBounds { id: u32 },
    /// A section does not start at a multiple of 16 bytes.
    SectionMisaligned { id: u32, offset: u64 },
    /// Two sections share bytes.
    SectionOverlap { first: u32, second: u32 },
    /// A section's element size or byte length is wrong for its id.
    SectionSizeMismatch { id: u32 },
    /// The same section id appears twice.
    DuplicateSection { id: u32 },
    /// A required section is absent.
    MissingSection { id: u32 },
    /// Two sections that are alternatives to each other are both present
    /// (the 32- and the 16-bit tree leaf faces).
    ConflictingSections { first: u32, second: u32 },
    /// A count in one place disagrees with another.
    CountMismatch {
        what: &'static str,
        expected: u64,
        found: u64,
    },
    /// A NaN or infinite float.
    NonFinite { what: &'static str, index: u64 },
    /// A vertex with negative clearance.
    NegativeClearance { vertex: u64 },
    /// A face uses the same vertex twice.
    DegenerateFace { face: u64 },
    /// A face's own corner radius is below its vertex's clearance (or negative).
    CornerBelowClearance { face: u64, corner: u8 },
    /// An index points past the end of what it indexes.
    IndexOutOfRange {
        what: &'static str,
        at: u64,
        index: u64,
        limit: u64,
    },
    /// CSR offsets do not start at 0, decrease, or do not end at the target count.
    BadOffsets { what: &'static str, at: u64 },
    /// Adjacency lists disagree with the faces (unsorted, duplicates, self
    /// loops, or a face listed under a vertex it does not use).
    InconsistentAdjacency { what: &'static str, vertex: u64 },
    /// Tree nodes do not form a tree (a node reached twice, an unreachable
    /// node, a child before its parent, or too deep).
    BadTreeStructure { node: u64, reason: &'static str },
    /// A tree node's contents are invalid (kind, split outside its cell).
    BadTreeNode { node: u64, reason: &'static str },
    /// The metadata section is not UTF-8 `key=value` lines.
    BadMetadata { line: u64 },
    /// [`crate::Vdg::from_aligned_bytes`] needs a 16-byte aligned buffer.
    UnalignedBuffer,
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use ReadError::*;
        let name = section::name;
        match self {
            Io(e) => write!(f, "cannot read .vdg file: {e}"),
            Truncated { expected, actual } => write!(
                f,
                "truncated .vdg file: {actual} bytes, expected {expected}"
            ),
            TrailingData { expected, actual } => write!(
                f,
                ".vdg file has trailing data: {actual} bytes, header says {expected}"
            ),
            BadMagic => write!(f, "not a .vdg file (wrong magic bytes)"),
            UnsupportedVersion { found, supported } => write!(
                f,
                "unsupported .vdg format version {found} (this reader supports {OLDEST_READABLE_VERSION} to {supported})"
            ),
            BadHeader(what) => write!(f, "corrupt .vdg header: {what}"),
            ChecksumMismatch { stored, computed } => write!(
                f,
                "corrupt .vdg file: checksum {computed:016x} does not match stored {stored:016x}"
            ),
            SectionTableOutOfBounds => write!(f, "corrupt .vdg file: section table out of bounds"),
            SectionOutOfBounds { id } => write!(
                f,
                "corrupt .vdg file: section {id} ({}) out of bounds",
                name(*id)
            ),
            SectionMisaligned { id, offset } => write!(
                f,
                "corrupt .vdg file: section {id} ({}) at offset {offset} is not {SECTION_ALIGN}-byte aligned",
                name(*id)
            ),
            SectionOverlap { first, second } => write!(
                f,
                "corrupt .vdg file: sections {first} ({}) and {second} ({}) overlap",
                name(*first),
                name(*second)
            ),
            SectionSizeMismatch { id } => write!(
                f,
                "corrupt .vdg file: section {id} ({}) has a wrong element size or length",
                name(*id)
            ),
            DuplicateSection { id } => write!(
                f,
                "corrupt .vdg file: section {id} ({}) appears twice",
                name(*id)
            ),
            MissingSection { id } => write!(
                f,
                "corrupt .vdg file: required section {id} ({}) is missing",
                name(*id)
            ),
            ConflictingSections { first, second } => write!(
                f,
                "corrupt .vdg file: sections {first} ({}) and {second} ({}) exclude each other, both are present",
                name(*first),
                name(*second)
            ),
            CountMismatch {
                what,
                expected,
                found,
            } => write!(
                f,
                "corrupt .vdg file: {what} is {found}, expected {expected}"
            ),
            NonFinite { what, index } => {
                write!(f, "corrupt .vdg file: {what} {index} is not finite")
            }
            NegativeClearance { vertex } => write!(
                f,
                "corrupt .vdg file: vertex {vertex} has negative clearance"
            ),
            CornerBelowClearance { face, corner } => write!(
                f,
                "corrupt .vdg file: corner {corner} of face {face} has a radius below its vertex's clearance"
            ),
            DegenerateFace { face } => {
                write!(f, "corrupt .vdg file: face {face} uses a vertex twice")
            }
            IndexOutOfRange {
                what,
                at,
                index,
                limit,
            } => write!(
                f,
                "corrupt .vdg file: {what} entry {at} is {index}, out of range (< {limit})"
            ),
            BadOffsets { what, at } => write!(
                f,
                "corrupt .vdg file: {what} offsets are not monotone/in range at entry {at}"
            ),
            InconsistentAdjacency { what, vertex } => write!(
                f,
                "corrupt .vdg file: {what} list of vertex {vertex} is inconsistent"
            ),
            BadTreeStructure { node, reason } => {
                write!(f, "corrupt .vdg file: tree node {node}: {reason}")
            }
            BadTreeNode { node, reason } => {
                write!(f, "corrupt .vdg file: tree node {node}: {reason}")
            }
            BadMetadata { line } => write!(
                f,
                "corrupt .vdg file: metadata line {line} is not UTF-8 key=value"
            ),
            UnalignedBuffer => write!(f, ".vdg buffer is not 16-byte aligned"),
        }
    }
}

impl std::error::Error for ReadError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ReadError::Io(e) => Some(e),
            _ => None,
        }
    }
}

impl From<std::io::Error> for ReadError {
    fn from(e: std::io::Error) -> Self {
        ReadError::Io(e)
    }
}

/// A validated, zero-copy view of a `.vdg` image. All queries live here
/// (see [`crate::query`]). Cheap to copy; borrow it from a [`VdgFile`].
#[derive(Clone, Copy)]
pub struct Vdg<'a> {
    pub(crate) info: &'a Info,
    pub(crate) vertices: &'a [Vertex],
    pub(crate) faces: FaceList<'a>,
    pub(crate) vf_offsets: &'a [u32],
    pub(crate) vf: IndexList<'a>,
    pub(crate) vn_offsets: &'a [u32],
    pub(crate) vn: IndexList<'a>,
    pub(crate) nodes: &'a [TreeNode],
    pub(crate) leaf_faces: IndexList<'a>,
    pub(crate) metadata: &'a str,
    pub(crate) node_bounds: &'a [NodeBounds],
    /// The faces' own corner radii (`FACE_RADII`), empty when the file has none.
    pub(crate) own_radii: &'a [[f32; 3]],
    /// The header's format version.
    pub(crate) version: u32,
}

impl fmt::Debug for Vdg<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Vdg")
            .field("vertices", &self.vertices.len())
            .field("faces", &self.faces.len())
            .field("tree_nodes", &self.nodes.len())
            .field("leaf_entries", &self.leaf_faces.len())
            .field("leaf_size", &self.info.leaf_size)
            .finish()
    }
}

/// 16-byte aligned owned storage (for files that are not memory-mapped).
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C, align(16))]
struct Block([u8; 16]);

enum Storage {
    Mapped(memmap2::Mmap),
    Owned { blocks: Vec<Block>, len: usize },
}

impl Storage {
    fn bytes(&self) -> &[u8] {
        match self {
            Storage::Mapped(m) => m,
            Storage::Owned { blocks, len } => &bytemuck::cast_slice(blocks)[..*len],
        }
    }
}

/// A validated `.vdg` file held in memory (mapped or owned).
///
/// ```no_run
/// let file = vdgformat::VdgFile::open("maps/graphs/crossfire.vdg")?;
/// let g = file.graph();
/// let c = g.clearance([0.0, 0.0, 64.0]);
/// # Ok::<(), vdgformat::ReadError>(())
/// ```
pub struct VdgFile {
    storage: Storage,
    layout: Layout,
}

impl fmt::Debug for VdgFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("VdgFile")
            .field("bytes", &self.storage.bytes().len())
            .field("graph", &self.graph())
            .finish()
    }
}

/// Validated byte ranges of the sections.
#[derive(Clone, Copy, Debug, Default)]
struct Layout {
    /// Byte ranges by position in [`section::KNOWN`]; the absent one of
    /// each pair of [`section::ALTERNATIVES`] has an empty range.
    ranges: [(usize, usize); section::KNOWN.len()],
    /// Whether each pair of [`section::ALTERNATIVES`] is stored 16-bit.
    narrow: [bool; section::ALTERNATIVES.len()],
    /// The header's format version.
    version: u32,
}

impl VdgFile {
    /// Memory-maps and validates a file. The mapping is read-only; as with
    /// any mmap the file must not be truncated or rewritten in place while
    /// open (`write_atomic` replaces files by rename, which is safe).
    pub fn open(path: impl AsRef<Path>) -> Result<VdgFile, ReadError> {
        let file = std::fs::File::open(path)?;
        // SAFETY: read-only private mapping; see the doc comment about
        // concurrent in-place modification. Queries use checked indexing,
        // so even then they cannot read outside the mapping.
        let map = unsafe { memmap2::Mmap::map(&file)? };
        let layout = validate(&map)?.1;
        Ok(VdgFile {
            storage: Storage::Mapped(map),
            layout,
        })
    }

    /// Copies `bytes` into aligned storage and validates them.
    pub fn from_bytes(bytes: &[u8]) -> Result<VdgFile, ReadError> {
        let mut blocks = vec![Block([0; 16]); bytes.len().div_ceil(16)];
        bytemuck::cast_slice_mut::<Block, u8>(&mut blocks)[..bytes.len()].copy_from_slice(bytes);
        let storage = Storage::Owned {
            blocks,
            len: bytes.len(),
        };
        let layout = validate(storage.bytes())?.1;
        Ok(VdgFile { storage, layout })
    }

    /// The zero-copy view on which all queries run.
    pub fn graph(&self) -> Vdg<'_> {
        view(self.storage.bytes(), &self.layout)
    }

    /// The whole file image.
    pub fn as_bytes(&self) -> &[u8] {
        self.storage.bytes()
    }
}

impl<'a> Vdg<'a> {
    /// Validates a file image that is already 16-byte aligned in memory
    /// (e.g. embedded or mapped by the caller) and views it in place.
    pub fn from_aligned_bytes(bytes: &'a [u8]) -> Result<Vdg<'a>, ReadError> {
        if !(bytes.as_ptr() as usize).is_multiple_of(SECTION_ALIGN as usize) {
            return Err(ReadError::UnalignedBuffer);
        }
        Ok(validate(bytes)?.0)
    }
}

/// The slot of a known section id in [`section::KNOWN`], found at compile time
/// (`view` runs on every [`VdgFile::graph`], e.g. once per C ABI call).
macro_rules! slot {
    ($id:ident) => {
        const { slot_of(section::$id) }
    };
}

fn view<'a>(bytes: &'a [u8], l: &Layout) -> Vdg<'a> {
    let s = |slot: usize| &bytes[l.ranges[slot].0..l.ranges[slot].1];
    // The stored one of pair `k` of the alternatives, 32- or 16-bit.
    let list = |k: usize, wide: usize, narrow: usize| {
        if l.narrow[k] {
            IndexList::narrow(bytemuck::cast_slice(s(narrow)))
        } else {
            IndexList::wide(bytemuck::cast_slice(s(wide)))
        }
    };
    Vdg {
        info: bytemuck::from_bytes(s(slot!(INFO))),
        vertices: bytemuck::cast_slice(s(slot!(VERTICES))),
        faces: if l.narrow[0] {
            FaceList::narrow(bytemuck::cast_slice(s(slot!(FACES16))))
        } else {
            FaceList::wide(bytemuck::cast_slice(s(slot!(FACES))))
        },
        vf_offsets: bytemuck::cast_slice(s(slot!(VERTEX_FACE_OFFSETS))),
        vf: list(1, slot!(VERTEX_FACES), slot!(VERTEX_FACES16)),
        vn_offsets: bytemuck::cast_slice(s(slot!(VERTEX_NEIGHBOUR_OFFSETS))),
        vn: list(2, slot!(VERTEX_NEIGHBOURS), slot!(VERTEX_NEIGHBOURS16)),
        nodes: bytemuck::cast_slice(s(slot!(TREE_NODES))),
        leaf_faces: list(3, slot!(TREE_LEAF_FACES), slot!(TREE_LEAF_FACES16)),
        metadata: std::str::from_utf8(s(slot!(METADATA))).unwrap_or(""),
        node_bounds: bytemuck::cast_slice(s(slot!(TREE_NODE_BOUNDS))),
        own_radii: bytemuck::cast_slice(s(slot!(FACE_RADII))),
        version: l.version,
    }
}

/// Position of a known section id in [`section::KNOWN`]; only ever asked of
/// the ids listed there (in a `const` block an unknown id does not compile).
const fn slot_of(id: u32) -> usize {
    let mut i = 0;
    while i < section::KNOWN.len() {
        if section::KNOWN[i] == id {
            return i;
        }
        i += 1;
    }
    panic!("not a known section id")
}

fn read_pod<T: bytemuck::Pod>(bytes: &[u8], at: usize) -> T {
    bytemuck::pod_read_unaligned(&bytes[at..at + size_of::<T>()])
}

/// The one validation pass. `bytes` must be 16-byte aligned. The checks
/// run in a fixed order (header, section table, contents), so a file with
/// several faults always names the same first one.
fn validate(bytes: &[u8]) -> Result<(Vdg<'_>, Layout), ReadError> {
    let h = check_header(bytes)?;
    let (entries, table_end) = read_section_table(bytes, &h)?;
    let layout = locate_sections(&h, &entries, table_end, bytes.len() as u64)?;
    let g = view(bytes, &layout);
    validate_contents(bytes, &layout, &g)?;
    Ok((g, layout))
}

/// Magic, version, length, checksum and the header's fixed fields.
fn check_header(bytes: &[u8]) -> Result<Header, ReadError> {
    use ReadError::*;
    let len = bytes.len() as u64;
    let header_len = size_of::<Header>();
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        // A short prefix of a real file is "truncated", anything else foreign.
        if bytes.len() < MAGIC.len() && MAGIC.starts_with(bytes) {
            return Err(Truncated {
                expected: header_len as u64,
                actual: len,
            });
        }
        return Err(BadMagic);
    }
    if bytes.len() < header_len {
        return Err(Truncated {
            expected: header_len as u64,
            actual: len,
        });
    }
    let h: Header = read_pod(bytes, 0);
    if !(OLDEST_READABLE_VERSION..=FORMAT_VERSION).contains(&h.version) {
        return Err(UnsupportedVersion {
            found: h.version,
            supported: FORMAT_VERSION,
        });
    }
    if h.file_len > len {
        return Err(Truncated {
            expected: h.file_len,
            actual: len,
        });
    }
    if h.file_len < len {
        return Err(TrailingData {
            expected: h.file_len,
            actual: len,
        });
    }
    let computed = xxh64(&bytes[CHECKSUM_END..], 0);
    if computed != h.checksum {
        return Err(ChecksumMismatch {
            stored: h.checksum,
            computed,
        });
    }
    if h.header_len as usize != header_len {
        return Err(BadHeader("header length"));
    }
    if h.reserved != [0; 6] {
        return Err(BadHeader("reserved bytes are not zero"));
    }
    if h.section_table_offset as usize != header_len {
        return Err(BadHeader("section table offset"));
    }
    Ok(h)
}

/// The section table's entries and where the table ends.
fn read_section_table(bytes: &[u8], h: &Header) -> Result<(Vec<SectionEntry>, u64), ReadError> {
    let header_len = size_of::<Header>();
    let table_end =
        header_len as u64 + u64::from(h.section_count) * size_of::<SectionEntry>() as u64;
    if table_end > bytes.len() as u64 {
        return Err(ReadError::SectionTableOutOfBounds);
    }
    let entries = (0..h.section_count as usize)
        .map(|i| read_pod(bytes, header_len + i * size_of::<SectionEntry>()))
        .collect();
    Ok((entries, table_end))
}

/// Every entry in bounds, aligned and of its section's size; the known
/// sections each found once, none overlapping another, one of each pair
/// of alternatives present: their byte ranges.
fn locate_sections(
    h: &Header,
    entries: &[SectionEntry],
    table_end: u64,
    len: u64,
) -> Result<Layout, ReadError> {
    use ReadError::*;
    let mut layout = Layout {
        version: h.version,
        ..Layout::default()
    };
    let mut found = [false; section::KNOWN.len()];
    // Ids newer than the file's version are unknown sections there (version
    // 1 knew no 16-bit leaf faces, version 2 no face radii, ...).
    let known =
        |id: u32| section::elem_size(id).is_some() && section::since_version(id) <= h.version;
    for e in entries {
        if e.offset < table_end || e.offset > len || e.byte_len > len - e.offset {
            return Err(SectionOutOfBounds { id: e.id });
        }
        if !e.offset.is_multiple_of(SECTION_ALIGN) {
            return Err(SectionMisaligned {
                id: e.id,
                offset: e.offset,
            });
        }
        let slot = section::KNOWN.iter().position(|&id| id == e.id);
        let (Some(slot), Some(size)) = (slot.filter(|_| known(e.id)), section::elem_size(e.id))
        else {
            continue; // unknown sections are skipped (checked for bounds/overlap)
        };
        if e.elem_size != size || e.count.checked_mul(u64::from(size)) != Some(e.byte_len) {
            return Err(SectionSizeMismatch { id: e.id });
        }
        if found[slot] {
            return Err(DuplicateSection { id: e.id });
        }
        found[slot] = true;
        layout.ranges[slot] = (e.offset as usize, (e.offset + e.byte_len) as usize);
    }
    check_overlaps(entries)?;
    check_presence(&found, &mut layout)?;
    if layout.ranges[0].1 - layout.ranges[0].0 != size_of::<Info>() {
        return Err(CountMismatch {
            what: "info record count",
            expected: 1,
            found: ((layout.ranges[0].1 - layout.ranges[0].0) / size_of::<Info>()) as u64,
        });
    }
    Ok(layout)
}

/// No two sections (known or not) share a byte.
fn check_overlaps(entries: &[SectionEntry]) -> Result<(), ReadError> {
    let mut sorted: Vec<&SectionEntry> = entries.iter().collect();
    sorted.sort_by_key(|e| (e.offset, e.byte_len));
    for w in sorted.windows(2) {
        if w[0].offset + w[0].byte_len > w[1].offset {
            return Err(ReadError::SectionOverlap {
                first: w[0].id,
                second: w[1].id,
            });
        }
    }
    Ok(())
}

/// Exactly one of each pair of alternatives (recording which width in
/// `layout`), and every section that is not optional.
fn check_presence(
    found: &[bool; section::KNOWN.len()],
    layout: &mut Layout,
) -> Result<(), ReadError> {
    use ReadError::*;
    for (k, &(wide, narrow)) in section::ALTERNATIVES.iter().enumerate() {
        match (found[slot_of(wide)], found[slot_of(narrow)]) {
            (true, true) => {
                return Err(ConflictingSections {
                    first: wide,
                    second: narrow,
                });
            }
            (_, n) => layout.narrow[k] = n,
        }
    }
    let optional = |id: u32| {
        id == section::FACE_RADII
            || section::ALTERNATIVES
                .iter()
                .any(|&(w, n)| id == w || id == n)
    };
    if let Some(slot) = (0..found.len()).find(|&i| !found[i] && !optional(section::KNOWN[i])) {
        return Err(MissingSection {
            id: section::KNOWN[slot],
        });
    }
    if let Some(&(wide, _)) = section::ALTERNATIVES
        .iter()
        .find(|&&(w, n)| !found[slot_of(w)] && !found[slot_of(n)])
    {
        return Err(MissingSection { id: wide });
    }
    Ok(())
}

fn check_count(what: &'static str, expected: u64, found: u64) -> Result<(), ReadError> {
    if expected != found {
        return Err(ReadError::CountMismatch {
            what,
            expected,
            found,
        });
    }
    Ok(())
}

/// The sections' contents, in a fixed order: counts, the info record,
/// vertices and faces, corner radii, the adjacency, the tree, its node
/// bounds, the metadata.
fn validate_contents(bytes: &[u8], layout: &Layout, g: &Vdg<'_>) -> Result<(), ReadError> {
    check_counts(g)?;
    check_info(g.info)?;
    check_vertices_and_faces(g)?;
    check_corner_radii(g)?;
    check_offsets("vertex-face", g.vf_offsets, g.vf.len())?;
    check_offsets("vertex-neighbour", g.vn_offsets, g.vn.len())?;
    check_adjacency(g)?;
    validate_tree(g)?;
    check_node_bounds(g)?;
    let meta = layout.ranges[slot!(METADATA)];
    validate_metadata(&bytes[meta.0..meta.1])
}

/// The sections' element counts agree with the info record and each other.
fn check_counts(g: &Vdg<'_>) -> Result<(), ReadError> {
    let info = g.info;
    let nv = g.vertices.len() as u64;
    let nf = g.faces.len() as u64;
    check_count("info vertex count", nv, u64::from(info.vertex_count))?;
    check_count("info face count", nf, u64::from(info.face_count))?;
    check_count(
        "info tree node count",
        g.nodes.len() as u64,
        u64::from(info.tree_node_count),
    )?;
    check_count(
        "vertex-face offset count",
        nv + 1,
        g.vf_offsets.len() as u64,
    )?;
    check_count(
        "vertex-neighbour offset count",
        nv + 1,
        g.vn_offsets.len() as u64,
    )?;
    check_count("vertex-face entry count", 3 * nf, g.vf.len() as u64)?;
    check_count(
        "tree node bounds count",
        g.nodes.len() as u64,
        g.node_bounds.len() as u64,
    )
}

/// The info record's floats are finite, its reserved fields zero and its
/// volume bounds ordered.
fn check_info(info: &Info) -> Result<(), ReadError> {
    use ReadError::*;
    let info_floats = info
        .vertex_min
        .iter()
        .chain(&info.vertex_max)
        .chain(&info.volume_min)
        .chain(&info.volume_max)
        .chain([&info.leaf_size, &info.max_clearance]);
    for (i, x) in info_floats.enumerate() {
        if !x.is_finite() {
            return Err(NonFinite {
                what: "info field",
                index: i as u64,
            });
        }
    }
    if info.reserved0 != 0 || info.reserved1 != 0 || info.reserved2 != 0 || info.reserved3 != 0 {
        return Err(BadHeader("reserved info fields are not zero"));
    }
    if (0..3).any(|i| info.volume_min[i] > info.volume_max[i]) {
        return Err(BadHeader("volume bounds min > max"));
    }
    Ok(())
}

/// Vertices finite with a clearance ≥ 0; faces over three distinct
/// vertices that exist.
fn check_vertices_and_faces(g: &Vdg<'_>) -> Result<(), ReadError> {
    use ReadError::*;
    let nv = g.vertices.len() as u64;
    for (i, v) in g.vertices.iter().enumerate() {
        if !(v.pos.iter().all(|c| c.is_finite()) && v.clearance.is_finite()) {
            return Err(NonFinite {
                what: "vertex",
                index: i as u64,
            });
        }
        if v.clearance < 0.0 {
            return Err(NegativeClearance { vertex: i as u64 });
        }
    }
    for (i, f) in g.faces.iter().enumerate() {
        for v in f {
            if u64::from(v) >= nv {
                return Err(IndexOutOfRange {
                    what: "face vertex",
                    at: i as u64,
                    index: u64::from(v),
                    limit: nv,
                });
            }
        }
        if f[0] == f[1] || f[1] == f[2] || f[0] == f[2] {
            return Err(DegenerateFace { face: i as u64 });
        }
    }
    Ok(())
}

/// Each face's own corner radii (when the file has them) finite and at
/// least their vertex's clearance.
fn check_corner_radii(g: &Vdg<'_>) -> Result<(), ReadError> {
    use ReadError::*;
    let nf = g.faces.len() as u64;
    if !g.own_radii.is_empty() {
        check_count("face corner radius count", nf, g.own_radii.len() as u64)?;
        for (i, (f, r)) in g.faces.iter().zip(g.own_radii).enumerate() {
            for k in 0..3 {
                if !r[k].is_finite() {
                    return Err(NonFinite {
                        what: "face corner radius",
                        index: 3 * i as u64 + k as u64,
                    });
                }
                // Written so that the vertex ball stays inside every face around it.
                if r[k] < g.vertices[f[k] as usize].clearance {
                    return Err(CornerBelowClearance {
                        face: i as u64,
                        corner: k as u8,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The vertex → faces and vertex → vertices rows: in range, ascending,
/// and each entry really adjacent.
fn check_adjacency(g: &Vdg<'_>) -> Result<(), ReadError> {
    let nv = g.vertices.len() as u64;
    let nf = g.faces.len() as u64;
    // vertex → faces: ascending, in range, and each face really uses the
    // vertex. With 3·F entries, no duplicates and 3 distinct vertices per
    // face, this makes the lists exactly the incidence relation.
    for v in 0..nv as usize {
        let (start, end) = (g.vf_offsets[v], g.vf_offsets[v + 1]);
        check_row("vertex-face", g.vf.between(start, end), start, nf, v, |f| {
            g.faces.get(f).contains(&(v as u32))
        })?;
        let (start, end) = (g.vn_offsets[v], g.vn_offsets[v + 1]);
        check_row(
            "vertex-neighbour",
            g.vn.between(start, end),
            start,
            nv,
            v,
            |w| w as usize != v,
        )?;
    }
    Ok(())
}

/// One CSR row of vertex `v`, starting at entry `start` of its list: every
/// entry below `limit`, ascending, and `adjacent` to `v`.
fn check_row(
    what: &'static str,
    row: IndexList<'_>,
    start: u32,
    limit: u64,
    v: usize,
    adjacent: impl Fn(u32) -> bool,
) -> Result<(), ReadError> {
    for (k, x) in row.iter().enumerate() {
        if u64::from(x) >= limit {
            return Err(ReadError::IndexOutOfRange {
                what,
                at: u64::from(start) + k as u64,
                index: u64::from(x),
                limit,
            });
        }
        if (k > 0 && row.get(k - 1) >= x) || !adjacent(x) {
            return Err(ReadError::InconsistentAdjacency {
                what,
                vertex: v as u64,
            });
        }
    }
    Ok(())
}

/// The stored node bounds are the ones the faces below each node give.
fn check_node_bounds(g: &Vdg<'_>) -> Result<(), ReadError> {
    use ReadError::*;
    // Node bounds steer the nearest-face search; they must be exactly what
    // the faces below each node give (the computation is deterministic).
    let expected =
        crate::build::node_bounds(g.nodes, g.leaf_faces, g.faces, g.vertices, g.own_radii);
    if let Some(i) = (0..expected.len()).find(|&i| expected[i] != g.node_bounds[i]) {
        return Err(BadTreeNode {
            node: i as u64,
            reason: "stored search bounds do not match the node's faces",
        });
    }
    Ok(())
}

fn check_offsets(what: &'static str, offsets: &[u32], targets: usize) -> Result<(), ReadError> {
    if offsets.first() != Some(&0) {
        return Err(ReadError::BadOffsets { what, at: 0 });
    }
    for (i, w) in offsets.windows(2).enumerate() {
        if w[0] > w[1] {
            return Err(ReadError::BadOffsets {
                what,
                at: i as u64 + 1,
            });
        }
    }
    if *offsets.last().expect("non-empty") as usize != targets {
        return Err(ReadError::BadOffsets {
            what,
            at: offsets.len() as u64 - 1,
        });
    }
    Ok(())
}

/// Preorder tree: every child index is larger than its parent's (so no
/// cycles), every node but the root has exactly one parent (so a tree, not a
/// DAG whose traversal could explode), depth ≤ 64, splits inside their cell,
/// leaf ranges and face indices in range.
fn validate_tree(g: &Vdg<'_>) -> Result<(), ReadError> {
    use ReadError::*;
    let n = g.nodes.len();
    if n == 0 {
        return Err(BadTreeStructure {
            node: 0,
            reason: "tree has no root",
        });
    }
    let mut parents = vec![0u8; n];
    for (i, node) in g.nodes.iter().enumerate() {
        match node.kind {
            0..=2 => {
                if !node.split.is_finite() {
                    return Err(NonFinite {
                        what: "tree split of node",
                        index: i as u64,
                    });
                }
                for c in [node.a, node.b] {
                    if c as usize >= n {
                        return Err(IndexOutOfRange {
                            what: "tree child",
                            at: i as u64,
                            index: u64::from(c),
                            limit: n as u64,
                        });
                    }
                    if c as usize <= i {
                        return Err(BadTreeStructure {
                            node: i as u64,
                            reason: "child stored before its parent (cycle)",
                        });
                    }
                    if parents[c as usize] > 0 {
                        return Err(BadTreeStructure {
                            node: u64::from(c),
                            reason: "node has two parents",
                        });
                    }
                    parents[c as usize] = 1;
                }
            }
            TreeNode::LEAF => {
                let end = u64::from(node.a) + u64::from(node.b);
                if end > g.leaf_faces.len() as u64 {
                    return Err(IndexOutOfRange {
                        what: "tree leaf range end",
                        at: i as u64,
                        index: end,
                        limit: g.leaf_faces.len() as u64 + 1,
                    });
                }
            }
            _ => {
                return Err(BadTreeNode {
                    node: i as u64,
                    reason: "unknown node kind",
                });
            }
        }
    }
    if let Some(orphan) = (1..n).find(|&i| parents[i] == 0) {
        return Err(BadTreeStructure {
            node: orphan as u64,
            reason: "node is not reachable from the root",
        });
    }
    let nf = g.faces.len() as u64;
    for (k, f) in g.leaf_faces.iter().enumerate() {
        if u64::from(f) >= nf {
            return Err(IndexOutOfRange {
                what: "tree leaf face",
                at: k as u64,
                index: u64::from(f),
                limit: nf,
            });
        }
    }
    let mut listed = vec![false; g.faces.len()];
    for f in g.leaf_faces.iter() {
        listed[f as usize] = true;
    }
    if listed.contains(&false) {
        return Err(BadTreeNode {
            node: 0,
            reason: "a face is listed in no tree leaf",
        });
    }
    // Depth and split placement, walking cells down from the root box.
    let root = (g.info.volume_min, g.info.volume_max);
    let mut stack = vec![(0usize, root, 0usize)];
    while let Some((i, (lo, hi), depth)) = stack.pop() {
        if depth > MAX_TREE_DEPTH {
            return Err(BadTreeStructure {
                node: i as u64,
                reason: "tree deeper than 64 levels",
            });
        }
        let node = g.nodes[i];
        if node.kind == TreeNode::LEAF {
            continue;
        }
        let ax = node.kind as usize;
        if !(lo[ax] <= node.split && node.split <= hi[ax]) {
            return Err(BadTreeNode {
                node: i as u64,
                reason: "split plane outside the node's cell",
            });
        }
        let (mut lhi, mut rlo) = (hi, lo);
        lhi[ax] = node.split;
        rlo[ax] = node.split;
        stack.push((node.a as usize, (lo, lhi), depth + 1));
        stack.push((node.b as usize, (rlo, hi), depth + 1));
    }
    Ok(())
}

fn validate_metadata(meta: &[u8]) -> Result<(), ReadError> {
    let text = std::str::from_utf8(meta).map_err(|e| {
        let line = meta[..e.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count();
        ReadError::BadMetadata {
            line: line as u64 + 1,
        }
    })?;
    if !(text.is_empty() || text.ends_with('\n')) {
        return Err(ReadError::BadMetadata {
            line: text.lines().count() as u64,
        });
    }
    for (i, line) in text.lines().enumerate() {
        let ok = line
            .split_once('=')
            .is_some_and(|(k, v)| is_metadata_key(k) && !v.contains('\r'));
        if !ok {
            return Err(ReadError::BadMetadata { line: i as u64 + 1 });
        }
    }
    Ok(())
}
