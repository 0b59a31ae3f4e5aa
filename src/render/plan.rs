//! The render plan: which passes and targets a frame needs, and nothing more.
//!
//! The renderer runs exactly the passes listed here, so `--explain` and the
//! viewer show what really happens.

use crate::view::settings::{Quality, RenderMode, RenderSettings};

/// One pass of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassKind {
    /// Depth only, pushed back by ε.
    Visibility,
    /// Additive Σw·colour, Σw·normal, Σw for fragments within ε of the front.
    Accumulate,
    /// Nearest elliptical splat wins (unfiltered quality).
    NearestSplat,
    /// Full-screen divide by Σw and shade.
    Normalize,
}

impl PassKind {
    pub fn draws_splats(self) -> bool {
        !matches!(self, PassKind::Normalize)
    }

    pub fn label(self) -> &'static str {
        match self {
            PassKind::Visibility => "visibility",
            PassKind::Accumulate => "accumulate",
            PassKind::NearestSplat => "nearest-splat",
            PassKind::Normalize => "normalize",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            PassKind::Visibility => "splats -> depth (linear f32, +ε)",
            PassKind::Accumulate => "splats -> Σw·rgb,Σw + Σw·n (additive, ε depth test, no depth write)",
            PassKind::NearestSplat => "splats -> rgb,1 + n (depth test and write, no blending)",
            PassKind::Normalize => "full screen: divide by Σw, Phong shading -> output",
        }
    }
}

/// A texture a frame allocates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedTarget {
    pub name: &'static str,
    pub format: &'static str,
    pub bytes_per_pixel: u32,
}

/// The passes and targets of one frame.
#[derive(Debug, Clone)]
pub struct RenderPlan {
    pub mode: RenderMode,
    pub quality: Quality,
    pub width: u32,
    pub height: u32,
    pub splats: usize,
    pub epsilon: f32,
    pub passes: Vec<PassKind>,
    pub targets: Vec<PlannedTarget>,
}

impl RenderPlan {
    pub fn new(settings: &RenderSettings, width: u32, height: u32, splats: usize, epsilon: f32) -> Self {
        let passes = match (settings.mode, settings.quality) {
            (RenderMode::TwoPass, Quality::Filtered) => {
                vec![PassKind::Visibility, PassKind::Accumulate, PassKind::Normalize]
            }
            (RenderMode::TwoPass, Quality::Unfiltered) => vec![PassKind::NearestSplat, PassKind::Normalize],
            (RenderMode::Reference, _) => Vec::new(),
        };
        let targets = if passes.is_empty() {
            Vec::new()
        } else {
            vec![
                PlannedTarget { name: "depth", format: "Depth32Float", bytes_per_pixel: 4 },
                PlannedTarget { name: "accumulated colour (Σw·rgb, Σw)", format: "Rgba16Float", bytes_per_pixel: 8 },
                PlannedTarget {
                    name: "accumulated normal (Σw·n, Σw·α)", format: "Rgba16Float", bytes_per_pixel: 8
                },
            ]
        };
        Self { mode: settings.mode, quality: settings.quality, width, height, splats, epsilon, passes, targets }
    }

    /// Passes that draw the splats (the "2" of "2+1").
    pub fn geometry_passes(&self) -> usize {
        self.passes.iter().filter(|p| p.draws_splats()).count()
    }

    /// Bytes of all intermediate targets.
    pub fn target_bytes(&self) -> u64 {
        let pixels = self.width as u64 * self.height as u64;
        self.targets.iter().map(|t| t.bytes_per_pixel as u64 * pixels).sum()
    }
}

impl std::fmt::Display for RenderPlan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.passes.is_empty() {
            return write!(
                f,
                "mode {}: exact A-buffer ray casting on the CPU, {} splats, {}x{}, ε = {:.4e}; no GPU passes",
                self.mode, self.splats, self.width, self.height, self.epsilon
            );
        }
        let full = self.passes.len() - self.geometry_passes();
        writeln!(
            f,
            "mode {} ({:?}): {} geometry + {} full-screen passes, {} splats, {}x{}, ε = {:.4e}",
            self.mode,
            self.quality,
            self.geometry_passes(),
            full,
            self.splats,
            self.width,
            self.height,
            self.epsilon
        )?;
        for (i, pass) in self.passes.iter().enumerate() {
            writeln!(f, "  pass {}: {:<14} {}", i + 1, pass.label(), pass.describe())?;
        }
        for t in &self.targets {
            writeln!(f, "  target: {:<34} {}", t.name, t.format)?;
        }
        write!(f, "  target memory: {:.1} MiB", self.target_bytes() as f64 / (1u64 << 20) as f64)
    }
}
