//! The mode registry: every render mode, what it is, which parameters it
//! reads (and their defaults), where it runs, and what it can draw
//! (transparency, groups, triangles, the environment). Front-end policy is
//! not here: the viewer's preview rule is `src/viewer/preview.rs`, and what
//! a plain mode name stands for in `bench` is `src/bench/variants.rs`.
//!
//! This file and the mode files (`crates/render/src/modes/*.rs`, where the
//! GPU modes plan their steps) are the only places that name a particular
//! mode. The CLI, `bench`, the viewer and the sidecars read the registry:
//! they iterate [`RenderMode::ALL`] and ask a mode for its [`ModeInfo`].
//! Adding a mode means one entry here and one mode file
//! (docs/ADDING_A_MODE.md).

use super::parameters::Parameter;
use crate::grouping::{Extension, GroupingAlgo, GroupingSpec, Relaxations};

/// A rendering algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RenderMode {
    /// Botsch & Kobbelt's 2+1-pass pipeline: ε-offset visibility, accumulation, normalisation.
    TwoPass,
    /// Zhang & Pajarola's deferred blending: one geometry pass into K group
    /// images, then ε-z compositing and deferred shading (1+1 passes).
    Deferred,
    /// Exact depth peeling of k transparent layers (the baseline of Zhang & Pajarola's Fig. 17).
    DepthPeel,
    /// Guennebaud's approximate depth peeling: k - 1 exact layers and one approximate.
    ApproxPeel,
    /// Zhang & Pajarola's Algorithm-1: each group back to front into its own
    /// image, then the average of the images (1+1 passes).
    Alg1,
    /// Zhang & Pajarola's Algorithm-2: the nearest layer as `deferred` draws
    /// it, the others as Algorithm-1 does, composited in one pass (2+1 passes).
    Alg2,
    /// Plain α-blending: every splat back to front over the ones behind, no
    /// culling; the double-blending baseline of Zhang & Pajarola §5.2.
    AlphaBlend,
    /// The exact reference's algorithm on the GPU: splats binned into screen
    /// tiles by compute passes, per-pixel ε-layers in depth order, composited
    /// front to back.
    Tiled,
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
    /// Whether it reads opacity (draws transparency); opaque modes draw every splat opaque.
    pub transparent: bool,
    /// Layers k it draws when the settings leave it open (modes that read `Parameter::PeelLayers`).
    pub default_peel_layers: u32,
    /// For modes whose groups must each cover the surface (§4.4.2): the
    /// grouping drawn when the settings hold the opaque default, and whose
    /// extension is added to any other grouping that names none.
    pub covering_grouping: Option<GroupingSpec>,
    /// For a transparent mode: whether it draws a scene with nothing
    /// transparent with its own plan (else it runs the two-pass plan).
    pub draws_opaque_scenes: bool,
    /// Whether it draws the environment effects (reflection, refraction,
    /// Fresnel, dispersion, absorption; Zhang & Pajarola §5.2.3) of a scene
    /// with an environment map. The others refuse such a scene.
    pub environment: bool,
    /// Whether it draws mesh triangles (`mesh` and `hybrid` scene objects,
    /// [`crate::hybrid`]); the others draw those objects as their vertex splats, and say so.
    pub triangles: bool,
}

/// Algorithm-1's grouping: WGC with K = 4 and radius enlargement, the best of
/// the paper's choices on our scans (the comparison is in docs/BENCHMARKS.md).
const ALG1_GROUPING: GroupingSpec = GroupingSpec {
    algo: GroupingAlgo::Wgc { k: 4, eq7: false },
    relax: Relaxations { coplanar: false, opposite: false },
    extension: Extension::Enlarge,
};

