//! libvdg: the C ABI of [`vdgformat`], for engines that cannot call Rust
//! (a GoldSrc mod's `client.dll`, Xash3D, FTEQW, ioquake3 forks, in-house C++
//! engines). It opens a `.vdg` written by `bsp2vdg` (from a path, memory-mapped,
//! or from a copy of bytes the engine read from its pak/pk3/wad filesystem),
//! answers the graph queries (clearance, line of sight, Voronoi distance,
//! paths with room for an agent), and runs the automatic camera and the
//! director, whose poses are Quake `vieworg`/`viewangles` ready for
//! `V_CalcRefdef`.
//!
//! The header `include/vdg.h` is generated from this file by cbindgen (the
//! test `tests/header.rs` fails when it is stale). Rules every function keeps:
//!
//! - No call crashes on what it can check: NULL pointers, non-finite floats,
//!   negative sizes and invalid parameters are errors. Failing calls return
//!   an error value (`NULL`, `-1`, NaN; each function says which) and set the
//!   thread's message, read with [`vdg_last_error`].
//! - No Rust panic crosses the boundary: every call catches them and reports
//!   an internal error instead.
//! - Pointers that are not NULL must be valid for what the function reads or
//!   writes (that cannot be checked).
//!
//! ```
//! use std::ffi::CStr;
//! // What a C caller sees when the file is missing.
//! let g = unsafe { vdg::vdg_open(c"no/such/map.vdg".as_ptr()) };
//! assert!(g.is_null());
//! let msg = unsafe { CStr::from_ptr(vdg::vdg_last_error()) }.to_str().unwrap();
//! assert!(msg.starts_with("no/such/map.vdg: cannot read .vdg file"));
//! ```

#![allow(non_camel_case_types)]
// Every function is `unsafe extern "C"` because it takes raw pointers; the
// safety contract is the same for all of them and stated once above and in
// the header rather than on each.
#![allow(clippy::missing_safety_doc)]

use std::cell::UnsafeCell;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;

use vdgformat::camera::{
    Camera, CameraId, CameraParams, Director, DirectorEvent, Pose, Status, Target,
};
use vdgformat::{Vdg, VdgFile};

/// Success.
pub const VDG_OK: c_int = 0;
/// Failure; [`vdg_last_error`] says why.
pub const VDG_ERROR: c_int = -1;

/// [`vdg_pose::status`]: normal tracking.
pub const VDG_STATUS_FOLLOWING: c_int = 0;
/// [`vdg_pose::status`]: the target stands outside the graph's free volume;
/// the camera follows the nearest part of the volume towards it.
pub const VDG_STATUS_TARGET_OUTSIDE: c_int = 1;
/// [`vdg_pose::status`]: the graph has no faces; the eye is on the target.
pub const VDG_STATUS_NO_GRAPH: c_int = 2;

/// [`vdg_event::kind`]: the active camera changed (`from` → `camera`).
pub const VDG_EVENT_SWITCHED: c_int = 1;
/// [`vdg_event::kind`]: `camera` cut (jumped) this frame.
pub const VDG_EVENT_CUT: c_int = 2;
/// [`vdg_event::kind`]: the graph differs from the last update's (a new map):
/// every camera started anew.
pub const VDG_EVENT_GRAPH_CHANGED: c_int = 3;

/// An opened `.vdg` graph. Immutable: any number of threads may query one
/// graph at the same time. Made by [`vdg_open`] or [`vdg_open_memory`],
/// released by [`vdg_close`].
pub struct vdg_graph {
    file: VdgFile,
}

/// An automatic camera following one target. Owns its scratch memory; use
/// it from one thread at a time (it may move between threads).
pub struct vdg_camera {
    camera: Camera,
}

/// Several cameras with their own targets, one of them shown. Use it from
/// one thread at a time (it may move between threads).
pub struct vdg_director {
    director: Director,
}

/// What a camera follows, in Quake units (z up).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct vdg_target {
    /// The point to keep in view: best the player's eye (origin + view
    /// offset, in Half-Life 28 standing and 12 crouched); given the origin,
    /// the parameter `target_height` adds a constant height.
    pub origin: [f32; 3],
    /// Where the target looks, Quake `viewangles` `[pitch, yaw, roll]` in
    /// degrees (pitch positive looking down; roll is ignored).
    pub angles: [f32; 3],
    /// The target's velocity in units per second.
    pub velocity: [f32; 3],
}

