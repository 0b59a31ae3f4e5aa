//! The viewer's preview while the camera moves on a large model: a faster
//! mode under the moving budget, so that orbiting stays interactive, then
//! the full frame once the camera rests (`frames::SETTLE`). The rule is the
//! viewer's, read from the registry's capabilities:
//! - an opaque mode previews with the default opaque mode (two-pass);
//! - a transparent mode that peels layers, draws groups, or runs on the CPU
//!   (the reference) previews with the GPU mode that peels the fewest layers
//!   by default (Guennebaud's approximate peeling keeps a transparent
//!   scene's look at a fraction of the cost);
//! - any other transparent mode (one pass over sorted splats, or the tile
//!   pipeline) previews as itself.

use crate::frame::{Parameter, RenderMode};

/// The mode that previews `mode`.
pub fn preview_mode(mode: RenderMode) -> RenderMode {
    let info = mode.info();
    if !info.transparent {
        return RenderMode::DEFAULT;
    }
    let layered = mode.reads(Parameter::PeelLayers) || mode.needs_grouping() || !mode.is_gpu();
    if !layered {
        return mode;
    }
    RenderMode::ALL
        .into_iter()
        .filter(|m| m.is_gpu() && m.info().transparent && m.reads(Parameter::PeelLayers))
        .min_by_key(|m| m.info().default_peel_layers)
        .unwrap_or(RenderMode::DEFAULT)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mode_previews_with_a_gpu_mode_as_fast_as_itself_or_faster() {
        let previews: Vec<(String, String)> =
            RenderMode::ALL.into_iter().map(|m| (m.to_string(), preview_mode(m).to_string())).collect();
        let expected = [
            ("two-pass", "two-pass"),
            ("deferred", "two-pass"),
            ("depth-peel", "approx-peel"),
            ("approx-peel", "approx-peel"),
            ("alg1", "approx-peel"),
            ("alg2", "approx-peel"),
            ("alpha-blend", "alpha-blend"),
            ("tiled", "tiled"),
            ("reference", "approx-peel"),
        ];
        let expected: Vec<(String, String)> = expected.iter().map(|(a, b)| (a.to_string(), b.to_string())).collect();
        assert_eq!(previews, expected);
        assert!(RenderMode::ALL.into_iter().all(|m| preview_mode(m).is_gpu()));
    }
}
