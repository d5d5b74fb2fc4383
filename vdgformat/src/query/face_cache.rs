//! What a caller that covers many sight lines per frame (a camera) keeps
//! about the faces of one graph: every face volume's box, and the clearance
//! functions of the faces it evaluated last.
//!
//! A tree-leaf search of a sight-line cover tests every face of the leaf
//! (many on open maps, whose big faces reach into many cells) for whether
//! its volume's box holds one point. Derived from the file, that box costs
//! three vertex loads and a dozen f64 operations per face and axis; stored
//! as six f32 it is six comparisons (24 bytes per face).
//!
//! A camera's sight lines of one frame all end at the target and start
//! near the camera, and the next frame's lie close to them: they cross the
//! same faces again and again. Setting up a face's clearance function
//! ([`FaceEval`], a square root and a division) costs about as much as two
//! evaluations; a small direct-mapped memo of the last ones saves most of
//! it. Face indices follow the vertices' spatial order, so neighbouring
//! faces fall into different slots.

use std::cell::{Cell, RefCell};

use crate::geom::{FaceEval, V3};
use crate::read::Vdg;

/// Slots of the memo of face clearance functions (a power of two).
const EVAL_SLOTS: usize = 512;
/// Slots of the memo of clearance values (a power of two).
const VALUE_SLOTS: usize = 256;

/// Per face, the box of its three vertex balls rounded outwards to f32
/// (`[lo_x, lo_y, lo_z, hi_x, hi_y, hi_z]`), and a memo of recently set-up
/// clearance functions. Interior mutability keeps the memo usable through
/// the shared references the queries pass around; it is not `Sync`, and
/// needs not be (one per camera).
#[derive(Clone, Debug, Default)]
pub(crate) struct FaceCache {
    boxes: Vec<[f32; 6]>,
    /// Per face, a ball holding its volume, `[x, y, z, radius]` (see
    /// [`FaceCache::reach_below`]).
    spheres: Vec<[f32; 4]>,
    /// Slots of recently set-up faces, lent out by reference
    /// ([`FaceCache::with_face`]): copying a face's 232 bytes out of a
    /// `Cell` on every use cost more than the borrow flag.
    evals: RefCell<Vec<Option<(u32, FaceEval)>>>,
    /// Recent clearances asked of [`FaceCache::fc`]: face, the point's
    /// bits, value. The camera asks the same face at the same point more
    /// than once (a climb at the end of a step, the local vertices at the
    /// start of the next update from the same point and face).
    values: Vec<Cell<(u32, [u64; 3], f64)>>,
    /// A set of vertices (see [`FaceCache::new_vertex_set`]).
    taken: StampSet,
    /// A set of faces (see [`FaceCache::new_face_set`]).
    met: StampSet,
}

/// A set of indices below a fixed bound, emptied in constant time: each
/// member carries the number of the set that took it, and a new set is a
/// new number. No sort to dedupe, no clearing of a list.
#[derive(Clone, Debug, Default)]
struct StampSet {
    stamps: Vec<Cell<u32>>,
    set: Cell<u32>,
}

impl StampSet {
    /// An empty set of indices below `n`, reusing the memory.
    fn reset(&mut self, n: usize) {
        self.stamps.clear();
        self.stamps.resize(n, Cell::new(0));
        self.set.set(0);
    }

    /// Empties the set.
    #[inline]
    fn clear(&self) {
        let next = self.set.get().wrapping_add(1);
        if next == 0 {
            // After 2³² sets the numbers come round: forget them all.
            self.stamps.iter().for_each(|t| t.set(0));
            self.set.set(1);
        } else {
            self.set.set(next);
        }
    }

    /// Puts `i` into the set: `true` if it was not in it.
    #[inline]
    fn insert(&self, i: u32) -> bool {
        let t = &self.stamps[i as usize];
        let set = self.set.get();
        t.replace(set) != set
    }
}

/// A point as the box test sees it: widened by the same relative slack as
/// [`Vdg::box_holds`] and rounded outwards to f32, so a face the stored
/// boxes rule out is one `box_holds` rules out too.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BoxProbe {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl BoxProbe {
    pub(crate) fn at(p: V3) -> BoxProbe {
        let q = [p.0, p.1, p.2];
        let slack = q.map(|x| 1e-6 * (1.0 + x.abs()));
        BoxProbe {
            lo: [0, 1, 2].map(|i| round_down_f32(q[i] - slack[i])),
            hi: [0, 1, 2].map(|i| round_up_f32(q[i] + slack[i])),
        }
    }
}