/// A camera's pose for one frame, in Quake units and degrees: copy `origin`
/// to `V_CalcRefdef`'s `vieworg` and `angles` to its `viewangles`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct vdg_pose {
    /// The eye position.
    pub origin: [f32; 3],
    /// `[pitch, yaw, roll]` in degrees: pitch positive looking down, yaw in
    /// (−180, 180] counter-clockwise from +x, roll 0.
    pub angles: [f32; 3],
    /// 1 when the camera cut (jumped) this frame: a reset, a new graph, a
    /// teleported target or one hidden for too long. Skip interpolation and
    /// motion blur across a cut.
    pub cut: c_int,
    /// 1 when the graph proves a clear line from the eye to the target.
    pub target_visible: c_int,
    /// The point the camera looks at.
    pub look_at: [f32; 3],
    /// `VDG_STATUS_*`.
    pub status: c_int,
    /// The graph face whose volume holds the eye, −1 if none.
    pub face: i32,
}

/// Something a director's last update did (see `VDG_EVENT_*`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct vdg_event {
    /// `VDG_EVENT_*`.
    pub kind: c_int,
    /// The camera concerned (the new active one for a switch), −1 if none.
    pub camera: c_int,
    /// For a switch, the previously active camera, −1 if none.
    pub from: c_int,
}

/// A graph's sizes and bounds.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct vdg_info {
    pub vertex_count: u32,
    pub face_count: u32,
    /// Bounds of the free volume the graph describes.
    pub volume_min: [f32; 3],
    pub volume_max: [f32; 3],
    /// The largest clearance of a vertex.
    pub max_clearance: f32,
    /// XXH64 (seed 0) of the `.bsp` the graph was compiled from, 0 if
    /// unknown; compare with [`vdg_xxh64`] of the map's bytes to detect a
    /// stale `.vdg`.
    pub source_hash: u64,
}

// ---------------------------------------------------------------- errors

/// Bytes of a thread's error buffer, the terminating NUL included: longer
/// messages are cut at a character boundary.
const ERROR_CAPACITY: usize = 1024;

thread_local! {
    /// The thread's message: one buffer for the thread's life, overwritten by
    /// each failing call and never freed or moved, so a pointer that
    /// [`vdg_last_error`] returned stays readable (it then shows the latest
    /// message) even when another call fails in between, as in
    /// `printf("%f %s", vdg_clearance(g, NULL), vdg_last_error())`.
    static LAST_ERROR: UnsafeCell<[c_char; ERROR_CAPACITY]> =
        const { UnsafeCell::new([0; ERROR_CAPACITY]) };
}

fn set_error(message: String) {
    let message = message.replace('\0', " ");
    let mut end = message.len().min(ERROR_CAPACITY - 1);
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    let _ = LAST_ERROR.try_with(|buffer| {
        // SAFETY: the buffer is this thread's; no reference to it is held (C
        // holds only a raw pointer, and reads it between our calls).
        let b = unsafe { &mut *buffer.get() };
        for (dst, &src) in b.iter_mut().zip(&message.as_bytes()[..end]) {
            *dst = src as c_char;
        }
        b[end] = 0;
    });
}

/// Runs a call's body: a returned error or a panic sets the thread's
/// message and turns into `fail`.
fn guard<T>(fail: T, body: impl FnOnce() -> Result<T, String>) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(v)) => v,
        Ok(Err(message)) => {
            set_error(message);
            fail
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_error(format!("internal error in libvdg (please report): {what}"));
            fail
        }
    }
}

/// The message of the last failed call on this thread: one line naming the
/// problem, the same text as the Rust API's errors (for files prefixed with
/// the path), at most 1023 bytes. An empty string when no call failed yet.
/// Successful calls do not clear it. The pointer is the thread's one message
/// buffer: it stays readable for the life of the thread (never freed by a
/// later call), and a later failing call on this thread overwrites the text
/// in it; copy the text to keep that message. Thread-safe (one buffer per
/// thread).
#[unsafe(no_mangle)]
pub extern "C" fn vdg_last_error() -> *const c_char {
    LAST_ERROR
        .try_with(|e| e.get() as *const c_char)
        .unwrap_or(c"".as_ptr())
}

/// The version of the C interface this header describes. It grows when a
/// function or struct changes incompatibly; the shared library's SONAME
/// (`libvdg.so.N`) carries the same number. Compare with [`vdg_abi_version`]
/// to check at run time that the library loaded is the one compiled against.
pub const VDG_ABI_VERSION: c_int = 1;

/// The [`VDG_ABI_VERSION`] the library was built with.
#[unsafe(no_mangle)]
pub extern "C" fn vdg_abi_version() -> c_int {
    VDG_ABI_VERSION
}

/// The library's version, e.g. "0.1.0": a static string, never freed.
#[unsafe(no_mangle)]
pub extern "C" fn vdg_version() -> *const c_char {
    const VERSION: &CStr =
        match CStr::from_bytes_with_nul(concat!(env!("CARGO_PKG_VERSION"), "\0").as_bytes()) {
            Ok(v) => v,
            Err(_) => c"unknown",
        };
    VERSION.as_ptr()
}

// ------------------------------------------------------- argument checks

