//! An object's material: a colour that replaces the splats' own, and an
//! opacity that multiplies theirs. Opaque modes ignore opacity; transparent
//! modes read it.

/// How an object's splats look.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Replaces every splat's colour when set.
    pub colour: Option<[u8; 3]>,
    /// Multiplies every splat's opacity (1: as loaded).
    pub opacity: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self { colour: None, opacity: 1.0 }
    }
}

impl Material {
    /// The colour a splat of colour `own` shows.
    pub fn colour(&self, own: [u8; 3]) -> [u8; 3] {
        self.colour.unwrap_or(own)
    }

    /// The opacity a splat of opacity `own` has, in 0..1.
    pub fn opacity(&self, own: f32) -> f32 {
        (own * self.opacity).clamp(0.0, 1.0)
    }
}
