use super::*;
use std::path::PathBuf;
use toolbox::SplitMix64;

fn put_i32(b: &mut Vec<u8>, v: i32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_f32(b: &mut Vec<u8>, v: f32) {
    b.extend_from_slice(&v.to_le_bytes());
}
fn put_str(b: &mut Vec<u8>, s: &str, n: usize) {
    let mut f = vec![0u8; n];
    f[..s.len()].copy_from_slice(s.as_bytes());
    b.extend_from_slice(&f);
}
fn frame_header(b: &mut Vec<u8>, kind: u8, time: f32, frame: i32) {
    b.push(kind);
    put_f32(b, time);
    put_i32(b, frame);
}

/// A protocol 5 network message frame with the given predicted state.
fn netmsg_v5(b: &mut Vec<u8>, time: f32, simorg: [f32; 3], yaw: f32, view: f32, msg: &[u8]) {
    frame_header(b, 1, time, (time * 100.0) as i32);
    let mut body = vec![0u8; 468];
    let mut at = |off: usize, v: f32| body[off..off + 4].copy_from_slice(&v.to_le_bytes());
    // simvel at 92, simorg at 104, viewheight at 116, cl_viewangles at 132.
    at(92, 250.0);
    for (k, &v) in simorg.iter().enumerate() {
        at(104 + 4 * k, v);
    }
    at(116 + 8, view);
    at(132 + 4, yaw);
    body[464..468].copy_from_slice(&(msg.len() as i32).to_le_bytes());
    b.extend_from_slice(&body);
    b.extend_from_slice(msg);
}

/// A small protocol 5 demo: a LOADING segment and a playback segment with every frame type.
fn synthetic_v5(frames: usize) -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(MAGIC);
    put_i32(&mut b, 5);
    put_i32(&mut b, 48);
    put_str(&mut b, "testmap", 260);
    put_str(&mut b, "valve", 260);
    put_i32(&mut b, 0);
    let dir_slot = b.len();
    put_i32(&mut b, 0);
    assert_eq!(b.len(), 544);
    let loading = b.len();
    netmsg_v5(&mut b, 0.0, [0.0; 3], 0.0, 28.0, b"hello");
    frame_header(&mut b, 5, 0.0, 0);
    let playback = b.len();
    frame_header(&mut b, 2, 0.0, 0);
    frame_header(&mut b, 3, 0.0, 0);
    put_str(&mut b, "+forward", 64);
    frame_header(&mut b, 4, 0.0, 0);
    b.extend_from_slice(&[0u8; 32]);
    frame_header(&mut b, 6, 0.0, 0);
    b.extend_from_slice(&[0u8; 84]);
    frame_header(&mut b, 7, 0.0, 0);
    b.extend_from_slice(&[0u8; 8]);
    frame_header(&mut b, 8, 0.0, 0);
    put_i32(&mut b, 1);
    put_i32(&mut b, 4);
    b.extend_from_slice(b"a.wa");
    b.extend_from_slice(&[0u8; 16]);
    frame_header(&mut b, 9, 0.0, 0);
    put_i32(&mut b, 3);
    b.extend_from_slice(b"xyz");
    for i in 0..frames {
        let t = i as f32 * 0.01;
        let view = if i % 10 == 9 { 12.0 } else { 28.0 };
        netmsg_v5(&mut b, t, [t * 250.0, 0.0, 36.0], 90.0, view, &[7u8; 3]);
        if i == 3 {
            // A second message in the same client frame.
            netmsg_v5(&mut b, t, [t * 250.0, 0.0, 36.0], 90.0, view, &[]);
        }
    }
    frame_header(&mut b, 5, frames as f32 * 0.01, 0);
    let dir = b.len();
    b[dir_slot..dir_slot + 4].copy_from_slice(&(dir as i32).to_le_bytes());
    put_i32(&mut b, 2);
    for (kind, name, off, len) in [
        (0, "LOADING", loading, playback - loading),
        (1, "Playback", playback, dir - playback),
    ] {
        put_i32(&mut b, kind);
        put_str(&mut b, name, 64);
        put_i32(&mut b, 0);
        put_i32(&mut b, -1);
        put_f32(&mut b, if kind == 1 { frames as f32 * 0.01 } else { 0.0 });
        put_i32(&mut b, frames as i32);
        put_i32(&mut b, off as i32);
        put_i32(&mut b, len as i32);
    }
    b
}

