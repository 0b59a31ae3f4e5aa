//! The compositing pass of deferred blending (Zhang & Pajarola 2007 Fig. 6):
//! ε-z visibility over the K group images, normalisation and deferred shading.

use super::super::targets::GroupTargets;

pub fn inputs_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    super::normalize::texture_inputs_layout(device, "Composite::inputs_layout", wgpu::TextureViewDimension::D2Array, 3)
}

pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    targets: &GroupTargets,
    output: &wgpu::TextureView,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    super::normalize::record_fullscreen(
        encoder,
        "Composite::pass",
        pipeline,
        frame,
        &targets.composite_inputs,
        output,
        timestamps,
    );
}
