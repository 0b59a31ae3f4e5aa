//! The splat kernel: elliptical shape, Gaussian weight and foreshortening bound.
//!
//! Botsch & Kobbelt 2003 §3.2-3.3: a pixel at splat-plane coordinates (x, y)
//! (in units of the radius) lies at depth offset δz = -(n_x x + n_y y)/n_z
//! (Eq. 2); it is inside the splat iff ρ² = x² + y² + δz² < 1 and gets the
//! weight w = exp(-ρ²/(2σ²)) (Eq. 3). |n_z| is bounded from below so that
//! splats seen edge-on stay at least a sliver wide instead of vanishing.

/// Parameters of the splat footprint, shared by every renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplatKernel {
    /// Gaussian standard deviation, as a fraction of the splat radius.
    pub sigma: f32,
    /// Smallest |n_z| used in Eq. 2 (bounds the foreshortening to 1/this).
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
}
