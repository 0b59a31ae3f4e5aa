//! A scene file's view keys: the `[camera]` table and the `[clip]` region
//! (boxes and planes in file coordinates, [`crate::frame::clip`]).

use serde::Deserialize;
use toml::Spanned;

use super::{Reader, SceneError};
use crate::frame::{CameraRequest, ClipRegion, NamedView, Projection, UpAxis};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraEntry {
    azimuth: Option<Spanned<f32>>,
    elevation: Option<Spanned<f32>>,
    distance: Option<Spanned<f32>>,
    fov: Option<Spanned<f32>>,
    up: Option<Spanned<String>>,
    /// `perspective` or `ortho`.
    projection: Option<Spanned<String>>,
    /// `top`, `bottom`, `front`, `back`, `left`, `right` or `iso`.
    view: Option<Spanned<String>>,
}

impl Reader<'_> {
    /// The `[camera]` table, checked by the rule the command line's flags get
    /// ([`CameraRequest::check`]), each bad value reported at its line and column.
    pub(super) fn camera(&self, c: &CameraEntry) -> Result<CameraRequest, SceneError> {
        let up = match &c.up {
            Some(u) => Some(u.get_ref().parse::<UpAxis>().map_err(|e| self.at(Some(u.span()), e))?),
            None => None,
        };
        let projection = match &c.projection {
            Some(p) => Some(p.get_ref().parse::<Projection>().map_err(|e| self.at(Some(p.span()), e))?),
            None => None,
        };
        let view = match &c.view {
            Some(v) => Some(v.get_ref().parse::<NamedView>().map_err(|e| self.at(Some(v.span()), e))?),
            None => None,
        };
        let value = |v: &Option<Spanned<f32>>| v.as_ref().map(|v| *v.get_ref());
        let request = CameraRequest {
            azimuth: value(&c.azimuth),
            elevation: value(&c.elevation),
            distance: value(&c.distance),
            fov: value(&c.fov),
            up,
            projection,
            view,
        };
        request.check().map_err(|e| {
            let entry = match e.key {
                "azimuth" => &c.azimuth,
                "elevation" => &c.elevation,
                "distance" => &c.distance,
                _ => &c.fov,
            };
            self.at(entry.as_ref().map(|v| v.span()), e.to_string())
        })?;
        Ok(request)
    }

    /// The `[clip]` table, checked.
    pub(super) fn clip(&self, clip: &Spanned<ClipRegion>) -> Result<ClipRegion, SceneError> {
        clip.get_ref().check().map_err(|e| self.at(Some(clip.span()), e.to_string()))?;
        Ok(clip.get_ref().clone())
    }
}
