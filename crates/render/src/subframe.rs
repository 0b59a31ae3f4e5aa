//! A frame drawn a sub-frame at a time: the sub-frame of a `width`×`height`
//! frame that one render covers, and the camera terms that make that render
//! the sub-frame's pixels of the whole frame exactly.
//!
//! The sub-frame's projection is the frame's, followed by the map of the
//! sub-frame's part of the frame's NDC square onto the whole square (an
//! off-axis frustum), and the pixel rays of `frame.wgsl` (`pixel_ray`) are
//! the sub-frame's NDC times its half extent at view depth 1 (`lens.xy`) plus
//! its centre there (`window.xy`). Everything measured in pixels (the EWA
//! low-pass radius, `--min-pixel-radius`, a splat's screen length) keeps the
//! frame's pixel size, so a sub-frame is drawn as the frame would draw it.
//!
//! [`tiles`] cuts a frame whose targets would pass the GPU's limits or the
//! memory a frame may take into sub-frames, each with a margin wide enough for
//! the passes that read neighbouring pixels (eye-dome lighting's radius, the
//! prefilter's coverage level).

use glam::{Mat4, Vec2, Vec4};

use crate::frame::Camera;

/// Pixels each sub-frame reaches past the part it keeps, for the passes that
/// read neighbours: eye-dome lighting (up to 16 px), the coverage level (2 px).
pub const MARGIN: u32 = 32;

/// The margin the sub-frames of a frame whose plan is `plan` are drawn
/// with: [`MARGIN`], or none for `tiled` (a plan of compute passes), whose
/// every pixel is computed from its own ray and reads no neighbour.
pub fn margin(plan: &crate::plan::RenderPlan) -> u32 {
    if plan.compute_passes() > 0 { 0 } else { MARGIN }
}

/// The least side of a sub-frame worth drawing (margins included): it keeps
/// half its pixels' width.
pub const MIN_SIDE: u32 = 4 * MARGIN;

/// The part of a frame one render covers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubFrame {
    /// The whole frame's size.
    pub frame: (u32, u32),
    /// The sub-frame's top-left pixel in the frame.
    pub origin: (u32, u32),
    /// The sub-frame's size.
    pub size: (u32, u32),
}

impl SubFrame {
    /// The whole frame.
    pub fn whole(size: (u32, u32)) -> Self {
        SubFrame { frame: size, origin: (0, 0), size }
    }

    pub fn is_whole(&self) -> bool {
        self.size == self.frame
    }

    /// The sub-frame's share of the frame's NDC square: its centre and half extent there.
    fn ndc(&self) -> (Vec2, Vec2) {
        let frame = Vec2::new(self.frame.0 as f32, self.frame.1 as f32);
        let origin = Vec2::new(self.origin.0 as f32, self.origin.1 as f32);
        let size = Vec2::new(self.size.0 as f32, self.size.1 as f32);
        let centre = (origin + size * 0.5) / frame * 2.0 - Vec2::ONE;
        // NDC y points up, pixel rows down.
        (Vec2::new(centre.x, -centre.y), size / frame)
    }

    /// The sub-frame's projection: the frame's, then the sub-frame's part of NDC onto the whole.
    pub fn projection(&self, camera: &Camera) -> Mat4 {
        let whole = camera.projection(self.frame.0 as f32 / self.frame.1 as f32);
        if self.is_whole() {
            return whole;
        }
        let (centre, scale) = self.ndc();
        let onto = Mat4::from_cols(
            Vec4::new(1.0 / scale.x, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 1.0 / scale.y, 0.0, 0.0),
            Vec4::Z,
            Vec4::new(-centre.x / scale.x, -centre.y / scale.y, 0.0, 1.0),
        );
        onto * whole
    }

    /// The sub-frame's half extent (x, y) and centre (x, y) at view depth 1, in eye space
    /// (in eye units when orthographic: `Camera::lens`).
    pub fn lens(&self, camera: &Camera) -> (Vec2, Vec2) {
        let whole = camera.lens(self.frame.0 as f32 / self.frame.1 as f32);
        let (centre, scale) = self.ndc();
        (whole * scale, whole * centre)
    }