impl FaceCache {
    /// Fills the boxes for graph `g`, reusing the memory of earlier ones.
    pub(crate) fn rebuild(&mut self, g: &Vdg<'_>) {
        // The memo names faces of the old graph.
        let evals = self.evals.get_mut();
        evals.clear();
        evals.resize(EVAL_SLOTS, None);
        self.values.clear();
        self.values
            .resize(VALUE_SLOTS, Cell::new((u32::MAX, [0; 3], f64::NAN)));
        self.taken.reset(g.vertex_count());
        self.met.reset(g.faces.len());
        self.boxes.clear();
        self.boxes.reserve(g.faces.len());
        for (fi, f) in g.faces.iter().enumerate() {
            let balls = f.map(|v| g.vertices[v as usize].pos);
            let radii = g.face_radii(fi as u32);
            let mut b = [0.0f32; 6];
            for i in 0..3 {
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for (v, &r) in balls.iter().zip(&radii) {
                    let (c, r) = (f64::from(v[i]), f64::from(r));
                    lo = lo.min(c - r);
                    hi = hi.max(c + r);
                }
                b[i] = round_down_f32(lo);
                b[i + 3] = round_up_f32(hi);
            }
            self.boxes.push(b);
        }
        self.spheres.clear();
        self.spheres.reserve(g.faces.len());
        for fi in 0..g.faces.len() as u32 {
            self.spheres.push(volume_sphere(g, fi));
        }
    }

    /// Whether face `f`'s clearance at `p` is certainly below `floor`
    /// (its computed value too, rounding included): `p` lies farther than
    /// `R − floor` from the centre of the face's stored ball (see
    /// [`volume_sphere`]).
    #[inline]
    pub(crate) fn reach_below(&self, f: u32, p: V3, floor: f64) -> bool {
        let [x, y, z, r] = self.spheres[f as usize];
        let room = f64::from(r) - floor;
        if room <= 0.0 {
            return true;
        }
        let d = p - V3(f64::from(x), f64::from(y), f64::from(z));
        d.norm2() > room * room
    }

    /// Runs `use_face` on face `f`'s clearance function, set up from the
    /// memo when it holds it (and put there otherwise). A nested call, made
    /// from inside `use_face`, finds the memo lent out and sets its face up
    /// afresh: the same function, only slower.
    #[inline]
    pub(crate) fn with_face<R>(
        &self,
        g: &Vdg<'_>,
        f: u32,
        use_face: impl FnOnce(&FaceEval) -> R,
    ) -> R {
        let Ok(mut evals) = self.evals.try_borrow_mut() else {
            return use_face(&g.face_eval(f));
        };
        let Some(slot) = evals.get_mut(f as usize & (EVAL_SLOTS - 1)) else {
            return use_face(&g.face_eval(f));
        };
        let (_, fe) = match slot {
            Some(held) if held.0 == f => held,
            _ => slot.insert((f, g.face_eval(f))),
        };
        use_face(fe)
    }

    /// Starts a new set of vertices for [`FaceCache::take`] (an empty one).
    #[inline]
    pub(crate) fn new_vertex_set(&self) {
        self.taken.clear();
    }

    /// Puts vertex `v` into the current set: `true` if it was not in it.
    #[inline]
    pub(crate) fn take(&self, v: u32) -> bool {
        self.taken.insert(v)
    }

    /// Starts a new set of faces for [`FaceCache::meet`] (an empty one).
    #[inline]
    pub(crate) fn new_face_set(&self) {
        self.met.clear();
    }

    /// Puts face `f` into the current set: `true` if it was not in it.
    #[inline]
    pub(crate) fn meet(&self, f: u32) -> bool {
        self.met.insert(f)
    }

    /// Clearance of `p` for face `f` ([`Vdg::fc`], the same value), the
    /// face set up from the memo when it holds it.
    #[inline]
    pub(crate) fn fc(&self, g: &Vdg<'_>, f: u32, p: V3) -> f64 {
        let bits = [p.0.to_bits(), p.1.to_bits(), p.2.to_bits()];
        let mix = bits.iter().fold(u64::from(f), |h, &b| {
            (h ^ b).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        });
        let slot = &self.values[(mix >> 56) as usize & (VALUE_SLOTS - 1)];
        let (face, at, value) = slot.get();
        if face == f && at == bits {
            return value;
        }
        let value = self.with_face(g, f, |fe| fe.eval(p));
        slot.set((f, bits, value));
        value
    }

