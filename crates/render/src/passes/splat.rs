//! The splat pass builder: every pass that draws splats (visibility,
//! accumulation, nearest splat, group layers) is an instanced 4-vertex strip
//! per splat through `vs_splat` (shaders/splat.wgsl), differing only in its
//! fragment entry point, its outputs and blending, and its depth test. A
//! pass that also draws the scene's mesh triangles ([`SplatPass::triangles`])
//! draws them after the splats, in the same render pass, through the same
//! fragment entry built with `Variant::TRIANGLES` (`vs_triangle`).

use super::{PipelineKind, SplatPass};
use crate::gpu_data::{SplatInstance, TriangleVertex};
use crate::gpu_scene::GpuScene;
use crate::shaders::Variant;

/// Builds the pipeline of a splat pass described by `kind`.
pub fn pipeline(
    source: &super::PipelineSource<'_>,
    kind: &PipelineKind,
    variant: Variant,
) -> Option<wgpu::RenderPipeline> {
    let PipelineKind::Splats { colour, depth, cull_back, .. } = kind else { return None };
    let super::PipelineSource { device, label, layout, module, .. } = *source;
    // A frame lit by scene lights reads each splat's shadow coefficients from a second instance buffer.
    let with_lights = [Some(SplatInstance::layout()), Some(crate::gpu_data::splat_light_layout())];
    let triangles = [Some(TriangleVertex::layout())];
    let (vertex_entry, buffers, topology) = if variant.has(Variant::TRIANGLES) {
        ("vs_triangle", &triangles[..], wgpu::PrimitiveTopology::TriangleList)
    } else if variant.has(Variant::LIGHTS) {
        ("vs_splat", &with_lights[..], wgpu::PrimitiveTopology::TriangleStrip)
    } else {
        ("vs_splat", &with_lights[..1], wgpu::PrimitiveTopology::TriangleStrip)
    };
    let targets: Vec<Option<wgpu::ColorTargetState>> = colour
        .iter()
        .map(|&(format, blend)| {
            Some(wgpu::ColorTargetState { format, blend: blend.state(), write_mask: wgpu::ColorWrites::ALL })
        })
        .collect();
    Some(device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex_entry),
            compilation_options: Default::default(),
            buffers,
        },
        primitive: wgpu::PrimitiveState {
            topology,
            // Outward faces wind counter-clockwise (the face normal is (b - a) × (c - a)).
            cull_mode: cull_back.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: depth.map(|(format, write, compare)| wgpu::DepthStencilState {
            format,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        fragment: Some(source.fragment(&targets)),
        multiview_mask: None,
        cache: None,
    }))
}

/// The views a splat pass draws into.
pub struct Attachments<'a> {
    pub colour: Vec<&'a wgpu::TextureView>,
    pub depth: Option<&'a wgpu::TextureView>,
}

/// Records `pass` into `encoder`.
#[allow(clippy::too_many_arguments)]
pub fn record(
    encoder: &mut wgpu::CommandEncoder,
    pass: &SplatPass,
    pipeline: &wgpu::RenderPipeline,
    frame: &wgpu::BindGroup,
    uniform_offset: u32,
    inputs: Option<&wgpu::BindGroup>,
    attachments: &Attachments<'_>,
    scene: &GpuScene,
    triangles: Option<&wgpu::RenderPipeline>,
    timestamps: Option<wgpu::RenderPassTimestampWrites<'_>>,
) {
    let colour: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = attachments
        .colour
        .iter()
        .map(|view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        })
        .collect();
    let depth = attachments.depth.zip(pass.depth).map(|(view, (_, test))| wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: if test.clear { wgpu::LoadOp::Clear(1.0) } else { wgpu::LoadOp::Load },
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    });
    let mut render_pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(pass.label),
        color_attachments: &colour,
        depth_stencil_attachment: depth,
        timestamp_writes: timestamps,
        ..Default::default()
    });
    render_pass.set_pipeline(pipeline);
    render_pass.set_bind_group(0, frame, &[uniform_offset]);
    if let Some(inputs) = inputs {
        render_pass.set_bind_group(1, inputs, &[]);
    }
    scene.draw_range(&mut render_pass, pass.splats.clone());
    if let (Some(pipeline), Some(draw)) = (triangles, &scene.triangles) {
        render_pass.set_pipeline(pipeline);
        render_pass.set_vertex_buffer(0, draw.buffer.slice(..));
        for range in &draw.ranges {
            render_pass.draw(range.start * 3..range.end * 3, 0..1);
        }
    }
}
