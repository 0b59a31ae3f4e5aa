//! The single geometry pass of the unfiltered quality level (Botsch & Kobbelt 2003 §5):
//! elliptical splats with per-pixel depth, the nearest one wins, weight 1.

use super::super::targets::{ACCUM_FORMAT, FrameTargets, colour_format};
use super::{DepthTest, FragmentVariant, cleared, depth, lighting_slots, record_splats, splat_pipeline};
use crate::render::splat_buffers::GpuCloud;

/// The nearest-splat pipeline; `lit` adds the normal target, `weight_only`
/// makes the colour target a single weight channel.
pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    lit: bool,
    weight_only: bool,
) -> wgpu::RenderPipeline {
    let replace = |format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL });
    let targets = lighting_slots(lit, &[replace(colour_format(weight_only)), replace(ACCUM_FORMAT)], 1);
    splat_pipeline(
        device,
        "NearestSplat::pipeline",
        layout,
        module,
        &FragmentVariant { entry: "fs_unfiltered", lit, weight_only },
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
