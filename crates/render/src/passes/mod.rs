//! The kinds of pass every mode is built from, as data: a splat pass
//! ([`SplatPass`]) draws splats into targets, a full-screen pass
//! ([`FullscreenPass`]) reads targets and writes the frame (or a target),
//! and a compute pass ([`ComputePass`]) runs one stage of the tile pipeline.
//!
//! Visibility, accumulation, nearest-splat and group-layer passes differ only
//! in their fragment entry point, what they write, how they depth-test and
//! how they blend, so one builder ([`splat`]) makes all of them; the
//! normalisation and compositing passes share the other ([`fullscreen`]).
//! A mode's plan holds its frame as steps of [`Command`]s; the renderer runs
//! them, taking pipelines from the cache by their [`PipelineKey`].

pub mod compute;
pub mod fullscreen;
pub mod splat;

use std::ops::Range;

use super::gpu_data::PassUniforms;
use super::shaders::Variant;
use super::target_id::TargetId;

/// How a colour output combines with what the target holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Blend {
    /// The fragment replaces the texel.
    Replace,
    /// The fragment is added to the texel (sums of weights).
    Add,
    /// Front-to-back compositing of premultiplied colour: the fragment goes
    /// under what is there, dst + (1 - dst.a)·src.
    Under,
    /// Back-to-front α-blending of premultiplied colour: the fragment goes
    /// over what is there, src + (1 - src.a)·dst.
    Over,
    /// [`Blend::Over`] for the colour, and the opacities summed, α_total =
    /// Σα (blend factors ONE, ONE on the α channel): the layer count of
    /// Zhang & Pajarola §5.2.3, l = α_total / α.
    OverSumAlpha,
}

/// How a splat pass uses its depth target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct DepthTest {
    /// Whether passing fragments write their depth.
    pub write: bool,
    pub compare: wgpu::CompareFunction,
    /// Clear the depth target to the far plane first (else keep it).
    pub clear: bool,
}

/// A colour output of a splat pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColourOutput {
    pub target: TargetId,
    pub blend: Blend,
}

/// What every pipeline builder starts from (the splat, full-screen and
/// compute builders): the shader module, the fragment or compute entry
/// point, the pipeline layout and a label.
pub struct PipelineSource<'a> {
    pub device: &'a wgpu::Device,
    pub label: &'a str,
    pub layout: &'a wgpu::PipelineLayout,
    pub module: &'a wgpu::ShaderModule,
    pub entry: &'a str,
}

impl<'a> PipelineSource<'a> {
    /// The fragment stage of a render pipeline: the source's entry point, writing `targets`.
    pub fn fragment(&self, targets: &'a [Option<wgpu::ColorTargetState>]) -> wgpu::FragmentState<'a> {
        wgpu::FragmentState {
            module: self.module,
            entry_point: Some(self.entry),
            compilation_options: Default::default(),
            targets,
        }
    }
}

/// A bind group layout of `entries`' binding types at bindings 0.. in order,
/// visible to `stages`: every layout the passes bind (the frame's uniforms,
/// the full-screen and compute inputs, the environment map).
pub fn group_layout(
    device: &wgpu::Device,
    label: &str,
    stages: wgpu::ShaderStages,
    entries: impl Iterator<Item = wgpu::BindingType>,
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .enumerate()
        .map(|(binding, ty)| wgpu::BindGroupLayoutEntry {
            binding: binding as u32,
            visibility: stages,
            ty,
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries: &entries })
}

/// A render pass that draws splats.
#[derive(Debug, Clone, PartialEq)]
pub struct SplatPass {
    /// The render pass's label.
    pub label: &'static str,
    pub shader: &'static str,
    pub entry: &'static str,
    pub variant: Variant,
    /// Colour outputs, in `@location` order; cleared to zero first.
    pub colour: Vec<ColourOutput>,
    pub depth: Option<(TargetId, DepthTest)>,
    /// Targets the fragment stage reads, bound as textures at group 1, bindings 0.. in order.
    pub inputs: Vec<TargetId>,
    /// The layer of array targets to draw into (0 for single images).
    pub layer: u32,
    /// The splats to draw (indices into the uploaded scene).
    pub splats: Range<u32>,
    /// Whether they must be drawn back to front for the view (the renderer
    /// sorts the scene's instances first, in the order the settings choose).
    pub back_to_front: bool,
    pub uniforms: PassUniforms,
    /// Whether the pass also draws the frame's mesh triangles (after its
    /// splats, through the same fragment entry; none when the scene has none).
    pub triangles: bool,
}

/// Where a full-screen pass writes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Output {
    /// The frame's output view.
    Frame,
    Target(TargetId),
}

/// A render pass that covers the screen with one triangle.
#[derive(Debug, Clone, PartialEq)]
pub struct FullscreenPass {
    pub label: &'static str,
    pub shader: &'static str,
    pub entry: &'static str,
    pub variant: Variant,
    /// Targets bound as textures at group 1, bindings 0.. in order.
    pub inputs: Vec<TargetId>,
    pub output: Output,
    /// How the output combines with what is there.
    pub blend: Blend,
    /// Clear the output first (to black) rather than keep it.
    pub clear: bool,
    pub uniforms: PassUniforms,
}

impl FullscreenPass {
    /// A compositing pass into the frame's output: it reads `inputs` and
    /// replaces what the output held.
    pub fn into_frame(
        label: &'static str,
        (shader, entry): (&'static str, &'static str),
        variant: Variant,
        inputs: Vec<TargetId>,
        uniforms: PassUniforms,
    ) -> Self {
        Self {
            label,
            shader,
            entry,
            variant,
            inputs,
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms,
        }
    }

