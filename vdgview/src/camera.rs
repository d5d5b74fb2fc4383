//! Cameras: a perspective eye (position, yaw, pitch, field of view) for renders and
//! the fly-through, and a top-down orthographic overview.
//!
//! World coordinates are the map's: z is up (Quake/GoldSrc convention). Yaw turns
//! about z (0 looks along +x), pitch tilts up (+) or down (−).

use glam::{Vec3, Vec3Swizzles};

/// How points are projected onto the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Perspective with a vertical field of view in degrees.
    Perspective { fov_deg: f32 },
    /// Orthographic, `half_height` world units from the image centre to its top edge.
    Orthographic { half_height: f32 },
}

/// A camera: an eye, a viewing direction and a projection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub pos: Vec3,
    /// Degrees about +z; 0 looks along +x.
    pub yaw: f32,
    /// Degrees; positive looks up. Clamped to ±89.9 except for top views (−90).
    pub pitch: f32,
    pub projection: Projection,
}

/// A camera's orthonormal basis, precomputed once per frame.
#[derive(Debug, Clone, Copy)]
pub struct ViewBasis {
    pub pos: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
}

/// Axis-aligned bounds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub min: Vec3,
    pub max: Vec3,
}

impl Bounds {
    /// The bounds of some points; `None` when there are none.
    pub fn of(points: impl IntoIterator<Item = Vec3>) -> Option<Bounds> {
        let mut it = points.into_iter();
        let first = it.next()?;
        let mut b = Bounds {
            min: first,
            max: first,
        };
        for p in it {
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
        Some(b)
    }

    pub fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }
}

impl Camera {
    /// A perspective camera at `pos` looking at `target`.
    pub fn look_at(pos: Vec3, target: Vec3, fov_deg: f32) -> Camera {
        let d = target - pos;
        let yaw = d.y.atan2(d.x).to_degrees();
        let pitch = d.z.atan2(d.xy().length()).to_degrees();
        Camera {
            pos,
            yaw,
            pitch: pitch.clamp(-89.9, 89.9),
            projection: Projection::Perspective { fov_deg },
        }
    }

    /// Frames `points` from above at an angle (yaw 225°, 45° down), aimed at the
    /// centre of `bounds`: the eye backs off along the viewing direction until
    /// every point fits the image, with a small margin.
    pub fn framing(
        bounds: &Bounds,
        points: impl IntoIterator<Item = Vec3>,
        fov_deg: f32,
        aspect: f32,
    ) -> Camera {
        let (yaw, pitch) = (225.0f32, -45.0f32);
        let points: Vec<Vec3> = points.into_iter().collect();
        let mut cam = Camera {
            pos: bounds.center(),
            yaw,
            pitch,
            projection: Projection::Perspective { fov_deg },
        };
        let b = cam.basis();
        // Aim at the middle of the points' extent across the view (a box's
        // centre leaves empty corners of an irregular level off-centre).
        let across = |p: &Vec3| {
            let d = *p - bounds.center();
            (d.dot(b.right), d.dot(b.up))
        };
        let (mut xr, mut yr) = (
            (f32::INFINITY, f32::NEG_INFINITY),
            (f32::INFINITY, f32::NEG_INFINITY),
        );
        for p in &points {
            let (x, y) = across(p);
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(y), yr.1.max(y));
        }
        let center = if xr.0 <= xr.1 {
            bounds.center() + b.right * ((xr.0 + xr.1) * 0.5) + b.up * ((yr.0 + yr.1) * 0.5)
        } else {
            bounds.center()
        };
        let tan_y = (fov_deg.to_radians() * 0.5).tan() * 0.95;
        let tan_x = tan_y * aspect;
        let mut dist = 1.0f32;
        for &p in &points {
            let d = p - center;
            let (x, y, z) = (d.dot(b.right), d.dot(b.up), d.dot(b.forward));
            // The point fits when |x| <= tan_x * (dist + z), likewise for y.
            dist = dist.max(x.abs() / tan_x - z).max(y.abs() / tan_y - z);
        }
        cam.pos = center - b.forward * dist;
        cam
    }

    /// A top-down orthographic view of `bounds` (x to the right, y up the image).
    pub fn top(bounds: &Bounds, aspect: f32) -> Camera {
        let s = bounds.size();
        let half_height = (s.y * 0.5).max(s.x * 0.5 / aspect) * 1.04 + 1.0;
        let c = bounds.center();
        Camera {
            pos: Vec3::new(c.x, c.y, bounds.max.z + 64.0),
            yaw: 90.0,
            pitch: -90.0,
            projection: Projection::Orthographic { half_height },
        }
    }

    /// The unit viewing direction.
    pub fn forward(&self) -> Vec3 {
        direction(self.yaw, self.pitch)
    }

    /// The camera's basis; for a straight-down view, "up" on the image is the yaw
    /// direction.
    pub fn basis(&self) -> ViewBasis {
        let forward = self.forward();
        let yaw_dir = direction(self.yaw, 0.0);
        let right = yaw_dir.cross(Vec3::Z).normalize();
        let up = right.cross(forward).normalize();
        ViewBasis {
            pos: self.pos,
            forward,
            right,
            up,
        }
    }
}

