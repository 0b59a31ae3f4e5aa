//! Generated objects for scenes: a sphere of splats, and a square plane
//! (a floor to cast shadows on).
//!
//! A sphere's splats sit on a Fibonacci lattice (evenly spread,
//! deterministic), face outwards, and their radius is 1.2 × the lattice
//! spacing sqrt(4π/n)·R, so neighbouring discs overlap and close the
//! surface. A plane's splats sit on a square grid with radius 0.8 × its
//! spacing (more than the half-diagonal 0.71, so the discs leave no hole).

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

/// A square plane of about `splats` splats, `size` on a side, centred at
/// `centre` with unit `normal`, in file coordinates.
pub fn plane(splats: usize, size: f32, centre: Vec3, normal: Vec3) -> PointCloud {
    let side = (splats.max(1) as f32).sqrt().ceil().max(1.0) as usize;
    let spacing = size / side as f32;
    let normal = normal.try_normalize().unwrap_or(Vec3::Y);
    let helper = if normal.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let a = normal.cross(helper).normalize();
    let b = normal.cross(a);
    let positions: Vec<Vec3> = (0..side * side)
        .map(|k| {
            let (i, j) = ((k % side) as f32 + 0.5, (k / side) as f32 + 0.5);
            centre + a * (i * spacing - size * 0.5) + b * (j * spacing - size * 0.5)
        })
        .collect();
    let n = positions.len();
    PointCloud {
        positions,
        normals: vec![normal; n],
        radii: vec![0.8 * spacing; n],
        colours: vec![DEFAULT_COLOR; n],
        opacity: vec![1.0; n],
        ..Default::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plane_covers_its_square_and_faces_its_normal() {
        let p = plane(400, 2.0, Vec3::new(0.0, -1.0, 0.0), Vec3::Y);
        assert!(p.is_consistent() && p.len() == 400);
        assert!(p.positions.iter().all(|q| q.y == -1.0 && q.x.abs() < 1.0 && q.z.abs() < 1.0));
        assert!(p.radii[0] > 0.1 / 2f32.sqrt() && p.normals.iter().all(|n| *n == Vec3::Y));
    }

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
