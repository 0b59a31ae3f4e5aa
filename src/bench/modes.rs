//! Benchmark mode names: `two-pass`, `reference`, and the deferred variants
//! `deferred[-GROUPING][-no-voronoi]`, e.g. `deferred-wgc-k8`, `deferred-mgc-c1-no-voronoi`.
//! As everywhere, deferred defaults to the paper's opaque setting: MGC at
//! c = 0.4 with Voronoi rasterisation (`-voronoi` may be written out).

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
        let Some(rest) = s.strip_prefix("deferred") else {
            let mode: RenderMode = s.parse()?;
            return Ok(ModeSpec { mode, grouping: None, voronoi: false, name: s.into() });
        };
        let (rest, voronoi) = match (rest.strip_suffix("-no-voronoi"), rest.strip_suffix("-voronoi")) {
            (Some(r), _) => (r, false),
            (None, Some(r)) => (r, true),
            (None, None) => (rest, true),
        };
        let grouping = match rest {
            "" => GroupingSpec::default(),
            _ => rest.strip_prefix('-').ok_or_else(|| format!("unknown mode '{s}'"))?.parse()?,
        };
        Ok(ModeSpec { mode: RenderMode::Deferred, grouping: Some(grouping), voronoi, name: s.into() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variant_names_parse() {
        let d: ModeSpec = "deferred-wgc-k8".parse().unwrap();
        assert_eq!((d.mode, d.grouping, d.voronoi), (RenderMode::Deferred, Some(GroupingSpec::Wgc { k: 8 }), true));
        let d: ModeSpec = "deferred-mgc-c0.4-no-voronoi".parse().unwrap();
        assert_eq!((d.grouping, d.voronoi), (Some(GroupingSpec::Mgc { c: 0.4 }), false));
        let d: ModeSpec = "deferred".parse().unwrap();
        assert_eq!((d.grouping, d.voronoi), (Some(GroupingSpec::Mgc { c: 0.4 }), true));
        assert!(!"deferred-no-voronoi".parse::<ModeSpec>().unwrap().voronoi);
        assert!("deferred-xyz".parse::<ModeSpec>().is_err());
        assert!("deferredx".parse::<ModeSpec>().is_err());
        assert_eq!("two-pass".parse::<ModeSpec>().unwrap().mode, RenderMode::TwoPass);
    }
}
