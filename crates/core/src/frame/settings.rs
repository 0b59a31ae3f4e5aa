//! What a frame is rendered with besides the camera: the mode, its quality
//! level and parameters. Plain data, shared by the GPU modes and the CPU reference.

use super::{RenderMode, Shading, SplatKernel};
use crate::grouping::GroupingSpec;

/// Botsch & Kobbelt §5's two quality levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quality {
    /// Gaussian-weighted blending of splats within ε (2+1 passes).
    #[default]
    Filtered,
    /// Elliptical splats, nearest wins, no blending (1+1 passes).
    Unfiltered,
}

/// Everything besides the camera that decides a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    pub mode: RenderMode,
    pub quality: Quality,
    /// ε of the visibility pass, as a multiple of the cloud's mean splat radius.
    pub epsilon_scale: f32,
    /// Eq. 10's low-precision depth step, as a multiple of ε: n = (d_max −
    /// d_min)/(step·ε). 1 is the paper's n; see [`DEFAULT_DEPTH_STEP`].
    pub depth_step: f32,
    pub backface_culling: bool,
    /// Every splat radius is multiplied by this (1: as loaded).
    pub radius_scale: f32,
    /// Far splats are drawn at least this many pixels in radius (0: as
    /// they are); see [`Self::pixel_radius_floor`].
    pub min_pixel_radius: f32,
    /// How modes that draw groups split the splats (the paper's opaque setting: MGC at c = 0.4).
    pub grouping: GroupingSpec,
    /// Voronoi rasterisation in the group images (Zhang & Pajarola Eq. 14).
    pub voronoi: bool,
    /// Phong lighting; without it the normalised colour is shown and no
    /// normal targets are allocated or written.
    pub lighting: bool,
    /// Eye-dome lighting of the nearest surface's depth (opaque modes), or none.
    pub eye_dome: Option<super::EyeDome>,
    /// Transparent layers k of a peeling mode; 0 leaves it to the mode's default.
    pub peel_layers: u32,
    pub kernel: SplatKernel,
    pub shading: Shading,
    /// Reflection and refraction of the scene's environment map, when it has one.
    pub environment: crate::frame::environment_effects::EnvironmentSettings,
    /// How modes that blend in order sort the splats back to front.
    pub order: crate::spatial::order::OrderKind,
    /// Scene lights (world space); none: the headlight of `shading`.
    pub lights: super::Lights,
    /// How lit splats find the light that reaches them.
    pub shadows: super::ShadowSettings,
    /// The splat passes' screen-space low-pass filter (Guennebaud's EWA approximation).
    pub prefilter: super::Prefilter,
    /// Rays per pixel of the reference, per side (N×N, box-filtered); 1 casts one through the centre.
    pub supersample: u32,
    /// Most splats a GPU frame draws, chosen from the multi-resolution
    /// hierarchy ([`crate::lod`]) by screen-space error; `None` draws every splat.
    pub point_budget: Option<u32>,
    /// A hybrid object's leaf is drawn as triangles where its largest splat
    /// would be wider than this radius in pixels ([`crate::hybrid::select`]).
    pub hybrid_pixels: f32,
    /// What is cut away, per pixel, in the flattened scene's frame (see [`super::clip`]).
    pub clip: super::Clip,
}

/// The default of [`RenderSettings::hybrid_pixels`]: a hybrid leaf is drawn
/// as triangles where its splats would be wider than 3 px in radius. On
/// lavapipe the rasterising modes draw the bunny's triangles faster than its
/// splats at every bench view at 512², `tiled` only close up
/// (docs/BENCHMARKS.md); the threshold is set by quality: splats of a few
/// pixels blend as well as the reference.
pub const DEFAULT_HYBRID_PIXELS: f32 = 3.0;

/// Most rays per pixel side of a supersampled reference.
pub const MAX_SUPERSAMPLE: u32 = 16;

