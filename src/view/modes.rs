//! The mode registry: every render mode, what it is, which parameters it
//! reads, where it runs, which mode previews it, and the variants `bench`
//! runs by default.
//!
//! This file and the mode files (`src/render/modes/*.rs`, where the GPU modes
//! plan and record their passes) are the only places that name a particular
//! mode. The CLI, `bench`, the viewer and the sidecars read the registry:
//! they iterate [`RenderMode::ALL`] and ask a mode for its [`ModeInfo`].
//! Adding a mode means one entry here and one mode file.

use super::parameters::Parameter;

/// A rendering algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RenderMode {
    /// Botsch & Kobbelt's 2+1-pass pipeline: ε-offset visibility, accumulation, normalisation.
    TwoPass,
    /// Zhang & Pajarola's deferred blending: one geometry pass into K group
    /// images, then ε-z compositing and deferred shading (1+1 passes).
    Deferred,
    /// The exact A-buffer renderer on the CPU: the ground truth for error.
    Reference,
}

/// Where a mode runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Device {
    Gpu,
    Cpu,
}

/// What the registry knows of a mode.
#[derive(Debug)]
pub struct ModeInfo {
    pub mode: RenderMode,
    /// The name on the command line, in files and in the viewer.
    pub name: &'static str,
    /// One sentence on what the mode does.
    pub description: &'static str,
    /// The settings it reads, in display order.
    pub parameters: &'static [Parameter],
    pub device: Device,
    /// The mode drawn (on a subsample) while the camera moves.
    pub preview: RenderMode,
    /// What a plain `bench --modes NAME` runs: one row per entry, each a
    /// list of `key=value` settings (see [`Parameter::key`]); "" is the defaults.
    pub bench_variants: &'static [&'static str],
}

const REGISTRY: [ModeInfo; 3] = [
    ModeInfo {
        mode: RenderMode::TwoPass,
        name: "two-pass",
        description: "Botsch & Kobbelt: ε-offset visibility, additive blending, normalisation (2+1 passes).",
        parameters: &[
            Parameter::Quality,
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Background,
        ],
        device: Device::Gpu,
        preview: RenderMode::TwoPass,
        bench_variants: &["", "quality=unfiltered"],
    },
    ModeInfo {
        mode: RenderMode::Deferred,
        name: "deferred",
        description: "Zhang & Pajarola: one geometry pass into K group images, then ε-z compositing (1+1 passes).",
        parameters: &[
            Parameter::Grouping,
            Parameter::Voronoi,
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Background,
        ],
        device: Device::Gpu,
        preview: RenderMode::TwoPass,
        bench_variants: &[""],
    },
    ModeInfo {
        mode: RenderMode::Reference,
        name: "reference",
        description: "Exact A-buffer ray casting on the CPU: the ground truth for error (slow).",
        parameters: &[
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Background,
        ],
        device: Device::Cpu,
        preview: RenderMode::TwoPass,
        bench_variants: &[""],
    },
];

impl RenderMode {
    pub const ALL: [RenderMode; 3] = [RenderMode::TwoPass, RenderMode::Deferred, RenderMode::Reference];

    /// The mode pointblend starts in when nothing else is asked for.
    pub const DEFAULT: RenderMode = RenderMode::TwoPass;

    /// The mode that measures every other: the exact reference.
    pub const RULER: RenderMode = RenderMode::Reference;

    pub fn info(self) -> &'static ModeInfo {
        // The registry lists the modes in the order of `ALL`.
        &REGISTRY[RenderMode::ALL.iter().position(|m| *m == self).unwrap_or(0)]
    }

    pub fn name(self) -> &'static str {
        self.info().name
    }

    pub fn description(self) -> &'static str {
        self.info().description
    }

    pub fn parameters(self) -> &'static [Parameter] {
        self.info().parameters
    }

    /// Whether the mode runs on the GPU.
    pub fn is_gpu(self) -> bool {
        self.info().device == Device::Gpu
    }

    /// Whether the mode draws groups (and so needs a grouping before it can render).
    pub fn needs_grouping(self) -> bool {
        self.parameters().contains(&Parameter::Grouping)
    }

    /// Whether the mode reads `parameter`.
    pub fn reads(self, parameter: Parameter) -> bool {
        self.parameters().contains(&parameter)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_describes_every_mode_once_in_order() {
        assert_eq!(REGISTRY.len(), RenderMode::ALL.len());
        for (info, mode) in REGISTRY.iter().zip(RenderMode::ALL) {
            assert_eq!(info.mode, mode);
            assert!(!info.description.is_empty() && !info.parameters.is_empty(), "{mode}");
            assert!(!info.bench_variants.is_empty(), "{mode}");
            assert!(info.preview.is_gpu(), "{mode} previews with a GPU mode");
            assert_eq!(mode.name().parse::<RenderMode>(), Ok(mode));
        }
        assert!(RenderMode::RULER.info().device == Device::Cpu);
    }
}
