//! Picking and measuring in the profile's panel: the section is drawn at
//! one scale (a [`SectionLayout`]: distance along the line to the right,
//! height up); a click takes the slab's point drawn nearest to it (within
//! [`PICK_REACH`] points on screen), a second click a second point, and the
//! panel gives what lies between them: the distance along the line, the
//! height difference, the slope and the length in the section's plane. A
//! third click starts again. Points are the slab's own, in file
//! coordinates, so a pick reads what the CSV export writes.

use glam::DVec3;

use super::state::{ProfileSlab, SectionLayout};

/// How far from a drawn point (points on screen) a click still takes it.
pub const PICK_REACH: f32 = 8.0;

/// The margin kept inside the section's rectangle, in points.
const MARGIN: f32 = 4.0;

impl SectionLayout {
    /// The layout that fits `slab` in `rect` at one scale.
    pub fn fitting(slab: &ProfileSlab, rect: egui::Rect) -> Self {
        let (low, high) =
            slab.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.z), hi.max(p.z)));
        let length = slab.profile.length();
        let fit_length = f64::from(rect.width() - 2.0 * MARGIN) / length;
        let scale = fit_length.min(f64::from(rect.height() - 2.0 * MARGIN) / (high - low).max(1e-9));
        Self { rect, low, scale }
    }

    /// Where the slab's point `p` (file coordinates) is drawn.
    pub fn screen(&self, slab: &ProfileSlab, p: DVec3) -> egui::Pos2 {
        let (distance, _) = slab.profile.place(p);
        let x = self.rect.left() + MARGIN + (distance * self.scale) as f32;
        let y = self.rect.bottom() - MARGIN - ((p.z - self.low) * self.scale) as f32;
        egui::pos2(x, y)
    }

    /// The slab's point drawn nearest to `at`, within [`PICK_REACH`].
    pub fn nearest(&self, slab: &ProfileSlab, at: egui::Pos2) -> Option<DVec3> {
        let distance = |p: &DVec3| self.screen(slab, *p).distance(at);
        let best = slab.points.iter().min_by(|a, b| distance(a).total_cmp(&distance(b)))?;
        (distance(best) <= PICK_REACH).then_some(*best)
    }
}

/// What lies between two picked points of the section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionMeasure {
    /// Along the line, from the first to the second.
    pub along: f64,
    /// The second's height less the first's.
    pub rise: f64,
    /// In the section's plane: √(along² + rise²).
    pub length: f64,
}

impl SectionMeasure {
    pub fn between(slab: &ProfileSlab, a: DVec3, b: DVec3) -> Self {
        let along = slab.profile.place(b).0 - slab.profile.place(a).0;
        let rise = b.z - a.z;
        Self { along, rise, length: along.hypot(rise) }
    }

    /// The slope, in per cent (none for two points at one distance along the line).
    pub fn slope_percent(&self) -> Option<f64> {
        (self.along.abs() > 0.0).then(|| 100.0 * self.rise / self.along)
    }

    /// A line for the panel, in `units`.
    pub fn text(&self, units: &str) -> String {
        let slope = self.slope_percent().map_or("vertical".to_string(), |s| format!("slope {s:+.2} %"));
        format!(
            "along {:.3} {units}, rise {:+.3} {units}, {slope}, length {:.3} {units}",
            self.along, self.rise, self.length
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::inspect::profile::Profile;
    use glam::DVec2;

    #[test]
    fn a_click_takes_the_nearest_drawn_point_and_two_give_the_rise_and_slope() {
        let profile = Profile::new(DVec2::new(100.0, 200.0), DVec2::new(110.0, 200.0), 1.0).unwrap();
        let points = vec![DVec3::new(101.0, 200.1, 5.0), DVec3::new(106.0, 199.9, 6.0), DVec3::new(109.0, 200.0, 5.5)];
        let slab = ProfileSlab { profile, colours: vec![[0; 3]; 3], points };
        let layout =
            SectionLayout::fitting(&slab, egui::Rect::from_min_size(egui::pos2(10.0, 20.0), egui::vec2(208.0, 100.0)));
        // 10 units long in 200 points: 20 points a unit; 1 unit high in 92 points.
        assert_eq!(layout.scale, 20.0);
        let drawn = layout.screen(&slab, slab.points[1]);
        assert_eq!(drawn, egui::pos2(10.0 + 4.0 + 120.0, 20.0 + 100.0 - 4.0 - 20.0));
        assert_eq!(layout.nearest(&slab, drawn + egui::vec2(3.0, -4.0)), Some(slab.points[1]));
        assert_eq!(layout.nearest(&slab, drawn + egui::vec2(0.0, PICK_REACH + 1.0)), None, "too far from every point");
        let m = SectionMeasure::between(&slab, slab.points[0], slab.points[1]);
        assert!((m.along - 5.0).abs() < 1e-12 && (m.rise - 1.0).abs() < 1e-12);
        assert!((m.slope_percent().unwrap() - 20.0).abs() < 1e-9);
        assert!((m.length - 26f64.sqrt()).abs() < 1e-12);
        assert_eq!(SectionMeasure::between(&slab, slab.points[0], slab.points[0]).slope_percent(), None);
    }
}
