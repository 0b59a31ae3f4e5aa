//! The geometry pass of deferred blending (Zhang & Pajarola 2007 Fig. 11):
//! group k's splats, drawn once, into layer k with that layer's own z-test.

use super::super::targets::{ACCUM_FORMAT, GROUP_DEPTH_FORMAT, GroupTargets, colour_format};
use super::{DepthTest, FragmentVariant, cleared, lighting_slots, record_splats, splat_pipeline};
use crate::render::splat_buffers::GpuCloud;
use crate::render::timer::PassTimer;

/// The group-image pipeline; `lit` adds the normal layer, `weight_only`
/// makes the colour layer a single weight channel.
pub fn pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    lit: bool,
    weight_only: bool,
) -> wgpu::RenderPipeline {
    let replace = |format| Some(wgpu::ColorTargetState { format, blend: None, write_mask: wgpu::ColorWrites::ALL });
    let slots = [replace(colour_format(weight_only)), replace(ACCUM_FORMAT), replace(GROUP_DEPTH_FORMAT)];
    let targets = lighting_slots(lit, &slots, 1);
    splat_pipeline(
        device,
        "DeferredGeometry::pipeline",
        layout,
        module,
        &FragmentVariant { entry: "fs_group", lit, weight_only },
        &targets,
        DepthTest { write: true, compare: wgpu::CompareFunction::Less },
    )
}

/// Records one render pass per group; the timer (if any) spans all of them as pass `index`.
pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    targets: &GroupTargets,
    cloud: &GpuCloud,
    timer: Option<(&PassTimer, usize)>,
) {
    let groups = cloud.groups.len().min(targets.layer_views.len());
    for (k, views) in targets.layer_views.iter().enumerate().take(groups.max(1)) {
        let stamps = timer.and_then(|(t, index)| t.writes_span(index, k == 0, k + 1 == groups.max(1)));
        let colour = lighting_slots(targets.lit, &[cleared(&views[0]), cleared(&views[1]), cleared(&views[2])], 1);
        let desc = wgpu::RenderPassDescriptor {
            label: Some("DeferredGeometry::pass"),
            color_attachments: &colour,
            depth_stencil_attachment: super::depth(&views[3], true),
            timestamp_writes: stamps,
            ..Default::default()
        };
        let range = cloud.groups.get(k).cloned().unwrap_or(0..0);
        record_splats(encoder, &desc, pipeline, frame, |pass| cloud.draw_range(pass, range));
    }
}
