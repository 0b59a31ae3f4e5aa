//! Zhang & Pajarola's Eq. 10: the number n of low-precision depth steps over
//! the depth range [d_min, d_max], n ≥ (d_max − d_min)/ε, so that two
//! surface layers more than ε apart fall into different steps, while the
//! fragments of one layer share a step (the Voronoi z-test of Eq. 14 and the
//! fragment culling of the transparent algorithms rely on this). The
//! renderer passes the step it wants as ε here: `RenderSettings::depth_step`
//! × ε (a layer whose fragments straddle a boundary counts twice, so a step
//! a little thicker than ε measured better; docs/BENCHMARKS.md).
//!
//! Guards: n is at least 1 (a range thinner than ε, d_max = d_min, or a
//! non-finite input); and at most [`MAX_DEPTH_STEPS`], because the z-test
//! value floor(z·n)/n + (d_i/r_i)/n lives in an f32 in 0..1 whose 24-bit
//! mantissa must still resolve the Voronoi term (d_i/r_i)/n within a step:
//! at n = 2^15 that term keeps 8 bits. Beyond the cap a step is thicker than
//! ε; a plan whose n equals the cap says so.

/// Most depth steps: 2^15, leaving 8 of f32's 23 fraction bits (at z near 1)
/// to the Voronoi term within a step.
pub const MAX_DEPTH_STEPS: f32 = 32_768.0;

/// Eq. 10's n for view depths `near..far` and ε `epsilon` (at the cap, the
/// steps are thicker than ε).
pub fn depth_steps(near: f32, far: f32, epsilon: f32) -> f32 {
    let n = ((far - near) / epsilon).ceil();
    // NaN (a NaN input) and -inf (far below near) give one step; +inf (ε = 0) the cap.
    if n.is_nan() || n == f32::NEG_INFINITY {
        return 1.0;
    }
    n.clamp(1.0, MAX_DEPTH_STEPS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_the_range_over_epsilon_at_least_one_and_capped() {
        assert_eq!(depth_steps(1.0, 2.0, 0.01), 100.0);
        assert_eq!(depth_steps(1.0, 1.0, 0.01), 1.0, "d_max = d_min");
        assert_eq!(depth_steps(1.0, 1.001, 0.01), 1.0, "a range thinner than ε");
        assert_eq!(depth_steps(0.1, 1e6, 1e-6), MAX_DEPTH_STEPS);
        assert_eq!(depth_steps(1.0, 2.0, 0.0), MAX_DEPTH_STEPS, "ε = 0 is a capped infinity");
        assert_eq!(depth_steps(f32::NAN, 2.0, 0.01), 1.0);
        assert_eq!(depth_steps(1.0, 2.0, f32::NAN), 1.0);
        // Within a step at the cap, the Voronoi term still has 2^8 levels.
        let z = 1.0 - 1.0 / MAX_DEPTH_STEPS;
        let levels = (0..=256).map(|i| z + (i as f32 / 256.0) / MAX_DEPTH_STEPS).collect::<Vec<_>>();
        assert!(levels.windows(2).all(|w| w[1] > w[0]), "distinct z-test values");
    }
}