unsafe fn nonnull<'a, T>(p: *const T, func: &str, name: &str) -> Result<&'a T, String> {
    // SAFETY: non-NULL pointers are valid by the crate's contract.
    unsafe { p.as_ref() }.ok_or_else(|| format!("{func}: {name} is NULL"))
}

unsafe fn nonnull_mut<'a, T>(p: *mut T, func: &str, name: &str) -> Result<&'a mut T, String> {
    // SAFETY: non-NULL pointers are valid and unaliased by the contract.
    unsafe { p.as_mut() }.ok_or_else(|| format!("{func}: {name} is NULL"))
}

fn finite3(v: [f32; 3], func: &str, name: &str) -> Result<[f32; 3], String> {
    if v.iter().all(|c| c.is_finite()) {
        Ok(v)
    } else {
        Err(format!(
            "{func}: {name} is not finite ({}, {}, {})",
            v[0], v[1], v[2]
        ))
    }
}

/// Reads a finite point of 3 floats.
unsafe fn point(p: *const f32, func: &str, name: &str) -> Result<[f32; 3], String> {
    if p.is_null() {
        return Err(format!("{func}: {name} is NULL"));
    }
    // SAFETY: the contract says `p` points at 3 floats.
    let v = unsafe { [p.read(), p.add(1).read(), p.add(2).read()] };
    finite3(v, func, name)
}

unsafe fn graph<'a>(g: *const vdg_graph, func: &str) -> Result<Vdg<'a>, String> {
    Ok(unsafe { nonnull(g, func, "graph") }?.file.graph())
}

unsafe fn target(t: *const vdg_target, func: &str) -> Result<Target, String> {
    let t = unsafe { nonnull(t, func, "target") }?;
    Ok(Target::from_angles(
        finite3(t.origin, func, "target origin")?,
        finite3(t.angles, func, "target angles")?,
        finite3(t.velocity, func, "target velocity")?,
    ))
}

fn delta_time(dt: f32, func: &str) -> Result<f32, String> {
    if dt.is_finite() && dt >= 0.0 {
        Ok(dt)
    } else {
        Err(format!("{func}: dt must be finite and >= 0 (got {dt})"))
    }
}

unsafe fn params(toml: *const c_char, func: &str) -> Result<CameraParams, String> {
    if toml.is_null() {
        return Ok(CameraParams::default());
    }
    // SAFETY: a non-NULL string is NUL-terminated by the contract.
    let text = unsafe { CStr::from_ptr(toml) }
        .to_str()
        .map_err(|_| format!("{func}: camera parameters are not UTF-8"))?;
    CameraParams::from_toml_str(text).map_err(|e| format!("{func}: {e}"))
}

fn pose(p: &Pose) -> vdg_pose {
    vdg_pose {
        origin: p.eye,
        angles: p.angles(),
        cut: p.cut.into(),
        target_visible: p.target_visible.into(),
        look_at: p.look_at,
        status: match p.status {
            Status::Following | Status::Held => VDG_STATUS_FOLLOWING,
            Status::TargetOutside => VDG_STATUS_TARGET_OUTSIDE,
            Status::NoGraph => VDG_STATUS_NO_GRAPH,
        },
        face: p.face.and_then(|f| i32::try_from(f).ok()).unwrap_or(-1),
    }
}

// ----------------------------------------------------------------- graphs

#[cfg(unix)]
fn path_of(c: &CStr) -> Result<PathBuf, String> {
    use std::os::unix::ffi::OsStrExt;
    Ok(std::ffi::OsStr::from_bytes(c.to_bytes()).into())
}

#[cfg(not(unix))]
fn path_of(c: &CStr) -> Result<PathBuf, String> {
    c.to_str()
        .map(PathBuf::from)
        .map_err(|_| "vdg_open: path is not UTF-8".to_string())
}

/// Opens a `.vdg` file by memory-mapping it and validating it once (checksum
/// and structure); NULL on failure. `path` is a NUL-terminated path (UTF-8 on
/// Windows). The file must not be modified in place while open; `bsp2vdg`
/// replaces files by renaming, which is safe on Linux and macOS. On Windows a
/// mapped file cannot be replaced or deleted while open: use
/// [`vdg_open_memory`] if the game must keep running while maps are
/// recompiled. Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_open(path: *const c_char) -> *mut vdg_graph {
    guard(std::ptr::null_mut(), || {
        if path.is_null() {
            return Err("vdg_open: path is NULL".into());
        }
        // SAFETY: NUL-terminated by the contract.
        let path = path_of(unsafe { CStr::from_ptr(path) })?;
        let file = VdgFile::open(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        Ok(Box::into_raw(Box::new(vdg_graph { file })))
    })
}

