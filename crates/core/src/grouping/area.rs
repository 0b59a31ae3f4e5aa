//! Overlap areas of two splat discs.
//!
//! A_ij of Eq. 8 is the part of disc i lying (within ε) over disc j. We use
//! the exact intersection area of the two discs in i's tangent plane: disc j
//! is projected onto that plane along i's normal, and the lens area of two
//! circles with radii r_i, r_j at the projected centre distance is taken.
//! For the nearly coplanar neighbours that overlap on a surface this equals
//! Eq. 8's region; `tests` compare it with a Monte-Carlo estimate of Eq. 8.

use std::f32::consts::PI;

use glam::Vec3;

/// Area of the intersection of two circles of radii `r0`, `r1` whose centres are `d` apart.
pub fn lens_area(r0: f32, r1: f32, d: f32) -> f32 {
    if !(r0 > 0.0 && r1 > 0.0) || d >= r0 + r1 {
        return 0.0;
    }
    let (small, large) = if r0 < r1 { (r0, r1) } else { (r1, r0) };
    if d <= large - small {
        return PI * small * small;
    }
    let d = d.max(1e-12);
    let a0 = ((d * d + r0 * r0 - r1 * r1) / (2.0 * d * r0)).clamp(-1.0, 1.0).acos();
    let a1 = ((d * d + r1 * r1 - r0 * r0) / (2.0 * d * r1)).clamp(-1.0, 1.0).acos();
    let kite = 0.5 * ((-d + r0 + r1) * (d + r0 - r1) * (d - r0 + r1) * (d + r0 + r1)).max(0.0).sqrt();
    (r0 * r0 * a0 + r1 * r1 * a1 - kite).max(0.0)
}

/// A_ij: the area of disc i (centre `pi`, normal `ni`, radius `ri`) covered by
/// disc j, measured in i's tangent plane.
pub fn covered_area(pi: Vec3, ni: Vec3, ri: f32, pj: Vec3, rj: f32) -> f32 {
    let offset = pj - pi;
    let tangential = offset - ni * ni.dot(offset);
    lens_area(ri, rj, tangential.length())
}

/// Eq. 7: w_ij = (A_ij + A_ji)·(1 - n_i·n_j), or the plain area sum when
/// `pure_area` is set.
pub fn overlap_weight(pi: Vec3, ni: Vec3, ri: f32, pj: Vec3, nj: Vec3, rj: f32, pure_area: bool) -> f32 {
    let area = covered_area(pi, ni, ri, pj, rj) + covered_area(pj, nj, rj, pi, ri);
    if pure_area { area } else { area * (1.0 - ni.dot(nj)).max(0.0) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator for sampling.
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (self.0 >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    /// Monte-Carlo estimate of Eq. 8's region: points x of disc i whose
    /// distance to j's plane is below ε and whose projection lies within r_j.
    fn monte_carlo(pi: Vec3, ni: Vec3, ri: f32, pj: Vec3, nj: Vec3, rj: f32, eps: f32) -> f32 {
        let (u, v) = ni.any_orthonormal_pair();
        let mut rng = Lcg(7);
        let samples = 200_000;
        let mut hits = 0;
        for _ in 0..samples {
            let (a, b) = (rng.next() * 2.0 - 1.0, rng.next() * 2.0 - 1.0);
            if a * a + b * b > 1.0 {
                continue;
            }
            let x = pi + (u * a + v * b) * ri;
            let d1 = (x - pj).dot(nj);
            let d2 = ((x - nj * d1) - pj).length();
            if d1.abs() < eps && d2 < rj {
                hits += 1;
            }
        }
        // The square [-1,1]^2 has area 4 ri^2.
        hits as f32 / samples as f32 * 4.0 * ri * ri
    }

    #[test]
    fn lens_area_has_the_right_limits() {
        assert_eq!(lens_area(1.0, 1.0, 2.0), 0.0);
        assert!((lens_area(1.0, 2.0, 0.5) - PI).abs() < 1e-5);
        assert!((lens_area(1.0, 1.0, 0.0) - PI).abs() < 1e-4);
        // Two unit circles one radius apart: 2π/3 - √3/2.
        let want = 2.0 * PI / 3.0 - 3f32.sqrt() / 2.0;
        assert!((lens_area(1.0, 1.0, 1.0) - want).abs() < 1e-5);
    }

    #[test]
    fn the_tangent_plane_area_matches_a_monte_carlo_estimate_of_eq_8() {
        let n = Vec3::new(0.1, 0.2, 1.0).normalize();
        let cases = [
            (Vec3::ZERO, n, 1.0, Vec3::new(0.8, 0.3, -0.1), n, 1.2),
            (Vec3::ZERO, n, 1.0, Vec3::new(1.5, 0.0, -0.15), Vec3::new(0.0, 0.3, 1.0).normalize(), 0.9),
            (Vec3::ZERO, Vec3::Z, 0.5, Vec3::new(0.2, 0.1, 0.0), Vec3::Z, 0.3),
        ];
        for (pi, ni, ri, pj, nj, rj) in cases {
            let exact = covered_area(pi, ni, ri, pj, rj);
            let sampled = monte_carlo(pi, ni, ri, pj, nj, rj, 0.5);
            let tolerance = 0.03 * std::f32::consts::PI * ri * ri;
            assert!((exact - sampled).abs() < tolerance, "{exact} vs Monte-Carlo {sampled}");
        }
    }
}