/// The unit vector for a yaw and pitch in degrees.
pub fn direction(yaw_deg: f32, pitch_deg: f32) -> Vec3 {
    let (sy, cy) = yaw_deg.to_radians().sin_cos();
    let (sp, cp) = pitch_deg.to_radians().sin_cos();
    Vec3::new(cy * cp, sy * cp, sp)
}

/// Parses `--camera X,Y,Z:TX,TY,TZ:FOV` (the FOV part may be left out: 75°).
pub fn parse_camera(s: &str) -> Result<Camera, String> {
    let parts: Vec<&str> = s.split(':').collect();
    if !(2..=3).contains(&parts.len()) {
        return Err(format!(
            "camera {s:?}: expected POS:TARGET[:FOV], e.g. 0,0,64:512,0,64:75"
        ));
    }
    let pos = parse_vec3(parts[0]).map_err(|e| format!("camera position: {e}"))?;
    let target = parse_vec3(parts[1]).map_err(|e| format!("camera target: {e}"))?;
    let fov = match parts.get(2) {
        Some(f) => f
            .trim()
            .parse::<f32>()
            .ok()
            .filter(|f| (1.0..=170.0).contains(f))
            .ok_or_else(|| format!("camera fov {f:?}: expected degrees in 1..170"))?,
        None => 75.0,
    };
    if (target - pos).length() < 1e-3 {
        return Err("camera position and target coincide".into());
    }
    Ok(Camera::look_at(pos, target, fov))
}

/// Parses `X,Y,Z` (finite numbers).
pub fn parse_vec3(s: &str) -> Result<Vec3, String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|c| c.trim().parse::<f32>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not X,Y,Z"))?;
    match v[..] {
        [x, y, z] => Ok(Vec3::new(x, y, z)),
        _ => Err(format!("{s:?} is not X,Y,Z")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_points_at_the_target() {
        let c = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(11.0, 12.0, 3.0), 60.0);
        let f = c.forward();
        assert!((f - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
        let b = c.basis();
        assert!(b.up.z > 0.99 && b.right.dot(f).abs() < 1e-5);
    }

    #[test]
    fn camera_strings_parse_or_fail_clearly() {
        let c = parse_camera("0,0,64:100,0,64:90").unwrap();
        assert_eq!(c.projection, Projection::Perspective { fov_deg: 90.0 });
        assert!(parse_camera("0,0:1,1,1").is_err());
        assert!(parse_camera("0,0,0:0,0,0").is_err());
        assert!(parse_camera("0,0,0:1,0,0:500").is_err());
        assert!(parse_camera("0,0,nan:1,0,0").is_err());
    }

    #[test]
    fn top_view_looks_down_with_y_up_the_image() {
        let b = Bounds::of([Vec3::ZERO, Vec3::new(100.0, 50.0, 20.0)]).unwrap();
        let c = Camera::top(&b, 1.0);
        let basis = c.basis();
        assert!(basis.forward.z < -0.999);
        assert!(basis.up.y > 0.999 && basis.right.x > 0.999);
    }
}
