//! How many points a streamed frame draws: the default budget (1M), a
//! number, or every point of the file.
//!
//! Under a budget (the default or a number) the selection also stops
//! refining where a node's spacing projects below [`FINEST_PX`] pixel, so a
//! far view reads only the top levels and never fills the budget with points
//! that land on one pixel. `all` means every point: nothing is culled and
//! nothing stops early, and it is refused in one line when the decoded
//! points would not fit the node cache's bound.

use super::CopcError;
use crate::lod::{Choosing, SelectOptions};

/// The budget a streamed file is drawn under unless told otherwise.
pub const DEFAULT_BUDGET: usize = 1_000_000;
/// Under a budget, nodes whose spacing projects below this many pixels are not refined.
pub const FINEST_PX: f32 = 1.0;

/// Bytes a decoded point takes beyond its record: the built cloud's
/// position, normal, radius, colour and opacity, and the selection's own columns.
const BUILT_BYTES_PER_POINT: u64 = 12 + 12 + 4 + 3 + 4 + 8;

/// The points a streamed frame draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StreamBudget {
    /// [`DEFAULT_BUDGET`], with the one-pixel stop.
    #[default]
    Default,
    /// At most this many, with the one-pixel stop.
    Points(usize),
    /// Every point of the file.
    All,
}

impl StreamBudget {
    /// From `--point-budget`'s text as given (`None`: not given).
    pub fn given(text: Option<&str>) -> Result<Self, String> {
        match text {
            None => Ok(StreamBudget::Default),
            Some("all") => Ok(StreamBudget::All),
            Some(n) => match n.parse::<usize>() {
                Ok(n) if n >= 1 => Ok(StreamBudget::Points(n)),
                _ => Err(format!("--point-budget must be a number of points (1 or more) or all, not {n}")),
            },
        }
    }

    /// From a frame's settings, where `None` means "as the front end chose":
    /// `all` when `all_when_unset`, else the default.
    pub fn of_settings(point_budget: Option<u32>, all_when_unset: bool) -> Self {
        match point_budget {
            Some(n) => StreamBudget::Points(n as usize),
            None if all_when_unset => StreamBudget::All,
            None => StreamBudget::Default,
        }
    }

    /// How a frame's selection runs under this budget, choosing as the
    /// in-memory budget does ([`Choosing`]: the frame's radius scale, and no
    /// culling when lit, so off-screen nodes still cast their shadows), with
    /// the one-pixel stop under a number; `all` culls nothing and refines everything.
    pub fn select_options(self, choosing: Choosing) -> SelectOptions {
        match self {
            StreamBudget::Default => SelectOptions::for_frame(DEFAULT_BUDGET, choosing, FINEST_PX),
            StreamBudget::Points(n) => SelectOptions::for_frame(n, choosing, FINEST_PX),
            StreamBudget::All => SelectOptions { cull: false, ..SelectOptions::for_frame(usize::MAX, choosing, 0.0) },
        }
    }

    /// Refuses `All` when `points` of `record_bytes` each, decoded and built,
    /// would pass `cache_bytes`: the frame needs them all at once.
    pub fn check_fits(self, name: &str, points: u64, record_bytes: u64, cache_bytes: usize) -> Result<(), CopcError> {
        if self != StreamBudget::All {
            return Ok(());
        }
        let needed = points.saturating_mul(record_bytes + BUILT_BYTES_PER_POINT);
        if needed > cache_bytes as u64 {
            return Err(CopcError::new(
                name,
                format!(
                    "--point-budget all: its {points} points need about {} MB decoded, more than the node cache's \
                     {} MB (--cache-mb); give a larger --cache-mb or a number of points",
                    needed.div_ceil(1 << 20),
                    cache_bytes >> 20
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn all_draws_every_point_and_a_number_keeps_the_pixel_stop() {
        let drawn = Choosing::default();
        let all = StreamBudget::given(Some("all")).unwrap().select_options(drawn);
        assert_eq!((all.budget, all.cull, all.finest_px), (usize::MAX, false, 0.0));
        let some = StreamBudget::given(Some("5000")).unwrap().select_options(drawn);
        assert_eq!((some.budget, some.cull, some.finest_px), (5000, true, FINEST_PX));
        assert_eq!(StreamBudget::given(None).unwrap().select_options(drawn).budget, DEFAULT_BUDGET);
        assert!(StreamBudget::given(Some("0")).is_err());
    }

    #[test]
    fn a_streamed_frame_chooses_as_an_in_memory_budget_does() {
        let mut lit = crate::frame::RenderSettings { radius_scale: 2.5, ..Default::default() };
        lit.lights = crate::frame::Lights::new(&[crate::frame::Light::directional(glam::Vec3::NEG_Z)]).unwrap();
        let options = StreamBudget::Points(5000).select_options(Choosing::of(&lit));
        assert_eq!(options.radius_scale, 2.5, "the frame's radius scale");
        assert!(!options.cull, "a lit frame keeps the nodes off screen, which cast shadows");
        let in_memory = SelectOptions::for_frame(5000, Choosing::of(&lit), FINEST_PX);
        assert_eq!(
            (options.budget, options.radius_scale, options.cull),
            (5000, in_memory.radius_scale, in_memory.cull)
        );
    }

    #[test]
    fn all_is_refused_when_it_passes_the_cache() {
        let all = StreamBudget::All;
        assert!(all.check_fits("f", 1000, 34, 1 << 20).is_ok());
        let error = all.check_fits("f.copc.laz", 1_000_000, 34, 1 << 20).unwrap_err().to_string();
        assert!(error.starts_with("f.copc.laz: --point-budget all") && error.contains("--cache-mb"), "{error}");
        assert!(StreamBudget::Points(10).check_fits("f", u64::MAX, 34, 0).is_ok());
    }
}
