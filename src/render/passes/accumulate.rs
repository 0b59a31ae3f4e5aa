//! Pass 2 of `two-pass` (Botsch & Kobbelt 2003 §3.3): additive Σw·colour, Σw·normal, Σw
//! for every fragment within ε of the visible surface.

use super::super::targets::{ACCUM_FORMAT, FrameTargets, colour_format};
use super::{DepthTest, FragmentVariant, cleared, depth, lighting_slots, record_splats, splat_pipeline};
use crate::render::splat_buffers::GpuCloud;

const ADDITIVE: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::One,
    operation: wgpu::BlendOperation::Add,
};

/// The accumulation pipeline; `lit` adds the normal target, `weight_only`
/// makes the colour target a single Σw channel.
pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    lit: bool,
    weight_only: bool,
) -> wgpu::RenderPipeline {
    let additive = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: Some(wgpu::BlendState { color: ADDITIVE, alpha: ADDITIVE }),
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    let targets = lighting_slots(lit, &[additive(colour_format(weight_only)), additive(ACCUM_FORMAT)], 1);
    splat_pipeline(
        device,
        "Accumulate::pipeline",
        layout,
        module,
        &FragmentVariant { entry: "fs_accumulate", lit, weight_only },
        &targets,
        DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual },
    )
}

pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    targets: &FrameTargets,
    cloud: &GpuCloud,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let colour = lighting_slots(targets.lit, &[cleared(&targets.accum_color), cleared(&targets.accum_normal)], 1);
    let desc = wgpu::RenderPassDescriptor {
        label: Some("Accumulate::pass"),
        color_attachments: &colour,
        depth_stencil_attachment: depth(&targets.depth, false),
        timestamp_writes: timestamps,
        ..Default::default()
    };
    record_splats(encoder, &desc, pipeline, frame, |pass| cloud.draw(pass));
}