    /// Minus the distance of `p` to face `f`'s stored box when `p` lies
    /// outside it, an upper bound of the face's clearance at `p` (the
    /// stored box holds the exact one); `None` inside.
    #[inline]
    pub(crate) fn box_bound(&self, f: u32, p: V3) -> Option<f64> {
        let b = &self.boxes[f as usize];
        let d2 = super::outside_box_d2(p, |i| (f64::from(b[i]), f64::from(b[i + 3])));
        (d2 > 0.0).then(|| -d2.sqrt())
    }

    /// Whether face `f`'s box may hold the probe's point: `false` proves the
    /// point is outside the face's volume. NaN anywhere answers `false`.
    #[inline]
    pub(crate) fn holds(&self, f: u32, p: &BoxProbe) -> bool {
        let b = &self.boxes[f as usize];
        b[0] <= p.hi[0]
            && b[3] >= p.lo[0]
            && b[1] <= p.hi[1]
            && b[4] >= p.lo[1]
            && b[2] <= p.hi[2]
            && b[5] >= p.lo[2]
    }
}

/// A ball `[x, y, z, R]` around face `f` with clearance `≤ R − |p − centre|`
/// everywhere. With `c` the triangle's centroid, `r(q) − |p − q| ≤ r(q) + |q − c|
/// − |p − c|` for every point `q` of the triangle, and `r(q) + |q − c|` is
/// convex, so largest at a corner: `R = max (r_i + |v_i − c|)`. The centre is
/// stored rounded to f32 and `R` rounded up, widened by that rounding and by a
/// thousandth of a unit, far more than an evaluation's rounding: a face this
/// rules out could not have beaten the floor even as computed.
fn volume_sphere(g: &Vdg<'_>, f: u32) -> [f32; 4] {
    let corners = g.faces.get(f).map(|v| g.pos(v));
    let radii = g.face_radii(f).map(f64::from);
    let c = (corners[0] + corners[1] + corners[2]) * (1.0 / 3.0);
    let mut reach = f64::NEG_INFINITY;
    for (v, r) in corners.iter().zip(radii) {
        reach = reach.max(r + (*v - c).norm());
    }
    let stored = c.to_f32();
    let moved = (V3::from_f32(stored) - c).norm();
    let slack = moved + 1e-3 + 1e-6 * reach.abs();
    [stored[0], stored[1], stored[2], round_up_f32(reach + slack)]
}

/// `x` rounded to an f32 no smaller than it (NaN stays NaN).
#[inline]
pub(crate) fn round_up_f32(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) < x { r.next_up() } else { r }
}

