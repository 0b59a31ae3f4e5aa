//! A scene file's view keys: the `[camera]` table and the `[clip]` region
//! (boxes and planes in file coordinates, [`crate::frame::clip`]).

use serde::Deserialize;
use toml::Spanned;

use super::{Reader, SceneError};
use crate::frame::{ClipRegion, UpAxis};
use crate::scene::SceneCamera;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraEntry {
    azimuth: Option<f32>,
    elevation: Option<f32>,
    distance: Option<Spanned<f32>>,
    fov: Option<Spanned<f32>>,
    up: Option<Spanned<String>>,
}

impl Reader<'_> {
    /// The `[camera]` table, checked.
    pub(super) fn camera(&self, c: &CameraEntry) -> Result<SceneCamera, SceneError> {
        if let Some(fov) = &c.fov {
            if !(0.5..=170.0).contains(fov.get_ref()) {
                return Err(self.at(Some(fov.span()), "fov must be between 0.5 and 170 degrees".into()));
            }
        }
        if let Some(d) = &c.distance {
            if !(d.get_ref().is_finite() && *d.get_ref() > 0.0) {
                return Err(self.at(Some(d.span()), "distance must be positive".into()));
            }
        }
        let up = match &c.up {
            Some(u) => Some(u.get_ref().parse::<UpAxis>().map_err(|e| self.at(Some(u.span()), e))?),
            None => None,
        };
        Ok(SceneCamera {
            azimuth: c.azimuth,
            elevation: c.elevation,
            distance: c.distance.as_ref().map(|d| *d.get_ref()),
            fov: c.fov.as_ref().map(|f| *f.get_ref()),
            up,
        })
    }

    /// The `[clip]` table, checked.
    pub(super) fn clip(&self, clip: &Spanned<ClipRegion>) -> Result<ClipRegion, SceneError> {
        clip.get_ref().check().map_err(|e| self.at(Some(clip.span()), e.to_string()))?;
        Ok(clip.get_ref().clone())
    }
}