/// Opens a `.vdg` file image held in memory (e.g. read from a pak/pk3/wad
/// virtual filesystem): the `len` bytes at `data` are copied into aligned
/// storage and validated, so the caller may free or reuse its buffer as soon
/// as the call returns. NULL on failure (NULL `data`, a truncated or corrupt
/// image). Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_open_memory(data: *const c_void, len: usize) -> *mut vdg_graph {
    guard(std::ptr::null_mut(), || {
        if data.is_null() {
            return Err("vdg_open_memory: data is NULL".into());
        }
        if len > isize::MAX as usize {
            return Err(format!("vdg_open_memory: length {len} is impossible"));
        }
        // SAFETY: the contract says `data` holds `len` readable bytes.
        let bytes = unsafe { std::slice::from_raw_parts(data.cast::<u8>(), len) };
        let file = VdgFile::from_bytes(bytes).map_err(|e| format!("memory image: {e}"))?;
        Ok(Box::into_raw(Box::new(vdg_graph { file })))
    })
}

/// Releases a graph (NULL is ignored). No other thread may be using it, and
/// no camera or director may be updated with it afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_close(graph: *mut vdg_graph) {
    guard((), || {
        if !graph.is_null() {
            // SAFETY: made by Box::into_raw in vdg_open*, released once.
            drop(unsafe { Box::from_raw(graph) });
        }
        Ok(())
    })
}

/// Fills `*out` with the graph's sizes and bounds. `VDG_OK` or `VDG_ERROR`.
/// Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_get_info(graph: *const vdg_graph, out: *mut vdg_info) -> c_int {
    guard(VDG_ERROR, || {
        let g = unsafe { self::graph(graph, "vdg_get_info") }?;
        let out = unsafe { nonnull_mut(out, "vdg_get_info", "out") }?;
        let info = g.info();
        *out = vdg_info {
            vertex_count: info.vertex_count,
            face_count: info.face_count,
            volume_min: info.volume_min,
            volume_max: info.volume_max,
            max_clearance: info.max_clearance,
            source_hash: g.source_hash(),
        };
        Ok(VDG_OK)
    })
}

/// XXH64 (seed 0) of `len` bytes, the hash `bsp2vdg` stores of the source
/// map ([`vdg_info::source_hash`]). 0 with an error for NULL `data` and
/// `len` > 0. Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_xxh64(data: *const c_void, len: usize) -> u64 {
    guard(0, || {
        if len == 0 {
            return Ok(vdgformat::xxh64(&[], 0));
        }
        if data.is_null() {
            return Err("vdg_xxh64: data is NULL".into());
        }
        // SAFETY: the contract says `data` holds `len` readable bytes.
        let bytes = unsafe { std::slice::from_raw_parts(data.cast::<u8>(), len) };
        Ok(vdgformat::xxh64(bytes, 0))
    })
}

// ---------------------------------------------------------------- queries

/// Clearance at `p` (3 floats): how far `p` is inside the graph's free
/// volume (thesis 3.7; the radius of free space around it), negative
/// outside the volume, −INFINITY for a graph without faces. NaN on error
/// (NULL or non-finite arguments). Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_clearance(graph: *const vdg_graph, p: *const f32) -> f32 {
    guard(f32::NAN, || {
        let g = unsafe { self::graph(graph, "vdg_clearance") }?;
        let p = unsafe { point(p, "vdg_clearance", "p") }?;
        Ok(g.clearance(p))
    })
}

/// Line of sight (thesis 3.9): 1 when the graph proves the segment from
/// `a` to `b` (3 floats each) runs inside its free volume, 0 when it does
/// not (or cannot tell), −1 on error. Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_visible(
    graph: *const vdg_graph,
    a: *const f32,
    b: *const f32,
) -> c_int {
    guard(VDG_ERROR, || {
        let g = unsafe { self::graph(graph, "vdg_visible") }?;
        let a = unsafe { point(a, "vdg_visible", "a") }?;
        let b = unsafe { point(b, "vdg_visible", "b") }?;
        Ok(g.visible(a, b).into())
    })
}

/// Voronoi distance `VDistance(p, q)` (thesis 5.1): the length of the
/// shortest way from `p` to `q` through the graph (entering at a vertex of
/// `p`'s face, along edges, leaving at a vertex of `q`'s face); the straight
/// distance when both share a face. INFINITY when no way connects them, NaN
/// on error. Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_vdistance(
    graph: *const vdg_graph,
    p: *const f32,
    q: *const f32,
) -> f32 {
    guard(f32::NAN, || {
        let g = unsafe { self::graph(graph, "vdg_vdistance") }?;
        let p = unsafe { point(p, "vdg_vdistance", "p") }?;
        let q = unsafe { point(q, "vdg_vdistance", "q") }?;
        Ok(g.vdistance(p, q).unwrap_or(f32::INFINITY))
    })
}

