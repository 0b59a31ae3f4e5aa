//! A camera as a user asks for it: any of azimuth, elevation, distance,
//! field of view, up axis, projection and named view, each optional. The command line's flags, a
//! scene file's `[camera]` and the viewer's start all give one; what it leaves
//! out, the default view of the model fills ([`Camera::default_for`]).
//!
//! One rule checks every source ([`CameraRequest::check`]): angles finite,
//! the field of view in 0.5..=170°, the distance positive. [`CameraRequest::over`]
//! lays one request over another (the flags over a scene file's), and
//! [`CameraRequest::camera`] makes the camera: the model's default view, the
//! up axis turned with the view direction kept, the projection, the named
//! view's angles, the angles asked for (over the named view's), then the
//! distance that fits every point (or the one asked for).

use super::camera::{Camera, UpAxis};
use super::projection::{NamedView, Projection};
use crate::cloud::PointCloud;

/// The field of view a request may ask for, in degrees.
pub const FOV_RANGE: std::ops::RangeInclusive<f32> = 0.5..=170.0;

/// A camera as asked for; `None` leaves the default view's value.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CameraRequest {
    /// Degrees around the up axis.
    pub azimuth: Option<f32>,
    /// Degrees above the horizon (clamped to -90..=90).
    pub elevation: Option<f32>,
    /// From the model's centre.
    pub distance: Option<f32>,
    /// Vertical field of view in degrees.
    pub fov: Option<f32>,
    pub up: Option<UpAxis>,
    pub projection: Option<Projection>,
    /// Sets azimuth and elevation; an azimuth or elevation asked for too wins.
    pub view: Option<NamedView>,
}

/// Which value of a request is out of range, and why (the caller names the source).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key} must be {rule}, not {value}")]
pub struct CameraRequestError {
    /// `azimuth`, `elevation`, `distance` or `fov`.
    pub key: &'static str,
    pub rule: &'static str,
    pub value: f32,
}

impl CameraRequest {
    /// Whether nothing is asked for.
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// This request's values, and `base`'s where this one has none; a named
    /// view here replaces `base`'s angles too (the flags' `--view top` over a
    /// scene file's azimuth and elevation).
    pub fn over(self, base: CameraRequest) -> CameraRequest {
        let base_angles = self.view.is_none();
        CameraRequest {
            azimuth: self.azimuth.or(base.azimuth.filter(|_| base_angles)),
            elevation: self.elevation.or(base.elevation.filter(|_| base_angles)),
            distance: self.distance.or(base.distance),
            fov: self.fov.or(base.fov),
            up: self.up.or(base.up),
            projection: self.projection.or(base.projection),
            view: self.view.or(base.view),
        }
    }

    /// The first value out of range, if any.
    pub fn check(&self) -> Result<(), CameraRequestError> {
        let bad = |key, rule, value| Err(CameraRequestError { key, rule, value });
        if let Some(a) = self.azimuth.filter(|a| !a.is_finite()) {
            return bad("azimuth", "a finite number of degrees", a);
        }
        if let Some(e) = self.elevation.filter(|e| !e.is_finite()) {
            return bad("elevation", "a finite number of degrees", e);
        }
        if let Some(d) = self.distance.filter(|d| !(d.is_finite() && *d > 0.0)) {
            return bad("distance", "a positive number", d);
        }
        if let Some(f) = self.fov.filter(|f| !FOV_RANGE.contains(f)) {
            return bad("fov", "between 0.5 and 170 degrees", f);
        }
        Ok(())
    }

    /// The camera for `cloud` in an image of `aspect` = w/h: its default
    /// view with this request's values (checked first).
    pub fn camera(&self, cloud: &PointCloud, aspect: f32) -> Result<Camera, CameraRequestError> {
        self.check()?;
        let mut camera = Camera::default_for(cloud, aspect);
        if let Some(up) = self.up.filter(|up| *up != camera.up) {
            let direction = camera.direction();
            camera.up = up;
            camera.look_from_direction(direction);
        }
        if let Some(fov) = self.fov {
            camera.fov_y_deg = fov;
        }
        if let Some(projection) = self.projection {
            camera.projection = projection;
        }
        if let Some(view) = self.view {
            camera.look_from(view);
        }
        if let Some(azimuth) = self.azimuth {
            camera.azimuth_deg = azimuth;
        }
        if let Some(elevation) = self.elevation {
            camera.elevation_deg = elevation.clamp(-90.0, 90.0);
        }
        let turned = self.up.is_some()
            || self.fov.is_some()
            || self.azimuth.is_some()
            || self.elevation.is_some()
            || self.projection.is_some()
            || self.view.is_some();
        camera.distance = match self.distance {
            Some(distance) => distance,
            // The default view is fitted already; a turned one fits again.
            None if turned => camera.fit_distance(&cloud.positions, aspect),
            None => camera.distance,
        };
        Ok(camera)
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;

    fn cloud() -> PointCloud {
        let positions = vec![Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.5), Vec3::new(0.0, 1.0, -0.5)];
        PointCloud::facing_z(positions, 0.1, [200; 3])
    }