/// `x` rounded to an f32 no larger than it (NaN stays NaN).
#[inline]
fn round_down_f32(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) > x { r.next_down() } else { r }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::query::{CoverBudget, CoverHint};
    use toolbox::SplitMix64;

    #[test]
    fn stored_boxes_never_rule_out_a_face_the_exact_box_holds() {
        let mut b = crate::VdgBuilder::new();
        let v = [
            b.add_vertex([0.1, -3.7, 1e3], 10.3),
            b.add_vertex([100.9, 0.0, 1e3], 0.7),
            b.add_vertex([0.0, 100.0, 999.3], 25.1),
        ];
        b.add_face(v);
        let file = crate::VdgFile::from_bytes(&b.to_bytes().unwrap()).unwrap();
        let g = file.graph();
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let mut rng = SplitMix64::new(5);
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..20_000 {
            let p = V3(
                rng.range(-40.0, 140.0),
                rng.range(-40.0, 140.0),
                rng.range(960.0, 1040.0),
            );
            let exact = g.box_holds(0, p);
            let stored = cache.holds(0, &BoxProbe::at(p));
            assert!(stored || !exact, "the stored box rules out {p:?}");
            if exact { inside += 1 } else { outside += 1 }
        }
        assert!(inside > 1000 && outside > 1000);
        // Right at the box's edge, and NaN.
        let edge = V3(f64::from(-25.1f32), 50.0, 1000.0);
        assert!(cache.holds(0, &BoxProbe::at(edge)) || !g.box_holds(0, edge));
        assert!(!cache.holds(0, &BoxProbe::at(V3(f64::NAN, 0.0, 1e3))));
    }

    /// A wavy sheet of `2 (n − 1)²` faces with varied clearances, and a
    /// second one 18 units above it whose volume overlaps the first, so
    /// that leaf searches find faces of the other sheet (sharing no vertex
    /// with the current one).
    pub(crate) fn two_sheets(n: usize) -> Vec<u8> {
        let mut b = crate::VdgBuilder::new();
        for layer in 0..2 {
            let z0 = 18.0 * layer as f32;
            let ids: Vec<u32> = (0..n * n)
                .map(|i| {
                    let (x, y) = ((i % n) as f32, (i / n) as f32);
                    let z = z0 + 6.0 * (0.7 * x).sin() * (0.5 * y).cos();
                    b.add_vertex(
                        [x * 16.0, y * 16.0, z],
                        9.0 + 7.0 * ((x * 1.3 + y * 0.7).sin()).abs(),
                    )
                })
                .collect();
            for y in 0..n - 1 {
                for x in 0..n - 1 {
                    let i = y * n + x;
                    b.add_face([ids[i], ids[i + 1], ids[i + n]]);
                    b.add_face([ids[i + 1], ids[i + n + 1], ids[i + n]]);
                }
            }
        }
        b.to_bytes().unwrap()
    }

    /// A random sight line over [`two_sheets`]: a face, a start near it
    /// (up to `lift` units off its plane; 0 draws no offset) and an end
    /// anywhere over the sheets.
    pub(crate) fn random_sight_line(
        g: &crate::Vdg<'_>,
        rng: &mut SplitMix64,
        lift: f64,
    ) -> (u32, [f32; 3], [f32; 3]) {
        let f = rng.below(g.face_count()) as u32;
        let [a, b, c] = g.faces.get(f).map(|v| g.pos(v));
        let (u, w) = (rng.range(0.0, 0.5), rng.range(0.0, 0.5));
        let mut s = a + (b - a) * u + (c - a) * w;
        if lift > 0.0 {
            s = s + V3(0.0, 0.0, rng.range(-lift, lift));
        }
        let e = [
            rng.range(0.0, 240.0) as f32,
            rng.range(0.0, 240.0) as f32,
            rng.range(-10.0, 50.0) as f32,
        ];
        (f, s.to_f32(), e)
    }

    #[test]
    fn sight_lines_and_advances_answer_the_same_with_the_camera_s_face_cache() {
        let bytes = two_sheets(16);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let mut rng = SplitMix64::new(9);
        let (mut seen, mut blocked) = (0, 0);
        for _ in 0..3000 {
            let (f, s, e) = random_sight_line(&g, &mut rng, 2.0);
            let start = CoverBudget {
                hops: 64,
                leaf_searches: 4,
            };
            let (mut b1, mut b2) = (start, start);
            let (mut h1, mut h2) = (CoverHint::default(), CoverHint::default());
            let plain = g.visible_hinted_cached(f, s, e, &mut b1, Some(&mut h1), None, u32::MAX);
            let cached =
                g.visible_hinted_cached(f, s, e, &mut b2, Some(&mut h2), Some(&cache), u32::MAX);
            assert_eq!(plain, cached, "{s:?} -> {e:?}");
            assert_eq!(b1, b2, "budgets spent differently for {s:?} -> {e:?}");
            if plain {
                seen += 1
            } else {
                blocked += 1
            }
            let (mut b1, mut b2) = (start, start);
            let a1 = g.advance_tol(f, s, e, 2.0, &mut b1, 0.125, None, None, u32::MAX);
            let a2 = g.advance_tol(f, s, e, 2.0, &mut b2, 0.125, None, Some(&cache), u32::MAX);
            assert_eq!(
                (a1.point, a1.face, a1.reached),
                (a2.point, a2.face, a2.reached)
            );
        }
        // Both answers occur often enough for the comparison to mean something.
        assert!(
            seen > 300 && blocked > 300,
            "seen {seen}, blocked {blocked}"
        );
    }

    /// A camera placed anew finds the target's face through its cache: the
    /// same face and clearance as the plain search, inside the volume (where
    /// the cache passes over the faces whose box misses the point) and
    /// outside (where it falls back to the plain search).
    #[test]
    fn the_cached_nearest_face_is_the_plain_one() {
        let bytes = two_sheets(16);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let mut rng = SplitMix64::new(13);
        let (mut inside, mut outside) = (0, 0);
        for _ in 0..3000 {
            let (_, s, _) = random_sight_line(&g, &mut rng, 30.0);
            let p = V3::from_f32(s);
            let plain = g.nearest_face_f64(p);
            assert_eq!(g.nearest_face_cached(&cache, p), plain, "{p:?}");
            match plain {
                Some((_, c)) if c > 0.0 => inside += 1,
                _ => outside += 1,
            }
        }
        assert!(
            inside > 300 && outside > 300,
            "inside {inside}, outside {outside}"
        );
    }

    #[test]
    fn the_cached_climb_and_local_vertices_answer_as_the_plain_ones() {
        let bytes = two_sheets(16);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let mut rng = SplitMix64::new(11);
        let (mut moved, mut outside, mut some_left_out) = (0, 0, 0);
        let mut local = Vec::new();
        for _ in 0..3000 {
            let f = rng.below(g.face_count()) as u32;
            let [a, b, c] = g.faces.get(f).map(|v| g.pos(v));
            let (u, w) = (rng.range(0.0, 0.5), rng.range(0.0, 0.5));
            let p = a + (b - a) * u + (c - a) * w + V3(0.0, 0.0, rng.range(-20.0, 20.0));
            for rounds in [1, 4, 32] {
                let plain = g.climb(f, p, rounds);
                let cached = g.climb_cached(&cache, f, p, rounds);
                assert_eq!(
                    (plain.0, plain.1.to_bits()),
                    (cached.0, cached.1.to_bits()),
                    "{p:?}"
                );
                moved += usize::from(plain.0 != f);
                outside += usize::from(plain.1 <= 0.0);
            }
            let q = p.to_f32();
            let mut expected = Vec::new();
            g.for_each_local_vertex(q, f, false, |v| expected.push(v));
            local.clear();
            g.local_vertices_cached(&cache, q, f, &mut local);
            assert_eq!(expected, local, "{p:?} in face {f}");
            let mut all = 0;
            g.for_each_local_vertex(q, f, true, |_| all += 1);
            some_left_out += usize::from(local.len() < all);
        }
        // The climbs move and fail, and the cheap local set is not all of Reachable.
        assert!(
            moved > 300 && outside > 300 && some_left_out > 100,
            "{moved} {outside} {some_left_out}"
        );
    }

    #[test]
    fn a_use_of_the_memo_inside_another_gets_the_same_values() {
        let bytes = two_sheets(8);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let p = V3(40.0, 50.0, 4.0);
        for f in 0..g.face_count() as u32 {
            let h = (f + 1) % g.face_count() as u32;
            // The memo is lent out to the outer use: the inner one sets its
            // face up afresh.
            let (outer, inner) = cache.with_face(&g, f, |fe| (fe.eval(p), cache.fc(&g, h, p)));
            assert_eq!(outer.to_bits(), g.fc(f, p).to_bits(), "face {f}");
            assert_eq!(inner.to_bits(), g.fc(h, p).to_bits(), "face {h}");
        }
    }

    #[test]
    fn the_memos_give_each_face_and_point_their_own_clearance() {
        // 2 · 2 · 15² = 900 faces: more than the memos' slots, so faces
        // share slots and must not get each other's functions or values;
        // nor may two points (one a signed zero away from the other) share
        // values.
        let bytes = two_sheets(16);
        let file = crate::VdgFile::from_bytes(&bytes).unwrap();
        let g = file.graph();
        assert!(g.face_count() > EVAL_SLOTS.max(VALUE_SLOTS));
        let mut cache = FaceCache::default();
        cache.rebuild(&g);
        let points = [
            V3(100.0, 90.0, 3.0),
            V3(100.0, 90.0, 3.5),
            V3(0.0, 12.0, 1.0),
            V3(-0.0, 12.0, 1.0),
        ];
        // Twice over, in an order that makes faces evict one another.
        for round in 0..2 {
            for k in 0..g.face_count() as u32 {
                let f = (k * 7 + round) % g.face_count() as u32;
                for p in points {
                    let cached = cache.fc(&g, f, p);
                    assert_eq!(
                        cached.to_bits(),
                        g.face_eval(f).eval(p).to_bits(),
                        "face {f} at {p:?}"
                    );
                }
            }
        }
    }
}
