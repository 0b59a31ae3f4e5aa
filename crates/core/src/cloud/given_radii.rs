//! Radii a file gives, kept within reason: one absurd radius would cover the
//! view and push the framing away, so given radii are clamped to a multiple
//! of their median and to a quarter of the model's diagonal.

/// Radii read from a file are clamped to this multiple of their median: one
/// absurd radius would otherwise cover the view and push the framing away.
pub const FILE_RADIUS_OVER_MEDIAN: f32 = 100.0;

/// Clamps the radii that were given (not `needed`) to
/// [`FILE_RADIUS_OVER_MEDIAN`] times their median, and to a quarter of the
/// model's `diagonal` when it has one; returns how many were clamped, and the limit.
pub(super) fn clamp_given_radii(radii: &mut [f32], needed: &[bool], diagonal: f32) -> (usize, f32) {
    let mut given: Vec<f32> = radii.iter().zip(needed).filter(|(_, n)| !**n).map(|(r, _)| *r).collect();
    if given.is_empty() {
        return (0, 0.0);
    }
    let mid = given.len() / 2;
    let mut limit = *given.select_nth_unstable_by(mid, f32::total_cmp).1 * FILE_RADIUS_OVER_MEDIAN;
    if diagonal > 0.0 {
        limit = limit.min(0.25 * diagonal);
    }
    let mut clamped = 0;
    for (r, _) in radii.iter_mut().zip(needed).filter(|(r, n)| !**n && **r > limit) {
        *r = limit;
        clamped += 1;
    }
    (clamped, limit)
}
