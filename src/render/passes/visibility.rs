//! Pass 1 of `two-pass` (Botsch & Kobbelt 2003 §3.3): splat depth plus ε into the depth buffer.

use super::super::targets::FrameTargets;
use super::{DepthTest, FragmentVariant, depth, record_splats, splat_pipeline};
use crate::render::splat_buffers::GpuCloud;

pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
) -> wgpu::RenderPipeline {
    splat_pipeline(
        device,
        "Visibility::pipeline",
        layout,
        module,
        &FragmentVariant { entry: "fs_visibility", lit: true, weight_only: false },
        &[],
        DepthTest { write: true, compare: wgpu::CompareFunction::Less },
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
    let desc = wgpu::RenderPassDescriptor {
        label: Some("Visibility::pass"),
        color_attachments: &[],
        depth_stencil_attachment: depth(&targets.depth, true),
        timestamp_writes: timestamps,
        ..Default::default()
    };
    record_splats(encoder, &desc, pipeline, frame, |pass| cloud.draw(pass));
}
