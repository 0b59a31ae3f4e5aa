//! Clipping: a box and up to [`MAX_CLIP_PLANES`] planes that cut the scene
//! per pixel, not per splat.
//!
//! The user gives a [`ClipRegion`] in file coordinates (f64: lidar files lie
//! far from the origin). [`ClipRegion::in_frame`] moves it into the
//! flattened scene's frame, as lights are moved ([`crate::scene::Scene`]),
//! giving the [`Clip`] a frame's settings carry. Every renderer asks the
//! same question of the point where a pixel's ray meets a splat (the
//! point Eq. 4's depth belongs to): is it kept? The GPU's splat passes
//! discard the fragment when it is not (`clip_keeps` in `frame.wgsl`), the
//! tile pipeline and the CPU reference drop the hit, and shadow rays and
//! the translucent shadow table drop the caster's hit, so a splat cut by a
//! plane shows, blends and shadows exactly its kept part. Rays are cast in
//! eye space, so [`Clip::in_eye`] carries the planes there: a box becomes
//! six planes.

use glam::{DVec3, Mat4, Vec3, Vec4};
use serde::{Deserialize, Serialize};

/// Most clip planes besides the box.
pub const MAX_CLIP_PLANES: usize = 6;

/// Which side of the clip box is hidden.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hidden {
    /// Keep what is inside the box.
    #[default]
    Outside,
    /// Cut the box out of the scene.
    Inside,
}

/// An axis-aligned box, in file coordinates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClipBox {
    pub min: [f64; 3],
    pub max: [f64; 3],
    #[serde(default)]
    pub hide: Hidden,
}

/// What the user asks to clip, in file coordinates: the box and planes
/// n·x + d ≥ 0 (the kept side), each `[nx, ny, nz, d]`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClipRegion {
    #[serde(rename = "box", default, skip_serializing_if = "Option::is_none")]
    pub clip_box: Option<ClipBox>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub planes: Vec<[f64; 4]>,
}

/// A clip region that cannot be used, in one line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClipError {
    #[error("at most {MAX_CLIP_PLANES} clip planes are supported, {0} were given")]
    TooManyPlanes(usize),
    #[error("a clip plane's normal must be finite and not zero, and its d finite: {0:?}")]
    Plane([f64; 4]),
    #[error("the clip box must have finite corners with min <= max on every axis: {0:?} .. {1:?}")]
    Box([f64; 3], [f64; 3]),
    #[error("'{0}' is not {1}")]
    Parse(String, &'static str),
}

