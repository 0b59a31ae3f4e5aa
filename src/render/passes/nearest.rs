//! The single geometry pass of the unfiltered quality level (Botsch & Kobbelt 2003 §5):
//! elliptical splats with per-pixel depth, the nearest one wins, weight 1.

use super::super::targets::{ACCUM_FORMAT, FrameTargets};
use super::{DepthTest, cleared, depth, lighting_entry, lighting_slots, record_splats, splat_pipeline};
use crate::render::splat_buffers::GpuCloud;

/// The nearest-splat pipeline; `lit` adds the normal target.
pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    lit: bool,
) -> wgpu::RenderPipeline {
    let replace =
        Some(wgpu::ColorTargetState { format: ACCUM_FORMAT, blend: None, write_mask: wgpu::ColorWrites::ALL });
    let targets = lighting_slots(lit, &[replace.clone(), replace], 1);
    splat_pipeline(
        device,
        "NearestSplat::pipeline",
        layout,
        module,
        &lighting_entry(lit, "fs_unfiltered"),
        &targets,
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
    let colour = lighting_slots(targets.lit, &[cleared(&targets.accum_color), cleared(&targets.accum_normal)], 1);
    let desc = wgpu::RenderPassDescriptor {
        label: Some("NearestSplat::pass"),
        color_attachments: &colour,
        depth_stencil_attachment: depth(&targets.depth, true),
        timestamp_writes: timestamps,
        ..Default::default()
    };
    record_splats(encoder, &desc, pipeline, frame, |pass| cloud.draw(pass));
}