const REGISTRY: [ModeInfo; 9] = [
    ModeInfo {
        mode: RenderMode::TwoPass,
        name: "two-pass",
        description: "Botsch & Kobbelt: ε-offset visibility, additive blending, normalisation (2+1 passes).",
        parameters: &[
            Parameter::Quality,
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::HybridPixels,
            Parameter::Prefilter,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::EyeDome,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: false,
        default_peel_layers: 1,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: true,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::Deferred,
        name: "deferred",
        description: "Zhang & Pajarola: one geometry pass into K group images, then ε-z compositing (1+1 passes).",
        parameters: &[
            Parameter::Grouping,
            Parameter::Voronoi,
            Parameter::Epsilon,
            Parameter::DepthStep,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::HybridPixels,
            Parameter::Prefilter,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::EyeDome,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: false,
        default_peel_layers: 1,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: true,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::DepthPeel,
        name: "depth-peel",
        description: "Depth peeling: k layers, each a full splat render behind the one before, composited front to back (k × (2+1) passes).",
        parameters: &[
            Parameter::PeelLayers,
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::HybridPixels,
            Parameter::Prefilter,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 8,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: true,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::ApproxPeel,
        name: "approx-peel",
        description: "Guennebaud: k - 1 exactly peeled layers, then all the rest blended into one approximate layer.",
        parameters: &[
            Parameter::PeelLayers,
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::Prefilter,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 3,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: false,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::Alg1,
        name: "alg1",
        description: "Zhang & Pajarola Algorithm-1: each group back to front into its own image (one geometry pass), then their average (1+1 passes).",
        parameters: &[
            Parameter::Grouping,
            Parameter::Order,
            Parameter::Epsilon,
            Parameter::DepthStep,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 1,
        covering_grouping: Some(ALG1_GROUPING),
        draws_opaque_scenes: false,
        triangles: false,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::Alg2,
        name: "alg2",
        description: "Zhang & Pajarola Algorithm-2: the nearest layer in high quality (deferred blending), the layers behind as Algorithm-1 draws them (2+1 passes).",
        parameters: &[
            Parameter::Grouping,
            Parameter::Voronoi,
            Parameter::Order,
            Parameter::Epsilon,
            Parameter::DepthStep,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
            Parameter::EnvironmentLayers,
            Parameter::Eta,
            Parameter::Dispersion,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 1,
        covering_grouping: Some(ALG1_GROUPING),
        draws_opaque_scenes: false,
        triangles: false,
        environment: true,
    },
    ModeInfo {
        mode: RenderMode::AlphaBlend,
        name: "alpha-blend",
        description: "Plain α-blending: every splat back to front over the ones behind, no culling (1+1 passes); overlapping splats of one surface blend twice or more, the artefact Algorithm-1 and -2 remove.",
        parameters: &[
            Parameter::Order,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 1,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: false,
        environment: false,
    },
    ModeInfo {
        mode: RenderMode::Tiled,
        name: "tiled",
        description: "The exact reference on the GPU: splats binned into screen tiles and sorted by compute passes, every pixel's hits grouped into ε-layers in depth order and composited front to back, with no layer cap.",
        parameters: &[
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::PointBudget,
            Parameter::HybridPixels,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::Shadows,
            Parameter::Background,
            Parameter::EnvironmentLayers,
            Parameter::Eta,
            Parameter::Dispersion,
        ],
        device: Device::Gpu,
        transparent: true,
        default_peel_layers: 1,
        covering_grouping: None,
        draws_opaque_scenes: true,
        triangles: true,
        environment: true,
    },
    ModeInfo {
        mode: RenderMode::Reference,
        name: "reference",
        description: "Exact A-buffer ray casting on the CPU: the ground truth for error (slow).",
        parameters: &[
            Parameter::Epsilon,
            Parameter::RadiusScale,
            Parameter::MinPixelRadius,
            Parameter::Supersample,
            Parameter::BackfaceCulling,
            Parameter::Lighting,
            Parameter::EyeDome,
            Parameter::Background,
            Parameter::EnvironmentLayers,
            Parameter::Eta,
            Parameter::Dispersion,
        ],
        device: Device::Cpu,
        transparent: true,
        default_peel_layers: 1,
        covering_grouping: None,
        draws_opaque_scenes: false,
        triangles: true,
        environment: true,
    },
];

impl RenderMode {
    pub const ALL: [RenderMode; 9] = [
        RenderMode::TwoPass,
        RenderMode::Deferred,
        RenderMode::DepthPeel,
        RenderMode::ApproxPeel,
        RenderMode::Alg1,
        RenderMode::Alg2,
        RenderMode::AlphaBlend,
        RenderMode::Tiled,
        RenderMode::Reference,
    ];

    /// The mode pointblend starts in when nothing else is asked for.
    pub const DEFAULT: RenderMode = RenderMode::TwoPass;

    /// The mode that measures every other: the exact reference.
    pub const RULER: RenderMode = RenderMode::Reference;

    /// The mode `pointblend view` opens the demo scene in when given no
    /// file: the transparent mode whose first frame shows best what
    /// pointblend is for (see-through surfaces, near the reference, fast).
    pub const FIRST_RUN: RenderMode = RenderMode::Alg2;

    /// Whether this mode, given a scene with transparency or not, runs the
    /// opaque two-pass plan instead of its own: a transparent GPU mode on a
    /// scene with nothing transparent, unless it draws opaque scenes itself.
    /// The render core, bench and `render` all ask this.
    pub fn runs_opaque(self, scene_has_transparency: bool) -> bool {
        let info = self.info();
        info.transparent && self.is_gpu() && !info.draws_opaque_scenes && !scene_has_transparency
    }

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

    /// Whether the mode draws groups for a scene that is `transparent` or
    /// not: a transparent mode runs the ungrouped opaque plan for an opaque
    /// scene, and grouping it (with enlarged radii) would change that image.
    pub fn needs_grouping_for(self, transparent: bool) -> bool {
        self.needs_grouping() && (transparent || !self.info().transparent)
    }

    /// Whether the mode reads `parameter`.
    pub fn reads(self, parameter: Parameter) -> bool {
        self.parameters().contains(&parameter)
    }
}

crate::by_name!(RenderMode, "mode");

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_registry_describes_every_mode_once_in_order() {
        assert_eq!(REGISTRY.len(), RenderMode::ALL.len());
        for (info, mode) in REGISTRY.iter().zip(RenderMode::ALL) {
            assert_eq!(info.mode, mode);
            assert!(!info.description.is_empty() && !info.parameters.is_empty(), "{mode}");
            assert_eq!(mode.name().parse::<RenderMode>(), Ok(mode));
        }
        assert!(RenderMode::RULER.info().device == Device::Cpu);
    }
}