/// Comma-separated finite numbers, exactly `N` of them.
fn numbers<const N: usize>(text: &str, what: &'static str) -> Result<[f64; N], ClipError> {
    let bad = || ClipError::Parse(text.to_string(), what);
    let values: Vec<f64> =
        text.split(',').map(|v| v.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
    let values: [f64; N] = values.try_into().map_err(|_| bad())?;
    if values.iter().all(|v| v.is_finite()) { Ok(values) } else { Err(bad()) }
}

impl ClipBox {
    /// `MINX,MINY,MINZ,MAXX,MAXY,MAXZ` (`--clip-box`), hiding the outside.
    pub fn parse(text: &str) -> Result<Self, ClipError> {
        let v = numbers::<6>(text, "a box MINX,MINY,MINZ,MAXX,MAXY,MAXZ (six numbers)")?;
        let clip_box = ClipBox { min: [v[0], v[1], v[2]], max: [v[3], v[4], v[5]], hide: Hidden::Outside };
        clip_box.check()?;
        Ok(clip_box)
    }

    fn check(&self) -> Result<(), ClipError> {
        let ordered = (0..3).all(|i| self.min[i].is_finite() && self.max[i].is_finite() && self.min[i] <= self.max[i]);
        if ordered { Ok(()) } else { Err(ClipError::Box(self.min, self.max)) }
    }
}

/// `NX,NY,NZ,D` (`--clip-plane`): keeps the side where n·x + d ≥ 0.
pub fn parse_plane(text: &str) -> Result<[f64; 4], ClipError> {
    let plane = numbers::<4>(text, "a plane NX,NY,NZ,D (four numbers)")?;
    check_plane(plane)?;
    Ok(plane)
}

fn check_plane(p: [f64; 4]) -> Result<(), ClipError> {
    let normal = DVec3::new(p[0], p[1], p[2]);
    if normal.is_finite() && normal.length_squared() > 0.0 && p[3].is_finite() {
        Ok(())
    } else {
        Err(ClipError::Plane(p))
    }
}

impl ClipRegion {
    pub fn is_empty(&self) -> bool {
        self.clip_box.is_none() && self.planes.is_empty()
    }

    /// The checks every source of a region goes through (flags, scene files, sidecars).
    pub fn check(&self) -> Result<(), ClipError> {
        if self.planes.len() > MAX_CLIP_PLANES {
            return Err(ClipError::TooManyPlanes(self.planes.len()));
        }
        self.planes.iter().try_for_each(|p| check_plane(*p))?;
        self.clip_box.as_ref().map_or(Ok(()), ClipBox::check)
    }

    /// Whether the point at `file` (file coordinates, f64) is kept: on the
    /// kept side of every plane, and inside the box (outside it when the box
    /// hides its inside). What `convert` writes of a clipped file.
    pub fn keeps_file_point(&self, file: DVec3) -> bool {
        let planes = self.planes.iter().all(|p| DVec3::new(p[0], p[1], p[2]).dot(file) + p[3] >= 0.0);
        let boxed = self.clip_box.is_none_or(|b| {
            let inside = (0..3).all(|a| (b.min[a]..=b.max[a]).contains(&file[a]));
            inside == (b.hide == Hidden::Outside)
        });
        planes && boxed
    }

    /// The region in a frame whose points are stored as (file − `origin`) / `unit`.
    pub fn in_frame(&self, origin: DVec3, unit: f64) -> Clip {
        let mut clip = Clip::default();
        for (slot, p) in clip.planes.iter_mut().zip(&self.planes) {
            // n·(q·unit + origin) + d ≥ 0  ⇔  n̂·q + (n·origin + d)/(unit·|n|) ≥ 0.
            let n = DVec3::new(p[0], p[1], p[2]);
            let length = n.length();
            *slot = ((n / length).as_vec3()).extend(((n.dot(origin) + p[3]) / (unit * length)) as f32);
        }
        clip.plane_count = self.planes.len().min(MAX_CLIP_PLANES) as u32;
        clip.clip_box = self.clip_box.map(|b| {
            let to_frame = |c: [f64; 3]| ((DVec3::from_array(c) - origin) / unit).as_vec3();
            ClipFrameBox { min: to_frame(b.min), max: to_frame(b.max), hide: b.hide }
        });
        clip
    }
}

/// The clip box in a frame's coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipFrameBox {
    pub min: Vec3,
    pub max: Vec3,
    pub hide: Hidden,
}

/// A clip region in the flattened scene's frame: what render settings carry
/// (fixed-size, so settings stay `Copy`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Clip {
    /// Planes (unit normal, d): n·p + d ≥ 0 is kept.
    pub planes: [Vec4; MAX_CLIP_PLANES],
    pub plane_count: u32,
    pub clip_box: Option<ClipFrameBox>,
}

/// The clip planes in eye space: the user's planes first, then the box's six
/// (inward), as the GPU's frame uniforms hold them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EyeClip {
    pub planes: [Vec4; 2 * MAX_CLIP_PLANES],
    /// The user's planes, the box's (0 or 6), and 1 when the box hides its inside.
    pub counts: [u32; 3],
}

impl Clip {
    /// Nothing is clipped.
    pub fn is_empty(&self) -> bool {
        self.plane_count == 0 && self.clip_box.is_none()
    }

    /// Whether the frame point `p` is kept.
    pub fn keeps(&self, p: Vec3) -> bool {
        let planes_keep = self.planes[..self.plane_count as usize].iter().all(|q| q.truncate().dot(p) + q.w >= 0.0);
        planes_keep
            && self.clip_box.is_none_or(|b| {
                let inside = p.cmpge(b.min).all() && p.cmple(b.max).all();
                inside == (b.hide == Hidden::Outside)
            })
    }

