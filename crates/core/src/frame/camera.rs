//! The orbit camera: a target, a distance, azimuth and elevation around an up axis.
//!
//! The default camera orbits the centre of the model's bounding sphere (which
//! also sets the near and far planes) at the distance where every splat fits
//! the view with a small margin ([`Camera::fit_distance`]). For a single-view
//! scan (see `PointCloud::scanner_position`) it looks from the scanner's side
//! with the vision convention (y down); z-up data (lidar, E57: `PointCloud::z_up`)
//! from 40° above the horizon with z up; otherwise from +z of the up frame.
//! An orthographic camera ([`Projection::Ortho`]) frames the same way, with
//! its window in place of the field of view (see [`super::projection`]).

use glam::{Mat4, Vec2, Vec3};

use super::projection::{NamedView, Projection};
use crate::cloud::PointCloud;

/// Which world axis points up on screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UpAxis {
    #[default]
    PosY,
    NegY,
    PosZ,
    NegZ,
    PosX,
    NegX,
}

impl UpAxis {
    /// (up, front): the camera sits on +front at azimuth 0, elevation 0.
    pub fn frame(self) -> (Vec3, Vec3) {
        match self {
            UpAxis::PosY => (Vec3::Y, Vec3::Z),
            UpAxis::NegY => (Vec3::NEG_Y, Vec3::NEG_Z),
            UpAxis::PosZ => (Vec3::Z, Vec3::NEG_Y),
            UpAxis::NegZ => (Vec3::NEG_Z, Vec3::Y),
            UpAxis::PosX => (Vec3::X, Vec3::Z),
            UpAxis::NegX => (Vec3::NEG_X, Vec3::NEG_Z),
        }
    }
}

impl std::str::FromStr for UpAxis {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.trim_start_matches('+') {
            "y" | "Y" => UpAxis::PosY,
            "-y" | "-Y" => UpAxis::NegY,
            "z" | "Z" => UpAxis::PosZ,
            "-z" | "-Z" => UpAxis::NegZ,
            "x" | "X" => UpAxis::PosX,
            "-x" | "-X" => UpAxis::NegX,
            _ => return Err(format!("'{s}' is not an axis; use x, -x, y, -y, z or -z")),
        })
    }
}

/// An orbit camera, perspective or orthographic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub target: Vec3,
    pub distance: f32,
    pub azimuth_deg: f32,
    pub elevation_deg: f32,
    /// Vertical field of view.
    pub fov_y_deg: f32,
    pub up: UpAxis,
    /// Radius of the scene's bounding sphere around `target` (sets near/far).
    pub scene_radius: f32,
    pub projection: Projection,
}

/// Default vertical field of view.
pub const DEFAULT_FOV_DEG: f32 = 35.0;

/// The least reach of the depth range to either side of the target, as a
/// share of its distance (see [`Camera::near_far`]).
pub const MIN_DEPTH_RANGE: f32 = 1.0 / 1024.0;

/// How far above the horizon the default view of z-up data looks down, in degrees.
pub const Z_UP_ELEVATION_DEG: f32 = 40.0;

impl Camera {
    /// Where it looks from and along: what back-to-front orders sort for.
    pub fn view_ray(&self) -> crate::spatial::order::ViewRay {
        crate::spatial::order::ViewRay { eye: self.eye(), forward: -self.direction(), parallel: self.is_ortho() }
    }

    /// A camera that frames a sphere at `centre` with `radius`, for an image of `aspect` = w/h.
    pub fn framing(centre: Vec3, radius: f32, aspect: f32) -> Self {
        let mut cam = Camera {
            target: centre,
            distance: 1.0,
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            fov_y_deg: DEFAULT_FOV_DEG,
            up: UpAxis::PosY,
            scene_radius: radius.max(f32::MIN_POSITIVE),
            projection: Projection::Perspective,
        };
        cam.distance = cam.framing_distance(aspect);
        cam
    }

    /// The default view of a cloud: framed, and from the scanner's side for a single-view scan.
    pub fn default_for(cloud: &PointCloud, aspect: f32) -> Self {
        let Some(bounds) = cloud.bounds() else {
            return Camera::framing(Vec3::ZERO, 1.0, aspect);
        };
        // Splats reach one radius beyond their centres.
        let reach = cloud.radii.iter().copied().filter(|r| r.is_finite()).fold(0.0f32, f32::max);
        let mut cam = Camera::framing(bounds.center(), bounds.radius() + reach, aspect);
        if let Some(scanner) = cloud.scanner_position {
            cam.up = UpAxis::NegY;
            cam.look_from_direction(scanner - cam.target);
        } else if cloud.z_up {
            // Survey data: z up, seen from the south-west and above, as GIS viewers open it.
            cam.up = UpAxis::PosZ;
            cam.azimuth_deg = 0.0;
            cam.elevation_deg = Z_UP_ELEVATION_DEG;
        }
        cam.distance = cam.fit_distance(&cloud.positions, aspect);
        cam
    }

