//! A profile's section drawn from the side: the slab of a
//! [`Profile`] seen in orthographic from the right of its line, level
//! (distance along the line against height, at one scale), clipped to the
//! slab by its four planes, in any mode. Every splat is turned to face the
//! viewer first: a section is read point by point, and level ground seen
//! edge-on would vanish. `profile --out` and the viewer's profile panel
//! ("export PNG…") both draw it here.

use std::sync::Arc;

use glam::{DVec2, DVec3};
use pointblend_core::frame::{Camera, ClipRegion, Projection, RenderSettings, UpAxis, View};
use pointblend_core::inspect::profile::Profile;
use pointblend_core::scene::Scene;

use crate::{Frame, GpuRenderer, PreparedScene, Readback};

/// What went wrong drawing a section.
#[derive(Debug, thiserror::Error)]
pub enum SectionError {
    #[error("{0} (the profile's slab takes four of the six planes)")]
    Clip(String),
    #[error("opening the GPU: {0}")]
    Gpu(#[from] crate::GpuError),
    #[error(transparent)]
    Frame(#[from] crate::FrameError),
}

/// Turns every splat of `scene` to face the side the section is seen from.
pub fn face_the_side(scene: &mut Scene, profile: &Profile) {
    let side = profile.side().as_vec3();
    for object in &mut scene.objects {
        let facing = object.transform.inverse().transform_vector3(side).normalize();
        Arc::make_mut(&mut object.cloud).normals.iter_mut().for_each(|n| *n = facing);
        // And the cloud a style is applied to again (a file without colours is styled on loading).
        if let Some(styled) = &mut object.styled {
            Arc::make_mut(&mut styled.source).normals.iter_mut().for_each(|n| *n = facing);
        }
    }
}

/// Draws the section of `scene` (its splats already facing the side) at
/// `size` in `settings`' mode, clipped by `region` and the slab's planes,
/// framing the slab's length and its heights `low..high` (file units): the
/// image and the mode that ran.
pub fn draw(
    scene: Scene,
    profile: &Profile,
    (low, high): (f64, f64),
    mut settings: RenderSettings,
    mut region: ClipRegion,
    (width, height): (u32, u32),
) -> Result<(image::RgbaImage, String), SectionError> {
    region.planes.extend(profile.planes());
    region.check().map_err(|e| SectionError::Clip(e.to_string()))?;
    settings.clip = scene.clip_in_frame(&region);
    let camera = side_camera(profile, (low, high), scene.frame_placement(), width as f32 / height as f32);
    let mut gpu = match settings.mode.is_gpu() {
        true => Some(GpuRenderer::new()?),
        false => None,
    };
    let mut frames = PreparedScene::of(Arc::new(scene));
    let spec = frames.resolve(&settings, View::still((width, height)));
    let Frame { image, plan, .. } = frames.render_frame(gpu.as_mut(), &camera, &spec, Readback::ImageWithProgress)?;
    Ok((image, plan.mode.to_string()))
}

/// An orthographic camera from the right of the line, level, framing the
/// slab's length and its heights `low..high`, in the scene's frame.
pub fn side_camera(profile: &Profile, (low, high): (f64, f64), (origin, unit): (DVec3, f64), aspect: f32) -> Camera {
    let middle = ((profile.start + profile.end) * 0.5).extend((low + high) * 0.5);
    let half_length = profile.length() * 0.5;
    let half_height = ((high - low) * 0.5).max(profile.width * 0.5);
    let mut camera = Camera {
        target: ((middle - origin) / unit).as_vec3(),
        distance: 1.0,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        fov_y_deg: pointblend_core::frame::camera::DEFAULT_FOV_DEG,
        up: UpAxis::PosZ,
        scene_radius: (DVec2::new(half_length, half_height).length().max(profile.width) / unit) as f32,
        projection: Projection::Ortho,
    };
    camera.look_from_direction(profile.side().as_vec3());
    // In orthographic the window's half height is tan(fov / 2) · distance.
    let needed = (half_height.max(half_length / aspect as f64) * 1.05 / unit) as f32;
    camera.distance = needed / (camera.fov_y_deg.to_radians() * 0.5).tan();
    camera
}
