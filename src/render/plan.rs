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
    /// One render pass per group k into layer k (deferred blending's single geometry traversal).
    DeferredGeometry,
    /// Full-screen ε-z compositing of the K group images, normalisation and shading.
    DeferredComposite,
}

impl PassKind {
    pub fn draws_splats(self) -> bool {
        !matches!(self, PassKind::Normalize | PassKind::DeferredComposite)
    }

    pub fn label(self) -> &'static str {
        match self {
            PassKind::Visibility => "visibility",
            PassKind::Accumulate => "accumulate",
            PassKind::NearestSplat => "nearest-splat",
            PassKind::Normalize => "normalize",
            PassKind::DeferredGeometry => "group images",
            PassKind::DeferredComposite => "composite",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            PassKind::Visibility => "splats -> depth (linear f32, +ε)",
            PassKind::Accumulate => "splats -> Σw·rgb,Σw + Σw·n (additive, ε depth test, no depth write)",
            PassKind::NearestSplat => "splats -> rgb,1 + n (depth test and write, no blending)",
            PassKind::Normalize => "full screen: divide by Σw, Phong shading -> output",
            PassKind::DeferredGeometry => "splats of group k -> layer k: w·rgb,w + w·n + depth (z-test per group)",
            PassKind::DeferredComposite => "full screen: d = min_k depth_k, sum layers within d+ε, normalise, shade",
        }
    }
}

/// A texture a frame allocates.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlannedTarget {
    pub name: &'static str,
    pub format: &'static str,
    pub bytes_per_pixel: u32,
    /// Array layers (1, or K for the group images).
    pub layers: u32,
    /// Why the frame needs it.
    pub why: &'static str,
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
    /// Groups K (1 unless the mode draws groups).
    pub groups: usize,
    /// Render passes that draw splats (K for the group images).
    pub geometry_render_passes: usize,
    pub passes: Vec<PassKind>,
    pub targets: Vec<PlannedTarget>,
}

impl RenderPlan {
    /// `weight_only`: the cloud has one colour, so colour targets hold only Σw.
    pub fn new(
        settings: &RenderSettings,
        width: u32,
        height: u32,
        splats: usize,
        epsilon: f32,
        groups: usize,
        weight_only: bool,
    ) -> Self {
        let target =
            |name, format, bytes_per_pixel, layers, why| PlannedTarget { name, format, bytes_per_pixel, layers, why };
        let two_pass_targets = || {
            vec![
                target("depth", "Depth32Float", 4, 1, "linear view depth for the ε test"),
                if weight_only {
                    target("accumulated weight (Σw)", "R16Float", 2, 1, "additive blending; the cloud has one colour")
                } else {
                    target("accumulated colour (Σw·rgb, Σw)", "Rgba16Float", 8, 1, "additive blending target")
                },
                target("accumulated normal (Σw·n, Σw·α)", "Rgba16Float", 8, 1, "normal for deferred shading"),
            ]
        };
        let k = groups.max(1);
        let (passes, targets, groups) = match (settings.mode, settings.quality) {
            (RenderMode::TwoPass, Quality::Filtered) => {
                (vec![PassKind::Visibility, PassKind::Accumulate, PassKind::Normalize], two_pass_targets(), 1)
            }
            (RenderMode::TwoPass, Quality::Unfiltered) => {
                (vec![PassKind::NearestSplat, PassKind::Normalize], two_pass_targets(), 1)
            }
            (RenderMode::Deferred, _) => (
                vec![PassKind::DeferredGeometry, PassKind::DeferredComposite],
                vec![
                    if weight_only {
                        target("group weight (w)", "R16Float", 2, k as u32, "Eq. 4's weight; the cloud has one colour")
                    } else {
                        target(
                            "group colour (w·rgb, w)",
                            "Rgba16Float",
                            8,
                            k as u32,
                            "Eq. 4: each group's weighted colour",
                        )
                    },
                    target("group normal (w·n, w·α)", "Rgba16Float", 8, k as u32, "normal for deferred shading"),
                    target("group depth", "R32Float", 4, k as u32, "true view depth for the ε-z test of Fig. 6"),
                    target(
                        "group z-buffer",
                        "Depth32Float",
                        4,
                        k as u32,
                        "z-test within each group (Voronoi depth if on)",
                    ),
                ],
                k,
            ),
            (RenderMode::Reference, _) => (Vec::new(), Vec::new(), 1),
        };
        let geometry_render_passes = passes
            .iter()
            .map(|p| match p {
                PassKind::DeferredGeometry => groups,
                p if p.draws_splats() => 1,
                _ => 0,
            })
            .sum();
        // Without lighting no normal is needed: its targets are not allocated.
        let targets = if settings.lighting {
            targets
        } else {
            targets.into_iter().filter(|t| !t.name.contains("normal")).collect()
        };
        Self {
            mode: settings.mode,
            quality: settings.quality,
            width,
            height,
            splats,
            epsilon,
            groups,
            geometry_render_passes,
            passes,
            targets,
        }
    }

    /// Passes that draw the splats (the "2" of "2+1").
    pub fn geometry_passes(&self) -> usize {
        self.passes.iter().filter(|p| p.draws_splats()).count()
    }

    /// Checks that this device can hold the plan's targets: array layers
    /// within its limit, bytes within `budget` (see `GpuContext::target_budget`).
    pub fn check_fits(&self, limits: &wgpu::Limits, budget: u64) -> Result<(), super::GpuError> {
        let hint = "use a grouping with a fixed, small K (--group hash-k8 or wgc-k8)";
        let layers = self.targets.iter().map(|t| t.layers).max().unwrap_or(1);
        if layers > limits.max_texture_array_layers {
            return Err(super::GpuError::TooLarge(format!(
                "{} needs {layers} group layers, more than the {} texture layers this GPU allows; {hint}",
                self.mode, limits.max_texture_array_layers
            )));
        }
        let hint = format!("{hint} or a smaller --size");
        let bytes = self.target_bytes();
        if bytes > budget {
            return Err(super::GpuError::TooLarge(format!(
                "{} with K = {} at {}x{} needs {} of render targets, more than the {} this GPU can give (POINTBLEND_GPU_MEMORY_MB sets it); {hint}",
                self.mode,
                self.groups,
                self.width,
                self.height,
                crate::memory::gib(bytes),
                crate::memory::gib(budget)
            )));
        }
        Ok(())
    }

    /// Bytes of all intermediate targets.
    pub fn target_bytes(&self) -> u64 {
        let pixels = self.width as u64 * self.height as u64;
        self.targets.iter().map(|t| t.bytes_per_pixel as u64 * t.layers as u64 * pixels).sum()
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
        writeln!(
            f,
            "  {} groups; each splat is drawn {} time(s) per frame in {} render pass(es) with {} draw range(s)",
            self.groups,
            self.geometry_passes(),
            self.geometry_render_passes,
            self.geometry_render_passes
        )?;
        for (i, pass) in self.passes.iter().enumerate() {
            writeln!(f, "  pass {}: {:<14} {}", i + 1, pass.label(), pass.describe())?;
        }
        let pixels = self.width as f64 * self.height as f64;
        for t in &self.targets {
            writeln!(
                f,
                "  target: {:<34} {:<13} x{:<3} {:>7.1} MiB  ({})",
                t.name,
                t.format,
                t.layers,
                t.bytes_per_pixel as f64 * t.layers as f64 * pixels / (1u64 << 20) as f64,
                t.why
            )?;
        }
        write!(f, "  target memory: {:.1} MiB", self.target_bytes() as f64 / (1u64 << 20) as f64)
    }
}