/// A small protocol 4 demo (Half-Life 1.0.0.5 layout).
fn synthetic_v4() -> Vec<u8> {
    let mut b = Vec::new();
    b.extend_from_slice(MAGIC);
    put_i32(&mut b, 4);
    put_i32(&mut b, 35);
    put_str(&mut b, "boot_camp", 128);
    put_str(&mut b, "valve", 128);
    put_i32(&mut b, 0x1234);
    let dir_slot = b.len();
    put_i32(&mut b, 0);
    assert_eq!(b.len(), 280);
    let playback = b.len();
    for i in 0..5 {
        let t = i as f32 * 0.05;
        frame_header(&mut b, 1, t, i);
        b.extend_from_slice(&[0u8; 24]);
        put_i32(&mut b, 2);
        b.extend_from_slice(&[1, 2]);
        frame_header(&mut b, 3, t, i);
        b.extend_from_slice(&[0u8; 28]);
        frame_header(&mut b, 6, t, i);
        for v in [
            10.0 * i as f32,
            0.0,
            36.0,
            if i == 4 { 12.0 } else { 28.0 },
            320.0,
        ] {
            put_f32(&mut b, v);
        }
        for v in [5.0, 180.0, 0.0, 0.0, 0.0, 0.0] {
            put_f32(&mut b, v);
        }
        put_i32(&mut b, 0);
        put_i32(&mut b, 0);
        put_f32(&mut b, 90.0);
        frame_header(&mut b, 2, t, i);
        frame_header(&mut b, 5, t, i);
        put_str(&mut b, "+attack", 64);
        frame_header(&mut b, 4, t, i);
    }
    frame_header(&mut b, 8, 0.25, 5);
    let dir = b.len();
    b[dir_slot..dir_slot + 4].copy_from_slice(&(dir as i32).to_le_bytes());
    put_i32(&mut b, 1);
    put_i32(&mut b, 1);
    put_str(&mut b, "Playback", 64);
    put_i32(&mut b, 0);
    put_i32(&mut b, -1);
    put_f32(&mut b, 0.2);
    put_i32(&mut b, 5);
    put_i32(&mut b, playback as i32);
    put_i32(&mut b, (dir - playback) as i32);
    b
}

#[test]
fn reads_a_synthetic_protocol_5_demo() {
    let d = Demo::parse(&synthetic_v5(20)).unwrap();
    assert_eq!(d.header.map_name, "testmap");
    assert_eq!((d.header.demo_protocol, d.header.net_protocol), (5, 48));
    assert_eq!(d.segments.len(), 2);
    assert!(!d.segments[0].is_playback() && d.segments[1].is_playback());
    let kinds: Vec<_> = d.segments[1]
        .frames
        .iter()
        .take(8)
        .map(|f| std::mem::discriminant(&f.kind))
        .collect();
    assert_eq!(kinds.len(), 8);
    assert!(
        matches!(d.segments[1].frames[1].kind, FrameKind::ConsoleCommand(ref s) if s == "+forward")
    );
    assert!(matches!(d.segments[1].frames[5].kind, FrameKind::Sound(ref s) if s.sample == "a.wa"));
    assert!(matches!(
        d.segments[1].frames[6].kind,
        FrameKind::DemoBuffer(3)
    ));
    assert!((d.duration() - 0.2).abs() < 1e-6);
    let p = d.player();
    // The LOADING segment's frame and the repeated time are left out.
    assert_eq!(p.len(), 20);
    assert_eq!(p[2].origin, [0.02f32 * 250.0, 0.0, 36.0]);
    assert_eq!(p[2].angles[1], 90.0);
    assert_eq!(p[2].velocity, Some([250.0, 0.0, 0.0]));
    assert!(p[9].crouched() && !p[8].crouched());
}

#[test]
fn reads_a_synthetic_protocol_4_demo() {
    let d = Demo::parse(&synthetic_v4()).unwrap();
    assert_eq!(d.header.map_name, "boot_camp");
    assert_eq!(d.header.map_crc, 0x1234);
    let p = d.player();
    assert_eq!(p.len(), 5);
    assert_eq!(p[3].origin, [30.0, 0.0, 36.0]);
    assert_eq!(p[3].angles, [5.0, 180.0, 0.0]);
    assert!(p[4].crouched() && !p[3].crouched());
    assert_eq!(p[0].velocity, None);
}

