//! An object's look: its opacity, the colour that replaces its splats'
//! own, and the box it is cut to ([`crate::scene::cut`]), as the viewer's
//! layer list sets them per layer ([`crate::scene::Scene::set_looks`]) and
//! a screenshot's sidecar records them for `render --camera`.

use serde::{Deserialize, Serialize};

use super::clip::ClipBox;

/// One object's opacity, the colour that replaces its splats' own (none:
/// theirs) and the box in file coordinates it is cut to (none: whole).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Look {
    pub opacity: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour: Option<[u8; 3]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clip: Option<ClipBox>,
}

impl Default for Look {
    fn default() -> Self {
        Self { opacity: 1.0, colour: None, clip: None }
    }
}

impl Look {
    /// Checks the opacity is in 0..1 and the box is ordered and finite.
    pub fn check(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.opacity) {
            return Err(format!("'{}' is not an opacity in 0..1", self.opacity));
        }
        let region = super::ClipRegion { clip_box: self.clip, planes: Vec::new() };
        region.check().map_err(|e| e.to_string())
    }
}
