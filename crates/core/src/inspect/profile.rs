//! Profiles (cross-sections): the slab of points within W/2 of a line
//! drawn on the ground, between its ends, in f64 file coordinates (the
//! CRS's units). A point's place in the profile is its distance along the
//! line from the start and its signed offset from it (positive to the
//! left, walking from start to end). The same slab is four clip planes
//! ([`Profile::planes`]), which is how `profile --out` draws it: in
//! orthographic, from the right of the line, the start on the left.

use glam::{DVec2, DVec3};

/// A line on the ground and the width of the slab around it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Profile {
    pub start: DVec2,
    pub end: DVec2,
    pub width: f64,
}

/// `X1,Y1,X2,Y2`: a line's ends.
pub fn parse_line(text: &str) -> Result<(DVec2, DVec2), String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}' is not a line X1,Y1,X2,Y2 (four numbers, file coordinates)"))?;
    match values[..] {
        [x1, y1, x2, y2] if values.iter().all(|v| v.is_finite()) => Ok((DVec2::new(x1, y1), DVec2::new(x2, y2))),
        _ => Err(format!("'{text}' is not a line X1,Y1,X2,Y2 (four finite numbers, file coordinates)")),
    }
}

impl Profile {
    /// A profile, or why not: the ends must differ and the width be positive.
    pub fn new(start: DVec2, end: DVec2, width: f64) -> Result<Profile, String> {
        if !(width.is_finite() && width > 0.0) {
            return Err(format!("the slab's width must be a positive number, not {width}"));
        }
        if start.distance(end) == 0.0 {
            return Err(format!("the line's ends are the same point ({}, {})", start.x, start.y));
        }
        Ok(Profile { start, end, width })
    }

    pub fn length(&self) -> f64 {
        self.start.distance(self.end)
    }

    /// The unit direction from start to end, and its left normal.
    pub fn axes(&self) -> (DVec2, DVec2) {
        let along = (self.end - self.start).normalize();
        (along, along.perp())
    }

    /// `(distance along, offset)` of a point, whether in the slab or not.
    pub fn place(&self, p: DVec3) -> (f64, f64) {
        let (along, left) = self.axes();
        let d = p.truncate() - self.start;
        (d.dot(along), d.dot(left))
    }

    /// Whether the point lies in the slab: at most W/2 from the line, and
    /// between its ends (both edges kept).
    /// The slab grown by `margin` on every side (wider, and past both
    /// ends): the points around it whose neighbours size its splats.
    pub fn widened(&self, margin: f64) -> Profile {
        let (along, _) = self.axes();
        Profile { start: self.start - along * margin, end: self.end + along * margin, width: self.width + 2.0 * margin }
    }

    pub fn holds(&self, p: DVec3) -> bool {
        let (t, offset) = self.place(p);
        offset.abs() <= self.width * 0.5 && (0.0..=self.length()).contains(&t)
    }

    /// The indices of `positions` in the slab, ascending.
    pub fn slab(&self, positions: &[DVec3]) -> Vec<u32> {
        (0..positions.len() as u32).filter(|&i| self.holds(positions[i as usize])).collect()
    }

    /// The slab as clip planes `[nx, ny, nz, d]`, each keeping n·x + d >= 0
    /// (file coordinates): the two sides, the start and the end.
    pub fn planes(&self) -> [[f64; 4]; 4] {
        let (along, left) = self.axes();
        let half = self.width * 0.5;
        let (a, l) = (self.start.dot(along), self.start.dot(left));
        [
            [-left.x, -left.y, 0.0, l + half],
            [left.x, left.y, 0.0, half - l],
            [along.x, along.y, 0.0, -a],
            [-along.x, -along.y, 0.0, a + self.length()],
        ]
    }

    /// The horizontal direction the side view looks from: the right of the
    /// line, so the start is on the image's left and the end on its right.
    pub fn side(&self) -> DVec3 {
        let (_, left) = self.axes();
        (-left).extend(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slab_and_its_planes_keep_the_same_points() {
        let profile =
            Profile::new(DVec2::new(500_000.0, 4_000_000.0), DVec2::new(500_030.0, 4_000_040.0), 2.0).unwrap();
        assert_eq!(profile.length(), 50.0);
        let mut inside = 0;
        for i in 0..4000 {
            let (u, v) = ((i % 80) as f64 * 0.8 - 5.0, (i / 80) as f64 * 0.1 - 2.5);
            let (along, left) = profile.axes();
            let p = (profile.start + along * u + left * v).extend(7.0);
            let by_planes = profile.planes().iter().all(|q| q[0] * p.x + q[1] * p.y + q[2] * p.z + q[3] >= -1e-6);
            let clear = v.abs() <= 0.999 && (0.001..=49.999).contains(&u);
            let outside = v.abs() >= 1.001 || !(-0.001..=50.001).contains(&u);
            if clear || outside {
                assert_eq!(profile.holds(p), clear, "u {u}, v {v}");
                assert_eq!(by_planes, clear, "planes, u {u}, v {v}");
            }
            inside += usize::from(profile.holds(p));
        }
        assert!(inside > 1000);
        assert!(Profile::new(DVec2::ZERO, DVec2::ZERO, 1.0).is_err());
        assert!(Profile::new(DVec2::ZERO, DVec2::X, 0.0).is_err());
        assert!(parse_line("1,2,3").is_err() && parse_line("1,2,3,nan").is_err());
        assert_eq!(parse_line(" 1, 2,3,4").unwrap(), (DVec2::new(1.0, 2.0), DVec2::new(3.0, 4.0)));
    }

    #[test]
    fn the_widened_slab_holds_the_points_around_the_slab() {
        let profile = Profile::new(DVec2::new(10.0, 0.0), DVec2::new(20.0, 0.0), 2.0).unwrap();
        let around = profile.widened(1.0);
        // Beside the slab, and past either end, by less than the margin.
        for (x, y) in [(15.0, 1.9), (15.0, -1.9), (9.2, 0.0), (20.8, 0.5)] {
            let p = DVec3::new(x, y, 3.0);
            assert!(!profile.holds(p) && around.holds(p), "{p}");
        }
        for (x, y) in [(15.0, 2.1), (8.9, 0.0), (21.1, 0.0)] {
            assert!(!around.holds(DVec3::new(x, y, 3.0)), "{x},{y}");
        }
        assert!(around.holds(DVec3::new(15.0, 0.0, -100.0)));
    }
}