    #[test]
    fn an_empty_request_is_the_default_view() {
        let cloud = cloud();
        assert_eq!(CameraRequest::default().camera(&cloud, 1.5).unwrap(), Camera::default_for(&cloud, 1.5));
    }

    #[test]
    fn given_values_are_taken_and_the_rest_framed() {
        let cloud = cloud();
        let asked =
            CameraRequest { azimuth: Some(30.0), elevation: Some(120.0), fov: Some(50.0), ..Default::default() };
        let camera = asked.camera(&cloud, 1.0).unwrap();
        assert_eq!((camera.azimuth_deg, camera.elevation_deg, camera.fov_y_deg), (30.0, 90.0, 50.0));
        assert_eq!(camera.distance, camera.fit_distance(&cloud.positions, 1.0));
        let far = CameraRequest { distance: Some(40.0), ..asked }.camera(&cloud, 1.0).unwrap();
        assert_eq!(far.distance, 40.0);
    }

    #[test]
    fn the_flags_lie_over_a_scene_files_camera() {
        let file = CameraRequest { azimuth: Some(10.0), fov: Some(20.0), ..Default::default() };
        let flags = CameraRequest { azimuth: Some(45.0), up: Some(UpAxis::PosZ), ..Default::default() };
        let both = flags.over(file);
        assert_eq!((both.azimuth, both.fov, both.up), (Some(45.0), Some(20.0), Some(UpAxis::PosZ)));
    }

    #[test]
    fn a_named_view_of_the_flags_replaces_a_scene_files_angles_and_an_angle_given_beside_it_wins() {
        let file = CameraRequest { azimuth: Some(30.0), elevation: Some(50.0), fov: Some(20.0), ..Default::default() };
        let top = CameraRequest { view: Some(NamedView::Top), ..Default::default() };
        let camera = top.over(file).camera(&cloud(), 1.0).unwrap();
        assert_eq!((camera.azimuth_deg, camera.elevation_deg, camera.fov_y_deg), (0.0, 90.0, 20.0));
        let turned = CameraRequest { azimuth: Some(15.0), ..top };
        let camera = turned.over(file).camera(&cloud(), 1.0).unwrap();
        assert_eq!((camera.azimuth_deg, camera.elevation_deg), (15.0, 90.0));
    }

    #[test]
    fn an_ortho_request_frames_every_point_and_a_top_view_of_z_up_data_has_north_up() {
        let mut cloud = cloud();
        cloud.z_up = true;
        let asked =
            CameraRequest { projection: Some(Projection::Ortho), view: Some(NamedView::Top), ..Default::default() };
        let camera = asked.camera(&cloud, 1.0).unwrap();
        assert!(camera.is_ortho());
        let clip = |p: Vec3| {
            let c = camera.projection(1.0) * camera.view_matrix() * p.extend(1.0);
            c.truncate() / c.w
        };
        for p in &cloud.positions {
            let ndc = clip(*p);
            assert!(ndc.x.abs() <= 1.0 && ndc.y.abs() <= 1.0 && (0.0..=1.0).contains(&ndc.z), "{p} at {ndc}");
        }
        // North (+y) is up on screen, east (+x) to the right.
        let (centre, north, east) = (clip(camera.target), clip(camera.target + Vec3::Y), clip(camera.target + Vec3::X));
        assert!(north.y > centre.y && (north.x - centre.x).abs() < 1e-4, "{north} from {centre}");
        assert!(east.x > centre.x && (east.y - centre.y).abs() < 1e-4, "{east} from {centre}");
    }

    #[test]
    fn every_value_out_of_range_is_named() {
        let cases = [
            (CameraRequest { azimuth: Some(f32::NAN), ..Default::default() }, "azimuth"),
            (CameraRequest { elevation: Some(f32::INFINITY), ..Default::default() }, "elevation"),
            (CameraRequest { distance: Some(0.0), ..Default::default() }, "distance"),
            (CameraRequest { fov: Some(171.0), ..Default::default() }, "fov"),
            (CameraRequest { fov: Some(0.4), ..Default::default() }, "fov"),
        ];
        for (request, key) in cases {
            let error = request.check().unwrap_err();
            assert_eq!(error.key, key, "{request:?}");
            assert!(request.camera(&cloud(), 1.0).is_err());
        }
        assert!(CameraRequest { fov: Some(170.0), distance: Some(1e-3), ..Default::default() }.check().is_ok());
    }
}