/// A path from `from` to `to` (3 floats each) for an agent of radius
/// `radius` (≥ 0): it uses only graph vertices with at least that
/// clearance, so the agent keeps `radius` from the walls along the way.
///
/// The path is `from`, the vertices' positions, then `to`: `n` ≥ 2 points of
/// 3 floats. Returns `n`; the points are written to `points` only when
/// `n <= capacity` (so call with `capacity` 0 and `points` NULL to learn the
/// size). Returns 0 when no path exists (e.g. a door narrower than the
/// agent) and −1 on error. `*length` (if `length` is not NULL) receives the
/// path's length whenever one exists. Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_path(
    graph: *const vdg_graph,
    from: *const f32,
    to: *const f32,
    radius: f32,
    points: *mut f32,
    capacity: usize,
    length: *mut f32,
) -> isize {
    guard(-1, || {
        const F: &str = "vdg_path";
        let g = unsafe { self::graph(graph, F) }?;
        let p = unsafe { point(from, F, "from") }?;
        let q = unsafe { point(to, F, "to") }?;
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(format!(
                "{F}: radius must be finite and >= 0 (got {radius})"
            ));
        }
        if points.is_null() && capacity > 0 {
            return Err(format!("{F}: points is NULL but capacity is {capacity}"));
        }
        if capacity > isize::MAX as usize / 12 {
            return Err(format!("{F}: capacity {capacity} is impossible"));
        }
        let Some(path) = g.path_with_clearance(p, q, radius) else {
            return Ok(0);
        };
        if let Some(length) = unsafe { length.as_mut() } {
            *length = path.length;
        }
        let n = path.vertices.len() + 2;
        if n <= capacity {
            // SAFETY: the contract says `points` holds `capacity` × 3 floats.
            let out = unsafe { std::slice::from_raw_parts_mut(points, 3 * n) };
            let vertices = g.vertices();
            let inner = path.vertices.iter().map(|&v| vertices[v as usize].pos);
            for (slot, pt) in out
                .chunks_exact_mut(3)
                .zip(std::iter::once(p).chain(inner).chain([q]))
            {
                slot.copy_from_slice(&pt);
            }
        }
        Ok(n as isize)
    })
}

// ----------------------------------------------------------------- camera

/// A new automatic camera; NULL on failure. `params_toml` is NULL for the
/// default parameters, or TOML text setting any fields of vdgformat's
/// `CameraParams` (`vdgformat/src/camera/params.rs`; e.g.
/// `"distance_mu = 96.0\n"`); unknown keys and out-of-range values are
/// errors. `graph` is the graph the camera will
/// follow, or NULL: it is not retained, since every update names its graph.
/// Thread-safe.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_camera_new(
    graph: *const vdg_graph,
    params_toml: *const c_char,
) -> *mut vdg_camera {
    let _ = graph;
    guard(std::ptr::null_mut(), || {
        let params = unsafe { params(params_toml, "vdg_camera_new") }?;
        let camera = Camera::new(params).map_err(|e| format!("vdg_camera_new: {e}"))?;
        Ok(Box::into_raw(Box::new(vdg_camera { camera })))
    })
}

/// Replaces a camera's parameters (TOML as in [`vdg_camera_new`]; NULL for
/// the defaults); it keeps its place. `VDG_OK` or `VDG_ERROR` (then the old
/// parameters stay).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_camera_set_params(
    camera: *mut vdg_camera,
    params_toml: *const c_char,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_camera_set_params";
        let cam = unsafe { nonnull_mut(camera, F, "camera") }?;
        let params = unsafe { params(params_toml, F) }?;
        cam.camera
            .set_params(params)
            .map_err(|e| format!("{F}: {e}"))?;
        Ok(VDG_OK)
    })
}

/// Advances the camera by `dt` seconds (≥ 0; long frames move as if they
/// were the parameter `max_dt`) towards the best view of `target` on
/// `graph`, and writes the pose to `*out`. The first update places the
/// camera (a cut). The graph must stay open while the camera uses it; a
/// different graph than the last update's (a map change) resets the camera
/// (a cut). `VDG_OK`, or `VDG_ERROR` for NULL pointers or a non-finite
/// target or `dt`; `*out` is then left unchanged. One thread at a time per
/// camera.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_camera_update(
    camera: *mut vdg_camera,
    graph: *const vdg_graph,
    target: *const vdg_target,
    dt: f32,
    out: *mut vdg_pose,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_camera_update";
        let cam = unsafe { nonnull_mut(camera, F, "camera") }?;
        let g = unsafe { self::graph(graph, F) }?;
        let t = unsafe { self::target(target, F) }?;
        let dt = delta_time(dt, F)?;
        let out = unsafe { nonnull_mut(out, F, "out") }?;
        *out = pose(&cam.camera.update(&g, &t, dt));
        Ok(VDG_OK)
    })
}

