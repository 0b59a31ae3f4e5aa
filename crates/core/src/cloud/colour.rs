//! Colour channels from the numbers files store: one rounding rule shared by
//! the PLY loader and the 3D Gaussian splats' SH colours.

/// `v` (0..255 scale) rounded and clamped to a u8 channel; 0 when it is not finite.
pub(super) fn to_u8(v: f64) -> u8 {
    if v.is_finite() { v.round().clamp(0.0, 255.0) as u8 } else { 0 }
}
