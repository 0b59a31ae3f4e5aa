//! The full-screen pass builder: one triangle through `vs_fullscreen`
//! (shaders/shading.wgsl) whose fragment stage reads the pass's input targets
//! (bind group 1) and writes one output, the frame or a target.

use super::{FullscreenPass, PipelineKind};

/// The layout of `dimensions.len()` unfilterable float textures at bindings 0.. of group 1.
pub fn inputs_layout(device: &wgpu::Device, dimensions: &[wgpu::TextureViewDimension]) -> wgpu::BindGroupLayout {
    let types = dimensions.iter().map(|&view_dimension| wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Float { filterable: false },
        view_dimension,
        multisampled: false,
    });
    super::group_layout(device, "Fullscreen::inputs_layout", wgpu::ShaderStages::FRAGMENT, types)
}

/// Builds the pipeline of a full-screen pass described by `kind`.
pub fn pipeline(source: &super::PipelineSource<'_>, kind: &PipelineKind) -> Option<wgpu::RenderPipeline> {
    let PipelineKind::Fullscreen { output, blend, .. } = kind else { return None };
    let super::PipelineSource { device, label, layout, module, .. } = *source;
    let targets =
        [Some(wgpu::ColorTargetState { format: *output, blend: blend.state(), write_mask: wgpu::ColorWrites::ALL })];
    Some(device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        fragment: Some(source.fragment(&targets)),
        multiview_mask: None,
        cache: None,
    }))
}

/// Records `pass`, reading `inputs` (bind group 1) and writing `output`.
#[allow(clippy::too_many_arguments)]
pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    pass: &FullscreenPass,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    uniform_offset: u32,
    inputs: &wgpu::BindGroup,
    environment: Option<&wgpu::BindGroup>,
    output: &wgpu::TextureView,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let mut render_pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(pass.label),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view: output,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: if pass.clear { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load },
                store: wgpu::StoreOp::Store,
            },
        })],
        timestamp_writes: timestamps,
        ..Default::default()
    });
    render_pass.set_pipeline(pipeline);
    render_pass.set_bind_group(0, frame, &[uniform_offset]);
    render_pass.set_bind_group(1, inputs, &[]);
    if let Some(environment) = environment {
        render_pass.set_bind_group(2, environment, &[]);
    }
    render_pass.draw(0..3, 0..1);
}
