//! Measuring between picked points, in f64 file coordinates: each
//! segment's length and height difference, the polyline's length, and the
//! angle at each interior vertex (between the segments that meet there).
//! Heights are along the view's up axis (z for lidar files).

use glam::DVec3;

/// One segment of the polyline through the picked points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Segment {
    /// The indices of its end points in [`Measurement::points`].
    pub from: usize,
    pub to: usize,
    pub length: f64,
    /// Height of `to` minus height of `from`.
    pub height: f64,
}

/// What the picked points measure.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    pub points: Vec<DVec3>,
    pub segments: Vec<Segment>,
    /// The polyline's length (the distance, for two points).
    pub distance: f64,
    /// The angle at each interior vertex, in degrees (none for fewer than three points).
    pub angles_deg: Vec<f64>,
    /// Height of the last point minus the first's.
    pub height: f64,
}

/// Measures the polyline through `points`; `up` is the unit up axis heights are read along.
pub fn measure(points: &[DVec3], up: DVec3) -> Measurement {
    let segments: Vec<Segment> = points
        .windows(2)
        .enumerate()
        .map(|(k, w)| Segment { from: k, to: k + 1, length: w[0].distance(w[1]), height: (w[1] - w[0]).dot(up) })
        .collect();
    let angles_deg = points
        .windows(3)
        .map(|w| {
            let (a, b) = (w[0] - w[1], w[2] - w[1]);
            let cos = a.dot(b) / (a.length() * b.length());
            // atan2 of |a×b| and a·b keeps its precision near 0° and 180°.
            if cos.is_finite() { a.cross(b).length().atan2(a.dot(b)).to_degrees() } else { f64::NAN }
        })
        .collect();
    let height = match (points.first(), points.last()) {
        (Some(a), Some(b)) => (*b - *a).dot(up),
        _ => 0.0,
    };
    Measurement {
        points: points.to_vec(),
        distance: segments.iter().map(|s| s.length).sum(),
        segments,
        angles_deg,
        height,
    }
}

impl Measurement {
    /// The segments as CSV (a header, then one row per segment): what the viewer copies.
    pub fn csv(&self) -> String {
        let mut out = String::from("from,to,x0,y0,z0,x1,y1,z1,length,height\n");
        for s in &self.segments {
            let (a, b) = (self.points[s.from], self.points[s.to]);
            out.push_str(&format!(
                "{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}\n",
                s.from + 1,
                s.to + 1,
                a.x,
                a.y,
                a.z,
                b.x,
                b.y,
                b.z,
                s.length,
                s.height
            ));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_right_angle_of_sides_three_and_four() {
        let m = measure(&[DVec3::new(3.0, 0.0, 0.0), DVec3::ZERO, DVec3::new(0.0, 4.0, 0.0)], DVec3::Y);
        assert_eq!(m.distance, 7.0);
        assert!((m.angles_deg[0] - 90.0).abs() < 1e-12);
        assert_eq!(m.height, 4.0);
        assert_eq!(m.segments[1].height, 4.0);
        assert_eq!(m.csv().lines().count(), 3);
    }
}
