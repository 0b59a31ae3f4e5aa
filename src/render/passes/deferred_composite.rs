//! The compositing pass of deferred blending (Zhang & Pajarola 2007 Fig. 6):
//! ε-z visibility over the K group images, normalisation and deferred shading.

use super::super::targets::GroupTargets;

pub fn inputs_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let array = |binding| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    };
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("Composite::inputs_layout"),
        entries: &[array(0), array(1), array(2)],
    })
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
