//! 3D Gaussian splats (Kerbl et al. 2023) as surface splats.
//!
//! A 3DGS file stores per Gaussian the SH DC colour `f_dc_*`, an opacity
//! logit, log scales `scale_*` and a rotation quaternion `rot_*` (w first).
//! The splat's normal is the Gaussian's thinnest axis, its radius spans
//! [`SIGMAS_PER_RADIUS`] standard deviations of the two other axes (their
//! geometric mean), its colour is 0.5 + C0·DC and its opacity the sigmoid of
//! the logit.

use glam::{Quat, Vec3};

/// The vertex properties a 3DGS file has.
pub const PROPERTIES: [&str; 11] =
    ["f_dc_0", "f_dc_1", "f_dc_2", "opacity", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"];

/// Zeroth-order spherical-harmonic constant used by 3D Gaussian splatting.
const SH_C0: f64 = 0.282_094_791_773_878_14;

/// How many Gaussian standard deviations a splat disc spans (our kernel has σ = 0.4 r).
pub const SIGMAS_PER_RADIUS: f32 = 2.5;

/// The disc of one Gaussian: unit normal and radius, or `None` when its
/// scales or rotation are degenerate or not finite.
pub fn disc(log_scales: [f64; 3], rotation_wxyz: [f64; 4]) -> Option<(Vec3, f32)> {
    let scales = log_scales.map(|s| s.exp() as f32);
    let [w, x, y, z] = rotation_wxyz.map(|v| v as f32);
    let q = Quat::from_xyzw(x, y, z, w);
    let (thin, a, b) = thinnest_axis(scales);
    let radius = SIGMAS_PER_RADIUS * (scales[a] * scales[b]).sqrt();
    let length = q.length();
    let usable = radius.is_finite() && radius > 0.0 && length.is_finite() && length > 1e-12;
    usable.then(|| ((q / length) * Vec3::AXES[thin], radius))
}

/// The colour (0..255 per channel) of the SH DC coefficients.
pub fn colour(dc: [f64; 3]) -> [u8; 3] {
    dc.map(|c| super::colour::to_u8((0.5 + SH_C0 * c) * 255.0))
}

/// Opacity in 0..1 from the stored logit (1 when it is not a number).
pub fn opacity(logit: f64) -> f32 {
    let s = 1.0 / (1.0 + (-logit).exp());
    if s.is_finite() { s as f32 } else { 1.0 }
}

/// Index of the smallest scale and of the other two.
fn thinnest_axis(s: [f32; 3]) -> (usize, usize, usize) {
    if s[0] <= s[1] && s[0] <= s[2] {
        (0, 1, 2)
    } else if s[1] <= s[2] {
        (1, 0, 2)
    } else {
        (2, 0, 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_thinnest_axis_becomes_the_normal() {
        let (normal, radius) = disc([0.0, -3.0, 0.0], [1.0, 0.0, 0.0, 0.0]).unwrap();
        assert!((normal - Vec3::Y).length() < 1e-6);
        assert!((radius - SIGMAS_PER_RADIUS).abs() < 1e-5);
        assert!(disc([f64::NAN, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]).is_none());
        assert!(disc([0.0; 3], [0.0; 4]).is_none());
    }
}
