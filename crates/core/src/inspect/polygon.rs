//! A polygon drawn on the ground, in f64 file coordinates (the CRS's
//! units): `"X1,Y1 X2,Y2 X3,Y3 ..."`, closed from the last vertex back to
//! the first. Its area is the shoelace formula about its first vertex (so
//! coordinates far from the origin lose nothing to cancellation); a point
//! is inside by the even-odd rule.

use glam::DVec2;

#[derive(Debug, Clone, PartialEq)]
pub struct Polygon {
    pub vertices: Vec<DVec2>,
}

impl std::str::FromStr for Polygon {
    type Err = String;

    fn from_str(text: &str) -> Result<Polygon, String> {
        let bad = |why: &str| format!("'{text}' is not a polygon \"X1,Y1 X2,Y2 X3,Y3 ...\": {why}");
        let mut vertices = Vec::new();
        for pair in text.split_whitespace() {
            let (x, y) = pair.split_once(',').ok_or_else(|| bad(&format!("'{pair}' is not X,Y")))?;
            let (x, y) = (x.parse::<f64>(), y.parse::<f64>());
            match (x, y) {
                (Ok(x), Ok(y)) if x.is_finite() && y.is_finite() => vertices.push(DVec2::new(x, y)),
                _ => return Err(bad(&format!("'{pair}' is not two finite numbers"))),
            }
        }
        if vertices.len() > 1 && vertices.first() == vertices.last() {
            vertices.pop();
        }
        if vertices.len() < 3 {
            return Err(bad("it needs at least three vertices"));
        }
        let polygon = Polygon { vertices };
        if polygon.area() == 0.0 {
            return Err(bad("its area is zero"));
        }
        Ok(polygon)
    }
}

impl Polygon {
    /// Its edges, each from one vertex to the next.
    pub fn edges(&self) -> impl Iterator<Item = (DVec2, DVec2)> + '_ {
        let n = self.vertices.len();
        (0..n).map(move |i| (self.vertices[i], self.vertices[(i + 1) % n]))
    }

    /// The horizontal area it encloses (unsigned).
    pub fn area(&self) -> f64 {
        let first = self.vertices[0];
        let twice: f64 = self.edges().map(|(a, b)| (a - first).perp_dot(b - first)).sum();
        twice.abs() * 0.5
    }

    /// Whether `p` is inside (even-odd rule).
    pub fn contains(&self, p: DVec2) -> bool {
        crate::spatial::even_odd::contains(&self.vertices, p)
    }

    /// The distance from `p` to the nearest edge.
    pub fn distance_to_border(&self, p: DVec2) -> f64 {
        self.edges()
            .map(|(a, b)| {
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                p.distance(a + ab * t)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Its bounding box's corners.
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let min = self.vertices.iter().fold(DVec2::splat(f64::INFINITY), |m, v| m.min(*v));
        let max = self.vertices.iter().fold(DVec2::splat(f64::NEG_INFINITY), |m, v| m.max(*v));
        (min, max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_polygon_reads_its_text_and_knows_its_area_and_inside() {
        let square: Polygon = "500000,4000000 500010,4000000 500010,4000010 500000,4000010".parse().unwrap();
        assert_eq!(square.area(), 100.0);
        assert!(square.contains(DVec2::new(500_005.0, 4_000_005.0)));
        assert!(!square.contains(DVec2::new(500_011.0, 4_000_005.0)));
        assert_eq!(square.distance_to_border(DVec2::new(500_002.0, 4_000_005.0)), 2.0);
        let closed: Polygon = "0,0 4,0 0,3 0,0".parse().unwrap();
        assert_eq!((closed.vertices.len(), closed.area()), (3, 6.0));
        for bad in ["0,0 1,1", "0,0 1,0 2,0", "0,0 1,x 2,2", "0,0 1 2,2", "0,0 1,inf 2,2"] {
            assert!(bad.parse::<Polygon>().is_err(), "{bad}");
        }
    }
}
