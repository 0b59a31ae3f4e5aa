//! The splat kernel: footprint, Gaussian weight and foreshortening bound.
//!
//! Every renderer casts each pixel's view ray on the splat's plane (the
//! perspective-correct rasterisation of Guennebaud's SPBG'06 slides): the hit
//! at squared distance ρ² (in units of the radius) from the centre is inside
//! the splat iff ρ² < 1 and gets Botsch & Kobbelt 2003's Gaussian weight
//! w = exp(-ρ²/(2σ²)) (Eq. 3); its depth is the exact depth of the hit (Eq. 4).
//! Foreshortening is bounded as in Botsch & Kobbelt §3.2 (|n_z| ≥ 0.15), but
//! relative to the ray to the splat's centre: a disc seen at a more grazing
//! angle is rasterised in a plane tilted towards the viewer
//! ([`SplatKernel::footprint_normal`]), so edge-on splats stay slivers instead
//! of vanishing. `shaders/splat.wgsl` does the same on the GPU.

use glam::Vec3;

/// Parameters of the splat footprint, shared by every renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplatKernel {
    /// Gaussian standard deviation, as a fraction of the splat radius.
    pub sigma: f32,
    /// Smallest |cos| between a footprint's plane normal and the view ray
    /// (bounds the foreshortening to 1/this).
    pub min_normal_z: f32,
}

impl Default for SplatKernel {
    fn default() -> Self {
        Self { sigma: 0.4, min_normal_z: 0.15 }
    }
}

impl SplatKernel {
    /// Weight at squared normalised distance `rho2` (0 outside the disc).
    pub fn weight(&self, rho2: f32) -> f32 {
        if rho2 >= 1.0 { 0.0 } else { (-rho2 * self.sharpness()).exp() }
    }

    /// The normal of the plane a disc with unit normal `n` is rasterised in,
    /// seen along the unit direction `view` (from the eye to its centre):
    /// `n` tilted towards `view` until |n·view| >= `min_normal_z`, on its side.
    pub fn footprint_normal(&self, n: Vec3, view: Vec3) -> Vec3 {
        let k = n.dot(view);
        let min = self.min_normal_z;
        if k.abs() >= min {
            return n;
        }
        let side = if k < 0.0 { -1.0 } else { 1.0 };
        let across = (n - k * view).normalize_or_zero();
        across * (1.0 - min * min).sqrt() + view * (side * min)
    }

    /// k in w = exp(-k ρ²).
    pub fn sharpness(&self) -> f32 {
        0.5 / (self.sigma * self.sigma)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_is_a_gaussian_of_sigma_cut_at_the_rim() {
        let k = SplatKernel::default();
        assert_eq!(k.weight(0.0), 1.0);
        let at_sigma = k.weight(k.sigma * k.sigma);
        assert!((at_sigma - (-0.5f32).exp()).abs() < 1e-6);
        assert_eq!(k.weight(1.0), 0.0);
    }

    #[test]
    fn grazing_discs_are_tilted_to_the_bound_and_others_kept() {
        let k = SplatKernel::default();
        let view = Vec3::NEG_Z;
        let facing = Vec3::new(0.0, 0.6, 0.8);
        assert_eq!(k.footprint_normal(facing, view), facing);
        let edge_on = k.footprint_normal(Vec3::X, view);
        assert!((edge_on.length() - 1.0).abs() < 1e-6);
        assert!((edge_on.dot(view).abs() - k.min_normal_z).abs() < 1e-6);
        assert!(edge_on.x > 0.98, "tilted only as far as needed: {edge_on}");
    }
}
