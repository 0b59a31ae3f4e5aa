//! The screen-space low-pass filter of the splat passes: Guennebaud's EWA
//! filtering approximation (SPBG'06 slides, "EWA filtering approximation").
//!
//! A splat whose footprint is smaller than a pixel is point-sampled by the
//! per-pixel ray cast, so a far model aliases. Full EWA splatting convolves
//! each warped reconstruction kernel with a screen-space low-pass filter; the
//! approximation instead adjusts the splat's object-space tangent vectors so
//! that their screen-space lengths are at least the filter's radius
//! ([`LOW_PASS_RADIUS_PX`]). For discs the slides' heuristic picks the
//! tangents s = p × n and t = n × s (p the centre, n the normal): s is
//! parallel to the screen and t is the direction of greatest
//! foreshortening, so checking the two lengths is exact at the screen centre
//! and for splats parallel to the screen. Only splats shorter than the
//! radius along s are stretched (in both directions): a large splat seen at
//! a grazing angle is left alone, so silhouettes of models whose splats are
//! large on screen do not widen (measured: docs/BENCHMARKS.md). A stretched splat keeps its total
//! weight (its Gaussian's peak is divided by the stretch, as the convolution
//! of two Gaussians is). The stretched disc stays in its own plane, so its
//! depth on every ray is well defined and coplanar neighbours stay within ε
//! of one another, unlike a screen-space footprint whose extrapolated depth
//! is arbitrary (the slides' "about depth values").
//!
//! Stretching alone widens a silhouette: the splat passes cover a pixel or
//! not, where the supersampled reference blends the rim with what is behind
//! it. So two-pass, filtered, also keeps coverage (`shaders/accumulate.wgsl`,
//! COVERAGE): a stretched splat's weight, times k = 1/(2σ²), is its own
//! projected area spread over the filter, its share of the pixel; the shares
//! are summed front and behind the front + ε apart (the ε test made in the
//! shader, so that what is behind is kept), and the normalisation divides
//! them by the sum a covered pixel has (the splats overlap), read from the
//! neighbours, and lays the front over what is behind it and that over the
//! background. A stretched splat is also shaded per fragment with its own
//! normal: below a pixel, what the filter averages is shaded colour, as the
//! reference averages shaded rays. Splats the filter leaves alone are solid
//! and shaded as without it, so the bench views do not change. The other
//! weighting modes stretch without coverage.
//!
//! `shaders/splat.wgsl` applies it in the splat passes of the modes that
//! read it (those whose passes weight each fragment: two-pass, deferred and
//! the peeling modes; alg1, alg2 and α-blending blend whole fragments by
//! opacity). The reference does not filter: its answer to aliasing is supersampling
//! (`ReferenceOptions::supersample`), the ruler the filter is measured against.

/// Radius in pixels that a splat's tangent vectors are stretched to at
/// least. Measured on the far views of docs/BENCHMARKS.md ("EWA
/// prefilter"): against the 4×4-supersampled reference.
pub const LOW_PASS_RADIUS_PX: f32 = 0.8;

/// Whether the splat passes low-pass filter splats smaller than a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Prefilter {
    /// Splats are drawn at their own size, however small (point-sampled).
    #[default]
    None,
    /// Guennebaud's EWA approximation: tangents stretched to the low-pass radius.
    Ewa,
}

impl Prefilter {
    pub const ALL: [Prefilter; 2] = [Prefilter::None, Prefilter::Ewa];

    pub fn name(self) -> &'static str {
        match self {
            Prefilter::None => "none",
            Prefilter::Ewa => "ewa",
        }
    }

    /// The low-pass radius in pixels the splat passes stretch to (0: none).
    pub fn radius_px(self) -> f32 {
        match self {
            Prefilter::None => 0.0,
            Prefilter::Ewa => LOW_PASS_RADIUS_PX,
        }
    }
}

crate::by_name!(Prefilter, "prefilter");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for p in Prefilter::ALL {
            assert_eq!(p.name().parse::<Prefilter>(), Ok(p));
        }
        assert!("gauss".parse::<Prefilter>().unwrap_err().contains("none, ewa"));
        assert_eq!(Prefilter::None.radius_px(), 0.0);
        assert!(Prefilter::Ewa.radius_px() > 0.0);
    }
}
