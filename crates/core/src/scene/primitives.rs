//! Generated objects for scenes: a sphere of splats.
//!
//! The splats sit on a Fibonacci lattice (evenly spread, deterministic),
//! face outwards, and their radius is 1.2 × the lattice spacing
//! sqrt(4π/n)·R, so neighbouring discs overlap and close the surface.

use glam::Vec3;

use crate::cloud::PointCloud;
use crate::cloud::load::DEFAULT_COLOR;

/// A sphere of `splats` splats of radius `radius` around `centre`, in file
/// coordinates (its origin is zero).
pub fn sphere(splats: usize, radius: f32, centre: Vec3) -> PointCloud {
    let n = splats.max(1);
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let directions: Vec<Vec3> = (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).max(0.0).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), y, r * phi.sin())
        })
        .collect();
    let spacing = radius * (4.0 * std::f32::consts::PI / n as f32).sqrt();
    PointCloud {
        positions: directions.iter().map(|d| centre + *d * radius).collect(),
        normals: directions,
        radii: vec![1.2 * spacing; n],
        colours: vec![DEFAULT_COLOR; n],
        opacity: vec![1.0; n],
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sphere_lies_on_its_radius_and_faces_out() {
        let s = sphere(500, 2.0, Vec3::new(1.0, 0.0, 0.0));
        assert!(s.is_consistent() && s.len() == 500);
        for (p, n) in s.positions.iter().zip(&s.normals) {
            let d = *p - Vec3::new(1.0, 0.0, 0.0);
            assert!((d.length() - 2.0).abs() < 1e-5);
            assert!(d.normalize().dot(*n) > 0.9999);
        }
    }
}
