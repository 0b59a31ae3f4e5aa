//! An object's look: its opacity and the colour that replaces its splats'
//! own, as the viewer's layer list sets them per layer
//! ([`crate::scene::Scene::set_looks`]) and a screenshot's sidecar records
//! them for `render --camera`.

use serde::{Deserialize, Serialize};

/// One object's opacity and the colour that replaces its splats' own (none: theirs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Look {
    pub opacity: f32,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colour: Option<[u8; 3]>,
}

impl Default for Look {
    fn default() -> Self {
        Self { opacity: 1.0, colour: None }
    }
}

impl Look {
    /// Checks the opacity is in 0..1.
    pub fn check(&self) -> Result<(), String> {
        if (0.0..=1.0).contains(&self.opacity) {
            Ok(())
        } else {
            Err(format!("'{}' is not an opacity in 0..1", self.opacity))
        }
    }
}