    /// The planes in the eye space of `view` (a plane transforms by the inverse transpose).
    pub fn in_eye(&self, view: &Mat4) -> EyeClip {
        let to_eye = view.inverse().transpose();
        let mut out = EyeClip::default();
        let mut count = 0;
        let mut push = |plane: Vec4| {
            let eye = to_eye * plane;
            // Kept unit-length, so a plane's d is a distance in eye space.
            out.planes[count] = eye / eye.truncate().length().max(f32::MIN_POSITIVE);
            count += 1;
        };
        self.planes[..self.plane_count as usize].iter().for_each(|p| push(*p));
        if let Some(b) = self.clip_box {
            for axis in 0..3 {
                let unit = Vec3::AXES[axis];
                push(unit.extend(-b.min[axis]));
                push((-unit).extend(b.max[axis]));
            }
        }
        out.counts = [self.plane_count, if self.clip_box.is_some() { 6 } else { 0 }, 0];
        out.counts[2] = self.clip_box.is_some_and(|b| b.hide == Hidden::Inside) as u32;
        out
    }
}

impl EyeClip {
    /// Whether the point at view depth `t` along `ray` (its direction has
    /// z = -1) is kept, each plane tested as (n·dir)·t + (n·origin + d): what
    /// `clip_keeps` in `frame.wgsl` computes.
    pub fn keeps_along(&self, ray: &crate::frame::eye_ray::EyeRay, t: f32) -> bool {
        let distance = |q: &Vec4| q.truncate().dot(ray.dir) * t + (q.truncate().dot(ray.origin) + q.w);
        let [user, boxed, hide_inside] = self.counts;
        if !self.planes[..user as usize].iter().all(|q| distance(q) >= 0.0) {
            return false;
        }
        if boxed == 0 {
            return true;
        }
        let inside = self.planes[user as usize..(user + boxed) as usize].iter().all(|q| distance(q) >= 0.0);
        inside != (hide_inside == 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The perspective ray from the eye through `dir`.
    fn from_eye(dir: Vec3) -> crate::frame::eye_ray::EyeRay {
        crate::frame::eye_ray::EyeRay { origin: Vec3::ZERO, dir }
    }

    #[test]
    fn a_region_in_file_coordinates_clips_the_same_points_in_frame_and_eye_space() {
        let origin = DVec3::new(500_000.0, 4_000_000.0, 100.0);
        let region = ClipRegion {
            clip_box: Some(ClipBox {
                min: [500_001.0, 4_000_000.0, 99.0],
                max: [500_003.0, 4_000_002.0, 101.0],
                hide: Hidden::Outside,
            }),
            planes: vec![[0.0, 0.0, 2.0, -200.0]],
        };
        let clip = region.in_frame(origin, 1.0);
        let view = glam::camera::rh::view::look_at_mat4(Vec3::new(3.0, -4.0, 5.0), Vec3::ZERO, Vec3::Z);
        let eye = clip.in_eye(&view);
        let file = |x: f64, y: f64, z: f64| (DVec3::new(x, y, z) - origin).as_vec3();
        for (p, kept) in [
            (file(500_002.0, 4_000_001.0, 100.5), true),
            (file(500_002.0, 4_000_001.0, 99.5), false),  // below z = 100
            (file(500_004.0, 4_000_001.0, 100.5), false), // outside the box
        ] {
            assert_eq!(clip.keeps(p), kept, "{p}");
            let q = view.transform_point3(p);
            assert_eq!(eye.keeps_along(&from_eye(q / -q.z), -q.z), kept, "{p} in eye space");
        }
        let inverted =
            ClipRegion { clip_box: region.clip_box.map(|b| ClipBox { hide: Hidden::Inside, ..b }), planes: vec![] };
        let clip = inverted.in_frame(origin, 1.0);
        assert!(!clip.keeps(file(500_002.0, 4_000_001.0, 100.5)));
        assert!(clip.keeps(file(500_004.0, 4_000_001.0, 100.5)));
        let q = view.transform_point3(file(500_004.0, 4_000_001.0, 100.5));
        assert!(clip.in_eye(&view).keeps_along(&from_eye(q / -q.z), -q.z));
    }

    #[test]
    fn bad_regions_are_refused() {
        assert!(parse_plane("0,0,0,1").is_err());
        assert!(parse_plane("1,0,0").is_err());
        assert!(parse_plane("1,0,0,nan").is_err());
        assert!(ClipBox::parse("0,0,0,1,1").is_err());
        assert!(ClipBox::parse("1,0,0,0,1,1").is_err());
        let many = ClipRegion { clip_box: None, planes: vec![[1.0, 0.0, 0.0, 0.0]; 7] };
        assert_eq!(many.check(), Err(ClipError::TooManyPlanes(7)));
    }
}
