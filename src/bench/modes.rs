//! Benchmark mode names: `two-pass`, `reference`, and the deferred variants
//! `deferred[-GROUPING][-voronoi]`, e.g. `deferred-mgc-c0.4`, `deferred-wgc-k8-voronoi`.
//! Plain `deferred` is the paper's opaque setting: MGC at c = 0.4 with Voronoi rasterisation.

use crate::grouping::GroupingSpec;
use crate::view::RenderMode;

/// A mode with the set-up it needs.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeSpec {
    pub mode: RenderMode,
    /// The grouping of a deferred variant.
    pub grouping: Option<GroupingSpec>,
    pub voronoi: bool,
    /// The name rows carry.
    pub name: String,
}

impl std::str::FromStr for ModeSpec {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "deferred" {
            return Ok(ModeSpec {
                mode: RenderMode::Deferred,
                grouping: Some(GroupingSpec::default()),
                voronoi: true,
                name: s.into(),
            });
        }
        if let Some(rest) = s.strip_prefix("deferred-") {
            let (grouping, voronoi) = match rest.strip_suffix("-voronoi") {
                Some(g) => (g, true),
                None if rest == "voronoi" => ("", true),
                None => (rest, false),
            };
            let grouping = if grouping.is_empty() { GroupingSpec::default() } else { grouping.parse()? };
            return Ok(ModeSpec { mode: RenderMode::Deferred, grouping: Some(grouping), voronoi, name: s.into() });
        }
        let mode: RenderMode = s.parse()?;
        Ok(ModeSpec { mode, grouping: None, voronoi: false, name: s.into() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variant_names_parse() {
        let d: ModeSpec = "deferred-wgc-k8-voronoi".parse().unwrap();
        assert_eq!((d.mode, d.grouping, d.voronoi), (RenderMode::Deferred, Some(GroupingSpec::Wgc { k: 8 }), true));
        let d: ModeSpec = "deferred-mgc-c0.4".parse().unwrap();
        assert_eq!((d.grouping, d.voronoi), (Some(GroupingSpec::Mgc { c: 0.4 }), false));
        assert!("deferred-xyz".parse::<ModeSpec>().is_err());
        assert_eq!("two-pass".parse::<ModeSpec>().unwrap().mode, RenderMode::TwoPass);
    }
}