#[test]
fn truncated_or_random_bytes_are_one_line_errors() {
    for good in [synthetic_v5(6), synthetic_v4()] {
        assert!(Demo::parse(&good).is_ok());
        for cut in 0..good.len() {
            let e = Demo::parse(&good[..cut]).unwrap_err().to_string();
            assert!(!e.contains('\n') && !e.is_empty(), "{e}");
        }
        let mut rng = SplitMix64::new(42);
        for _ in 0..3000 {
            let mut b = good.clone();
            for _ in 0..1 + rng.below(6) {
                let i = rng.below(b.len());
                b[i] = rng.next_u64() as u8;
            }
            if let Err(e) = Demo::parse(&b) {
                assert!(!e.to_string().contains('\n'));
            }
        }
    }
}

#[test]
fn other_protocols_and_bad_counts_are_named() {
    let mut b = synthetic_v5(2);
    b[8] = 3;
    assert_eq!(Demo::parse(&b).unwrap_err(), Error::UnsupportedProtocol(3));
    assert!(
        Error::UnsupportedProtocol(3)
            .to_string()
            .contains("protocol 3")
    );
    let mut b = synthetic_v5(2);
    b[0] = b'X';
    assert!(matches!(Demo::parse(&b), Err(Error::BadMagic(_))));
    let mut b = synthetic_v5(2);
    let dir = i32::from_le_bytes(b[540..544].try_into().unwrap()) as usize;
    b[dir..dir + 4].copy_from_slice(&5000i32.to_le_bytes());
    assert_eq!(Demo::parse(&b).unwrap_err(), Error::BadSegmentCount(5000));
}

fn shared_demo(name: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/testmaps/demos")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!("skipped: {} absent", p.display());
        None
    }
}

#[test]
fn the_shared_c1a0_recording_reads() {
    let Some(p) = shared_demo("hldemo-rs-basic.dem") else {
        return;
    };
    let d = Demo::open(&p).unwrap();
    assert_eq!(
        (d.header.map_name.as_str(), d.header.game_dir.as_str()),
        ("c1a0", "valve")
    );
    assert_eq!(d.segments.len(), 2);
    assert_eq!(d.segments[1].frame_count, 289);
    let p = d.player();
    assert!(p.len() > 200, "{} player frames", p.len());
    // The player walks: finite, plausible speeds between frames and a standing view.
    for w in p.windows(2) {
        let dt = w[1].t - w[0].t;
        let d = (0..3)
            .map(|k| (w[1].origin[k] - w[0].origin[k]).powi(2))
            .sum::<f32>()
            .sqrt();
        assert!(dt > 0.0 && (d as f64) / dt < 2000.0, "{d} units in {dt} s");
    }
    assert!(p.iter().any(|f| f.view_height > 20.0));
}

#[test]
fn the_shared_frame_type_and_protocol_4_files_read() {
    if let Some(p) = shared_demo("hldemo-rs-frame-types.dem") {
        let d = Demo::open(&p).unwrap();
        let mut seen = std::collections::BTreeSet::new();
        for f in d.segments.iter().flat_map(|s| &s.frames) {
            seen.insert(format!("{:?}", std::mem::discriminant(&f.kind)));
        }
        assert!(seen.len() >= 9, "{seen:?}");
    }
    if let Some(p) = shared_demo("sourceless-HL1005-boot_camp.dem") {
        let d = Demo::open(&p).unwrap();
        assert_eq!((d.header.demo_protocol, d.header.net_protocol), (4, 35));
        assert_eq!(d.header.map_name, "boot_camp");
        assert!((d.duration() - 25.46).abs() < 0.1, "{}", d.duration());
        let p = d.player();
        assert!(p.len() > 1000, "{} player frames", p.len());
        let span = p[p.len() - 1].t - p[0].t;
        assert!(span > 20.0, "{span}");
    }
}

#[test]
fn the_shared_broken_files_are_one_line_errors() {
    for (name, expect) in [
        ("hldemo-rs-invalid-demo-protocol.dem", "protocol"),
        ("hldemo-rs-invalid-directory-entry-count.dem", "segments"),
        ("hldemo-rs-invalid-frame-type.dem", "frame type"),
        ("hldemo-rs-invalid-magic.dem", "not a GoldSrc demo"),
        (
            "hldemo-rs-invalid-netmsg-length.dem",
            "network message length",
        ),
    ] {
        let Some(p) = shared_demo(name) else { continue };
        let e = Demo::open(&p).unwrap_err().to_string();
        assert!(e.contains(expect) && !e.contains('\n'), "{name}: {e}");
    }
}