/// Starts a new scene (e.g. the spectator switched players): places the
/// camera for `target` at once (a cut) and writes that pose to `*out`.
/// `VDG_OK` or `VDG_ERROR` as [`vdg_camera_update`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_camera_reset(
    camera: *mut vdg_camera,
    graph: *const vdg_graph,
    target: *const vdg_target,
    out: *mut vdg_pose,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_camera_reset";
        let cam = unsafe { nonnull_mut(camera, F, "camera") }?;
        let g = unsafe { self::graph(graph, F) }?;
        let t = unsafe { self::target(target, F) }?;
        let out = unsafe { nonnull_mut(out, F, "out") }?;
        *out = pose(&cam.camera.reset(&g, &t));
        Ok(VDG_OK)
    })
}

/// Releases a camera (NULL is ignored).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_camera_free(camera: *mut vdg_camera) {
    guard((), || {
        if !camera.is_null() {
            // SAFETY: made by Box::into_raw in vdg_camera_new, released once.
            drop(unsafe { Box::from_raw(camera) });
        }
        Ok(())
    })
}

// --------------------------------------------------------------- director

fn camera_id(id: c_int, func: &str) -> Result<CameraId, String> {
    u32::try_from(id)
        .map(CameraId)
        .map_err(|_| format!("{func}: no camera {id}"))
}

fn c_id(id: CameraId) -> c_int {
    c_int::try_from(id.0).unwrap_or(-1)
}

/// A director without cameras (thesis 6.2): several cameras with their own
/// targets and parameters on one graph, one of them shown. NULL only if out
/// of memory. Thread-safe.
#[unsafe(no_mangle)]
pub extern "C" fn vdg_director_new() -> *mut vdg_director {
    guard(std::ptr::null_mut(), || {
        Ok(Box::into_raw(Box::new(vdg_director {
            director: Director::new(),
        })))
    })
}

/// Releases a director and its cameras (NULL is ignored).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_free(director: *mut vdg_director) {
    guard((), || {
        if !director.is_null() {
            // SAFETY: made by Box::into_raw in vdg_director_new, released once.
            drop(unsafe { Box::from_raw(director) });
        }
        Ok(())
    })
}

/// Adds a camera with parameters as in [`vdg_camera_new`] (NULL: defaults)
/// and returns its id (≥ 0); the first camera added becomes active. −1 on
/// error.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_add_camera(
    director: *mut vdg_director,
    params_toml: *const c_char,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_add_camera";
        let d = unsafe { nonnull_mut(director, F, "director") }?;
        let params = unsafe { params(params_toml, F) }?;
        let id = d
            .director
            .add_camera(params)
            .map_err(|e| format!("{F}: {e}"))?;
        let c = c_id(id);
        if c < 0 {
            d.director.remove_camera(id);
            return Err(format!("{F}: too many cameras added"));
        }
        Ok(c)
    })
}

/// Removes a camera (if it was active, none is). `VDG_OK`, or `VDG_ERROR`
/// for an unknown id.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_remove_camera(
    director: *mut vdg_director,
    camera: c_int,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_remove_camera";
        let d = unsafe { nonnull_mut(director, F, "director") }?;
        if d.director.remove_camera(camera_id(camera, F)?) {
            Ok(VDG_OK)
        } else {
            Err(format!("{F}: no camera {camera}"))
        }
    })
}

/// Sets what a camera follows from the next update on (call every frame
/// with the target's current state). `VDG_OK`, or `VDG_ERROR` for an
/// unknown id, NULL or a non-finite target.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_set_target(
    director: *mut vdg_director,
    camera: c_int,
    target: *const vdg_target,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_set_target";
        let d = unsafe { nonnull_mut(director, F, "director") }?;
        let t = unsafe { self::target(target, F) }?;
        if d.director.set_target(camera_id(camera, F)?, t) {
            Ok(VDG_OK)
        } else {
            Err(format!("{F}: no camera {camera}"))
        }
    })
}

/// Makes a camera the one shown from the next update on. `VDG_OK`, or
/// `VDG_ERROR` for an unknown id.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_activate(
    director: *mut vdg_director,
    camera: c_int,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_activate";
        let d = unsafe { nonnull_mut(director, F, "director") }?;
        if d.director.activate(camera_id(camera, F)?) {
            Ok(VDG_OK)
        } else {
            Err(format!("{F}: no camera {camera}"))
        }
    })
}

/// The active camera's id, −1 if none is active (or `director` is NULL,
/// which also sets the error).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_active(director: *const vdg_director) -> c_int {
    guard(VDG_ERROR, || {
        let d = unsafe { nonnull(director, "vdg_director_active", "director") }?;
        Ok(d.director.active().map_or(-1, c_id))
    })
}