/// Largest image side any mode renders, the CPU reference too (its buffers
/// grow with the pixel count).
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Largest splat radius scale (the viewer's slider reaches 3).
pub const MAX_RADIUS_SCALE: f32 = 100.0;

/// Checks an image size: each side 1..=[`MAX_IMAGE_SIDE`].
pub fn check_image_size(width: u32, height: u32) -> Result<(), String> {
    if width == 0 || height == 0 || width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE {
        return Err(format!("{width}x{height}: each side must be 1..={MAX_IMAGE_SIDE}"));
    }
    Ok(())
}

/// The smallest radius a splat is drawn with, per unit of view depth, in an
/// image `height` pixels high whose window's half height is `half_y`
/// (`Camera::half_extent_y`: tan(fov_y / 2) in perspective):
/// `min_pixel_radius` pixels at that depth (`--min-pixel-radius`; 0 when
/// unset). Every renderer applies it to the splat's disc in its own plane,
/// max(r · scale, this · depth), before the EWA prefilter stretches what is
/// still smaller than the low-pass radius: with a floor at or above the
/// prefilter's radius the filter has nothing left to stretch. In
/// orthographic `half_y` is in eye units, and so is the floor, at any depth.
pub fn pixel_radius_floor(min_pixel_radius: f32, half_y: f32, height: u32) -> f32 {
    min_pixel_radius * 2.0 * half_y / height.max(1) as f32
}

/// The default Eq. 10 step, in multiples of ε. A layer whose fragments
/// straddle a step boundary is blended twice in one group image (alg1,
/// alg2's other layers); a coarser step straddles less often but merges
/// layers less than a step apart. Measured on six scenes (docs/BENCHMARKS.md,
/// 2026-11-24, "Eq. 10's step"), with the facing split and the α-trimmed
/// mean in place.
pub const DEFAULT_DEPTH_STEP: f32 = 1.25;

/// Most layers a peeling mode draws.
pub const MAX_PEEL_LAYERS: u32 = 64;

impl RenderSettings {
    /// The checks every source of settings goes through (the command line's
    /// flags, a screenshot's sidecar): values a frame can be drawn with.
    pub fn check(&self) -> Result<(), String> {
        if !(self.epsilon_scale.is_finite() && self.epsilon_scale > 0.0) {
            return Err(format!(
                "epsilon (--epsilon) must be a positive multiple of the mean splat radius, not {} (at 0 no two splats would blend)",
                self.epsilon_scale
            ));
        }
        if !(self.depth_step.is_finite() && self.depth_step > 0.0) {
            return Err(format!(
                "the depth step (--depth-step) must be a positive multiple of ε, not {}",
                self.depth_step
            ));
        }
        if !(self.radius_scale > 0.0 && self.radius_scale <= MAX_RADIUS_SCALE) {
            return Err(format!("the radius scale must be in (0, {MAX_RADIUS_SCALE}], not {}", self.radius_scale));
        }
        if self.point_budget == Some(0) {
            return Err("the point budget (--point-budget) must be at least 1 splat".into());
        }
        if !(1..=MAX_SUPERSAMPLE).contains(&self.supersample) {
            return Err(format!("supersample (--supersample) must be 1..={MAX_SUPERSAMPLE}, not {}", self.supersample));
        }
        if self.hybrid_pixels.is_nan() || self.hybrid_pixels < 0.0 {
            return Err(format!("hybrid-px (--hybrid-px) must be 0 or more, not {}", self.hybrid_pixels));
        }
        Ok(())
    }

    /// These settings with no point budget: what a frame whose splats were
    /// already chosen (under a budget, or beside a hybrid object's triangles) is drawn with.
    pub fn without_budget(&self) -> Self {
        RenderSettings { point_budget: None, ..*self }
    }

    /// The layers k the mode draws: the setting, else the registry's default for the mode.
    pub fn peel_layers_or_default(&self) -> u32 {
        if self.peel_layers == 0 { self.mode.info().default_peel_layers } else { self.peel_layers }
    }

    /// The grouping the mode draws. Modes whose groups must cover the surface
    /// (`alg1`) draw their own grouping in place of the opaque default, and
    /// add its extension (§4.4.2) to any other grouping that names none.
    pub fn grouping_for_mode(&self) -> GroupingSpec {
        match self.mode.info().covering_grouping {
            None => self.grouping,
            Some(own) if self.grouping == GroupingSpec::default() => own,
            Some(own) if self.grouping.extension == crate::grouping::Extension::None => {
                self.grouping.extended(own.extension)
            }
            Some(_) => self.grouping,
        }
    }

    /// Whether a frame of these settings draws a scene's environment map:
    /// the mode draws the effects (registry) and they are on.
    pub fn draws_environment(&self) -> bool {
        self.environment.enabled && self.mode.info().environment
    }

    /// The low-pass radius in pixels the splat passes stretch to: the
    /// prefilter's, where the mode reads it (the registry lists it), else 0.
    pub fn low_pass_radius_px(&self) -> f32 {
        if self.mode.parameters().contains(&super::Parameter::Prefilter) { self.prefilter.radius_px() } else { 0.0 }
    }

    /// Whether the frame is lit by scene lights (and their shadows) rather
    /// than the headlight.
    pub fn lit_by_lights(&self) -> bool {
        self.lighting && !self.lights.is_empty()
    }

    /// The eye-dome lighting a frame of these settings draws: asked for, and
    /// read by the mode (a transparent mode drawing an opaque scene with the
    /// two-pass plan, or `tiled`, does not).
    pub fn eye_dome_drawn(&self) -> Option<super::EyeDome> {
        self.eye_dome.filter(|_| self.mode.reads(super::Parameter::EyeDome))
    }

    /// [`pixel_radius_floor`] of these settings' `min_pixel_radius`.
    pub fn pixel_radius_floor(&self, half_y: f32, height: u32) -> f32 {
        pixel_radius_floor(self.min_pixel_radius, half_y, height)
    }

    /// ε in view-depth units for a cloud whose mean splat radius is `mean_radius`.
    pub fn epsilon(&self, mean_radius: f32) -> f32 {
        self.epsilon_scale * mean_radius
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            mode: RenderMode::DEFAULT,
            quality: Quality::Filtered,
            epsilon_scale: 1.0,
            depth_step: DEFAULT_DEPTH_STEP,
            backface_culling: true,
            radius_scale: 1.0,
            min_pixel_radius: 0.0,
            grouping: GroupingSpec::default(),
            voronoi: true,
            lighting: true,
            eye_dome: None,
            peel_layers: 0,
            kernel: SplatKernel::default(),
            shading: Shading::default(),
            environment: Default::default(),
            order: crate::spatial::order::OrderKind::Bucket,
            lights: Default::default(),
            shadows: Default::default(),
            prefilter: Default::default(),
            supersample: 1,
            point_budget: None,
            hybrid_pixels: DEFAULT_HYBRID_PIXELS,
            clip: Default::default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alg1_draws_covering_groups_and_other_modes_the_grouping_as_set() {
        let with = |mode: &str, group: &str| RenderSettings {
            mode: mode.parse().unwrap(),
            grouping: group.parse().unwrap(),
            ..Default::default()
        };
        let drawn = |mode: &str, group: &str| with(mode, group).grouping_for_mode().to_string();
        assert_eq!(drawn("deferred", "mgc-c0.4"), "mgc-c0.4");
        assert_eq!(drawn("alg1", "mgc-c0.4"), "wgc-k4-radius", "the opaque default is replaced");
        assert_eq!(drawn("alg1", "hash-k8"), "hash-k8-radius", "an extension is added");
        assert_eq!(drawn("alg1", "wgc-k4-dup"), "wgc-k4-dup", "a named extension is kept");
    }
}