    /// The sub-frame grown by `margin` on every side, within the frame.
    pub fn grown(&self, margin: u32) -> Self {
        let x0 = self.origin.0.saturating_sub(margin);
        let y0 = self.origin.1.saturating_sub(margin);
        let x1 = (self.origin.0 + self.size.0 + margin).min(self.frame.0);
        let y1 = (self.origin.1 + self.size.1 + margin).min(self.frame.1);
        SubFrame { frame: self.frame, origin: (x0, y0), size: (x1 - x0, y1 - y0) }
    }
}

/// The sub-frames a `frame`-sized frame is drawn in when a sub-frame may have at
/// most `max_pixels` pixels and `max_side` a side (margins included): the
/// whole frame when it fits, else a grid of kept parts, row by row, each to
/// be drawn grown by [`MARGIN`].
pub fn tiles(frame: (u32, u32), max_pixels: u64, max_side: u32) -> Vec<SubFrame> {
    let fits = frame.0 <= max_side && frame.1 <= max_side && frame.0 as u64 * frame.1 as u64 <= max_pixels;
    if fits {
        return vec![SubFrame::whole(frame)];
    }
    // The kept part of a square sub-frame that fits, margins included.
    let side = ((max_pixels as f64).sqrt() as u32).min(max_side);
    let kept = side.saturating_sub(2 * MARGIN).max(MARGIN);
    let mut windows = Vec::new();
    for y in (0..frame.1).step_by(kept as usize) {
        for x in (0..frame.0).step_by(kept as usize) {
            let size = (kept.min(frame.0 - x), kept.min(frame.1 - y));
            windows.push(SubFrame { frame, origin: (x, y), size });
        }
    }
    windows
}

/// Least side of a part [`split`] makes, in pixels: one tile of `tiled`.
pub const MIN_PART_SIDE: u32 = 8;