/// Once per frame: updates every camera that has a target by `dt` seconds
/// on `graph` and writes the active camera's pose to `*out`. Returns 1 when
/// a pose was written, 0 when no camera is active or it has no target yet
/// (`*out` unchanged), −1 on error (NULL pointers, non-finite `dt`). A
/// different graph than last time (a map change) restarts every camera
/// (`VDG_EVENT_GRAPH_CHANGED`). The graph must stay open while the director
/// uses it. One thread at a time per director.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_update(
    director: *mut vdg_director,
    graph: *const vdg_graph,
    dt: f32,
    out: *mut vdg_pose,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_update";
        let d = unsafe { nonnull_mut(director, F, "director") }?;
        let g = unsafe { self::graph(graph, F) }?;
        let dt = delta_time(dt, F)?;
        let out = unsafe { nonnull_mut(out, F, "out") }?;
        Ok(match d.director.update(&g, dt) {
            Some(p) => {
                *out = pose(&p);
                1
            }
            None => 0,
        })
    })
}

/// A camera's pose of the last update: 1 when written to `*out`, 0 when the
/// camera has not been updated yet, −1 on error (unknown id, NULL).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_pose(
    director: *const vdg_director,
    camera: c_int,
    out: *mut vdg_pose,
) -> c_int {
    guard(VDG_ERROR, || {
        const F: &str = "vdg_director_pose";
        let d = unsafe { nonnull(director, F, "director") }?;
        let out = unsafe { nonnull_mut(out, F, "out") }?;
        let id = camera_id(camera, F)?;
        if d.director.camera(id).is_none() {
            return Err(format!("{F}: no camera {camera}"));
        }
        Ok(match d.director.pose(id) {
            Some(p) => {
                *out = pose(&p);
                1
            }
            None => 0,
        })
    })
}

