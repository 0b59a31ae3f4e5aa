//! Screen regions: what a selection drawn on the screen holds, kept or
//! hidden. A region is a shape in normalised device coordinates (a box's
//! four corners or a lasso's outline) and the camera it was drawn through;
//! it holds every point in front of that camera whose place on screen falls
//! inside the shape (by the even-odd rule, [`crate::spatial::even_odd`]),
//! at any depth: a prism
//! through the scene in orthographic, a cone from the eye in perspective, as
//! a segmentation tool cuts. It is part of the [`super::Style`], beside the
//! attribute filters, so the view, every mode, the reference, the viewer's
//! tools, exports and a sidecar's `render --camera` drop the same points.
//! It is tested in f64 on file coordinates, so a point keeps its side of the
//! outline whatever frame the scene is drawn in.

use glam::{DMat4, DVec2, DVec3};
use serde::{Deserialize, Serialize};

/// A shape on screen through a camera, and whether its inside is kept or hidden.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// Frame coordinates to clip space: the camera's projection × view, column by column.
    pub view_projection: [f64; 16],
    /// The frame the camera looked at: frame = (file − origin) / unit.
    pub origin: [f64; 3],
    pub unit: f64,
    /// The shape, in normalised device coordinates (x right, y up, −1..1); three vertices or more.
    pub outline: Vec<[f64; 2]>,
    /// Whether the inside is kept (the rest hidden), else hidden.
    pub keep: bool,
}

impl Region {
    /// Whether the point at `file` (file coordinates) is in front of the
    /// camera and inside the shape on screen.
    pub fn holds(&self, file: DVec3) -> bool {
        let frame = (file - DVec3::from(self.origin)) / self.unit;
        let clip = DMat4::from_cols_array(&self.view_projection) * frame.extend(1.0);
        if clip.w <= 0.0 || !clip.is_finite() {
            return false;
        }
        let outline: Vec<DVec2> = self.outline.iter().map(|v| DVec2::from(*v)).collect();
        crate::spatial::even_odd::contains(&outline, DVec2::new(clip.x / clip.w, clip.y / clip.w))
    }

    /// Whether the point at `file` is shown: held and kept, or not held and hidden.
    pub fn shows(&self, file: DVec3) -> bool {
        self.holds(file) == self.keep
    }

    /// Whether the region is usable: a finite camera, a positive unit and three vertices or more.
    pub fn check(&self) -> Result<(), String> {
        let finite = self.view_projection.iter().chain(&self.origin).all(|v| v.is_finite());
        if !finite || self.unit.is_nan() || self.unit <= 0.0 {
            return Err("a selection's camera is not finite".into());
        }
        if self.outline.len() < 3 || self.outline.iter().flatten().any(|v| !v.is_finite()) {
            return Err("a selection's outline needs three finite vertices or more".into());
        }
        Ok(())
    }
}

/// The indices of `0..n` whose file position (`position(i)`) every region shows.
pub fn shown_by(regions: &[Region], kept: Vec<u32>, position: impl Fn(usize) -> DVec3) -> Vec<u32> {
    if regions.is_empty() {
        return kept;
    }
    kept.into_iter().filter(|&i| regions.iter().all(|r| r.shows(position(i as usize)))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Looking down −z from above in orthographic over −10..10: NDC = file / 10.
    fn top_view(outline: Vec<[f64; 2]>, keep: bool) -> Region {
        let projection = glam::dcamera::rh::proj::directx::orthographic(-10.0, 10.0, -10.0, 10.0, 0.1, 100.0);
        let view = glam::dcamera::rh::view::look_at_mat4(DVec3::new(0.0, 0.0, 50.0), DVec3::ZERO, DVec3::Y);
        Region {
            view_projection: (projection * view).to_cols_array(),
            origin: [1000.0, 2000.0, 0.0],
            unit: 1.0,
            outline,
            keep,
        }
    }

    #[test]
    fn a_lasso_holds_what_its_outline_covers_at_any_depth() {
        // An L: the square 0..0.5 × 0..0.5 (NDC) less its upper right quarter.
        let l = vec![[0.0, 0.0], [0.5, 0.0], [0.5, 0.25], [0.25, 0.25], [0.25, 0.5], [0.0, 0.5]];
        let region = top_view(l, true);
        let at = |x: f64, y: f64, z: f64| DVec3::new(1000.0 + x, 2000.0 + y, z);
        assert!(region.holds(at(1.0, 1.0, 0.0)));
        assert!(region.holds(at(1.0, 1.0, -500.0)), "beyond the far plane: still in the prism");
        assert!(region.holds(at(4.0, 1.0, 3.0)));
        assert!(!region.holds(at(4.0, 4.0, 0.0)), "the L's missing quarter");
        assert!(!region.holds(at(-1.0, 1.0, 0.0)));
        let hidden = Region { keep: false, ..region.clone() };
        assert!(!hidden.shows(at(1.0, 1.0, 0.0)) && hidden.shows(at(4.0, 4.0, 0.0)));
        let kept = shown_by(&[region], vec![0, 1, 2], |i| at([1.0, 4.0, 1.0][i], [1.0, 4.0, 4.0][i], 0.0));
        assert_eq!(kept, vec![0, 2]);
    }

    #[test]
    fn a_region_behind_the_eye_holds_nothing() {
        let projection = glam::dcamera::rh::proj::directx::perspective(1.0, 1.0, 0.1, 100.0);
        let view = glam::dcamera::rh::view::look_at_mat4(DVec3::ZERO, DVec3::NEG_Z, DVec3::Y);
        let square = vec![[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        let view_projection = (projection * view).to_cols_array();
        let region = Region { view_projection, origin: [0.0; 3], unit: 1.0, outline: square, keep: true };
        assert!(region.holds(DVec3::new(0.0, 0.0, -5.0)));
        assert!(!region.holds(DVec3::new(0.0, 0.0, 5.0)));
        assert!(region.check().is_ok());
        assert!(Region { outline: vec![[0.0, 0.0]; 2], ..region.clone() }.check().is_err());
        assert!(Region { unit: 0.0, ..region }.check().is_err());
    }
}
