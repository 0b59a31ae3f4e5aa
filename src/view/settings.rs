//! What a frame is rendered with: the mode, its quality level and parameters.
//! Plain data, shared by the GPU modes and the CPU reference.

use super::{Shading, SplatKernel};

/// The rendering algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderMode {
    /// Botsch & Kobbelt's 2+1-pass pipeline: ε-offset visibility, accumulation, normalisation.
    TwoPass,
    /// Zhang & Pajarola's deferred blending: one geometry pass into K group
    /// images, then ε-z compositing and deferred shading (1+1 passes).
    Deferred,
    /// The exact A-buffer renderer on the CPU: the ground truth for error.
    Reference,
}

impl RenderMode {
    pub const ALL: [RenderMode; 3] = [RenderMode::TwoPass, RenderMode::Deferred, RenderMode::Reference];

    pub fn name(self) -> &'static str {
        match self {
            RenderMode::TwoPass => "two-pass",
            RenderMode::Deferred => "deferred",
            RenderMode::Reference => "reference",
        }
    }

    /// Whether the mode runs on the GPU.
    pub fn is_gpu(self) -> bool {
        !matches!(self, RenderMode::Reference)
    }
}

impl std::fmt::Display for RenderMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for RenderMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        RenderMode::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| {
            let names: Vec<_> = RenderMode::ALL.iter().map(|m| m.name()).collect();
            format!("unknown mode '{s}'; available: {}", names.join(", "))
        })
    }
}

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
    pub backface_culling: bool,
    /// Every splat radius is multiplied by this (1: as loaded).
    pub radius_scale: f32,
    /// Voronoi rasterisation in the deferred geometry pass (Zhang & Pajarola Eq. 14).
    pub voronoi: bool,
    /// Phong lighting; without it the normalised colour is shown and no
    /// normal targets are allocated or written.
    pub lighting: bool,
    pub kernel: SplatKernel,
    pub shading: Shading,
}

impl RenderSettings {
    /// ε in view-depth units for a cloud whose mean splat radius is `mean_radius`.
    pub fn epsilon(&self, mean_radius: f32) -> f32 {
        self.epsilon_scale * mean_radius
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            mode: RenderMode::TwoPass,
            quality: Quality::Filtered,
            epsilon_scale: 1.0,
            backface_culling: true,
            radius_scale: 1.0,
            voronoi: true,
            lighting: true,
            kernel: SplatKernel::default(),
            shading: Shading::default(),
        }
    }
}