/// `kept` cut into a grid of at least `over` × 1.25 parts (two at least),
/// as square as the part's shape allows, for a `tiled` frame whose splats
/// or lists passed the memory given to it `over` times over (the quarter
/// more: splats do not spread evenly over a frame). `None` when the part
/// is too small to cut ([`MIN_PART_SIDE`]).
pub fn split(kept: SubFrame, over: f64) -> Option<Vec<SubFrame>> {
    let (width, height) = kept.size;
    let most = ((width / MIN_PART_SIDE).max(1), (height / MIN_PART_SIDE).max(1));
    if most.0 * most.1 < 2 {
        return None;
    }
    let wanted = (over * 1.25).ceil().clamp(2.0, (most.0 * most.1) as f64) as u32;
    let columns = ((wanted as f64 * width as f64 / height as f64).sqrt().round() as u32).clamp(1, most.0);
    let rows = wanted.div_ceil(columns).clamp(1, most.1);
    let columns = wanted.div_ceil(rows).clamp(1, most.0);
    let mut parts = Vec::new();
    for row in 0..rows {
        let (y0, y1) = (height * row / rows, height * (row + 1) / rows);
        for column in 0..columns {
            let (x0, x1) = (width * column / columns, width * (column + 1) / columns);
            let origin = (kept.origin.0 + x0, kept.origin.1 + y0);
            parts.push(SubFrame { frame: kept.frame, origin, size: (x1 - x0, y1 - y0) });
        }
    }
    Some(parts)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn camera() -> Camera {
        Camera {
            target: Vec3::new(0.1, -0.2, 0.0),
            distance: 3.0,
            azimuth_deg: 20.0,
            elevation_deg: 10.0,
            fov_y_deg: 40.0,
            up: crate::frame::UpAxis::PosY,
            scene_radius: 1.0,
            projection: Default::default(),
        }
    }

    /// The NDC the whole frame's projection gives a point, in the sub-frame's pixels.
    fn pixel_in(window: &SubFrame, p: Vec3) -> Vec2 {
        let camera = camera();
        let clip = window.projection(&camera) * camera.view_matrix() * p.extend(1.0);
        let ndc = Vec2::new(clip.x, clip.y) / clip.w;
        let size = Vec2::new(window.size.0 as f32, window.size.1 as f32);
        Vec2::new((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y)
    }

    #[test]
    fn a_point_lands_on_the_same_frame_pixel_in_the_whole_frame_and_in_a_window() {
        let whole = SubFrame::whole((640, 480));
        let window = SubFrame { frame: (640, 480), origin: (200, 100), size: (150, 90) };
        for p in [Vec3::new(0.1, 0.2, 0.0), Vec3::new(-0.3, 0.05, 0.2), Vec3::new(0.25, -0.1, -0.1)] {
            let in_frame = pixel_in(&whole, p);
            let in_window = pixel_in(&window, p) + Vec2::new(200.0, 100.0);
            assert!((in_frame - in_window).length() < 1e-3, "{p}: {in_frame} ≠ {in_window}");
        }
    }

    #[test]
    fn a_windows_pixel_rays_are_the_frames() {
        let camera = camera();
        let whole = SubFrame::whole((640, 480));
        let window = SubFrame { frame: (640, 480), origin: (200, 100), size: (150, 90) };
        // pixel_ray (frame.wgsl): ndc · lens + centre, at a pixel's centre.
        let ray = |w: &SubFrame, (x, y): (f32, f32)| {
            let (half, centre) = w.lens(&camera);
            let ndc = Vec2::new((x + 0.5) / w.size.0 as f32 * 2.0 - 1.0, 1.0 - (y + 0.5) / w.size.1 as f32 * 2.0);
            ndc * half + centre
        };
        for (x, y) in [(0.0, 0.0), (17.0, 42.0), (149.0, 89.0)] {
            let a = ray(&whole, (x + 200.0, y + 100.0));
            let b = ray(&window, (x, y));
            assert!((a - b).length() < 1e-5, "({x}, {y}): {a} ≠ {b}");
        }
    }

    #[test]
    fn tiles_cover_the_frame_once_and_fit_with_their_margins() {
        assert_eq!(tiles((800, 600), 1 << 20, 4096), vec![SubFrame::whole((800, 600))]);
        for (frame, max_pixels, max_side) in [((8192, 8192), 1u64 << 24, 16384), ((5000, 300), 1 << 16, 4096)] {
            let windows = tiles(frame, max_pixels, max_side);
            let mut covered = vec![0u8; (frame.0 * frame.1) as usize];
            for w in &windows {
                let grown = w.grown(MARGIN);
                assert!(grown.size.0 as u64 * grown.size.1 as u64 <= max_pixels, "{grown:?}");
                assert!(grown.size.0 <= max_side && grown.size.1 <= max_side);
                for y in w.origin.1..w.origin.1 + w.size.1 {
                    for x in w.origin.0..w.origin.0 + w.size.0 {
                        covered[(y * frame.0 + x) as usize] += 1;
                    }
                }
            }
            assert!(covered.iter().all(|c| *c == 1), "{frame:?}: a pixel is kept twice or never");
        }
    }

    #[test]
    fn a_split_part_is_covered_once_by_parts_no_smaller_than_a_tile() {
        let kept = SubFrame { frame: (500, 300), origin: (40, 20), size: (300, 170) };
        for over in [1.0, 1.7, 3.0, 10.0, 1e6] {
            let parts = split(kept, over).unwrap();
            assert!(parts.len() as f64 >= (over * 1.25).clamp(2.0, 37.0 * 21.0), "{over}: {}", parts.len());
            let mut covered = vec![0u8; 500 * 300];
            for p in &parts {
                assert!(p.size.0 >= MIN_PART_SIDE && p.size.1 >= MIN_PART_SIDE, "{p:?}");
                for y in p.origin.1..p.origin.1 + p.size.1 {
                    for x in p.origin.0..p.origin.0 + p.size.0 {
                        covered[(y * 500 + x) as usize] += 1;
                    }
                }
            }
            for y in 0..300 {
                for x in 0..500 {
                    let inside = (40..340).contains(&x) && (20..190).contains(&y);
                    assert_eq!(covered[(y * 500 + x) as usize], inside as u8, "{over}: ({x}, {y})");
                }
            }
        }
        assert!(split(SubFrame { frame: (20, 20), origin: (0, 0), size: (12, 15) }, 4.0).is_none());
    }
}
