//! A screenshot's scene lights, as its sidecar records them: each light's
//! kind, where it is (point lights, in the file's coordinates, f64) or where
//! it shines (directional lights), its colour, intensity and falloff, so that
//! `render --camera` lights the view again as the viewer lit it.

use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};

use super::super::{Light, LightKind, Lights};

/// One light of a sidecar.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LightRecord {
    /// A point light's position in file coordinates.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    /// A directional light's direction of travel.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub direction: Option<[f32; 3]>,
    pub colour: [f32; 3],
    pub intensity: f32,
    #[serde(default)]
    pub inverse_square: bool,
}

impl LightRecord {
    /// `light`, whose position is in the scene's frame: file = frame · unit + origin.
    pub fn of(light: &Light, (origin, unit): (DVec3, f64)) -> Self {
        let (position, direction) = match light.kind {
            LightKind::Point(p) => (Some((p.as_dvec3() * unit + origin).to_array()), None),
            LightKind::Directional(d) => (None, Some(d.to_array())),
        };
        LightRecord {
            position,
            direction,
            colour: light.colour.to_array(),
            intensity: light.intensity,
            inverse_square: light.inverse_square,
        }
    }

    /// The light in file coordinates (what scene files and `--light` give), or why it cannot be one.
    pub fn light(&self) -> Result<Light, String> {
        let kind = match (self.position, self.direction) {
            (Some(p), None) => LightKind::Point(DVec3::from_array(p).as_vec3()),
            (None, Some(d)) => LightKind::Directional(Vec3::from_array(d)),
            _ => return Err("a light needs either a position or a direction".into()),
        };
        let light = Light {
            kind,
            colour: Vec3::from_array(self.colour),
            intensity: self.intensity,
            inverse_square: self.inverse_square,
        };
        Lights::new(&[light]).map_err(|e| e.to_string())?;
        Ok(light)
    }
}

/// The records of `lights` (positions in the scene frame placed by `placement`).
pub fn records(lights: &Lights, placement: (DVec3, f64)) -> Vec<LightRecord> {
    lights.as_slice().iter().map(|l| LightRecord::of(l, placement)).collect()
}
