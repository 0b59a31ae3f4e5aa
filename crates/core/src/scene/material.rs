//! An object's material: a colour that replaces the splats' own, an opacity
//! that multiplies theirs, and whether both sides are drawn. Opaque modes
//! ignore opacity; transparent modes read it. A transparent object is
//! two-sided by default: it is not back-face culled, and every renderer
//! shades a surface from the side the viewer sees.
//!
//! [`Materials`] are the overrides the command line gives every object of a
//! scene (`--opacity`, `--color`, and colour and opacity by attribute), as
//! `render`, `bench` and the viewer apply them. A [`Look`] is one object's
//! opacity and colour ([`crate::frame::look`]), set per object here.

use std::sync::Arc;

pub use crate::frame::look::Look;

use crate::style::Style;

/// Materials every object gets (`--opacity`, `--color`, `--color-by` and the
/// rest of the style), and whether a scene's own background applies (no `--background`).
#[derive(Debug, Clone, Default)]
pub struct Materials {
    pub opacity: Option<f32>,
    pub colour: Option<[u8; 3]>,
    pub style: Option<Arc<Style>>,
    pub scene_background: bool,
}

impl Materials {
    /// Gives every object of `scene` these materials; an error names the
    /// object whose file lacks an attribute the style reads.
    pub fn apply(&self, scene: &mut super::Scene) -> Result<(), String> {
        if let Some(style) = &self.style {
            scene.apply_style(style)?;
        }
        if let Some(opacity) = self.opacity {
            scene.set_opacity(opacity);
        }
        if let Some(colour) = self.colour {
            scene.set_colour(colour);
        }
        Ok(())
    }
}

/// How an object's splats look.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Replaces every splat's colour when set.
    pub colour: Option<[u8; 3]>,
    /// Multiplies every splat's opacity (1: as loaded).
    pub opacity: f32,
    /// Draw back faces too (never back-face culled).
    pub two_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Self { colour: None, opacity: 1.0, two_sided: false }
    }
}

impl Material {
    /// A material of `opacity`, two-sided when it is transparent.
    pub fn with_opacity(opacity: f32) -> Self {
        Self { opacity, two_sided: opacity < 1.0, ..Default::default() }
    }

    /// The colour a splat of colour `own` shows.
    pub fn colour(&self, own: [u8; 3]) -> [u8; 3] {
        self.colour.unwrap_or(own)
    }

    /// The opacity a splat of opacity `own` has, in 0..1.
    pub fn opacity(&self, own: f32) -> f32 {
        (own * self.opacity).clamp(0.0, 1.0)
    }
}

impl super::Scene {
    /// Each object's look, in order.
    pub fn looks(&self) -> Vec<Look> {
        let look = |o: &super::SceneObject| Look {
            opacity: o.material.opacity,
            colour: o.material.colour,
            clip: o.clip_box(),
        };
        self.objects.iter().map(look).collect()
    }

    /// Gives object k `looks[k]` (two-sided when it or its style is
    /// translucent), cut to its box ([`super::cut`]); an error when the
    /// counts differ, a look is not valid, or an object's file lacks what its style reads.
    pub fn set_looks(&mut self, looks: &[Look]) -> Result<(), String> {
        if looks.len() != self.objects.len() {
            return Err(format!("{} looks for {} objects", looks.len(), self.objects.len()));
        }
        for (object, look) in self.objects.iter_mut().zip(looks) {
            look.check()?;
            object.set_cut(look.clip)?;
            object.material.opacity = look.opacity;
            let translucent = object.styled.as_ref().is_some_and(|s| s.applied.translucent);
            object.material.two_sided = look.opacity < 1.0 || translucent;
            object.material.colour = look.colour;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looks_set_each_objects_material_and_refuse_a_wrong_count_or_opacity() {
        let mut scene = super::super::Scene::single("a", crate::cloud::PointCloud::default(), 1);
        scene.objects.push(scene.objects[0].clone());
        let looks = [Look { opacity: 0.25, colour: Some([200, 10, 10]), clip: None }, Look::default()];
        scene.set_looks(&looks).unwrap();
        assert_eq!(scene.looks(), looks);
        assert!(scene.objects[0].material.two_sided && !scene.objects[1].material.two_sided);
        assert_eq!(scene.set_looks(&looks[..1]).unwrap_err(), "1 looks for 2 objects");
        let bad = [Look { opacity: 1.5, ..Look::default() }, Look::default()];
        assert_eq!(scene.set_looks(&bad).unwrap_err(), "'1.5' is not an opacity in 0..1");
    }
}
