//! Pass 1 of `two-pass` (Botsch & Kobbelt 2003 §3.3): splat depth plus ε into the depth buffer.

use super::super::targets::FrameTargets;
use super::{DepthTest, depth, record_splats, splat_pipeline};
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
        "fs_visibility",
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
) {
    record_splats(encoder, "Visibility::pass", pipeline, frame, &[], depth(&targets.depth, true), cloud);
}
