//! Whether a point is inside a closed outline by the even-odd rule: a ray
//! from the point crosses its edges an odd number of times. The outline
//! closes from its last vertex back to the first; it may cross itself (a
//! lasso drawn by hand does), and what a crossing encloses twice is outside.

use glam::DVec2;

/// Whether `p` is inside the outline through `vertices` (even-odd rule).
pub fn contains(vertices: &[DVec2], p: DVec2) -> bool {
    let n = vertices.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (vertices[i], vertices[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bow_tie_holds_its_two_wings_and_not_its_outside() {
        let bow_tie = [DVec2::new(0.0, 0.0), DVec2::new(2.0, 2.0), DVec2::new(2.0, 0.0), DVec2::new(0.0, 2.0)];
        assert!(contains(&bow_tie, DVec2::new(0.2, 1.0)) && contains(&bow_tie, DVec2::new(1.8, 1.0)));
        assert!(!contains(&bow_tie, DVec2::new(1.0, 1.8)) && !contains(&bow_tie, DVec2::new(3.0, 1.0)));
        assert!(!contains(&bow_tie[..2], DVec2::new(1.0, 1.0)), "two vertices hold nothing");
    }
}
