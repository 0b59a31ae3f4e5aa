//! How a camera projects: perspective, or orthographic (parallel rays, the
//! plan and elevation views of survey drawings), and the named views
//! (`top`, `front`, ..., `iso`) that set its direction.
//!
//! An orthographic orbit camera keeps the perspective camera's framing: its
//! window's half height is `distance · tan(fov_y / 2)`, so the target's
//! neighbourhood is as large on screen in both projections and zooming
//! (changing the distance) scales the window. Its eye stands outside the
//! scene's sphere, whatever the distance, so nothing is cut by the near
//! plane ([`super::Camera::eye_distance`]). A pixel's ray starts on the
//! eye's plane at the pixel's place and runs along the view axis: every
//! renderer casts it from [`super::Camera::lens`]'s half extent, which is
//! in eye units in orthographic and per unit of view depth in perspective.

use std::str::FromStr;

/// The projection of a camera (in sidecars and views files: `"perspective"`
/// or `"ortho"`; absent is perspective).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Projection {
    #[default]
    Perspective,
    /// Parallel rays along the view axis.
    Ortho,
}

impl Projection {
    pub fn name(self) -> &'static str {
        match self {
            Projection::Perspective => "perspective",
            Projection::Ortho => "ortho",
        }
    }
}

impl FromStr for Projection {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "perspective" => Ok(Projection::Perspective),
            "ortho" | "orthographic" => Ok(Projection::Ortho),
            _ => Err(format!("'{s}' is not a projection; use perspective or ortho")),
        }
    }
}

impl std::fmt::Display for Projection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A named view direction, about the camera's up axis and front
/// ([`super::UpAxis::frame`]): for z-up survey data `front` looks north
/// from the south and `right` looks west from the east.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NamedView {
    Top,
    Bottom,
    Front,
    Back,
    Left,
    Right,
    /// From the front-right corner, 35.26° up (the isometric angle, atan(1/√2)).
    Iso,
}

impl NamedView {
    pub const ALL: [NamedView; 7] = [
        NamedView::Top,
        NamedView::Bottom,
        NamedView::Front,
        NamedView::Back,
        NamedView::Left,
        NamedView::Right,
        NamedView::Iso,
    ];

    pub fn name(self) -> &'static str {
        match self {
            NamedView::Top => "top",
            NamedView::Bottom => "bottom",
            NamedView::Front => "front",
            NamedView::Back => "back",
            NamedView::Left => "left",
            NamedView::Right => "right",
            NamedView::Iso => "iso",
        }
    }

    /// (azimuth, elevation) in degrees.
    pub fn angles(self) -> (f32, f32) {
        match self {
            NamedView::Top => (0.0, 90.0),
            NamedView::Bottom => (0.0, -90.0),
            NamedView::Front => (0.0, 0.0),
            NamedView::Back => (180.0, 0.0),
            NamedView::Left => (-90.0, 0.0),
            NamedView::Right => (90.0, 0.0),
            NamedView::Iso => (45.0, (1.0f32 / 2.0f32.sqrt()).atan().to_degrees()),
        }
    }
}

impl FromStr for NamedView {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        NamedView::ALL
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| format!("'{s}' is not a view; use top, bottom, front, back, left, right or iso"))
    }
}