    /// A pass that computes an image into `target` from `inputs`, replacing
    /// what it held.
    pub fn into_target(
        label: &'static str,
        (shader, entry): (&'static str, &'static str),
        variant: Variant,
        inputs: Vec<TargetId>,
        target: TargetId,
        uniforms: PassUniforms,
    ) -> Self {
        Self { output: Output::Target(target), ..Self::into_frame(label, (shader, entry), variant, inputs, uniforms) }
    }

    /// A layer composited front to back under what `target` holds (cleared
    /// to transparent first when `clear`).
    pub fn under(
        label: &'static str,
        (shader, entry): (&'static str, &'static str),
        variant: Variant,
        inputs: Vec<TargetId>,
        (target, clear): (TargetId, bool),
        uniforms: PassUniforms,
    ) -> Self {
        Self {
            label,
            shader,
            entry,
            variant,
            inputs,
            output: Output::Target(target),
            blend: Blend::Under,
            clear,
            uniforms,
        }
    }
}

/// What a compute pass of the tile pipeline does (`tiled`; the buffers it
/// binds and the size of its dispatch are the tile engine's, see
/// `tile_engine.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TileWork {
    /// Per splat: eye space, footprint, covered tiles counted.
    Project,
    /// Per drawn mesh triangle, after the splats: covered tiles counted.
    ProjectTriangles,
    /// One workgroup: the counts' prefix sum into offsets, on the GPU,
    /// within the entry buffer's room (an overflow flag when past it).
    Scan,
    /// Per splat (and triangle): an entry in every covered tile's list.
    Bin,
    /// Per tile of a short list: sorted by nearest depth, one invocation each.
    SortShort,
    /// Per tile of a long list: sorted by nearest depth, one workgroup each.
    SortLong,
    /// Per tile, per pixel: ε-layers in depth order, composited.
    Raster,
}

/// A compute pass of the tile pipeline.
#[derive(Debug, Clone, PartialEq)]
pub struct ComputePass {
    pub label: &'static str,
    pub shader: &'static str,
    pub entry: &'static str,
    pub variant: Variant,
    pub work: TileWork,
    /// Targets it writes as storage textures, at group 1 from binding 4 on
    /// (the raster's image and, with an environment map, its glass layers).
    pub outputs: Vec<TargetId>,
    pub uniforms: PassUniforms,
}

/// One pass of a recorded frame.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    Splats(SplatPass),
    Fullscreen(FullscreenPass),
    Compute(ComputePass),
}

impl Command {
    pub fn uniforms(&self) -> &PassUniforms {
        match self {
            Command::Splats(pass) => &pass.uniforms,
            Command::Fullscreen(pass) => &pass.uniforms,
            Command::Compute(pass) => &pass.uniforms,
        }
    }

    /// The WGSL root file its pipeline is built from.
    pub fn shader(&self) -> &'static str {
        match self {
            Command::Splats(pass) => pass.shader,
            Command::Fullscreen(pass) => pass.shader,
            Command::Compute(pass) => pass.shader,
        }
    }
}

/// What makes two pipelines the same: shader, entry point, variant, and the
/// formats and fixed-function state of what they write.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    pub shader: &'static str,
    pub entry: &'static str,
    pub variant: Variant,
    pub kind: PipelineKind,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum PipelineKind {
    Splats {
        colour: Vec<(wgpu::TextureFormat, Blend)>,
        depth: Option<(wgpu::TextureFormat, bool, wgpu::CompareFunction)>,
        inputs: Vec<wgpu::TextureViewDimension>,
        /// Cull triangles facing away by their winding (mesh triangles of
        /// one-sided objects only: splats are culled by their normals).
        cull_back: bool,
    },
    Fullscreen {
        inputs: Vec<wgpu::TextureViewDimension>,
        output: wgpu::TextureFormat,
        blend: Blend,
    },
}

impl PipelineKey {
    /// The same pass drawing the frame's mesh triangles: the TRIANGLES
    /// variant, culled by winding when the mesh is one-sided.
    pub fn for_triangles(&self, cull_back: bool) -> PipelineKey {
        let kind = match self.kind.clone() {
            PipelineKind::Splats { colour, depth, inputs, .. } => {
                PipelineKind::Splats { colour, depth, inputs, cull_back }
            }
            other => other,
        };
        PipelineKey { variant: self.variant.with(Variant::TRIANGLES, true), kind, ..self.clone() }
    }
}

impl PipelineKind {
    /// The dimensions of the textures it reads at group 1.
    pub fn inputs(&self) -> &[wgpu::TextureViewDimension] {
        match self {
            PipelineKind::Splats { inputs, .. } | PipelineKind::Fullscreen { inputs, .. } => inputs,
        }
    }
}

const ONE: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

const OVER: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
    operation: wgpu::BlendOperation::Add,
};

const UNDER: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

impl Blend {
    /// The blend state of a colour target.
    pub fn state(self) -> Option<wgpu::BlendState> {
        match self {
            Blend::Replace => None,
            Blend::Add => Some(wgpu::BlendState { color: ONE, alpha: ONE }),
            Blend::Under => Some(wgpu::BlendState { color: UNDER, alpha: UNDER }),
            Blend::Over => Some(wgpu::BlendState { color: OVER, alpha: OVER }),
            Blend::OverSumAlpha => Some(wgpu::BlendState { color: OVER, alpha: ONE }),
        }
    }
}