    /// The smallest distance (plus a margin) at which every point lies inside
    /// the view, for the current direction; at most the bounding-sphere distance.
    pub fn fit_distance(&self, points: &[Vec3], aspect: f32) -> f32 {
        const MARGIN: f32 = 1.06;
        const MAX_SAMPLES: usize = 20_000;
        let dir = self.direction();
        let view = self.view_matrix();
        let right = view.row(0).truncate();
        let up = view.row(1).truncate();
        let tan_y = (self.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * aspect.max(1e-3);
        let step = (points.len() / MAX_SAMPLES).max(1);
        let needed = points
            .iter()
            .step_by(step)
            .map(|p| {
                let d = (*p - self.target) * MARGIN;
                // An orthographic window does not widen with depth.
                let toward_eye = if self.is_ortho() { 0.0 } else { d.dot(dir) };
                toward_eye + (d.dot(right).abs() / tan_x).max(d.dot(up).abs() / tan_y)
            })
            .fold(0.0f32, f32::max);
        let sphere = self.framing_distance(aspect);
        if needed.is_finite() && needed > 0.0 { needed.min(sphere) } else { sphere }
    }

    /// Distance at which the bounding sphere fits the narrower field of view
    /// (in orthographic, the narrower side of the window).
    pub fn framing_distance(&self, aspect: f32) -> f32 {
        let half_y = self.fov_y_deg.to_radians() * 0.5;
        let half_x = (half_y.tan() * aspect.max(1e-3)).atan();
        match self.projection {
            Projection::Perspective => self.scene_radius / half_y.min(half_x).sin(),
            Projection::Ortho => self.scene_radius / half_y.min(half_x).tan(),
        }
    }

    pub fn is_ortho(&self) -> bool {
        self.projection == Projection::Ortho
    }

    /// Looks from the named view's direction (about the camera's up axis).
    pub fn look_from(&mut self, view: NamedView) {
        (self.azimuth_deg, self.elevation_deg) = view.angles();
    }

    /// The window's half height: per unit of view depth in perspective
    /// (tan(fov_y / 2)), in eye units in orthographic (the same at the target).
    pub fn half_extent_y(&self) -> f32 {
        let tan_y = (self.fov_y_deg.to_radians() * 0.5).tan();
        match self.projection {
            Projection::Perspective => tan_y,
            Projection::Ortho => tan_y * self.distance,
        }
    }

    /// The window's half extent (x, y) for an image of `aspect` = w/h: what
    /// a pixel's ray is cast from (frame.wgsl's `pixel_ray`, the reference's).
    pub fn lens(&self, aspect: f32) -> Vec2 {
        let half_y = self.half_extent_y();
        Vec2::new(half_y * aspect, half_y)
    }

    /// How far the eye stands from the target: the distance in perspective;
    /// in orthographic, which the distance does not change the image of,
    /// outside the scene's sphere (twice its radius), so the near plane cuts nothing.
    pub fn eye_distance(&self) -> f32 {
        match self.projection {
            Projection::Perspective => self.distance,
            Projection::Ortho => 2.0 * self.scene_radius * 1.02,
        }
    }

    /// Sets azimuth and elevation so that the camera lies along `dir` from the target.
    pub fn look_from_direction(&mut self, dir: Vec3) {
        let Some(dir) = dir.try_normalize() else { return };
        let (up, front) = self.up.frame();
        let right = up.cross(front);
        self.elevation_deg = dir.dot(up).clamp(-1.0, 1.0).asin().to_degrees();
        self.azimuth_deg = dir.dot(right).atan2(dir.dot(front)).to_degrees();
    }

    /// Unit vector from the target towards the eye.
    pub fn direction(&self) -> Vec3 {
        let (up, front) = self.up.frame();
        let right = up.cross(front);
        let (az, el) = (self.azimuth_deg.to_radians(), self.elevation_deg.to_radians());
        (right * az.sin() * el.cos() + front * az.cos() * el.cos() + up * el.sin()).normalize()
    }

    pub fn eye(&self) -> Vec3 {
        self.target + self.direction() * self.eye_distance()
    }

    /// Screen up when the camera looks straight along the up axis (plan
    /// views): the horizontal direction away from the camera's azimuth, so
    /// a top view of z-up data at azimuth 0 has north up.
    fn plan_up(&self) -> glam::DVec3 {
        let (up, front) = self.up.frame();
        let (up, front) = (up.as_dvec3(), front.as_dvec3());
        let right = up.cross(front);
        let az = (self.azimuth_deg as f64).to_radians();
        -(right * az.sin() + front * az.cos())
    }

    /// World to eye space (right-handed, looking down -z, y up on screen).
    pub fn view_matrix(&self) -> Mat4 {
        let (up, _) = self.up.frame();
        let dir = self.direction();
        // Straight above or below: up on screen is away from the azimuth.
        let up = if dir.cross(up).length_squared() < 1e-8 { self.plan_up().as_vec3() } else { up };
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, up)
    }