/// What the last [`vdg_director_update`] did: returns the number of events
/// and writes the first `min(count, capacity)` of them to `events` (NULL
/// allowed with `capacity` 0). −1 on error.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn vdg_director_events(
    director: *const vdg_director,
    events: *mut vdg_event,
    capacity: usize,
) -> isize {
    guard(-1, || {
        const F: &str = "vdg_director_events";
        let d = unsafe { nonnull(director, F, "director") }?;
        if events.is_null() && capacity > 0 {
            return Err(format!("{F}: events is NULL but capacity is {capacity}"));
        }
        let all = d.director.events();
        for (i, e) in all.iter().take(capacity).enumerate() {
            let e = match *e {
                DirectorEvent::Switched { from, to } => vdg_event {
                    kind: VDG_EVENT_SWITCHED,
                    camera: c_id(to),
                    from: from.map_or(-1, c_id),
                },
                DirectorEvent::Cut { camera } => vdg_event {
                    kind: VDG_EVENT_CUT,
                    camera: c_id(camera),
                    from: -1,
                },
                DirectorEvent::GraphChanged => vdg_event {
                    kind: VDG_EVENT_GRAPH_CHANGED,
                    camera: -1,
                    from: -1,
                },
            };
            // SAFETY: the contract says `events` holds `capacity` entries.
            unsafe { events.add(i).write(e) };
        }
        Ok(all.len() as isize)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn last_error() -> String {
        unsafe { CStr::from_ptr(vdg_last_error()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn graph_and_camera_handles_cross_threads_as_documented() {
        fn send_sync<T: Send + Sync>() {}
        fn send<T: Send>() {}
        send_sync::<vdg_graph>();
        send::<vdg_camera>();
        send::<vdg_director>();
    }

    #[test]
    fn null_arguments_are_errors_not_crashes() {
        unsafe {
            assert!(vdg_open(std::ptr::null()).is_null());
            assert_eq!(last_error(), "vdg_open: path is NULL");
            assert!(vdg_open_memory(std::ptr::null(), 10).is_null());
            assert_eq!(last_error(), "vdg_open_memory: data is NULL");
            assert!(vdg_clearance(std::ptr::null(), [0.0f32; 3].as_ptr()).is_nan());
            assert_eq!(last_error(), "vdg_clearance: graph is NULL");
            assert_eq!(
                vdg_visible(std::ptr::null(), std::ptr::null(), std::ptr::null()),
                -1
            );
            let cam = vdg_camera_new(std::ptr::null(), std::ptr::null());
            assert!(!cam.is_null());
            let mut out = vdg_pose::default();
            assert_eq!(
                vdg_camera_update(cam, std::ptr::null(), std::ptr::null(), 0.0, &mut out),
                VDG_ERROR
            );
            assert_eq!(last_error(), "vdg_camera_update: graph is NULL");
            vdg_camera_free(cam);
            vdg_camera_free(std::ptr::null_mut());
            vdg_close(std::ptr::null_mut());
            vdg_director_free(std::ptr::null_mut());
            assert_eq!(vdg_director_active(std::ptr::null()), -1);
            assert_eq!(last_error(), "vdg_director_active: director is NULL");
        }
    }

    #[test]
    fn bad_camera_parameters_name_the_problem() {
        let cam = unsafe { vdg_camera_new(std::ptr::null(), c"distance_mu = -5.0".as_ptr()) };
        assert!(cam.is_null());
        let e = last_error();
        assert!(
            e.starts_with("vdg_camera_new: invalid camera parameters:"),
            "{e}"
        );
        assert!(e.contains("distance_mu"), "{e}");
        assert!(!e.contains('\n'));
        let cam = unsafe { vdg_camera_new(std::ptr::null(), c"no_such_key = 1".as_ptr()) };
        assert!(cam.is_null());
        assert!(last_error().contains("no_such_key"), "{}", last_error());
    }

    #[test]
    fn errors_are_per_thread() {
        unsafe { vdg_open(std::ptr::null()) };
        let other = std::thread::spawn(last_error).join().unwrap();
        assert_eq!(other, "");
        assert_eq!(last_error(), "vdg_open: path is NULL");
    }

    /// Two 256 × 64 strips of clearance 32 side by side at z = 0.
    fn strip_bytes() -> Vec<u8> {
        let mut b = vdgformat::VdgBuilder::new();
        let v: Vec<u32> = [[0.0, 0.0], [256.0, 0.0], [0.0, 64.0], [256.0, 64.0]]
            .iter()
            .map(|&[x, y]| b.add_vertex([x, y, 0.0], 32.0))
            .collect();
        b.add_face([v[0], v[1], v[2]]);
        b.add_face([v[1], v[3], v[2]]);
        b.to_bytes().unwrap()
    }

    #[test]
    fn damaged_images_are_refused_with_a_message() {
        let good = strip_bytes();
        let mut rng = 0x9e37_79b9_7f4a_7c15_u64;
        for i in 0..300 {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let mut bytes = good.clone();
            if i % 2 == 0 {
                bytes.truncate((rng >> 33) as usize % good.len());
            } else {
                let at = (rng >> 33) as usize % good.len();
                bytes[at] ^= 1 << (rng % 8);
            }
            let g = unsafe { vdg_open_memory(bytes.as_ptr().cast(), bytes.len()) };
            assert!(g.is_null(), "damage {i} accepted");
            let e = last_error();
            assert!(e.starts_with("memory image: ") && !e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn one_graph_answers_many_threads_alike() {
        let bytes = strip_bytes();
        let g = unsafe { vdg_open_memory(bytes.as_ptr().cast(), bytes.len()) };
        assert!(!g.is_null());
        struct Shared(*const vdg_graph);
        unsafe impl Sync for Shared {}
        let shared = Shared(g);
        let answers: Vec<Vec<u32>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4)
                .map(|_| {
                    let shared = &shared;
                    s.spawn(move || {
                        (0..200)
                            .map(|i| {
                                let p = [i as f32, 10.0, 5.0];
                                let q = [250.0, 60.0 - i as f32 * 0.1, -5.0];
                                let c = unsafe { vdg_clearance(shared.0, p.as_ptr()) };
                                let d = unsafe { vdg_vdistance(shared.0, p.as_ptr(), q.as_ptr()) };
                                c.to_bits() ^ d.to_bits().rotate_left(7)
                            })
                            .collect()
                    })
                })
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        assert!(answers.windows(2).all(|w| w[0] == w[1]));
        unsafe { vdg_close(g) };
    }

    #[test]
    fn path_reports_the_size_it_needs() {
        let bytes = strip_bytes();
        let g = unsafe { vdg_open_memory(bytes.as_ptr().cast(), bytes.len()) };
        let (p, q) = ([5.0f32, 5.0, 0.0], [250.0f32, 60.0, 0.0]);
        let mut len = -1.0f32;
        let n = unsafe {
            vdg_path(
                g,
                p.as_ptr(),
                q.as_ptr(),
                0.0,
                std::ptr::null_mut(),
                0,
                &mut len,
            )
        };
        assert!(n >= 2 && len > 0.0, "{n} {len}");
        let mut buf = vec![f32::NAN; 3 * n as usize + 3];
        let m = unsafe {
            vdg_path(
                g,
                p.as_ptr(),
                q.as_ptr(),
                0.0,
                buf.as_mut_ptr(),
                n as usize,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(m, n);
        assert_eq!(&buf[..3], &p);
        assert_eq!(&buf[3 * n as usize - 3..3 * n as usize], &q);
        assert!(buf[3 * n as usize].is_nan(), "wrote past the count");
        // An agent wider than the strip's clearance has no way through.
        let none = unsafe {
            vdg_path(
                g,
                p.as_ptr(),
                q.as_ptr(),
                40.0,
                std::ptr::null_mut(),
                0,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(none, 0);
        unsafe { vdg_close(g) };
    }

    #[test]
    fn a_panic_becomes_an_error() {
        let v = guard(-1, || -> Result<i32, String> { panic!("boom") });
        assert_eq!(v, -1);
        assert_eq!(
            last_error(),
            "internal error in libvdg (please report): boom"
        );
    }
}