    /// [`Camera::view_matrix`] computed in f64 from the camera's own values:
    /// the eye far from the frame's origin keeps its millimetres (an f32
    /// matrix's translation rounds to 4 mm at 50 km), for picking and measuring.
    pub fn view_matrix_f64(&self) -> glam::DMat4 {
        let (up, front) = self.up.frame();
        let (up, front) = (up.as_dvec3(), front.as_dvec3());
        let right = up.cross(front);
        let (az, el) = ((self.azimuth_deg as f64).to_radians(), (self.elevation_deg as f64).to_radians());
        let direction = (right * az.sin() * el.cos() + front * az.cos() * el.cos() + up * el.sin()).normalize();
        let target = self.target.as_dvec3();
        let eye = target + direction * self.eye_distance() as f64;
        let up = if direction.cross(up).length_squared() < 1e-8 { self.plan_up() } else { up };
        glam::dcamera::rh::view::look_at_mat4(eye, target, up)
    }

    /// Near and far clipping distances, enclosing the scene sphere.
    pub fn near_far(&self) -> (f32, f32) {
        let r = self.scene_radius * 1.02;
        let distance = self.eye_distance();
        // A model tiny against its distance (1e-6 of it and less) would leave
        // far − near a few f32 steps wide, or none: far would round to the
        // distance itself and 1/(far − near) to infinity. The range reaches at
        // least MIN_DEPTH_RANGE of the distance to either side, which only
        // widens it around the model.
        let far = (distance + r).max(distance * (1.0 + MIN_DEPTH_RANGE));
        let near = (distance - r).max(far * 1e-5).min(distance * (1.0 - MIN_DEPTH_RANGE));
        (near, far)
    }

    /// The projection to wgpu clip space (z in 0..1).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let (near, far) = self.near_far();
        match self.projection {
            Projection::Perspective => {
                glam::camera::rh::proj::directx::perspective(self.fov_y_deg.to_radians(), aspect, near, far)
            }
            Projection::Ortho => {
                let half = self.lens(aspect);
                glam::camera::rh::proj::directx::orthographic(-half.x, half.x, -half.y, half.y, near, far)
            }
        }
    }

    /// Focal length in pixels for an image `height` pixels tall: h / (2 tan(fov/2)),
    /// i.e. n·h/(t-b) of Botsch & Kobbelt Eq. 1.
    pub fn focal_pixels(&self, height: u32) -> f32 {
        height as f32 / (2.0 * (self.fov_y_deg.to_radians() * 0.5).tan())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_from_direction_round_trips_for_every_up_axis() {
        for up in [UpAxis::PosY, UpAxis::NegY, UpAxis::PosZ, UpAxis::NegZ, UpAxis::PosX, UpAxis::NegX] {
            let mut cam = Camera::framing(Vec3::ZERO, 1.0, 1.0);
            cam.up = up;
            for dir in [Vec3::new(0.3, -0.5, 0.8), Vec3::new(-1.0, 0.2, 0.1), Vec3::new(0.0, 0.4, -1.0)] {
                cam.look_from_direction(dir);
                assert!(cam.direction().dot(dir.normalize()) > 1.0 - 1e-5, "{up:?} {dir}");
            }
        }
    }

    #[test]
    fn the_target_projects_to_the_image_centre_at_the_given_distance() {
        let mut cam = Camera::framing(Vec3::new(1.0, 2.0, 3.0), 0.5, 1.5);
        cam.azimuth_deg = 40.0;
        cam.elevation_deg = -20.0;
        let eye_space = cam.view_matrix().transform_point3(cam.target);
        assert!(eye_space.truncate().length() < 1e-4);
        assert!((-eye_space.z - cam.distance).abs() < 1e-4);
        let (near, far) = cam.near_far();
        assert!(near > 0.0 && near < cam.distance && far > cam.distance);
    }
}
